"""`raceway fmu`: the BallBearing FMU for any bearing, packed around the binaries of the FMU that
fmu-build made (no Rust toolchain needed). For every preset the FMU it writes
- passes fmpy's validation and the FMU Compliance Checker (Co-Simulation and Model Exchange;
  skipped without $FMUCHK);
- has one per-ball output of each kind per ball of that bearing;
- simulates in fmpy, and the envelope spectrum of its pedestal acceleration (outer-race spall,
  the FMU's default scene) peaks at the BPFO that `raceway frequencies` gives for that bearing
  at the loaded contact angle (`raceway static` at the FMU's operating point), within 1 %.
A template made by another version, or none at all, is refused with a message.
"""

import json
import math
import subprocess
import tomllib
import zipfile

import numpy as np
import pytest
from fmpy import read_model_description, simulate_fmu
from fmpy.validation import validate_fmu
from scipy.signal import butter, hilbert, sosfiltfilt

from conftest import REPO, fmu_path
from test_compliance import checked

PRESETS = ["niu2014-table1", "cwru-6205-de", "cwru-6203-fe", "ims-za2115"]


def run(raceway, *args, ok=True):
    proc = subprocess.run([str(raceway), *map(str, args)], capture_output=True, text=True,
                          timeout=600)
    assert (proc.returncode == 0) == ok, proc.stdout + proc.stderr
    return proc


@pytest.fixture(scope="module")
def made(raceway, fmu, tmp_path_factory):
    """preset -> the FMU `raceway fmu` wrote for it."""
    d = tmp_path_factory.mktemp("any-bearing")
    out = {}
    for p in PRESETS:
        out[p] = d / f"{p}.fmu"
        run(raceway, "fmu", "--bearing", p, "--template", fmu, "--out", out[p])
    return out


def start(md, name):
    return float(next(v.start for v in md.modelVariables if v.name == name))


@pytest.mark.parametrize("preset", PRESETS)
def test_valid_with_per_ball_outputs_for_its_bearing(made, preset):
    fmu = made[preset]
    assert validate_fmu(str(fmu)) == []
    md = read_model_description(str(fmu))
    with zipfile.ZipFile(fmu) as z:
        balls = tomllib.loads(z.read("resources/bearing.toml").decode())["bearing"]["z"]
        names = z.namelist()
    assert balls == tomllib.loads((REPO / "presets" / f"{preset}.toml").read_text())["bearing"]["z"]
    with zipfile.ZipFile(fmu_path()) as z:
        assert sorted(n for n in names if n.startswith("binaries/")) == sorted(
            n for n in z.namelist() if n.startswith("binaries/"))
    for kind in ["ball.orbit_speed", "contact.inner.Q", "contact.outer.Q"]:
        per_ball = [v.name for v in md.modelVariables if v.name.startswith(kind + "[")]
        assert per_ball == [f"{kind}[{j}]" for j in range(1, balls + 1)]


@pytest.mark.parametrize("kind", ["cs", "me"])
@pytest.mark.parametrize("preset", PRESETS)
def test_compliance_checker(made, preset, kind, tmp_path):
    text = checked(made[preset], tmp_path, kind)
    assert "0 Warning(s)" in text and "0 Error(s)" in text, text[-4000:]


def envelope_peak(a, fs, lo, hi):
    """The envelope spectrum's strongest line in (lo, hi) [Hz] (2-12 kHz band, Hann window,
    parabolic interpolation between bins)."""
    sos = butter(4, [2000, 12000], btype="band", fs=fs, output="sos")
    env = np.abs(hilbert(sosfiltfilt(sos, a)))
    env -= env.mean()
    s = np.abs(np.fft.rfft(env * np.hanning(len(env))))
    f = np.fft.rfftfreq(len(env), 1 / fs)
    k = int(np.argmax(np.where((f > lo) & (f < hi), s, 0.0)))
    y0, y1, y2 = s[k - 1:k + 2]
    return f[k] + 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2) * (f[1] - f[0])


@pytest.mark.parametrize("preset", PRESETS)
def test_envelope_bpfo_matches_raceway_frequencies(raceway, made, preset):
    fmu = made[preset]
    md = read_model_description(str(fmu))
    rpm = start(md, "shaft.speed") * 60 / (2 * math.pi)
    fa, fz = start(md, "load.Fx"), start(md, "load.Fz")
    assert start(md, "defect.ring") == 1  # the default scene's outer-race spall
    st = json.loads(run(raceway, "static", "--bearing", preset, "--fa", fa, "--fr", -fz,
                        "--speed-rpm", rpm, "--json").stdout)
    alpha = np.mean([b["alpha_inner"] for b in st["balls"]])
    fr = json.loads(run(raceway, "frequencies", "--bearing", preset, "--speed-rpm", rpm,
                        "--contact-angle-deg", math.degrees(alpha), "--json").stdout)
    fs = 51200
    r = simulate_fmu(str(fmu), stop_time=0.5, output_interval=1 / fs, output=["pedestal.a.z"])
    a = r["pedestal.a.z"][len(r) // 10:]  # past the start transient
    peak = envelope_peak(a, fs, 0.5 * fr["bpfo"], 1.5 * fr["bpfo"])
    print(f"{preset}: envelope BPFO {peak:.2f} Hz, raceway frequencies {fr['bpfo']:.2f} Hz at "
          f"{math.degrees(alpha):.2f} deg ({100 * (peak / fr['bpfo'] - 1):+.2f} %)")
    assert peak == pytest.approx(fr["bpfo"], rel=0.01), (peak, fr)


def test_a_template_of_another_version_or_none_is_refused(raceway, fmu, tmp_path):
    other = tmp_path / "other.fmu"
    with zipfile.ZipFile(fmu) as src, zipfile.ZipFile(other, "w") as dst:
        for n in src.namelist():
            data = src.read(n)
            if n == "modelDescription.xml":
                data = data.replace(b'generationTool="', b'generationTool="older ')
            dst.writestr(n, data)
    p = run(raceway, "fmu", "--bearing", "cwru-6205-de", "--template", other,
            "--out", tmp_path / "x.fmu", ok=False)
    assert "not made by this version" in p.stderr, p.stderr
    p = run(raceway, "fmu", "--bearing", "cwru-6205-de", "--template", tmp_path / "none.fmu",
            "--out", tmp_path / "x.fmu", ok=False)
    assert "none.fmu" in p.stderr, p.stderr
    assert not (tmp_path / "x.fmu").exists()
    p = run(raceway, "fmu", "--bearing", "no-such-bearing", "--template", fmu,
            "--out", tmp_path / "x.fmu", ok=False)
    assert "neither a preset" in p.stderr, p.stderr
