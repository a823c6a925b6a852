"""Builds the rotor <-> bearing system of SystemStructure.ssd programmatically in libcosimpy
(no SSP file): the same FMUs, parameters and connections (taken from build_ssp.py), run with
libcosim's fixed-step (Jacobi) master.

Usage: python examples/systems/rotor_bearing_libcosim.py [--stop 1.1] [--step 1e-4]
                                                         [--out out/systems/libcosim_api.npz]
"""

import argparse
import pathlib
import sys

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent))
import build_ssp  # noqa: E402
from cosim_master import fmu_path  # noqa: E402


def parameters_from_ssd():
    """Per-component parameter values as written in the committed SystemStructure.ssd."""
    import xml.etree.ElementTree as ET

    ns = {"ssd": "http://ssp-standard.org/SSP1/SystemStructureDescription",
          "ssv": "http://ssp-standard.org/SSP1/SystemStructureParameterValues"}
    root = ET.parse(build_ssp.SSD).getroot()
    out = {}
    for comp in root.iter(f"{{{ns['ssd']}}}Component"):
        vals = {}
        for p in comp.iter(f"{{{ns['ssv']}}}Parameter"):
            (v,) = list(p)
            kind = v.tag.split("}")[1]
            vals[p.get("name")] = int(v.get("value")) if kind == "Integer" else float(v.get("value"))
        out[comp.get("name")] = vals
    return out


def quiet():
    """libcosim logs every FMU message at trace level by default: warnings and up only."""
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level

    log_output_level(CosimLogLevel.WARNING)


def build(step):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimSlave import CosimLocalSlave

    quiet()
    ex = CosimExecution.from_step_size(step_size=int(round(step * 1e9)))
    idx, names = {}, {}
    for comp, fmu in (("rotor", "JeffcottRotor"), ("bearing", "BallBearing")):
        idx[comp] = ex.add_local_slave(CosimLocalSlave(fmu_path=str(fmu_path(fmu)), instance_name=comp))
        names[comp] = {(v.name.decode() if isinstance(v.name, bytes) else v.name): v.reference
                       for v in ex.slave_variables(idx[comp])}
    for comp, vals in parameters_from_ssd().items():
        for k, v in vals.items():
            if isinstance(v, int):
                assert ex.integer_initial_value(idx[comp], names[comp][k], v), (comp, k)
            else:
                assert ex.real_initial_value(idx[comp], names[comp][k], v), (comp, k)
    for se, sc, ee, ec in build_ssp.CONNECTIONS:
        ex.connect_real_variables(idx[se], names[se][sc], idx[ee], names[ee][ec])
    return ex, idx, names


def record(ex, idx, names, stop, step, signals):
    """Runs to `stop` and returns {"time": ..., "<comp>.<var>": ...} from a time-series observer."""
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimObserver import CosimObserver

    n = int(round(stop / step))
    obs = CosimObserver.create_time_series(buffer_size=n + 10)
    ex.add_observer(obs)
    for comp, var in signals:
        obs.start_time_series(idx[comp], names[comp][var], CosimVariableType.REAL)
    assert ex.simulate_until(target_time=int(round(stop * 1e9))), "libcosim simulation failed"
    out = {}
    for comp, var in signals:
        vals, steps, times = [], [], []
        start = 0
        while start < n:
            # (libcosimpy drops samples whose step number is 0 from what it returns)
            t, s, v = obs.time_series_real_samples(idx[comp], names[comp][var], from_step=start,
                                                  sample_count=min(50000, n + 1))
            if not s:
                break
            times += t
            steps += s
            vals += v
            start = s[-1] + 1
        out[f"{comp}.{var}"] = np.array(vals)
        out["time"] = np.array(times) * 1e-9
    return out


SIGNALS = ([("rotor", f"journal.{a}") for a in "xyz"] + [("rotor", "disk.y"), ("rotor", "disk.z"),
           ("rotor", "shaft.speed"), ("rotor", "shaft.angle"), ("bearing", "ring.y"), ("bearing", "ring.z"),
           ("bearing", "bearing.F.z"), ("bearing", "cage.speed"), ("bearing", "pedestal.a.z")])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stop", type=float, default=build_ssp.STOP)
    ap.add_argument("--step", type=float, default=build_ssp.STEP)
    ap.add_argument("--out", default="out/systems/libcosim_api.npz")
    a = ap.parse_args()
    ex, idx, names = build(a.step)
    res = record(ex, idx, names, a.stop, a.step, SIGNALS)
    out = pathlib.Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    np.savez(out, **res)
    print(f"wrote {out} ({len(res['time'])} samples, t = {res['time'][0]} .. {res['time'][-1]} s)")


if __name__ == "__main__":
    main()
