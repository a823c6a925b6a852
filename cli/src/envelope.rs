//! `raceway envelope`: runs a grid of operating points (speed, axial and radial load, pedestal
//! stiffness, spall on/off) through the library at every fidelity level, briefly, and sorts each
//! point into ok / error / garbage / hang / crash (issue 17, item 6).
//!
//! Every point runs in its own worker process (this program with the hidden `--run-point`), a
//! few at a time on a rayon pool; a watchdog kills a worker that runs past the wall-time limit
//! and records a hang, so the grid always finishes and reports. The grid, the bounds and the
//! classes are documented in the markdown summary it writes (`grid.rs`, `report.rs`).

mod grid;
mod point;
mod report;

use grid::{GridPoint, PointSpec, Scales};
use raceway::models::{level_names, LEVELS};
use raceway::{Bearing, Fidelity, DEFAULT_PRESET, PRESETS};
use report::{Bounds, Class, Outcome, Raw};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[derive(clap::Args)]
pub struct Args {
    /// Bearing: a preset (niu2014-table1, cwru-6205-de, cwru-6203-fe, ims-za2115) or a TOML file
    #[arg(long, default_value = DEFAULT_PRESET, conflicts_with = "all_presets")]
    pub bearing: String,
    /// Every preset instead of one bearing
    #[arg(long)]
    pub all_presets: bool,
    /// Comma-separated levels (kinematic,quasi_static,lumped,reduced,full; default all)
    #[arg(long, value_delimiter = ',')]
    pub levels: Option<Vec<String>>,
    /// The small grid: speeds 0, ½, 1 × the limit; four load cases (pure axial and pure radial
    /// heavy, Fr ≈ Fa, partial load zone); the preset's and a soft pedestal; spall on
    #[arg(long)]
    pub quick: bool,
    /// Output folder for envelope.csv, envelope-l1.csv and envelope.md
    #[arg(long, default_value = "docs/envelope")]
    pub out: PathBuf,
    /// Worker processes at a time (default: one per core)
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Wall-time limit of one point [s]: beyond it the worker is killed and the point is a hang
    #[arg(long, default_value_t = 60.0, allow_negative_numbers = true)]
    pub time_limit: f64,
    /// Relative numerical margin around the loaded balls' race-control range of the cage speed
    /// with finite contacts at the kinematic, quasi-static and lumped levels (default 0.001; the
    /// reduced and full levels' is 0.01)
    #[arg(long, allow_negative_numbers = true)]
    pub cage_margin: Option<f64>,
    /// No progress bar
    #[arg(long)]
    pub quiet: bool,
    /// Worker mode: run one point given as JSON and print its measurements (used by the grid)
    #[arg(long, hide = true)]
    pub run_point: Option<String>,
    /// Test hook: the first N points stall instead of running (exercises the watchdog)
    #[arg(long, hide = true, default_value_t = 0)]
    pub debug_stall: usize,
}

/// Marks the start of a worker's result on its stdout (a TOML document follows: TOML, unlike
/// JSON, carries NaN and infinities, which garbage outputs are made of).
const RESULT_MARK: &str = "RACEWAY-ENVELOPE-RESULT";

pub fn run(args: Args) -> Result<(), String> {
    if let Some(spec) = &args.run_point {
        return run_worker(spec);
    }
    if !(args.time_limit.is_finite() && args.time_limit > 0.0) {
        return Err(format!(
            "--time-limit {}: must be a positive number of seconds",
            args.time_limit
        ));
    }
    let mut bounds = Bounds::default();
    if let Some(m) = args.cage_margin {
        if !(m.is_finite() && (0.0..1.0).contains(&m)) {
            return Err(format!("--cage-margin {m}: must lie in [0, 1)"));
        }
        bounds.cage_margin = m;
    }
    let levels = parse_levels(args.levels.as_deref())?;
    let sources: Vec<String> = if args.all_presets {
        PRESETS.iter().map(|(n, _)| n.to_string()).collect()
    } else {
        vec![args.bearing.clone()]
    };
    let mut scales = Vec::new();
    for src in &sources {
        let b = Bearing::load(src).map_err(|e| format!("--bearing {src}: {e}"))?;
        // A file path goes to the workers absolute, whatever their working directory.
        let src = if PRESETS.iter().any(|(n, _)| n == src) {
            src.clone()
        } else {
            std::fs::canonicalize(src)
                .map_err(|e| format!("--bearing {src}: {e}"))?
                .to_string_lossy()
                .into_owned()
        };
        scales.push(Scales::new(&src, &b));
    }
    let mut points = grid::build(&scales, &levels, args.quick);
    for p in points.iter_mut().take(args.debug_stall) {
        p.spec.stall = true;
    }
    std::fs::create_dir_all(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let exe = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    let jobs = if args.jobs == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        args.jobs
    };
    // The revision the grid runs at, before it writes its tables (which may be tracked files).
    let revision = git_revision(&args.out);
    let started = Instant::now();
    let raw = run_all(&exe, &points, jobs, args.time_limit, !args.quiet)?;
    let total_wall = started.elapsed().as_secs_f64();
    let mut outcomes: Vec<Outcome> = points
        .iter()
        .zip(&raw)
        .map(|(p, (r, wall))| report::classify(p, &scales[p.bearing], r, *wall, &bounds))
        .collect();
    report::flag_neighbours(&points, &mut outcomes, &bounds);

    let csv = args.out.join("envelope.csv");
    let l1_csv = args.out.join("envelope-l1.csv");
    report::write_csv(&csv, &l1_csv, &points, &outcomes, &scales)?;
    let cx = report::Context {
        command: command_line(),
        revision,
        quick: args.quick,
        time_limit: args.time_limit,
        jobs,
        total_wall,
        scales: &scales,
        levels: &levels,
        bounds,
    };
    let md = args.out.join("envelope.md");
    std::fs::write(&md, report::markdown(&cx, &points, &outcomes))
        .map_err(|e| format!("cannot write {}: {e}", md.display()))?;

    let count = |c: Class| outcomes.iter().filter(|o| o.class == c).count();
    let counts: Vec<String> = Class::ALL
        .iter()
        .map(|&c| format!("{} {}", count(c), c.name()))
        .collect();
    let flagged = outcomes.iter().filter(|o| !o.flags.is_empty()).count();
    eprintln!(
        "envelope: {} points in {total_wall:.1} s: {}; {flagged} flagged; wrote {}, {} and {}",
        points.len(),
        counts.join(", "),
        csv.display(),
        l1_csv.display(),
        md.display()
    );
    let failing = outcomes.iter().filter(|o| o.class.fails()).count();
    if failing > 0 {
        return Err(format!(
            "{failing} of {} points hang, crash or return garbage (see {})",
            points.len(),
            md.display()
        ));
    }
    Ok(())
}

/// The levels asked for, in ladder order; an unknown name is an error naming the valid ones.
fn parse_levels(names: Option<&[String]>) -> Result<Vec<Fidelity>, String> {
    let all: Vec<Fidelity> = LEVELS.iter().map(|l| l.fidelity).collect();
    let Some(names) = names else {
        return Ok(all);
    };
    let mut levels = Vec::new();
    for n in names {
        let n = n.trim();
        let l = Fidelity::from_name(n)
            .ok_or_else(|| format!("--levels: unknown level '{n}'; valid: {}", level_names()))?;
        if !levels.contains(&l) {
            levels.push(l);
        }
    }
    if levels.is_empty() {
        return Err("--levels: no level given".into());
    }
    levels.sort_by_key(|l| l.code());
    Ok(levels)
}

/// Worker mode: runs the point and prints the marker and its measurements as TOML.
fn run_worker(spec: &str) -> Result<(), String> {
    let p: PointSpec =
        serde_json::from_str(spec).map_err(|e| format!("--run-point: not a point: {e}"))?;
    if p.stall {
        std::thread::sleep(Duration::from_secs(3600));
    }
    let m = point::run(&p);
    let text = toml::to_string(&m).map_err(|e| format!("cannot encode the result: {e}"))?;
    println!("{RESULT_MARK}\n{text}");
    Ok(())
}

/// Runs every point in a worker process, `jobs` at a time; returns each point's raw result and
/// wall time in the points' order.
fn run_all(
    exe: &Path,
    points: &[GridPoint],
    jobs: usize,
    limit: f64,
    progress: bool,
) -> Result<Vec<(Raw, f64)>, String> {
    let bar = if progress {
        let b = indicatif::ProgressBar::new(points.len() as u64);
        b.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} points, {msg} (eta {eta})",
        ) {
            b.set_style(style);
        }
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| format!("cannot start {jobs} threads: {e}"))?;
    let failures = std::sync::atomic::AtomicUsize::new(0);
    let results = pool.install(|| {
        use rayon::prelude::*;
        points
            .par_iter()
            .with_max_len(1)
            .map(|p| {
                let r = run_one(exe, &p.spec, limit);
                if !matches!(&r.0, Raw::Done(m) if m.error.is_none()) {
                    failures.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                }
                bar.inc(1);
                bar.set_message(format!(
                    "{} not ok so far",
                    failures.load(std::sync::atomic::Ordering::Relaxed)
                ));
                r
            })
            .collect()
    });
    bar.finish_and_clear();
    Ok(results)
}

/// One worker with its watchdog: polls the child (briefly at first, since most points take
/// milliseconds) and kills it at the wall-time limit.
fn run_one(exe: &Path, spec: &PointSpec, limit: f64) -> (Raw, f64) {
    let started = Instant::now();
    let json = match serde_json::to_string(spec) {
        Ok(j) => j,
        Err(e) => return (Raw::Crash(format!("cannot encode the point: {e}")), 0.0),
    };
    let child = Command::new(exe)
        .args(["envelope", "--run-point", &json])
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => return (Raw::Crash(format!("cannot start a worker: {e}")), 0.0),
    };
    // Drain both pipes on their own threads, so a chatty worker never blocks on a full pipe.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut s = String::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_string(&mut s);
            }
            s
        })
    };
    let out = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let err = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let mut nap = Duration::from_micros(200);
    let status = loop {
        match child.try_wait() {
            Ok(Some(s)) => break Some(s),
            Ok(None) => {}
            Err(_) => break None,
        }
        if started.elapsed().as_secs_f64() > limit {
            let _ = child.kill();
            let _ = child.wait();
            let wall = started.elapsed().as_secs_f64();
            let _ = (out.join(), err.join());
            return (Raw::Hang, wall);
        }
        std::thread::sleep(nap);
        nap = (nap * 2).min(Duration::from_millis(20));
    };
    let wall = started.elapsed().as_secs_f64();
    let stdout = out.join().unwrap_or_default();
    let stderr = err.join().unwrap_or_default();
    let result = stdout
        .split_once(RESULT_MARK)
        .map(|(_, doc)| toml::from_str::<point::Measured>(doc));
    match (status, result) {
        (Some(s), Some(Ok(m))) if s.success() => (Raw::Done(Box::new(m)), wall),
        (s, r) => {
            let tail: String = stderr
                .lines()
                .filter(|l| !l.trim().is_empty())
                .take(6)
                .collect::<Vec<_>>()
                .join(" / ");
            let why = match r {
                Some(Err(e)) => format!("unreadable result ({e}); "),
                _ => String::new(),
            };
            let code = s.map_or("unknown".to_string(), |s| s.to_string());
            (
                Raw::Crash(format!(
                    "worker exited without a result ({code}): {why}{tail}"
                )),
                wall,
            )
        }
    }
}

/// The command line as typed after the program name, prefixed by `raceway`.
fn command_line() -> String {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .map(|a| {
            if a.is_empty()
                || a.chars()
                    .any(|c| c.is_whitespace() || "'\"$`\\".contains(c))
            {
                format!("'{}'", a.replace('\'', r"'\''"))
            } else {
                a
            }
        })
        .collect();
    format!("raceway {}", args.join(" "))
}

/// The checked-out revision, when this runs in a git work tree, marked when tracked files
/// other than those in the output folder `out` differ from it (regenerating committed tables
/// is not an uncommitted change of what made them).
fn git_revision(out: &Path) -> Option<String> {
    let head = Command::new("git")
        .args(["rev-parse", "--short=12", "HEAD"])
        .stderr(Stdio::null())
        .output()
        .ok()?;
    let rev = String::from_utf8(head.stdout).ok()?.trim().to_string();
    if !head.status.success() || rev.is_empty() {
        return None;
    }
    let status = |extra: &[&str]| {
        Command::new("git")
            .args(["status", "--porcelain", "--untracked-files=no", "--", ":/"])
            .args(extra)
            .stderr(Stdio::null())
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| !o.stdout.is_empty())
    };
    // An output folder outside the work tree is no valid pathspec: then everything counts.
    let exclude = format!(":(exclude){}", out.display());
    let dirty = status(&[&exclude]).or_else(|| status(&[])).unwrap_or(false);
    Some(if dirty {
        format!("{rev} (with uncommitted changes)")
    } else {
        rev
    })
}
