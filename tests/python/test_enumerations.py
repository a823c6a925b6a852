"""The mode switches of both FMUs are FMI 2.0 Enumerations with named items (issue 22): fmpy
reads the types and items, the values pass through fmi2SetInteger/fmi2GetInteger under the old
value references, and a value that is no item is refused with a message."""

import pytest

from conftest import fmu_path

# Switch -> (declared type, item names in value order 0, 1, ...), as the model descriptions list them.
BEARING = {
    "fidelity": ("Fidelity", ["kinematic", "quasi_static", "lumped", "reduced", "full"]),
    "defect.ring": ("DefectRing", ["none", "outer", "inner", "ball"]),
    "defect.mode": ("DefectMode", ["finite", "point"]),
    "solver.method": ("IntegrationMethod", ["rkf45", "dopri5", "dop853"]),
    "lumped.cage_speed": ("CageSpeed", ["traction", "outer_race_control"]),
    "ring.axial": ("AxialMounting", ["load", "located", "located_offset"]),
    "cage": ("Cage", ["none", "rigid"]),
    # spalls 2-4 (issue 23): the same type as defect.ring
    "defect2.ring": ("DefectRing", ["none", "outer", "inner", "ball"]),
    "defect3.ring": ("DefectRing", ["none", "outer", "inner", "ball"]),
    "defect4.ring": ("DefectRing", ["none", "outer", "inner", "ball"]),
}
ROTOR = {
    "disk.axial": ("DiskAxial", ["lateral", "with_journal"]),
}
# Value references from before the switches were Enumerations: they never move.
BEARING_VRS = {"fidelity": 100, "defect.ring": 102, "defect.mode": 106,
               "solver.method": 120, "lumped.cage_speed": 123, "ring.axial": 125, "cage": 128,
               "defect2.ring": 130, "defect3.ring": 135, "defect4.ring": 140}


def switches(path):
    from fmpy import read_model_description

    md = read_model_description(str(path))
    return md, {v.name: v for v in md.modelVariables if v.type == "Enumeration"}


def test_fmpy_reads_the_bearings_enumerations(fmu):
    md, enums = switches(fmu)
    assert set(enums) == set(BEARING)
    for name, (type_name, items) in BEARING.items():
        v = enums[name]
        assert v.valueReference == BEARING_VRS[name]
        assert v.declaredType.name == type_name
        assert [(i.name, int(i.value)) for i in v.declaredType.items] == [
            (n, k) for k, n in enumerate(items)], name
        assert all(i.description for i in v.declaredType.items), name
        assert int(v.start) in range(len(items)), name
    fid = enums["fidelity"]
    assert fid.declaredType in md.typeDefinitions
    assert int(fid.start) == 2 and fid.declaredType.items[int(fid.start)].name == "lumped"
    # The Integers that are counts or seeds stay Integers, and so does coupling: libcosim
    # ignores Enumeration variables, and the rotor-bearing system run there sets it.
    ints = {v.name for v in md.modelVariables if v.type == "Integer"}
    assert {"coupling", "lumped.seed", "solver.max_steps", "solver.warn_steps", "solver.steps"} <= ints


def test_fmpy_reads_the_rotors_enumeration():
    p = fmu_path().with_name("JeffcottRotor.fmu")
    if not p.is_file():
        pytest.fail(f"{p} does not exist: build it with `cargo run --release -p fmu-build`")
    _, enums = switches(p)
    assert set(enums) == set(ROTOR)  # coupling stays an Integer (libcosim)
    for name, (type_name, items) in ROTOR.items():
        t = enums[name].declaredType
        assert t.name == type_name
        assert [(i.name, int(i.value)) for i in t.items] == [(n, k) for k, n in enumerate(items)]


def test_enumeration_values_pass_as_integers_and_a_non_item_is_refused(probe):
    r = probe("enumeration")
    assert set(r) == set(BEARING) | {"get_real", "log"}
    for name, (_, items) in BEARING.items():
        e = r[name]
        assert e["values"] == list(range(len(items))), name
        assert e["got"] == [[0, k] for k in range(len(items))], (name, e["got"])
        status, message = e["bad"]
        assert status == 3, (name, e["bad"])  # fmi2Error
        assert f"'{name}' = {len(items)} is outside its range [0, {len(items) - 1}]" in message, message
    status, message = r["get_real"]
    assert status == 3 and "an Enumeration variable (read and written as an Integer)" in message, message


def test_fmpy_simulate_sets_an_enumeration_start_value(fmu):
    from fmpy import simulate_fmu

    # fmpy applies Enumeration start values with fmi2SetInteger; quasi-static: cheap.
    res = simulate_fmu(str(fmu), stop_time=2e-3, step_size=1e-3, output_interval=1e-3,
                       start_values={"fidelity": 1}, output=["bearing.F.z"])
    assert len(res) == 3 and abs(res["bearing.F.z"][-1]) > 0
