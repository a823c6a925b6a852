"""The FMU Compliance Checker (modelica-tools/FMUComplianceChecker) on both FMUs.

The checker does not install from a package registry; its path comes from $FMUCHK (`.ci/run`
sets it when the project's tools provide one). Without it the tests skip with that reason."""

import os
import subprocess
from pathlib import Path

import pytest

from conftest import REPO, fmu_path

CHECKER = os.environ.get("FMUCHK")


def checked(fmu: Path, tmp_path: Path) -> str:
    if not CHECKER:
        pytest.skip("FMUCHK is not set (path of the FMU Compliance Checker, fmuCheck.linux64)")
    if not fmu.is_file():
        pytest.fail(f"{fmu} does not exist: build it with `cargo run --release -p fmu-build`")
    proc = subprocess.run(
        [CHECKER, "-k", "cs", "-h", "1e-4", "-s", "0.01", "-o", str(tmp_path / "out.csv"),
         "-t", str(tmp_path), str(fmu)],
        capture_output=True, text=True, timeout=600,
    )
    text = proc.stdout + proc.stderr
    assert proc.returncode == 0, text[-4000:]
    return text


@pytest.mark.parametrize("name", ["BallBearing", "JeffcottRotor"])
def test_compliance_checker_reports_no_warning_and_no_error(name, tmp_path):
    fmu = fmu_path().with_name(f"{name}.fmu")
    text = checked(fmu, tmp_path)
    assert "0 Warning(s)" in text and "0 Error(s)" in text, text[-4000:]
