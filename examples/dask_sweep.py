"""Spread a `raceway sweep` study over a dask.distributed cluster and gather the same table.

Usage:
    python examples/dask_sweep.py examples/sweeps/bench40.toml --out out/bench40-dask
    python examples/dask_sweep.py STUDY.toml --out DIR --scheduler tcp://host:8786
    python examples/dask_sweep.py STUDY.toml --out DIR --workers 4 --raceway target/release/raceway

Each task is one run of the grid: the worker calls
`raceway sweep STUDY.toml --runs INDEX --jobs 1 --out TMP` and returns the single row of TMP's
results.csv, so a row is computed by exactly the code of the rayon sweep (same run index, run id,
seeded noise and metrics). Rows are appended to DIR/results.csv as tasks finish; ids already in
the file are skipped, so an interrupted study resumes. DIR/results.sorted.csv is the canonical
copy (sorted by run index), comparable with a rayon sweep's results.sorted.csv once the
`wall_s` column is dropped.

Without --scheduler a LocalCluster with --workers processes (1 thread each) is started. With a
scheduler address on many machines, every worker must see the raceway binary, the sweep file and
its base scene at the same paths (a shared file system or the same checkout everywhere).
"""

import argparse
import csv
import io
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def default_raceway() -> Path:
    """The release binary in $CARGO_TARGET_DIR (or target/)."""
    if os.environ.get("RACEWAY_BIN"):
        return Path(os.environ["RACEWAY_BIN"])
    target = Path(os.environ.get("CARGO_TARGET_DIR") or REPO / "target")
    if not target.is_absolute():
        target = REPO / target
    return target / "release" / "raceway"


def list_runs(raceway: str, sweep: str):
    """(header, rows) of `raceway sweep --list`: run_index, run_id and the parameters."""
    out = subprocess.run(
        [raceway, "sweep", sweep, "--list"], capture_output=True, text=True, check=True
    ).stdout
    rows = list(csv.reader(io.StringIO(out)))
    return rows[0], rows[1:]


def run_one(raceway: str, sweep: str, index: int):
    """One task: run one grid point with the CLI and return (header, row) of its results.csv."""
    with tempfile.TemporaryDirectory(prefix="raceway-dask-") as tmp:
        proc = subprocess.run(
            [raceway, "sweep", sweep, "--runs", str(index), "--jobs", "1", "--quiet",
             "--out", tmp],
            capture_output=True,
            text=True,
        )
        if proc.returncode != 0:
            raise RuntimeError(f"run {index}: raceway sweep failed: {proc.stderr.strip()}")
        with open(Path(tmp) / "results.csv", newline="") as f:
            rows = list(csv.reader(f))
    if len(rows) != 2:
        raise RuntimeError(f"run {index}: expected one result row, got {len(rows) - 1}")
    return rows[0], rows[1]


def run_study(client, sweep, out, raceway=None, progress=True):
    """Runs every run of `sweep` not yet in out/results.csv on the cluster of `client`.

    Returns (ran, skipped). Writes out/results.csv (append order) and out/results.sorted.csv.
    """
    from distributed import as_completed

    raceway = str(Path(raceway or default_raceway()).resolve())
    sweep = str(Path(sweep).resolve())
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    _, grid = list_runs(raceway, sweep)
    results = out / "results.csv"
    done, header = set(), None
    if results.exists() and results.stat().st_size > 0:
        with open(results, newline="") as f:
            rows = list(csv.reader(f))
        header = rows[0]
        done = {r[1] for r in rows[1:] if len(r) == len(header)}
    todo = [int(r[0]) for r in grid if r[1] not in done]
    futures = client.map(run_one, [raceway] * len(todo), [sweep] * len(todo), todo, pure=False)
    n = 0
    with open(results, "a", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        for fut in as_completed(futures):
            h, row = fut.result()
            if header is None:
                header = h
                w.writerow(h)
            elif h != header:
                raise RuntimeError(f"{results} was written by a different sweep")
            w.writerow(row)
            f.flush()
            n += 1
            if progress:
                print(f"\r{n}/{len(todo)} runs", end="", file=sys.stderr, flush=True)
    if progress and todo:
        print(file=sys.stderr)
    with open(results, newline="") as f:
        rows = list(csv.reader(f))
    rows[1:] = sorted(rows[1:], key=lambda r: int(r[0]))
    with open(out / "results.sorted.csv", "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows(rows)
    return len(todo), len(grid) - len(todo)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sweep", help="sweep file (TOML)")
    ap.add_argument("--out", required=True, help="output folder (results.csv, resumable)")
    ap.add_argument("--scheduler", help="dask scheduler address; default: a LocalCluster")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes")
    ap.add_argument("--raceway", default=None, help="raceway binary (default: target/release)")
    a = ap.parse_args()
    from distributed import Client, LocalCluster

    if a.scheduler:
        client, cluster = Client(a.scheduler), None
    else:
        cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True)
        client = Client(cluster)
    try:
        ran, skipped = run_study(client, a.sweep, a.out, a.raceway)
        print(f"dask sweep: {ran} runs now, {skipped} already in {a.out}/results.csv "
              f"({len(client.scheduler_info()['workers'])} workers)")
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


if __name__ == "__main__":
    main()
