//! Parameter sweeps: a base scene, axes of values, and per-run metrics, run in parallel.
//!
//! A sweep file (TOML) names a base scene (`base = "../scenes/default.toml"`, relative to the
//! sweep file, or an inline `[scene]` table in the scene-file format), optional fixed values
//! (`[set]`), the axes (`[axes]`: lists, `{ start, stop, num }` or `{ start, stop, step }`) and
//! what to keep per run (`[keep]`, see [`Keep`]):
//!
//! ```toml
//! base = "../scenes/default.toml"
//! [set]
//! "output.duration" = 0.1
//! [axes]
//! "defect.width" = { start = 0.5e-3, stop = 2.0e-3, num = 4 }
//! "operating.speed_rpm" = [6000, 9900]
//! "noise.rms" = [0.0, 5.0]
//! [keep]
//! harmonics = 3
//! raw_signal = false
//! ```
//!
//! The grid is the Cartesian product of the axes in alphabetical key order (the last key
//! varies fastest); a run's index is its position in that order and its id a stable hash of
//! its parameters ([`spec::run_id`]). [`execute`] runs the grid on a rayon pool of N threads,
//! one [`Simulation`](crate::simulation::Simulation) per run, and appends one row per finished
//! run to `results.csv` ([`ResultsFile`]), so an interrupted sweep resumes where it stopped and a
//! failed run is recorded with its message. A run counts as done only if its row's key (a hash
//! of its resolved scene, what is kept and the model version) is its key now, and a folder
//! holding another study's table is refused with what changed ([`OnChange`]). Every random number (measurement noise) is seeded
//! from the run's parameters, so the rows do not depend on the number of threads; only their
//! order in the file and the `wall_s` column do.

mod error;
mod metrics;
mod results;
mod spec;
mod study;

pub use error::SweepError;
pub use metrics::{evaluate, metric_columns};
pub use results::{canonical_rows, write_sorted, OnChange, OpenReport, ResultsFile};
pub use spec::{fnv1a64, known_keys, run_id, Axis, AxisValue, Keep, Run, Sweep};

use std::path::Path;
use std::sync::Mutex;
use std::time::Instant;

/// How to execute a sweep.
#[derive(Debug, Clone, Default)]
pub struct ExecOptions {
    /// Worker threads (0 = one per core).
    pub jobs: usize,
    /// Only these run indices (e.g. one task of a distributed sweep); `None` = all.
    pub only: Option<Vec<usize>>,
    /// What to do when the folder holds a table of another study or model version.
    pub on_change: OnChange,
}

/// Receives [`execute_with_progress`]'s reports, e.g. to draw a progress bar; every method
/// does nothing by default. [`run_done`](Progress::run_done) is called from the worker threads.
pub trait Progress: Sync {
    /// Before the first run: how many runs will be executed now.
    fn start(&self, _runs: usize) {}
    /// After each run (failed or not): its index in the grid and its wall time in seconds.
    fn run_done(&self, _index: usize, _wall_s: f64) {}
    /// After the last run.
    fn finish(&self) {}
}

/// No progress reports.
impl Progress for () {}

/// What [`execute`] did.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Summary {
    /// Runs selected from the grid.
    pub selected: usize,
    /// Runs skipped because results.csv already has them.
    pub skipped: usize,
    /// Runs executed now.
    pub ran: usize,
    /// Runs executed now that failed (recorded with their message).
    pub failed: usize,
    /// What opening results.csv found: damaged rows dropped (run again), an old table kept.
    pub opened: OpenReport,
}

/// Runs the selected runs of `sweep` that `out_dir/results.csv` does not have yet, on
/// `opts.jobs` threads, appending a row per run as it finishes.
pub fn execute(sweep: &Sweep, out_dir: &Path, opts: &ExecOptions) -> Result<Summary, SweepError> {
    execute_with_progress(sweep, out_dir, opts, &())
}

/// [`execute`], reporting to `progress` as the runs start and finish.
pub fn execute_with_progress(
    sweep: &Sweep,
    out_dir: &Path,
    opts: &ExecOptions,
    progress: &dyn Progress,
) -> Result<Summary, SweepError> {
    std::fs::create_dir_all(out_dir)
        .map_err(|e| SweepError::new(format!("cannot create {}: {e}", out_dir.display())))?;
    let runs = sweep.runs();
    let selected: Vec<&Run> = match &opts.only {
        None => runs.iter().collect(),
        Some(idx) => {
            if let Some(bad) = idx.iter().find(|i| **i >= runs.len()) {
                return Err(SweepError::new(format!(
                    "run index {bad} is outside the grid (0..{})",
                    runs.len()
                )));
            }
            runs.iter().filter(|r| idx.contains(&r.index)).collect()
        }
    };
    let file = ResultsFile::open(out_dir, sweep, opts.on_change)?;
    let todo: Vec<&Run> = selected
        .iter()
        .copied()
        .filter(|r| !file.is_done(sweep, r))
        .collect();
    let mut summary = Summary {
        selected: selected.len(),
        skipped: selected.len() - todo.len(),
        opened: file.report().clone(),
        ..Summary::default()
    };
    progress.start(todo.len());
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.jobs)
        .build()
        .map_err(|e| SweepError::new(format!("cannot start {} threads: {e}", opts.jobs)))?;
    let signal_dir = out_dir.join("signals");
    let file = Mutex::new(file);
    let failed = Mutex::new(0usize);
    let write_error: Mutex<Option<SweepError>> = Mutex::new(None);
    pool.install(|| {
        use rayon::prelude::*;
        todo.par_iter().with_max_len(1).for_each(|run| {
            let started = Instant::now();
            let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                evaluate(sweep, run, Some(&signal_dir))
            }))
            .unwrap_or_else(|p| {
                let msg = p
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| p.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                Err(format!("internal error (panic): {msg}"))
            });
            let wall = started.elapsed().as_secs_f64();
            if result.is_err() {
                if let Ok(mut f) = failed.lock() {
                    *f += 1;
                }
            }
            let row = results::row(sweep, run, &result, wall);
            let outcome = match file.lock() {
                Ok(mut f) => f.append(&row),
                Err(_) => Err(SweepError::new("results writer poisoned")),
            };
            if let Err(e) = outcome {
                if let Ok(mut w) = write_error.lock() {
                    w.get_or_insert(e);
                }
            }
            progress.run_done(run.index, wall);
        });
    });
    progress.finish();
    if let Some(e) = write_error.into_inner().ok().flatten() {
        return Err(e);
    }
    summary.ran = todo.len();
    summary.failed = failed.into_inner().unwrap_or(0);
    Ok(summary)
}
