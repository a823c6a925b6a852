"""The journal's start position for the rotor <-> bearing system: where the BallBearing (motion
mode) puts the inner ring under the rotor's static loads (its external load and weight) at the
start speed, read from the FMU in initialization mode (same frame and origin as ring.x/y/z)."""

import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
import cosim_master as cm  # noqa: E402


def rotor_defaults():
    from fmpy import read_model_description

    md = read_model_description(str(cm.fmu_path("JeffcottRotor")))
    return {v.name: float(v.start) for v in md.modelVariables if v.causality == "parameter"}


def journal_equilibrium(speed, rotor=None, bearing_extra=None):
    p = rotor_defaults()
    p.update(rotor or {})
    weight = (p["journal.mass"] + p["disk.mass"]) * p["gravity"]
    sv = {"coupling": 1, "shaft.speed": speed, "load.Fx": p["load.Fx"], "load.Fy": p["load.Fy"],
          "load.Fz": p["load.Fz"] - weight, **(bearing_extra or {})}
    b = cm.Fmu(cm.fmu_path("BallBearing"), "statics", sv)
    try:
        return [float(v) for v in b.get(["ring.x", "ring.y", "ring.z"])]
    finally:
        b.slave.freeInstance()


if __name__ == "__main__":
    print(journal_equilibrium(float(sys.argv[1]) if len(sys.argv) > 1 else 0.0))
