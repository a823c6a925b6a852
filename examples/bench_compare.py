"""Compare two `raceway bench` runs on S2 at equal work (e.g. two step-size controllers).

Usage:
    python examples/bench_compare.py BASE_DIR OTHER_DIR [--levels reduced,full]

For every level and method present in both `bench.csv` files, prints a Markdown table: at the
RHS counts of OTHER's sweep, the E1 of each run (log-log interpolation along BASE's rtol sweep
for BASE), their ratio, and the E1-against-rtol slope of both sweeps over 1e-4 ... 1e-9 (the
acceptance measure of performance.md). A ratio below 1 means OTHER is more accurate at equal
work. Standard library only.
"""

import argparse
import csv
import math
from pathlib import Path


def load(d):
    rows = []
    with open(Path(d) / "bench.csv") as f:
        for r in csv.DictReader(f):
            if r["scene"] != "S2" or r["status"] != "ok":
                continue
            rows.append((r["level"], r["method"], float(r["rtol"]), float(r["rhs_evals"]),
                         float(r["E1"])))
    return rows


def sweep(rows, level, method):
    return sorted(((rt, n, e) for lv, m, rt, n, e in rows if lv == level and m == method),
                  key=lambda x: x[1])


def e1_at(sw, n):
    """E1 at RHS count n by log-log interpolation along the sweep (None outside it)."""
    for (r0, n0, e0), (r1, n1, e1) in zip(sw, sw[1:]):
        if n0 <= n <= n1 and e0 > 0 and e1 > 0:
            f = (math.log(n) - math.log(n0)) / (math.log(n1) - math.log(n0))
            return math.exp(math.log(e0) + f * (math.log(e1) - math.log(e0)))
    return None


def slope(sw):
    pts = [(math.log10(rt), math.log10(e)) for rt, n, e in sw
           if 1e-9 * 0.999 <= rt <= 1e-4 * 1.001 and e > 0]
    if len(pts) < 3:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("other")
    ap.add_argument("--levels", default="reduced,full")
    a = ap.parse_args()
    base, other = load(a.base), load(a.other)
    print(f"| level | method | rtol ({a.other}) | RHS | E1 {a.other} | E1 {a.base} at equal RHS "
          f"| ratio |")
    print("|---|---|---|---|---|---|---|")
    slopes = []
    for level in a.levels.split(","):
        for method in ("rkf45", "dopri5", "dop853"):
            sb, so = sweep(base, level, method), sweep(other, level, method)
            if not sb or not so:
                continue
            for rt, n, e in sorted(so, key=lambda x: -x[0]):
                eb = e1_at(sb, n)
                ratio = f"{e / eb:.2f}" if eb else "–"
                ebs = f"{eb:.2e}" if eb else "outside the sweep"
                print(f"| {level} | {method} | {rt:.0e} | {n:.3g} | {e:.2e} | {ebs} | {ratio} |")
            slopes.append((level, method, slope(sb), slope(so)))
    print()
    print(f"| level | method | E1 slope {a.base} | E1 slope {a.other} |")
    print("|---|---|---|---|")
    for level, method, s0, s1 in slopes:
        f = (lambda s: f"{s:.2f}" if s is not None else "–")
        print(f"| {level} | {method} | {f(s0)} | {f(s1)} |")


if __name__ == "__main__":
    main()
