//! One run: simulate the scene, add seeded measurement noise, compute the kept metrics.

use super::spec::{fnv1a64, Keep, Run, Sweep};
use crate::signal::{envelope_spectrum, peak_near, Window};
use crate::simulation::{out, Simulation};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The fault frequencies whose envelope peaks are recorded, in column order: the cage, the
/// outer- and inner-race ball passes, and twice the ball spin (a spall on a ball).
pub const FAULTS: [&str; 4] = ["ftf", "bpfo", "bpfi", "two_bsf"];

/// The metric columns of a sweep (after the parameter columns), in order.
pub fn metric_columns(keep: &Keep) -> Vec<String> {
    let mut c: Vec<String> = FAULTS.iter().map(|f| format!("{f}_hz")).collect();
    if keep.rms {
        c.push("rms".into());
    }
    if keep.kurtosis {
        c.push("kurtosis".into());
    }
    if keep.crest_factor {
        c.push("crest_factor".into());
    }
    if keep.max_contact_force {
        c.extend(
            [
                "max_contact_force",
                "max_q_inner",
                "max_q_outer",
                "impact_q_median",
                "impact_q_zone",
                "impact_passes",
            ]
            .map(String::from),
        );
    }
    if keep.envelope_peaks {
        for f in FAULTS {
            for h in 1..=keep.harmonics {
                c.push(format!("env_{f}_{h}"));
            }
        }
    }
    if keep.raw_signal {
        c.push("signal_file".into());
    }
    c
}

/// Standard normal numbers from a seed: SplitMix64 and Box–Muller (no global state).
pub struct Gaussian {
    state: u64,
    spare: Option<f64>,
}

impl Gaussian {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            state: seed,
            spare: None,
        }
    }

    fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in (0, 1].
    fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 1.0) / (1u64 << 53) as f64
    }

    /// The next standard normal number.
    pub fn sample(&mut self) -> f64 {
        if let Some(s) = self.spare.take() {
            return s;
        }
        let r = (-2.0 * self.uniform().ln()).sqrt();
        let (s, c) = (std::f64::consts::TAU * self.uniform()).sin_cos();
        self.spare = Some(r * s);
        r * c
    }
}

/// The metric values of one successful run, in [`metric_columns`] order (as text).
pub type MetricRow = Vec<String>;

fn num(v: f64) -> String {
    format!("{v:e}")
}

/// Simulates one run and returns its metric row, or the error message.
/// `signal_dir` is where the raw signal goes if `keep.raw_signal` (created if missing).
pub fn evaluate(sweep: &Sweep, run: &Run, signal_dir: Option<&Path>) -> Result<MetricRow, String> {
    let (scene, noise_rms) = sweep.scene_for(run)?;
    let keep = &sweep.keep;
    let mut sim = Simulation::new(&scene).map_err(|e| e.to_string())?;
    let names: Vec<String> = sim.output_table().into_iter().map(|o| o.name).collect();
    let col = names
        .iter()
        .position(|n| *n == keep.signal)
        .ok_or_else(|| format!("output '{}' does not exist", keep.signal))?;
    let z = sim.bearing().z;
    let dt = 1.0 / scene.output.sample_rate;
    let skip = scene.output.skip;
    let mut times = Vec::new();
    let mut x = Vec::new();
    let (mut q_in, mut q_out) = (0.0_f64, 0.0_f64);
    // Largest contact force on the defective race (outer if healthy or a ball) at each sample.
    let race_offset = match scene.defect.as_ref().map(|d| d.ring) {
        Some(crate::defect::Site::Inner) => 0,
        _ => z,
    };
    let mut q_race = Vec::new();
    // The paper's impact force (Sec. 3.1, 3.4: "the maximum contact force at impact point"):
    // per ball pass, the largest force on the defective race while that ball is inside the
    // spall zone (the trailing-edge hit), not the rattling after it left. Needs a level that
    // knows ball positions (Model::in_spall_zone); otherwise no passes are recorded.
    // Per ball: Some((largest force so far, pass started after output.skip)) while inside.
    let mut zone_max: Vec<Option<(f64, bool)>> = vec![None; z];
    let mut pass_maxima: Vec<f64> = Vec::new();
    sim.advance_sampled_with_model(scene.output.duration, dt, &mut |t, o, model| {
        let counted = t >= skip - 1e-12;
        let r = out::CONTACT_START + race_offset;
        for (j, zm) in zone_max.iter_mut().enumerate() {
            if model.in_spall_zone(j) {
                let q = o[r + j];
                *zm = Some(zm.map_or((q, counted), |(m, c)| (m.max(q), c)));
            } else if let Some((m, c)) = zm.take() {
                if c {
                    pass_maxima.push(m);
                }
            }
        }
        if !counted {
            return;
        }
        times.push(t);
        x.push(o[col]);
        let c = out::CONTACT_START;
        for q in &o[c..c + z] {
            q_in = q_in.max(*q);
        }
        for q in &o[c + z..c + 2 * z] {
            q_out = q_out.max(*q);
        }
        let r = c + race_offset;
        q_race.push(o[r..r + z].iter().fold(0.0_f64, |m, q| m.max(*q)));
    })
    .map_err(|e| e.to_string())?;
    if x.len() < 16 {
        return Err(format!(
            "only {} samples after output.skip: lengthen output.duration",
            x.len()
        ));
    }
    if noise_rms > 0.0 {
        // Seeded by the run's parameters, never by the thread that runs it.
        let mut g = Gaussian::new(fnv1a64(format!("noise:{}", run.id).as_bytes()));
        for v in x.iter_mut() {
            *v += noise_rms * g.sample();
        }
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(format!(
            "{} is not finite at t = {} s",
            keep.signal, times[i]
        ));
    }

    let shaft_hz = scene.operating.shaft_speed / std::f64::consts::TAU;
    let ftf = sim.cage_speed() / std::f64::consts::TAU;
    // 2·BSF: the kinematic balls' spin at the model's cage speed (docs/model.md#ball-spall).
    let two_bsf = 2.0 * sim.bearing().kinematic_spin_per_orbit() * ftf;
    let freqs = [ftf, z as f64 * ftf, z as f64 * (shaft_hz - ftf), two_bsf];
    let mut row: MetricRow = freqs.iter().map(|f| num(*f)).collect();

    let mean = x.iter().sum::<f64>() / x.len() as f64;
    let m2 = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / x.len() as f64;
    let m4 = x.iter().map(|v| (v - mean).powi(4)).sum::<f64>() / x.len() as f64;
    let rms = m2.sqrt();
    let peak = x.iter().map(|v| (v - mean).abs()).fold(0.0, f64::max);
    if keep.rms {
        row.push(num(rms));
    }
    if keep.kurtosis {
        row.push(num(if m2 > 0.0 { m4 / (m2 * m2) } else { f64::NAN }));
    }
    if keep.crest_factor {
        row.push(num(if rms > 0.0 { peak / rms } else { f64::NAN }));
    }
    if keep.max_contact_force {
        // Typical impact: the median over ball passes (segments of 1/BPFO, or 1/BPFI for an
        // inner-race spall) of the largest force on the defective race in each pass; robust
        // to a single rattling spike, unlike the maximum.
        let f_pass = if race_offset == 0 { freqs[2] } else { freqs[1] };
        let seg = (scene.output.sample_rate / f_pass).round() as usize;
        let mut maxima: Vec<f64> = if seg >= 1 {
            q_race
                .chunks_exact(seg)
                .map(|c| c.iter().fold(0.0_f64, |m, q| m.max(*q)))
                .collect()
        } else {
            Vec::new()
        };
        maxima.sort_by(|a, b| a.total_cmp(b));
        let median = match maxima.len() {
            0 => f64::NAN,
            n if n % 2 == 1 => maxima[n / 2],
            n => 0.5 * (maxima[n / 2 - 1] + maxima[n / 2]),
        };
        // Passes still inside the zone at the end are incomplete and not counted.
        pass_maxima.sort_by(|a, b| a.total_cmp(b));
        let n = pass_maxima.len();
        let zone = match n {
            0 => f64::NAN,
            n if n % 2 == 1 => pass_maxima[n / 2],
            n => 0.5 * (pass_maxima[n / 2 - 1] + pass_maxima[n / 2]),
        };
        row.extend([
            num(q_in.max(q_out)),
            num(q_in),
            num(q_out),
            num(median),
            num(zone),
            n.to_string(),
        ]);
    }
    if keep.envelope_peaks {
        let fs = scene.output.sample_rate;
        let hi = keep.band[1].min(0.49 * fs);
        let spec = envelope_spectrum(&x, fs, Some((keep.band[0], hi)), Window::Hann)
            .map_err(|e| format!("envelope spectrum: {e}"))?;
        for f in freqs {
            for h in 1..=keep.harmonics {
                let fh = h as f64 * f;
                let a = peak_near(&spec, fh, keep.tolerance * fh).map_or(f64::NAN, |p| p.value);
                row.push(num(a));
            }
        }
    }
    if keep.raw_signal {
        let dir = signal_dir.ok_or("raw_signal needs an output folder")?;
        let name = format!("run-{:05}-{}.csv", run.index, run.id);
        write_signal(&dir.join(&name), &keep.signal, &times, &x)?;
        row.push(PathBuf::from("signals").join(name).display().to_string());
    }
    Ok(row)
}

fn write_signal(path: &Path, name: &str, t: &[f64], x: &[f64]) -> Result<(), String> {
    let err = |e: std::io::Error| format!("writing {}: {e}", path.display());
    if let Some(d) = path.parent() {
        std::fs::create_dir_all(d).map_err(err)?;
    }
    let mut w = std::io::BufWriter::new(std::fs::File::create(path).map_err(err)?);
    writeln!(w, "time,{name}").map_err(err)?;
    for (t, v) in t.iter().zip(x) {
        writeln!(w, "{t:.9},{v:e}").map_err(err)?;
    }
    w.flush().map_err(err)
}
