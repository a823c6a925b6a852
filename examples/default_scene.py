"""Run the default scene through the BallBearing FMU with fmpy and show the spall's signature.

Usage: python examples/default_scene.py [--fmu target/fmu/BallBearing.fmu] [--stop 0.5]
                                         [--ball 1] [--out out/default_scene.png]

The default scene is the paper's Table-1 bearing at 9900 rpm, Fa = 4000 N, Fr = 1000 N, with an
outer-race spall 1.0 x 0.2 mm at the load-zone centre. The script prints the kinematic fault
frequencies (pure rolling at the free contact angle of the FMU's own bearing,
resources/bearing.toml), the BPFO implied by the cage speed the model uses, and the
envelope-spectrum peak it finds near BPFO. It saves a figure with
- one ball's outer- and inner-race contact forces above the pedestal acceleration, zoomed on a
  spall passage by that ball (the force drop and the impact, and the burst they excite);
- the acceleration spectrum and the envelope spectrum, with the shaft rate f_s, FTF, BPFO, BPFI
  and 2xBSF and their harmonics marked (the frequencies the model implies, as `raceway
  simulate` reports them: FTF from the model's cage speed, 2xBSF from pure rolling).
"""

import argparse
import math
import pathlib
import sys
import zipfile

import numpy as np
from fmpy import read_model_description, simulate_fmu


def bearing_table(text):
    """The [bearing] table of a bearing file (tomllib from Python 3.11; before, its plain
    `key = number` lines)."""
    try:
        import tomllib
    except ImportError:
        section, table = None, {}
        for line in text.splitlines():
            line = line.split("#")[0].strip()
            if line.startswith("["):
                section = line.strip("[] ")
            elif section == "bearing" and "=" in line:
                key, value = line.split("=", 1)
                table[key.strip()] = float(value)
        return table
    return tomllib.loads(text)["bearing"]


def bearing_of(fmu):
    """The FMU's bearing (resources/bearing.toml): ball count z, ball diameter D [m], pitch
    diameter dm [m], free contact angle alpha0 [rad]."""
    with zipfile.ZipFile(fmu) as z:
        b = bearing_table(z.read("resources/bearing.toml").decode())
    return {"z": int(b["z"]), "D": b["ball_diameter"], "dm": b["pitch_diameter"],
            "alpha0": math.radians(b["contact_angle_free_deg"])}


def kinematic_frequencies(shaft_hz, bearing, alpha=None):
    """Pure-rolling fault frequencies at the contact angle `alpha` (default: the free contact
    angle), the formulas of `raceway frequencies` (src/fault_frequencies.rs)."""
    z, d, dm = bearing["z"], bearing["D"], bearing["dm"]
    gamma = d * math.cos(bearing["alpha0"] if alpha is None else alpha) / dm
    ftf = shaft_hz / 2 * (1 - gamma)
    bsf = dm / (2 * d) * shaft_hz * (1 - gamma**2)
    return {"FTF": ftf, "BPFO": z * ftf, "BPFI": z * (shaft_hz - ftf), "BSF": bsf, "2*BSF": 2 * bsf}


def model_frequencies(shaft_hz, cage_hz, bearing):
    """The frequencies the model implies, as `raceway simulate` reports them: FTF is the model's
    cage speed, BPFO = z FTF, BPFI = z (f_s - FTF); 2xBSF from pure rolling."""
    z = bearing["z"]
    return {"f_s": shaft_hz, "FTF": cage_hz, "BPFO": z * cage_hz, "BPFI": z * (shaft_hz - cage_hz),
            "2×BSF": kinematic_frequencies(shaft_hz, bearing)["2*BSF"]}


# Marker style per family: colour, line style.
FAMILIES = {
    "f_s": ("0.35", (0, (1, 1))),
    "FTF": ("tab:purple", "-."),
    "BPFO": ("tab:red", "--"),
    "BPFI": ("tab:blue", "--"),
    "2×BSF": ("tab:green", ":"),
}
# The family of each spalled ring (the FMU's defect.ring: 1 outer, 2 inner): labelled first.
FAULT_FAMILY = {1: "BPFO", 2: "BPFI"}


def envelope_spectrum(x, fs, band=(2000.0, 12000.0)):
    """Band-pass by FFT mask, Hilbert envelope, amplitude spectrum of the envelope."""
    n = len(x)
    spec = np.fft.fft(x - x.mean())
    f = np.fft.fftfreq(n, 1 / fs)
    spec[(np.abs(f) < band[0]) | (np.abs(f) > band[1])] = 0
    h = np.zeros(n)
    h[0] = 1
    if n % 2 == 0:
        h[n // 2] = 1
        h[1 : n // 2] = 2
    else:
        h[1 : (n + 1) // 2] = 2
    env = np.abs(np.fft.ifft(spec * h))
    env -= env.mean()
    w = np.hanning(n)
    amp = np.abs(np.fft.rfft(env * w)) * 2 / w.sum()
    return np.fft.rfftfreq(n, 1 / fs), amp


def amplitude_spectrum(x, fs):
    w = np.hanning(len(x))
    amp = np.abs(np.fft.rfft((x - x.mean()) * w)) * 2 / w.sum()
    return np.fft.rfftfreq(len(x), 1 / fs), amp


def peak_near(f, amp, f0, rel=0.1):
    """The largest peak within f0 (1 ± rel), by parabolic interpolation of the log amplitude."""
    near = (f > (1 - rel) * f0) & (f < (1 + rel) * f0)
    i = np.argmax(np.where(near, amp, 0))
    d = 0.0
    if 0 < i < len(amp) - 1:
        l, c, r = np.log(amp[i - 1 : i + 2] + 1e-300)
        d = 0.5 * (l - r) / (l - 2 * c + r)
    return f[i] + d * (f[1] - f[0])


def simulate(fmu, stop, step, skip, ball=1):
    """The default scene: time, pedestal.a.z, cage speed and ball `ball`'s contact forces
    after the start-up transient `skip`."""
    q_out, q_in = f"contact.outer.Q[{ball}]", f"contact.inner.Q[{ball}]"
    res = simulate_fmu(fmu, stop_time=stop, output_interval=step, step_size=step,
                       output=["pedestal.a.z", "cage.speed", q_out, q_in])
    if not np.all(np.isfinite(res["pedestal.a.z"])):
        sys.exit("the FMU returned non-finite accelerations")
    keep = res["time"] >= skip
    return {"t": res["time"][keep], "a": res["pedestal.a.z"][keep],
            "cage": res["cage.speed"][keep], "q_out": res[q_out][keep], "q_in": res[q_in][keep],
            "ball": ball}


def spall_passage(run, period):
    """A time window [t0, t1] around the ball's deepest contact-force drop (its passage over
    the spall): half a ball-pass `period` before it, one and a half after (the drop, the
    impact at the spall's exit edge, the ringing, the next ball's passage). Also returns the
    drop's time."""
    t = run["t"]
    i = int(np.argmin(run["q_out"] + run["q_in"]))
    t0 = max(t[0], t[i] - 0.5 * period)
    return t0, min(t[-1], t0 + 2.0 * period), t[i]


def harmonic_label(name, k):
    """"BPFO", "2×BPFO", ...; the harmonics of 2×BSF are 4×BSF, 6×BSF."""
    if k == 1:
        return name
    if "×" in name:
        m, base = name.split("×", 1)
        return f"{k * int(m)}×{base}"
    return f"{k}×{name}"


def mark_frequencies(ax, freqs, xmax, harmonics=3, first="BPFO"):
    """Vertical lines at the harmonics 1..`harmonics` of each family inside (0, xmax], one
    colour and line style per family (one legend entry each), and rotated text labels ("BPFO",
    "2×BPFO", ...) where they do not crowd one already placed (fundamentals first, the spall's
    family `first` before the others). Returns the markers: dicts family, k, f, line, label
    (the text placed, or None)."""
    from matplotlib.transforms import blended_transform_factory

    markers = []
    for name, f in freqs.items():
        colour, style = FAMILIES[name]
        for k in range(1, harmonics + 1):
            if k * f > xmax:
                break
            line = ax.axvline(k * f, color=colour, ls=style, lw=1.1 if k == 1 else 0.8,
                              alpha=0.9 if k == 1 else 0.6,
                              label=f"{name} = {f:.1f} Hz (and harmonics)" if k == 1 else None)
            markers.append({"family": name, "k": k, "f": k * f, "line": line, "label": None})
    # Labels: fundamentals, then 2nd, 3rd harmonics; the spall's family first in each round.
    order = sorted(markers, key=lambda m: (m["k"], m["family"] != first,
                                           list(freqs).index(m["family"])))
    gap = 0.012 * xmax  # about one rotated label's width
    placed = []
    tr = blended_transform_factory(ax.transData, ax.transAxes)
    for m in order:
        if any(abs(m["f"] - p) < gap for p in placed):
            continue
        text = harmonic_label(m["family"], m["k"])
        ax.text(m["f"], 0.98, text, transform=tr, rotation=90, ha="center", va="top",
                fontsize=7, color=FAMILIES[m["family"]][0],
                bbox={"fc": "white", "ec": "none", "alpha": 0.7, "pad": 0.5})
        m["label"] = text
        placed.append(m["f"])
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    return markers


def make_figure(run, freqs, fs, band=(2000.0, 12000.0), defect_ring=1, peak=None):
    """The figure: ball forces and pedestal acceleration through a spall passage (shared time
    axis), the acceleration spectrum and the envelope spectrum with the fault frequencies
    marked. Returns (figure, {"spectrum": markers, "envelope": markers})."""
    import matplotlib.pyplot as plt

    t, a, ball = run["t"], run["a"], run["ball"]
    first = FAULT_FAMILY.get(defect_ring, "BPFO")
    fig = plt.figure(figsize=(13, 13))
    gs = fig.add_gridspec(4, 1, height_ratios=[1, 1, 1.3, 1.3], hspace=0.45,
                          left=0.07, right=0.76, top=0.96, bottom=0.05)
    ax_q = fig.add_subplot(gs[0])
    ax_a = fig.add_subplot(gs[1], sharex=ax_q)
    ax_sp = fig.add_subplot(gs[2])
    ax_env = fig.add_subplot(gs[3])

    # Ball passes over the spall: one per 1/BPFO (outer race) or 1/BPFI (inner race).
    period = 1.0 / freqs[first]
    t0, t1, t_drop = spall_passage(run, period)
    w = (t >= t0) & (t <= t1)
    ms = (t[w] - t_drop) * 1e3
    q_out, q_in = run["q_out"][w], run["q_in"][w]
    ax_q.plot(ms, q_out, color="tab:red", lw=1.2, label=f"outer race, contact.outer.Q[{ball}]")
    ax_q.plot(ms, q_in, color="tab:blue", lw=1.0, ls="--", label=f"inner race, contact.inner.Q[{ball}]")
    same = np.allclose(q_out, q_in, rtol=1e-9, atol=1e-9)
    ax_q.set(ylabel="normal contact force [N]",
             title=f"Ball {ball}'s contact forces through its spall passage at t = {t_drop * 1e3:.2f} ms"
                   + (" (inner = outer: this level's balls carry no inertia)" if same else ""))
    ax_q.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax_q.tick_params(labelbottom=False)
    ax_a.plot(ms, a[w], color="k", lw=0.8)
    ax_a.set(xlabel=f"time from ball {ball}'s deepest force drop [ms]",
             ylabel="pedestal.a.z [m/s²]", title="Pedestal acceleration")
    passes = np.arange(-1, 3) * period * 1e3
    passes = passes[(passes >= ms[0]) & (passes <= ms[-1])]
    for ax in (ax_q, ax_a):
        for k, p in enumerate(passes):
            ax.axvline(p, color="0.5", lw=0.8, ls="--",
                       label=f"ball passes over the spall (every 1/{first})" if k == 0 else None)
        ax.grid(alpha=0.3)
    ax_a.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)

    # Both spectra up to a little beyond the 3rd harmonic of the highest fundamental.
    xmax = 500.0 * math.ceil(3.3 * max(freqs.values()) / 500.0)
    f_sp, sp = amplitude_spectrum(a, fs)
    ax_sp.semilogy(f_sp, sp, color="k", lw=0.6)
    sel = (f_sp > 0) & (f_sp <= xmax)
    ax_sp.set(xlim=(0, xmax), ylim=(sp[sel].min() * 0.5, sp[sel].max() * 30),
              xlabel="frequency [Hz]", ylabel="amplitude [m/s²]",
              title="Spectrum of pedestal.a.z (Hann window)")
    f_env, env = envelope_spectrum(a, fs, band)
    ax_env.plot(f_env, env, color="k", lw=0.8)
    sel = (f_env > 0) & (f_env <= xmax)
    ax_env.set(xlim=(0, xmax), ylim=(0, env[sel].max() * 1.35), xlabel="frequency [Hz]",
               ylabel="amplitude [m/s²]",
               title=f"Envelope spectrum ({band[0] / 1e3:g}–{band[1] / 1e3:g} kHz band)"
                     + (f": peak {peak:.1f} Hz" if peak is not None else ""))
    markers = {"spectrum": mark_frequencies(ax_sp, freqs, xmax, first=first),
               "envelope": mark_frequencies(ax_env, freqs, xmax, first=first)}
    return fig, markers


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fmu", default="target/fmu/BallBearing.fmu")
    ap.add_argument("--stop", type=float, default=0.5, help="simulated time [s]")
    ap.add_argument("--step", type=float, default=1.0 / 51200, help="communication step [s]")
    ap.add_argument("--skip", type=float, default=0.02, help="start-up transient to discard [s]")
    ap.add_argument("--ball", type=int, default=1, help="the ball whose contact forces are shown")
    ap.add_argument("--out", default="out/default_scene.png")
    args = ap.parse_args()

    md = read_model_description(args.fmu)
    start = {v.name: v.start for v in md.modelVariables}
    bearing = bearing_of(args.fmu)
    rpm = float(start["shaft.speed"]) * 60 / (2 * math.pi)
    shaft_hz = rpm / 60
    kin = kinematic_frequencies(shaft_hz, bearing)
    print(f"BallBearing FMU: {md.description}")
    print(f"shaft speed {rpm:.0f} rpm ({shaft_hz:.2f} Hz); kinematic frequencies at "
          f"{math.degrees(bearing['alpha0']):.0f} deg:")
    for k, v in kin.items():
        print(f"  {k:6s} {v:9.2f} Hz")

    run = simulate(args.fmu, args.stop, args.step, args.skip, args.ball)
    fs = 1.0 / args.step
    cage_hz = float(np.mean(run["cage"])) / (2 * math.pi)
    freqs = model_frequencies(shaft_hz, cage_hz, bearing)
    print(f"cage speed used by the model {cage_hz:.3f} Hz -> BPFO {freqs['BPFO']:.2f} Hz")

    f_env, env = envelope_spectrum(run["a"], fs)
    peak = peak_near(f_env, env, kin["BPFO"])
    print(f"envelope-spectrum peak near BPFO: {peak:.2f} Hz "
          f"({100 * (peak / freqs['BPFO'] - 1):+.2f} % from the model's BPFO, "
          f"{100 * (peak / kin['BPFO'] - 1):+.2f} % from the kinematic BPFO)")

    import matplotlib

    matplotlib.use("Agg")
    fig, _ = make_figure(run, freqs, fs, defect_ring=int(start["defect.ring"]), peak=peak)
    _, _, t_drop = spall_passage(run, 1.0 / freqs["BPFO"])
    print(f"ball {args.ball}'s deepest contact-force drop (a spall passage) at t = "
          f"{t_drop * 1e3:.2f} ms: its forces and the acceleration around it in the figure")
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"figure saved to {out}")


if __name__ == "__main__":
    main()
