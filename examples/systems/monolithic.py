"""Rotor and bearing integrated together: one CVODE solver over both Model Exchange FMUs.

Usage: .venv/bin/python examples/systems/monolithic.py [--stop 0.3] [--rtol 1e-8]

No master that runs a system of Model Exchange FMUs installs from the package registries here
(PyFMI's coupled ME model needs the FMI Library, which PyPI does not carry as a wheel;
OMSimulator's Python package downloads its binary at install time), so this is a small one of
our own over fmpy's low-level FMU2Model and its CVODE binding. The connections are the
contact cut's (the rotor owns the journal, coupling = 0; the bearing takes the journal's motion,
coupling = 1) and are made inside every evaluation, so the system is integrated as one ODE:

    rotor journal.x/y/z, journal.v.x/y/z  ->  bearing journal.*     (rotor states: no loop)
    bearing bearing.F.x/y/z               ->  rotor bearing.F.*     (no feedthrough back)

The rotor's shaft speed reaches the bearing at each output point as an input event (the
bearing's Model Exchange interface treats a speed change as a discrete change: its time events
are predicted at the speed they were set with); the unbalance force is the rotor's own, at
its exact speed. Events: the bearing's indicators (CVODE locates their roots) and time
events, and each FMU's completedIntegratorStep request.
"""

from __future__ import annotations

import argparse
import ctypes
import math
import pathlib
import shutil
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
import cosim_master as cm  # noqa: E402

JOURNAL = ["journal.x", "journal.y", "journal.z", "journal.v.x", "journal.v.y", "journal.v.z"]
FORCE = ["bearing.F.x", "bearing.F.y", "bearing.F.z"]
_DOUBLE_P = ctypes.POINTER(ctypes.c_double)


class MeFmu:
    """One Model Exchange FMU instance (fmpy's FMU2Model) with its variables by name."""

    def __init__(self, path, name, start_values, t0=0.0, tolerance=None):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Model
        from fmpy.simulation import apply_start_values

        self.md = read_model_description(str(path))
        self.unzip = extract(str(path))
        self.fmu = FMU2Model(guid=self.md.guid, unzipDirectory=self.unzip,
                             modelIdentifier=self.md.modelExchange.modelIdentifier,
                             instanceName=name)
        self.fmu.instantiate(loggingOn=False)
        self.fmu.setupExperiment(tolerance=tolerance, startTime=t0)
        self.vrs = {v.name: v.valueReference for v in self.md.modelVariables}
        apply_start_values(self.fmu, self.md, dict(start_values))
        self.fmu.enterInitializationMode()
        self.nx = self.md.numberOfContinuousStates
        self.nz = self.md.numberOfEventIndicators

    def vr(self, names):
        return [self.vrs[n] for n in names]

    def get(self, names):
        return np.array(self.fmu.getReal(self.vr(names)))

    def set(self, names, values):
        self.fmu.setReal(self.vr(names), [float(v) for v in values])

    def event_iteration(self):
        """newDiscreteStates until converged; returns the next time event (or inf)."""
        while True:
            need, terminate, _, _, defined, t_next = self.fmu.newDiscreteStates()
            if terminate:
                raise RuntimeError("the FMU asked to terminate")
            if not need:
                return t_next if defined else math.inf

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()
        shutil.rmtree(self.unzip, ignore_errors=True)


class System:
    """Rotor (force coupling) and bearing (motion coupling) as one ODE for CVODE."""

    def __init__(self, rotor: MeFmu, bearing: MeFmu):
        self.r, self.b = rotor, bearing
        self.nx = rotor.nx + bearing.nx
        self.nz = rotor.nz + bearing.nz
        self._jr, self._jb = rotor.vr(JOURNAL), bearing.vr(JOURNAL)
        self._fb, self._fr = bearing.vr(FORCE), rotor.vr(FORCE)

    def connect(self):
        """Journal from the rotor to the bearing, then the bearing's force back."""
        self.b.fmu.setReal(self._jb, self.r.fmu.getReal(self._jr))
        self.r.fmu.setReal(self._fr, self.b.fmu.getReal(self._fb))

    def _split(self, p, n):
        a = np.ctypeslib.as_array(p, (n,))
        return a, a[: self.r.nx], a[self.r.nx:]

    def set_time(self, t):
        self.r.fmu.setTime(t)
        self.b.fmu.setTime(t)

    def get_x(self, p, n):
        _, xr, xb = self._split(p, n)
        if self.r.nx:
            self.r.fmu.getContinuousStates(xr.ctypes.data_as(_DOUBLE_P), self.r.nx)
        self.b.fmu.getContinuousStates(xb.ctypes.data_as(_DOUBLE_P), self.b.nx)

    def set_x(self, p, n):
        _, xr, xb = self._split(p, n)
        if self.r.nx:
            self.r.fmu.setContinuousStates(xr.ctypes.data_as(_DOUBLE_P), self.r.nx)
        self.b.fmu.setContinuousStates(xb.ctypes.data_as(_DOUBLE_P), self.b.nx)
        self.connect()

    def get_dx(self, p, n):
        _, dr, db = self._split(p, n)
        if self.r.nx:
            self.r.fmu.getDerivatives(dr.ctypes.data_as(_DOUBLE_P), self.r.nx)
        self.b.fmu.getDerivatives(db.ctypes.data_as(_DOUBLE_P), self.b.nx)

    def get_z(self, p, n):
        a = np.ctypeslib.as_array(p, (n,))
        if self.r.nz:
            self.r.fmu.getEventIndicators(a[: self.r.nz].ctypes.data_as(_DOUBLE_P), self.r.nz)
        self.b.fmu.getEventIndicators(a[self.r.nz:].ctypes.data_as(_DOUBLE_P), self.b.nz)

    def get_nominals(self, p, n):
        _, xr, xb = self._split(p, n)
        if self.r.nx:
            self.r.fmu.getNominalsOfContinuousStates(xr.ctypes.data_as(_DOUBLE_P), self.r.nx)
        self.b.fmu.getNominalsOfContinuousStates(xb.ctypes.data_as(_DOUBLE_P), self.b.nx)


class _NoInput:
    """fmpy's CVodeSolver applies an input object in its root function; the system has none
    from outside."""

    def apply(self, *a, **k):
        pass


def run(rotor_start, bearing_start, stop, output_interval=1e-5, rtol=1e-8, record=None,
        rotor_fmu=None, bearing_fmu=None, speed_every=10, max_steps=100_000):
    """Integrates the rotor and bearing together from 0 to `stop`. `record(t, rotor, bearing)`
    is called at every output point (multiples of output_interval); the bearing takes the
    rotor's shaft speed at every `speed_every`-th of them. Returns the wall time and the count
    of events (each a CVODE restart)."""
    from fmpy.sundials import CVodeSolver

    b = MeFmu(bearing_fmu or cm.fmu_path("BallBearing"), "bearing",
              {**bearing_start, "coupling": 1})
    # The rotor's journal starts where the bearing's start loads put the ring.
    x0 = b.get(["ring.x", "ring.y", "ring.z"])
    r = MeFmu(rotor_fmu or cm.fmu_path("JeffcottRotor"), "rotor",
              {**rotor_start, "coupling": 0, **{f"journal.{a}0": v for a, v in zip("xyz", x0)}})
    sysm = System(r, b)
    wall = time.time()
    events = 0
    try:
        # Initialization: the journal and speed the bearing starts on come from the rotor.
        b.set(JOURNAL, r.get(JOURNAL))
        b.set(["shaft.speed"], r.get(["shaft.speed"]))
        r.set(FORCE, b.get(FORCE))
        r.fmu.exitInitializationMode()
        b.fmu.exitInitializationMode()
        t_event = min(r.event_iteration(), b.event_iteration())
        r.fmu.enterContinuousTimeMode()
        b.fmu.enterContinuousTimeMode()
        solver = CVodeSolver(nx=sysm.nx, nz=sysm.nz, get_x=sysm.get_x, set_x=sysm.set_x,
                             get_dx=sysm.get_dx, get_z=sysm.get_z,
                             get_nominals=sysm.get_nominals, set_time=sysm.set_time,
                             input=_NoInput(), startTime=0.0, maxStep=stop / 50,
                             relativeTolerance=rtol, maxNumSteps=max_steps)
        t, k = 0.0, 0
        if record:
            sysm.connect()
            record(t, r, b)
        while t < stop - 1e-12:
            t_out = min((k + 1) * output_interval, stop)
            t_next = min(t_out, t_event)
            state_event, _, t = solver.step(t, t_next)
            sysm.set_time(t)
            # (CVodeSolver.step has set the state it returns into the FMUs and connected them)
            step_r = r.fmu.completedIntegratorStep()[0]
            step_b = b.fmu.completedIntegratorStep()[0]
            at_out = abs(t - t_out) <= 1e-12 * max(1.0, t)
            speed_now = r.get(["shaft.speed"])
            speed_event = (at_out and (k + 1) % speed_every == 0
                           and speed_now[0] != b.get(["shaft.speed"])[0])
            time_event = abs(t - t_event) <= 1e-12 * max(1.0, t)
            if state_event or step_r or step_b or time_event or speed_event:
                events += 1
                r.fmu.enterEventMode()
                b.fmu.enterEventMode()
                if speed_event:
                    b.set(["shaft.speed"], speed_now)
                t_event = min(r.event_iteration(), b.event_iteration())
                r.fmu.enterContinuousTimeMode()
                b.fmu.enterContinuousTimeMode()
                x = np.empty(sysm.nx)
                sysm.get_x(x.ctypes.data_as(_DOUBLE_P), sysm.nx)
                sysm.set_x(x.ctypes.data_as(_DOUBLE_P), sysm.nx)
                solver.reset(t)
            if at_out:
                k += 1
                if record:
                    record(t, r, b)
        return {"wall": time.time() - wall, "events": events}
    finally:
        r.free()
        b.free()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stop", type=float, default=0.3)
    ap.add_argument("--rtol", type=float, default=1e-8)
    a = ap.parse_args()
    import build_ssp

    # The shipped system's rotor, its loads the defaults (its tlm loads act on the bearing).
    rotor = {k: v for k, v in build_ssp.ROTOR.items()
             if k not in ("coupling", "tlm.delay", "load.Fx", "load.Fz")}
    rotor["disk.axial"] = 0
    w = build_ssp.RUNUP["speed.initial"]
    # The bearing's start loads: the rotor's (its defaults) and the weight of journal and disk.
    bearing = {"fidelity": 2, "shaft.speed": w, "load.Fx": 4000.0, "load.Fy": 0.0,
               "load.Fz": -1000.0 - (build_ssp.JOURNAL_MASS + 8.0) * build_ssp.G}
    rows = []
    res = run(rotor, bearing, a.stop, output_interval=1e-4, rtol=a.rtol, speed_every=1,
              record=lambda t, r, b: rows.append((t, *r.get(["disk.z", "shaft.speed"]),
                                                 *b.get(["bearing.F.z"]))))
    rows = np.array(rows)
    print(f"{a.stop} s in {res['wall']:.1f} s wall, {res['events']} events; at the end: "
          f"disk.z {rows[-1, 1]:.4e} m, shaft.speed {rows[-1, 2]:.1f} rad/s, "
          f"bearing.F.z {rows[-1, 3]:.1f} N")


if __name__ == "__main__":
    main()
