"""Tests of the JeffcottRotor FMU (target/fmu/JeffcottRotor.fmu, built by
`cargo run --release -p fmu-build`) and of the co-simulation master in examples/cosim_master.py.

The stability checks couple the rotor FMU to a linear bearing stand-in (F = -k x - c v) for which
the closed-form limits are known (docs/model.md#coupling-stability)."""

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "examples"))
import cosim_master as cm  # noqa: E402

# The full FMI 2.0 set: the common and Co-Simulation functions, then Model Exchange's.
FMI2_FUNCTIONS = {
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate",
    "fmi2FreeInstance", "fmi2SetupExperiment", "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset", "fmi2GetReal", "fmi2GetInteger",
    "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal", "fmi2SetInteger", "fmi2SetBoolean",
    "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate", "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives", "fmi2DoStep", "fmi2CancelStep", "fmi2GetStatus",
    "fmi2GetRealStatus", "fmi2GetIntegerStatus", "fmi2GetBooleanStatus", "fmi2GetStringStatus",
    "fmi2EnterEventMode", "fmi2NewDiscreteStates", "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep", "fmi2SetTime", "fmi2SetContinuousStates", "fmi2GetDerivatives",
    "fmi2GetEventIndicators", "fmi2GetContinuousStates", "fmi2GetNominalsOfContinuousStates",
}
assert len(FMI2_FUNCTIONS) == 44

M, K = 2.0, 1.3e8
W = np.sqrt(K / M)
RIGID = {"disk.mass": 0.0, "journal.mass": M, "gravity": 0.0, "load.Fx": 0.0, "load.Fz": 0.0,
         "unbalance": 0.0, "journal.y0": 1e-6, "journal.z0": 0.5e-6}


@pytest.fixture(scope="session")
def rotor_fmu():
    p = cm.fmu_path("JeffcottRotor")
    if not p.is_file():
        pytest.fail(f"{p} does not exist: build it with `cargo run --release -p fmu-build`")
    return p


def test_rotor_fmu_validates(rotor_fmu):
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(rotor_fmu)) == []


def test_rotor_library_exports_exactly_one_set_of_fmi2_functions(rotor_fmu, tmp_path):
    if shutil.which("nm") is None:
        pytest.skip("nm not available")
    with zipfile.ZipFile(rotor_fmu) as z:
        z.extract("binaries/linux64/JeffcottRotor.so", tmp_path)
    out = subprocess.run(["nm", "-D", "--defined-only",
                          str(tmp_path / "binaries/linux64/JeffcottRotor.so")],
                         capture_output=True, text=True, check=True).stdout
    names = [line.split()[-1] for line in out.splitlines() if line.strip()]
    fmi = [n for n in names if n.startswith("fmi2")]
    assert sorted(fmi) == sorted(FMI2_FUNCTIONS)  # each once, nothing else named fmi2*


def _run(rotor_fmu, zeta, wH, scheme, periods=60, feedthrough=True):
    c = 2 * zeta * M * W
    H = wH / W
    rot = cm.Fmu(rotor_fmu, "rotor", RIGID)
    try:
        b = cm.LinearBearing(-K * np.eye(3), -c * np.eye(3))
        r = cm.run_coupled(rot, b, H, max(periods * 2 * np.pi / W, 40 * H), scheme,
                           feedthrough=feedthrough)
    finally:
        rot.free()
    return r


@pytest.mark.parametrize("zeta", [0.02, 0.05])
def test_constant_input_coupling_boundary_is_omega_h_4_zeta(rotor_fmu, zeta):
    below = _run(rotor_fmu, zeta, 0.85 * 4 * zeta, "constant")
    above = _run(rotor_fmu, zeta, 1.15 * 4 * zeta, "constant")
    assert below["ok"] and cm.growth_rate(below["t"], below["x"][:, 1]) < 0
    assert (not above["ok"]) or cm.growth_rate(above["t"], above["x"][:, 1]) > 0


def test_linear_extrapolation_boundary_matches_the_spec_table(rotor_fmu):
    # docs/model.md#coupling-stability: omega H < 0.50 for zeta = 0.02 with linear extrapolation
    below = _run(rotor_fmu, 0.02, 0.45, "extrapolate")
    above = _run(rotor_fmu, 0.02, 0.55, "extrapolate")
    assert below["ok"] and cm.growth_rate(below["t"], below["x"][:, 1]) < 0
    assert (not above["ok"]) or cm.growth_rate(above["t"], above["x"][:, 1]) > 0


def test_interface_jacobian_coupling_is_exact_for_a_linear_bearing(rotor_fmu):
    # omega H = 8, a hundred times the explicit limit: stable, and the free vibration equals
    # the closed-form damped oscillator (the rotor integrates F = -k x - c v itself)
    zeta = 0.02
    r = _run(rotor_fmu, zeta, 8.0, "jacobian", periods=30, feedthrough=False)
    assert r["ok"]
    t = r["t"]
    wd = W * np.sqrt(1 - zeta**2)
    exact = 1e-6 * np.exp(-zeta * W * t) * (np.cos(wd * t) + zeta * W / wd * np.sin(wd * t))
    assert np.max(np.abs(r["x"][:, 1] - exact)) < 1e-3 * 1e-6


def test_fmu_state_roundtrip_continues_identically(rotor_fmu):
    from fmpy.fmi2 import FMU2Slave  # noqa: F401  (the Fmu wrapper uses it)

    rot = cm.Fmu(rotor_fmu, "rotor", {"speed.initial": 100.0, "speed.final": 800.0,
                                      "speed.rate": 4000.0})
    rot.exit_init()
    s = rot.slave
    rot.set(cm.BF, [0.0, 5.0, 30.0])
    rot.step(0.0, 1e-3)
    state = s.getFMUstate()
    blob = s.serializeFMUstate(state)
    names = cm.JX + cm.JV + ["disk.z", "shaft.angle"]
    rot.step(1e-3, 2e-3)
    a = rot.get(names)
    s.setFMUstate(state)
    rot.step(1e-3, 2e-3)
    b = rot.get(names)
    s.setFMUstate(s.deSerializeFMUstate(blob))
    rot.step(1e-3, 2e-3)
    c = rot.get(names)
    s.freeFMUstate(state)
    rot.free()
    assert np.array_equal(a, b) and np.array_equal(a, c)


def test_invalid_parameter_is_rejected(rotor_fmu):
    rot = cm.Fmu(rotor_fmu, "rotor", {"disk.mass": 5.0, "shaft.k": 0.0})
    with pytest.raises(Exception):
        rot.exit_init()
    rot.slave.freeInstance()
