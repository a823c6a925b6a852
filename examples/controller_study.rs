//! Step-size controller study: RHS evaluations, steps and rejections against the error E1 for
//! several controller settings, per level (lumped, reduced, full) and method, in one run.
//! Writes `docs/step-control.csv` and `docs/step-control.md`.
//!
//! ```text
//! cargo run --release --example controller_study [-- --quick]
//! ```
//!
//! Scenes: S2 of `raceway bench` (default scene: outer-race spall 1.0 × 0.2 mm at the load-zone
//! centre, Fa 4000 N, Fr 1000 N, 9900 rpm) at the lumped and reduced levels, and
//! `examples/scenes/sec3.5-outer-full.toml` (the same spall, `[full] lock_tilt = true`) at the
//! full level. Error E1 as in `raceway bench`: relative RMS error of `pedestal.a.z` sampled at
//! 51.2 kHz after the transient, against DOP853 at rtol 1e-11 with the baseline controller
//! (reference RMS floored at 1 m/s²). The integrator knows nothing about bearings: every
//! setting is a generic controller option of `raceway::solver::Options`.

use raceway::scene::{Fidelity, MethodName, Scene};
use raceway::simulation::{out, Simulation, WorkStats};
use raceway::solver::{Method, Options};
use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

const FS: f64 = 51_200.0;

/// One controller setting.
struct Ctrl {
    name: &'static str,
    what: &'static str,
    set: fn(MethodName, &mut Options),
}

fn base(_: MethodName, _: &mut Options) {}

fn controllers() -> Vec<Ctrl> {
    vec![
        Ctrl {
            name: "I",
            what: "baseline: I-controller, safety 0.9, fac 0.2…10, beta 0",
            set: base,
        },
        Ctrl {
            name: "hairer",
            what: "Hairer's codes: DOPRI5 (and RKF45) beta 0.04, fac 0.2…10; DOP853 beta 0, fac 0.333…6",
            set: |m, o| {
                if m == MethodName::Dop853 {
                    o.fac_min = 0.333;
                    o.fac_max = 6.0;
                } else {
                    o.pi_beta = 0.04;
                }
            },
        },
        Ctrl {
            name: "PI.04",
            what: "PI beta 0.04 for every method",
            set: |_, o| o.pi_beta = 0.04,
        },
        Ctrl {
            name: "PI.08",
            what: "PI beta 0.08 for every method",
            set: |_, o| o.pi_beta = 0.08,
        },
        Ctrl {
            name: "s0.8",
            what: "I-controller, safety 0.8",
            set: |_, o| o.safety = 0.8,
        },
        Ctrl {
            name: "fmax2",
            what: "I-controller, fac_max 2 (step may at most double)",
            set: |_, o| o.fac_max = 2.0,
        },
        Ctrl {
            name: "restart",
            what: "I-controller, fresh initial step (hinit) after every event/stop/discontinuity",
            set: |_, o| o.restart_after_discontinuity = true,
        },
        Ctrl {
            name: "PI.04+rs",
            what: "PI beta 0.04 and restart after discontinuities",
            set: |_, o| {
                o.pi_beta = 0.04;
                o.restart_after_discontinuity = true;
            },
        },
    ]
}

fn method_of(m: MethodName) -> Method {
    match m {
        MethodName::Rkf45 => Method::Rkf45,
        MethodName::Dopri5 => Method::Dopri5,
        MethodName::Dop853 => Method::Dop853,
    }
}

struct Run {
    signal: Vec<f64>,
    stats: WorkStats,
    wall: f64,
    /// Rejections per 0.5 ms window (for the "where" analysis).
    rej_windows: Vec<u64>,
}

fn run(
    scene: &Scene,
    m: MethodName,
    rtol: f64,
    ctrl: &Ctrl,
    dur: f64,
    skip: f64,
) -> Result<Run, String> {
    let mut sc = scene.clone();
    sc.solver.method = m;
    sc.solver.rtol = rtol;
    sc.solver.max_steps = 20_000_000;
    let start = Instant::now();
    let mut sim = Simulation::new(&sc).map_err(|e| e.to_string())?;
    let mut o = Options::new(method_of(m), rtol, vec![1.0]);
    (ctrl.set)(m, &mut o);
    sim.set_step_control(&o).map_err(|e| e.to_string())?;
    let mut signal = Vec::new();
    let mut rej_windows = Vec::new();
    // 0.5 ms chunks: the samples land on multiples of 1/FS, so chunk ends do not change them;
    // the integrator keeps its un-shortened step across chunk ends.
    let chunk = 5e-4;
    let nch = (dur / chunk).round() as usize;
    let mut last_rej = 0;
    for i in 1..=nch {
        let t_next = i as f64 * chunk;
        sim.advance_sampled(t_next, 1.0 / FS, &mut |ts, o| {
            if ts >= skip - 1e-12 {
                signal.push(o[out::PEDESTAL_A_Z]);
            }
        })
        .map_err(|e| e.to_string())?;
        let r = sim.stats().rejected;
        rej_windows.push(r - last_rej);
        last_rej = r;
    }
    Ok(Run {
        signal,
        stats: sim.stats(),
        wall: start.elapsed().as_secs_f64(),
        rej_windows,
    })
}

fn e1(x: &[f64], r: &[f64]) -> f64 {
    let n = x.len().min(r.len());
    let num: f64 = x[..n].iter().zip(r).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = r[..n].iter().map(|b| b * b).sum::<f64>() / n as f64;
    (num / n as f64).sqrt() / den.sqrt().max(1.0)
}

/// Share of all rejections that fall into the busiest 10 % of the 0.5 ms windows.
fn concentration(w: &[u64]) -> f64 {
    let total: u64 = w.iter().sum();
    if total == 0 {
        return 0.0;
    }
    let mut v = w.to_vec();
    v.sort_unstable_by(|a, b| b.cmp(a));
    let k = (v.len() / 10).max(1);
    v[..k].iter().sum::<u64>() as f64 / total as f64
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let quick = std::env::args().any(|a| a == "--quick");
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut s2 = Scene::default_scene();
    s2.name = "S2".into();
    let full = Scene::load(&root.join("examples/scenes/sec3.5-outer-full.toml"))?;
    // (label, scene, level, duration, skip)
    let mut levels: Vec<(&str, Scene, f64, f64)> = Vec::new();
    let mut l = s2.clone();
    l.fidelity = Fidelity::Lumped;
    levels.push(("lumped", l, 0.1, 0.02));
    let mut r = s2.clone();
    r.fidelity = Fidelity::Reduced;
    levels.push(("reduced", r, if quick { 0.04 } else { 0.06 }, 0.02));
    if !quick {
        levels.push(("full", full, 0.025, 0.015));
    }
    let methods = [MethodName::Rkf45, MethodName::Dopri5, MethodName::Dop853];
    let rtols = [1e-4, 1e-6];
    let ctrls = controllers();
    let mut csv = String::from(
        "level,method,rtol,controller,steps,rejected,rhs_evals,wall_s,E1,rej_top10pct_windows\n",
    );
    let mut rows: Vec<(String, String, f64, String, WorkStats, f64, f64)> = Vec::new();
    for (label, scene, dur, skip) in &levels {
        let is_full = *label == "full";
        let reference = run(scene, MethodName::Dop853, 1e-11, &ctrls[0], *dur, *skip)?;
        eprintln!(
            "{label}: reference {} RHS, {:.1} s",
            reference.stats.rhs_evals, reference.wall
        );
        for &m in &methods {
            for &rtol in &rtols {
                for c in &ctrls {
                    // The full level is expensive: the baseline and the two candidates only.
                    if is_full && !matches!(c.name, "I" | "PI.04" | "restart") {
                        continue;
                    }
                    let r = match run(scene, m, rtol, c, *dur, *skip) {
                        Ok(r) => r,
                        Err(e) => {
                            eprintln!("{label} {m:?} {rtol:e} {}: failed: {e}", c.name);
                            writeln!(csv, "{label},{m:?},{rtol:e},{},,,,,,failed", c.name)?;
                            continue;
                        }
                    };
                    let err = e1(&r.signal, &reference.signal);
                    let conc = concentration(&r.rej_windows);
                    eprintln!(
                        "{label} {m:?} {rtol:e} {:9}: steps {} rej {} rhs {} E1 {:.3e} wall {:.2} s conc {:.2}",
                        c.name, r.stats.steps, r.stats.rejected, r.stats.rhs_evals, err, r.wall, conc
                    );
                    writeln!(
                        csv,
                        "{label},{m:?},{rtol:e},{},{},{},{},{:.3},{:.4e},{:.3}",
                        c.name,
                        r.stats.steps,
                        r.stats.rejected,
                        r.stats.rhs_evals,
                        r.wall,
                        err,
                        conc
                    )?;
                    rows.push((
                        label.to_string(),
                        format!("{m:?}"),
                        rtol,
                        c.name.to_string(),
                        r.stats,
                        err,
                        conc,
                    ));
                }
            }
        }
    }
    let docs = root.join("docs");
    std::fs::write(docs.join("step-control.csv"), &csv)?;
    // Markdown
    let mut md = String::new();
    writeln!(md, "# Step-size control\n")?;
    writeln!(
        md,
        "Generated by `cargo run --release --example controller_study` (raw data: \
         `docs/step-control.csv`). Do not edit by hand.\n"
    )?;
    writeln!(
        md,
        "Controller settings (generic options of `raceway::solver::Options`):\n"
    )?;
    for c in &ctrls {
        writeln!(md, "- `{}`: {}", c.name, c.what)?;
    }
    writeln!(
        md,
        "\nScenes: S2 (outer-race spall, default scene) at the lumped and reduced levels, \
         `examples/scenes/sec3.5-outer-full.toml` (`lock_tilt`) at the full level. \
         E1: relative RMS error of `pedestal.a.z` against DOP853 at rtol 1e-11 (baseline \
         controller). `rhs Δ` is the change of RHS evaluations against the baseline `I` row of \
         the same level, method and rtol. `top10%`: share of the rejections that fall into the \
         busiest 10 % of 0.5 ms windows (1.0 = all rejections bunched, 0.1 = spread evenly).\n"
    )?;
    writeln!(
        md,
        "| level | method | rtol | controller | steps | rejected | rej % | RHS evals | rhs Δ | E1 | top10% |"
    )?;
    writeln!(md, "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|")?;
    for (lv, m, rtol, c, st, err, conc) in &rows {
        let base = rows
            .iter()
            .find(|r| &r.0 == lv && &r.1 == m && r.2 == *rtol && r.3 == "I")
            .map(|r| r.4.rhs_evals as f64)
            .unwrap_or(f64::NAN);
        let rej_pct = 100.0 * st.rejected as f64 / (st.steps + st.rejected).max(1) as f64;
        writeln!(
            md,
            "| {lv} | {m} | {rtol:e} | {c} | {} | {} | {rej_pct:.1} | {} | {:+.1} % | {err:.2e} | {conc:.2} |",
            st.steps,
            st.rejected,
            st.rhs_evals,
            100.0 * (st.rhs_evals as f64 / base - 1.0)
        )?;
    }
    std::fs::write(docs.join("step-control.md"), &md)?;
    eprintln!("wrote docs/step-control.md and docs/step-control.csv");
    Ok(())
}
