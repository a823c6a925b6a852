"""Spread a `raceway sweep` study over a dask.distributed cluster and gather the same table.

Usage:
    python examples/dask_sweep.py examples/sweeps/bench40.toml --out out/bench40-dask
    python examples/dask_sweep.py STUDY.toml --out DIR --scheduler tcp://host:8786
    python examples/dask_sweep.py STUDY.toml --out DIR --workers 4 --raceway target/release/raceway

Each task is one run of the grid: the worker calls
`raceway sweep STUDY.toml --runs INDEX --jobs 1 --out TMP` and returns TMP's results.csv (and the
raw signal of a study that keeps one, written to DIR/signals/ before the row is merged), so a
row is computed by exactly the code of the rayon sweep (same run index, run id, run key, seeded
noise and metrics). The table is read and written only by the CLI, with the reader of the rayon
sweep: `--pending` lists the runs DIR/results.csv does not have yet (it drops a last line cut
short by a kill and any row failing its check, and refuses a table of another study or model
version, saying what changed; `--new-table` keeps that one aside), and `--merge` appends each
finished task's row (checked against the run's key) and rewrites DIR/results.sorted.csv, the
canonical copy sorted by run index, comparable with a rayon sweep's once the `wall_s` and `check`
columns are dropped. An interrupted study resumes.

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


def cli(raceway: str, *args) -> str:
    """Runs the raceway CLI; its stdout (an error carries its stderr)."""
    proc = subprocess.run([raceway, *args], capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"raceway {' '.join(args[:2])}: {proc.stderr.strip()}")
    return proc.stdout


def pending_runs(raceway: str, sweep: str, out: Path, new_table=False):
    """Indices of the runs out/results.csv does not have yet (the CLI's reader decides)."""
    args = ["sweep", sweep, "--out", str(out), "--pending"] + (["--new-table"] if new_table else [])
    rows = list(csv.reader(io.StringIO(cli(raceway, *args))))
    return [int(r[0]) for r in rows[1:]]


def run_one(raceway: str, sweep: str, index: int):
    """One task: run one grid point with the CLI; its results.csv as text and the files its
    row points to (the raw signal of a study that keeps it) as {path in the folder: bytes}."""
    with tempfile.TemporaryDirectory(prefix="raceway-dask-") as tmp:
        cli(raceway, "sweep", sweep, "--runs", str(index), "--jobs", "1", "--quiet", "--out", tmp)
        files = {str(p.relative_to(tmp)): p.read_bytes()
                 for p in (Path(tmp) / "signals").glob("*") if p.is_file()}
        return (Path(tmp) / "results.csv").read_text(), files


def save_files(out: Path, files):
    """Writes a task's files under out (each to a temporary name, then renamed into place), so a
    row merged after them never points to a missing or partial file."""
    for rel, data in files.items():
        dest = out / rel
        dest.parent.mkdir(parents=True, exist_ok=True)
        part = dest.with_name(dest.name + ".part")
        part.write_bytes(data)
        os.replace(part, dest)


def run_study(client, sweep, out, raceway=None, progress=True, new_table=False):
    """Runs every run of `sweep` not yet in out/results.csv on the cluster of `client`.

    Returns (ran, skipped). Writes out/results.csv (append order) and out/results.sorted.csv.
    """
    from distributed import as_completed

    raceway = str(Path(raceway or default_raceway()).resolve())
    sweep = str(Path(sweep).resolve())
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    total = len(list(csv.reader(io.StringIO(cli(raceway, "sweep", sweep, "--list"))))) - 1
    todo = pending_runs(raceway, sweep, out, new_table)
    futures = client.map(run_one, [raceway] * len(todo), [sweep] * len(todo), todo, pure=False)
    n = 0
    with tempfile.TemporaryDirectory(prefix="raceway-dask-merge-") as tmp:
        for fut in as_completed(futures):
            table, files = fut.result()
            save_files(out, files)
            task = Path(tmp) / f"task-{n}.csv"
            task.write_text(table)
            cli(raceway, "sweep", sweep, "--out", str(out), "--merge", str(task), "--quiet")
            n += 1
            if progress:
                print(f"\r{n}/{len(todo)} runs", end="", file=sys.stderr, flush=True)
    if progress and todo:
        print(file=sys.stderr)
    if n == 0:  # nothing new: the canonical copy from the table as it stands
        cli(raceway, "sweep", sweep, "--out", str(out), "--merge", "--quiet")
    return len(todo), total - len(todo)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sweep", help="sweep file (TOML)")
    ap.add_argument("--out", required=True, help="output folder (results.csv, resumable)")
    ap.add_argument("--scheduler", help="dask scheduler address; default: a LocalCluster")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster worker processes")
    ap.add_argument("--raceway", default=None, help="raceway binary (default: target/release)")
    ap.add_argument("--new-table", action="store_true",
                    help="if DIR holds a table of another study or model version, keep it as "
                         "results.N.csv and start a new one (default: refuse)")
    a = ap.parse_args()
    from distributed import Client, LocalCluster

    if a.scheduler:
        client, cluster = Client(a.scheduler), None
    else:
        cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True)
        client = Client(cluster)
    try:
        ran, skipped = run_study(client, a.sweep, a.out, a.raceway, new_table=a.new_table)
        print(f"dask sweep: {ran} runs now, {skipped} already in {a.out}/results.csv "
              f"({len(client.scheduler_info()['workers'])} workers)")
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


if __name__ == "__main__":
    main()
