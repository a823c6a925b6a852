"""`raceway fmu --scene`: the BallBearing FMU made from a scene (issue 23), through fmpy.

The FMU packed from examples/scenes/two-spalls.toml
- passes fmpy's validation, ships the scene as resources/scene.toml (its bearing the resource
  beside it) and names it in its description;
- starts from the scene's values: its two outer spalls are defect.* and defect2.*;
- runs exactly as the default FMU with the same two spalls set through defect2.* (bit for bit),
  and differently from its first spall alone (defect2.ring = 0);
- refuses to instantiate once its scene resource is edited (the GUID covers it).
`--scene` and `--bearing` together are refused.
"""

import subprocess
import tomllib
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu

from conftest import REPO

SCENE = REPO / "examples" / "scenes" / "two-spalls.toml"
OUTPUTS = ["pedestal.a.z", "pedestal.a.y", "bearing.F.z", "contact.outer.Q[1]"]
# 10 ms: every ball passes both spalls (ball-pass period about 1 ms)
STOP, STEP = 0.01, 1e-4


def run(raceway, *args, ok=True):
    proc = subprocess.run([str(raceway), *map(str, args)], capture_output=True, text=True,
                          timeout=600)
    assert (proc.returncode == 0) == ok, proc.stdout + proc.stderr
    return proc


@pytest.fixture(scope="module")
def scene_fmu(raceway, fmu, tmp_path_factory):
    out = tmp_path_factory.mktemp("scene fmu") / "TwoSpalls.fmu"
    run(raceway, "fmu", "--scene", SCENE, "--template", fmu, "--out", out, "--no-reference")
    return out


def simulate(fmu, start_values=None):
    r = simulate_fmu(str(fmu), stop_time=STOP, step_size=STEP, output_interval=STEP,
                     start_values=start_values or {}, output=OUTPUTS)
    return np.array([r[name] for name in OUTPUTS])


def test_the_scene_fmu_is_valid_and_starts_from_the_scene(scene_fmu):
    assert validate_fmu(str(scene_fmu)) == []
    with zipfile.ZipFile(scene_fmu) as z:
        packed = tomllib.loads(z.read("resources/scene.toml").decode())
        bearing = tomllib.loads(z.read("resources/bearing.toml").decode())
        html = z.read("documentation/index.html").decode()
    assert "This FMU was made from the scene" in html and "two-spalls" in html
    assert "<code>defect2.*</code>" in html
    assert packed["bearing"] == "bearing.toml"
    assert bearing["name"] == "niu2014-table1"
    assert [d["theta0"] for d in packed["defect"]] == [2.3562, 3.9270]
    md = read_model_description(str(scene_fmu))
    assert "base scene 'two-spalls' from resources/scene.toml (SHA-256 " in md.description
    start = {v.name: v.start for v in md.modelVariables}
    assert float(start["defect.theta0"]) == 2.3562
    assert int(start["defect2.ring"]) == 1
    assert float(start["defect2.theta0"]) == 3.927
    assert int(start["defect3.ring"]) == 0 and int(start["defect4.ring"]) == 0
    refs = {v.name: v.valueReference for v in md.modelVariables}
    assert [refs[f"defect2.{f}"] for f in ["ring", "width", "depth", "theta0", "ball"]] == [
        130, 131, 132, 133, 134]


def test_the_scene_fmu_runs_as_the_default_fmu_with_defect2_set(scene_fmu, fmu):
    from_scene = simulate(scene_fmu)
    assert np.all(np.isfinite(from_scene))
    by_parameters = simulate(fmu, {
        "defect.theta0": 2.3562,
        "defect2.ring": 1,
        "defect2.width": 1.0e-3,
        "defect2.depth": 0.2e-3,
        "defect2.theta0": 3.9270,
    })
    np.testing.assert_array_equal(from_scene, by_parameters)
    first_only = simulate(scene_fmu, {"defect2.ring": 0})
    assert not np.array_equal(from_scene, first_only)


def test_an_edited_scene_resource_is_refused(scene_fmu, tmp_path):
    edited = tmp_path / "Edited.fmu"
    with zipfile.ZipFile(scene_fmu) as src, zipfile.ZipFile(edited, "w") as dst:
        for item in src.infolist():
            data = src.read(item.filename)
            if item.filename == "resources/scene.toml":
                data = data.replace(b"3.927", b"3.9")
            dst.writestr(item, data)
    with pytest.raises(Exception):
        simulate(edited)


def test_scene_and_bearing_are_exclusive(raceway, fmu, tmp_path):
    p = run(raceway, "fmu", "--scene", SCENE, "--bearing", "cwru-6205-de", "--template", fmu,
            "--out", tmp_path / "x.fmu", ok=False)
    assert "--bearing" in p.stderr and "--scene" in p.stderr, p.stderr
