"""A small co-simulation master over fmpy's FMU2Slave for the rotor <-> bearing coupling.

Used by studies/coupling_study.py, examples/systems/*.py and tests/python/test_rotor.py.

Coupling (Jacobi, macro step H): at t_k the master reads the rotor's journal motion
(x_k, v_k) and the bearing's reaction F_k, hands x_k, v_k to the bearing (which moves the
journal as x_k + v_k (t - t_k) inside the step) and F_k to the rotor, then both step in
parallel. The rotor's force law inside the step (see the JeffcottRotor documentation) is
    F(t) = bearing.F + bearing.dF (t - t_k) + bearing.dF_dx (x(t) - x_k) + bearing.dF_dv (v(t) - v_k)
and the schemes differ only in what the master sets:
- "constant":    bearing.F = F_k (zero-order hold);
- "extrapolate": bearing.F = F_k, bearing.dF = (F_k - F_{k-1}) / H (linear extrapolation);
- "jacobian":    K = dF/dx, C = dF/dv from the bearing's fmi2GetDirectionalDerivative at t_k,
                 bearing.F = F_k + K (x_k - xhat_k) + C (v_k - vhat_k) (F_k was computed for the
                 journal motion xhat_k, vhat_k the bearing extrapolated to t_k), and K, C set as
                 bearing.dF_dx / bearing.dF_dv: the rotor integrates the linearised bearing
                 reaction inside its step (a linearly implicit coupling step).
- "tlm" (run_tlm): a transmission line through the shaft, the journal's mass inside the bearing
                 (BallBearing coupling = 2, JeffcottRotor coupling = 1 with tlm.delay = H): the
                 rotor hands the line's force over the step (tlm.c0, tlm.c1) and its impedance
                 (tlm.Zc) to the bearing, the bearing its journal velocity (ring.v) to the rotor.
                 Passive, so stable at any H; neither FMU's outputs depend on its inputs at the
                 same instant, so the order of sets and gets does not matter.
- "implicit":    rolled-back step sensitivities (fmi2GetFMUstate/fmi2SetFMUstate): trial steps
                 of the bearing (perturbed journal velocity) and the rotor (perturbed end force)
                 give a linearised interface condition, solved for the journal velocity over the
                 step; covers the bearing's internal modes (pedestal), which the instantaneous
                 Jacobian leaves explicit. About 5x the FMU work per macro step.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
AXES = ("x", "y", "z")
JX = [f"journal.{a}" for a in AXES]
JV = [f"journal.v.{a}" for a in AXES]
BF = [f"bearing.F.{a}" for a in AXES]
DF = [f"bearing.dF.{a}" for a in AXES]
KX = [f"bearing.dF_dx.{a}{b}" for a in AXES for b in AXES]
KV = [f"bearing.dF_dv.{a}{b}" for a in AXES for b in AXES]
SCHEMES = ("constant", "extrapolate", "jacobian")
ALL_SCHEMES = SCHEMES + ("implicit",)


def fmu_dir() -> Path:
    target = Path(os.environ.get("CARGO_TARGET_DIR") or REPO / "target")
    if not target.is_absolute():
        target = REPO / target
    return target / "fmu"


def fmu_path(name: str) -> Path:
    """target/fmu/<name>.fmu; $RACEWAY_FMU overrides BallBearing, $RACEWAY_ROTOR_FMU the rotor."""
    env = {"BallBearing": "RACEWAY_FMU", "JeffcottRotor": "RACEWAY_ROTOR_FMU"}.get(name)
    if env and os.environ.get(env):
        return Path(os.environ[env])
    return fmu_dir() / f"{name}.fmu"


class Fmu:
    """One FMI 2.0 CS instance with name-based get/set."""

    _unzipped: dict = {}

    def __init__(self, path, name, start_values=None, t0=0.0, tolerance=None):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        path = str(path)
        if path not in Fmu._unzipped:
            Fmu._unzipped[path] = (read_model_description(path), extract(path))
        self.md, self.unzipdir = Fmu._unzipped[path]
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.slave = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.unzipdir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        self.slave.instantiate()
        self.slave.setupExperiment(tolerance=tolerance, startTime=t0)
        for k, v in (start_values or {}).items():
            self.set_any(k, v)
        self.slave.enterInitializationMode()
        self.t0 = t0

    def vr(self, names):
        try:
            return [self.vars[n].valueReference for n in names]
        except KeyError as e:
            raise KeyError(f"{self.md.modelName} has no variable {e}") from None

    def set_any(self, name, value):
        v = self.vars[name]
        if v.type in ("Integer", "Enumeration"):  # an Enumeration is set as an Integer
            self.slave.setInteger([v.valueReference], [int(value)])
        elif v.type == "Boolean":
            self.slave.setBoolean([v.valueReference], [bool(value)])
        else:
            self.slave.setReal([v.valueReference], [float(value)])

    def exit_init(self):
        self.slave.exitInitializationMode()

    def get(self, names):
        return np.array(self.slave.getReal(self.vr(names)))

    def set(self, names, values):
        self.slave.setReal(self.vr(names), [float(x) for x in values])

    def step(self, t, h):
        try:
            self.slave.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        except Exception:
            self.failed = True
            raise

    def jacobian(self, outputs, inputs):
        """d outputs / d inputs (dense, one directional derivative per input)."""
        vu, vk = self.vr(outputs), self.vr(inputs)
        cols = []
        for j in range(len(inputs)):
            seed = [0.0] * len(inputs)
            seed[j] = 1.0
            cols.append(self.slave.getDirectionalDerivative(vu, vk, seed))
        return np.array(cols).T

    failed = False

    def free(self):
        # After fmi2Error only fmi2FreeInstance is allowed (fmi2Terminate would be refused).
        if not self.failed:
            try:
                self.slave.terminate()
            except Exception:
                pass
        self.slave.freeInstance()


class LinearBearing:
    """A linear stand-in for the BallBearing in motion mode: F = F0 + K (x - x0) + C v, with the
    BallBearing's interface (journal motion in, bearing.F out, exact Jacobian). Used to check
    the master against the closed-form stability analysis."""

    def __init__(self, K, C, F0=(0.0, 0.0, 0.0), x0=(0.0, 0.0, 0.0)):
        self.K, self.C = np.asarray(K, float), np.asarray(C, float)
        self.F0, self.x0 = np.asarray(F0, float), np.asarray(x0, float)
        self.x = self.x0.copy()
        self.v = np.zeros(3)
        self.xin, self.vin, self.tin, self.t = self.x0.copy(), np.zeros(3), 0.0, 0.0

    def force(self):
        return self.F0 + self.K @ (self.x - self.x0) + self.C @ self.v

    def exit_init(self):
        pass

    def get(self, names):
        if names == BF:
            return self.force()
        raise KeyError(names)

    def set(self, names, values):
        values = np.asarray(values, float)
        if names == JX + JV:
            self.xin, self.vin, self.tin = values[:3].copy(), values[3:].copy(), self.t
            self.x, self.v = self.xin.copy(), self.vin.copy()
        else:
            raise KeyError(names)

    def step(self, t, h):
        self.t = t + h
        self.x = self.xin + self.vin * (self.t - self.tin)
        self.v = self.vin.copy()

    def jacobian(self, outputs, inputs):
        return self.K if inputs == JX else self.C

    def free(self):
        pass


def run_coupled(rotor, bearing, H, t_end, scheme="constant", t0=0.0, on_step=None,
                blowup=1e-2, feedthrough=False):
    """Jacobi co-simulation rotor <-> bearing (both already in initialization mode, parameters
    set). Returns dict of arrays: t, x (journal), v, F (force used by the rotor at t_k), and
    'ok' (False if a step failed or the journal left a 'blowup' [m] ball around its start).
    feedthrough=True: the bearing gets x_k, v_k before its reaction is read (Gauss-Seidel on the
    algebraic output), otherwise the reaction lags by the bearing's own step (plain Jacobi)."""
    if scheme not in ALL_SCHEMES:
        raise ValueError(f"scheme must be one of {ALL_SCHEMES}")
    xv = rotor.get(JX + JV)
    bearing.set(JX + JV, xv)
    rotor.exit_init()
    bearing.exit_init()
    xv = rotor.get(JX + JV)
    bearing.set(JX + JV, xv)
    x_start = xv[:3].copy()
    n = int(round((t_end - t0) / H))
    ts, xs, vs, fs = [t0], [xv[:3]], [xv[3:]], []
    F_prev = None
    xhat = xv.copy()  # journal motion the bearing's current output belongs to
    ok = True
    error = None
    t = t0
    for k in range(n):
        if feedthrough:
            # the bearing's reaction depends algebraically on the journal motion: read it for
            # the current x_k, v_k (no lag; needs an FMU whose outputs follow its inputs)
            try:
                bearing.set(JX + JV, xv)
            except Exception as e:  # an FMU refusing the journal's motion counts as a failure
                ok = False
                error = f"t = {t}: {e}"
                break
            xhat = xv.copy()
        if isinstance(bearing, Fmu):  # the rotor's speed (a ramp) drives the bearing's
            bearing.set(SPEED, rotor.get(SPEED))
        F = bearing.get(BF)
        if scheme == "constant":
            rotor.set(BF, F)
        elif scheme == "extrapolate":
            dF = np.zeros(3) if F_prev is None else (F - F_prev) / H
            rotor.set(BF + DF, np.concatenate([F, dF]))
        else:
            Kx = bearing.jacobian(BF, JX)
            Kv = bearing.jacobian(BF, JV)
            Fc = F + Kx @ (xv[:3] - xhat[:3]) + Kv @ (xv[3:] - xhat[3:])
            rotor.set(BF + KX + KV, np.concatenate([Fc, Kx.ravel(), Kv.ravel()]))
            F = Fc
        fs.append(F)
        F_prev = F
        try:
            if not feedthrough:
                bearing.set(JX + JV, xv)
            if scheme == "implicit":
                F = implicit_step(rotor, bearing, t, H, xv, F)
                fs[-1] = F
            else:
                rotor.step(t, H)
                bearing.step(t, H)
        except Exception as e:  # an FMU refusing to continue counts as a failure
            ok = False
            error = f"t = {t}: {e}"
            break
        t = t0 + (k + 1) * H
        xhat = np.concatenate([xv[:3] + H * xv[3:], xv[3:]])
        xv = rotor.get(JX + JV)
        ts.append(t)
        xs.append(xv[:3])
        vs.append(xv[3:])
        if on_step:
            on_step(t, rotor, bearing)
        if not np.all(np.isfinite(xv)) or np.max(np.abs(xv[:3] - x_start)) > blowup:
            ok = False
            error = f"t = {t}: the journal left the {blowup} m ball around its start"
            break
    fs.append(bearing.get(BF) if ok else np.full(3, np.nan))
    return {
        "t": np.array(ts), "x": np.array(xs), "v": np.array(vs),
        "F": np.array(fs[: len(ts)]), "ok": ok, "error": error,
    }


TLM_WAVE = ["tlm.c0.y", "tlm.c0.z", "tlm.c1.y", "tlm.c1.z", "tlm.Zc"]
SPEED = ["shaft.speed"]
TLM_V_IN = ["tlm.v.y", "tlm.v.z"]
RING_V = ["ring.v.y", "ring.v.z"]
RING_X = ["ring.x", "ring.y", "ring.z"]


def run_tlm(rotor, bearing, H, t_end, t0=0.0, on_step=None, blowup=1e-2):
    """Jacobi co-simulation through the transmission line (both FMUs in initialization mode,
    parameters set: rotor coupling = 1 and tlm.delay = H, bearing coupling = 2). Plain value
    exchange at each communication point, as any master does: the line's samples and the shaft
    speed from the rotor, the journal velocity from the bearing. Returns dict of arrays: t, x (the
    journal: bearing ring.x/y/z), disk (rotor disk.y/z), and 'ok', 'error'."""
    rotor.exit_init()
    bearing.set(TLM_WAVE, rotor.get(TLM_WAVE))  # the line's force at rest: the start's equilibrium
    bearing.exit_init()
    x_start = bearing.get(RING_X)
    n = int(round((t_end - t0) / H))
    ts, xs, ds = [t0], [x_start], [rotor.get(["disk.y", "disk.z"])]
    ok, error, t = True, None, t0
    for k in range(n):
        try:
            bearing.set(TLM_WAVE + SPEED, rotor.get(TLM_WAVE + SPEED))
            rotor.set(TLM_V_IN, bearing.get(RING_V))
            rotor.step(t, H)
            bearing.step(t, H)
        except Exception as e:  # an FMU refusing to continue counts as a failure
            ok, error = False, f"t = {t}: {e}"
            break
        t = t0 + (k + 1) * H
        x = bearing.get(RING_X)
        ts.append(t)
        xs.append(x)
        ds.append(rotor.get(["disk.y", "disk.z"]))
        if on_step:
            on_step(t, rotor, bearing)
        if not np.all(np.isfinite(x)) or np.max(np.abs(x - x_start)) > blowup:
            ok, error = False, f"t = {t}: the journal left the {blowup} m ball around its start"
            break
    return {"t": np.array(ts), "x": np.array(xs), "disk": np.array(ds), "ok": ok, "error": error}


def half_ball_mass():
    """Half the balls' mass of the default bearing (presets/niu2014-table1.toml): the lumped level
    (L2) adds it to the inner ring in force mode (m1 = inner_ring.mass + z m_b / 2)."""
    import math
    import tomllib

    doc = tomllib.loads((REPO / "presets" / "niu2014-table1.toml").read_text())
    flat = {}

    def walk(d):
        for k, v in d.items():
            walk(v) if isinstance(v, dict) else flat.setdefault(k, v)
    walk(doc)
    d = flat["ball_diameter"]
    return 0.5 * flat["z"] * flat["density"] * math.pi * d ** 3 / 6


def is_stable(t, e):
    """Whether the oscillation e(t) decays: negative growth rate, or (when it has decayed into
    round-off, where the slope is noise) its last eighth below 1e-3 of its first eighth."""
    e = np.asarray(e) - np.mean(np.asarray(e)[len(e) // 2:])
    n = max(len(e) // 8, 1)
    first, last = np.max(np.abs(e[:n])), np.max(np.abs(e[-n:]))
    return bool(growth_rate(t, e) < 0 or last < 1e-3 * first)


def implicit_step(rotor, bearing, t, H, xv, F0):
    """One linearly implicit macro step with the step sensitivities of both FMUs (rolled-back
    trial steps via fmi2GetFMUstate/fmi2SetFMUstate). Unknown: the journal's mean velocity u
    over the step that the bearing is given (x(t) = x_k + u (t - t_k)); the rotor gets the force
    ramp F_k -> F_{k+1}(u) and must end where the bearing's journal ends: x_{k+1}(F_{k+1}(u)) =
    x_k + u H. One Newton step from u = v_k with finite-difference sensitivities covers the
    bearing's internal modes (pedestal) too. Returns the force at the step start used."""
    xk, vk = xv[:3], xv[3:]
    sb, sr = bearing.slave.getFMUstate(), rotor.slave.getFMUstate()

    def bearing_end(u):
        bearing.slave.setFMUstate(sb)
        bearing.set(JX + JV, np.concatenate([xk, u]))
        bearing.step(t, H)
        return bearing.get(BF)

    def rotor_end(F1):
        rotor.slave.setFMUstate(sr)
        rotor.set(BF + DF, np.concatenate([F0, (F1 - F0) / H]))
        rotor.step(t, H)
        return rotor.get(JX)

    du = 1e-6  # m/s
    Fb = bearing_end(vk)
    Jb = np.column_stack([(bearing_end(vk + du * e) - Fb) / du for e in np.eye(3)])
    dF = 1.0  # N
    X = rotor_end(Fb)
    Jr = np.column_stack([(rotor_end(Fb + dF * e) - X) / dF for e in np.eye(3)])
    r = X - (xk + vk * H)
    u = vk - np.linalg.solve(Jr @ Jb - H * np.eye(3), r)
    F1 = bearing_end(u)
    rotor_end(F1)
    bearing.slave.freeFMUstate(sb)
    rotor.slave.freeFMUstate(sr)
    return F0


def growth_rate(t, e):
    """Exponential growth rate [1/s] of the oscillation e(t) (1-D): slope of log peak envelope
    over windows; positive: unstable."""
    e = np.asarray(e) - np.mean(e[len(e) // 2:])
    nwin = 8
    edges = np.linspace(0, len(e), nwin + 1).astype(int)
    tm, lm = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        if b - a < 2:
            continue
        m = np.max(np.abs(e[a:b]))
        if m > 0:
            tm.append(np.mean(t[a:b]))
            lm.append(np.log(m))
    if len(tm) < 3:
        return np.inf
    return float(np.polyfit(tm, lm, 1)[0])
