"""Equal-physics peer comparison (issue 24, item 4): raceway's full level against Exudyn's ball-bearing
model (ObjectContactSphereTorus), the Table-1 bearing, healthy, Fa 4000 N, Fr 1000 N, 9900 rpm.

A benchmark, not a test: Exudyn is a benchmark dependency only (never in scripts/test.sh or CI).

The committed numbers (docs/research/exudyn-peer.md, docs/research/exudyn-peer.csv) were made by:

    cargo build --release --bin raceway
    python3 -m venv .venv-peer && .venv-peer/bin/pip install exudyn numpy scipy
    .venv-peer/bin/python studies/exudyn_peer.py --reps 3

Both models, the same physics (docs/performance.md#exudyn-peer states every remaining difference):
  - geometry of niu2014-table1: 14 balls D 12.7 mm, dm 70 mm, alpha0 30 deg, f_i 0.515, f_o 0.52; each
    race a torus (groove-centre circle at x_g, R_g of docs/model.md#geometry, minor radius f D);
  - Hertz Q = K delta^1.5 with our exact K per race (computed here as in docs/model.md#hertz,
    3.608e10 / 3.408e10 N/m^1.5), plus the linear contact damping c_br = 20 N s/m (C6);
  - frictionless contacts ([full] traction = false; Exudyn dynamicFriction = 0), no cage
    ([full] cage = false; no cage body in Exudyn), no gravity;
  - inner ring 0.50 kg, free in x, y, z, tilt held (D1), spin prescribed 9900 rpm; loads (Fa, 0, -Fr)
    on it; the outer ring on the 2-DOF pedestal: 0.55 kg, k 15e6 N/m, c 1800 N s/m in y and z.
  - the same initial state as far as it can be read from raceway's t = 0 output (ring and pedestal
    positions, the balls' orbital speed); each ball's (x, r) from its own frictionless equilibrium.

Accuracy: pedestal.a.z (the housing's radial acceleration) sampled at 51.2 kHz, 20 ms skipped, band-passed
1-12 kHz (zero-phase FFT mask); error = RMS(band(y) - band(y_ref)) / RMS(band(y_ref)), each code against
its own converged reference (raceway DOP853 rtol 1e-10; Exudyn generalized-alpha at a 0.153 us step)
and the two references against each other. Speed: wall s per simulated s, each code's solve only
(raceway's `wall_seconds_per_simulated_second` of its JSON: Simulation::new and the advance, no process
start; Exudyn's mbs.SolveDynamic, no model building), runs interleaved, median of --reps.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq, fsolve
from scipy.special import ellipe, ellipk

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "studies" / "exudyn_peer_healthy.toml"
FS = 51200.0  # output sample rate [Hz]
SKIP = 0.02  # transient skipped [s]
BAND = (1000.0, 12000.0)

# niu2014-table1 (presets/niu2014-table1.toml)
Z = 14
D = 12.7e-3
DM = 70.0e-3
ALPHA0 = np.radians(30.0)
F_I, F_O = 0.515, 0.52
E_MOD, NU, RHO = 208e9, 0.3, 7850.0
C_BR = 20.0
M_IR = 0.50
I_IR = (3.97e-4, 2.24e-4)  # polar, diametral (irrelevant here: rotations prescribed/held)
M_P, K_P, C_P = 0.55, 15e6, 1800.0
FA, FR = 4000.0, 1000.0
RPM = 9900.0
OMEGA = RPM * 2 * np.pi / 60
M_B = RHO * np.pi * D**3 / 6


def hertz_k(race: str) -> float:
    """Exact Hertz constant K [N/m^1.5] at alpha0 (docs/model.md#hertz, C5)."""
    g = D * np.cos(ALPHA0) / DM
    r_ii1 = (2 / D) * g / (1 - g) if race == "inner" else -(2 / D) * g / (1 + g)
    r_ii2 = -1 / ((F_I if race == "inner" else F_O) * D)
    irx, iry = 2 / D + r_ii1, 2 / D + r_ii2
    fr = (irx - iry) / (irx + iry)
    r = 1 / (irx + iry)
    ep = E_MOD / (1 - NU**2)

    def f(k):
        m = 1 - 1 / k**2
        return ((k * k + 1) * ellipe(m) - 2 * ellipk(m)) / ((k * k - 1) * ellipe(m)) - fr

    k = brentq(f, 1.0001, 200)
    m = 1 - 1 / k**2
    return float(np.pi * k * ep * np.sqrt(2 * ellipe(m) * r / (9 * ellipk(m) ** 3)))


K_I, K_O = hertz_k("inner"), hertz_k("outer")
# groove-centre circles in the ring frame (docs/model.md#geometry)
XG_I, RG_I = (F_I - 0.5) * D * np.sin(ALPHA0), DM / 2 + (F_I - 0.5) * D * np.cos(ALPHA0)
XG_O, RG_O = -(F_O - 0.5) * D * np.sin(ALPHA0), DM / 2 - (F_O - 0.5) * D * np.cos(ALPHA0)


def e_r(th):
    return np.array([0.0, -np.sin(th), np.cos(th)])


def e_th(th):
    return np.array([0.0, -np.cos(th), -np.sin(th)])


def contact_force(p, ring_c, xg, rg, f, k):
    """Hertz force on a ball at p from the groove (torus) of a ring centred at ring_c."""
    rb = p - ring_c
    th = np.arctan2(-rb[1], rb[2])
    g = ring_c + np.array([xg, 0, 0]) + rg * e_r(th)
    d = p - g
    dist = np.linalg.norm(d)
    delta = dist - (f - 0.5) * D
    return -k * max(delta, 0.0) ** 1.5 * d / dist, delta


def ball_equilibrium(th, ring_c, ped_c, thdot):
    """Frictionless quasi-static (x, r) of the ball at azimuth th, with its centrifugal force."""

    def res(q):
        x, r = q
        p = np.array([x, 0, 0]) + r * e_r(th)
        fi, _ = contact_force(p, ring_c, XG_I, RG_I, F_I, K_I)
        fo, _ = contact_force(p, ped_c, XG_O, RG_O, F_O, K_O)
        ftot = fi + fo + M_B * thdot**2 * r * e_r(th)
        return [ftot[0] / 1e3, ftot @ e_r(th) / 1e3]

    x, r = fsolve(res, [ring_c[0] * 0.5, DM / 2], xtol=1e-14)
    return x, r


# ---------------------------------------------------------------------------------------------- raceway
def raceway_bin() -> Path:
    tgt = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return tgt / "release" / "raceway"


def run_raceway(duration, rtol, out_dir, columns="pedestal.a.z,pedestal.a.y"):
    out = Path(out_dir) / f"raceway_{rtol:g}.csv"
    cmd = [str(raceway_bin()), "simulate", str(SCENE), "--fidelity", "full", "--duration", str(duration),
           "--rtol", str(rtol), "--sample-rate", str(FS), "--out", str(out), "--quiet"]
    if columns:
        cmd += ["--columns", columns]
    subprocess.run(cmd, check=True, cwd=ROOT)
    meta = json.loads(Path(str(out) + ".json").read_text())
    data = np.genfromtxt(out, delimiter=",", names=True)
    return data, meta


def raceway_initial_state(out_dir):
    """raceway's state at t = 0: ring and pedestal positions, the balls' orbital speeds, and each ball's
    (x, r) recovered from its two contact loads (at rest, Q = K delta^1.5: two deflections, two unknowns).
    Balls j = 0..13 at azimuth 2 pi j / z (theta_start = 0 without a spall), at rest but for the orbit."""
    cols = ["ring.x", "ring.y", "ring.z", "pedestal.y", "pedestal.z"]
    cols += [f"ball.orbit_speed[{j}]" for j in range(1, Z + 1)]
    cols += [f"contact.{race}.Q[{j}]" for race in ("inner", "outer") for j in range(1, Z + 1)]
    data, _ = run_raceway(1e-4, 1e-6, out_dir, columns=",".join(cols))
    row = data[0]
    ring = np.array([row["ringx"], row["ringy"], row["ringz"]])
    ped = np.array([0.0, row["pedestaly"], row["pedestalz"]])
    thdot = np.array([row[f"ballorbit_speed{j}"] for j in range(1, Z + 1)])
    balls = []
    for j in range(Z):
        th = 2 * np.pi * j / Z
        v = thdot[j] * e_th(th)  # per unit radius

        def q_of(p, c, xg, rg, f, k):
            fvec, delta = contact_force(p, c, xg, rg, f, k)
            qn = np.linalg.norm(fvec)
            n = -fvec / qn  # from the ball centre toward the contact
            return qn + C_BR * (n @ (v * np.hypot(p[1], p[2])))  # Q = K delta^1.5 + c_br n.v at t = 0

        def res(q):
            p = np.array([q[0], 0, 0]) + q[1] * e_r(th)
            return [q_of(p, ring, XG_I, RG_I, F_I, K_I) - row[f"contactinnerQ{j + 1}"],
                    q_of(p, ped, XG_O, RG_O, F_O, K_O) - row[f"contactouterQ{j + 1}"]]

        # the two loads fix the ball only up to a mirror across the line of the groove centres:
        # start from the frictionless equilibrium to take the branch next to it
        x, r = fsolve(res, ball_equilibrium(th, ring, ped, thdot[j]), xtol=1e-14)
        assert max(abs(v) for v in res([x, r])) < 1e-5, "ball position not recovered"
        balls.append((x, r))
    return ring, ped, thdot, np.array(balls)


# ---------------------------------------------------------------------------------------------- Exudyn
def make_uf(xg, rg, f, k):
    """Our contact law as an ObjectConnectorCartesianSpringDamper user function between the ring centre
    (marker 0) and the ball centre (marker 1): the Hertz force of the ball in the groove torus, along the
    groove-circle-to-ball direction, plus c_br on the approach rate, clipped at >= 0 (C6)."""
    d0 = (f - 0.5) * D

    def uf(mbs, t, item, u, v, stiffness, damping, offset):
        ux, uy, uz = u
        rho = (uy * uy + uz * uz) ** 0.5
        dx, dy, dz = ux - xg, uy * (1 - rg / rho), uz * (1 - rg / rho)
        dist = (dx * dx + dy * dy + dz * dz) ** 0.5
        delta = dist - d0
        if delta <= 0:
            return [0.0, 0.0, 0.0]
        nx, ny, nz = dx / dist, dy / dist, dz / dist
        q = k * delta**1.5 + C_BR * (nx * v[0] + ny * v[1] + nz * v[2])
        if q <= 0:
            return [0.0, 0.0, 0.0]
        return [q * nx, q * ny, q * nz]  # the connector puts -f on marker 1 (the ball): -Q n

    return uf


def build_exudyn(ring0, ped0, thdot, balls0=None, variant="native", friction=0.0, v_reg=1e-3, spin=True):
    """variant "native": Exudyn's ObjectContactSphereTorus (as exudyn.machines.CreateBallBearing uses it),
    rigid-body balls and rings; "uf": our contact law in a CartesianSpringDamper user function, mass-point
    balls and rings (frictionless: ball and ring rotations carry no force)."""
    import exudyn as exu
    from exudyn.utilities import (InertiaSphere, MarkerBodyRigid, MarkerBodyPosition, NodeGenericData,
                                  ObjectConnectorCartesianSpringDamper, ObjectContactSphereTorus, SensorNode)

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.CreateGround()
    native = variant == "native"

    # outer ring + pedestal: moves in y, z only (C3)
    if native:
        outer = mbs.CreateRigidBody(referencePosition=list(ped0), nodeType=exu.NodeType.RotationRxyz,
                                    inertia=_inertia(InertiaSphere, M_P))
        fixed = (0, 3, 4, 5)
    else:
        outer = mbs.CreateMassPoint(referencePosition=list(ped0), physicsMass=M_P)
        fixed = (0,)
    n_outer = mbs.GetObject(outer)["nodeNumber"]
    for c in fixed:
        mbs.CreateCoordinateConstraint(bodyNumbers=[outer, None], coordinates=[c, None], show=False)
    mbs.CreateCartesianSpringDamper(bodyNumbers=[ground, outer], localPosition0=[0, 0, 0], localPosition1=[0, 0, 0],
                                    stiffness=[0, K_P, K_P], damping=[0, C_P, C_P], show=False)

    # inner ring: x, y, z free, tilt held (D1), spin prescribed (C4; without friction it carries no force)
    if native:
        inner = mbs.CreateRigidBody(referencePosition=list(ring0), nodeType=exu.NodeType.RotationRxyz,
                                    inertia=_inertia(InertiaSphere, M_IR),
                                    initialAngularVelocity=[OMEGA if spin else 0.0, 0, 0])
        mbs.CreateCoordinateConstraint(bodyNumbers=[inner, None], coordinates=[3, None], velocityLevel=spin,
                                       offset=OMEGA if spin else 0.0, show=False)
        for c in (4, 5):
            mbs.CreateCoordinateConstraint(bodyNumbers=[inner, None], coordinates=[c, None], show=False)
        m_in = mbs.AddMarker(MarkerBodyRigid(bodyNumber=inner, localPosition=[XG_I, 0, 0]))
        m_out = mbs.AddMarker(MarkerBodyRigid(bodyNumber=outer, localPosition=[XG_O, 0, 0]))
    else:
        inner = mbs.CreateMassPoint(referencePosition=list(ring0), physicsMass=M_IR)
        m_in = mbs.AddMarker(MarkerBodyPosition(bodyNumber=inner))
        m_out = mbs.AddMarker(MarkerBodyPosition(bodyNumber=outer))
    mbs.CreateForce(bodyNumber=inner, loadVector=[FA, 0, -FR], show=False)

    contacts = {"inner": [], "outer": []}
    for j in range(Z):
        th = 2 * np.pi * j / Z
        x, r = balls0[j] if balls0 is not None else ball_equilibrium(th, ring0, ped0, thdot[j])
        p = np.array([x, 0, 0]) + r * e_r(th)
        v = r * thdot[j] * e_th(th)
        if native:
            ball = mbs.CreateRigidBody(referencePosition=list(p), initialVelocity=list(v),
                                       nodeType=exu.NodeType.RotationRxyz,
                                       inertia=InertiaSphere(density=RHO, radius=D / 2))
            mb = mbs.AddMarker(MarkerBodyRigid(bodyNumber=ball))
        else:
            ball = mbs.CreateMassPoint(referencePosition=list(p), initialVelocity=list(v), physicsMass=M_B)
            mb = mbs.AddMarker(MarkerBodyPosition(bodyNumber=ball))
        for race, mr, xg, rg, f, k in (("inner", m_in, XG_I, RG_I, F_I, K_I), ("outer", m_out, XG_O, RG_O, F_O, K_O)):
            if native:
                nd = mbs.AddNode(NodeGenericData(initialCoordinates=[-1e-6, 0, 0, 0], numberOfDataCoordinates=4))
                o = mbs.AddObject(ObjectContactSphereTorus(
                    markerNumbers=[mb, mr], nodeNumber=nd, sphereRadius=D / 2, torusMajorRadius=rg,
                    torusMinorRadius=f * D, torusAxis=[1, 0, 0], contactStiffness=k, contactStiffnessExponent=1.5,
                    contactDamping=C_BR, dynamicFriction=friction, frictionProportionalZone=v_reg, impactModel=0))
            else:
                o = mbs.AddObject(ObjectConnectorCartesianSpringDamper(
                    markerNumbers=[mr, mb], stiffness=[0, 0, 0], damping=[0, 0, 0],
                    springForceUserFunction=make_uf(xg, rg, f, k), visualization={"show": False, "drawSize": -1.0, "color": [-1.0] * 4}))
            contacts[race].append(o)

    s_acc = mbs.AddSensor(SensorNode(nodeNumber=n_outer, storeInternal=True,
                                     outputVariableType=exu.OutputVariableType.Coordinates_tt))
    mbs.Assemble()
    return sc, mbs, s_acc, contacts


def _inertia(kind, mass):
    """A sphere inertia of the given mass (the rings' rotations are held or prescribed: only the mass acts)."""
    r = 0.03
    return kind(density=mass / (4 / 3 * np.pi * r**3), radius=r)


def run_exudyn(h, duration, ring0, ped0, thdot, spectral_radius=0.9, newton_rtol=1e-6, newton_atol=1e-8, **kw):
    """One Exudyn run (generalized-alpha, fixed step h, modified Newton as in Exudyn's ballBearingTest);
    returns time, pedestal z and y accelerations and the wall time of mbs.SolveDynamic."""
    import exudyn as exu

    sc, mbs, s_acc, _ = build_exudyn(ring0, ped0, thdot, **kw)
    ss = exu.SimulationSettings()
    ss.solutionSettings.writeSolutionToFile = False
    ss.solutionSettings.sensorsWritePeriod = min(1 / FS, h) * 0.999
    ss.timeIntegration.numberOfSteps = int(round(duration / h))
    ss.timeIntegration.endTime = duration
    ss.timeIntegration.newton.absoluteTolerance = newton_atol
    ss.timeIntegration.newton.relativeTolerance = newton_rtol
    ss.timeIntegration.newton.useModifiedNewton = True
    ss.timeIntegration.generalizedAlpha.spectralRadius = spectral_radius
    ss.timeIntegration.verboseMode = 0
    ss.linearSolverType = exu.LinearSolverType.EigenSparse
    ss.parallel.numberOfThreads = 1
    ss.displayStatistics = False
    ss.displayComputationTime = False
    t0 = time.perf_counter()
    mbs.SolveDynamic(ss)
    wall = time.perf_counter() - t0
    d = mbs.GetSensorStoredData(s_acc)  # time, then the node's accelerations (x, y, z[, rotations])
    return d[:, 0], d[:, 3], d[:, 2], wall


# ---------------------------------------------------------------------------------------------- errors
def band(y, fs=FS, lo=BAND[0], hi=BAND[1]):
    y = np.asarray(y) - np.mean(y)
    spec = np.fft.rfft(y)
    f = np.fft.rfftfreq(len(y), 1 / fs)
    spec[(f < lo) | (f > hi)] = 0
    return np.fft.irfft(spec, len(y))


def on_grid(t, y, duration):
    tg = np.arange(int(round(SKIP * FS)), int(round(duration * FS)) + 1) / FS
    return np.interp(tg, t, y)


def band_err(y, yref):
    a, b = band(y), band(yref)
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b**2)))


def cached(path: Path, fn):
    if path.exists():
        z = np.load(path)
        return {k: z[k] for k in z.files}
    r = fn()
    np.savez(path, **r)
    return r


def fmt(x, n=3):
    return f"{x:.{n}g}" if isinstance(x, float) else str(x)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=0.06, help="simulated s per run (first 20 ms skipped)")
    ap.add_argument("--reps", type=int, default=3, help="timed repetitions, raceway and Exudyn interleaved")
    ap.add_argument("--rtols", default="1e-5,1e-6,1e-7,1e-8")
    ap.add_argument("--steps", default="1e-4,1.953125e-5,9.765625e-6,4.8828125e-6,2.44140625e-6,1.220703125e-6",
                    help="Exudyn fixed steps [s] (0.1 ms: Exudyn's ballBearingTest; the rest divide 1/51.2 kHz)")
    ap.add_argument("--ref-step", type=float, default=1.953125e-5 / 128)
    ap.add_argument("--ref-rtol", type=float, default=1e-10)
    ap.add_argument("--work", default=str(ROOT / "target" / "exudyn_peer"), help="run files and cached references")
    ap.add_argument("--out", default=str(ROOT / "docs" / "research" / "exudyn-peer"))
    args = ap.parse_args()
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    dur = args.duration
    rtols = [float(x) for x in args.rtols.split(",")]
    steps = [float(x) for x in args.steps.split(",")]
    import exudyn

    ring0, ped0, thdot, balls0 = raceway_initial_state(work)
    print(f"initial state from raceway: ring {ring0}, pedestal {ped0}, orbit speed {thdot[0]:.4f} rad/s", flush=True)

    # references (cached in --work: delete them to recompute)
    def ours_ref(rtol):
        def f():
            d, meta = run_raceway(dur, rtol, work)
            return {"t": d["time"], "az": d["pedestalaz"], "rhs": np.array(meta["solver"]["rhs_evals"])}
        return f

    def exu_ref(h):
        def f():
            t, az, _, wall = run_exudyn(h, dur, ring0, ped0, thdot, balls0=balls0, variant="uf", newton_rtol=1e-10, newton_atol=1e-10)
            return {"t": t, "az": az, "wall": np.array(wall)}
        return f

    print("references ...", flush=True)
    r_ours = cached(work / f"ref_raceway_{args.ref_rtol:g}_{dur:g}.npz", ours_ref(args.ref_rtol))
    r_ours2 = cached(work / f"ref_raceway_{args.ref_rtol * 10:g}_{dur:g}.npz", ours_ref(args.ref_rtol * 10))
    r_exu = cached(work / f"ref_exudyn_{args.ref_step:g}_{dur:g}.npz", exu_ref(args.ref_step))
    r_exu2 = cached(work / f"ref_exudyn_{args.ref_step * 2:g}_{dur:g}.npz", exu_ref(args.ref_step * 2))
    g_ours = on_grid(r_ours["t"], r_ours["az"], dur)
    g_exu = on_grid(r_exu["t"], r_exu["az"], dur)
    ref_check = {
        "raceway": band_err(on_grid(r_ours2["t"], r_ours2["az"], dur), g_ours),
        "exudyn": band_err(on_grid(r_exu2["t"], r_exu2["az"], dur), g_exu),
        "cross": band_err(g_exu, g_ours),
        "cross_rms_ratio": float(np.sqrt(np.mean(band(g_exu) ** 2)) / np.sqrt(np.mean(band(g_ours) ** 2))),
    }
    print("reference checks:", ref_check, flush=True)

    rows = []  # code, setting, rep, wall s per simulated s, error
    for rep in range(args.reps):
        for i in range(max(len(rtols), len(steps))):
            if i < len(rtols):
                d, meta = run_raceway(dur, rtols[i], work)
                e = band_err(on_grid(d["time"], d["pedestalaz"], dur), g_ours)
                ec = band_err(on_grid(d["time"], d["pedestalaz"], dur), g_exu)
                rows.append(("raceway", rtols[i], rep, meta["solver"]["wall_seconds_per_simulated_second"], e, ec))
                print(rows[-1], flush=True)
            if i < len(steps):
                t, az, _, wall = run_exudyn(steps[i], dur, ring0, ped0, thdot, balls0=balls0, variant="uf")
                e = band_err(on_grid(t, az, dur), g_exu)
                ec = band_err(on_grid(t, az, dur), g_ours)
                rows.append(("exudyn_uf", steps[i], rep, wall / dur, e, ec))
                print(rows[-1], flush=True)

    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(str(out) + ".csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["code", "setting", "rep", "wall_s_per_sim_s", "err_band_own_ref", "err_band_other_ref"])
        w.writerows(rows)
    summary = summarize(rows, rtols, steps, ref_check, r_exu, dur, exudyn.__version__)
    Path(str(out) + ".md").write_text(summary)
    print(summary)


def summarize(rows, rtols, steps, ref_check, r_exu, dur, exu_version):
    def med(code, setting, col):
        return statistics.median(r[col] for r in rows if r[0] == code and r[1] == setting)

    ours = {r: (med("raceway", r, 3), med("raceway", r, 4), med("raceway", r, 5)) for r in rtols}
    exu = {h: (med("exudyn_uf", h, 3), med("exudyn_uf", h, 4), med("exudyn_uf", h, 5)) for h in steps}
    e6 = ours.get(1e-6)
    lines = []
    lines.append("| code | setting | wall s per simulated s (median) | band error vs own reference | band error vs the other code's reference |")
    lines.append("|---|---|---|---|---|")
    for r in rtols:
        lines.append(f"| raceway full | DOP853 rtol {r:g} | {ours[r][0]:.3f} | {ours[r][1]:.2e} | {ours[r][2]:.2e} |")
    for h in steps:
        lines.append(f"| Exudyn {exu_version} (user-function Hertz) | gen.-alpha h = {h * 1e6:.3g} us | {exu[h][0]:.3f} | {exu[h][1]:.2e} | {exu[h][2]:.2e} |")
    verdict = []
    if e6 is not None:
        ok = [h for h in steps if exu[h][1] <= e6[1]]
        if ok:
            h = max(ok)
            ratio = exu[h][0] / e6[0]
            verdict.append(f"At equal or better accuracy (band error <= raceway's {e6[1]:.2e} at rtol 1e-6): Exudyn's largest step "
                           f"that reaches it is h = {h * 1e6:.3g} us ({exu[h][1]:.2e}), {exu[h][0]:.3f} s/s against raceway's "
                           f"{e6[0]:.3f} s/s: raceway is **{ratio:.1f}x** faster.")
        else:
            h = min(steps)
            verdict.append(f"No Exudyn step of the sweep reaches raceway's band error {e6[1]:.2e} at rtol 1e-6; the smallest, "
                           f"h = {h * 1e6:.3g} us, has {exu[h][1]:.2e} at {exu[h][0]:.3f} s/s: raceway is at least "
                           f"**{exu[h][0] / e6[0]:.1f}x** faster at equal accuracy.")
        hd = max(steps)
        verdict.append(f"At Exudyn's ballBearingTest step (h = {hd * 1e6:.3g} us): {exu[hd][0]:.3f} s/s, band error {exu[hd][1]:.2e}; "
                       f"ratio to raceway at rtol 1e-6: {exu[hd][0] / e6[0]:.1f}x.")
    txt = ["# Exudyn peer: equal-physics comparison on the healthy bearing (9900 rpm)", "",
           "*Written by `studies/exudyn_peer.py`; see its docstring for the command and the settings.*", "",
           f"Simulated {dur:g} s per run, errors over {dur - SKIP:g} s after the 20 ms skip; pedestal.a.z at 51.2 kHz, "
           f"band 1-12 kHz; relative RMS error of the band-passed signal.", "",
           f"Reference checks (band error): raceway rtol 1e-9 vs 1e-10: {ref_check['raceway']:.2e}; Exudyn h 0.305 us vs "
           f"0.153 us: {ref_check['exudyn']:.2e}; **the two references against each other: {ref_check['cross']:.2e}** "
           f"(band RMS ratio Exudyn/raceway {ref_check['cross_rms_ratio']:.4f}); the Exudyn reference took "
           f"{float(r_exu['wall']):.0f} s.", ""]
    txt += lines + [""] + verdict + [""]
    return "\n".join(txt)


if __name__ == "__main__":
    main()
