"""examples/default_scene.py (the main job's figure, scripts/demo.sh): its printed lines, and a
figure that marks and labels the shaft rate, FTF, BPFO, BPFI and 2×BSF with their harmonics on
both spectra, and shows one ball's contact forces above the pedestal acceleration through a
spall passage."""

import math
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO

sys.path.insert(0, str(REPO / "examples"))
import default_scene as ds  # noqa: E402

FAMILIES = ["f_s", "FTF", "BPFO", "BPFI", "2×BSF"]


@pytest.fixture(scope="module")
def short_run(fmu):
    """0.04 s after the start-up transient: about three passages of ball 1 over the spall."""
    return ds.simulate(str(fmu), stop=0.06, step=1.0 / 51200, skip=0.02, ball=1)


def test_the_frequencies_come_from_the_fmu(fmu, short_run):
    from fmpy import read_model_description

    b = ds.bearing_of(str(fmu))
    md = read_model_description(str(fmu))
    z = sum(1 for v in md.modelVariables if v.name.startswith("contact.outer.Q["))
    assert b["z"] == z == 14 and math.degrees(b["alpha0"]) == pytest.approx(30.0)
    cage_hz = float(np.mean(short_run["cage"])) / (2 * math.pi)
    f = ds.model_frequencies(165.0, cage_hz, b)
    assert list(f) == FAMILIES
    assert f["BPFO"] == pytest.approx(z * cage_hz) and f["BPFI"] == pytest.approx(z * (165.0 - cage_hz))
    kin = ds.kinematic_frequencies(165.0, b)
    # `raceway frequencies --bearing niu2014-table1 --speed-rpm 9900`
    assert (kin["FTF"], kin["BPFO"], kin["BPFI"], kin["2*BSF"]) == pytest.approx(
        (69.54, 973.52, 1336.48, 887.00), abs=0.01)


def test_the_figure_marks_every_family_and_the_ball_forces(fmu, short_run):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cage_hz = float(np.mean(short_run["cage"])) / (2 * math.pi)
    freqs = ds.model_frequencies(165.0, cage_hz, ds.bearing_of(str(fmu)))
    fig, markers = ds.make_figure(short_run, freqs, 51200.0)
    try:
        ax_q, ax_a, ax_sp, ax_env = fig.axes
        for axis in ["spectrum", "envelope"]:
            ms = markers[axis]
            ax = ax_sp if axis == "spectrum" else ax_env
            xmax = ax.get_xlim()[1]
            legend = [t.get_text() for t in ax.get_legend().get_texts()]
            for fam in FAMILIES:
                mine = [m for m in ms if m["family"] == fam]
                # the fundamental and the harmonics up to the 3rd inside the axis, at k·f
                want = [k for k in (1, 2, 3) if k * freqs[fam] <= xmax]
                assert [m["k"] for m in mine] == want, (axis, fam)
                assert all(m["f"] == pytest.approx(m["k"] * freqs[fam]) for m in mine)
                assert all(m["line"] in ax.lines for m in mine)
                # the fundamental is labelled with the family's name, and it is in the legend
                assert mine[0]["label"] == fam, (axis, fam)
                assert any(t.startswith(f"{fam} = {freqs[fam]:.1f} Hz") for t in legend), legend
            labels = {m["label"] for m in ms} - {None}
            assert {"2×BPFO", "3×BPFO", "2×BPFI", "4×BSF"} <= labels, labels
            texts = {t.get_text() for t in ax.texts}
            assert labels == texts
        # one ball's forces above the acceleration, on the same time axis, through the drop
        assert ax_q.get_shared_x_axes().joined(ax_q, ax_a)
        names = [line.get_label() for line in ax_q.lines]
        assert "outer race, contact.outer.Q[1]" in names and "inner race, contact.inner.Q[1]" in names
        q = ax_q.lines[0].get_ydata()
        t = ax_q.lines[0].get_xdata()
        assert t[0] < 0 < t[-1] and q.min() < 0.2 * np.median(q), "the window holds the force drop"
        assert len(ax_a.lines[0].get_xdata()) == len(t)
    finally:
        plt.close(fig)


def test_the_example_prints_its_lines_and_saves_the_figure(fmu, tmp_path):
    out = tmp_path / "scene.png"
    proc = subprocess.run(
        [sys.executable, str(REPO / "examples/default_scene.py"), "--fmu", str(fmu), "--stop", "0.06",
         "--out", str(out)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    text = proc.stdout
    for line in ["BallBearing FMU: ", "shaft speed 9900 rpm (165.00 Hz); kinematic frequencies at 30 deg:",
                 "  BPFO      973.5", "cage speed used by the model ", "envelope-spectrum peak near BPFO: ",
                 f"figure saved to {out}"]:
        assert line in text, (line, text)
    assert out.stat().st_size > 50_000
