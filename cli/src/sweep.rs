//! `raceway sweep`: run a parameter grid on N threads, appending to `DIR/results.csv`.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use raceway::sweep::{self, ExecOptions, OnChange, Progress, ResultsFile, Run, Sweep};
use std::path::PathBuf;
use std::sync::OnceLock;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Sweep file (TOML), e.g. examples/sweeps/small.toml
    pub sweep: PathBuf,
    /// Output folder: results.csv (appended, resumed), results.sorted.csv, signals/
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: one per core)
    #[arg(long, default_value_t = 0)]
    pub jobs: usize,
    /// Only these run indices, e.g. `--runs 0,3,7` (one task of a distributed sweep)
    #[arg(long, value_delimiter = ',')]
    pub runs: Option<Vec<usize>>,
    /// Print the grid (run_index, run_id, parameters) as CSV and exit
    #[arg(long)]
    pub list: bool,
    /// Print the runs of the grid that DIR/results.csv does not have yet (as --list) and exit
    #[arg(long, requires = "out")]
    pub pending: bool,
    /// Append the rows of these results.csv files (tasks of a distributed sweep) to
    /// DIR/results.csv, read by the same reader and checked against this sweep, rewrite
    /// DIR/results.sorted.csv, and exit (no files: only the rewrite)
    #[arg(long, num_args = 0.., value_name = "FILE", requires = "out")]
    pub merge: Option<Vec<PathBuf>>,
    /// If DIR holds a table of another study or model version, keep it as results.N.csv and
    /// start a new table (default: refuse, saying what changed)
    #[arg(long)]
    pub new_table: bool,
    /// No progress bar and no summary
    #[arg(long)]
    pub quiet: bool,
}

pub fn run(args: Args) -> Result<(), String> {
    let sw = Sweep::load(&args.sweep).map_err(|e| e.to_string())?;
    if args.list {
        print_runs(&sw, |_| true);
        return Ok(());
    }
    let out = args
        .out
        .ok_or("--out DIR is required (where results.csv is written)")?;
    let on_change = if args.new_table {
        OnChange::NewTable
    } else {
        OnChange::Refuse
    };
    if args.pending || args.merge.is_some() {
        std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
        let mut file = ResultsFile::open(&out, &sw, on_change).map_err(|e| e.to_string())?;
        if let Some(files) = &args.merge {
            let mut added = 0;
            for f in files {
                added += file.merge(&sw, f).map_err(|e| e.to_string())?;
            }
            let results = out.join("results.csv");
            sweep::write_sorted(&results, &out.join("results.sorted.csv"))
                .map_err(|e| e.to_string())?;
            if !args.quiet {
                eprintln!("merged {added} rows into {}", results.display());
            }
        } else {
            print_runs(&sw, |r| !file.is_done(&sw, r));
        }
        return Ok(());
    }
    let started = Instant::now();
    let opts = ExecOptions {
        jobs: args.jobs,
        only: args.runs,
        on_change,
    };
    let bar = Bar {
        show: !args.quiet,
        bar: OnceLock::new(),
    };
    let s = sweep::execute_with_progress(&sw, &out, &opts, &bar).map_err(|e| e.to_string())?;
    let results = out.join("results.csv");
    sweep::write_sorted(&results, &out.join("results.sorted.csv")).map_err(|e| e.to_string())?;
    if !args.quiet {
        if s.opened.dropped > 0 {
            eprintln!(
                "{}: dropped {} damaged rows (cut short or failing their check); they ran again",
                results.display(),
                s.opened.dropped
            );
        }
        if let Some(kept) = &s.opened.kept_as {
            eprintln!("the previous table is kept as {}", kept.display());
        }
        eprintln!(
            "sweep '{}': {} runs selected, {} already in {}, {} run now ({} failed) in {:.2} s wall on {} threads",
            sw.name,
            s.selected,
            s.skipped,
            results.display(),
            s.ran,
            s.failed,
            started.elapsed().as_secs_f64(),
            if args.jobs == 0 {
                rayon::current_num_threads()
            } else {
                args.jobs
            }
        );
    }
    Ok(())
}

/// Prints the runs of the grid that `keep` selects as CSV: run_index, run_id, the parameters.
fn print_runs(sw: &Sweep, keep: impl Fn(&Run) -> bool) {
    let keys: Vec<&str> = sw.axes.iter().map(|a| a.key.as_str()).collect();
    println!("run_index,run_id,{}", keys.join(","));
    for r in sw.runs().iter().filter(|r| keep(r)) {
        let vals: Vec<String> = r.params.iter().map(|(_, v)| v.canonical()).collect();
        println!("{},{},{}", r.index, r.id, vals.join(","));
    }
}

/// The sweep's progress bar with ETA on stderr (hidden when stderr is not a terminal), made when
/// the sweep knows how many runs it executes; none with `--quiet`.
struct Bar {
    show: bool,
    bar: OnceLock<ProgressBar>,
}

impl Progress for Bar {
    fn start(&self, runs: usize) {
        if !self.show {
            return;
        }
        let b = ProgressBar::new(runs as u64);
        b.set_draw_target(ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs, {msg} (eta {eta})",
        ) {
            b.set_style(style);
        }
        let _ = self.bar.set(b);
    }

    fn run_done(&self, index: usize, wall_s: f64) {
        if let Some(b) = self.bar.get() {
            b.inc(1);
            b.set_message(format!("last: run {index} {wall_s:.2} s"));
        }
    }

    fn finish(&self) {
        if let Some(b) = self.bar.get() {
            b.finish_and_clear();
        }
    }
}
