//! L3 reduced per-ball model (docs/model.md#l3): energy conservation without traction and damping
//! (docs/model.md#verification applied to L3), static equilibrium at zero speed against L1, the dynamic cage
//! speed between pure rolling and outer-race control (also after a speed step), the paper's
//! Sec. 3.5 BPFO from impact spacing, the Sec. 3.1 flight through a wide outer spall and an
//! inner-ring spall turning with the shaft.

#[path = "common/bounces.rs"]
mod bounces;
use bounces::inner_outer_alternations;
use raceway::load_distribution;
use raceway::models::Model;
use raceway::models::{ReducedModel, ReducedOptions};
use raceway::solver::{Integrator, Method, Options, System};
use raceway::{out, Bearing, DefectSpec, Fidelity, OperatingPoint, Race, Scene, Simulation};
use std::f64::consts::TAU;

struct Sys<'a>(&'a mut ReducedModel);

impl System for Sys<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        self.0.rhs(t, y, dydt)
    }
}

fn scene(rpm: f64, fa: f64, fr: f64) -> Scene {
    let file = raceway::BearingFile::load("niu2014-table1").unwrap();
    let mut s = Scene::healthy(file, OperatingPoint::from_rpm(rpm, fa, fr));
    s.fidelity = Fidelity::Reduced;
    s
}

fn model(scene: &Scene, traction: bool) -> (ReducedModel, Vec<f64>) {
    model_with(
        scene,
        ReducedOptions {
            traction,
            ..Default::default()
        },
    )
}

fn model_with(scene: &Scene, options: ReducedOptions) -> (ReducedModel, Vec<f64>) {
    let bearing = Bearing::new(&scene.bearing).unwrap();
    let inputs = scene.operating;
    let mut m = ReducedModel::with_options(scene, &bearing, &inputs, options).unwrap();
    let mut y0 = vec![0.0; m.dim()];
    m.initial_state(&mut y0);
    m.update_mode(0.0, &y0);
    (m, y0)
}

fn integrator(m: &ReducedModel, y0: &[f64], rtol: f64) -> Integrator {
    let mut nominal = vec![0.0; m.dim()];
    m.nominal(&mut nominal);
    let atol = nominal.iter().map(|v| v * rtol).collect();
    Integrator::new(Options::new(Method::Dop853, rtol, atol), 0.0, y0).unwrap()
}

/// Largest |Δẋ| of ball 0 over 1.5…2 ms after its axial velocity was pushed by `push` [m/s],
/// as a fraction of the push (default scene without spall, rtol 1e-10).
fn axial_push_left_after_2ms(options: ReducedOptions, push: f64) -> f64 {
    let sc = scene(9900.0, 4000.0, 1000.0);
    let runs: Vec<Vec<f64>> = [0.0, push]
        .iter()
        .map(|&dv| {
            let (mut m, mut y0) = model_with(&sc, options);
            let b = m.layout().ball(0);
            y0[b + 3] += dv;
            let mut integ = integrator(&m, &y0, 1e-10);
            (0..=10)
                .map(|k| {
                    integ
                        .advance(&mut Sys(&mut m), 1.5e-3 + 0.05e-3 * k as f64, None)
                        .unwrap();
                    integ.y()[b + 3]
                })
                .collect()
        })
        .collect();
    runs[0]
        .iter()
        .zip(&runs[1])
        .map(|(a, b)| (a - b).abs() / push)
        .fold(0.0, f64::max)
}

/// Why L3 takes its traction over strips (studies/divergence.rs): with the rolling traction
/// of docs/model.md#l3 alone (`strips = 0`), nothing but the normal contacts acts on a ball's motion
/// across the groove (along c1 in its axial–radial plane), so that motion rings on: about 40 %
/// of an axial push is left after 2 ms, and long runs over a spall separate at about 180/s
/// whatever the tolerance. L4's strip traction damps it (0.9 % left at 1.5…2 ms,
/// studies/divergence.rs level=full), and so does L3's default strip traction.
#[test]
fn motion_across_the_groove_is_damped_by_the_strip_traction() {
    let push = 1e-5; // 1e-3 of the velocity nominal
    let rolling_only = axial_push_left_after_2ms(
        ReducedOptions {
            strips: 0,
            ..Default::default()
        },
        push,
    );
    let strips = axial_push_left_after_2ms(ReducedOptions::default(), push);
    eprintln!(
        "axial push left after 1.5…2 ms: {rolling_only:.3e} (rolling point only), {strips:.3e} (strips)"
    );
    assert!(
        rolling_only > 0.1,
        "rolling traction only: {rolling_only:.3e} left"
    );
    assert!(strips < 0.02, "with strip traction: {strips:.3e} left");
}

#[test]
fn energy_is_conserved_without_traction_and_damping() {
    // 9900 rpm, Fa 4000 N, Fr 1000 N with κ = 0, c_br = 0, c_p = 0: the balls, the ring and the
    // pedestal exchange kinetic and elastic energy (the radial load makes the orbit non-uniform).
    // Without a cage (the paper's bearing; the cage's own energy test is in tests/cage.rs).
    let mut sc = scene(9900.0, 4000.0, 1000.0);
    sc.full.cage = false;
    sc.bearing.contact.c_br = 0.0;
    sc.bearing.pedestal.c_y = 0.0;
    sc.bearing.pedestal.c_z = 0.0;
    let (mut m, y0) = model(&sc, false);
    let mut integ = integrator(&m, &y0, 1e-9);
    let (e0, v0) = (m.energy(&y0), m.hertz_potential(&y0));
    let (duration, n) = (4e-3, 20);
    let mut dev: f64 = 0.0;
    let mut swing: f64 = 0.0;
    for k in 1..=n {
        integ
            .advance(&mut Sys(&mut m), duration * k as f64 / n as f64, None)
            .unwrap();
        let y = integ.y();
        dev = dev.max((m.energy(y) - e0).abs());
        swing = swing.max((m.hertz_potential(y) - v0).abs());
    }
    eprintln!(
        "energy drift {dev:.3e} J of E = {e0:.4} J; Hertz potential {v0:.4e} J swings by {swing:.3e} J"
    );
    assert!(dev / e0.abs() < 1e-5, "relative drift {}", dev / e0.abs());
    // Stricter: relative to the elastic energy the dynamics exchange (which does move).
    assert!(dev / v0 < 1e-4, "drift relative to the Hertz potential");
    assert!(swing > 100.0 * dev, "the test exchanges no energy");
}

/// Runs at zero speed for `duration` and returns (Q_i, Q_o, largest |θ̈|, largest ball speed).
fn run_static(fa: f64, fr: f64, duration: f64) -> (Vec<f64>, Vec<f64>, f64, f64) {
    let sc = scene(0.0, fa, fr);
    let (mut m, y0) = model(&sc, true);
    let mut integ = integrator(&m, &y0, 1e-7);
    integ.advance(&mut Sys(&mut m), duration, None).unwrap();
    let y = integ.y().to_vec();
    let mut d = vec![0.0; m.dim()];
    m.rhs(duration, &y, &mut d);
    let lay = m.layout();
    let z = lay.z;
    let acc = (0..z).map(|j| d[lay.ball(j) + 5].abs()).fold(0.0, f64::max);
    let speed = (0..z)
        .map(|j| y[lay.ball(j) + 3].hypot(y[lay.ball(j) + 4]))
        .fold(0.0, f64::max);
    let (qi, qo) = m.contact_forces();
    (qi.to_vec(), qo.to_vec(), acc, speed)
}

#[test]
fn balls_started_from_l1_stay_put_at_zero_speed() {
    let bearing = Bearing::load("niu2014-table1").unwrap();
    for (fa, fr) in [(4000.0, 0.0), (4000.0, 1000.0)] {
        let (qi, qo, acc, speed) = run_static(fa, fr, 2e-3);
        let qs =
            load_distribution::solve(&bearing, &OperatingPoint::from_rpm(0.0, fa, fr)).unwrap();
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
        // Pure axial: the closed form Q = 530.86 N (docs/model.md#ref-quasi-static).
        if fr == 0.0 {
            assert!(qi.iter().all(|q| (q / 530.86 - 1.0).abs() < 0.01), "{qi:?}");
        }
        eprintln!("Fa {fa} Fr {fr}: |θ̈| ≤ {acc:.2e} rad/s², ball speed ≤ {speed:.2e} m/s");
        assert!(acc < 1.0, "|θ̈| = {acc} rad/s²");
        assert!(speed < 1e-3, "ball speed {speed} m/s");
    }
}

#[test]
fn cage_speed_between_pure_rolling_and_outer_race_control() {
    let sc = scene(9900.0, 4000.0, 1000.0);
    let mut sim = Simulation::new(&sc).unwrap();
    let (t_settle, t_end) = (4e-3, 10e-3);
    let mut speeds = Vec::new();
    sim.advance_sampled(t_end, 2e-5, &mut |t, o| {
        if t > t_settle {
            speeds.push(o[out::CAGE_SPEED]);
        }
    })
    .unwrap();
    let mean = speeds.iter().sum::<f64>() / speeds.len() as f64 / TAU;
    eprintln!("mean cage speed {mean:.3} Hz");
    // Pure rolling at α0 69.537 Hz (L0), outer-race control 70.42 Hz (L1), docs/model.md#ref-kinematics, #ref-quasi-static.
    assert!(mean > 69.537 && mean < 70.42, "cage speed {mean} Hz");
}

/// Samples (t, Q_i per ball, Q_o per ball) every `dt` up to `t_end`.
fn run(scene: &Scene, t_end: f64, dt: f64) -> (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let z = scene.bearing.bearing.z as usize;
    let mut sim = Simulation::new(scene).expect("builds");
    let (mut t, mut qi, mut qo) = (Vec::new(), vec![Vec::new(); z], vec![Vec::new(); z]);
    sim.advance_sampled(t_end, dt, &mut |ts, o| {
        t.push(ts);
        for j in 0..z {
            qi[j].push(o[out::CONTACT_START + j]);
            qo[j].push(o[out::CONTACT_START + z + j]);
        }
    })
    .expect("runs");
    (t, qi, qo)
}

#[test]
fn sec35_outer_bpfo_from_impact_spacing() {
    // Paper Sec. 3.5 (Fa 4000 N, Fr 1000 N, 9900 rpm, outer spall 1.0 × 0.2 mm at θ_d0 = π):
    // the BPFO from the mean interval between impacts lies between pure rolling (973.5 Hz) and
    // outer-race control (985.9 Hz), docs/model.md#ref-dynamic.
    let p =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/sec3.5-outer.toml");
    let mut sc = Scene::load(&p).unwrap();
    sc.fidelity = Fidelity::Reduced;
    let dt = 5e-6;
    let (t, _, qo) = run(&sc, 0.066, dt);
    // An impact event: some ball's outer contact opens (spall entry; a ball outside the spall
    // may dip deep under the ring's vibration, but its contact stays closed); its time is that
    // of the largest outer force of any ball within the next 150 µs (the trailing-edge impact).
    // One event per 0.5 ms (half the ball-pass interval): a neighbour that momentarily unloads
    // under the ring's response to the impact is not a second event, and neither is the
    // impacting ball's rattle (it was not in steady contact just before).
    let (skip, back, win, hold) = (0.02, 20, (150e-6 / dt) as usize, (0.5e-3 / dt) as usize);
    let mut impacts = Vec::new();
    let mut k = 2 * back;
    while k < t.len() {
        // Entry of a ball that was in contact (> 100 N) 100–200 µs earlier (not one that still
        // rattles after its own impact).
        let entry = t[k] > skip
            && qo
                .iter()
                .any(|q| q[k] == 0.0 && q[k - 2 * back..k - back].iter().all(|&v| v > 100.0));
        if entry {
            let hi = (k + win).min(t.len());
            let peak = |kk: usize| qo.iter().map(|q| q[kk]).fold(0.0, f64::max);
            let kmax = (k..hi)
                .max_by(|&a, &b| peak(a).total_cmp(&peak(b)))
                .unwrap();
            impacts.push(t[kmax]);
            k += hold;
        } else {
            k += 1;
        }
    }
    // No pass missed or doubled: every interval near the nominal 1.02 ms (the cage-less balls
    // are unevenly spaced, ±40 %).
    let gaps: Vec<f64> = impacts.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(
        gaps.iter().all(|&g| g > 0.5e-3 && g < 1.6e-3),
        "impact intervals {gaps:?}"
    );
    // Whole cage revolutions (z events: the same ball again) so that the uneven spacing cancels.
    let z = qo.len();
    let revs = (impacts.len() - 1) / z;
    assert!(revs >= 3, "{} impacts", impacts.len());
    let (n, span) = (revs * z, impacts[revs * z] - impacts[0]);
    let bpfo = n as f64 / span;
    eprintln!("BPFO {bpfo:.2} Hz from {n} impact intervals ({revs} cage revolutions)");
    assert!(bpfo > 973.5 && bpfo < 985.9, "BPFO {bpfo}");
}

#[test]
fn sec31_ball_flies_through_the_spall_and_hits_the_trailing_edge() {
    // Paper Sec. 3.1: Fa 3000 N, 10 000 rpm, outer spall 2.0 × 0.5 mm. Running load: L1 gives
    // Q_o = 417.6 N (docs/model.md#ref-quasi-static).
    let mut sc = scene(10_000.0, 3000.0, 0.0);
    sc.defect = Some(DefectSpec {
        ring: Race::Outer.into(),
        width: 2.0e-3,
        depth: 0.5e-3,
        theta0: 0.0,
    });
    let dt = 0.5e-6;
    let (t, qi, qo) = run(&sc, 0.9e-3, dt);
    let running = 417.6;
    let (j, k_entry) = (0..qo.len())
        .filter_map(|j| {
            (20..t.len())
                .find(|&k| qo[j][k] < 0.05 * running)
                .map(|k| (j, k))
        })
        .min_by_key(|&(_, k)| k)
        .expect("a ball enters the spall");
    let before = qo[j][k_entry.saturating_sub(40)];
    assert!(
        (before / running - 1.0).abs() < 0.15,
        "outer force before entry {before:.1} N"
    );
    let k_end = (k_entry + (150e-6 / dt) as usize).min(t.len());
    // Separation: the ball touches neither race for a while.
    let k_free = (k_entry..k_end)
        .find(|&k| qi[j][k] == 0.0 && qo[j][k] == 0.0)
        .expect("no contact-separation stage");
    let k_hit = (k_free..k_end)
        .find(|&k| qo[j][k] > 0.0)
        .expect("no trailing-edge impact before the pass ends");
    let peak = (k_hit..(k_hit + (40e-6 / dt) as usize).min(t.len()))
        .map(|k| qo[j][k])
        .fold(0.0, f64::max);
    eprintln!(
        "ball {j}: entry at {:.1} µs, free from {:.1} µs, outer impact from {:.1} µs, peak \
         {peak:.0} N ({:.1}x running load)",
        t[k_entry] * 1e6,
        t[k_free] * 1e6,
        t[k_hit] * 1e6,
        peak / running
    );
    assert!(t[k_hit] - t[k_free] > 20e-6, "no real flight");
    assert!(peak > 2.0 * running, "impact force {peak:.1} N");
    // After the impact the ball jumps between the races (as in the full model,
    // tests/full_spall.rs): within 250 µs inner-only and outer-only contact alternate.
    let k_hit_end = (k_hit + (40e-6 / dt) as usize).min(t.len());
    let k_after = (k_hit_end + (250e-6 / dt) as usize).min(t.len());
    let switches = inner_outer_alternations(&qi[j], &qo[j], k_hit_end, k_after);
    eprintln!("after the impact: {switches} switches between inner-only and outer-only contact");
    assert!(
        switches >= 3,
        "the ball does not bounce between the races ({switches})"
    );
}

#[test]
fn cage_follows_a_speed_step() {
    let sc = scene(9900.0, 4000.0, 1000.0);
    let mut sim = Simulation::new(&sc).unwrap();
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
    eprintln!("cage after the step {mean:.3} Hz");
    // 10 % faster shaft: between 1.1 × pure rolling and 1.1 × outer-race control.
    assert!(mean > 1.1 * 69.537 && mean < 1.1 * 70.42 * 1.005, "{mean}");
}

#[test]
fn inner_spall_turns_with_the_shaft_and_is_hit() {
    // Sec. 3.1 conditions with the spall on the inner ring at θ_d0 = 0: it turns at Ω while the
    // balls orbit at ≈ 0.43 Ω, so it meets a ball within 2π/14/(0.57 Ω) ≈ 0.75 ms; the ball loses
    // its inner contact and is hit by the edge with a multiple of the running inner load
    // (368.3 N, docs/model.md#ref-quasi-static), while its outer contact is not the spalled one.
    let mut sc = scene(10_000.0, 3000.0, 0.0);
    sc.defect = Some(DefectSpec {
        ring: Race::Inner.into(),
        width: 2.0e-3,
        depth: 0.5e-3,
        theta0: 0.0,
    });
    let dt = 0.5e-6;
    let (t, qi, qo) = run(&sc, 1.0e-3, dt);
    let running = 368.3;
    let (j, k_entry) = (0..qi.len())
        .filter_map(|j| {
            (20..t.len())
                .find(|&k| qi[j][k] < 0.05 * running)
                .map(|k| (j, k))
        })
        .min_by_key(|&(_, k)| k)
        .expect("a ball meets the inner spall");
    assert!(t[k_entry] < 0.8e-3, "first entry at {} s", t[k_entry]);
    let k_end = (k_entry + (150e-6 / dt) as usize).min(t.len());
    let peak = (k_entry..k_end).map(|k| qi[j][k]).fold(0.0, f64::max);
    eprintln!(
        "inner spall: ball {j} enters at {:.1} µs, inner impact {peak:.0} N",
        t[k_entry] * 1e6
    );
    assert!(peak > 2.0 * running, "inner impact {peak:.1} N");
    assert!(qo[j][k_entry] > 0.0);
}
