"""Two-way rotor <-> BallBearing co-simulation (motion mode), issue #6 acceptance in small:
the constant-input boundary against omega H = 4 zeta, the interface Jacobian at H = 1 ms, the
convergence to the monolithic force-mode reference, and the SSP system in libcosimpy and fmpy.
The full-size numbers are in docs/coupling.md (studies/coupling_study.py)."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "examples"))
sys.path.insert(0, str(REPO / "examples" / "systems"))
sys.path.insert(0, str(REPO / "studies"))
import cosim_master as cm  # noqa: E402
import coupling_study as cs  # noqa: E402


@pytest.fixture(scope="module")
def fmus():
    for name in ("JeffcottRotor", "BallBearing"):
        p = cm.fmu_path(name)
        if not p.is_file():
            pytest.fail(f"{p} does not exist: build it with `cargo run --release -p fmu-build`")
    from fmpy import read_model_description

    md = read_model_description(str(cm.fmu_path("BallBearing")))
    if not any(v.name == "coupling" for v in md.modelVariables):
        pytest.skip("this BallBearing.fmu has no motion mode (parameter 'coupling')")
    return True


@pytest.fixture(scope="module")
def journal_mode(fmus):
    """Stiffness and damping of the 2 kg rigid rotor's journal on the bearing (part B setup)."""
    b = cm.Fmu(cm.fmu_path("BallBearing"), "bearing", cs.bearing_start(cs.M_RIGID, 0.0, cs.B_BEARING))
    b.exit_init()
    Kx, Kv = cs.reaction_jacobian(b)
    b.free()
    w, zb, _ = cs.modal(cs.M_RIGID, -Kx, -Kv)
    return -Kx, -Kv, w, zb


def _growth(rotor_params, H, scheme, T):
    r, b, _ = cs.coupled_pair(rotor_params, cs.bearing_start(cs.M_RIGID, 0.0, cs.B_BEARING),
                              cs.B_OFFSET)
    try:
        res = cm.run_coupled(r, b, H, T, scheme, feedthrough=True, blowup=1e-4)
    finally:
        r.free()
        b.free()
    if not res["ok"]:
        return math.inf
    return max(cm.growth_rate(res["t"], res["x"][:, i]) for i in (1, 2))


def test_directional_derivatives_give_a_stiff_symmetric_bearing(journal_mode):
    K, C, w, _ = journal_mode
    # radial stiffness of the order of the L1 value (1e8 N/m), positive definite, nearly symmetric
    assert np.all(np.linalg.eigvalsh(0.5 * (K + K.T)) > 1e7)
    assert np.max(np.abs(K - K.T)) < 0.05 * np.max(np.abs(K))


def test_constant_input_boundary_within_15_percent_of_4_zeta(journal_mode):
    K, C, w, zb = journal_mode
    zeta = 0.05
    wmax = float(np.max(w))
    cj = 2 * zeta * cs.M_RIGID * wmax - 2 * cs.M_RIGID * wmax * zb[np.argmax(w)]
    wm, zm, _ = cs.modal(cs.M_RIGID, K, C + cj * np.eye(3))
    h_pred = float(np.min(4 * zm / wm))
    rotor = {"disk.mass": 0.0, "journal.mass": cs.M_RIGID, "unbalance": 0.0,
             "speed.initial": 0.0, "speed.final": 0.0, "journal.c": cj}
    T = 30 * 2 * math.pi / wmax
    assert _growth(rotor, 0.85 * h_pred, "constant", T) < 0
    assert _growth(rotor, 1.15 * h_pred, "constant", T) > 0


@pytest.mark.xfail(
    strict=False,
    reason="issue 19: at 1 ms the interface-Jacobian scheme stays bounded or settles into a larger "
    "orbit depending on the spall's frequency. At 9900 rpm the journal's excursion grows from 2.5 "
    "to 15 um over 0.3 s with the caged traction cage speed (69.95 Hz) and stays at 1.2 um with "
    "L1's (70.38 Hz); the build before the caged solve stayed at 1.8 um with 69.97 Hz and grew to "
    "4.4 um with 70.42 Hz. A 1 ms step sits at this scheme's stability edge.",
)
def test_interface_jacobian_is_stable_at_1ms_for_the_default_rotor_on_a_grounded_bearing(fmus):
    # the default (flexible, 10 kg) rotor at 9900 rpm with the spall; a grounded outer ring keeps
    # the bearing's internal journal-pedestal mode out (see docs/coupling.md, part B)
    r, b, x0 = cs.coupled_pair({}, cs.bearing_start(10.0, 9900.0, cs.GROUNDED), cs.B_OFFSET)
    try:
        res = cm.run_coupled(r, b, 1e-3, 0.1, "jacobian", feedthrough=True, blowup=1e-3)
    finally:
        r.free()
        b.free()
    assert res["ok"], res["error"]
    # no growth: the last quarter stays within 1.5 x the excursion of the first half
    dev = np.max(np.abs(res["x"] - x0), axis=1)
    assert np.max(dev[-25:]) <= 1.5 * np.max(dev[:50])


def test_step_sensitivity_coupling_is_stable_at_1ms_for_the_default_rotor(fmus):
    # default rotor, default (spalled) bearing with its pedestal, 9900 rpm: the instantaneous
    # Jacobian blows up at 1 ms (docs/coupling.md, part B); the rolled-back step sensitivity not
    r, b, x0 = cs.coupled_pair({}, cs.bearing_start(10.0, 9900.0), cs.B_OFFSET)
    try:
        res = cm.run_coupled(r, b, 1e-3, 0.1, "implicit", feedthrough=True, blowup=1e-3)
    finally:
        r.free()
        b.free()
    assert res["ok"], res["error"]
    dev = np.max(np.abs(res["x"] - x0), axis=1)
    assert np.max(dev[-25:]) <= 1.5 * np.max(dev[:50])
    assert np.max(dev) < 2e-5  # the unbalance/spall response is a few µm


def test_cosimulation_converges_towards_the_monolithic_reference(fmus, monkeypatch):
    # force mode with the rotor mass in the inner ring and the unbalance as a rotating load,
    # against the two-way co-simulation with the interface Jacobian (docs/coupling.md, part C)
    monkeypatch.setattr(cs, "C_T", 0.006)
    t_ref, x_ref = cs.monolithic_reference(2e-6)
    errs = []
    for H in (2e-5, 5e-6):
        res = cs.cosim_run(H, "jacobian")
        assert res["ok"], res["error"]
        xr = np.array([np.interp(res["t"], t_ref, x_ref[:, i]) for i in range(3)]).T
        errs.append(np.max(np.abs(res["x"][:, 1:] - xr[:, 1:])))
    amp = np.max(np.abs(x_ref[:, 1:] - x_ref[0, 1:]))
    assert errs[1] < 0.25 * amp
    assert errs[1] < errs[0] / 2  # 4x smaller step: more than 2x smaller error


@pytest.mark.xfail(
    strict=False,
    reason="issue 19: fmpy and libcosim differ pointwise by where the spall's impulses fall on the "
    "communication grid, so the difference moves with the cage speed: journal.z by 3.7 % of its "
    "range with L1's cage speed, 5.3-6.6 % with the former traction speed, 11.7 % with the caged "
    "one (69.95 Hz) against the 8 % this test allows. Issue 19 removes the master dependence.",
)
def test_ssp_system_same_outputs_in_libcosim_and_fmpy(fmus, tmp_path, monkeypatch):
    pytest.importorskip("libcosimpy")
    import build_ssp
    import run_system

    # the committed system at constant speed (no ramp: keeps the test short)
    text = build_ssp.SSD.read_text()
    rate = '<ssv:Parameter name="speed.rate"><ssv:Real value="600.0"/></ssv:Parameter>'
    assert rate in text
    ssd = tmp_path / "SystemStructure.ssd"
    ssd.write_text(text.replace(rate, rate.replace("600.0", "0.0")))
    ssp = tmp_path / "RotorBearing.ssp"
    subprocess.run([sys.executable, str(REPO / "examples/systems/build_ssp.py"), "--out", str(ssp),
                    "--ssd", str(ssd)], check=True, capture_output=True)
    monkeypatch.setattr(run_system, "SSP", ssp)
    monkeypatch.setattr(build_ssp, "SSD", ssd)  # the programmatic build reads its parameters
    stop, step = 0.25, build_ssp.STEP
    a = run_system.run_libcosim_ssp(stop, step)
    b = run_system.run_fmpy_ssp(stop, step)
    c = run_system.run_libcosim_api(stop, step)
    t = a["time"]
    late = t > 0.2  # after fmpy's start transient (its connections start at 0.0)
    # The two masters differ pointwise by a steady amount, not a decaying transient: journal.z
    # by 5.3-6.6 % of its range in every 50 ms window from 0.1 to 0.45 s, disk.z by 0.1-0.7 %
    # (measured with the traction cage speed; 3.7 % with L1's, where the spall impulses fell
    # differently on the communication grid).
    for key, tol in (("rotor.journal.z", 0.08), ("rotor.disk.z", 0.02), ("bearing.bearing.F.z", None)):
        yb = np.interp(t, b["time"], b[key])
        yc = np.interp(t, c["time"], c[key])
        assert np.all(np.isfinite(a[key])) and np.all(np.isfinite(b[key]))
        # the SSP file and the programmatic build are the same system for libcosim (bitwise at
        # constant speed; with a speed ramp they differ by ~2e-5 of the value, see the report)
        assert np.max(np.abs(yc - a[key])) <= 1e-12 * np.max(np.abs(a[key]))
        if tol is not None:  # pointwise, relative to the dynamic range
            assert np.max(np.abs(yb[late] - a[key][late])) < tol * np.ptp(a[key][late]), key
        # the spall's force impulses make pointwise F sensitive to sub-step history: the mean
        assert abs(np.mean(yb[late]) / np.mean(a[key][late]) - 1) < 1e-3, key
