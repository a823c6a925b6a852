"""examples/dask_sweep.py on a LocalCluster with 2 workers gives the rayon sweep's table.

A 6-run study (3 spall widths x 2 noise levels, 0.05 s simulated each, raw signals kept) is run once by
`raceway sweep --jobs 2` and once through dask; the tables, sorted by run index and without the
wall_s and check columns, must be equal; resuming after dropped rows or a last line cut short by
a kill gives the same table, and another study into the same folder is refused. The raceway binary is conftest.py's ($RACEWAY_BIN, or built with
`cargo build --release --bin raceway` into $CARGO_TARGET_DIR or target/).
"""

import csv
import importlib.util
import subprocess
from pathlib import Path

import pytest

distributed = pytest.importorskip("distributed")

REPO = Path(__file__).resolve().parents[2]

STUDY = """
name = "dask-test"
base = "{base}"
[set]
"output.duration" = 0.05
"output.skip" = 0.01
[axes]
"defect.width" = [0.8e-3, 1.2e-3, 1.6e-3]
"noise.rms" = [0.0, 15.0]
[keep]
harmonics = 2
raw_signal = true
"""


def load_example():
    spec = importlib.util.spec_from_file_location("dask_sweep", REPO / "examples" / "dask_sweep.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def canonical(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    drop = {rows[0].index("wall_s"), rows[0].index("check")}  # machine-dependent, and its check
    strip = [[v for i, v in enumerate(r) if i not in drop] for r in rows]
    return strip[0], sorted(strip[1:], key=lambda r: int(r[0]))


def test_dask_table_equals_rayon_table(tmp_path, raceway):
    study = tmp_path / "study.toml"
    study.write_text(STUDY.format(base=(REPO / "examples/scenes/default.toml").as_posix()))
    subprocess.run(
        [str(raceway), "sweep", str(study), "--out", str(tmp_path / "rayon"), "--jobs", "2",
         "--quiet"],
        check=True,
    )
    mod = load_example()
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        assert len(client.scheduler_info()["workers"]) == 2
        ran, skipped = mod.run_study(client, study, tmp_path / "dask", raceway, progress=False)
        assert (ran, skipped) == (6, 0)
        # Resume: drop the last 2 rows, only those 2 runs are run again.
        results = tmp_path / "dask" / "results.csv"
        lines = results.read_text().splitlines(keepends=True)
        results.write_text("".join(lines[:-2]))
        ran, skipped = mod.run_study(client, study, tmp_path / "dask", raceway, progress=False)
        assert (ran, skipped) == (2, 4)
        # A last line cut short by a kill (issue 21: it swallowed the next row): dropped by the
        # CLI's reader and run again.
        lines = results.read_text().splitlines(keepends=True)
        results.write_text("".join(lines[:-1]) + lines[-1][: len(lines[-1]) // 2])
        ran, skipped = mod.run_study(client, study, tmp_path / "dask", raceway, progress=False)
        assert (ran, skipped) == (1, 5)
        # Another study into the same folder: refused with what changed.
        other = tmp_path / "other.toml"
        other.write_text(study.read_text().replace('"output.duration" = 0.05',
                                                   '"output.duration" = 0.06'))
        with pytest.raises(RuntimeError, match="set.output.duration: 0.05 → 0.06"):
            mod.run_study(client, other, tmp_path / "dask", raceway, progress=False)

    h1, r1 = canonical(tmp_path / "rayon" / "results.csv")
    h2, r2 = canonical(tmp_path / "dask" / "results.csv")
    assert h1 == h2
    assert len(r1) == 6
    assert all(r[h1.index("status")] == "ok" for r in r1)
    assert r1 == r2
    assert canonical(tmp_path / "dask" / "results.sorted.csv") == (h2, r2)
    # The raw signals come back from the workers: the same files, byte for byte.
    names = [r[h1.index("signal_file")] for r in r1]
    assert all(n.startswith("signals/") for n in names)
    for n in names:
        assert (tmp_path / "dask" / n).read_bytes() == (tmp_path / "rayon" / n).read_bytes(), n
    assert not list((tmp_path / "dask" / "signals").glob("*.part"))
