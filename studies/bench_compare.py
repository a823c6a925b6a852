"""Compare two `raceway bench` runs on S2 at equal work (e.g. two step-size controllers).

Usage:
    python studies/bench_compare.py BASE_DIR OTHER_DIR [--levels reduced,full]

For every level and method present in both `bench.csv` files, prints a Markdown table: at the
RHS counts of OTHER's sweep, the E1 of each run (log-log interpolation along BASE's rtol sweep
for BASE), their ratio, and the E1-against-rtol slope of both sweeps over 1e-4 ... 1e-9 (the
acceptance measure of performance.md). A ratio below 1 means OTHER is more accurate at equal
work. The CSV reading, the interpolation and the slope are those of `bench_charts.py`.
"""

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench_charts import METHODS, load, loglog_interp, slope, sweep_rows  # noqa: E402


def sweep(rows, level, method):
    """The S2 runs that finished (status ok) of one level and method, by rtol, loosest first."""
    return [r for r in sweep_rows(rows, "S2", level, method) if r["status"] == "ok"]


def e1_at(sw, n):
    """E1 at RHS count n by log-log interpolation along the sweep (None outside it)."""
    pts = sorted((r["rhs_evals"], r["E1"]) for r in sw if r["E1"] > 0)
    return loglog_interp(pts, n)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("base")
    ap.add_argument("other")
    ap.add_argument("--levels", default="reduced,full")
    a = ap.parse_args()
    base, other = load(Path(a.base) / "bench.csv"), load(Path(a.other) / "bench.csv")
    print(f"| level | method | rtol ({a.other}) | RHS | E1 {a.other} | E1 {a.base} at equal RHS "
          f"| ratio |")
    print("|---|---|---|---|---|---|---|")
    slopes = []
    for level in a.levels.split(","):
        for method in METHODS:
            sb, so = sweep(base, level, method), sweep(other, level, method)
            if not sb or not so:
                continue
            for r in so:
                rt, n, e = r["rtol"], r["rhs_evals"], r["E1"]
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
