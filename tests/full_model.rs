//! L4 full model (docs/model.md#frames, #geometry, #strips, #spall, #eom, #initial-state) through its own integrator and through `Simulation`:
//! energy conservation without traction and damping (docs/model.md#verification), static equilibrium at zero
//! speed against L1, and the dynamic cage speed between pure rolling and outer-race control.

use raceway::load_distribution;
use raceway::models::Model;
use raceway::models::{FullModel, FullOptions};
use raceway::solver::{Integrator, Method, Options, System};
use raceway::{out, Bearing, Fidelity, OperatingPoint, Scene, Simulation};
use std::f64::consts::TAU;

#[path = "common/pulse_response.rs"]
mod pulse_response;
use pulse_response::pulse_response_spectrum;

struct Sys<'a>(&'a mut FullModel);

impl System for Sys<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        self.0.rhs(t, y, dydt)
    }
}

fn healthy_scene(rpm: f64, fa: f64, fr: f64) -> Scene {
    let file = raceway::BearingFile::load("niu2014-table1").unwrap();
    let mut s = Scene::healthy(file, OperatingPoint::from_rpm(rpm, fa, fr));
    s.fidelity = Fidelity::Full;
    s
}

/// Energy drift over `duration` s at 9900 rpm with κ = 0, c_br = 0, c_p = 0, without a cage
/// (the paper's bearing; the cage's own energy test is in tests/cage.rs).
fn energy_drift(duration: f64, rtol: f64) -> (f64, f64, f64) {
    let mut scene = healthy_scene(9900.0, 4000.0, 1000.0);
    scene.full.cage = false;
    scene.bearing.contact.c_br = 0.0;
    scene.bearing.pedestal.c_y = 0.0;
    scene.bearing.pedestal.c_z = 0.0;
    let bearing = Bearing::new(&scene.bearing).unwrap();
    let inputs = scene.operating;
    let mut model = FullModel::with_options(
        &scene,
        &bearing,
        &inputs,
        FullOptions {
            traction: false,
            lock_tilt: false,
            ..FullOptions::default()
        },
    )
    .unwrap();
    let n = model.dim();
    let mut y0 = vec![0.0; n];
    model.initial_state(&mut y0);
    model.update_mode(0.0, &y0);
    let mut nominal = vec![0.0; n];
    model.nominal(&mut nominal);
    let atol = nominal.iter().map(|v| v * rtol).collect();
    let mut integ = Integrator::new(Options::new(Method::Dop853, rtol, atol), 0.0, &y0).unwrap();
    let e0 = model.energy(&y0);
    let v0 = model.hertz_potential(&y0);
    let mut max_dev: f64 = 0.0;
    let steps = 20;
    for k in 1..=steps {
        integ
            .advance(
                &mut Sys(&mut model),
                duration * k as f64 / steps as f64,
                None,
            )
            .unwrap();
        let e = model.energy(integ.y());
        max_dev = max_dev.max((e - e0).abs());
    }
    (max_dev, e0, v0)
}

#[test]
fn energy_is_conserved_without_traction_and_damping() {
    let (dev, e0, v0) = energy_drift(10e-3, 1e-9);
    eprintln!("energy drift {dev:.3e} J of E = {e0:.4} J (Hertz potential {v0:.4e} J)");
    assert!(dev / e0.abs() < 1e-5, "relative drift {}", dev / e0.abs());
    // Stricter: relative to the elastic energy that the dynamics exchange.
    assert!(
        dev / v0 < 1e-4,
        "drift relative to the Hertz potential {}",
        dev / v0
    );
}

/// Runs the model (no traction at rest: it changes nothing there) for `duration` and returns
/// the normal forces (inner, outer) at the end.
fn run_static(fa: f64, fr: f64, lock_tilt: bool, duration: f64) -> (Vec<f64>, Vec<f64>, f64) {
    let scene = healthy_scene(0.0, fa, fr);
    let bearing = Bearing::new(&scene.bearing).unwrap();
    let inputs = scene.operating;
    let mut model = FullModel::with_options(
        &scene,
        &bearing,
        &inputs,
        FullOptions {
            traction: true,
            lock_tilt,
            ..FullOptions::default()
        },
    )
    .unwrap();
    let n = model.dim();
    let mut y0 = vec![0.0; n];
    model.initial_state(&mut y0);
    model.update_mode(0.0, &y0);
    let mut nominal = vec![0.0; n];
    model.nominal(&mut nominal);
    let rtol = 1e-7;
    let atol = nominal.iter().map(|v| v * rtol).collect();
    let mut integ = Integrator::new(Options::new(Method::Dop853, rtol, atol), 0.0, &y0).unwrap();
    integ.advance(&mut Sys(&mut model), duration, None).unwrap();
    let y = integ.y().to_vec();
    let mut d = vec![0.0; n];
    model.rhs(duration, &y, &mut d);
    // Largest orbital acceleration |θ̈| of any ball.
    let lay = model.layout();
    let max_acc = (0..bearing.z)
        .map(|j| d[lay.ball(j) + 5].abs())
        .fold(0.0, f64::max);
    let (qi, qo) = model.contact_forces();
    (qi.to_vec(), qo.to_vec(), max_acc)
}

fn assert_close_to_l1(fa: f64, fr: f64, qi: &[f64], qo: &[f64]) {
    let bearing = Bearing::load("niu2014-table1").unwrap();
    let qs = load_distribution::solve(&bearing, &OperatingPoint::from_rpm(0.0, fa, fr)).unwrap();
    for (j, b) in qs.balls.iter().enumerate() {
        assert!(
            (qi[j] / b.q_inner - 1.0).abs() < 0.01 && (qo[j] / b.q_outer - 1.0).abs() < 0.01,
            "Fa {fa} Fr {fr} ball {j}: Q_i {:.2} vs L1 {:.2}, Q_o {:.2} vs L1 {:.2}",
            qi[j],
            b.q_inner,
            qo[j],
            b.q_outer
        );
    }
}

#[test]
fn balls_started_from_l1_stay_put_at_zero_speed() {
    // Pure axial load: no moment, so the free ring tilt stays at zero; closed form Q = 530.86 N.
    let (qi, qo, acc) = run_static(4000.0, 0.0, false, 2e-3);
    assert!(
        qi.iter()
            .chain(&qo)
            .all(|q| (q / 530.86 - 1.0).abs() < 0.01),
        "{qi:?} {qo:?}"
    );
    assert!(acc < 1.0, "|θ̈| = {acc} rad/s²");
    assert_close_to_l1(4000.0, 0.0, &qi, &qo);
    // Combined load with the tilt held as in L1 (a free ring tilts under the radial load's
    // moment imbalance and shares the load differently from a tilt-free L1).
    let (qi, qo, acc) = run_static(4000.0, 1000.0, true, 2e-3);
    assert!(acc < 1.0, "|θ̈| = {acc} rad/s²");
    assert_close_to_l1(4000.0, 1000.0, &qi, &qo);
}

#[test]
fn cage_speed_between_pure_rolling_and_outer_race_control() {
    let scene = healthy_scene(9900.0, 4000.0, 1000.0);
    let mut sim = Simulation::new(&scene).unwrap();
    let (t_settle, t_end) = (5e-3, 10e-3);
    let mut speeds = Vec::new();
    sim.advance_sampled(t_end, 2e-5, &mut |t, o| {
        if t > t_settle {
            speeds.push(o[out::CAGE_SPEED]);
        }
    })
    .unwrap();
    let mean = speeds.iter().sum::<f64>() / speeds.len() as f64 / TAU;
    eprintln!("mean cage speed {mean:.3} Hz");
    // Pure rolling at α0 69.537 Hz, outer-race control 70.42 Hz (docs/model.md#ref-kinematics, #ref-quasi-static).
    assert!(mean > 69.54 && mean < 70.42, "cage speed {mean} Hz");
}

#[test]
fn cage_follows_a_speed_step() {
    let scene = healthy_scene(9900.0, 4000.0, 1000.0);
    let mut sim = Simulation::new(&scene).unwrap();
    sim.advance(2e-3).unwrap();
    let mut inputs = sim.inputs();
    inputs.shaft_speed *= 1.1;
    sim.set_inputs(inputs).unwrap();
    let mut speeds = Vec::new();
    sim.advance_sampled(8e-3, 2e-5, &mut |t, o| {
        if t > 6e-3 {
            speeds.push(o[out::CAGE_SPEED]);
        }
    })
    .unwrap();
    let mean = speeds.iter().sum::<f64>() / speeds.len() as f64 / TAU;
    // 10 % faster shaft: the cage follows to between 1.1 × pure rolling and 1.1 × outer-race
    // control of the original speed (the contact angles barely change).
    eprintln!("cage after the step {mean:.3} Hz");
    assert!(mean > 1.1 * 69.54 && mean < 1.1 * 70.42 * 1.005, "{mean}");
}

#[test]
fn scene_full_table_reaches_the_model() {
    let text = |extra: &str| {
        format!(
            "fidelity = \"full\"\n[operating]\nspeed_rpm = 9900.0\nfa = 4000.0\nfr = 1000.0\n{extra}"
        )
    };
    let sc = Scene::from_toml_str(
        &text("[full]\nlock_tilt = false\ntraction = false\nshaft_tilt_inertia = 0.5\ntilt_stiffness = 1e6\n"),
        "t",
        None,
    )
    .unwrap();
    assert!(!sc.full.lock_tilt && !sc.full.traction);
    assert_eq!(
        (sc.full.shaft_tilt_inertia, sc.full.tilt_stiffness),
        (0.5, 1e6)
    );
    // decision D1: the tilt is held by default
    let dflt = Scene::from_toml_str(&text(""), "t", None).unwrap();
    assert!(dflt.full.lock_tilt && dflt.full.traction);
    let e = Scene::from_toml_str(&text("[full]\ntilt_stiffness = -1.0\n"), "t", None).unwrap_err();
    assert!(e.to_string().contains("full.tilt_stiffness"), "{e}");
    let e = Scene::from_toml_str(&text("[full]\ntilt = 1\n"), "t", None).unwrap_err();
    assert!(e.to_string().contains("tilt"), "{e}");
    // Normal forces act through planes containing the shaft axis: without traction the
    // friction torque is zero up to roundoff; with it, it is not.
    let torque = |sc: &Scene| {
        let mut sim = Simulation::new(sc).unwrap();
        sim.advance(2e-4).unwrap();
        let mut o = vec![0.0; sim.output_table().len()];
        sim.outputs(&mut o);
        o[out::FRICTION_TORQUE]
    };
    let (t_off, t_on) = (torque(&sc), torque(&dflt));
    assert!(t_off.abs() < 1e-9, "{t_off}");
    assert!(t_on.abs() > 1e-4, "{t_on}");
}

/// Paper Table 2 at L4 (Fa 4000 N, Fr 1000 N, 9900 rpm, tilt held): fel is the peak of the
/// pedestal-acceleration spectrum of the pulse response (run minus the same run without the
/// pulse, rectangular window, zero-padded to 1 Hz bins). Independent number: the single-DOF
/// acceleration peak ω_n/√(1−2ζ²) of the whole mass on the pedestal spring,
/// m = m_p + m_ir + z m_b, and the paper's 593.7 Hz ± 2 %. Sampled at 200 kHz, where the
/// pulse's corners fall on samples (at 51.2 kHz they do not, and the sampled pulse moves the
/// broad peak by up to 4 Hz: `studies/fel_sampling.rs`).
#[test]
fn impact_test_fel_is_the_pedestal_mode() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/scenes/impact-test-fa4000.toml");
    let mut scene = Scene::load(&path).unwrap();
    scene.fidelity = Fidelity::Full;
    scene.full.lock_tilt = true;
    let t0 = 2e-3;
    scene.pulse.as_mut().unwrap().t0 = t0;
    scene.output.sample_rate = 200_000.0;
    let s = pulse_response_spectrum(&scene, 0.05);
    let fel = raceway::signal::dominant_peak(&s, 400.0, 800.0)
        .unwrap()
        .freq;
    let b = Bearing::new(&scene.bearing).unwrap();
    let p = &scene.bearing.pedestal;
    let m = p.mass + scene.bearing.inner_ring.mass + b.z as f64 * b.ball_mass;
    let wn = (p.k_z / m).sqrt();
    let zeta = p.c_z / (2.0 * (p.k_z * m).sqrt());
    let sdof = wn / (1.0 - 2.0 * zeta * zeta).sqrt() / TAU;
    eprintln!("fel {fel:.1} Hz, single-DOF acceleration peak {sdof:.1} Hz");
    assert!((fel / sdof - 1.0).abs() < 0.01, "fel {fel} vs {sdof}");
    assert!((fel / 593.7 - 1.0).abs() < 0.02, "fel {fel} vs paper 593.7");
}

/// Decision D1, free tilt: the ring carries the shaft's tilt inertia I_s and tilt stiffness k_t,
/// (I_d + I_s) β̈ = M − k_t β (docs/model.md#d1). The change of β̈_y between tilts ±ε, less the
/// same change with k_t = 0 (which leaves the contacts' own moment), is −2 k_t ε / (I_d + I_s).
#[test]
fn the_free_tilt_carries_the_shafts_inertia_and_stiffness() {
    let sc = Scene::from_toml_str(
        "fidelity = \"full\"\n[operating]\nspeed_rpm = 9900.0\nfa = 4000.0\nfr = 1000.0\n",
        "t",
        None,
    )
    .unwrap();
    let bearing = Bearing::new(&sc.bearing).unwrap();
    let (i_s, k_t, eps) = (0.3, 2.0e7, 1e-6);
    let accel_with = |i_s: f64, k: f64, beta: f64| {
        let mut m = FullModel::with_options(
            &sc,
            &bearing,
            &sc.operating,
            FullOptions {
                traction: false,
                lock_tilt: false,
                shaft_tilt_inertia: i_s,
                tilt_stiffness: k,
            },
        )
        .unwrap();
        let n = m.dim();
        let find = |name: &str| (0..n).find(|&i| m.state_name(i) == name).unwrap();
        let (iby, iwy) = (
            find("inner-ring tilt β_y"),
            find("inner-ring tilt rate β̇_y"),
        );
        let mut y = vec![0.0; n];
        m.initial_state(&mut y);
        y[iby] = beta;
        m.update_mode(0.0, &y);
        let mut d = vec![0.0; n];
        m.rhs(0.0, &y, &mut d);
        d[iwy]
    };
    let accel = |k: f64, beta: f64| accel_with(i_s, k, beta);
    let i_d = sc.bearing.inner_ring.i_diam + i_s;
    let with = accel(k_t, eps) - accel(k_t, -eps);
    let without = accel(0.0, eps) - accel(0.0, -eps);
    let expected = -2.0 * k_t * eps / i_d;
    assert!(
        ((with - without) / expected - 1.0).abs() < 1e-9,
        "{} against {expected}",
        with - without
    );
    // and the contacts' own moment is divided by the same inertia: against the ring alone
    let ring = sc.bearing.inner_ring.i_diam;
    let alone = accel_with(0.0, 0.0, eps) - accel_with(0.0, 0.0, -eps);
    assert!(without.abs() > 0.0, "the contacts resist the tilt");
    assert!(
        (without / alone - ring / i_d).abs() < 1e-9,
        "{without} / {alone} against {ring} / {i_d}"
    );
}
