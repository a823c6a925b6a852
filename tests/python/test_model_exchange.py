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
from default_scene import envelope_spectrum, kinematic_frequencies  # noqa: E402

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

    for fmu, nx, nz in [(bearing_fmu(), 142, 70), (rotor_fmu(), 10, 0)]:
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
    bpfo = kinematic_frequencies(float(start["shaft.speed"]) / (2 * math.pi))["BPFO"]
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
    for name, scale in [("pedestal.z", 1e-6), ("bearing.F.z", 1000.0), ("cage.speed", 400.0),
                        ("pedestal.a.z", 1000.0)]:
        _, a = on_grid(cs, name, skip=0)
        _, b = on_grid(me, name, skip=0)
        assert len(a) == len(b)
        err = np.max(np.abs(a - b)) / scale
        assert err < 1e-3, (name, err)


def test_the_kinematic_level_and_tlm_coupling_are_refused_in_model_exchange(capfd):
    """Refused at fmi2ExitInitializationMode with a message naming why (fmpy's logger prints
    it)."""
    cases = [
        (bearing_fmu(), {"fidelity": 0}, "the kinematic level (L0) has no continuous dynamics"),
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
