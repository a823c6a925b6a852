//! `raceway simulate`: run a scene and write `time` plus the FMU's output names as CSV.

use raceway::fault_frequencies;
use raceway::models::level_names;
use raceway::{out, Fidelity, MethodName, Scene, Simulation};
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML), e.g. examples/scenes/default.toml
    pub scene: PathBuf,
    /// Fidelity level: kinematic, quasi_static, lumped, reduced, full
    #[arg(long)]
    pub fidelity: Option<String>,
    /// Simulated time [s] (default: the scene's output.duration)
    #[arg(long)]
    pub duration: Option<f64>,
    /// Integration method: dop853, dopri5, rkf45
    #[arg(long)]
    pub method: Option<String>,
    /// Relative tolerance
    #[arg(long)]
    pub rtol: Option<f64>,
    /// Output sample rate [Hz] (default: the scene's output.sample_rate)
    #[arg(long)]
    pub sample_rate: Option<f64>,
    /// Output CSV file; a metadata file `<out>.json` (fault frequencies, solver statistics) is
    /// written beside it
    #[arg(long)]
    pub out: PathBuf,
    /// Comma-separated output columns to write after `time` (default: all), e.g.
    /// `pedestal.a.z,bearing.F.z`. Without a per-ball column the models skip the per-ball work
    /// at every sample.
    #[arg(long, value_delimiter = ',')]
    pub columns: Option<Vec<String>>,
    /// No progress bar and no statistics
    #[arg(long)]
    pub quiet: bool,
}

/// Indices of the requested columns in the output table `names` (all when `None`), in the order
/// asked; an unknown or repeated name is an error that names it.
fn select_columns(names: &[String], wanted: Option<&[String]>) -> Result<Vec<usize>, String> {
    let Some(wanted) = wanted else {
        return Ok((0..names.len()).collect());
    };
    let mut picked = Vec::with_capacity(wanted.len());
    for w in wanted {
        let w = w.trim();
        let i = names.iter().position(|n| n == w).ok_or_else(|| {
            format!(
                "--columns: unknown output '{w}'; the outputs are: {}",
                names.join(", ")
            )
        })?;
        if picked.contains(&i) {
            return Err(format!("--columns: '{w}' is asked for twice"));
        }
        picked.push(i);
    }
    if picked.is_empty() {
        return Err("--columns: no column given".into());
    }
    Ok(picked)
}

/// The run's step budget in units of `solver.max_steps`.
const RUN_BUDGET_PARTS: u64 = 100;

pub fn run(args: Args) -> Result<(), String> {
    let mut scene = Scene::load(&args.scene).map_err(|e| e.to_string())?;
    if let Some(f) = &args.fidelity {
        scene.fidelity = Fidelity::from_name(f)
            .ok_or_else(|| format!("--fidelity {f}: expected one of {}", level_names()))?;
    }
    if let Some(m) = &args.method {
        scene.solver.method = MethodName::from_name(m)
            .ok_or_else(|| format!("--method {m}: expected dop853, dopri5 or rkf45"))?;
    }
    if let Some(r) = args.rtol {
        scene.solver.rtol = r;
    }
    if let Some(d) = args.duration {
        scene.output.duration = d;
    }
    if let Some(fs) = args.sample_rate {
        scene.output.sample_rate = fs;
    }
    scene.validate().map_err(|e| e.to_string())?;
    // The run is one advance: its step budget is solver.max_steps per 1 % of the run (the
    // budget the earlier 100 chunked advances had).
    scene.solver.max_steps = scene.solver.max_steps.saturating_mul(RUN_BUDGET_PARTS);

    let mut sim = Simulation::new(&scene).map_err(|e| e.to_string())?;
    let warn = |sim: &mut Simulation| {
        for w in sim.take_warnings() {
            eprintln!("raceway: warning: {w}");
        }
    };
    warn(&mut sim);
    let all: Vec<String> = sim.output_table().into_iter().map(|o| o.name).collect();
    let columns = select_columns(&all, args.columns.as_deref())?;
    // Only bearing-level columns: the samplers get (and the models compute) no per-ball block.
    sim.set_ball_outputs(columns.iter().any(|&i| i >= out::BEARING_OUTPUTS));
    let names: Vec<&str> = columns.iter().map(|&i| all[i].as_str()).collect();
    let file = std::fs::File::create(&args.out)
        .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
    let mut w = BufWriter::new(file);
    let io = |e: std::io::Error| format!("writing {}: {e}", args.out.display());
    writeln!(w, "time,{}", names.join(",")).map_err(io)?;

    let mut row = vec![0.0; all.len()];
    sim.outputs(&mut row);
    // One row is formatted into this buffer, then written whole.
    let mut line = Vec::with_capacity(24 * (names.len() + 1));
    write_row(&mut w, &mut line, 0.0, &row, &columns).map_err(io)?;

    let duration = scene.output.duration;
    let dt = 1.0 / scene.output.sample_rate;
    let bar = if args.quiet {
        indicatif::ProgressBar::hidden()
    } else {
        let b = indicatif::ProgressBar::new(1000);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:40} {percent:>3}% {msg} (eta {eta})",
            )
            .expect("valid template"),
        );
        b
    };
    let started = Instant::now();
    let mut write_err: Option<std::io::Error> = None;
    // Time of the last row written: a failed advance puts the simulation back to its start, but
    // the rows it wrote before the integrator stopped (accepted steps) stay in the file.
    let mut written_to = 0.0;
    // One advance over the whole run, so that the step-size control runs on undisturbed (an
    // advance lands its last step on its end time; chunked advances left a comb at the chunk
    // rate in the spectra). The progress bar moves with the samples.
    let mut percent = 0;
    let result = sim.advance_sampled(duration, dt, &mut |t, out| {
        if write_err.is_none() {
            match write_row(&mut w, &mut line, t, out, &columns) {
                Ok(()) => written_to = t,
                Err(e) => write_err = Some(e),
            }
        }
        let p = (100.0 * t / duration) as u64;
        if p > percent {
            percent = p;
            bar.set_position(10 * p);
            bar.set_message(format!("t = {t:.4} s"));
        }
    });
    if let Some(e) = write_err.take() {
        return Err(io(e));
    }
    warn(&mut sim);
    if let Err(e) = result {
        bar.abandon();
        w.flush().map_err(io)?;
        return Err(format!(
            "{e}\n(the outputs up to t = {written_to:.6} s are in {})",
            args.out.display()
        ));
    }
    bar.finish_and_clear();
    w.flush().map_err(io)?;
    let wall = started.elapsed().as_secs_f64();

    // Metadata for `raceway spectrum`: kinematic and model fault frequencies.
    let bearing = sim.bearing();
    let fs = scene.operating.speed_rpm() / 60.0;
    let kin = fault_frequencies::fault_frequencies(bearing, fs, bearing.alpha0);
    let ftf = sim.cage_speed() / std::f64::consts::TAU;
    let z = bearing.z as f64;
    let stats = sim.stats();
    let meta = serde_json::json!({
        "scene": scene.name,
        "fidelity": scene.fidelity.name(),
        "method": scene.solver.method.name(),
        "rtol": scene.solver.rtol,
        "duration": duration,
        "sample_rate": scene.output.sample_rate,
        "skip": scene.output.skip,
        "shaft_hz": fs,
        // What the model implies: cage-based FTF/BPFO/BPFI from the cage speed the model
        // uses; BSF and 2·BSF are kinematic at α0 (the lumped level has no ball spin).
        "fault_frequencies": {
            "ftf": ftf,
            "bpfo": z * ftf,
            "bpfi": z * (fs - ftf),
            "bsf": kin.bsf,
            "two_bsf": kin.two_bsf,
        },
        "kinematic_frequencies": kin,
        "solver": {
            "steps": stats.steps,
            "rejected": stats.rejected,
            "rhs_evals": stats.rhs_evals,
            "wall_seconds": wall,
            "wall_seconds_per_simulated_second": wall / duration,
        },
    });
    let meta_path = PathBuf::from(format!("{}.json", args.out.display()));
    std::fs::write(
        &meta_path,
        serde_json::to_string_pretty(&meta).expect("json"),
    )
    .map_err(|e| format!("cannot write {}: {e}", meta_path.display()))?;

    if !args.quiet {
        eprintln!(
            "simulated {duration} s ({} level, {} rtol {:e}) in {wall:.3} s wall ({:.4} s per simulated s)",
            scene.fidelity.name(),
            scene.solver.method.name(),
            scene.solver.rtol,
            wall / duration
        );
        eprintln!(
            "solver: {} steps, {} rejected, {} RHS evaluations; cage {:.3} Hz, BPFO {:.2} Hz, BPFI {:.2} Hz",
            stats.steps,
            stats.rejected,
            stats.rhs_evals,
            ftf,
            z * ftf,
            z * (fs - ftf)
        );
        eprintln!("wrote {} and {}", args.out.display(), meta_path.display());
    }
    Ok(())
}

/// One CSV row: the time with 9 decimals, then the outputs `columns` of `row` with ten
/// significant digits (`{:.9e}`, formatted by [`raceway::signal::push_sci10`]: the
/// exact-precision path of `core::fmt` took longer than the lumped level's integration).
fn write_row(
    w: &mut impl Write,
    line: &mut Vec<u8>,
    t: f64,
    row: &[f64],
    columns: &[usize],
) -> std::io::Result<()> {
    line.clear();
    write!(line, "{t:.9}")?;
    for &i in columns {
        line.push(b',');
        raceway::signal::push_sci10(line, row[i]);
    }
    line.push(b'\n');
    w.write_all(line)
}
