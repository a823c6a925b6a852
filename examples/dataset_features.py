"""Features of a labelled data set made by `raceway sweep` (raw signals kept), plotted by class.

Usage:
    raceway sweep examples/sweeps/cwru-6205-de.toml --out out/cwru-6205-de
    python examples/dataset_features.py out/cwru-6205-de [--plot features.png] [--csv features.csv]

For every signal of DIR/results.csv (status ok) it computes the usual features: RMS, kurtosis,
and the envelope spectrum's lines at the run's own fault frequencies (BPFO, BPFI, 2 x BSF and
the cage rate FTF, from the columns bpfo_hz, bpfi_hz, two_bsf_hz, ftf_hz), each as the line's
height over the median of the envelope spectrum around it (dimensionless, so that runs of
different loads and sample rates compare). The class is the label `defect.ring` (none, outer,
inner, ball). It plots BPFO against BPFI and 2 x BSF against kurtosis, coloured by class, and
reports how well the features separate the classes: the leave-one-out accuracy of a
nearest-centroid classifier on the standardized log features (1.0: every signal is nearer its
own class's centre than any other's).
"""

import argparse
import csv
import math
from pathlib import Path

import numpy as np
from scipy.signal import butter, hilbert, sosfiltfilt

CLASSES = ["none", "outer", "inner", "ball"]
LINES = ["bpfo", "bpfi", "two_bsf", "ftf"]
FEATURES = ["rms", "kurtosis"] + [f"env_{k}" for k in LINES]


def envelope_spectrum(x, fs, band):
    """One-sided amplitude spectrum of the band-passed signal's envelope (Hann window)."""
    lo, hi = band[0], min(band[1], 0.45 * fs)
    sos = butter(4, [lo, hi], btype="bandpass", fs=fs, output="sos")
    env = np.abs(hilbert(sosfiltfilt(sos, x)))
    env -= env.mean()
    w = np.hanning(len(env))
    spec = np.abs(np.fft.rfft(env * w)) * 2.0 / w.sum()
    return np.fft.rfftfreq(len(env), 1.0 / fs), spec


def line_ratio(freq, spec, f0, tol=0.02):
    """Largest bin within f0 (1 +- tol) (at least +-1.5 bins) over the median of the bins
    within +-25 % of f0."""
    reach = max(tol * f0, 1.5 * (freq[1] - freq[0]))
    near = np.abs(freq - f0) <= reach
    around = (freq > 0.75 * f0) & (freq < 1.25 * f0)
    if not near.any() or not around.any():
        return math.nan
    return float(spec[near].max() / max(np.median(spec[around]), 1e-300))


def features(signal_path, row, band):
    t, x = np.loadtxt(signal_path, delimiter=",", skiprows=1, unpack=True)
    fs = 1.0 / np.median(np.diff(t))
    x = x - x.mean()
    rms = float(np.sqrt(np.mean(x**2)))
    kurt = float(np.mean(x**4) / np.mean(x**2) ** 2)
    freq, spec = envelope_spectrum(x, fs, band)
    out = {"rms": rms, "kurtosis": kurt}
    for k in LINES:
        out[f"env_{k}"] = line_ratio(freq, spec, float(row[f"{k}_hz"]))
    return out


def table(folder, band):
    """One dict per ok row of folder/results.csv: its labels and features."""
    rows = []
    with open(Path(folder) / "results.csv", newline="") as f:
        for r in csv.DictReader(f):
            if r.get("status") != "ok" or not r.get("signal_file"):
                continue
            feats = features(Path(folder) / r["signal_file"], r, band)
            rows.append({"class": r["defect.ring"], **{k: r[k] for k in r if "." in k}, **feats})
    return rows


def separation(rows):
    """Leave-one-out accuracy of a nearest-centroid classifier on the standardized log features."""
    classes = [c for c in CLASSES if any(r["class"] == c for r in rows)]
    y = np.array([classes.index(r["class"]) for r in rows])
    x = np.log10(np.array([[max(r[k], 1e-300) for k in FEATURES] for r in rows]))
    x = (x - x.mean(axis=0)) / np.where(x.std(axis=0) > 0, x.std(axis=0), 1.0)
    hits = 0
    for i in range(len(rows)):
        keep = np.arange(len(rows)) != i
        centres = [x[keep & (y == c)].mean(axis=0) for c in range(len(classes))]
        guess = int(np.argmin([np.linalg.norm(x[i] - c) for c in centres]))
        hits += guess == y[i]
    return hits / len(rows)


def plot(rows, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.5))
    colours = {"none": "tab:gray", "outer": "tab:blue", "inner": "tab:orange", "ball": "tab:green"}
    for c in CLASSES:
        sel = [r for r in rows if r["class"] == c]
        if not sel:
            continue
        label = "healthy" if c == "none" else c
        axes[0].scatter([r["env_bpfo"] for r in sel], [r["env_bpfi"] for r in sel],
                        s=12, c=colours[c], label=label)
        axes[1].scatter([r["env_two_bsf"] for r in sel], [r["kurtosis"] for r in sel],
                        s=12, c=colours[c], label=label)
    for ax, (xl, yl) in zip(axes, [("BPFO", "BPFI"), ("2 x BSF", None)]):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(f"envelope line at {xl} / local median")
        ax.set_ylabel(f"envelope line at {yl} / local median" if yl else "kurtosis")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend()
    fig.suptitle(f"{len(rows)} signals")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("folder", help="the sweep's --out folder (results.csv and signals/)")
    ap.add_argument("--band", nargs=2, type=float, default=[1500.0, 5500.0],
                    help="envelope band-pass [Hz] (default 1500 5500)")
    ap.add_argument("--plot", default=None, help="figure path (default FOLDER/features.png)")
    ap.add_argument("--csv", default=None, help="features table (default FOLDER/features.csv)")
    a = ap.parse_args()
    rows = table(a.folder, a.band)
    if not rows:
        raise SystemExit(f"{a.folder}/results.csv has no ok row with a signal_file")
    out_csv = a.csv or str(Path(a.folder) / "features.csv")
    with open(out_csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    fig = a.plot or str(Path(a.folder) / "features.png")
    plot(rows, fig)
    print(f"{len(rows)} signals; medians by class:")
    print(f"  {'class':6} {'n':>4} " + " ".join(f"{k:>12}" for k in FEATURES))
    for c in CLASSES:
        sel = [r for r in rows if r["class"] == c]
        if sel:
            med = [np.median([r[k] for r in sel]) for k in FEATURES]
            print(f"  {c:6} {len(sel):4d} " + " ".join(f"{m:12.4g}" for m in med))
    print(f"nearest-centroid leave-one-out accuracy: {separation(rows):.3f}")
    print(f"wrote {out_csv} and {fig}")


if __name__ == "__main__":
    main()
