//! Step-size controller study: RHS evaluations, steps and rejections against the error E1 for
//! several controller settings, per level (lumped, reduced, full) and method, in one run.
//! Writes `docs/research/step-control.csv` and `docs/research/step-control.md`.
//!
//! ```text
//! cargo run --release -p raceway-studies --bin controller_study [-- --quick]
//! cargo run --release -p raceway-studies --bin controller_study -- --strays   # docs/research/step-control-strays.md
//! cargo run --release -p raceway-studies --bin controller_study -- --slopes   # docs/research/step-control-slopes.md
//! ```
//!
//! Scenes: S2 of `raceway bench` (default scene: outer-race spall 1.0 × 0.2 mm at the load-zone
//! centre, Fa 4000 N, Fr 1000 N, 9900 rpm) at the lumped and reduced levels, and
//! `examples/scenes/sec3.5-outer-full.toml` (the same spall, `[full] lock_tilt = true`) at the
//! full level. Error E1 as in `raceway bench`: relative RMS error of `pedestal.a.z` sampled at
//! 51.2 kHz after the transient, against DOP853 at rtol 1e-11 with the baseline controller
//! (reference RMS floored at 1 m/s²). The integrator knows nothing about bearings: every
//! setting is a generic controller option of `raceway::solver::Options`.

use raceway::signal::{envelope_spectrum, peak_near, Window};
use raceway::solver::Stats as WorkStats;
use raceway::solver::{Method, Options};
use raceway::{out, Fidelity, MethodName, Scene, Simulation};
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
            name: "obs-p",
            what: "I-controller; after two rejections in a row the retry uses the local order observed from them",
            set: |_, o| o.observed_order_on_reject = true,
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
    /// Outer-race fault frequency (BPFO) [Hz].
    bpfo: f64,
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
        let r = sim.solver_stats().rejected;
        rej_windows.push(r - last_rej);
        last_rej = r;
    }
    let bpfo = sim.bearing().z as f64 * sim.cage_speed() / std::f64::consts::TAU;
    Ok(Run {
        signal,
        stats: sim.solver_stats(),
        wall: start.elapsed().as_secs_f64(),
        rej_windows,
        bpfo,
    })
}

fn e1(x: &[f64], r: &[f64]) -> f64 {
    let n = x.len().min(r.len());
    let num: f64 = x[..n].iter().zip(r).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = r[..n].iter().map(|b| b * b).sum::<f64>() / n as f64;
    (num / n as f64).sqrt() / den.sqrt().max(1.0)
}

/// E2: largest relative amplitude error of the envelope-spectrum peaks (band 1–20 kHz, Hann) at
/// BPFO × 1…5 against the reference's (as in `raceway bench`); 1 if a peak is missing.
fn e2(x: &[f64], r: &[f64], f0: f64) -> f64 {
    let n = x.len().min(r.len());
    let band = Some((1_000.0, 20_000.0));
    let (Ok(sx), Ok(sr)) = (
        envelope_spectrum(&x[..n], FS, band, Window::Hann),
        envelope_spectrum(&r[..n], FS, band, Window::Hann),
    ) else {
        return f64::NAN;
    };
    let tol = (0.1 * f0).max(3.0 * sr.resolution());
    let mut e = 0.0f64;
    for h in 1..=5 {
        let f = f0 * h as f64;
        match (peak_near(&sx, f, tol), peak_near(&sr, f, tol)) {
            (Some(px), Some(pr)) if pr.amplitude > 0.0 => {
                e = e.max((px.amplitude - pr.amplitude).abs() / pr.amplitude)
            }
            (None, Some(_)) => return 1.0,
            _ => return f64::NAN,
        }
    }
    e
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

/// Where the rejections fall: DOP853, rtol 1e-6, baseline controller, integrated in 0.1 ms
/// chunks (this adds up to one step per chunk) and folded over the spall-passage period 1/BPFO
/// into `NB` phase bins. Returns (share of rejections, share of accepted steps, mean |a_z| of
/// the pedestal) per bin; the |a_z| column shows where the impacts are.
const NB: usize = 10;
fn where_rejected(scene: &Scene, dur: f64) -> Result<Vec<(f64, f64, f64)>, String> {
    let mut sc = scene.clone();
    sc.solver.method = MethodName::Dop853;
    sc.solver.rtol = 1e-6;
    let mut sim = Simulation::new(&sc).map_err(|e| e.to_string())?;
    let period = std::f64::consts::TAU / (sim.bearing().z as f64 * sim.cage_speed());
    let bin = |t: f64| (((t / period).fract() * NB as f64) as usize).min(NB - 1);
    let mut rej = [0u64; NB];
    let mut acc = [0u64; NB];
    let mut asum = [0.0f64; NB];
    let mut acnt = [0u64; NB];
    let chunk = 1e-4;
    let skip = 0.02;
    let nch = (dur / chunk).round() as usize;
    let mut last = sim.solver_stats();
    for i in 1..=nch {
        let t_next = i as f64 * chunk;
        sim.advance_sampled(t_next, 1.0 / FS, &mut |ts, o| {
            if ts >= skip {
                asum[bin(ts)] += o[out::PEDESTAL_A_Z].abs();
                acnt[bin(ts)] += 1;
            }
        })
        .map_err(|e| e.to_string())?;
        let st = sim.solver_stats();
        let tm = t_next - 0.5 * chunk;
        if tm >= skip {
            rej[bin(tm)] += st.rejected - last.rejected;
            acc[bin(tm)] += st.steps - last.steps;
        }
        last = st;
    }
    let (rt, at) = (
        rej.iter().sum::<u64>().max(1) as f64,
        acc.iter().sum::<u64>().max(1) as f64,
    );
    Ok((0..NB)
        .map(|k| {
            (
                rej[k] as f64 / rt,
                acc[k] as f64 / at,
                asum[k] / acnt[k].max(1) as f64,
            )
        })
        .collect())
}

/// One measured row.
struct Row {
    level: String,
    method: String,
    rtol: f64,
    ctrl: String,
    st: WorkStats,
    e1: f64,
    e2: f64,
    conc: f64,
}

/// Least-squares line `y = a + b x` through the points: (a, b); None with fewer than two
/// points or no spread in x.
fn line_fit(pts: &[(f64, f64)]) -> Option<(f64, f64)> {
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let b = sxy / sxx;
    Some((my - b * mx, b))
}

/// Least-squares fit `ln rhs = a + b ln err` over the rows; None unless the error falls with
/// work (b < 0) and every error is finite and positive.
fn fit(rows: &[&Row], err: fn(&Row) -> f64) -> Option<(f64, f64)> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (err(r).ln(), (r.st.rhs_evals as f64).ln()))
        .collect();
    if pts.iter().any(|p| !p.0.is_finite()) {
        return None;
    }
    line_fit(&pts).filter(|&(_, b)| b < 0.0)
}

/// RHS evaluations of controller `c` at the baseline's accuracy, relative to the baseline,
/// geometric mean over the baseline's rtols (from the fits of both): < 1 means less work.
fn equal_accuracy_ratio(rows: &[Row], lv: &str, m: &str, c: &str, err: fn(&Row) -> f64) -> f64 {
    let sel = |cn: &str| -> Vec<&Row> {
        rows.iter()
            .filter(|r| r.level == lv && r.method == m && r.ctrl == cn)
            .collect()
    };
    let (base, cand) = (sel("I"), sel(c));
    let (Some((ab, bb)), Some((ac, bc))) = (fit(&base, err), fit(&cand, err)) else {
        return f64::NAN;
    };
    let mut acc = 0.0;
    for r in &base {
        let le = err(r).ln();
        acc += (ac + bc * le) - (ab + bb * le);
    }
    (acc / base.len() as f64).exp()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let quick = std::env::args().any(|a| a == "--quick");
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."));
    if std::env::args().any(|a| a == "--strays") {
        return strays(root);
    }
    if std::env::args().any(|a| a == "--slopes") {
        return slopes(root);
    }
    let mut s2 = Scene::default_scene();
    s2.name = "S2".into();
    let full = Scene::load(&root.join("examples/scenes/sec3.5-outer-full.toml"))?;
    // (label, scene, duration, skip)
    let mut levels: Vec<(&str, Scene, f64, f64)> = Vec::new();
    let mut l = s2.clone();
    l.fidelity = Fidelity::Lumped;
    levels.push(("lumped", l, 0.1, 0.02));
    let mut r = s2.clone();
    r.fidelity = Fidelity::Reduced;
    levels.push(("reduced", r, if quick { 0.04 } else { 0.1 }, 0.02));
    if !quick {
        levels.push(("full", full, 0.035, 0.015));
    }
    let methods = [MethodName::Rkf45, MethodName::Dopri5, MethodName::Dop853];
    let rtols = [1e-4, 1e-5, 1e-6];
    let ctrls = controllers();
    let mut csv = String::from(
        "level,method,rtol,controller,steps,rejected,rhs_evals,events,stiff_steps,wall_s,E1,E2,rej_top10pct_windows\n",
    );
    let mut rows: Vec<Row> = Vec::new();
    let mut refs = Vec::new();
    let mut wheres = Vec::new();
    for (label, scene, dur, _) in &levels {
        let w = where_rejected(scene, *dur)?;
        eprintln!("{label}: where {w:?}");
        wheres.push((label.to_string(), w));
    }
    for (label, scene, dur, skip) in &levels {
        let is_full = *label == "full";
        let reference = run(scene, MethodName::Dop853, 1e-11, &ctrls[0], *dur, *skip)?;
        eprintln!(
            "{label}: reference {} RHS, {:.1} s",
            reference.stats.rhs_evals, reference.wall
        );
        refs.push(format!(
            "{label}: {dur} s simulated, errors on t ≥ {skip} s; reference DOP853 rtol 1e-11: {} steps, {} rejected, {} RHS; BPFO {:.1} Hz",
            reference.stats.steps, reference.stats.rejected, reference.stats.rhs_evals, reference.bpfo
        ));
        for &m in &methods {
            for &rtol in &rtols {
                // The full level is expensive: rtol 1e-4 and 1e-6 only.
                if is_full && rtol == 1e-5 {
                    continue;
                }
                for c in &ctrls {
                    // ... and the baseline and the main candidates only.
                    if is_full && !matches!(c.name, "I" | "PI.04" | "s0.8" | "restart" | "obs-p") {
                        continue;
                    }
                    let r = match run(scene, m, rtol, c, *dur, *skip) {
                        Ok(r) => r,
                        Err(e) => {
                            eprintln!("{label} {m:?} {rtol:e} {}: failed: {e}", c.name);
                            writeln!(csv, "{label},{m:?},{rtol:e},{},,,,,,,,,failed", c.name)?;
                            continue;
                        }
                    };
                    let err1 = e1(&r.signal, &reference.signal);
                    let err2 = e2(&r.signal, &reference.signal, reference.bpfo);
                    let conc = concentration(&r.rej_windows);
                    eprintln!(
                        "{label} {m:?} {rtol:e} {:9}: steps {} rej {} rhs {} E1 {:.3e} E2 {:.3e} wall {:.2} s conc {:.2}",
                        c.name, r.stats.steps, r.stats.rejected, r.stats.rhs_evals, err1, err2, r.wall, conc
                    );
                    writeln!(
                        csv,
                        "{label},{m:?},{rtol:e},{},{},{},{},{},{},{:.3},{:.4e},{:.4e},{:.3}",
                        c.name,
                        r.stats.steps,
                        r.stats.rejected,
                        r.stats.rhs_evals,
                        r.stats.events,
                        r.stats.stiff_steps,
                        r.wall,
                        err1,
                        err2,
                        conc
                    )?;
                    rows.push(Row {
                        level: label.to_string(),
                        method: format!("{m:?}"),
                        rtol,
                        ctrl: c.name.to_string(),
                        st: r.stats,
                        e1: err1,
                        e2: err2,
                        conc,
                    });
                }
            }
        }
    }
    let docs = root.join("docs/research");
    let stem = if quick {
        "step-control-quick"
    } else {
        "step-control"
    };
    std::fs::write(docs.join(format!("{stem}.csv")), &csv)?;
    // Markdown
    let mut md = String::new();
    writeln!(md, "# Step-size control\n")?;
    writeln!(
        md,
        "Generated by `cargo run --release -p raceway-studies --bin controller_study{}` (raw data: \
         `docs/research/{stem}.csv`); do not edit by hand. Conclusions are in the hand-written section \
         of `docs/research/step-control.md` below the marker line, which this command keeps.\n",
        if quick { " -- --quick" } else { "" }
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
        "\nScenes: S2 of `raceway bench` (outer-race spall, default scene) at the lumped and \
         reduced levels, `examples/scenes/sec3.5-outer-full.toml` (`lock_tilt`) at the full \
         level; outputs sampled at 51.2 kHz, integration in 0.5 ms chunks. \
         E1: relative RMS error of `pedestal.a.z`; E2: largest relative error of the envelope \
         peaks at BPFO × 1…5; both against the reference below. `top10%`: share of the \
         rejections in the busiest 10 % of the 0.5 ms windows (0.1 = spread evenly, 1 = all \
         in a few windows).\n"
    )?;
    for r in &refs {
        writeln!(md, "- {r}")?;
    }
    writeln!(md, "\n## Where steps are rejected\n")?;
    writeln!(
        md,
        "DOP853, rtol 1e-6, baseline controller, t ≥ 0.02 s, folded over the spall-passage \
         period 1/BPFO into {NB} phase bins (integration in 0.1 ms chunks for this \
         attribution). Per bin: share of all rejections / share of all accepted steps / mean \
         |pedestal.a.z| [m/s²] (the impact is where |a_z| is largest). Evenly spread would be \
         {:.2} per bin.\n",
        1.0 / NB as f64
    )?;
    write!(md, "| level |")?;
    for k in 0..NB {
        write!(md, " bin {k} |")?;
    }
    writeln!(md)?;
    write!(md, "|---|")?;
    for _ in 0..NB {
        write!(md, "---|")?;
    }
    writeln!(md)?;
    for (lv, w) in &wheres {
        write!(md, "| {lv} |")?;
        for (r, a, g) in w {
            write!(md, " {r:.2} / {a:.2} / {g:.0} |")?;
        }
        writeln!(md)?;
    }
    writeln!(md, "\n## Work at equal accuracy\n")?;
    writeln!(
        md,
        "RHS evaluations of each setting at the baseline's error, relative to the baseline `I` \
         (fit ln RHS = a + b ln E over the rtols of each setting, evaluated at the baseline's \
         errors, geometric mean): below 1 = less work for the same error. `n/a`: the error does \
         not fall with work for one of the two (e.g. chaotic trajectories, E1 at the reduced \
         level).\n"
    )?;
    write!(md, "| level | method | measure |")?;
    for c in &ctrls[1..] {
        write!(md, " {} |", c.name)?;
    }
    writeln!(md)?;
    write!(md, "|---|---|---|")?;
    for _ in &ctrls[1..] {
        write!(md, "---:|")?;
    }
    writeln!(md)?;
    type Measure = (&'static str, fn(&Row) -> f64);
    let measures: [Measure; 2] = [("E1", |r| r.e1), ("E2", |r| r.e2)];
    for (lv, _, _, _) in &levels {
        for m in &methods {
            let m = format!("{m:?}");
            for (mn, f) in measures {
                write!(md, "| {lv} | {m} | {mn} |")?;
                for c in &ctrls[1..] {
                    let q = equal_accuracy_ratio(&rows, lv, &m, c.name, f);
                    if q.is_finite() {
                        write!(md, " {q:.3} |")?;
                    } else {
                        write!(md, " n/a |")?;
                    }
                }
                writeln!(md)?;
            }
        }
    }
    writeln!(md, "\n## All runs\n")?;
    writeln!(
        md,
        "`rhs Δ`: change of RHS evaluations against the baseline `I` row of the same level, \
         method and rtol (at whatever error each reached). `events`: located events and stops \
         handled by the integrator. `stiff %`: share of accepted steps flagged by Hairer's \
         stiffness detection (h·ρ > 3.25 for DOPRI5, > 6.1 for DOP853; RKF45 has none: –), i.e. \
         steps whose size is bounded by stability rather than accuracy.\n"
    )?;
    writeln!(
        md,
        "| level | method | rtol | controller | steps | rejected | rej % | RHS evals | rhs Δ | E1 | E2 | events | stiff % | top10% |"
    )?;
    writeln!(
        md,
        "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
    )?;
    for r in &rows {
        let base = rows
            .iter()
            .find(|b| {
                b.level == r.level && b.method == r.method && b.rtol == r.rtol && b.ctrl == "I"
            })
            .map(|b| b.st.rhs_evals as f64)
            .unwrap_or(f64::NAN);
        let st = r.st;
        let rej_pct = 100.0 * st.rejected as f64 / (st.steps + st.rejected).max(1) as f64;
        writeln!(
            md,
            "| {} | {} | {:e} | {} | {} | {} | {rej_pct:.1} | {} | {:+.1} % | {:.2e} | {:.2e} | {} | {} | {:.2} |",
            r.level,
            r.method,
            r.rtol,
            r.ctrl,
            st.steps,
            st.rejected,
            st.rhs_evals,
            100.0 * (st.rhs_evals as f64 / base - 1.0),
            r.e1,
            r.e2,
            st.events,
            if r.method == "Rkf45" {
                "–".to_string()
            } else {
                format!("{:.0}", 100.0 * st.stiff_steps as f64 / st.steps.max(1) as f64)
            },
            r.conc
        )?;
    }
    // Keep the hand-written conclusions below the marker.
    let path = docs.join(format!("{stem}.md"));
    const MARKER: &str = "<!-- conclusions (hand-written, kept by controller_study) -->";
    let kept = std::fs::read_to_string(&path)
        .ok()
        .and_then(|old| old.find(MARKER).map(|i| old[i..].to_string()))
        .unwrap_or_else(|| format!("{MARKER}\n"));
    writeln!(md, "\n{kept}")?;
    std::fs::write(&path, md.trim_end().to_string() + "\n")?;
    eprintln!("wrote {}", path.display());
    Ok(())
}

/// The five S2 trajectories of `--strays` and `--slopes`: shaft speeds [rpm].
const TRAJECTORY_SPEEDS: [f64; 5] = [9500.0, 9700.0, 9900.0, 10_100.0, 10_300.0];
// An odd count: the median over the trajectories is one of them ([`median_of`]).
const _: () = assert!(TRAJECTORY_SPEEDS.len() % 2 == 1);

/// (label, fidelity, duration, skip) of the levels in `--strays` and `--slopes`.
const TRAJECTORY_LEVELS: [(&str, Fidelity, f64, f64); 3] = [
    ("lumped", Fidelity::Lumped, 0.1, 0.02),
    ("reduced", Fidelity::Reduced, 0.04, 0.015),
    ("full", Fidelity::Full, 0.04, 0.015),
];

/// S2 of `raceway bench`: the default scene.
fn s2_scene() -> Scene {
    let mut s2 = Scene::default_scene();
    s2.name = "S2".into();
    s2
}

/// Median over the trajectories (an odd count: the middle value), by the library's median.
fn median_of(v: &[f64]) -> f64 {
    raceway::signal::median(v.to_vec()).expect("a value per trajectory")
}

/// `--strays`: how often a run leaves the reference's trajectory at loose tolerances (E1 above
/// 0.05, a different rattle sequence rather than a small error), with the I-controller and with
/// PI β = 0.04 / 0.08, over five trajectories (shaft speed 9500 … 10 300 rpm, otherwise S2) per
/// level, DOP853. Writes `docs/research/step-control-strays.csv` and `docs/research/step-control-strays.md`.
fn strays(root: &Path) -> Result<(), Box<dyn std::error::Error>> {
    const STRAY: f64 = 0.05;
    let speeds = TRAJECTORY_SPEEDS;
    let rtols = [1e-3, 1e-4, 1e-5, 1e-6];
    let all = controllers();
    let ctrls: Vec<&Ctrl> = all
        .iter()
        .filter(|c| matches!(c.name, "I" | "PI.04" | "PI.08"))
        .collect();
    let s2 = s2_scene();
    let levels = TRAJECTORY_LEVELS;
    let mut csv =
        String::from("level,speed_rpm,rtol,controller,steps,rejected,rhs_evals,events,E1\n");
    // One cell per (level, rtol, controller): E1 and RHS per speed.
    struct Cell {
        level: &'static str,
        rtol: f64,
        ctrl: &'static str,
        e1: Vec<f64>,
        rhs: Vec<f64>,
    }
    let mut cells: Vec<Cell> = Vec::new();
    let start = Instant::now();
    for (label, fid, dur, skip) in levels {
        for &rpm in &speeds {
            let mut sc = s2.clone();
            sc.fidelity = fid;
            sc.operating.shaft_speed = raceway::rpm_to_rad_s(rpm);
            let reference = run(&sc, MethodName::Dop853, 1e-11, &all[0], dur, skip)?;
            eprintln!(
                "{label} {rpm} rpm: reference {} RHS",
                reference.stats.rhs_evals
            );
            for &rtol in &rtols {
                for c in &ctrls {
                    let r = run(&sc, MethodName::Dop853, rtol, c, dur, skip)?;
                    let e = e1(&r.signal, &reference.signal);
                    let st = r.stats;
                    writeln!(
                        csv,
                        "{label},{rpm},{rtol:e},{},{},{},{},{},{e:.6e}",
                        c.name, st.steps, st.rejected, st.rhs_evals, st.events
                    )?;
                    let i = match cells
                        .iter()
                        .position(|x| x.level == label && x.rtol == rtol && x.ctrl == c.name)
                    {
                        Some(i) => i,
                        None => {
                            cells.push(Cell {
                                level: label,
                                rtol,
                                ctrl: c.name,
                                e1: Vec::new(),
                                rhs: Vec::new(),
                            });
                            cells.len() - 1
                        }
                    };
                    cells[i].e1.push(e);
                    cells[i].rhs.push(st.rhs_evals as f64);
                }
            }
        }
    }
    let docs = root.join("docs/research");
    std::fs::write(docs.join("step-control-strays.csv"), &csv)?;
    let median = median_of;
    let mut md = String::new();
    writeln!(
        md,
        "# Loose tolerances: runs that leave the reference trajectory\n\n\
         Generated by `cargo run --release -p raceway-studies --bin controller_study -- --strays` ({:.0} s; raw \
         data: `docs/research/step-control-strays.csv`); do not edit by hand.\n\n\
         DOP853 on S2 of `raceway bench` (outer spall, Fa 4000 N, Fr 1000 N) at five shaft speeds, \
         {} rpm, i.e. five trajectories per level; errors E1 (relative RMS of `pedestal.a.z` at \
         51.2 kHz after the transient) against DOP853 at rtol 1e-11 with the I-controller at the \
         same speed. Lumped 0.1 s (E1 from 0.02 s), reduced and full 0.04 s (E1 from 0.015 s). A \
         *stray* is a run with E1 > {STRAY}: a different rattle or impact sequence, not a small \
         error. RHS is relative to the I-controller's at the same level, rtol and speed (mean over \
         the speeds).\n",
        start.elapsed().as_secs_f64(),
        speeds.map(|v| format!("{v}")).join(" / "),
    )?;
    writeln!(
        md,
        "| level | rtol | controller | strays (of {}) | median E1 | largest E1 | RHS vs I |\n|---|---|---|---|---|---|---|",
        speeds.len()
    )?;
    for Cell {
        level: lv,
        rtol,
        ctrl: c,
        e1: es,
        rhs,
    } in &cells
    {
        let base = cells
            .iter()
            .find(|x| x.level == *lv && x.rtol == *rtol && x.ctrl == "I")
            .map(|x| x.rhs.clone())
            .unwrap_or_default();
        let ratio = rhs.iter().zip(&base).map(|(a, b)| a / b).sum::<f64>() / rhs.len() as f64;
        let n_stray = es.iter().filter(|&&e| e > STRAY).count();
        let largest = es.iter().copied().fold(0.0, f64::max);
        writeln!(
            md,
            "| {lv} | {rtol:e} | {c} | {n_stray} | {:.2e} | {largest:.2e} | {ratio:.3} |",
            median(es)
        )?;
    }
    std::fs::write(docs.join("step-control-strays.md"), &md)?;
    print!("{md}");
    Ok(())
}

/// Least-squares slope of log10(E1) against log10(rtol) (None with fewer than 3 positive E1).
fn log_slope(pts: &[(f64, f64)]) -> Option<f64> {
    let p: Vec<(f64, f64)> = pts
        .iter()
        .filter(|(_, e)| *e > 0.0)
        .map(|(r, e)| (r.log10(), e.log10()))
        .collect();
    if p.len() < 3 {
        return None;
    }
    line_fit(&p).map(|(_, b)| b)
}

/// `--slopes`: the E1-against-rtol slope of `docs/performance.md` (acceptance 0.7 … 1.3 over
/// rtol 1e-4 … 1e-9 on S2), measured over the five trajectories of `--strays` instead of one:
/// every method with the I-controller, per level. Writes `docs/research/step-control-slopes.csv` and
/// `docs/research/step-control-slopes.md`.
fn slopes(root: &Path) -> Result<(), Box<dyn std::error::Error>> {
    let speeds = TRAJECTORY_SPEEDS;
    let rtols = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
    let methods = [MethodName::Rkf45, MethodName::Dopri5, MethodName::Dop853];
    let all = controllers();
    let base = &all[0];
    assert_eq!(base.name, "I");
    let s2 = s2_scene();
    let levels = TRAJECTORY_LEVELS;
    let mut csv = String::from("level,speed_rpm,method,rtol,steps,rejected,rhs_evals,E1\n");
    // (level, method, per speed the (rtol, E1) sweep).
    type Sweep = Vec<(f64, f64)>;
    let mut sweeps: Vec<(&str, MethodName, Vec<Sweep>)> = Vec::new();
    let start = Instant::now();
    for (label, fid, dur, skip) in levels {
        let mut per_method: Vec<Vec<Sweep>> = vec![Vec::new(); methods.len()];
        for &rpm in &speeds {
            let mut sc = s2.clone();
            sc.fidelity = fid;
            sc.operating.shaft_speed = raceway::rpm_to_rad_s(rpm);
            let reference = run(&sc, MethodName::Dop853, 1e-11, base, dur, skip)?;
            for (k, &m) in methods.iter().enumerate() {
                let mut sweep = Vec::new();
                for &rtol in &rtols {
                    let r = run(&sc, m, rtol, base, dur, skip)?;
                    let e = e1(&r.signal, &reference.signal);
                    let st = r.stats;
                    writeln!(
                        csv,
                        "{label},{rpm},{},{rtol:e},{},{},{},{e:.6e}",
                        m.name(),
                        st.steps,
                        st.rejected,
                        st.rhs_evals
                    )?;
                    sweep.push((rtol, e));
                }
                eprintln!(
                    "{label} {rpm} rpm {}: slope {:.2}",
                    m.name(),
                    log_slope(&sweep).unwrap_or(f64::NAN)
                );
                per_method[k].push(sweep);
            }
        }
        for (k, &m) in methods.iter().enumerate() {
            sweeps.push((label, m, std::mem::take(&mut per_method[k])));
        }
    }
    let docs = root.join("docs/research");
    std::fs::write(docs.join("step-control-slopes.csv"), &csv)?;
    let median = median_of;
    let ok = |s: f64| (0.7..=1.3).contains(&s);
    let mut md = String::new();
    writeln!(
        md,
        "# Tolerance proportionality over five trajectories\n\n\
         Generated by `cargo run --release -p raceway-studies --bin controller_study -- --slopes` ({:.0} s; raw \
         data: `docs/research/step-control-slopes.csv`); do not edit by hand.\n\n\
         The acceptance measure of `docs/performance.md`: the least-squares slope of log E1 \
         against log rtol over rtol 1e-4 … 1e-9 on S2, within 0.7 … 1.3, there measured on one \
         trajectory. Here on the five trajectories of `docs/research/step-control-strays.md` (S2 at {} \
         rpm), I-controller, every method; E1 against DOP853 at rtol 1e-11 at the same speed. \
         Lumped 0.1 s (E1 from 0.02 s), reduced and full 0.04 s (E1 from 0.015 s). \
         \"median E1\": the slope through the median over the five trajectories at each rtol; \
         \"per trajectory\": the five slopes of the single sweeps; \"without strays\": the slope \
         of the median E1 over the rtols at which no trajectory strays (E1 > 0.05, a different \
         rattle sequence: docs/research/step-control-strays.md), which a stray at the loose end would \
         otherwise steepen.\n",
        start.elapsed().as_secs_f64(),
        speeds.map(|v| format!("{v}")).join(" / "),
    )?;
    writeln!(
        md,
        "| level | method | median E1 at rtol 1e-4 … 1e-9 | slope of the median E1 | within 0.7 … 1.3 | \
         per-trajectory slopes (min / median / max) | trajectories within | without strays (rtols) |\n\
         |---|---|---|---|---|---|---|---|"
    )?;
    for (label, m, per_speed) in &sweeps {
        let med: Vec<(f64, f64)> = rtols
            .iter()
            .enumerate()
            .map(|(i, &r)| {
                let es: Vec<f64> = per_speed.iter().map(|sw| sw[i].1).collect();
                (r, median(&es))
            })
            .collect();
        let s_med = log_slope(&med).unwrap_or(f64::NAN);
        let each: Vec<f64> = per_speed
            .iter()
            .map(|sw| log_slope(sw).unwrap_or(f64::NAN))
            .collect();
        // The rtols at which no trajectory strays.
        let clean: Vec<(f64, f64)> = med
            .iter()
            .enumerate()
            .filter(|(i, _)| per_speed.iter().all(|sw| sw[*i].1 <= 0.05))
            .map(|(_, p)| *p)
            .collect();
        let s_clean = log_slope(&clean).unwrap_or(f64::NAN);
        let lo = each.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = each.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        writeln!(
            md,
            "| {label} | {} | {} | {s_med:.2} | {} | {lo:.2} / {:.2} / {hi:.2} | {} of {} | {s_clean:.2} ({}) |",
            m.name(),
            med.iter()
                .map(|(_, e)| format!("{e:.1e}"))
                .collect::<Vec<_>>()
                .join(", "),
            if ok(s_med) { "yes" } else { "**no**" },
            median(&each),
            each.iter().filter(|&&s| ok(s)).count(),
            each.len(),
            clean.len()
        )?;
    }
    std::fs::write(docs.join("step-control-slopes.md"), &md)?;
    print!("{md}");
    Ok(())
}
