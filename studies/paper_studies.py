"""Regenerate the paper-study plots of docs/sweeps.md (Niu et al. 2014, Sec. 3.2-3.4).

Usage:
    python studies/paper_studies.py [--raceway target/release/raceway] [--jobs 2]
                                     [--out out/sweeps] [--img docs/img] [--no-run]

Runs `raceway sweep` on examples/sweeps/sec3.2-speed.toml, sec3.3-width.toml and
sec3.4-position.toml (resumable: finished runs are kept in OUT/<study>/results.csv), then plots
the impact force (the median over ball passes of the largest force on the defective race in each
pass; the largest outer- and inner-race forces of the run are shown faintly) against the
swept parameter for each fidelity level, saves IMG/sweep-<study>.png and prints the numbers as
Markdown tables (pasted into docs/sweeps.md).
"""

import argparse
import csv
import os
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
STUDIES = [
    # (study, x column, x label, x scale, curve column)
    ("sec3.2-speed", "operating.speed_rpm", "shaft speed [rpm]", 1.0, "fidelity"),
    ("sec3.3-width", "defect.width", "spall width [mm]", 1e3, "fidelity"),
    ("sec3.3-width-blend", "defect.width", "spall width [mm], edge stiffness blended over b",
     1e3, "fidelity"),
    ("sec3.4-position", "defect.theta0", "spall position theta_d0 [rad] (pi = load-zone centre)",
     1.0, "fidelity"),
    ("sec3.4-position-blend", "defect.theta0",
     "spall position theta_d0 [rad] (pi = load-zone centre), edge stiffness blended over b", 1.0,
     "fidelity"),
    ("sec3.4-speed-position", "defect.theta0",
     "spall position theta_d0 [rad] (pi = load-zone centre), full level", 1.0,
     "operating.speed_rpm"),
]


def default_raceway():
    target = Path(os.environ.get("CARGO_TARGET_DIR") or REPO / "target")
    if not target.is_absolute():
        target = REPO / target
    return target / "release" / "raceway"


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return sorted(rows, key=lambda r: int(r["run_index"]))


def series(rows, xcol, scale, group="fidelity"):
    """{fidelity: [(x, impact, max_q_outer, max_q_inner, status, segment_max)]} sorted by x;
    impact is impact_q_zone where the level records passes, else impact_q_median."""
    out = {}
    for r in rows:
        fid = r.get(group, "base")
        if group != "fidelity":
            fid = f"{float(fid):g} rpm" if group == "operating.speed_rpm" else fid
        ok = r["status"] == "ok"
        vals = [float(r[k]) if ok else float("nan")
                for k in ("impact_q_zone", "max_q_outer", "max_q_inner", "impact_q_median")]
        seg = vals.pop()
        if ok and not int(r.get("impact_passes", "0") or 0):
            vals[0] = seg
        out.setdefault(fid, []).append((float(r[xcol]) * scale, *vals, r["status"], seg))
    for v in out.values():
        v.sort()
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--raceway", default=None)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--out", default=str(REPO / "out" / "sweeps"))
    ap.add_argument("--img", default=str(REPO / "docs" / "img"))
    ap.add_argument("--no-run", action="store_true", help="only plot existing results")
    a = ap.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    raceway = str(a.raceway or default_raceway())
    Path(a.img).mkdir(parents=True, exist_ok=True)
    for study, xcol, xlabel, scale, group in STUDIES:
        out = Path(a.out) / study
        if not a.no_run:
            subprocess.run(
                [raceway, "sweep", str(REPO / "examples" / "sweeps" / f"{study}.toml"),
                 "--out", str(out), "--jobs", str(a.jobs)],
                check=True,
            )
        data = series(read(out / "results.csv"), xcol, scale, group)
        fig, ax = plt.subplots(figsize=(10, 4.2))
        for fid, pts in data.items():
            xs = [p[0] for p in pts]
            label = ("impact: median over passes of the largest force inside the spall zone"
                     if fid != "lumped" else "median over 1/BPFO segments of the largest race force")
            line, = ax.plot(xs, [p[1] for p in pts], "o-", lw=2, label=f"{fid}: {label}")
            if fid != "lumped":
                ax.plot(xs, [p[5] for p in pts], "s--", color=line.get_color(), alpha=0.6,
                        label=f"{fid}: old measure, segment maximum (incl. rattling after exit)")
            ax.plot(xs, [p[2] for p in pts], "^:", color=line.get_color(), alpha=0.5,
                    label=f"{fid}: largest outer-race force")
            ax.plot(xs, [p[3] for p in pts], "v:", color=line.get_color(), alpha=0.3,
                    label=f"{fid}: largest inner-race force")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("contact force on the races [N]")
        ax.set_yscale("log")
        ax.set_title(f"{study}: impact force")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
        fig.tight_layout()
        png = Path(a.img) / f"sweep-{study}.png"
        fig.savefig(png, dpi=110)
        plt.close(fig)
        print(f"\n### {study}  ({png.relative_to(REPO) if png.is_relative_to(REPO) else png})\n")
        fids = list(data)
        print("| " + xlabel + " | " + " | ".join(
            f"{f}: impact / segment max / max Q_out / max Q_in [N]" for f in fids) + " |")
        print("|---" * (len(fids) + 1) + "|")
        xs = sorted({p[0] for pts in data.values() for p in pts})
        for x in xs:
            cells = []
            for f in fids:
                p = next((p for p in data[f] if p[0] == x), None)
                cells.append("—" if p is None or p[4] != "ok"
                             else f"**{p[1]:.0f}** / {p[5]:.0f} / {p[2]:.0f} / {p[3]:.0f}")
            print(f"| {x:g} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
