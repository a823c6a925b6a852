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


def _tlm(H, T, rpm=9900.0, rotor=None):
    r, b = cs.tlm_pair(rotor or {}, rpm, H)
    try:
        return cm.run_tlm(r, b, H, T, blowup=1e-3)
    finally:
        r.free()
        b.free()


@pytest.fixture(scope="module")
def tlm_reference(fmus):
    """The transmission-line coupling at 1 us (the line's parasitic mass k_s T^2 = 2e-6 kg): the
    converged co-simulation the coarser steps are compared with (docs/coupling.md shows it agrees
    with the constant-input motion coupling at 1 us)."""
    return _tlm(1e-6, 0.05)


@pytest.mark.parametrize("H", [1e-6, 1e-5, 1e-4, 1e-3])
def test_tlm_coupling_is_stable_at_every_step_without_a_damper(fmus, H):
    # default rotor (no journal damper), default spalled bearing with its pedestal, 9900 rpm,
    # plain value exchange: bounded at every step from 1 us to 1 ms
    T = 0.3 if H >= 1e-4 else 0.05
    res = _tlm(H, T)
    assert res["ok"], res["error"]
    n = len(res["t"])
    dev = np.max(np.abs(res["x"] - res["x"][0]), axis=1)
    assert np.max(dev[-n // 4:]) <= 1.5 * np.max(dev[: n // 2])
    assert np.max(dev) < 5e-5  # the unbalance and spall response: tens of micrometres at most


def test_tlm_coupling_is_accurate_at_0_1ms(tlm_reference):
    ref = tlm_reference
    res = _tlm(1e-4, 0.05)
    assert res["ok"], res["error"]
    k = np.searchsorted(ref["t"], res["t"] - 1e-12)
    for name, a, b, tol in (("journal z", res["x"][:, 2], ref["x"][k, 2], 0.05),
                            ("disk z", res["disk"][:, 1], ref["disk"][k, 1], 0.02)):
        err = np.max(np.abs(a - b))
        assert err < tol * np.ptp(b), f"{name}: {err} against a range of {np.ptp(b)}"


def test_constant_input_beyond_the_stable_step_warns(fmus, capfd):
    # the plain constant-input scheme of motion coupling at 20 us (stable below ~0.6 us on the
    # bearing's own damping): the bearing logs its stable step at initialization and the first
    # longer step warns at warning level
    r, b, _ = cs.coupled_pair({}, cs.bearing_start(10.0, 9900.0), cs.B_OFFSET)
    try:
        cm.run_coupled(r, b, 2e-5, 2e-4, "constant", feedthrough=True)
    finally:
        r.free()
        b.free()
    out = capfd.readouterr().out
    assert "[WARNING]" in out and "is longer than" in out, out[-2000:]


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


def test_ssp_system_same_outputs_in_libcosim_and_fmpy(fmus, tmp_path, monkeypatch):
    pytest.importorskip("libcosimpy")
    import build_ssp
    import run_system

    # the committed system: a run-up through the critical speed at a 0.1 ms communication step
    ssp = tmp_path / "RotorBearing.ssp"
    subprocess.run([sys.executable, str(REPO / "examples/systems/build_ssp.py"), "--out", str(ssp)],
                   check=True, capture_output=True)
    monkeypatch.setattr(run_system, "SSP", ssp)
    stop, step = build_ssp.STOP, build_ssp.STEP
    a = run_system.run_libcosim_ssp(stop, step)
    b = run_system.run_fmpy_ssp(stop, step)
    c = run_system.run_libcosim_api(stop, step)
    t = a["time"]
    # The transmission line leaves no feedthrough, so the masters' different orders of setting
    # and reading do not matter: libcosim's two routes agree to round-off, and fmpy's SSP runner
    # (its communication times accumulated in floating point, libcosim's in integer ns) to the
    # integrator's tolerance, pointwise, from the first step (with fmpy's start values patched,
    # see run_system.py): 1.5e-5 of bearing.F.z's range measured with the abrupt spall edge
    # (D2), whose force jumps at events the two runs reach from times a round-off apart.
    for key in ("bearing.ring.z", "rotor.disk.z", "bearing.bearing.F.z"):
        yb = np.interp(t[1:], b["time"], b[key])
        yc = np.interp(t, c["time"], c[key])
        assert np.all(np.isfinite(a[key])) and np.all(np.isfinite(b[key]))
        assert np.max(np.abs(yc - a[key])) <= 1e-12 * np.max(np.abs(a[key])), key
        assert np.max(np.abs(yb - a[key][1:])) <= 5e-5 * np.ptp(a[key]), key
