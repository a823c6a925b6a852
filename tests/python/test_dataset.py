"""The labelled data-set recipe (docs/sweeps.md#cwru): a slice of examples/sweeps/cwru-6205-de.toml
through `raceway sweep`, its features by examples/dataset_features.py, and the four classes apart.

The slice is the 12 runs at 1797 rpm, 500 N and 12 kHz (4 classes x 3 fault sizes; the healthy
class repeats over the size with its own noise and slip), 1 s each. Each class must be where its
fault frequency says: the outer-race faults' envelope line at BPFO, the inner-race ones' at BPFI,
the ball faults' at 2 x BSF (the run's own frequencies, from its results row), each far above the
healthy signals' lines there; and the nearest-centroid leave-one-out accuracy must be 1 (the
features script's command line prints it).
"""

import csv
import importlib.util
import subprocess
import sys
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
STUDY = REPO / "examples" / "sweeps" / "cwru-6205-de.toml"


def load_features():
    spec = importlib.util.spec_from_file_location(
        "dataset_features", REPO / "examples" / "dataset_features.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_cwru_recipe_separates_healthy_outer_inner_and_ball_faults(raceway, tmp_path):
    grid = subprocess.run(
        [str(raceway), "sweep", str(STUDY), "--list"], capture_output=True, text=True, check=True
    ).stdout
    rows = list(csv.DictReader(grid.splitlines()))
    assert len(rows) == 4 * 3 * 2 * 4 * 2
    pick = [
        r["run_index"]
        for r in rows
        if float(r["operating.speed_rpm"]) == 1797
        and float(r["operating.fr"]) == 500
        and float(r["output.sample_rate"]) == 12000
    ]
    assert len(pick) == 12
    out = tmp_path / "cwru"
    subprocess.run(
        [str(raceway), "sweep", str(STUDY), "--out", str(out), "--runs", ",".join(pick)],
        check=True,
        capture_output=True,
    )
    f = load_features()
    table = f.table(out, [1500.0, 5500.0])
    assert len(table) == 12
    assert sorted({r["class"] for r in table}) == sorted(f.CLASSES)

    def median(cls, key):
        return float(np.median([r[key] for r in table if r["class"] == cls]))

    for cls, line in [("outer", "env_bpfo"), ("inner", "env_bpfi"), ("ball", "env_two_bsf")]:
        lowest = min(r[line] for r in table if r["class"] == cls)
        healthy = max(r[line] for r in table if r["class"] == "none")
        assert lowest > 5 * healthy, (cls, line, lowest, healthy)
        # Its own line is its largest of the three.
        for other in {"env_bpfo", "env_bpfi", "env_two_bsf"} - {line}:
            assert median(cls, line) > median(cls, other), (cls, line, other)
    # The healthy signals are the 1 m/s^2 noise: RMS 1, Gaussian kurtosis 3, every one of them
    # (the bearing's own vibration is 3e-4 m/s^2; a lubricated ball re-entering the load zone
    # once switched in at 48 N, a burst that lifted a healthy run's kurtosis to 4, tests/film.rs).
    for r in table:
        if r["class"] == "none":
            assert abs(r["rms"] - 1.0) < 0.05 and abs(r["kurtosis"] - 3.0) < 0.2, r
    assert f.separation(table) == 1.0
    # The script's command line writes the table and the figure.
    done = subprocess.run(
        [sys.executable, str(REPO / "examples" / "dataset_features.py"), str(out)],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "leave-one-out accuracy: 1.000" in done.stdout, done.stdout
    assert (out / "features.png").stat().st_size > 10_000
    assert (out / "features.csv").is_file()
