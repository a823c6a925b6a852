#!/usr/bin/env python3
"""Which whirl state the full level's cage settles in, run by run (docs/research/cage.md#two-states).

Runs `raceway simulate` at the full level on the default scene (outer spall, Fa 4000 N,
Fr 1000 N, the default cage) at one shaft speed, once per tolerance and method, and prints per
run the cage centre's mean whirl radius and the RMS of `pedestal.a.z` over a window after the
start, and the same without the cage (`[full] cage = false`). Runs that differ only in their
tolerance or method differ by round-off-sized perturbations; where the runs split into groups
with different whirl radii and RMS that persist, the model has several steady states and a
perturbation picks one.

    cargo build --release --bin raceway
    python3 studies/cage_states.py [--speed 10100] [--duration 0.15] [--window 0.05]
        [--rtols 1e-6,5e-7,2e-7,1e-7,5e-8,2e-8,1e-9] [--methods dop853,dopri5]

Writes a Markdown table to stdout (the command line in its first line). No dependencies beyond
Python 3.
"""

import argparse
import csv
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = ROOT / "target" / "release" / "raceway"


def scene_text(speed, cage):
    """The default scene at `speed` rpm, with or without the cage."""
    text = (ROOT / "examples" / "scenes" / "default.toml").read_text()
    lines = []
    for line in text.splitlines():
        if line.strip().startswith("speed_rpm"):
            line = f"speed_rpm = {speed}"
        lines.append(line)
    out = "\n".join(lines) + "\n"
    if not cage:
        out += "\n[full]\ncage = false\n"
    return out


def run(scene, cage, method, rtol, duration, window, work):
    """(whirl radius [µm] or None, pedestal.a.z over the window, events, rejected, RHS) of one
    run."""
    out = work / f"run-{cage}-{method}-{rtol}.csv"
    columns = "pedestal.a.z,cage.y,cage.z" if cage else "pedestal.a.z"
    cmd = [str(BIN), "simulate", str(scene), "--fidelity", "full", "--duration", str(duration),
           "--rtol", rtol, "--method", method, "--columns", columns, "--quiet", "--out", str(out)]
    subprocess.run(cmd, check=True)
    whirl, acc = 0.0, []
    with open(out, newline="") as f:
        rows = csv.reader(f)
        header = next(rows)
        ia = header.index("pedestal.a.z")
        iy, iz = (header.index(c) for c in ("cage.y", "cage.z")) if cage else (None, None)
        for r in rows:
            if float(r[0]) < window:
                continue
            acc.append(float(r[ia]))
            if cage:
                whirl += math.hypot(float(r[iy]), float(r[iz]))
    s = json.loads(Path(str(out) + ".json").read_text())["solver"]
    w = whirl / len(acc) * 1e6 if cage else None
    return w, acc, s["events"], s["rejected"], s["rhs_evals"]


def rms(x):
    return math.sqrt(sum(v * v for v in x) / len(x))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--speed", type=float, default=10100.0)
    p.add_argument("--duration", type=float, default=0.15)
    p.add_argument("--window", type=float, default=0.05, help="start of the measured window [s]")
    p.add_argument("--rtols", default="1e-6,5e-7,2e-7,1e-7,5e-8,2e-8,1e-9")
    p.add_argument("--methods", default="dop853,dopri5")
    a = p.parse_args()
    if not BIN.is_file():
        sys.exit(f"{BIN} missing: run `cargo build --release --bin raceway` first")
    print(f"*Made by `{' '.join(['python3 studies/cage_states.py'] + sys.argv[1:])}`.* Full level, "
          f"default scene at {a.speed:g} rpm, {a.duration:g} s simulated; whirl radius (the cage "
          f"centre's mean distance from the bearing axis) and RMS of `pedestal.a.z` over "
          f"t ≥ {a.window:g} s.\n")
    rtols = a.rtols.split(",")
    methods = a.methods.split(",")
    # The loosest and the tightest rtol, once each when they are one.
    ends = list(dict.fromkeys([rtols[0], rtols[-1]]))
    print(f"E1: relative RMS difference of `pedestal.a.z` over the window against the run with "
          f"the cage setting's tightest rtol ({rtols[-1]}) and the first method ({methods[0]}).\n")
    print("| cage | method | rtol | whirl radius [µm] | RMS pedestal.a.z [m/s²] | E1 | events | rejected | RHS |")
    print("|---|---|---|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for cage in (True, False):
            scene = work / f"scene-{cage}.toml"
            scene.write_text(scene_text(a.speed, cage))
            # Cage on: every rtol with the first method, the loosest and tightest with the
            # others; cage off: the loosest and tightest with the first method.
            plan = [(methods[0], r) for r in (rtols if cage else ends)]
            if cage:
                plan += [(m, r) for m in methods[1:] for r in ends]
            results = [(m, r, run(scene, cage, m, r, a.duration, a.window, work)) for m, r in plan]
            ref = next(res[1] for m, r, res in results if m == methods[0] and r == rtols[-1])
            for m, r, (w, acc, ev, rej, rhs) in results:
                n = min(len(acc), len(ref))
                e1 = rms([x - y for x, y in zip(acc[:n], ref[:n])]) / rms(ref[:n])
                whirl = f"{w:.1f}" if w is not None else "–"
                print(f"| {'on' if cage else 'off'} | {m} | {r} | {whirl} | {rms(acc):.0f} | "
                      f"{e1:.1e} | {ev} | {rej} | {rhs} |", flush=True)


if __name__ == "__main__":
    main()
