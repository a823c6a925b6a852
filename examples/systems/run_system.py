"""Runs the rotor <-> bearing SSP (target/fmu/RotorBearing.ssp, packed by build_ssp.py) in
libcosimpy (CosimExecution.from_ssp_file) and in fmpy (fmpy.ssp.simulate_ssp), and the same
system built programmatically in libcosimpy (rotor_bearing_libcosim.py); compares their rotor
and bearing outputs and draws the run-up's order/waterfall plot.

Usage: python examples/systems/run_system.py [--stop 1.1] [--masters libcosim-ssp,fmpy-ssp,libcosim-api]
                                             [--out docs/img/runup_waterfall.png]
                                             [--summary docs/coupling/ssp.json]

fmpy's simulate_ssp (fmpy 0.3.x) and what this script does about it:
- it ignores the SSD's ParameterBindings; the script reads them (fmpy.ssp.ssd.read_ssd) and
  passes them as its `parameter_set` argument, names prefixed with the component;
- it starts every connection at 0.0 (not at the outputs after initialization), so each FMU's
  first step sees 0.0 on its inputs (a shaft speed of 0, no line force); the script patches it to
  hand the outputs after initialization to the connected inputs first, as libcosim does
  (`_fmpy_with_start_values`);
- it records each row with the time at the *start* of the step that produced it (one-step
  label shift), which the comparison corrects (row k is t_{k+1});
- fixed step, Jacobi order (all components step, then all connections are applied).
"""

import argparse
import json
import math
import os
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
import build_ssp  # noqa: E402
import rotor_bearing_libcosim as api  # noqa: E402
from cosim_master import fmu_path  # noqa: E402

SSP = fmu_path("BallBearing").parent / "RotorBearing.ssp"
COMPARE = ["bearing.ring.z", "rotor.disk.z", "bearing.bearing.F.z"]


def run_libcosim_ssp(stop, step):
    import shutil
    import tempfile
    import zipfile

    from libcosimpy.CosimExecution import CosimExecution

    # libcosim reads an SSP directory (SystemStructure.ssd + the FMUs it names)
    api.quiet()
    d = pathlib.Path(tempfile.mkdtemp(prefix="rotor-bearing-ssp-"))
    with zipfile.ZipFile(SSP) as z:
        z.extractall(d)
    ex = CosimExecution.from_ssp_file(str(d), step_size=int(round(step * 1e9)))
    idx, names = {}, {}
    for comp in ("rotor", "bearing"):
        idx[comp] = ex.slave_index_from_instance_name(comp)
        names[comp] = {(v.name.decode() if isinstance(v.name, bytes) else v.name): v.reference
                       for v in ex.slave_variables(idx[comp])}
    res = api.record(ex, idx, names, stop, step, api.SIGNALS)
    shutil.rmtree(d, ignore_errors=True)
    return res


def run_libcosim_api(stop, step):
    ex, idx, names = api.build(step)
    return api.record(ex, idx, names, stop, step, api.SIGNALS)


def _fmpy_with_start_values():
    """fmpy's simulate_ssp (0.3.x) starts every connection at 0.0, so each FMU's first step gets
    0.0 on its inputs (here shaft.speed = 0 and no line force on the bearing for 0.1 ms, and the
    bearing's start equilibrium without the disk's weight: a different system from the one the
    SSD describes). This patch initializes the FMUs in the SSD's order and, in each one's
    initialization mode, sets its inputs from the outputs of those already initialized, as
    libcosim's initialization does. Returns the function that undoes it."""
    import fmpy.ssp.simulation as sim
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    orig_conn, orig_inst = sim.get_connections, sim.instantiate_fmu
    state = {"connections": [], "done": []}

    def get_connections(system):
        state["connections"] = orig_conn(system)
        return state["connections"]

    def instantiate_fmu(component, ssp_unzipdir, start_time, stop_time=None, parameter_set=None):
        # fmpy's instantiate_fmu for FMI 2.0, plus the inputs set in initialization mode
        path = os.path.join(ssp_unzipdir, component.source)
        component.unzipdir = extract(path)
        md = read_model_description(path, validate=False)
        component.variables = {v.name: v for v in md.modelVariables}
        component.fmu = FMU2Slave(guid=md.guid, unzipDirectory=component.unzipdir,
                                  modelIdentifier=md.coSimulation.modelIdentifier,
                                  instanceName=component.name)
        component.fmu.instantiate()
        component.fmu.setupExperiment(startTime=start_time)
        if parameter_set is not None:
            sim.set_parameters(component, parameter_set)
        component.fmu.enterInitializationMode()
        for a, b in state["connections"]:
            if b in component.connectors and a.value is not None:
                sim.set_value(component, b.name, a.value)
                b.value = a.value
        component.fmu.exitInitializationMode()
        for conn in component.connectors:
            if conn.kind == "output":
                conn.value = sim.get_value(component, conn.name)
        for a, b in state["connections"]:
            if a in component.connectors:
                b.value = a.value

    sim.get_connections, sim.instantiate_fmu = get_connections, instantiate_fmu

    def undo():
        sim.get_connections, sim.instantiate_fmu = orig_conn, orig_inst
    return undo


def run_fmpy_ssp(stop, step, start_values=True):
    from fmpy.ssp.simulation import simulate_ssp
    from fmpy.ssp.ssd import ParameterSet, read_ssd

    ssd = read_ssd(str(SSP))
    pset = ParameterSet(name="bindings")
    for comp in ssd.system.elements:
        for binding in comp.parameterBindings:
            for ps in binding.parameterValues:
                for p in ps.parameters:
                    p.name = f"{comp.name}.{p.name}"
                    pset.parameters.append(p)
    undo = _fmpy_with_start_values() if start_values else (lambda: None)
    try:
        r = simulate_ssp(str(SSP), stop_time=stop, step_size=step, parameter_set=pset)
    finally:
        undo()
    out = {"time": r["time"] + step}  # fmpy labels a row with the start of its step
    for comp, var in api.SIGNALS:
        key = f"{comp}.{var}"
        if key in r.dtype.names:
            out[key] = r[key]
    return out


MASTERS = {"libcosim-ssp": run_libcosim_ssp, "fmpy-ssp": run_fmpy_ssp,
           "libcosim-api": run_libcosim_api}


def order_track(t, x, phase, speed, window=0.04, skip=0.05):
    """The 1x order of x(t): least-squares fit of a + b cos(phase) + c sin(phase) over windows of
    `window` seconds (hop a quarter of it) after `skip`; returns (speed [rpm], amplitude)."""
    dt = t[1] - t[0]
    seg = int(round(window / dt))
    rpm, amp = [], []
    for a in range(int(round(skip / dt)), len(x) - seg, seg // 4):
        p = phase[a:a + seg]
        A = np.column_stack([np.ones(seg), np.cos(p), np.sin(p)])
        amp.append(float(np.hypot(*np.linalg.lstsq(A, x[a:a + seg], rcond=None)[0][1:])))
        rpm.append(float(np.mean(speed[a:a + seg]) * 30 / math.pi))
    return np.array(rpm), np.array(amp)


def waterfall(res, out, title):
    """Order map (STFT of rotor.disk.z against shaft speed) and the 1x order track."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = res["time"]
    dt = t[1] - t[0]
    z = res["rotor.disk.z"]
    spd = res["rotor.shaft.speed"]
    seg = int(round(0.04 / dt))
    hop = seg // 4
    win = np.hanning(seg)
    rows, rpms = [], []
    for a in range(int(round(0.05 / dt)), len(z) - seg, hop):
        x = z[a:a + seg]
        rows.append(np.abs(np.fft.rfft((x - x.mean()) * win)) * 2 / win.sum())
        rpms.append(np.mean(spd[a:a + seg]) * 30 / math.pi)
    f = np.fft.rfftfreq(seg, dt)
    S = np.array(rows)
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    fmax = 1200.0
    sel = f < fmax
    pc = ax[0].pcolormesh(f[sel], rpms, 20 * np.log10(S[:, sel] * 1e6 + 1e-6), shading="auto",
                          cmap="viridis")
    fig.colorbar(pc, ax=ax[0], label="disk z [dB re 1 µm]")
    rr = np.array(rpms)
    for order, lab in ((1, "1×"), (2, "2×")):
        ax[0].plot(order * rr / 60, rr, "w--", lw=0.8)
        ax[0].text(order * rr[-1] / 60, rr[-1], lab, color="w")
    if "bearing.cage.speed" in res:
        c = np.interp(rr, spd * 30 / math.pi, res["bearing.cage.speed"])
        ax[0].plot(14 * c / (2 * math.pi), rr, "r:", lw=0.8)
        ax[0].text(min(fmax * 0.8, 14 * c[0] / (2 * math.pi)), rr[0], "BPFO", color="r")
    ax[0].set_xlim(0, fmax)
    ax[0].set_xlabel("frequency [Hz]")
    ax[0].set_ylabel("shaft speed [rpm]")
    ax[0].set_title("Run-up waterfall (disk z)")
    # 1x order track
    _, amp1 = order_track(t, z, res["phase"], spd)
    ax[1].plot(rr, np.array(amp1) * 1e6, "C0-", label="disk z, 1× order")
    ax[1].set_xlabel("shaft speed [rpm]")
    ax[1].set_ylabel("1× amplitude [µm]")
    ax[1].set_title(title)
    ax[1].grid(alpha=0.3)
    ax[1].legend()
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    i = int(np.argmax(amp1))
    return {"peak_rpm": float(rr[i]), "peak_amp_um": float(amp1[i] * 1e6)}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stop", type=float, default=build_ssp.STOP)
    ap.add_argument("--step", type=float, default=build_ssp.STEP)
    ap.add_argument("--masters", default="libcosim-ssp,fmpy-ssp,libcosim-api")
    ap.add_argument("--out", default=str(HERE.parents[1] / "docs" / "img" / "runup_waterfall.png"))
    ap.add_argument("--summary", default=str(HERE.parents[1] / "docs" / "coupling" / "ssp.json"))
    a = ap.parse_args()
    if not SSP.is_file():
        sys.exit(f"{SSP} does not exist: run examples/systems/build_ssp.py first")
    results, wall = {}, {}
    for m in a.masters.split(","):
        t0 = time.time()
        results[m] = MASTERS[m](a.stop, a.step)
        wall[m] = time.time() - t0
        print(f"{m}: {len(results[m]['time'])} samples in {wall[m]:.1f} s", flush=True)
    summary = {"stop": a.stop, "step": a.step, "wall_s": wall, "compare": {}}
    names = list(results)
    ref = names[0]
    for m in names[1:]:
        for key in COMPARE:
            if key not in results[m] or key not in results[ref]:
                continue
            t = results[ref]["time"]
            y = np.interp(t, results[m]["time"], results[m][key])
            x = results[ref][key]
            late = t > 0.2  # after the start transients (fmpy's zero first step)
            scale = float(np.max(np.abs(x[late] - np.mean(x[late]))))
            d_all = float(np.max(np.abs(y - x)))
            d_late = float(np.max(np.abs(y[late] - x[late])))
            summary["compare"][f"{m} vs {ref}: {key}"] = {
                "max_diff": d_all, "max_diff_after_0.2s": d_late, "dynamic_range": scale,
                "rel_after_0.2s": d_late / scale if scale else None}
            print(f"{m} vs {ref}: {key}: max diff {d_all:.3e}, after 0.2 s {d_late:.3e} "
                  f"({d_late / scale:.2e} of the dynamic range)", flush=True)
    r = results[ref]
    dt = r["time"][1] - r["time"][0]
    w = r["rotor.shaft.speed"]
    r["phase"] = np.cumsum(w) * dt
    summary["runup"] = waterfall(r, pathlib.Path(a.out),
                                 f"Run-up {w[0] * 30 / math.pi:.0f} → {w[-1] * 30 / math.pi:.0f} rpm ({ref})")
    print(f"run-up: 1x peak {summary['runup']['peak_amp_um']:.1f} um at {summary['runup']['peak_rpm']:.0f} rpm")
    pathlib.Path(a.summary).parent.mkdir(parents=True, exist_ok=True)
    pathlib.Path(a.summary).write_text(json.dumps(summary, indent=1))
    print(f"wrote {a.out}, {a.summary}")


if __name__ == "__main__":
    main()
