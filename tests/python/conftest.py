"""Shared fixtures of the FMU tests: where the FMU is, its unzipped copy, and the probe runner.

The FMU is taken from $RACEWAY_FMU, else from <target dir>/fmu/BallBearing.fmu with the target
dir from $CARGO_TARGET_DIR or <repo>/target. Build it first with
`cargo run --release -p fmu-build`.
"""

import json
import os
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PROBES = Path(__file__).with_name("probes.py")


def fmu_path() -> Path:
    if os.environ.get("RACEWAY_FMU"):
        return Path(os.environ["RACEWAY_FMU"])
    target = Path(os.environ.get("CARGO_TARGET_DIR") or REPO / "target")
    if not target.is_absolute():
        target = REPO / target
    return target / "fmu" / "BallBearing.fmu"


@pytest.fixture(scope="session")
def raceway():
    """The raceway CLI: $RACEWAY_BIN, else the release binary, built here."""
    if os.environ.get("RACEWAY_BIN"):
        return Path(os.environ["RACEWAY_BIN"])
    subprocess.run(
        ["cargo", "build", "--quiet", "--release", "--bin", "raceway"], cwd=REPO, check=True
    )
    target = Path(os.environ.get("CARGO_TARGET_DIR") or REPO / "target")
    if not target.is_absolute():
        target = REPO / target
    return target / "release" / "raceway"


@pytest.fixture(scope="session")
def fmu():
    p = fmu_path()
    if not p.is_file():
        pytest.fail(f"{p} does not exist: build it with `cargo run --release -p fmu-build`")
    return p


@pytest.fixture(scope="session")
def fmu_dir(fmu, tmp_path_factory):
    d = tmp_path_factory.mktemp("BallBearing fmu")  # a space: the resource URI is percent-encoded
    with zipfile.ZipFile(fmu) as z:
        z.extractall(d)
    so = d / "binaries" / "linux64" / "BallBearing.so"
    so.chmod(0o755)
    return d


def run_probe(fmu_dir, name, *args, timeout=600, coupling=0):
    """Runs one probe in a fresh Python process; a crash or a missing result fails the test.
    `coupling` (0 force, 1 motion) is the FMU parameter the probe's instances get."""
    env = dict(os.environ, RACEWAY_PROBE_COUPLING=str(int(coupling)))
    proc = subprocess.run(
        [sys.executable, str(PROBES), name, str(fmu_dir), *map(str, args)],
        capture_output=True,
        text=True,
        timeout=timeout,
        env=env,
    )
    for line in proc.stdout.splitlines():
        if line.startswith("RESULT "):
            if proc.returncode != 0:
                break
            return json.loads(line[len("RESULT "):])
    pytest.fail(
        f"probe '{name}' did not complete (exit code {proc.returncode}; a negative code is the "
        f"signal that killed it)\n--- stdout ---\n{proc.stdout[-4000:]}\n--- stderr ---\n{proc.stderr[-4000:]}"
    )


@pytest.fixture(scope="session")
def probe(fmu_dir):
    return lambda name, *args, **kw: run_probe(fmu_dir, name, *args, **kw)


@pytest.fixture(scope="session")
def dynamics(probe):
    """Skips a test that needs the dynamic model while Simulation::advance is not wired yet."""
    r = probe("advance_check")
    if not r["ok"]:
        if "unsupported" in r["message"]:
            pytest.skip("the dynamic model is not available yet (Simulation::advance: "
                        f"{r['message']})")
        pytest.fail(f"the first fmi2DoStep of the default scene failed: {r}")
    return True
