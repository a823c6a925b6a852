//! The cage of the reduced and full levels (docs/model.md#cage): the pocket force of a
//! constructed state against a hand computation, the derived constants (docs/model.md#cage-defaults)
//! and the presets that write them out, energy conservation with the cage's pockets and lands
//! (frictionless and undamped), caged runs on a partial load zone in which the balls never
//! come near each other and the pockets carry the cage, and the `[cage]` errors that name
//! their key.

use raceway::models::internals::cage::{self, Cage, CageParams, CagePose};
use raceway::models::internals::layout::{Layout, BR, BTH, BVR, BVX, BW, BX, CA, CV, CW, CY};
use raceway::models::{FullModel, FullOptions, Model, ModelSystem};
use raceway::solver::{Integrator, Method, Options, StepView};
use raceway::{
    out, Bearing, BearingFile, CageGuidance, CageSection, Fidelity, OperatingPoint, Scene,
    Simulation,
};
use std::f64::consts::{PI, TAU};

fn table1() -> BearingFile {
    BearingFile::load("niu2014-table1").unwrap()
}

/// e_r(θ) and e_θ(θ) of docs/model.md#frames.
fn er(t: f64) -> [f64; 3] {
    [0.0, -t.sin(), t.cos()]
}
fn et(t: f64) -> [f64; 3] {
    [0.0, -t.cos(), -t.sin()]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The ball's offset from its pocket's centre plane computed as an angle: ρ sin(θ_q − φ) with
/// θ_q the ball's azimuth about the cage's centre (docs/model.md#c1: θ = atan2(−y, z)).
fn offset_by_angle(p: [f64; 3], c: [f64; 3], phi: f64) -> f64 {
    let (qy, qz) = (p[1] - c[1], p[2] - c[2]);
    let rho = qy.hypot(qz);
    rho * ((-qy).atan2(qz) - phi).sin()
}

#[test]
fn pocket_force_of_a_constructed_state_is_the_hand_computed_one() {
    // A Table-1 bearing with explicit pocket constants; one ball pressed 3 µm into the leading
    // face of pocket 0 of a moving, turning, displaced cage.
    let mut file = table1();
    file.cage = CageSection {
        pocket_clearance: Some(0.25e-3),
        pocket_stiffness: Some(2.0e10),
        pocket_damping: Some(15.0),
        pocket_friction: Some(0.1),
        ..CageSection::default()
    };
    let b = Bearing::new(&file).unwrap();
    let cage = Cage::new(&b);
    let pose = CagePose {
        angle: 0.3,
        c: [0.0, 12e-6, -20e-6],
        w: 440.0,
        v: [0.0, 0.01, -0.02],
    };
    let (rho, u, x) = (35.0e-3, 0.125e-3 + 3e-6, 0.1e-3);
    let (phi, er0, et0) = (pose.angle, er(pose.angle), et(pose.angle));
    let p = [
        x,
        pose.c[1] + rho * er0[1] + u * et0[1],
        pose.c[2] + rho * er0[2] + u * et0[2],
    ];
    // Moving with the pocket (ω_c ρ along e_θ, the cage's translation), closing on the face
    // at 2 cm/s and drifting outwards at 1 cm/s, 5 cm/s axially.
    let v: [f64; 3] = std::array::from_fn(|k| {
        [0.05, 0.0, 0.0][k] + pose.v[k] + (pose.w * rho + 0.02) * et0[k] + 0.01 * er0[k]
    });
    let omega = [900.0, 2500.0, -700.0];
    let pc = cage.pocket(&pose, phi, p, v, omega);

    // By hand: the overlap from the angle, its rate by a central difference of that offset
    // along the motion of the ball and of the cage (centre and angle).
    let offset = offset_by_angle(p, pose.c, phi);
    let delta = offset - 0.125e-3;
    assert!((delta - 3e-6).abs() < 1e-12, "δ = {delta:e}");
    let h = 1e-9;
    let at = |s: f64| {
        let pp = [p[0] + v[0] * s, p[1] + v[1] * s, p[2] + v[2] * s];
        let cc = [0.0, pose.c[1] + pose.v[1] * s, pose.c[2] + pose.v[2] * s];
        offset_by_angle(pp, cc, phi + pose.w * s)
    };
    let rate = (at(h) - at(-h)) / (2.0 * h);
    let p_hand = 2.0e10 * delta.powf(1.5) + 15.0 * rate;
    assert!(
        (pc.p / p_hand - 1.0).abs() < 1e-6,
        "P = {} N, by hand {p_hand} N (δ̇ = {rate} m/s)",
        pc.p
    );
    assert!(p_hand > 1.0, "the constructed contact carries {p_hand} N");
    // Normal force on the ball against the face: −P e_θ(φ) (the ball is ahead of the centre).
    // Friction: μ P against the slip of the ball's surface at r_b + R e_θ(φ) over the face's
    // point along the face in the radial plane (here far beyond the rounding speed of 0.01 m/s).
    let r_cp = [0.0, b.ball_radius() * et0[1], b.ball_radius() * et0[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let surf = cross(omega, r_cp);
    let point = [p[0] + r_cp[0], p[1] + r_cp[1], p[2] + r_cp[2]];
    let face = [
        pose.v[0],
        pose.v[1] - pose.w * (point[2] - pose.c[2]),
        pose.v[2] + pose.w * (point[1] - pose.c[1]),
    ];
    let rel: Vec<f64> = (0..3).map(|k| v[k] + surf[k] - face[k]).collect();
    let rel = [rel[0], rel[1], rel[2]];
    // The slip along the wall in the radial plane (the cage has no axial freedom): along e_r
    // for the face normal e_θ.
    let sr = dot(rel, er0);
    let slip = [0.0, sr * er0[1], sr * er0[2]];
    let s = sr.abs();
    assert!(s > 1.0, "slip {s} m/s");
    for k in 0..3 {
        let f = -pc.p * et0[k] - 0.1 * pc.p * slip[k] / (s * s + 1e-4).sqrt();
        assert!(
            (pc.f[k] - f).abs() < 1e-9 * pc.p,
            "force component {k}: {} vs {f}",
            pc.f[k]
        );
    }
    // Free in the pocket: no force.
    let inside = [p[0], p[1] - 10e-6 * et0[1], p[2] - 10e-6 * et0[2]];
    assert_eq!(cage.pocket(&pose, phi, inside, v, omega).p, 0.0);
}

#[test]
fn pocket_force_in_the_full_model_is_the_hand_computed_one() {
    // The hand computation on the full model's own state: ball 4 moved forward in its pocket
    // until its offset along the orbit is c_p/2 + 2 µm (the ball-riding pocket adds its radial
    // offset of a few µm); the model's pocket force after one right-hand side against
    // K δ^{3/2} + c δ̇ from the state.
    let mut sc = Scene::healthy(table1(), OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0));
    sc.fidelity = Fidelity::Full;
    let b = Bearing::new(&sc.bearing).unwrap();
    let mut m = FullModel::new(&sc, &b, &sc.operating).unwrap();
    let lay = m.layout();
    assert!(lay.cage && m.has_cage());
    let mut y = vec![0.0; m.dim()];
    m.initial_state(&mut y);
    let params = CageParams::of(&b);
    let j = 3;
    let c = lay.cage_block();
    let centre = [0.0, y[c + CY], y[c + CY + 1]];
    let phi = y[lay.psi()] + y[c + CA] + TAU * j as f64 / 14.0;
    let ball = |y: &[f64]| {
        let bj = lay.ball(j);
        let theta = y[lay.psi()] + TAU * j as f64 / 14.0 + y[bj + BTH];
        let r = 0.5 * b.dm + y[bj + BR];
        ([y[bj + BX], r * er(theta)[1], r * er(theta)[2]], theta, r)
    };
    // Move the ball along its orbit until the offset is c_p/2 + 2 µm (Newton on θ).
    let target = 0.5 * params.pocket_clearance + 2e-6;
    for _ in 0..20 {
        let (p, _, r) = ball(&y);
        let g = offset_by_angle(p, centre, phi) - target;
        y[lay.ball(j) + BTH] -= g / r;
    }
    let (p, theta, r) = ball(&y);
    // The ball-riding pocket's offsets: along the orbit (from the angle) and radially (the
    // distance from the cage's centre less dm/2).
    let u = offset_by_angle(p, centre, phi);
    let q = [p[0], p[1] - centre[1], p[2] - centre[2]];
    let w = q[1].hypot(q[2]) * ((-q[1]).atan2(q[2]) - phi).cos() - 0.5 * b.dm;
    let len = u.hypot(w);
    let delta = len - 0.5 * params.pocket_clearance;
    assert!(
        (u - target).abs() < 1e-13 && w.abs() < 20e-6,
        "u {u:e}, w {w:e}"
    );
    // Its approach: the ball's velocity along e_θ(φ) less the cage's, less ω_c times the
    // radial distance (docs/model.md#cage), from the states.
    let bj = lay.ball(j);
    let vb: Vec<f64> = (0..3)
        .map(|k| {
            [y[bj + BVX], 0.0, 0.0][k] + y[bj + BVR] * er(theta)[k] + r * y[bj + BW] * et(theta)[k]
        })
        .collect();
    let vc = [0.0, y[c + CV], y[c + CV + 1]];
    let dv = [vb[0], vb[1] - vc[1], vb[2] - vc[2]];
    let u_rate = dot(dv, et(phi)) - y[c + CW] * dot(q, er(phi));
    let w_rate = dot(dv, er(phi)) + y[c + CW] * dot(q, et(phi));
    let rate = (u * u_rate + w * w_rate) / len;
    let p_hand = params.pocket_stiffness * delta.powf(1.5) + params.pocket_damping * rate;
    let mut d = vec![0.0; m.dim()];
    m.update_mode(0.0, &y);
    m.rhs(0.0, &y, &mut d);
    let pc = m.core().cage().unwrap().pockets[j];
    eprintln!("P = {} N by the model, {p_hand} N by hand", pc.p);
    assert!((pc.p / p_hand - 1.0).abs() < 1e-9, "{} vs {p_hand}", pc.p);
    // The other balls sit free in their pockets.
    for (k, other) in m.core().cage().unwrap().pockets.iter().enumerate() {
        assert!(k == j || other.p == 0.0, "ball {k}: {}", other.p);
    }
    // The outputs carry it, signed (the ball presses the leading face: > 0).
    let mut o = vec![0.0; raceway::output_table_with_cage(14).len()];
    m.outputs(0.0, &y, &mut o);
    assert_eq!(o[out::pocket_force(14, j)], pc.p);
    assert_eq!(o[out::CAGE_SPEED], y[c + CW]);
    assert_eq!(
        (o[out::cage_y(14)], o[out::cage_z(14)]),
        (centre[1], centre[2])
    );
}

#[test]
fn derived_pocket_stiffness_agrees_with_hamrock_brewe() {
    // The ball in its cylindrical brass pocket: curvature sums 2/D and 2/D − 2/(D + c_p); the
    // exact Hertz constant against the Hamrock–Brewe fits (within their few per cent).
    let b = Bearing::new(&table1()).unwrap();
    let d = b.d;
    let cp = 0.02 * d;
    let k = cage::pocket_stiffness(d, cp, 208e9, 0.3, 105e9, 0.34);
    let (s1, s2) = (2.0 / d, 2.0 / d - 2.0 / (d + cp));
    let ratio = s1 / s2;
    let kappa = 1.0339 * ratio.powf(0.636);
    let e = 1.0003 + 0.5968 / ratio;
    let f = 1.5277 + 0.6023 * ratio.ln();
    let e_star = 1.0 / ((1.0 - 0.09) / 208e9 + (1.0 - 0.34 * 0.34) / 105e9);
    let k_hb = PI * kappa * 2.0 * e_star * (2.0 * e / (s1 + s2) / (9.0 * f.powi(3))).sqrt();
    eprintln!("pocket K exact {k:.4e}, Hamrock–Brewe {k_hb:.4e}");
    assert!((k / k_hb - 1.0).abs() < 0.05, "{k:e} vs {k_hb:e}");
}

#[test]
fn presets_write_out_the_derived_cage() {
    for (name, _) in raceway::PRESETS {
        let file = BearingFile::load(name).unwrap();
        assert!(!file.cage.is_empty(), "{name} has a [cage] section");
        let written = CageParams::of(&Bearing::new(&file).unwrap());
        let mut bare = file.clone();
        bare.cage = CageSection::default();
        let derived = CageParams::of(&Bearing::new(&bare).unwrap());
        let b = Bearing::new(&bare).unwrap();
        assert!((derived.mass / (0.3 * b.z as f64 * b.ball_mass) - 1.0).abs() < 1e-12);
        assert!((derived.pocket_clearance / (0.02 * b.d) - 1.0).abs() < 1e-12);
        assert_eq!(derived.guidance, CageGuidance::Balls);
        for (what, a, c) in [
            ("mass", written.mass, derived.mass),
            ("inertia", written.inertia, derived.inertia),
            (
                "pocket_clearance",
                written.pocket_clearance,
                derived.pocket_clearance,
            ),
            (
                "pocket_stiffness",
                written.pocket_stiffness,
                derived.pocket_stiffness,
            ),
            (
                "pocket_damping",
                written.pocket_damping,
                derived.pocket_damping,
            ),
            (
                "pocket_friction",
                written.pocket_friction,
                derived.pocket_friction,
            ),
        ] {
            assert!(
                (a / c - 1.0).abs() < 1e-3,
                "{name}: {what} {a} vs derived {c}"
            );
        }
    }
}

/// Energy over a run of the frictionless, undamped bearing (traction off, c_br = 0, pedestal
/// undamped, pocket and land damping and friction 0) with a cage of `guidance` kicked by `kick`
/// (added to the start's cage rate, y and z velocities): the largest deviation of the model's
/// energy, the kinetic energy of the kick, and the deepest pocket and land overlaps met
/// (computed here from the states).
fn caged_energy(guidance: CageGuidance, kick: [f64; 3], duration: f64) -> (f64, f64, f64, f64) {
    let mut file = table1();
    file.contact.c_br = 0.0;
    file.pedestal.c_y = 0.0;
    file.pedestal.c_z = 0.0;
    file.cage = CageSection {
        pocket_damping: Some(0.0),
        pocket_friction: Some(0.0),
        guidance,
        ..CageSection::default()
    };
    if guidance != CageGuidance::Balls {
        file.cage.land_damping = Some(0.0);
        file.cage.land_friction = Some(0.0);
    }
    let mut sc = Scene::healthy(file, OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0));
    sc.fidelity = Fidelity::Full;
    let b = Bearing::new(&sc.bearing).unwrap();
    let options = FullOptions {
        traction: false,
        ..FullOptions::default()
    };
    let mut m = FullModel::with_options(&sc, &b, &sc.operating, options).unwrap();
    let lay = m.layout();
    let params = CageParams::of(&b);
    let n = m.dim();
    let mut y0 = vec![0.0; n];
    m.initial_state(&mut y0);
    let c = lay.cage_block();
    y0[c + CW] += kick[0];
    y0[c + CV] += kick[1];
    y0[c + CV + 1] += kick[2];
    // The energy of the kick relative to the balls (what the impacts exchange).
    let ke = 0.5 * params.inertia * kick[0] * kick[0]
        + 0.5 * params.mass * (kick[1] * kick[1] + kick[2] * kick[2]);
    m.update_mode(0.0, &y0);
    let mut nominal = vec![0.0; n];
    m.nominal(&mut nominal);
    let rtol = 1e-9;
    let atol = nominal.iter().map(|v| v * rtol).collect();
    let mut integ = Integrator::new(Options::new(Method::Dop853, rtol, atol), 0.0, &y0).unwrap();
    let e0 = m.energy(&y0);
    let (mut dev, mut pocket, mut land): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let mut buf = vec![0.0; n];
    let depth = |y: &[f64], pocket: &mut f64, land: &mut f64| {
        let centre = [0.0, y[c + CY], y[c + CY + 1]];
        for j in 0..14 {
            let bj = lay.ball(j);
            let theta = y[lay.psi()] + TAU * j as f64 / 14.0 + y[bj + BTH];
            let r = 0.5 * b.dm + y[bj + BR];
            let p = [0.0, r * er(theta)[1], r * er(theta)[2]];
            let phi = y[lay.psi()] + y[c + CA] + TAU * j as f64 / 14.0;
            let u = offset_by_angle(p, centre, phi);
            *pocket = pocket.max(u.abs() - 0.5 * params.pocket_clearance);
        }
        let ring = match guidance {
            CageGuidance::InnerLand => [y[lay.ring() + 1], y[lay.ring() + 2]],
            _ => [y[lay.pedestal()], y[lay.pedestal() + 1]],
        };
        let e = (centre[1] - ring[0]).hypot(centre[2] - ring[1]);
        *land = land.max(e - params.land_clearance);
    };
    let spans = 40;
    for k in 1..=spans {
        let mut obs = |s: &StepView| {
            for i in 1..=4 {
                s.interpolate(
                    s.t_start() + (s.t_end() - s.t_start()) * i as f64 / 4.0,
                    &mut buf,
                );
                depth(&buf, &mut pocket, &mut land);
            }
        };
        integ
            .advance(
                &mut ModelSystem(&mut m),
                duration * k as f64 / spans as f64,
                Some(&mut obs),
            )
            .unwrap();
        dev = dev.max((m.energy(integ.y()) - e0).abs());
    }
    (dev, ke, pocket, land)
}

#[test]
fn energy_is_conserved_with_a_frictionless_undamped_cage() {
    // Balls guidance, the cage turning 5 rad/s faster than the balls: it strikes the pockets
    // (the balls' share of the clearance, 127 µm, in about 1 ms) and rattles between them.
    let (dev, ke, pocket, _) = caged_energy(CageGuidance::Balls, [5.0, 0.0, 0.0], 6e-3);
    eprintln!(
        "balls: energy deviation {dev:.3e} J, kick {ke:.3e} J, pocket overlap {pocket:.3e} m"
    );
    assert!(
        pocket > 1e-7,
        "the pockets were never struck ({pocket:e} m)"
    );
    assert!(
        dev < 1e-4 * ke,
        "energy deviation {dev:e} J against the kick {ke:e} J"
    );
    // Outer and inner land: the cage thrown sideways at 0.1 m/s hits the land (63.5 µm away).
    for g in [CageGuidance::OuterLand, CageGuidance::InnerLand] {
        let (dev, ke, _, land) = caged_energy(g, [0.0, 0.1, 0.05], 4e-3);
        eprintln!(
            "{g:?}: energy deviation {dev:.3e} J, kick {ke:.3e} J, land overlap {land:.3e} m"
        );
        assert!(
            land > 1e-8,
            "{g:?}: the land was never touched ({land:e} m)"
        );
        assert!(
            dev < 1e-3 * ke,
            "{g:?}: energy deviation {dev:e} J against the kick {ke:e} J"
        );
    }
}

/// Samples of a caged run (through `Simulation`, events and all): every 20 µs the smallest
/// centre distance of neighbouring balls minus D (from the states), and the outputs; also the
/// largest eccentricity of the cage about the outer ring's centre.
fn caged_run(level: Fidelity, duration: f64) -> (f64, Vec<Vec<f64>>) {
    caged_run_guided(level, duration, CageGuidance::Balls).0
}

fn caged_run_guided(
    level: Fidelity,
    duration: f64,
    guidance: CageGuidance,
) -> ((f64, Vec<Vec<f64>>), f64) {
    // The partial load zone of the Table-1 bearing: Fa 1000 N, Fr 4000 N, 9900 rpm.
    let mut file = table1();
    file.cage.guidance = guidance;
    let mut sc = Scene::healthy(file, OperatingPoint::from_rpm(9900.0, 1000.0, 4000.0));
    sc.fidelity = level;
    let b = Bearing::new(&sc.bearing).unwrap();
    let mut sim = Simulation::new(&sc).unwrap();
    let lay = match level {
        Fidelity::Full => Layout::full(14),
        _ => Layout::reduced(14),
    }
    .with_cage(true);
    assert_eq!(sim.state_dim(), lay.dim());
    let gap = |y: &[f64]| {
        let pos = |j: usize| {
            let bj = lay.ball(j);
            let theta = y[lay.psi()] + TAU * j as f64 / 14.0 + y[bj + BTH];
            let r = 0.5 * b.dm + y[bj + BR];
            [y[bj + BX], r * er(theta)[1], r * er(theta)[2]]
        };
        (0..14)
            .map(|j| {
                let (a, c) = (pos(j), pos((j + 1) % 14));
                ((c[0] - a[0]).powi(2) + (c[1] - a[1]).powi(2) + (c[2] - a[2]).powi(2)).sqrt() - b.d
            })
            .fold(f64::INFINITY, f64::min)
    };
    let mut min_gap = gap(sim.state());
    let mut rows = Vec::new();
    let mut eccentricity: f64 = 0.0;
    let dt = 20e-6;
    let steps = (duration / dt).round() as usize;
    let mut o = vec![0.0; sim.output_table().len()];
    for k in 1..=steps {
        sim.advance(dt * k as f64).unwrap();
        let y = sim.state();
        min_gap = min_gap.min(gap(y));
        let (c, p) = (lay.cage_block(), lay.pedestal());
        eccentricity = eccentricity.max((y[c + CY] - y[p]).hypot(y[c + CY + 1] - y[p + 1]));
        sim.outputs(&mut o);
        rows.push(o.clone());
    }
    ((min_gap, rows), eccentricity)
}

#[test]
fn caged_balls_never_come_near_each_other_on_a_partial_load_zone() {
    // Fa 1000 N, Fr 4000 N: a partial load zone, where the cage-less balls drift (the long run
    // of docs/research/cage.md). With the cage the balls keep their spacing within the pocket
    // clearance, the pockets carry the cage (forces on both faces) and the cage turns between
    // pure rolling and outer-race control.
    for (level, duration) in [(Fidelity::Reduced, 0.04), (Fidelity::Full, 0.03)] {
        let (min_gap, rows) = caged_run(level, duration);
        let spacing = 70e-3 * (PI / 14.0).sin() - 12.7e-3;
        let cp = 0.02 * 12.7e-3;
        eprintln!(
            "{level:?}: smallest gap {:.4} mm of {:.4} mm at even spacing",
            min_gap * 1e3,
            spacing * 1e3
        );
        // Two neighbours can each sit c_p/2 towards the other (plus the cage's own offset).
        assert!(min_gap > spacing - 3.0 * cp, "{level:?}: gap {min_gap:e} m");
        let pockets = |sign: f64| {
            rows.iter()
                .flat_map(|o| (0..14).map(move |j| o[out::pocket_force(14, j)]))
                .filter(|p| p * sign > 0.0)
                .count()
        };
        assert!(
            pockets(1.0) > 0 && pockets(-1.0) > 0,
            "{level:?}: the pockets are idle"
        );
        let half = rows.len() / 2;
        let cage_hz = rows[half..].iter().map(|o| o[out::CAGE_SPEED]).sum::<f64>()
            / (rows.len() - half) as f64
            / TAU;
        eprintln!("{level:?}: cage {cage_hz:.3} Hz");
        // The partial load zone brakes the cage: the unloaded balls, pressed on the outer race
        // by their centrifugal force, hold it back below pure rolling (cage slip), but not by
        // more than a few per cent in this short run.
        assert!(
            cage_hz > 65.0 && cage_hz < 71.0,
            "{level:?}: cage {cage_hz} Hz"
        );
    }
}

#[test]
fn an_outer_land_guides_the_cage_and_the_balls_keep_apart() {
    // The same partial load zone with the cage riding on the outer ring's land (radial
    // clearance c_p/4 = 63.5 µm): the cage's eccentricity about the outer ring reaches the land
    // and stays within its clearance plus the land contact's elastic overlap, the balls apart,
    // the pockets loaded.
    let ((min_gap, rows), ecc) = caged_run_guided(Fidelity::Reduced, 0.03, CageGuidance::OuterLand);
    let params = CageParams::of(&Bearing::new(&table1()).unwrap());
    eprintln!(
        "outer land: smallest gap {:.4} mm, largest eccentricity {:.2} µm (land clearance {:.2} µm)",
        min_gap * 1e3,
        ecc * 1e6,
        params.land_clearance * 1e6
    );
    assert!(min_gap > 70e-3 * (PI / 14.0).sin() - 12.7e-3 - 3.0 * 0.02 * 12.7e-3);
    // The land is reached (the cage does not float in the middle) and holds it.
    assert!(ecc > 0.5 * params.land_clearance, "eccentricity {ecc:e} m");
    // (The land-guided pockets are cylinders that leave the cage free radially: only the land
    // holds it, within its clearance plus the contact's overlap of a few µm under the pocket
    // forces of the load zone.)
    assert!(
        ecc < params.land_clearance + 10e-6,
        "eccentricity {ecc:e} m"
    );
    assert!(rows
        .iter()
        .any(|o| (0..14).any(|j| o[out::pocket_force(14, j)] != 0.0)));
}

/// The preset's text with its `[cage]` section replaced by `section` (TOML lines).
fn with_cage(section: &str) -> String {
    let text = raceway::PRESETS
        .iter()
        .find(|(n, _)| *n == "niu2014-table1")
        .unwrap()
        .1;
    let start = text.find("\n[cage]").unwrap();
    format!("{}\n[cage]\n{section}\n", &text[..start])
}

#[test]
fn cage_section_errors_name_their_key() {
    let cases: &[(&str, &str, &str)] = &[
        ("mass = -0.01", "cage.mass", "must be > 0"),
        ("inertia = 0.0", "cage.inertia", "must be > 0"),
        (
            "youngs_modulus = -1.0",
            "cage.youngs_modulus",
            "must be > 0",
        ),
        ("poisson = 0.7", "cage.poisson", "(−1, 0.5)"),
        (
            "pocket_clearance = 0.0",
            "cage.pocket_clearance",
            "must be > 0",
        ),
        (
            "pocket_clearance = 3.0e-3",
            "cage.pocket_clearance",
            "leaves no web",
        ),
        (
            "pocket_stiffness = 0.0",
            "cage.pocket_stiffness",
            "must be > 0",
        ),
        (
            "pocket_damping = -1.0",
            "cage.pocket_damping",
            "must be ≥ 0",
        ),
        (
            "pocket_friction = 1.5",
            "cage.pocket_friction",
            "not a lubricated",
        ),
        (
            "land_clearance = 1e-4",
            "cage.land_clearance",
            "land-guided cage only",
        ),
        (
            "guidance = \"balls\"\nland_friction = 0.1",
            "cage.land_friction",
            "land-guided cage only",
        ),
        (
            "guidance = \"outer_land\"\nland_radius = 0.03",
            "cage.land_radius",
            "outside the pitch circle",
        ),
        (
            "guidance = \"inner_land\"\nland_radius = 0.04",
            "cage.land_radius",
            "inside the pitch circle",
        ),
        (
            "guidance = \"outer_land\"\nland_clearance = -1e-5",
            "cage.land_clearance",
            "must be > 0",
        ),
        (
            "guidance = \"outer_land\"\nland_stiffness = 0.0",
            "cage.land_stiffness",
            "must be > 0",
        ),
        (
            "guidance = \"outer_land\"\nland_damping = -2.0",
            "cage.land_damping",
            "must be ≥ 0",
        ),
        (
            "guidance = \"outer_land\"\nland_friction = 2.0",
            "cage.land_friction",
            "not a lubricated",
        ),
        (
            "guidance = \"sideways\"",
            "cage.guidance",
            "unknown variant",
        ),
        ("colour = \"yellow\"", "cage.colour", "unknown field"),
        ("mass = \"heavy\"", "cage.mass", "invalid type"),
    ];
    for (section, field, words) in cases {
        match BearingFile::from_toml_str(&with_cage(section), "t") {
            Ok(_) => panic!("[cage] {section}: accepted"),
            Err(e) => {
                assert_eq!(e.field, *field, "[cage] {section}: {e}");
                assert!(e.to_string().contains(words), "[cage] {section}: {e}");
            }
        }
    }
    // Valid: land guidance with its keys, and an empty section (everything derived).
    for ok in [
        "guidance = \"outer_land\"\nland_clearance = 5e-5\nland_radius = 0.039\nland_friction = 0.05",
        "guidance = \"inner_land\"",
        "",
    ] {
        BearingFile::from_toml_str(&with_cage(ok), "t").unwrap_or_else(|e| panic!("{ok}: {e}"));
    }
}

#[test]
fn the_scene_switches_the_cage_and_its_outputs() {
    // [full] cage: on by default at the reduced and full levels (the cage block in the outputs),
    // off in the paper's scenes; the other levels never have one.
    let sc = Scene::default_scene();
    assert!(sc.full.cage);
    for (level, cage) in [
        (Fidelity::Lumped, false),
        (Fidelity::Reduced, true),
        (Fidelity::Full, true),
    ] {
        let mut s = sc.clone();
        s.fidelity = level;
        let sim = Simulation::new(&s).unwrap();
        let names: Vec<String> = sim.output_table().into_iter().map(|o| o.name).collect();
        assert_eq!(names.iter().any(|n| n == "cage.y"), cage, "{level:?}");
        assert_eq!(
            names.iter().any(|n| n == "cage.pocket.P[14]"),
            cage,
            "{level:?}"
        );
    }
    for name in [
        "sec3.5-outer",
        "sec3.5-inner",
        "sec3.5-outer-full",
        "sec3.1-outer-full",
        "sec3.4-deep-groove-full",
        "impact-test-fa3000",
        "impact-test-fa4000",
        "impact-test-fa5000",
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(format!("examples/scenes/{name}.toml"));
        let s = Scene::load(&path).unwrap();
        assert!(
            !s.full.cage,
            "{name}: the paper's scenes run without a cage"
        );
    }
    let bad = Scene::from_toml_str(
        "[operating]\nspeed_rpm = 9900.0\n[full]\ncage = \"yes\"\n",
        "t",
        None,
    );
    assert!(bad.unwrap_err().to_string().contains("cage"));
}

#[test]
fn sweeps_switch_the_cage_by_full_cage() {
    // `full.cage` in [set] or on an axis: true/false (or 1/0); another word is a sweep-file
    // error naming the key. The sweeps that reproduce the paper set it false.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sweeps");
    let text = "name = \"t\"\nbase = \"../scenes/default.toml\"\n[set]\n\"full.cage\" = false\n\
                [axes]\n\"fidelity\" = [\"reduced\", \"full\"]\n";
    let sweep = raceway::sweep::Sweep::from_toml_str(text, "t", &dir).unwrap();
    for run in sweep.runs() {
        let (scene, _) = sweep.scene_for(&run).unwrap();
        assert!(!scene.full.cage, "{}", run.id);
    }
    let text =
        "name = \"t\"\nbase = \"../scenes/default.toml\"\n[axes]\n\"full.cage\" = [0, true]\n";
    let sweep = raceway::sweep::Sweep::from_toml_str(text, "t", &dir).unwrap();
    let cages: Vec<bool> = sweep
        .runs()
        .iter()
        .map(|r| sweep.scene_for(r).unwrap().0.full.cage)
        .collect();
    assert_eq!(cages, [false, true]);
    let bad = "name = \"t\"\nbase = \"../scenes/default.toml\"\n[set]\n\"full.cage\" = \"maybe\"\n";
    let e = raceway::sweep::Sweep::from_toml_str(bad, "t", &dir).unwrap_err();
    assert!(e.to_string().contains("full.cage"), "{e}");
    for name in [
        "sec3.2-speed",
        "sec3.3-width",
        "sec3.3-width-blend",
        "sec3.4-position",
        "sec3.4-position-blend",
        "sec3.4-speed-position",
    ] {
        let sweep = raceway::sweep::Sweep::load(&dir.join(format!("{name}.toml"))).unwrap();
        for run in sweep.runs() {
            assert!(!sweep.scene_for(&run).unwrap().0.full.cage, "{name}");
        }
    }
}
