"""The FMU Compliance Checker (modelica-tools/FMUComplianceChecker) on both FMUs, as
Co-Simulation (`-k cs`) and as Model Exchange (`-k me`: the checker integrates with explicit
Euler at the step `-h`, so the step is short: the bearing's contacts are stiff for it).

The checker does not install from a package registry; its path comes from $FMUCHK (`.ci/run`
sets it when the project's tools provide one). Without it the tests skip with that reason."""

import os
import subprocess
from pathlib import Path

import pytest

from conftest import REPO, fmu_path

CHECKER = os.environ.get("FMUCHK")


# Checker options per interface: (step, stop time).
RUNS = {"cs": ("1e-4", "0.01"), "me": ("1e-6", "0.002")}


def checked(fmu: Path, tmp_path: Path, kind: str = "cs") -> str:
    if not CHECKER:
        pytest.skip("FMUCHK is not set (path of the FMU Compliance Checker, fmuCheck.linux64)")
    if not fmu.is_file():
        pytest.fail(f"{fmu} does not exist: build it with `cargo run --release -p fmu-build`")
    step, stop = RUNS[kind]
    proc = subprocess.run(
        [CHECKER, "-k", kind, "-h", step, "-s", stop, "-o", str(tmp_path / "out.csv"),
         "-t", str(tmp_path), str(fmu)],
        capture_output=True, text=True, timeout=600,
    )
    text = proc.stdout + proc.stderr
    assert proc.returncode == 0, text[-4000:]
    return text


@pytest.mark.parametrize("kind", ["cs", "me"])
@pytest.mark.parametrize("name", ["BallBearing", "JeffcottRotor"])
def test_compliance_checker_reports_no_warning_and_no_error(name, kind, tmp_path):
    fmu = fmu_path().with_name(f"{name}.fmu")
    text = checked(fmu, tmp_path, kind)
    assert "0 Warning(s)" in text and "0 Error(s)" in text, text[-4000:]
    if kind == "me":
        assert "FMU kind: ModelExchange and CoSimulation" in text, text[-4000:]
        # the checker simulated to the stop time: its output file ends there
        last = (tmp_path / "out.csv").read_text().strip().splitlines()[-1]
        assert float(last.split(",")[0]) == pytest.approx(float(RUNS[kind][1])), last
