//! Where the time of a dynamic level goes, and what its speed target would ask of it.
//!
//! For the lumped, reduced and full levels on the default scene (outer spall, DOP853, rtol 1e-6,
//! sampled at 51.2 kHz, every output), this measures side by side in one run:
//!
//! - the integrator's work per simulated second (accepted and rejected steps, RHS evaluations)
//!   and the wall time per simulated second;
//! - the bare cost of one RHS evaluation: the model's right-hand side alone, called in a loop
//!   at the quasi-static start state (every ball loaded, none in the spall), the fastest of 25
//!   batches;
//! - so the share of the wall time that is RHS evaluations, and the RHS cost the level's target
//!   (issues 4 and 5: lumped 0.02, reduced 1, full 5 wall s per simulated s) would need at this
//!   number of evaluations, and the number of evaluations it would need at this cost.
//!
//! Then a pure harmonic oscillator integrated by the same DOP853 integrator sets the step count
//! a vibration of frequency f needs by itself: accepted steps per period against the tolerance
//! relative to the vibration's amplitude (the ball modes ring near 29 kHz, the inner ring on the
//! bearing near 5.4 kHz, docs/model.md#stiffness).
//!
//! Usage: `cargo run --release -p raceway-studies --bin speed_floor -- [--out docs/research/speed-floor.md] [lumped_s]
//! [dynamic_s]` (simulated seconds measured after a 20 ms transient: default 0.5 at the lumped
//! level and 0.03 at the reduced and full levels). Prints CSV; with `--out` also writes the
//! Markdown report.

use raceway::models;
use raceway::signal::median;
use raceway::solver::{Integrator, Method, Options, System};
use raceway::{out, Fidelity, Scene, Simulation};
use std::fmt::Write as _;
use std::time::Instant;

/// RHS evaluations of one accepted DOP853 step without its dense output (12 stages; the last
/// one is not the next step's first).
const STAGES: f64 = 12.0;

/// Timed batches of bare RHS calls (about 10 ms each); the fastest counts (the host is shared).
const BATCHES: usize = 25;

/// The fastest mode that rings between spall passes (docs/model.md#stiffness and the Table-2 impact test):
/// the ball between the races at the levels with ball states, the inner ring on the bearing
/// (feh) at the lumped level, whose balls have no states.
fn mode_of(level: Fidelity) -> (&'static str, f64) {
    match level {
        Fidelity::Lumped => (
            "inner ring on the bearing (feh, Table-2 impact test at Fa 4000 N)",
            5578.0,
        ),
        _ => (
            "ball between the races ([stiffness](../model.md#stiffness), Q ≈ 700 N)",
            29.1e3,
        ),
    }
}

struct Row {
    level: Fidelity,
    target: f64,
    measured: f64,
    steps: f64,
    rejected: f64,
    rhs: f64,
    wall: f64,
    bare: f64,
}

/// x'' = −ω² x as (x, v).
struct Oscillator {
    w2: f64,
}

impl System for Oscillator {
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) {
        dydt[0] = y[1];
        dydt[1] = -self.w2 * y[0];
    }
}

/// Accepted steps per period of a unit-amplitude oscillation with DOP853 at relative tolerance
/// `tol` (atol = tol · amplitude on x and tol · ω · amplitude on v), over 200 periods.
fn steps_per_period(tol: f64) -> (f64, f64) {
    let f = 1.0;
    let w = std::f64::consts::TAU * f;
    let mut o = Options::new(Method::Dop853, tol, vec![tol, tol * w]);
    o.max_steps = 10_000_000;
    let mut it = Integrator::new(o, 0.0, &[1.0, 0.0]).expect("options");
    let mut sys = Oscillator { w2: w * w };
    let periods = 200.0;
    it.advance(&mut sys, periods / f, None).expect("oscillator");
    let s = it.stats();
    // Error at the end against the exact cos.
    let err = (it.y()[0] - (w * periods / f).cos()).abs();
    (s.steps as f64 / periods, err)
}

fn main() {
    let mut a: Vec<String> = std::env::args().skip(1).collect();
    let out_path = a.iter().position(|v| v == "--out").map(|i| {
        let p = a.get(i + 1).cloned().expect("--out needs a file");
        a.drain(i..i + 2);
        p
    });
    let lumped_s: f64 = a.first().and_then(|v| v.parse().ok()).unwrap_or(0.5);
    let dynamic_s: f64 = a.get(1).and_then(|v| v.parse().ok()).unwrap_or(0.03);
    let mut rows = Vec::new();
    let transient = 0.02;
    println!(
        "level,target_s_per_s,simulated_s,steps_per_s,rejected_per_s,rhs_per_s,wall_s_per_s,\
         bare_rhs_us,rhs_share,rhs_us_for_target,rhs_per_s_for_target"
    );
    for (level, target, measured) in [
        (Fidelity::Lumped, 0.02, lumped_s),
        (Fidelity::Reduced, 1.0, dynamic_s),
        (Fidelity::Full, 5.0, dynamic_s),
    ] {
        let mut scene = Scene::default_scene();
        scene.fidelity = level;
        // The integrator's work and the wall time over `measured` after the transient, three
        // runs, the median wall time.
        let mut walls = Vec::new();
        let mut work = (0, 0, 0);
        for _ in 0..3 {
            let mut sim = Simulation::new(&scene).expect("scene");
            sim.advance(transient).expect("transient");
            let s0 = sim.stats();
            let start = Instant::now();
            let mut acc = 0.0;
            sim.advance_sampled(transient + measured, 1.0 / 51_200.0, &mut |_, o| {
                acc += o[out::PEDESTAL_A_Z]
            })
            .expect("advance");
            std::hint::black_box(acc);
            walls.push(start.elapsed().as_secs_f64() / measured);
            let s = sim.stats();
            work = (
                s.steps - s0.steps,
                s.rejected - s0.rejected,
                s.rhs_evals - s0.rhs_evals,
            );
        }
        let wall = median(walls).expect("three timed runs");
        let per_s = |n: u64| n as f64 / measured;
        let rhs_per_s = per_s(work.2);
        // Bare RHS at the quasi-static start (modes set as the simulation sets them at t = 0).
        let sim = Simulation::new(&scene).expect("scene");
        let bearing = sim.bearing().clone();
        let inputs = scene.operating;
        let mut model = models::build(&scene, &bearing, &inputs).expect("model");
        let n = model.dim();
        let mut y = vec![0.0; n];
        model.initial_state(&mut y);
        model.update_mode(0.0, &y);
        let mut dydt = vec![0.0; n];
        let calls = match level {
            Fidelity::Lumped => 50_000,
            _ => 2_000,
        };
        let mut best = f64::INFINITY;
        for _ in 0..BATCHES {
            let start = Instant::now();
            for i in 0..calls {
                // A time that moves (the pulse and the inputs are time-independent here).
                model.rhs(i as f64 * 1e-9, &y, &mut dydt);
                std::hint::black_box(&dydt);
            }
            best = best.min(start.elapsed().as_secs_f64() / calls as f64);
        }
        let share = rhs_per_s * best / wall;
        rows.push(Row {
            level,
            target,
            measured,
            steps: per_s(work.0),
            rejected: per_s(work.1),
            rhs: rhs_per_s,
            wall,
            bare: best,
        });
        println!(
            "{},{target},{measured},{:.0},{:.0},{:.0},{:.4},{:.4},{:.2},{:.4},{:.0}",
            level.name(),
            per_s(work.0),
            per_s(work.1),
            rhs_per_s,
            wall,
            best * 1e6,
            share,
            // The RHS cost that would meet the target at this many evaluations (all of the
            // target spent on RHS evaluations), and the evaluations it allows at this cost.
            target / rhs_per_s * 1e6,
            target / best,
        );
    }
    println!();
    println!(
        "tolerance_relative_to_amplitude,dop853_steps_per_period,final_error_over_200_periods"
    );
    let mut osc = Vec::new();
    for tol in [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
        let (spp, err) = steps_per_period(tol);
        println!("{tol:e},{spp:.2},{err:.2e}");
        osc.push((tol, spp, err));
    }
    if let Some(path) = out_path {
        std::fs::write(&path, report(&rows, &osc, &a)).expect("write the report");
        eprintln!("wrote {path}");
    }
}

/// The oscillator tolerance at which DOP853 takes `spp` steps per period (log-linear between
/// the table's rows), if inside the table.
fn equivalent_tolerance(osc: &[(f64, f64, f64)], spp: f64) -> Option<f64> {
    osc.windows(2).find_map(|w| {
        let ((t0, s0, _), (t1, s1, _)) = (w[0], w[1]);
        (s0 <= spp && spp <= s1).then(|| {
            let u = (spp - s0) / (s1 - s0);
            (t0.ln() + u * (t1.ln() - t0.ln())).exp()
        })
    })
}

/// The Markdown report: the measured table, what the targets would ask, the oscillator table.
fn report(rows: &[Row], osc: &[(f64, f64, f64)], args: &[String]) -> String {
    let mut m = String::new();
    let args = if args.is_empty() {
        String::new()
    } else {
        format!(" {}", args.join(" "))
    };
    let _ = writeln!(
        m,
        "# Where the time goes, and what the speed targets would ask\n\n*Generated by \
         `cargo run --release -p raceway-studies --bin speed_floor -- --out docs/research/speed-floor.md{args}`; do not \
         edit by hand.* One run on this machine (release, one thread); the default scene (outer \
         spall 1.0 × 0.2 mm, Fa 4000 N, Fr 1000 N, 9900 rpm), DOP853 at rtol 1e-6, sampled at \
         51.2 kHz with every output, measured after a 20 ms transient (median of three runs). \
         \"Bare RHS\" is the model's right-hand side alone in a loop at the quasi-static start \
         (every ball loaded, none in the spall), the fastest of 25 batches of about 10 ms (the \
         host is shared).\n"
    );
    let _ = writeln!(
        m,
        "| level | target [s/s] | measured over [s] | accepted steps /s | rejected /s | RHS evals \
         /s | wall [s/s] | bare RHS [µs] | RHS share of the wall | floor: accepted steps × 12 \
         stages × bare RHS [s/s] | accepted steps per period of the fastest ringing mode |\n|---|---|---|\
         ---|---|---|---|---|---|---|---|"
    );
    for r in rows {
        let (_, f) = mode_of(r.level);
        let _ = writeln!(
            m,
            "| {} | {} | {} | {:.0} | {:.0} | {:.0} | {:.3} | {:.3} | {:.0} % | {:.3} | {:.1} \
             ({:.1} kHz) |",
            r.level.name(),
            r.target,
            r.measured,
            r.steps,
            r.rejected,
            r.rhs,
            r.wall,
            r.bare * 1e6,
            100.0 * r.rhs * r.bare / r.wall,
            r.steps * STAGES * r.bare,
            r.steps / f,
            f * 1e-3
        );
    }
    let _ = writeln!(
        m,
        "\n**What the targets ask.** The floor column is the cost of the accepted steps' main \
         stages alone, with no rejected step, no dense output, no event function, no sampling and \
         no integrator arithmetic: the least a DOP853 run of this many steps can cost with this \
         right-hand side.\n"
    );
    for r in rows {
        let (mode, f) = mode_of(r.level);
        let floor = r.steps * STAGES * r.bare;
        let _ = writeln!(
            m,
            "- **{}** (target {} s/s): the floor is {:.3} s/s, {:.1}× the target. At this step \
             count the target leaves {:.3} µs per RHS evaluation even with nothing else to do \
             ({:.1}× less than the {:.3} µs measured); at this RHS cost it allows {:.0} accepted \
             steps per simulated second, {:.1} per period of the {:.1} kHz {mode}, where the \
             run takes {:.1}.",
            r.level.name(),
            r.target,
            floor,
            floor / r.target,
            r.target / (r.steps * STAGES) * 1e6,
            r.bare / (r.target / (r.steps * STAGES)),
            r.bare * 1e6,
            r.target / (STAGES * r.bare),
            r.target / (STAGES * r.bare) / f,
            f * 1e-3,
            r.steps / f,
        );
    }
    let _ = writeln!(
        m,
        "\n**What a vibration costs by itself.** A pure harmonic oscillator x″ = −ω²x of unit \
         amplitude, integrated by the same DOP853 integrator over 200 periods with the tolerance \
         relative to its amplitude (atol = tol on x and tol·ω on ẋ, rtol = tol):\n\n| \
         tolerance / amplitude | accepted steps per period | error after 200 periods |\n|---|\
         ---|---|"
    );
    for (tol, spp, err) in osc {
        let _ = writeln!(m, "| {tol:.0e} | {spp:.2} | {err:.1e} |");
    }
    m.push('\n');
    for r in rows {
        let (mode, f) = mode_of(r.level);
        let spp = r.steps / f;
        let _ = writeln!(
            m,
            "- {}: {:.1} steps per period of the {:.1} kHz {mode}, what the oscillator needs at \
             a tolerance of {} of its amplitude.",
            r.level.name(),
            spp,
            f * 1e-3,
            equivalent_tolerance(osc, spp)
                .map_or("(outside the table)".into(), |t| format!("{t:.1e}")),
        );
    }
    let _ = writeln!(
        m,
        "\nTaking fewer steps than that means resolving the mode less well, i.e. another \
         tolerance or another integrator (implicit or multirate for the fast modes), not a faster \
         loop."
    );
    m
}
