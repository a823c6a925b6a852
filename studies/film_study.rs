//! The lubricant film at the full level (docs/research/film.md, docs/model.md#film): the default
//! scene (examples/scenes/default.toml: 9900 rpm, Fa 4000 N, Fr 1000 N, outer-race spall
//! 1.0 × 0.2 mm) at the full level with the tilt held (D1), once with the paper's constant
//! contact damping and once with an ISO VG 68 film at 70 °C, advanced side by side in
//! alternating 5 ms slices so that both see the same machine load; then the impact test
//! (examples/scenes/impact-test-fa4000.toml) at the full level, with and without the film.
//!
//! Measures: the film at the L1 operating point; the ball-rattle decay after each spall
//! impact (outer contact force of the ball, 15–80 kHz band, e-folding time of its envelope and
//! the time to fall to 10 %); kurtosis and peak-to-RMS of `pedestal.a.z` (sampled at 51.2 kHz);
//! its envelope spectrum (2–20 kHz band) at BPFO and harmonics; the damping ratios of the
//! pedestal mode (fel) and the ring-on-bearing mode (feh) from the pulse response; the cost of
//! the film (wall time, steps, RHS evaluations) as a ratio to the run without it.
//!
//! Usage: cargo run --release -p raceway-studies --bin film_study -- [OUT_DIR] [DURATION_S]
//! (default target/film_study, 0.3 s). Writes summary.json and the CSVs that
//! studies/film_study.py draws; prints the numbers.

use raceway::contact::FilmContact;
use raceway::load_distribution::solve;
use raceway::signal::{self, Window};
use raceway::{
    out, Bearing, Fidelity, LubricationSection, OperatingPoint, Race, Scene, Simulation,
};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Sample rate of the recorded signals [Hz] (8 × 51.2 kHz: resolves the ≈ 30 kHz rattle).
const FS: f64 = 409_600.0;
/// Decimation to the usual 51.2 kHz for the pedestal statistics and envelope spectrum.
const DECIM: usize = 8;
/// Start transient skipped [s].
const SKIP: f64 = 0.02;

fn lubrication() -> LubricationSection {
    LubricationSection {
        viscosity_40: Some(68.0),
        viscosity_100: Some(8.7),
        temperature: 70.0,
        density: 845.0,
        dynamic_viscosity: None,
        pressure_viscosity: 2.0e-8,
        roughness: 0.1e-6,
    }
}

fn scene(name: &str, film: bool) -> Scene {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../examples/scenes")
        .join(name);
    let mut s = Scene::load(&p).unwrap_or_else(|e| panic!("{name}: {e}"));
    s.fidelity = Fidelity::Full;
    s.full.lock_tilt = true;
    if film {
        s.bearing.lubrication = Some(lubrication());
    }
    s
}

/// One run's record: pedestal.a.z and each ball's outer contact force at FS after `SKIP`.
struct Record {
    a: Vec<f64>,
    q_outer: Vec<Vec<f64>>,
    wall: f64,
    steps: u64,
    rejected: u64,
    rhs: u64,
}

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

fn kurtosis(x: &[f64]) -> f64 {
    let m = mean(x);
    let m2 = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / x.len() as f64;
    let m4 = x.iter().map(|v| (v - m).powi(4)).sum::<f64>() / x.len() as f64;
    m4 / (m2 * m2)
}

fn peak_to_rms(x: &[f64]) -> f64 {
    let m = mean(x);
    let rms = (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / x.len() as f64).sqrt();
    x.iter().map(|v| (v - m).abs()).fold(0.0, f64::max) / rms
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        f64::NAN
    } else {
        v[v.len() / 2]
    }
}

/// Least-squares slope of ln(env) against time over the samples from the envelope's maximum
/// while it stays above `floor`·max: (decay rate σ [1/s], time to fall to 10 % [s]).
fn decay(env: &[f64], fs: f64, floor: f64) -> (f64, f64) {
    let (i0, &emax) = env
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .unwrap();
    let mut pts = Vec::new();
    let mut t10 = f64::NAN;
    for (k, &e) in env.iter().enumerate().skip(i0) {
        if e < floor * emax {
            break;
        }
        pts.push(((k - i0) as f64 / fs, e.ln()));
    }
    for (k, &e) in env.iter().enumerate().skip(i0) {
        if e < 0.1 * emax {
            t10 = (k - i0) as f64 / fs;
            break;
        }
    }
    let n = pts.len() as f64;
    let (st, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (t, y)| (a + t, b + y));
    let (tm, ym) = (st / n, sy / n);
    let (num, den) = pts.iter().fold((0.0, 0.0), |(a, b), (t, y)| {
        (a + (t - tm) * (y - ym), b + (t - tm) * (t - tm))
    });
    (-num / den, t10)
}

/// Advances both simulations to `duration` in alternating 5 ms slices, timing each.
fn run_side_by_side(scenes: [Scene; 2], duration: f64) -> [Record; 2] {
    let mut sims = scenes.map(|s| {
        let mut sim = Simulation::new(&s).expect("simulation builds");
        sim.set_ball_outputs(true);
        sim
    });
    let z = sims[0].bearing().z;
    let mut recs: [Record; 2] = std::array::from_fn(|_| Record {
        a: Vec::new(),
        q_outer: vec![Vec::new(); z],
        wall: 0.0,
        steps: 0,
        rejected: 0,
        rhs: 0,
    });
    let slice = 0.005;
    let mut t = 0.0;
    while t < duration - 1e-12 {
        t = (t + slice).min(duration);
        for (sim, rec) in sims.iter_mut().zip(recs.iter_mut()) {
            let start = Instant::now();
            let (a, q) = (&mut rec.a, &mut rec.q_outer);
            sim.advance_sampled(t, 1.0 / FS, &mut |ts, o| {
                if ts >= SKIP {
                    a.push(o[out::PEDESTAL_A_Z]);
                    for (j, qj) in q.iter_mut().enumerate() {
                        qj.push(o[out::CONTACT_START + z + j]);
                    }
                }
            })
            .expect("simulation runs");
            rec.wall += start.elapsed().as_secs_f64();
        }
    }
    for (sim, rec) in sims.iter().zip(recs.iter_mut()) {
        let s = sim.stats();
        (rec.steps, rec.rejected, rec.rhs) = (s.steps, s.rejected, s.rhs_evals);
    }
    recs
}

/// Wall time, accepted and rejected steps and RHS evaluations of one run to `duration` with no
/// sampling.
fn run_work(sc: &Scene, duration: f64) -> (f64, u64, u64, u64) {
    let mut sim = Simulation::new(sc).expect("simulation builds");
    let start = Instant::now();
    sim.advance(duration).expect("simulation runs");
    let wall = start.elapsed().as_secs_f64();
    let s = sim.stats();
    (wall, s.steps, s.rejected, s.rhs_evals)
}

/// Each spall pass of each ball: the outer force drops to exactly 0 (the ball is off the outer
/// race in the spall), returns, and peaks at the trailing-edge impact. Returns (ball, index of
/// the impact peak).
fn impacts(q: &[Vec<f64>]) -> Vec<(usize, usize)> {
    let search = (0.2e-3 * FS) as usize;
    let mut found = Vec::new();
    for (j, qj) in q.iter().enumerate() {
        let mut k = 1;
        while k < qj.len() {
            // End of a run of zeros of at least 10 µs.
            if qj[k - 1] == 0.0 && qj[k] > 0.0 {
                let zeros = qj[..k].iter().rev().take_while(|&&v| v == 0.0).count();
                if zeros as f64 / FS >= 10e-6 && k + search < qj.len() {
                    let peak = (k..k + search)
                        .max_by(|&a, &b| qj[a].total_cmp(&qj[b]))
                        .unwrap();
                    found.push((j, peak));
                    k += search;
                    continue;
                }
            }
            k += 1;
        }
    }
    found
}

/// Ring-down of the outer contact force after each impact: the 15–80 kHz band's envelope over
/// 1.5 ms from the peak, its decay rate and time to 10 %. Returns the per-pass (τ, t10) and the
/// first pass's segment (force, envelope) for the figure.
#[allow(clippy::type_complexity)]
fn rattle(q: &[Vec<f64>]) -> (Vec<(f64, f64)>, Option<(Vec<f64>, Vec<f64>)>) {
    let len = (1.5e-3 * FS) as usize;
    let pre = (0.1e-3 * FS) as usize;
    let mut res = Vec::new();
    let mut first = None;
    for (j, k) in impacts(q) {
        let qj = &q[j];
        if k < pre || k + len > qj.len() {
            continue;
        }
        let seg = &qj[k - pre..k + len];
        let Ok(band) = signal::bandpass(seg, FS, 15e3, 80e3) else {
            continue;
        };
        let env: Vec<f64> = signal::analytic_signal(&band)
            .unwrap()
            .iter()
            .map(|c| c.norm())
            .collect();
        // From the impact on (the first `pre` samples only pad the band-pass).
        let (sigma, t10) = decay(&env[pre..], FS, 0.05);
        res.push((1.0 / sigma, t10));
        if first.is_none() {
            first = Some((seg.to_vec(), env));
        }
    }
    (res, first)
}

/// pedestal.a.z of an impact-test scene minus the same run without the pulse, from the pulse
/// on for `window` s.
fn pulse_response(sc: &Scene, window: f64) -> Vec<f64> {
    let t0 = sc.pulse.as_ref().unwrap().t0;
    let run = |sc: &Scene| {
        let mut sim = Simulation::new(sc).unwrap();
        let mut a = Vec::new();
        sim.advance_sampled(t0 + window, 1.0 / FS, &mut |t, o| {
            if t >= t0 {
                a.push(o[out::PEDESTAL_A_Z]);
            }
        })
        .unwrap();
        a
    };
    let mut quiet = sc.clone();
    quiet.pulse = None;
    let (a, b) = (run(sc), run(&quiet));
    a.iter().zip(&b).map(|(x, y)| x - y).collect()
}

/// Damping ratio and frequency of the mode in `band` of a pulse response: the spectrum's
/// peak in the band, the band-passed envelope's decay rate σ, ζ = σ/√(σ² + ω_d²).
fn mode_damping(x: &[f64], band: (f64, f64)) -> (f64, f64) {
    let mut padded = x.to_vec();
    padded.resize((FS / 10.0) as usize, 0.0); // 10 Hz bins
    let spec = signal::amplitude_spectrum(&padded, FS, Window::Rectangular).unwrap();
    let f = signal::dominant_peak(&spec, band.0, band.1).unwrap().freq;
    let bp = signal::bandpass(x, FS, band.0, band.1).unwrap();
    let env: Vec<f64> = signal::analytic_signal(&bp)
        .unwrap()
        .iter()
        .map(|c| c.norm())
        .collect();
    let (sigma, _) = decay(&env, FS, 0.05);
    let wd = std::f64::consts::TAU * f;
    (sigma / (sigma * sigma + wd * wd).sqrt(), f)
}

fn write_csv(path: &Path, header: &str, cols: &[&[f64]]) {
    let n = cols.iter().map(|c| c.len()).min().unwrap_or(0);
    let mut s = String::from(header);
    s.push('\n');
    for i in 0..n {
        let row: Vec<String> = cols.iter().map(|c| format!("{:.6e}", c[i])).collect();
        s.push_str(&row.join(","));
        s.push('\n');
    }
    std::fs::write(path, s).unwrap();
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let out_dir = PathBuf::from(args.get(1).map_or("target/film_study", |s| s.as_str()));
    let duration: f64 = args
        .get(2)
        .map_or(0.3, |s| s.parse().expect("duration in s"));
    std::fs::create_dir_all(&out_dir).unwrap();
    let mut json = String::from("{\n");

    // The film at the L1 operating point (most loaded ball).
    let dry = scene("default.toml", false);
    let wet = scene("default.toml", true);
    let b = Bearing::new(&wet.bearing).unwrap();
    let op = OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0);
    let qs = solve(&b, &op).unwrap();
    let ball = qs
        .balls
        .iter()
        .max_by(|a, c| a.q_inner.total_cmp(&c.q_inner))
        .unwrap();
    println!(
        "oil: eta0 = {:.4e} Pa s at 70 C, alpha = 2e-8 1/Pa",
        b.film(Race::Inner).unwrap().lubricant.viscosity
    );
    for (race, q, alpha) in [
        (Race::Inner, ball.q_inner, ball.alpha_inner),
        (Race::Outer, ball.q_outer, ball.alpha_outer),
    ] {
        let f: &FilmContact = b.film(race).unwrap();
        let g = b.d * alpha.cos() / b.dm;
        let u = match race {
            Race::Inner => (op.shaft_speed - ball.cage_speed) * 0.5 * b.dm * (1.0 - g),
            Race::Outer => ball.cage_speed * 0.5 * b.dm * (1.0 + g),
        };
        let s = f.state(q, u);
        let k = b.k(race);
        let delta = (q / k).powf(2.0 / 3.0);
        let kh = 1.5 * k * delta.sqrt();
        let phi = FilmContact::series_factor(delta, s.h_central);
        println!(
            "{}: Q = {q:.1} N, u = {u:.2} m/s, U = {:.3e}, G = {:.0}, W = {:.3e}, k = {:.2}; \
             h_c = {:.3} um, h_min = {:.3} um, lambda = {:.1}; k_H = {kh:.3e}, k_f = {:.3e} N/m, \
             phi = {phi:.4}; c_f = {:.2} N s/m (c_br = 20)",
            race.name(),
            s.u,
            s.g,
            s.w,
            f.ellipticity,
            s.h_central * 1e6,
            s.h_min * 1e6,
            s.h_min / 0.1e-6,
            s.stiffness,
            s.damping
        );
        let _ = writeln!(
            json,
            "  \"film_{}\": {{\"q\": {q}, \"u\": {u}, \"U\": {}, \"G\": {}, \"W\": {}, \"k\": {}, \
             \"h_c\": {}, \"h_min\": {}, \"k_H\": {kh}, \"k_f\": {}, \"phi\": {phi}, \"c_f\": {}}},",
            race.name(),
            s.u,
            s.g,
            s.w,
            f.ellipticity,
            s.h_central,
            s.h_min,
            s.stiffness,
            s.damping
        );
    }

    // The spall scene, side by side.
    println!("default scene, full level (tilt held), {duration} s, dry and film side by side ...");
    let [r_dry, r_wet] = run_side_by_side([dry, wet], duration);
    for (name, r) in [("dry", &r_dry), ("film", &r_wet)] {
        println!(
            "{name}: {:.2} s wall ({:.2} s per simulated s), {} steps, {} rejected, {} RHS",
            r.wall,
            r.wall / duration,
            r.steps,
            r.rejected,
            r.rhs
        );
    }
    let cost = r_wet.wall / r_dry.wall;
    println!(
        "cost of the film: wall x{cost:.3}, RHS x{:.3}, wall per RHS x{:.3}",
        r_wet.rhs as f64 / r_dry.rhs as f64,
        cost / (r_wet.rhs as f64 / r_dry.rhs as f64)
    );
    // Controls for the cost: the paper's law with c_br = 11 N s/m (about the film's inner
    // c_f) on the same scene, and the healthy bearing with and without the film.
    let mut soft = scene("default.toml", false);
    soft.bearing.contact.c_br = 11.0;
    let w_soft = run_work(&soft, duration);
    println!(
        "control, c_br = 11 N s/m, no film: {:.2} s wall, {} steps, {} rejected, {} RHS",
        w_soft.0, w_soft.1, w_soft.2, w_soft.3
    );
    let healthy = |film: bool| {
        let mut s = scene("default.toml", film);
        s.defect = None;
        s
    };
    // Healthy: 0.2 s each, dry and film alternated twice, the faster of each pair kept.
    let hd = 0.2;
    let (sd, sf) = (healthy(false), healthy(true));
    let (mut w_hd, mut w_hf) = (run_work(&sd, hd), run_work(&sf, hd));
    let (d2, f2) = (run_work(&sd, hd), run_work(&sf, hd));
    w_hd.0 = w_hd.0.min(d2.0);
    w_hf.0 = w_hf.0.min(f2.0);
    println!(
        "control, healthy bearing {hd} s: c_br {} RHS ({:.2} s), film {} RHS ({:.2} s)",
        w_hd.3, w_hd.0, w_hf.3, w_hf.0
    );
    let _ = writeln!(
        json,
        "  \"control_soft\": [{}, {}, {}, {}],\n  \"control_healthy_duration\": {hd},\n  \"control_healthy\": [[{}, {}, {}, {}], [{}, {}, {}, {}]],",
        w_soft.0, w_soft.1, w_soft.2, w_soft.3, w_hd.0, w_hd.1, w_hd.2, w_hd.3, w_hf.0, w_hf.1,
        w_hf.2, w_hf.3
    );
    let _ = writeln!(
        json,
        "  \"duration\": {duration},\n  \"wall\": [{}, {}],\n  \"steps\": [{}, {}],\n  \"rejected\": [{}, {}],\n  \"rhs\": [{}, {}],",
        r_dry.wall, r_wet.wall, r_dry.steps, r_wet.steps, r_dry.rejected, r_wet.rejected, r_dry.rhs, r_wet.rhs
    );

    // Pedestal statistics and envelope spectra at 51.2 kHz.
    let fs_d = FS / DECIM as f64;
    let dec = |x: &[f64]| x.iter().step_by(DECIM).copied().collect::<Vec<f64>>();
    let (a_dry, a_wet) = (dec(&r_dry.a), dec(&r_wet.a));
    let mut env_specs = Vec::new();
    for (name, a) in [("dry", &a_dry), ("film", &a_wet)] {
        let (ku, cr) = (kurtosis(a), peak_to_rms(a));
        let rms = {
            let m = mean(a);
            (a.iter().map(|v| (v - m).powi(2)).sum::<f64>() / a.len() as f64).sqrt()
        };
        let es = signal::envelope_spectrum(a, fs_d, Some((2e3, 20e3)), Window::Hann).unwrap();
        let h: Vec<String> = signal::harmonics(&es, 980.0, 3, 15.0)
            .iter()
            .map(|p| p.map_or("null".into(), |p| format!("[{}, {}]", p.freq, p.amplitude)))
            .collect();
        println!(
            "{name}: pedestal.a.z rms {rms:.2} m/s2, kurtosis {ku:.2}, peak/rms {cr:.2}; \
             envelope (2-20 kHz) at BPFO x1..3 [Hz, m/s2]: {}",
            h.join(", ")
        );
        let _ = writeln!(
            json,
            "  \"pedestal_{name}\": {{\"rms\": {rms}, \"kurtosis\": {ku}, \"peak_to_rms\": {cr}, \"envelope_bpfo\": [{}]}},",
            h.join(", ")
        );
        env_specs.push(es);
    }
    let n = env_specs[0].len().min(env_specs[1].len());
    let freq: Vec<f64> = (0..n)
        .map(|i| i as f64 * env_specs[0].resolution())
        .collect();
    write_csv(
        &out_dir.join("envelope.csv"),
        "f_hz,dry,film",
        &[&freq, &env_specs[0].value[..n], &env_specs[1].value[..n]],
    );
    let seg = (0.02 * fs_d) as usize;
    let t: Vec<f64> = (0..seg).map(|i| SKIP + i as f64 / fs_d).collect();
    write_csv(
        &out_dir.join("pedestal.csv"),
        "t_s,dry,film",
        &[&t, &a_dry[..seg], &a_wet[..seg]],
    );

    // Ball rattle after the spall impacts.
    let mut first = Vec::new();
    for (name, r) in [("dry", &r_dry), ("film", &r_wet)] {
        let (passes, seg) = rattle(&r.q_outer);
        let tau = median(passes.iter().map(|p| p.0).collect());
        let t10 = median(passes.iter().map(|p| p.1).collect());
        println!(
            "{name}: ball rattle after {} impacts: e-folding time {:.1} us, time to 10 % {:.1} us (medians)",
            passes.len(),
            tau * 1e6,
            t10 * 1e6
        );
        let _ = writeln!(
            json,
            "  \"rattle_{name}\": {{\"impacts\": {}, \"tau\": {tau}, \"t10\": {t10}}},",
            passes.len()
        );
        first.push(seg.expect("an impact"));
    }
    let m = first[0].0.len().min(first[1].0.len());
    let t: Vec<f64> = (0..m).map(|i| i as f64 / FS - 0.1e-3).collect();
    write_csv(
        &out_dir.join("rattle.csv"),
        "t_s,q_dry,env_dry,q_film,env_film",
        &[&t, &first[0].0, &first[0].1, &first[1].0, &first[1].1],
    );

    // Impact test: damping ratios of fel and feh.
    println!("impact test (Fa 4000 N), full level, with and without the film ...");
    let window = 0.015;
    let mut resp = Vec::new();
    for (name, film) in [("dry", false), ("film", true)] {
        let x = pulse_response(&scene("impact-test-fa4000.toml", film), window);
        let (z_l, f_l) = mode_damping(&x, (300.0, 1200.0));
        let (z_h, f_h) = mode_damping(&x, (3000.0, 9000.0));
        println!("{name}: fel {f_l:.0} Hz, zeta {z_l:.4}; feh {f_h:.0} Hz, zeta {z_h:.4}");
        let _ = writeln!(
            json,
            "  \"modes_{name}\": {{\"fel\": {f_l}, \"zeta_fel\": {z_l}, \"feh\": {f_h}, \"zeta_feh\": {z_h}}},"
        );
        resp.push(x);
    }
    let m = resp[0].len().min(resp[1].len());
    let t: Vec<f64> = (0..m).map(|i| i as f64 / FS).collect();
    write_csv(
        &out_dir.join("pulse.csv"),
        "t_s,dry,film",
        &[&t, &resp[0][..m], &resp[1][..m]],
    );
    let _ = writeln!(json, "  \"cost_wall_ratio\": {cost}\n}}");
    std::fs::write(out_dir.join("summary.json"), json).unwrap();
    println!("wrote {}", out_dir.display());
}
