//! Where two runs of a ball-level model separate (diagnostics, not part of CI): runs the default
//! scene (S2: outer-race spall) twice, with two tolerances / methods or with a tiny perturbation
//! of one initial state, samples the whole state from the dense output and prints, per time
//! window, the largest difference of each state block in units of its nominal value (the ball
//! blocks are reported as the largest over the balls, with the ball's index).
//!
//! `cargo run --release -p raceway-studies --bin divergence -- [key=value ...]`
//! keys: level (reduced|full), duration, window, fs (state sample rate), rtol_a, rtol_b,
//! method_a, method_b (dop853|dopri5|rkf45), eps (relative perturbation of run b's initial
//! state), eps_state (index of the perturbed state; default: ball 0's radial velocity),
//! traction (on|off), strips (N: reduced only, [`ReducedOptions::strips`]; 0 = the original single rolling point, docs/model.md#l3),
//! defect (on|off), ball (report only this ball's states in the ball
//! columns).

use raceway::models::Model;
use raceway::models::{FullModel, FullOptions};
use raceway::models::{ReducedModel, ReducedOptions};
use raceway::solver::{AdvanceOutcome, Integrator, Method, Options, StepView};
use raceway::{Bearing, Scene};

use raceway::models::ModelSystem as Driver;

struct Run {
    states: Vec<f64>,
    steps: u64,
    rejected: u64,
    rhs: u64,
}

#[allow(clippy::too_many_arguments)]
fn run(
    scene: &Scene,
    level: &str,
    traction: bool,
    strips: usize,
    method: Method,
    rtol: f64,
    duration: f64,
    fs: f64,
    perturb: Option<(usize, f64)>,
) -> (Run, usize) {
    let bearing = Bearing::new(&scene.bearing).expect("bearing");
    let inputs = scene.operating;
    let mut model: Box<dyn Model> = if level == "full" {
        Box::new(
            FullModel::with_options(
                scene,
                &bearing,
                &inputs,
                FullOptions {
                    traction,
                    lock_tilt: scene.full.lock_tilt,
                    ..FullOptions::default()
                },
            )
            .expect("model"),
        )
    } else {
        Box::new(
            ReducedModel::with_options(
                scene,
                &bearing,
                &inputs,
                ReducedOptions { traction, strips },
            )
            .expect("model"),
        )
    };
    let n = model.dim();
    let mut y0 = vec![0.0; n];
    model.initial_state(&mut y0);
    let mut nominal = vec![0.0; n];
    model.nominal(&mut nominal);
    if let Some((i, eps)) = perturb {
        y0[i] += eps * nominal[i];
    }
    model.update_mode(0.0, &y0);
    let atol = nominal.iter().map(|v| v * rtol).collect();
    let mut opts = Options::new(method, rtol, atol);
    opts.max_steps = u64::MAX / 4;
    let mut integ = Integrator::new(opts, 0.0, &y0).expect("integrator");
    let mut states = y0.clone();
    let mut buf = vec![0.0; n];
    while integ.t() < duration {
        let mut obs = |v: &StepView| {
            let mut k = (v.t_start() * fs).floor() as i64 + 1;
            while k as f64 / fs <= v.t_end() && (k as f64 / fs) <= duration * (1.0 + 1e-12) {
                v.interpolate(k as f64 / fs, &mut buf);
                states.extend_from_slice(&buf);
                k += 1;
            }
        };
        let out = integ
            .advance_with_events(&mut Driver(model.as_mut()), duration, Some(&mut obs))
            .expect("advance");
        if matches!(out, AdvanceOutcome::Stopped { .. }) {
            let t = integ.t();
            model.update_mode(t, integ.y());
            integ.discontinuity();
        }
    }
    let st = integ.stats();
    (
        Run {
            states,
            steps: st.steps,
            rejected: st.rejected,
            rhs: st.rhs_evals,
        },
        n,
    )
}

fn main() {
    let mut scene = Scene::default_scene();
    let mut level = "reduced".to_string();
    let (mut duration, mut window, mut fs) = (0.05, 0.0025, 20_000.0);
    let (mut rtol_a, mut rtol_b) = (1e-10, 1e-11);
    let (mut method_a, mut method_b) = (Method::Dop853, Method::Dop853);
    let (mut eps, mut eps_state) = (0.0, None);
    let mut traction = true;
    let mut strips = raceway::models::internals::L3_STRIPS;
    let mut watch: Option<usize> = None;
    let method = |s: &str| match s {
        "dopri5" => Method::Dopri5,
        "rkf45" => Method::Rkf45,
        _ => Method::Dop853,
    };
    for arg in std::env::args().skip(1) {
        let (k, v) = arg.split_once('=').expect("key=value");
        match k {
            "level" => level = v.to_string(),
            "duration" => duration = v.parse().expect("duration"),
            "window" => window = v.parse().expect("window"),
            "fs" => fs = v.parse().expect("fs"),
            "rtol_a" => rtol_a = v.parse().expect("rtol_a"),
            "rtol_b" => rtol_b = v.parse().expect("rtol_b"),
            "method_a" => method_a = method(v),
            "method_b" => method_b = method(v),
            "eps" => eps = v.parse().expect("eps"),
            "eps_state" => eps_state = Some(v.parse::<usize>().expect("eps_state")),
            "traction" => traction = v == "on",
            "strips" => strips = v.parse().expect("strips=N"),
            "ball" => watch = Some(v.parse().expect("ball")),
            "defect" => {
                if v == "off" {
                    scene.defect = None
                }
            }
            _ => panic!("unknown key {k}"),
        }
    }
    let z = 14;
    let per_ball = if level == "full" { 9 } else { 7 };
    let perturb = (eps != 0.0).then(|| (eps_state.unwrap_or(4), eps));
    let (a, n) = run(
        &scene, &level, traction, strips, method_a, rtol_a, duration, fs, None,
    );
    let (b, _) = run(
        &scene, &level, traction, strips, method_b, rtol_b, duration, fs, perturb,
    );
    println!(
        "a: {method_a:?} rtol {rtol_a:e}: steps {} rejected {} rhs {}",
        a.steps, a.rejected, a.rhs
    );
    println!(
        "b: {method_b:?} rtol {rtol_b:e}: steps {} rejected {} rhs {} perturb {perturb:?}",
        b.steps, b.rejected, b.rhs
    );
    let mut nominal = vec![0.0; n];
    {
        let bearing = Bearing::new(&scene.bearing).expect("bearing");
        let inputs = scene.operating;
        if level == "full" {
            FullModel::new(&scene, &bearing, &inputs)
                .expect("model")
                .nominal(&mut nominal);
        } else {
            ReducedModel::new(&scene, &bearing, &inputs)
                .expect("model")
                .nominal(&mut nominal);
        }
    }
    let samples = a.states.len().min(b.states.len()) / n;
    let names: Vec<String> = (0..per_ball)
        .map(|k| format!("ball[{k}]"))
        .chain(["ring".into(), "pedestal".into(), "angles".into()])
        .collect();
    print!("{:>8}", "t0 [ms]");
    for s in &names {
        print!(" {s:>12}");
    }
    println!();
    let per_window = ((window * fs).round() as usize).max(1);
    let mut rms: Vec<(f64, f64)> = Vec::new();
    let mut i0 = 0;
    while i0 < samples {
        let i1 = (i0 + per_window).min(samples);
        let mut best = vec![(0.0f64, 0usize); names.len()];
        for i in i0..i1 {
            for (k, nom) in nominal.iter().enumerate() {
                let d = (a.states[i * n + k] - b.states[i * n + k]).abs() / nom;
                let (blk, ball) = if let Some(w) = watch.filter(|_| k < per_ball * z) {
                    if k / per_ball != w {
                        continue;
                    }
                    (k % per_ball, w)
                } else if k < per_ball * z {
                    (k % per_ball, k / per_ball)
                } else if k < per_ball * z + if level == "full" { 10 } else { 6 } {
                    (per_ball, 0)
                } else if k < n - 2 {
                    (per_ball + 1, 0)
                } else {
                    (per_ball + 2, 0)
                };
                if d > best[blk].0 {
                    best[blk] = (d, ball);
                }
            }
        }
        // Run a's ball motion in this window: RMS over balls and samples of the axial and
        // radial velocities ẋ, ṙ [m/s] (the transverse and rattle motion).
        let (mut sx, mut sr) = (0.0, 0.0);
        for i in i0..i1 {
            for j in 0..z {
                let yb = &a.states[i * n + per_ball * j..];
                sx += yb[3] * yb[3];
                sr += yb[4] * yb[4];
            }
        }
        let cnt = ((i1 - i0) * z) as f64;
        rms.push(((sx / cnt).sqrt(), (sr / cnt).sqrt()));
        print!("{:8.2}", 1e3 * i0 as f64 / fs);
        for (blk, (d, ball)) in best.iter().enumerate() {
            if blk < per_ball {
                print!(" {d:9.2e}@{ball:<2}");
            } else {
                print!(" {d:12.2e}");
            }
        }
        println!(
            "   rms xdot {:.2e} rdot {:.2e}",
            rms[rms.len() - 1].0,
            rms[rms.len() - 1].1
        );
        i0 = i1;
    }
}
