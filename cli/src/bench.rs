//! `raceway bench`: speed against accuracy for every available level and method (
//! docs/model.md#measuring). Not part of CI.
//!
//! Scenes (all on the default scene's Table-1 bearing, Fa 4000 N, Fr 1000 N, 9900 rpm):
//! S1 healthy, S2 outer-race spall 1.0 × 0.2 mm at the load-zone centre, S3 inner-race spall
//! 1.0 × 0.2 mm, S4 speed run-up 6000 → 9900 rpm with the outer-race spall (the speed is an input
//! changed every millisecond, as an FMU master would). Every scene is run at every level that
//! [`raceway::models::build`] supports (unsupported levels get one row with status
//! `unsupported`), with RKF45, DOPRI5 and DOP853 at rtol 1e-3 … 1e-10, against a reference per
//! scene and level: DOP853 at rtol 1e-12, cross-checked by DOPRI5 at 1e-11 (that row's errors
//! are the reference's own error estimate, status `crosscheck`).
//!
//! Error measures on the post-transient window (t ≥ skip) of `pedestal.a.z`, sampled at 51.2 kHz:
//! E1 relative RMS error (reference RMS floored at 1 m/s²); E2 largest relative amplitude error of the envelope-spectrum peaks at
//! the fault frequency × 1…5 (band 1–20 kHz) and E2_df the largest shift of those peaks in bins;
//! E3 RMS difference of the Welch PSDs in dB over 0.1–20 kHz. E2 is not defined for the healthy
//! bearing (no lines) and the run-up (the fault frequency sweeps). The cheap levels (kinematic, quasi-static) integrate only two
//! angles exactly, so they get one row per scene with their errors against the reference of the
//! highest dynamic level (status `vs_<level>`), and so does each lower dynamic level's
//! reference: the level-against-level comparison.
//!
//! Work: steps, rejected steps, RHS evaluations, and the median wall time of 3 runs (release,
//! one thread). A run that fails (step-size underflow, step budget, wall-time limit) is a row
//! with its status, never a hang.

use raceway::signal::{envelope_spectrum, peak_near, welch_psd, Spectrum, WelchConfig, Window};
use raceway::{out, Fidelity, MethodName, OperatingPoint, Scene, SimError, Simulation, WorkStats};
use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Output folder for bench.csv and throughput.csv
    #[arg(long, default_value = "docs/bench")]
    pub out: PathBuf,
    /// Quick run: 0.1 s scenes, rtol 1e-3 … 1e-10 by decades at the cheap dynamic levels (the
    /// E1-against-rtol slope needs 1e-4 … 1e-9); the expensive levels (reduced, full) only on
    /// S2, at rtol 1e-4 … 1e-9 by decades, one timed run each
    #[arg(long)]
    pub quick: bool,
    /// Simulated time per scene [s] (default 0.15, quick 0.1)
    #[arg(long)]
    pub duration: Option<f64>,
    /// Comma-separated scenes (S1,S2,S3,S4)
    #[arg(long, default_value = "S1,S2,S3,S4")]
    pub scenes: String,
    /// Comma-separated methods (rkf45,dopri5,dop853)
    #[arg(long, default_value = "rkf45,dopri5,dop853")]
    pub methods: String,
    /// Comma-separated levels (kinematic,quasi_static,lumped,reduced,full)
    #[arg(long, default_value = "kinematic,quasi_static,lumped,reduced,full")]
    pub levels: String,
    /// Comma-separated relative tolerances (default 1e-3 … 1e-10 by decades)
    #[arg(long)]
    pub rtols: Option<String>,
    /// Timed repetitions per point (the median is reported)
    #[arg(long, default_value_t = 3)]
    pub repeats: usize,
    /// Wall-time limit of one run [s]: beyond it the run ends with status `timeout`
    #[arg(long, default_value_t = 60.0)]
    pub time_limit: f64,
    /// Simulated time of the throughput measurement on the default scene [s]
    #[arg(long, default_value_t = 1.0)]
    pub throughput_duration: f64,
    /// PI step-size controller β (`solver.pi_beta`, 0 … 0.2) of the measured runs and the
    /// throughput runs (not of the references); default: the scene's (0, the I-controller)
    #[arg(long)]
    pub pi_beta: Option<f64>,
}

/// Output sample rate [Hz] and the transient skipped before measuring errors [s].
const FS: f64 = 51_200.0;
const SKIP: f64 = 0.02;
/// Floor of the reference RMS in E1 [m/s²] (a healthy bearing's vibration is below it).
const E1_FLOOR: f64 = 1.0;
/// Envelope band [Hz].
const ENV_BAND: (f64, f64) = (1_000.0, 20_000.0);
/// Welch PSD band for E3 [Hz].
const PSD_BAND: (f64, f64) = (100.0, 20_000.0);
/// Run-up speeds [rpm].
const RUNUP: (f64, f64) = (6_000.0, 9_900.0);
/// Input update interval of the run-up [s].
const RUNUP_DT: f64 = 1e-3;

/// One simulated signal with its work counters.
struct Run {
    signal: Vec<f64>,
    stats: WorkStats,
    wall: f64,
    fault_hz: f64,
}

fn scene_of(name: &str, level: Fidelity) -> Result<Scene, String> {
    let mut s = Scene::default_scene();
    s.fidelity = level;
    s.name = name.to_string();
    match name {
        "S1" => s.defect = None,
        "S2" | "S4" => {}
        "S3" => {
            if let Some(d) = s.defect.as_mut() {
                d.ring = raceway::Site::Inner;
                d.theta0 = 0.0;
            }
        }
        other => return Err(format!("unknown scene {other}: expected S1, S2, S3 or S4")),
    }
    if name == "S4" {
        s.operating.shaft_speed = raceway::rpm_to_rad_s(RUNUP.0);
    }
    Ok(s)
}

/// Scenes whose envelope spectrum has fault lines at a fixed frequency (E2 is defined): not the
/// healthy bearing (no lines) and not the run-up (the frequency sweeps).
fn has_lines(scene: &str) -> bool {
    scene == "S2" || scene == "S3"
}

fn is_outer(scene: &Scene) -> bool {
    !matches!(
        scene.defect.as_ref().map(|d| d.ring),
        Some(raceway::Site::Inner)
    )
}

/// Runs one scene; returns the post-transient pedestal acceleration.
fn run(
    scene: &Scene,
    method: MethodName,
    rtol: f64,
    duration: f64,
    time_limit: f64,
) -> Result<Run, SimError> {
    let mut sc = scene.clone();
    sc.solver.method = method;
    sc.solver.rtol = rtol;
    sc.solver.max_steps = 5_000_000;
    let start = Instant::now();
    let mut sim = Simulation::new(&sc)?;
    let n = (duration * FS).round() as usize;
    let mut signal = Vec::with_capacity(n);
    let runup = sc.name == "S4";
    let chunk = if runup { RUNUP_DT } else { 0.01 };
    let mut t = 0.0;
    let base = sc.operating;
    while t < duration - 1e-12 {
        let t_next = (t + chunk).min(duration);
        if runup {
            let rpm = RUNUP.0 + (RUNUP.1 - RUNUP.0) * (t / duration);
            sim.set_inputs(OperatingPoint {
                shaft_speed: rpm * std::f64::consts::TAU / 60.0,
                ..base
            })?;
        }
        sim.advance_sampled(t_next, 1.0 / FS, &mut |ts, o| {
            if ts >= SKIP - 1e-12 {
                signal.push(o[out::PEDESTAL_A_Z]);
            }
        })?;
        t = t_next;
        if start.elapsed().as_secs_f64() > time_limit {
            return Err(SimError::Solver {
                t,
                message: format!("timeout: wall-time limit {time_limit} s reached"),
            });
        }
    }
    let wall = start.elapsed().as_secs_f64();
    let z = sim.bearing().z as f64;
    let wc = sim.cage_speed();
    let fault_hz = if is_outer(&sc) {
        z * wc / std::f64::consts::TAU
    } else {
        z * (sim.inputs().shaft_speed - wc) / std::f64::consts::TAU
    };
    Ok(Run {
        signal,
        stats: sim.stats(),
        wall,
        fault_hz,
    })
}

/// Error measures of `x` against `r`: (E1, E2, E2_df, E3).
fn errors(x: &[f64], r: &[f64], fault_hz: Option<f64>) -> (f64, f64, f64, f64) {
    let n = x.len().min(r.len());
    if n < 64 {
        return (f64::NAN, f64::NAN, f64::NAN, f64::NAN);
    }
    let (x, r) = (&x[..n], &r[..n]);
    let num: f64 = x.iter().zip(r).map(|(a, b)| (a - b) * (a - b)).sum();
    // Relative to the reference RMS, floored at E1_FLOOR so that the nearly silent healthy
    // bearing is not divided by the reference's own round-off.
    let ref_ms = r.iter().map(|b| b * b).sum::<f64>() / n as f64;
    let e1 = (num / n as f64).sqrt() / ref_ms.sqrt().max(E1_FLOOR);
    let (mut e2, mut df) = (f64::NAN, f64::NAN);
    let silent = x.iter().all(|v| *v == 0.0);
    if silent && fault_hz.is_some() {
        // No vibration at all (quasi-static level): every peak is missing.
        e2 = 1.0;
    } else if let Some(f0) = fault_hz.filter(|f| *f > 0.0) {
        let band = Some(ENV_BAND);
        if let (Ok(sx), Ok(sr)) = (
            envelope_spectrum(x, FS, band, Window::Hann),
            envelope_spectrum(r, FS, band, Window::Hann),
        ) {
            let (a, b) = envelope_peaks(&sx, &sr, f0);
            e2 = a;
            df = b;
        }
    }
    let seg = 2048.min(n);
    let cfg = WelchConfig {
        segment_len: seg,
        overlap: 0.5,
        window: Window::Hann,
    };
    let e3 = match (welch_psd(x, FS, &cfg), welch_psd(r, FS, &cfg)) {
        (Ok(px), Ok(pr)) => {
            let mut acc = 0.0;
            let mut cnt = 0usize;
            let floor = pr.value.iter().cloned().fold(0.0, f64::max) * 1e-30 + 1e-300;
            for k in 0..px.len().min(pr.len()) {
                let f = pr.freq[k];
                if f >= PSD_BAND.0 && f <= PSD_BAND.1 {
                    let d = 10.0 * ((px.value[k] + floor) / (pr.value[k] + floor)).log10();
                    acc += d * d;
                    cnt += 1;
                }
            }
            if cnt > 0 {
                (acc / cnt as f64).sqrt()
            } else {
                f64::NAN
            }
        }
        _ => f64::NAN,
    };
    (e1, e2, df, e3)
}

/// Largest relative amplitude error and bin shift of the envelope peaks at f0 × 1…5.
fn envelope_peaks(sx: &Spectrum, sr: &Spectrum, f0: f64) -> (f64, f64) {
    let tol = (0.1 * f0).max(3.0 * sr.resolution());
    let (mut e2, mut df) = (0.0f64, 0.0f64);
    for h in 1..=5 {
        let f = f0 * h as f64;
        match (peak_near(sx, f, tol), peak_near(sr, f, tol)) {
            (Some(px), Some(pr)) => {
                if pr.amplitude > 0.0 {
                    e2 = e2.max((px.amplitude - pr.amplitude).abs() / pr.amplitude);
                }
                df = df.max((px.bin as f64 - pr.bin as f64).abs());
            }
            (None, Some(_)) => return (1.0, f64::NAN),
            _ => return (f64::NAN, f64::NAN),
        }
    }
    (e2, df)
}

fn parse_list<T>(s: &str, f: impl Fn(&str) -> Option<T>, what: &str) -> Result<Vec<T>, String> {
    s.split(',')
        .map(|x| x.trim())
        .filter(|x| !x.is_empty())
        .map(|x| f(x).ok_or_else(|| format!("unknown {what} '{x}'")))
        .collect()
}

/// Runs `repeats` times (stopping at the first failure): the wall times of the successful runs
/// and the last outcome (`None` only when `repeats` is 0).
fn run_repeated(
    scene: &Scene,
    method: MethodName,
    rtol: f64,
    duration: f64,
    time_limit: f64,
    repeats: usize,
) -> (Vec<f64>, Option<Result<Run, SimError>>) {
    let mut walls = Vec::new();
    let mut last = None;
    for _ in 0..repeats {
        match run(scene, method, rtol, duration, time_limit) {
            Ok(r) => {
                walls.push(r.wall);
                last = Some(Ok(r));
            }
            Err(e) => {
                last = Some(Err(e));
                break;
            }
        }
    }
    (walls, last)
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn fmt(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        format!("{v:.6e}")
    }
}

/// One CSV row.
#[allow(clippy::too_many_arguments)]
fn row(
    w: &mut impl Write,
    scene: &str,
    level: &str,
    method: &str,
    rtol: f64,
    stats: Option<WorkStats>,
    wall: f64,
    e: (f64, f64, f64, f64),
    status: &str,
) -> Result<(), String> {
    let (st, rj, ev) = stats.map_or((String::new(), String::new(), String::new()), |s| {
        (
            s.steps.to_string(),
            s.rejected.to_string(),
            s.rhs_evals.to_string(),
        )
    });
    let status = status.replace([',', '\n', '"'], ";");
    writeln!(
        w,
        "{scene},{level},{method},{},{st},{rj},{ev},{},{},{},{},{},{status}",
        if rtol.is_nan() {
            String::new()
        } else {
            format!("{rtol:e}")
        },
        fmt(wall),
        fmt(e.0),
        fmt(e.1),
        fmt(e.2),
        fmt(e.3)
    )
    .map_err(|e| e.to_string())
}

fn status_of(e: &SimError) -> String {
    match e {
        SimError::Solver { message, .. } if message.starts_with("timeout") => {
            format!("timeout: {message}")
        }
        other => format!("failed: {other}"),
    }
}

pub fn run_cli(args: Args) -> Result<(), String> {
    let started = Instant::now();
    let result = run_all(&args);
    // What the document needs to know about this run: how it was made and how long it took.
    let info = args.out.join("run.csv");
    let default_method = Scene::default_scene().solver.method.name();
    let command: Vec<String> = std::env::args().collect();
    let text = format!(
        "key,value\ncommand,\"{}\"\nwall_s,{:.1}\nquick,{}\ncode_default_method,{default_method}\nstatus,{}\n",
        command.join(" ").replace('"', "'"),
        started.elapsed().as_secs_f64(),
        args.quick,
        match &result {
            Ok(()) => "ok".to_string(),
            Err(e) => format!("failed: {}", e.replace([',', '\n', '"'], ";")),
        }
    );
    if std::fs::write(&info, text).is_ok() {
        eprintln!(
            "wrote {} (bench wall time {:.1} s)",
            info.display(),
            started.elapsed().as_secs_f64()
        );
    }
    result
}

fn run_all(args: &Args) -> Result<(), String> {
    let duration = args.duration.unwrap_or(if args.quick { 0.1 } else { 0.15 });
    if duration.is_nan() || duration <= SKIP + 0.02 {
        return Err(format!(
            "--duration {duration}: must exceed {} s",
            SKIP + 0.02
        ));
    }
    if let Some(b) = args.pi_beta {
        // The scene's own check of solver.pi_beta, before any run.
        let mut s = Scene::default_scene();
        s.solver.pi_beta = b;
        s.validate().map_err(|e| format!("--pi-beta {b}: {e}"))?;
    }
    let rtols: Vec<f64> = match &args.rtols {
        Some(s) => parse_list(s, |x| x.parse().ok().filter(|v: &f64| *v > 0.0), "rtol")?,
        None => (3..=10).map(|k| 10f64.powi(-k)).collect(),
    };
    let scenes = parse_list(
        &args.scenes,
        |x| ["S1", "S2", "S3", "S4"].contains(&x).then(|| x.to_string()),
        "scene",
    )?;
    let methods = parse_list(&args.methods, MethodName::from_name, "method")?;
    let levels = parse_list(&args.levels, Fidelity::from_name, "level")?;
    let repeats = args.repeats.max(1);
    std::fs::create_dir_all(&args.out).map_err(|e| format!("{}: {e}", args.out.display()))?;
    let path = args.out.join("bench.csv");
    let mut w = std::io::BufWriter::new(
        std::fs::File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?,
    );
    writeln!(
        w,
        "scene,level,method,rtol,steps,rejected,rhs_evals,wall_s,E1,E2,E2_df,E3,status"
    )
    .map_err(|e| e.to_string())?;
    let dynamic = |l: Fidelity| !matches!(l, Fidelity::Kinematic | Fidelity::QuasiStatic);
    for scene_name in &scenes {
        // Reference of the highest dynamic level available (for the cheap levels' rows).
        let mut top: Option<(String, Vec<f64>)> = None;
        // References of the dynamic levels: (level, signal, work, wall, fault frequency).
        let mut refs: Vec<(String, Vec<f64>, WorkStats, f64, f64)> = Vec::new();
        let mut cheap: Vec<Fidelity> = Vec::new();
        for &level in &levels {
            let scene = scene_of(scene_name, level)?;
            if let Err(e) = Simulation::new(&scene) {
                let status = match &e {
                    SimError::Unsupported(_) => "unsupported".to_string(),
                    other => status_of(other),
                };
                eprintln!("{scene_name} {}: {status}", level.name());
                row(
                    &mut w,
                    scene_name,
                    level.name(),
                    "",
                    f64::NAN,
                    None,
                    f64::NAN,
                    (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
                    &status,
                )?;
                continue;
            }
            if !dynamic(level) {
                cheap.push(level);
                continue;
            }
            let expensive = matches!(level, Fidelity::Reduced | Fidelity::Full);
            if args.quick && expensive && scene_name != "S2" {
                row(
                    &mut w,
                    scene_name,
                    level.name(),
                    "",
                    f64::NAN,
                    None,
                    f64::NAN,
                    (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
                    "skipped (--quick: expensive levels on S2 only)",
                )?;
                continue;
            }
            let (level_rtols, level_repeats) = if args.quick && expensive {
                (
                    rtols
                        .iter()
                        .copied()
                        .filter(|r| {
                            // The decades 1e-4 … 1e-9 that the E1-against-rtol slope is fitted
                            // over (six points: three gave slopes that hung on one lucky point).
                            let k = -r.log10();
                            (1e-9 * 0.999..=1e-4 * 1.001).contains(r)
                                && (k - k.round()).abs() < 1e-6
                        })
                        .collect::<Vec<f64>>(),
                    1,
                )
            } else {
                (rtols.clone(), repeats)
            };
            let limit = args.time_limit;
            // Reference: DOP853 at 1e-12 (1e-11 if that fails), cross-checked by DOPRI5 at 1e-11.
            let reference = run(&scene, MethodName::Dop853, 1e-12, duration, limit * 4.0)
                .or_else(|_| run(&scene, MethodName::Dop853, 1e-11, duration, limit * 4.0));
            let reference = match reference {
                Ok(r) => r,
                Err(e) => {
                    row(
                        &mut w,
                        scene_name,
                        level.name(),
                        "dop853",
                        1e-12,
                        None,
                        f64::NAN,
                        (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
                        &format!("reference {}", status_of(&e)),
                    )?;
                    continue;
                }
            };
            let fault = has_lines(scene_name).then_some(reference.fault_hz);
            row(
                &mut w,
                scene_name,
                level.name(),
                "dop853",
                1e-12,
                Some(reference.stats),
                reference.wall,
                (0.0, 0.0, 0.0, 0.0),
                "reference",
            )?;
            match run(&scene, MethodName::Dopri5, 1e-11, duration, limit * 4.0) {
                Ok(c) => row(
                    &mut w,
                    scene_name,
                    level.name(),
                    "dopri5",
                    1e-11,
                    Some(c.stats),
                    c.wall,
                    errors(&c.signal, &reference.signal, fault),
                    "crosscheck",
                )?,
                Err(e) => row(
                    &mut w,
                    scene_name,
                    level.name(),
                    "dopri5",
                    1e-11,
                    None,
                    f64::NAN,
                    (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
                    &format!("crosscheck {}", status_of(&e)),
                )?,
            }
            let mut measured = scene.clone();
            if let Some(b) = args.pi_beta {
                measured.solver.pi_beta = b;
            }
            for &method in &methods {
                for &rtol in &level_rtols {
                    let (walls, last) =
                        run_repeated(&measured, method, rtol, duration, limit, level_repeats);
                    match last {
                        Some(Ok(r)) => {
                            let e = errors(&r.signal, &reference.signal, fault);
                            eprintln!(
                                "{scene_name} {} {} {rtol:e}: {} RHS, {:.4} s, E1 {:.2e}",
                                level.name(),
                                method.name(),
                                r.stats.rhs_evals,
                                median(walls.clone()),
                                e.0
                            );
                            row(
                                &mut w,
                                scene_name,
                                level.name(),
                                method.name(),
                                rtol,
                                Some(r.stats),
                                median(walls),
                                e,
                                "ok",
                            )?;
                        }
                        Some(Err(e)) => {
                            eprintln!(
                                "{scene_name} {} {} {rtol:e}: {}",
                                level.name(),
                                method.name(),
                                status_of(&e)
                            );
                            row(
                                &mut w,
                                scene_name,
                                level.name(),
                                method.name(),
                                rtol,
                                None,
                                f64::NAN,
                                (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
                                &status_of(&e),
                            )?;
                        }
                        None => {}
                    }
                }
            }
            refs.push((
                level.name().to_string(),
                reference.signal.clone(),
                reference.stats,
                reference.wall,
                reference.fault_hz,
            ));
            top = Some((level.name().to_string(), reference.signal));
        }
        // The lower dynamic levels' references against the highest one (level against level).
        if let Some((top_name, top_sig)) = &top {
            for (name, sig, stats, wall, fault_hz) in refs.iter().filter(|r| &r.0 != top_name) {
                row(
                    &mut w,
                    scene_name,
                    name,
                    "dop853",
                    1e-12,
                    Some(*stats),
                    *wall,
                    errors(sig, top_sig, has_lines(scene_name).then_some(*fault_hz)),
                    &format!("vs_{top_name}"),
                )?;
            }
        }
        // The cheap levels against the highest dynamic level's reference.
        for level in cheap {
            let scene = scene_of(scene_name, level)?;
            let (walls, last) = run_repeated(
                &scene,
                MethodName::Dop853,
                1e-6,
                duration,
                args.time_limit,
                repeats,
            );
            match last {
                Some(Ok(r)) => {
                    let (e, status) = match &top {
                        Some((name, sig)) => (
                            errors(&r.signal, sig, has_lines(scene_name).then_some(r.fault_hz)),
                            format!("vs_{name}"),
                        ),
                        None => (
                            (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
                            "ok (no dynamic reference)".to_string(),
                        ),
                    };
                    row(
                        &mut w,
                        scene_name,
                        level.name(),
                        "dop853",
                        1e-6,
                        Some(r.stats),
                        median(walls),
                        e,
                        &status,
                    )?;
                }
                Some(Err(e)) => row(
                    &mut w,
                    scene_name,
                    level.name(),
                    "dop853",
                    1e-6,
                    None,
                    f64::NAN,
                    (f64::NAN, f64::NAN, f64::NAN, f64::NAN),
                    &status_of(&e),
                )?,
                None => {}
            }
        }
        w.flush().map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())?;
    drop(w);
    eprintln!("wrote {}", path.display());
    throughput(args, &levels)
}

/// Wall seconds per simulated second of the default scene (examples/scenes/default.toml) at each
/// available level, DOP853 at the scene's rtol, sampled at 51.2 kHz, median of the repeats
/// (reduced and full: at most 50 ms, one run). Each point twice, side by side: with every output
/// (`all`) and with the bearing-level outputs only (`bearing`, what a spectrum of
/// `pedestal.a.z` needs: [`Simulation::set_ball_outputs`]`(false)`).
fn throughput(args: &Args, levels: &[Fidelity]) -> Result<(), String> {
    let path = args.out.join("throughput.csv");
    let mut w = std::io::BufWriter::new(
        std::fs::File::create(&path).map_err(|e| format!("{}: {e}", path.display()))?,
    );
    writeln!(
        w,
        "scene,level,method,rtol,simulated_s,steps,rhs_evals,wall_s,wall_per_simulated_s,cpu_s,cpu_per_simulated_s,status,setup_s,advance_per_simulated_s,outputs"
    )
    .map_err(|e| e.to_string())?;
    // The lumped level also at the loose tolerances that keep the fault lines in their bins
    // (E2_df = 0 at rtol 1e-3 in the sweep): the cost of the "fault frequencies only" question.
    let mut points: Vec<(Fidelity, Option<f64>, bool)> = Vec::new();
    for &level in levels {
        points.push((level, None, true));
        points.push((level, None, false));
        if level == Fidelity::Lumped {
            points.push((level, Some(1e-3), true));
            points.push((level, Some(1e-4), true));
        }
    }
    for (level, rtol, ball_outputs) in points {
        // The expensive levels (reduced, full) are timed over at most 50 ms, once.
        let expensive = matches!(level, Fidelity::Reduced | Fidelity::Full);
        let d = if expensive {
            args.throughput_duration.min(0.05)
        } else {
            args.throughput_duration
        };
        let repeats = if expensive { 1 } else { args.repeats.max(1) };
        let mut scene = Scene::default_scene();
        scene.fidelity = level;
        if let Some(r) = rtol {
            scene.solver.rtol = r;
        }
        if let Some(b) = args.pi_beta {
            scene.solver.pi_beta = b;
        }
        let mut walls = Vec::new();
        let mut cpus = Vec::new();
        // Set-up (Simulation::new: L1 solve, spall table) and advance timed apart as well: the
        // per-simulated-second cost of a long run is the advance's, a short run pays the set-up.
        let mut setups = Vec::new();
        let mut advances = Vec::new();
        let mut stats = None;
        let mut status = "ok".to_string();
        for _ in 0..repeats {
            let start = Instant::now();
            let cpu0 = thread_cpu_seconds();
            let mut setup = f64::NAN;
            let result = Simulation::new(&scene).and_then(|mut sim| {
                setup = start.elapsed().as_secs_f64();
                sim.set_ball_outputs(ball_outputs);
                let mut acc = 0.0;
                sim.advance_sampled(d, 1.0 / FS, &mut |_, o| acc += o[out::PEDESTAL_A_Z])?;
                std::hint::black_box(acc);
                Ok(sim.stats())
            });
            match result {
                Ok(s) => {
                    let wall = start.elapsed().as_secs_f64();
                    walls.push(wall);
                    setups.push(setup);
                    advances.push(wall - setup);
                    cpus.push(thread_cpu_seconds() - cpu0);
                    stats = Some(s);
                }
                Err(SimError::Unsupported(_)) => {
                    status = "unsupported".into();
                    break;
                }
                Err(e) => {
                    status = status_of(&e);
                    break;
                }
            }
        }
        // Medians of the timed runs (NaN when none finished).
        let med = |v: Vec<f64>| if v.is_empty() { f64::NAN } else { median(v) };
        let (wall, cpu, setup, advance) = (med(walls), med(cpus), med(setups), med(advances));
        let (steps, evals) = stats.map_or((String::new(), String::new()), |s| {
            (s.steps.to_string(), s.rhs_evals.to_string())
        });
        let outputs = if ball_outputs { "all" } else { "bearing" };
        eprintln!(
            "default scene, {} ({outputs} outputs): {} wall s ({} CPU s) per simulated s, of \
             which set-up {} s and advance {} s per simulated s ({status})",
            level.name(),
            fmt(wall / d),
            fmt(cpu / d),
            fmt(setup),
            fmt(advance / d)
        );
        writeln!(
            w,
            "default,{},{},{:e},{d},{steps},{evals},{},{},{},{},{status},{},{},{outputs}",
            level.name(),
            scene.solver.method.name(),
            scene.solver.rtol,
            fmt(wall),
            fmt(wall / d),
            fmt(cpu),
            fmt(cpu / d),
            fmt(setup),
            fmt(advance / d)
        )
        .map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// CPU time of the calling thread [s] (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)` on Unix,
/// `GetThreadTimes` on Windows, through the `cpu-time` crate; NaN where that is not
/// available). On a shared machine it is the fairer measure of one thread's work than wall
/// time. (/proc/thread-self/schedstat, used before, misses the running slice since the last
/// scheduler tick.)
fn thread_cpu_seconds() -> f64 {
    cpu_time::ThreadTime::try_now().map_or(f64::NAN, |t| t.as_duration().as_secs_f64())
}
