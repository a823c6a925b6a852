//! The `raceway` command-line program: one file per subcommand, over the `raceway` library.

use clap::{Parser, Subcommand};

mod bench;
mod envelope;
mod fmu;
mod frequencies;
mod levels;
mod simulate;
mod spectrum;
mod static_load;
mod sweep;

#[derive(Parser)]
#[command(
    name = "raceway",
    version,
    about = "Ball-bearing dynamics with raceway spalls"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Kinematic fault frequencies (L0): FTF, BPFO, BPFI, BSF, 2·BSF
    Frequencies(frequencies::Args),
    /// The fidelity levels (name, FMU code, ladder label, what each computes, which are
    /// deprecated and why)
    Levels(levels::Args),
    /// Quasi-static load distribution and stiffness (L1)
    Static(static_load::Args),
    /// Simulate a scene and write a CSV of the outputs
    Simulate(simulate::Args),
    /// Spectrum, Welch PSD or envelope spectrum of a CSV column
    Spectrum(spectrum::Args),
    /// Run a parameter sweep (grid of scenes) in parallel, resumable, into DIR/results.csv
    Sweep(sweep::Args),
    /// Speed against accuracy of every level and method (CSV for docs/performance.md)
    Bench(bench::Args),
    /// Operating-envelope test: a grid of speeds, loads, pedestals and spall on/off at every
    /// level, each point ok / error / garbage / hang (CSV and summary in docs/envelope/)
    ///
    /// Speeds from 0 to the bearing's limiting speed (dm·n = 1e6 mm·rpm), axial and radial
    /// loads as fractions of its static load rating C0 (ISO 76, from its geometry: pure axial,
    /// pure radial, Fr ≈ Fa, partial load zone, light and heavy; pure radial also on an axially
    /// located ring where α0 > 0), the preset's, a soft and a stiff pedestal, spall off and on;
    /// every point briefly at every level, each in its own worker process under a watchdog. A
    /// point is ok (finite outputs within physical bounds), error (a clear error message),
    /// garbage (non-finite or out-of-bounds outputs returned as success), hang (past
    /// --time-limit, killed) or crash. Writes envelope.csv (every point), envelope-l1.csv (L1's
    /// reference at each operating point) and envelope.md (the command, the bounds, counts per
    /// bearing and level, the failures); the exit status is non-zero when any point hangs,
    /// crashes or returns garbage.
    Envelope(envelope::Args),
    /// Write the BallBearing FMU for any bearing (preset or TOML file), without a Rust
    /// toolchain: the binaries come from a template FMU made by fmu-build of this version
    Fmu(fmu::Args),
}

fn main() {
    std::process::exit(run());
}

/// Runs the program; returns the process exit code.
fn run() -> i32 {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Frequencies(a) => frequencies::run(a),
        Command::Levels(a) => levels::run(a),
        Command::Static(a) => static_load::run(a),
        Command::Simulate(a) => simulate::run(a),
        Command::Spectrum(a) => spectrum::run(a),
        Command::Sweep(a) => sweep::run(a),
        Command::Bench(a) => bench::run_cli(a),
        Command::Envelope(a) => envelope::run(a),
        Command::Fmu(a) => fmu::run(a),
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("raceway: error: {e}");
            1
        }
    }
}
