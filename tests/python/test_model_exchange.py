"""Model Exchange of both FMUs through fmpy (issue 19 item 2): the importer integrates the
states with SUNDIALS CVODE (BDF, dense Newton), locates the state events and lands on the time
events, and the result reproduces the Co-Simulation run of the same FMU.

The CVODE tolerance: relative 1e-8 (absolute 1e-8 x each state's nominal, which the FMU gives:
1e-5 m for displacements, 1e-2 m/s for velocities, 1 rad for angles). At 1e-6 the default scene's
statistics below already agree to 0.1 %; 1e-8 leaves a margin of ten to the 1 % asked for.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import REPO, fmu_path

sys.path.insert(0, str(REPO / "examples"))
from default_scene import bearing_of, envelope_spectrum, kinematic_frequencies  # noqa: E402

RTOL = 1e-8
DT = 1.0 / 51200  # the default scene's sampling (examples/default_scene.py)
SKIP = 0.02  # the start-up transient
STOP = 0.22


def bearing_fmu() -> Path:
    p = fmu_path()
    if not p.is_file():
        pytest.fail(f"{p} does not exist: build it with `cargo run --release -p fmu-build`")
    return p


def rotor_fmu() -> Path:
    p = fmu_path().with_name("JeffcottRotor.fmu")
    if not p.is_file():
        pytest.fail(f"{p} does not exist: build it with `cargo run --release -p fmu-build`")
    return p


def on_grid(res, name, skip=SKIP):
    """The samples of `name` at the multiples of DT after `skip` (fmpy's ME result also holds
    the events' instants; the first sample at a grid time is the one at the output point)."""
    t = res["time"]
    k = np.round(t / DT).astype(int)
    keep = np.isclose(t / DT, k, rtol=0, atol=1e-6) & (t >= skip - DT / 2)
    _, first = np.unique(k[keep], return_index=True)
    return t[keep][first], res[name][keep][first]


def same_samples(cs, me, scaled):
    """The two runs sample by sample on the grid: for each (name, scale), the largest difference
    below 1e-3 x scale."""
    for name, scale in scaled:
        _, a = on_grid(cs, name, skip=0)
        _, b = on_grid(me, name, skip=0)
        assert len(a) == len(b)
        err = np.max(np.abs(a - b)) / scale
        assert err < 1e-3, (name, err)


def signature(res, bpfo):
    """Envelope-spectrum peak near BPFO (frequency by parabolic interpolation of the log peak,
    as examples/default_scene.py), its amplitude, and the RMS of pedestal.a.z."""
    _, a = on_grid(res, "pedestal.a.z")
    f, env = envelope_spectrum(a, 1 / DT)
    near = (f > 0.9 * bpfo) & (f < 1.1 * bpfo)
    i = int(np.argmax(np.where(near, env, 0)))
    l, c, r = np.log(env[i - 1:i + 2] + 1e-300)
    d = 0.5 * (l - r) / (l - 2 * c + r)
    return {
        "peak_hz": f[i] + d * (f[1] - f[0]),
        "peak_amplitude": env[i],
        "rms": float(np.sqrt(np.mean(a**2))),
        "samples": len(a),
    }


def run(fmu, kind, stop, **kw):
    from fmpy import simulate_fmu

    args = dict(stop_time=stop, output_interval=DT, fmi_type=kind)
    if kind == "ModelExchange":
        args.update(solver="CVode", relative_tolerance=RTOL)
    else:
        args.update(step_size=DT)
    args.update(kw)
    return simulate_fmu(str(fmu), **args)


def test_both_fmus_declare_model_exchange_and_co_simulation_and_validate():
    from fmpy import read_model_description
    from fmpy.validation import validate_fmu

    for fmu, nx, nz in [(bearing_fmu(), 148, 70), (rotor_fmu(), 10, 0)]:
        assert validate_fmu(str(fmu)) == []
        md = read_model_description(str(fmu))
        assert md.modelExchange is not None and md.coSimulation is not None
        assert md.modelExchange.modelIdentifier == md.coSimulation.modelIdentifier
        assert md.numberOfContinuousStates == nx
        assert md.numberOfEventIndicators == nz
        states = [d.variable.derivative for d in md.derivatives]
        assert [s.name for s in states] == [f"state[{i + 1}]" for i in range(nx)]
        assert [d.variable.name for d in md.derivatives] == [
            f"der(state[{i + 1}])" for i in range(nx)]


def test_cvode_reproduces_the_co_simulation_of_the_default_scene():
    """The default scene (lumped level, outer-race spall, 9900 rpm) integrated by CVODE through
    Model Exchange: envelope-spectrum peak frequency and amplitude near BPFO and the RMS of
    pedestal.a.z within 1 % of the Co-Simulation run's."""
    from fmpy import read_model_description

    fmu = bearing_fmu()
    md = read_model_description(str(fmu))
    start = {v.name: v.start for v in md.modelVariables}
    shaft_hz = float(start["shaft.speed"]) / (2 * math.pi)
    bpfo = kinematic_frequencies(shaft_hz, bearing_of(fmu))["BPFO"]
    cs = signature(run(fmu, "CoSimulation", STOP, output=["pedestal.a.z"]), bpfo)
    me = signature(run(fmu, "ModelExchange", STOP, output=["pedestal.a.z"]), bpfo)
    assert me["samples"] == cs["samples"] == round((STOP - SKIP) / DT) + 1
    # `pytest tests/python/test_model_exchange.py -k default_scene -s` prints the comparison
    for k in ["peak_hz", "peak_amplitude", "rms"]:
        print(f"{k}: Co-Simulation {cs[k]:.6g}, Model Exchange (CVODE rtol {RTOL:g}) {me[k]:.6g}, "
              f"{100 * (me[k] / cs[k] - 1):+.4f} %")
    for k in ["peak_hz", "peak_amplitude", "rms"]:
        assert me[k] == pytest.approx(cs[k], rel=0.01), (k, me, cs)
    # the peak is the spall's: within 2 % of the kinematic BPFO (the model's cage slips)
    assert cs["peak_hz"] == pytest.approx(bpfo, rel=0.02)


@pytest.mark.parametrize("fidelity", [1, 2])
def test_cvode_follows_the_co_simulation_sample_by_sample_on_the_smooth_levels(fidelity):
    """The quasi-static and lumped levels are deterministic: over 5 ms the two runs agree
    sample by sample (to the integrators' tolerances) for the pedestal and the ring force."""
    fmu = bearing_fmu()
    out = ["pedestal.a.z", "pedestal.z", "bearing.F.z", "cage.speed"]
    sv = {"fidelity": fidelity}
    cs = run(fmu, "CoSimulation", 0.005, output=out, start_values=sv)
    me = run(fmu, "ModelExchange", 0.005, output=out, start_values=sv)
    same_samples(cs, me, [("pedestal.z", 1e-6), ("bearing.F.z", 1000.0), ("cage.speed", 400.0),
                          ("pedestal.a.z", 1000.0)])


def journal_input(x0, amp, freq, stop):
    """fmpy input signal: the journal at x0, moving along z as x0 + amp sin(2 pi freq t)."""
    t = np.arange(0.0, stop + DT / 2, DT / 4)
    w = 2 * math.pi * freq
    names = ["journal.x", "journal.y", "journal.z", "journal.v.x", "journal.v.y", "journal.v.z"]
    sig = np.zeros(len(t), dtype=[("time", float)] + [(n, float) for n in names])
    sig["time"] = t
    sig["journal.x"], sig["journal.y"] = x0[0], x0[1]
    sig["journal.z"] = x0[2] + amp * np.sin(w * t)
    sig["journal.v.z"] = amp * w * np.cos(w * t)
    return sig


def test_motion_coupling_in_model_exchange_follows_the_co_simulation():
    """Coupling mode motion (the journal's displacement and velocity in, the reaction out) at
    the lumped level with the journal moving 1 um at 200 Hz about its start: CVODE through Model
    Exchange, where the journal inputs take the ring's states at every evaluation, against the
    Co-Simulation run, where the ring moves linearly over each step. The reaction follows the
    journal's stiffness (about 3e8 N/m: 1 um is 300 N) in both, sample by sample."""
    from fmpy import read_model_description

    fmu = bearing_fmu()
    sv = {"fidelity": 2, "coupling": 1}
    x0 = [run(fmu, "CoSimulation", DT, output=[f"ring.{a}"], start_values=sv)[f"ring.{a}"][0]
          for a in "xyz"]
    sig = journal_input(x0, 1e-6, 200.0, 0.01)
    out = ["bearing.F.z", "pedestal.z", "ring.z", "cage.speed"]
    cs = run(fmu, "CoSimulation", 0.01, output=out, start_values=sv, input=sig)
    me = run(fmu, "ModelExchange", 0.01, output=out, start_values=sv, input=sig)
    _, rz = on_grid(me, "ring.z", skip=0)
    assert np.ptp(rz) > 1.9e-6, "the journal input moves the ring in Model Exchange"
    _, f = on_grid(cs, "bearing.F.z", skip=0)
    assert np.ptp(f) > 400.0, "the reaction follows the journal"
    same_samples(cs, me, [("bearing.F.z", 1000.0), ("pedestal.z", 1e-6), ("ring.z", 1e-6),
                          ("cage.speed", 400.0)])
    # the ring's six states hold the inputs: declared as states, they have derivative 0
    assert read_model_description(str(fmu)).numberOfContinuousStates == 148


def test_monolithic_rotor_and_bearing_conserve_momentum_and_match_the_fine_co_simulation():
    """examples/systems/monolithic.py: the JeffcottRotor (force coupling, it owns the journal)
    and the BallBearing (motion coupling) integrated as one ODE by CVODE over both Model
    Exchange FMUs. Checked against (a) the momentum balance of the rotor, sum of m dv = integral
    of the external forces (bearing force, load, weight, unbalance), and (b) the constant-input
    co-simulation of the same cut at 1 us, an independent route to the same system."""
    sys.path.insert(0, str(REPO / "examples" / "systems"))
    import cosim_master as cm
    import monolithic

    w, stop, g = 250.0, 0.01, 9.81
    rotor = {"speed.initial": w, "speed.final": w, "shaft.c": 400.0, "unbalance": 1e-4,
             "disk.axial": 0}
    bearing = {"fidelity": 2, "shaft.speed": w, "load.Fx": 4000.0, "load.Fy": 0.0,
               "load.Fz": -1000.0 - 10.0 * g}
    rows = []
    names = ["journal.v.z", "disk.v.z", "unbalance.F.z", "disk.z", "journal.z"]
    res = monolithic.run(rotor, bearing, stop, output_interval=1e-5,
                         record=lambda t, r, b: rows.append(
                             (t, *r.get(names), *b.get(["bearing.F.z"]))),
                         rotor_fmu=rotor_fmu(), bearing_fmu=bearing_fmu())
    assert res["events"] > 0
    t, vj, vd, u, dz, jz, f = np.array(rows).T
    # (a) 2 kg journal, 8 kg disk (the rotor's defaults); load.Fz -1000 N on the journal
    dp = 2.0 * (vj[-1] - vj[0]) + 8.0 * (vd[-1] - vd[0])
    impulse = np.trapezoid(f + u - 1000.0 - 10.0 * g, t)
    assert abs(dp - impulse) < 1e-3 * np.trapezoid(np.abs(f), t), (dp, impulse)
    # (b) the contact cut, the force held over steps of 1 and 0.5 us: first order in the step,
    # it converges to the monolithic run (its error halves), and its extrapolation to step 0
    # (Richardson, 2 x(H/2) - x(H)) meets it
    fine = {}
    for h in (1e-6, 5e-7):
        b = cm.Fmu(bearing_fmu(), "bearing", {**bearing, "coupling": 1})
        x0 = b.get(["ring.x", "ring.y", "ring.z"])
        r = cm.Fmu(rotor_fmu(), "rotor", {**rotor, "coupling": 0,
                                          **{f"journal.{a}0": v for a, v in zip("xyz", x0)}})
        rec = []

        def every_10_us(tt, rr, _):
            if abs(tt / 1e-5 - round(tt / 1e-5)) < 1e-6:
                rec.append(rr.get(["disk.z"])[0])

        try:
            out = cm.run_coupled(r, b, h, stop, "constant", feedthrough=True,
                                 on_step=every_10_us)
        finally:
            r.free()
            b.free()
        assert out["ok"], out["error"]
        assert len(rec) == len(t) - 1, len(rec)
        fine[h] = np.array(rec)
    mono = dz[1:]
    e1, e2 = (np.max(np.abs(fine[h] - mono)) for h in (1e-6, 5e-7))
    assert e2 < 0.6 * e1, (e1, e2)
    extrapolated = 2 * fine[5e-7] - fine[1e-6]
    assert np.max(np.abs(extrapolated - mono)) < 5e-4 * np.ptp(dz), (e1, e2)


def test_the_kinematic_and_quasi_static_levels_and_tlm_coupling_are_refused_where_they_cannot_run(
        capfd):
    """Refused at fmi2ExitInitializationMode with a message naming why (fmpy's logger prints
    it)."""
    cases = [
        (bearing_fmu(), {"fidelity": 0}, "the kinematic level (L0) has no continuous dynamics"),
        (bearing_fmu(), {"fidelity": 1, "coupling": 1},
         "coupling mode motion in Model Exchange needs a level whose inner ring is a dynamic"),
        (bearing_fmu(), {"coupling": 2}, "coupling = 2 (tlm) is refused"),
        (rotor_fmu(), {"coupling": 1}, "coupling = 1 (tlm) is refused"),
    ]
    for fmu, sv, why in cases:
        with pytest.raises(Exception, match="fmi2ExitInitializationMode"):
            run(fmu, "ModelExchange", 0.001, start_values=sv)
        assert why in capfd.readouterr().out


def test_rotor_model_exchange_reproduces_its_co_simulation():
    """The JeffcottRotor's default run (speed ramp, unbalance, gravity, no bearing force) by
    CVODE against its own DOPRI5 co-simulation: journal and disk within 1e-3 of their range."""
    fmu = rotor_fmu()
    out = ["journal.y", "journal.z", "disk.y", "disk.z"]
    cs = run(fmu, "CoSimulation", 0.05, output=out, output_interval=1e-4, step_size=1e-4)
    me = run(fmu, "ModelExchange", 0.05, output=out, output_interval=1e-4)
    for name in out:
        a = cs[name]
        t = me["time"]
        b = np.interp(cs["time"], t, me[name])
        span = max(np.ptp(a), 1e-9)
        assert np.max(np.abs(a - b)) < 1e-3 * span, name
