//! Ball-to-ball contact of the cage-less ball-level models (docs/model.md#ball-ball): the
//! Hertz constant of two spheres against its closed form, and a constructed collision at both
//! levels: ball 1 sent along the groove against its resting neighbour (no traction, no
//! damping, zero shaft speed, axial load only). The centres never come closer than the
//! closed-form Hertz approach of two spheres meeting at that speed (and do come that close:
//! the contact acts), the contact force at the deepest point is the closed-form Hertz force
//! at the overlap computed here from the states, the momentum passes to the struck ball (equal
//! masses, elastic), and the full model's energy, with the ball-to-ball potential, is
//! conserved through the impact.

use raceway::models::internals::layout::{Layout, BR, BTH, BVR, BVX, BW, BX};
use raceway::models::internals::{ball_ball_stiffness, BallBall};
use raceway::models::{FullModel, FullOptions, Model, ModelSystem, ReducedModel, ReducedOptions};
use raceway::solver::{Integrator, Method, Options, StepView};
use raceway::{Bearing, BearingFile, Fidelity, OperatingPoint, Scene};
use std::f64::consts::TAU;

/// Closed-form Hertz constant of two equal spheres of diameter d:
/// Q = (4/3) E* √R* δ^{3/2}, E* = E / (2 (1 − ν²)), R* = d/4.
fn closed_form_k(file: &BearingFile) -> f64 {
    let (e, nu) = (file.material.youngs_modulus, file.material.poisson);
    let e_star = e / (2.0 * (1.0 - nu * nu));
    4.0 / 3.0 * e_star * (file.bearing.ball_diameter / 4.0).sqrt()
}

#[test]
fn sphere_sphere_hertz_constant_and_pair_law_are_the_closed_form() {
    let file = BearingFile::load("niu2014-table1").unwrap();
    let b = Bearing::new(&file).unwrap();
    let k = ball_ball_stiffness(b.d, b.e_prime);
    let k0 = closed_form_k(&file);
    assert!(
        (k / k0 - 1.0).abs() < 1e-12,
        "K = {k:.6e}, closed form {k0:.6e}"
    );
    // The pair law at an overlap and an approach rate: K δ^{3/2} + c δ̇ along the centre line.
    let bb = BallBall::new(b.z, b.d, b.e_prime, 20.0);
    let delta = 3e-6;
    let p = bb.pair_at([0.0; 3], [0.0, 0.1, 0.0], [0.0, b.d - delta, 0.0], [0.0; 3]);
    assert!((p.delta - delta).abs() < 1e-15);
    assert!((p.delta_rate - 0.1).abs() < 1e-15);
    let q = k0 * delta.powf(1.5) + 20.0 * 0.1;
    assert!((p.q / q - 1.0).abs() < 1e-9, "Q = {}, expected {q}", p.q);
    assert_eq!(p.n, [0.0, 1.0, 0.0]);
    // Apart, or separating faster than the spring pushes: no force (never a pull).
    let apart = bb.pair_at([0.0; 3], [0.0; 3], [0.0, b.d + 1e-6, 0.0], [0.0; 3]);
    assert_eq!(apart.q, 0.0);
    let pulling = bb.pair_at(
        [0.0; 3],
        [0.0, -10.0, 0.0],
        [0.0, b.d - delta, 0.0],
        [0.0; 3],
    );
    assert_eq!(pulling.q, 0.0);
}

/// Scene: Table-1 bearing at rest under Fa 4000 N, no damping anywhere, no cage (the
/// ball-to-ball contact is the cage-less models').
fn scene() -> (Scene, Bearing) {
    let mut file = BearingFile::load("niu2014-table1").unwrap();
    file.contact.c_br = 0.0;
    file.pedestal.c_y = 0.0;
    file.pedestal.c_z = 0.0;
    let mut s = Scene::healthy(file, OperatingPoint::from_rpm(0.0, 4000.0, 0.0));
    s.fidelity = Fidelity::Full;
    s.full.cage = false;
    let b = Bearing::new(&s.bearing).unwrap();
    (s, b)
}

/// Ball j's centre and velocity from the state (docs/model.md#frames, the layout's
/// deviations; no spall, so ball 1 starts at θ = 0).
fn ball(lay: &Layout, dm: f64, y: &[f64], j: usize) -> ([f64; 3], [f64; 3]) {
    let b = lay.ball(j);
    let theta = y[lay.psi()] + TAU * j as f64 / lay.z as f64 + y[b + BTH];
    let (s, c) = theta.sin_cos();
    let (er, et) = ([0.0, -s, c], [0.0, -c, -s]);
    let r = 0.5 * dm + y[b + BR];
    let (vr, w) = (y[b + BVR], y[b + BW]);
    (
        [y[b + BX], r * er[1], r * er[2]],
        [
            y[b + BVX],
            vr * er[1] + r * w * et[1],
            vr * er[2] + r * w * et[2],
        ],
    )
}

struct Collision {
    /// Smallest centre distance of balls 1 and 2 minus D \[m\].
    min_gap: f64,
    /// The state there.
    deepest: Vec<f64>,
    /// Orbital rates of the striking and the struck ball at the end, times r, over v.
    after: (f64, f64),
    /// Largest |E − E0| over the run \[J\] (when an energy function is given).
    energy_dev: f64,
}

/// Sends ball 1 (index 0) towards ball 2 at `v` m/s along the groove and integrates over
/// `duration` s, sampling the dense output 16 times per step.
fn collide<M: Model>(
    model: &mut M,
    lay: Layout,
    dm: f64,
    v: f64,
    duration: f64,
    energy: Option<fn(&M, &[f64]) -> f64>,
) -> Collision {
    let n = model.dim();
    let mut y0 = vec![0.0; n];
    model.initial_state(&mut y0);
    y0[lay.ball(0) + BW] = v / (0.5 * dm + y0[lay.ball(0) + BR]);
    model.update_mode(0.0, &y0);
    let mut nominal = vec![0.0; n];
    model.nominal(&mut nominal);
    let rtol = 1e-9;
    let atol = nominal.iter().map(|x| x * rtol).collect();
    let mut integ = Integrator::new(Options::new(Method::Dop853, rtol, atol), 0.0, &y0).unwrap();
    let d = 12.7e-3;
    let gap = |y: &[f64]| {
        let (a, b) = (ball(&lay, dm, y, 0).0, ball(&lay, dm, y, 1).0);
        ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt() - d
    };
    let mut min_gap = gap(&y0);
    let mut deepest = y0.clone();
    let mut buf = vec![0.0; n];
    let mut energy_dev: f64 = 0.0;
    let e0 = energy.map_or(0.0, |e| e(model, &y0));
    // Advance in short spans so that the energy can be read between them.
    let spans = 200;
    for k in 1..=spans {
        let mut obs = |s: &StepView| {
            for i in 1..=16 {
                let t = s.t_start() + (s.t_end() - s.t_start()) * i as f64 / 16.0;
                s.interpolate(t, &mut buf);
                let g = gap(&buf);
                if g < min_gap {
                    min_gap = g;
                    deepest.copy_from_slice(&buf);
                }
            }
        };
        integ
            .advance(
                &mut ModelSystem(model),
                duration * k as f64 / spans as f64,
                Some(&mut obs),
            )
            .unwrap();
        if let Some(e) = energy {
            energy_dev = energy_dev.max((e(model, integ.y()) - e0).abs());
        }
    }
    let y = integ.y();
    let rate = |j: usize| y[lay.ball(j) + BW] * (0.5 * dm + y[lay.ball(j) + BR]) / v;
    Collision {
        min_gap,
        deepest,
        after: (rate(0), rate(1)),
        energy_dev,
    }
}

/// Checks a collision at speed v against the closed forms: the largest approach of two
/// spheres of reduced mass m/2 meeting at v, ½ (m/2) v² = (2/5) K δ^{5/2} (the radial part of
/// the chord is carried by the races, which leaves the energy balance along the orbit), the
/// Hertz force at the deepest state, and the exchange of velocities.
fn check(c: &Collision, q_model: f64, v: f64, level: &str) {
    let file = BearingFile::load("niu2014-table1").unwrap();
    let b = Bearing::new(&file).unwrap();
    let k0 = closed_form_k(&file);
    let mu = 0.5 * b.ball_mass;
    let delta_max = (5.0 * mu * v * v / (4.0 * k0)).powf(0.4);
    let delta = -c.min_gap;
    eprintln!(
        "{level}: deepest overlap {:.4} µm, closed form {:.4} µm; after: striker {:.4} v, struck {:.4} v",
        delta * 1e6,
        delta_max * 1e6,
        c.after.0,
        c.after.1
    );
    assert!(delta > 0.0, "{level}: the balls never touched");
    assert!(
        (delta / delta_max - 1.0).abs() < 0.05,
        "{level}: overlap {delta:.4e} m against the closed form {delta_max:.4e} m"
    );
    // The force the model applied at that state, against the closed form at the overlap
    // computed here from the states.
    let q0 = k0 * delta.powf(1.5);
    assert!(
        (q_model / q0 - 1.0).abs() < 1e-9,
        "{level}: force {q_model} N against the closed form {q0} N"
    );
    assert!(
        c.after.0.abs() < 0.1 && c.after.1 > 0.9,
        "{level}: the momentum did not pass ({:?})",
        c.after
    );
}

#[test]
fn full_model_balls_collide_elastically_and_never_overlap() {
    let (scene, b) = scene();
    let options = FullOptions {
        traction: false,
        ..FullOptions::default()
    };
    let mut m = FullModel::with_options(&scene, &b, &scene.operating, options).unwrap();
    let lay = m.layout();
    let v = 0.5;
    // Gap at rest ≈ dm sin(π/z) − D = 2.88 mm: contact after ≈ 5.8 ms, lasting ≈ 60 µs.
    let c = collide(&mut m, lay, b.dm, v, 7e-3, Some(FullModel::energy));
    let mut d = vec![0.0; m.dim()];
    m.rhs(0.0, &c.deepest, &mut d);
    let q = m.core().ball_ball().unwrap().pairs[0].q;
    check(&c, q, v, "full");
    // Energy through the impact, the ball-to-ball potential included, against the striking
    // ball's kinetic energy.
    let ke = 0.5 * b.ball_mass * v * v;
    eprintln!(
        "full: energy deviation {:.3e} J of {ke:.3e} J",
        c.energy_dev
    );
    assert!(
        c.energy_dev < 1e-4 * ke,
        "energy deviation {:.3e} J",
        c.energy_dev
    );
}

#[test]
fn reduced_model_balls_collide_elastically_and_never_overlap() {
    let (scene, b) = scene();
    let options = ReducedOptions {
        traction: false,
        ..ReducedOptions::default()
    };
    let mut m = ReducedModel::with_options(&scene, &b, &scene.operating, options).unwrap();
    let lay = m.layout();
    let v = 0.5;
    let c = collide(&mut m, lay, b.dm, v, 7e-3, None);
    let mut d = vec![0.0; m.dim()];
    m.rhs(0.0, &c.deepest, &mut d);
    let q = m.core().ball_ball().unwrap().pairs[0].q;
    check(&c, q, v, "reduced");
}
