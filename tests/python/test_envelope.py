"""The operating envelope through the FMU (issue 17, item 6), a sample: a handful of operating
points, each run by fmpy at every fidelity level in its own Python process with a timeout, so
that a hang fails the test instead of blocking it.

At each level a point must either simulate to the end with finite outputs (the cage speed in
(0, shaft speed), at rest near 0; the bearing force within 5 x (load + the balls' centrifugal
forces), the bound of `raceway envelope`) or stop with fmi2Error / fmi2Discard, which fmpy raises
(FMICallException) and the FMU explains in its log. The points are issue 17's: the partial load
zone (9900 rpm, Fa 1000 N, Fr 4000 N), Fr close to Fa, the operating points that hung or returned
garbage through fmpy, the shaft at rest, and a pure radial load, on a free ring (which an
angular-contact bearing cannot carry: a clear error) and on an axially located one (ring.axial = 1:
it must run at every level with the ring held in place). They are on the Table-1 bearing,
the one the FMU is built for; the whole grid over every preset runs through the library:
`raceway envelope --all-presets` (docs/envelope/envelope.md).

Run as a script (`python test_envelope.py FMU_DIR POINT_JSON`) this file is the worker: it prints
one `RESULT {...}` line per level as soon as the level is done.
"""

import json
import math
import os
import subprocess
import sys

import pytest

# (name, speed [rpm], Fa [N], Fr [N], pedestal stiffness [N/m] or None for the bearing's, spall,
# ring located axially)
POINTS = [
    ("partial-zone-9900rpm-fa1000-fr4000", 9900.0, 1000.0, 4000.0, None, True, False),
    ("fr-near-fa-4000rpm-fa4000-fr4250", 4000.0, 4000.0, 4250.0, None, True, False),
    ("fmpy-hang-5376rpm-fr3913.5", 5376.0, 4000.0, 3913.5, None, True, False),
    ("fmpy-garbage-7140rpm-fr3000-soft-pedestal", 7140.0, 4000.0, 3000.0, 5e6, False, False),
    ("at-rest-fa4000-fr1000", 0.0, 4000.0, 1000.0, None, True, False),
    ("pure-radial-9900rpm-fr4000", 9900.0, 0.0, 4000.0, None, False, False),
    ("pure-radial-9900rpm-fr4000-located", 9900.0, 0.0, 4000.0, None, True, True),
]

# The axial reaction of the located ring at 9900 rpm, Fr 4000 N [N] (L1: `raceway static --fr 4000
# --speed-rpm 9900 --axial-offset 0`): the axial load the bearing then carries.
LOCATED_REACTION = 3245.35

# Level code: (name, simulated time [s], communication step [s]), as `raceway envelope` runs them.
LEVELS = {
    0: ("kinematic", 0.1, 1e-3),
    1: ("quasi_static", 0.1, 1e-3),
    2: ("lumped", 0.02, 1e-3),
    3: ("reduced", 0.004, 5e-4),
    4: ("full", 0.004, 5e-4),
}

# Wall-time limit of one point's process (all five levels); a few seconds are normal.
TIMEOUT = 120.0

# Table-1 bearing: Z, ball mass [kg], pitch radius [m] (the balls' centrifugal forces at speed).
Z, BALL_MASS, PITCH_RADIUS = 14, 8.419e-3, 0.035
# Limiting speed [rad/s] of `raceway envelope` (dm n = 1e6 mm rpm): the rest bound is 1e-3 of it.
OMEGA_LIMIT = 1e6 / 70.0 * math.pi / 30.0


def run_level(ctx, probes, point, code):
    """Runs one level of the point through fmpy's FMU2Slave; never raises."""
    from fmpy.fmi1 import FMICallException

    name, rpm, fa, fr, k, spall, located = point
    _, duration, step = LEVELS[code]
    omega = rpm * math.pi / 30.0
    result = {"level": code, "completed": False, "stage": "instantiate", "t": 0.0}
    first_message = len(probes.MESSAGES)
    outputs = [v for v in ctx.md.modelVariables if v.causality == "output" and v.type == "Real"]
    refs = [v.valueReference for v in outputs]
    index = {v.name: i for i, v in enumerate(outputs)}
    track = {"nonfinite": [], "cage_min": math.inf, "cage_max": -math.inf, "max_f": 0.0,
             "ring_x": [math.inf, -math.inf]}

    def check(values, t):
        for v, x in zip(outputs, values):
            if not math.isfinite(x) and len(track["nonfinite"]) < 5:
                track["nonfinite"].append(f"{v.name} = {x} at t = {t:.6f} s")
        w = values[index["cage.speed"]]
        track["cage_min"] = min(track["cage_min"], w)
        track["cage_max"] = max(track["cage_max"], w)
        f = math.sqrt(sum(values[index[f"bearing.F.{a}"]] ** 2 for a in "xyz"))
        track["max_f"] = max(track["max_f"], f)
        x = values[index["ring.x"]]
        track["ring_x"] = [min(track["ring_x"][0], x), max(track["ring_x"][1], x)]

    s = None
    try:
        s = ctx.new(name=f"envelope-{code}", logging=False)
        result["stage"] = "initialization"
        s.setupExperiment(tolerance=1e-6, startTime=0.0, stopTime=duration)
        s.setInteger([ctx.vr["fidelity"]], [code])
        s.setInteger([ctx.vr["defect.ring"]], [1 if spall else 0])
        if k is not None:
            s.setReal([ctx.vr["pedestal.k_y"], ctx.vr["pedestal.k_z"]], [k, k])
        if located:
            s.setInteger([ctx.vr["ring.axial"]], [1])
        s.setReal([ctx.vr["shaft.speed"], ctx.vr["load.Fx"], ctx.vr["load.Fy"], ctx.vr["load.Fz"]],
                  [omega, fa, 0.0, -fr])
        s.enterInitializationMode()
        s.exitInitializationMode()
        check(s.getReal(refs), 0.0)
        result["stage"] = "step"
        n = int(round(duration / step))
        for i in range(n):
            t = i * step
            s.doStep(currentCommunicationPoint=t, communicationStepSize=step)
            result["t"] = (i + 1) * step
            check(s.getReal(refs), result["t"])
        result["completed"] = True
    except FMICallException as e:
        result["status"] = int(e.status)
        result["exception"] = str(e)
    except Exception as e:  # anything else from fmpy is a failure of the test, reported as such
        result["status"] = -1
        result["exception"] = f"{type(e).__name__}: {e}"
    finally:
        if s is not None:
            try:
                s.terminate()
                s.freeInstance()
            except Exception:
                pass
    result["log"] = [m for m in probes.MESSAGES[first_message:] if m[0] >= 2][-3:]
    result.update(track)
    return result


def worker(fmu_dir, point_json):
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import probes

    ctx = probes.Ctx(fmu_dir)
    point = tuple(json.loads(point_json))
    for code in LEVELS:
        r = run_level(ctx, probes, point, code)
        print("RESULT " + json.dumps(r), flush=True)


def problems_of(point, r):
    """What is wrong with one level's result (empty when it is fine)."""
    name, rpm, fa, fr, _, _, located = point
    level = LEVELS[r["level"]][0]
    omega = rpm * math.pi / 30.0
    if located:
        # The located ring carries the pure radial load at every level, held in place (at 0: no
        # load.Fx), with the location's reaction as its axial load.
        if not r["completed"]:
            return [f"{level}: a located ring must carry a pure radial load: "
                    f"{r.get('exception')} at {r['stage']}"]
        fa = LOCATED_REACTION
        if max(abs(v) for v in r["ring_x"]) > 1e-9:
            return [f"{level}: located ring.x moved: {r['ring_x']} m"]
    if not r["completed"]:
        # A failure must be a clear fmi2Discard or fmi2Error: fmpy raised, the FMU said why.
        bad = []
        if r.get("status") not in (2, 3):
            bad.append(f"{level}: failed with status {r.get('status')} at {r['stage']}: "
                       f"{r.get('exception')}")
        elif "failed with status" not in r.get("exception", ""):
            bad.append(f"{level}: fmpy did not raise FMICallException: {r.get('exception')}")
        messages = [m[2] for m in r["log"]]
        if not any(len(m) > 30 for m in messages):
            bad.append(f"{level}: {r.get('exception')} at {r['stage']}, t = {r['t']} s, without "
                       f"a message from the FMU (log: {messages})")
        return bad
    bad = [f"{level}: {x}" for x in r["nonfinite"]]
    if omega > 0:
        if not (r["cage_min"] > 0 and r["cage_max"] < omega):
            bad.append(f"{level}: cage.speed {r['cage_min']:.6g} … {r['cage_max']:.6g} rad/s "
                       f"outside (0, {omega:.6g})")
    elif max(abs(r["cage_min"]), abs(r["cage_max"])) > 1e-3 * OMEGA_LIMIT:
        bad.append(f"{level}: cage.speed {r['cage_min']:.3g} … {r['cage_max']:.3g} rad/s at rest")
    bound = 5.0 * (math.hypot(fa, fr) + Z * BALL_MASS * PITCH_RADIUS * omega ** 2)
    if not r["max_f"] <= bound:
        bad.append(f"{level}: |bearing.F| up to {r['max_f']:.6g} N (bound {bound:.6g} N)")
    return bad


@pytest.mark.parametrize("point", POINTS, ids=[p[0] for p in POINTS])
def test_point_runs_or_fails_clearly_at_every_level(fmu_dir, point):
    proc = subprocess.Popen(
        [sys.executable, os.path.abspath(__file__), str(fmu_dir), json.dumps(point)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    hung = False
    try:
        out, err = proc.communicate(timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        proc.kill()
        out, err = proc.communicate()
        hung = True
    results = [json.loads(line[len("RESULT "):]) for line in out.splitlines()
               if line.startswith("RESULT ")]
    done = {r["level"] for r in results}
    problems = []
    if hung:
        missing = [LEVELS[c][0] for c in LEVELS if c not in done]
        problems.append(f"hang: no result within {TIMEOUT:.0f} s at {missing[0]} "
                        f"(levels without a result: {', '.join(missing)})")
    elif proc.returncode != 0 or len(done) != len(LEVELS):
        problems.append(f"the worker died (exit code {proc.returncode}; a negative code is the "
                        f"signal that killed it) after levels {sorted(done)}:\n{err[-3000:]}")
    for r in results:
        problems += problems_of(point, r)
    summary = "\n".join(
        f"  {LEVELS[r['level']][0]}: " + (
            f"ok to t = {r['t']:.4f} s, cage {r['cage_min']:.6g} … {r['cage_max']:.6g} rad/s"
            if r["completed"] else
            f"{r.get('exception')} at {r['stage']}, t = {r['t']:.4f} s: "
            f"{[m[2] for m in r['log']]}")
        for r in results)
    assert not problems, ("\n".join(problems) + f"\nall levels of {point[0]}:\n{summary}")


if __name__ == "__main__":
    worker(sys.argv[1], sys.argv[2])
