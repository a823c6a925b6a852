//! `raceway simulate`: run a scene and write `time` plus the FMU's output names as CSV.

use raceway::fault_frequencies;
use raceway::models::level_names;
use raceway::{out, Fidelity, MethodName, Scene, Simulation};
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::sync::mpsc::{channel, sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML), e.g. examples/scenes/default.toml
    pub scene: PathBuf,
    /// Fidelity level: kinematic, quasi_static, lumped, reduced (deprecated), full
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
    let mut rows = RowPipe::start(w, columns.len());

    let mut row = vec![0.0; all.len()];
    sim.outputs(&mut row);
    rows.push(0.0, &row, &columns);

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
    // One advance over the whole run, so that the step-size control runs on undisturbed (an
    // advance lands its last step on its end time; chunked advances left a comb at the chunk
    // rate in the spectra). The progress bar moves with the samples.
    let mut percent = 0;
    let result = sim.advance_sampled(duration, dt, &mut |t, out| {
        rows.push(t, out, &columns);
        let p = (100.0 * t / duration) as u64;
        if p > percent {
            percent = p;
            bar.set_position(10 * p);
            bar.set_message(format!("t = {t:.4} s"));
        }
    });
    // A failed advance puts the simulation back to its start, but the rows it wrote before the
    // integrator stopped (accepted steps) stay in the file.
    let (written_to, written) = rows.finish();
    written.map_err(io)?;
    warn(&mut sim);
    if let Err(e) = result {
        bar.abandon();
        return Err(format!(
            "{e}\n(the outputs up to t = {written_to:.6} s are in {})",
            args.out.display()
        ));
    }
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();

    // Metadata for `raceway spectrum`: kinematic and model fault frequencies.
    let bearing = sim.bearing();
    let fs = scene.operating.speed_rpm() / 60.0;
    let kin = fault_frequencies::fault_frequencies(bearing, fs, bearing.alpha0);
    let ftf = sim.cage_speed() / std::f64::consts::TAU;
    let bsf = bearing.kinematic_spin_per_orbit() * ftf;
    let z = bearing.z as f64;
    let stats = sim.solver_stats();
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
        // uses; BSF and 2·BSF the spin of pure rolling on the outer race at α0 at that cage
        // speed, (dm/D)(1 + γ0)·FTF: the kinematic balls' spin (ball spalls, ball waviness).
        "fault_frequencies": {
            "ftf": ftf,
            "bpfo": z * ftf,
            "bpfi": z * (fs - ftf),
            "bsf": bsf,
            "two_bsf": 2.0 * bsf,
        },
        "kinematic_frequencies": kin,
        "solver": {
            "steps": stats.steps,
            "rejected": stats.rejected,
            "rhs_evals": stats.rhs_evals,
            "events": stats.events,
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
            "solver: {} steps, {} rejected, {} RHS evaluations, {} events; cage {:.3} Hz, BPFO {:.2} Hz, BPFI {:.2} Hz",
            stats.steps,
            stats.rejected,
            stats.rhs_evals,
            stats.events,
            ftf,
            z * ftf,
            z * (fs - ftf)
        );
        eprintln!("wrote {} and {}", args.out.display(), meta_path.display());
    }
    Ok(())
}

/// Rows on their way to the CSV file: gathered in blocks and formatted and written by a thread
/// of their own, beside the simulation (formatting 70 columns at 51.2 kHz took as long as the
/// lumped level's integration). Blocks go back to be refilled: no allocation per block.
struct RowPipe {
    /// `None` once the writer has stopped (an error) or the pipe is finished.
    to_writer: Option<SyncSender<Vec<f64>>>,
    from_writer: Receiver<Vec<f64>>,
    block: Vec<f64>,
    width: usize,
    writer: JoinHandle<(f64, std::io::Result<()>)>,
}

/// Rows per block handed to the writer.
const BLOCK_ROWS: usize = 1024;

impl RowPipe {
    /// A writer thread for rows of the time and `n` columns, written to `w`.
    fn start<W: Write + Send + 'static>(mut w: W, n: usize) -> Self {
        let width = n + 1;
        let (to_writer, blocks) = sync_channel::<Vec<f64>>(4);
        let (give_back, from_writer) = channel::<Vec<f64>>();
        let writer = std::thread::spawn(move || {
            let mut line = Vec::with_capacity(24 * width);
            let mut last = 0.0;
            for mut block in blocks {
                for r in block.chunks_exact(width) {
                    if let Err(e) = write_row(&mut w, &mut line, r) {
                        return (last, Err(e));
                    }
                    last = r[0];
                }
                block.clear();
                let _ = give_back.send(block);
            }
            (last, w.flush())
        });
        Self {
            to_writer: Some(to_writer),
            from_writer,
            block: Vec::with_capacity(BLOCK_ROWS * width),
            width,
            writer,
        }
    }

    /// Adds the row of time `t` and the outputs `columns` of `row`.
    fn push(&mut self, t: f64, row: &[f64], columns: &[usize]) {
        self.block.push(t);
        self.block.extend(columns.iter().map(|&i| row[i]));
        if self.block.len() >= BLOCK_ROWS * self.width {
            self.send();
        }
    }

    fn send(&mut self) {
        let next = self
            .from_writer
            .try_recv()
            .unwrap_or_else(|_| Vec::with_capacity(BLOCK_ROWS * self.width));
        let full = std::mem::replace(&mut self.block, next);
        if let Some(tx) = &self.to_writer {
            if tx.send(full).is_err() {
                // The writer stopped on an error, which `finish` returns.
                self.to_writer = None;
            }
        }
        self.block.clear();
    }

    /// Writes what is left and waits for the writer: the time of the last row written, and
    /// the first write error.
    fn finish(mut self) -> (f64, std::io::Result<()>) {
        if !self.block.is_empty() {
            self.send();
        }
        self.to_writer = None;
        self.writer.join().expect("the CSV writer does not panic")
    }
}

/// One CSV row `r` = (time, outputs...): the time with 9 decimals, then the outputs with ten
/// significant digits (`{:.9e}`, formatted by [`raceway::signal::push_sci10`]: the
/// exact-precision path of `core::fmt` took longer than the lumped level's integration).
fn write_row(w: &mut impl Write, line: &mut Vec<u8>, r: &[f64]) -> std::io::Result<()> {
    line.clear();
    write!(line, "{:.9}", r[0])?;
    for &x in &r[1..] {
        line.push(b',');
        raceway::signal::push_sci10(line, x);
    }
    line.push(b'\n');
    w.write_all(line)
}
