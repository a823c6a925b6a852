//! T7 (docs/model.md#coupling-stability): a bearing `Simulation` in coupling mode
//! "motion" coupled to a 1-DOF rotor by a master loop; the observed stability boundary of the
//! constant-force (zero-order-hold) Jacobi coupling against ωH = 4ζ, and the interface-Jacobian
//! (linearly implicit) coupling stable far beyond it.
//!
//! Theory (which ζ enters). Rotor: M z̈ + c_r ż = f_ext + F, bearing reaction F ≈ F₀ − k (z − z₀)
//! − c_c ż (k = −∂F_z/∂z, c_c = −∂F_z/∂v_z from the bearing's directional derivatives). With F
//! held at F_k = F(z_k, v_k) over [t_k, t_k + H] and the rotor integrated exactly, the one-step
//! map of (z, v) has
//!
//! ```text
//!   det A = 1 − (a_r + a_c) H + ω² H²/2 + O(H³),     a_r = c_r/M, a_c = c_c/M, ω² = k/M,
//! ```
//!
//! (exact for a_r = 0: det A = 1 − a_c H + ω²H²/2). The oscillatory pair has |λ|² = det A, so the
//! coupling is stable iff (a_r + a_c) > ω² H/2, i.e. **ωH < 4ζ with ζ = (c_r + c_c)/(2Mω)**: the
//! rotor's own damping (integrated exactly inside the rotor) and the contact damping (sampled
//! with the force) enter alike to first order in ωH; without any damping every H is unstable.
//! The held stiffness force injects energy ≈ ω²H/4 per unit time and unit energy; damping
//! removes 2ζω.
//!
//! Set-up: the default bearing at zero speed (constant stiffness: no ball passage modulation)
//! under Fa = 4000 N, Fr = 1000 N, a rotor of M = 2 kg moving in z only (x, y held at the
//! equilibrium), rotor damping ζ_r = 0.02, and a stiff, heavy pedestal (so that the rotor sees
//! the bearing alone: k_p = 1e13 N/m, m_p = 1000 kg, ω_p = 1e5 rad/s ≫ ω).
#![allow(clippy::needless_range_loop)] // 3×3 index arithmetic reads best with indices

use raceway::{out, CouplingMode, Journal, Scene, Simulation};

const M: f64 = 2.0;
const ZETA_ROTOR: f64 = 0.02;
const F_EXT: f64 = -1000.0; // the radial load the rotor carries (load.Fz of the scene)

fn scene() -> Scene {
    let mut s = Scene::default_scene();
    s.coupling = CouplingMode::Motion;
    s.defect = None;
    s.operating.shaft_speed = raceway::rpm_to_rad_s(0.0);
    let p = &mut s.bearing.pedestal;
    p.mass = 1000.0;
    p.k_y = 1e13;
    p.k_z = 1e13;
    p.c_y = 2e6;
    p.c_z = 2e6;
    s
}

/// exp(A) of a 3×3 matrix (scaling and squaring with a Taylor series).
fn expm3(a: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let norm = a
        .iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let s = (norm / 0.25).log2().ceil().max(0.0) as i32;
    let scale = 0.5_f64.powi(s);
    let mul = |x: &[[f64; 3]; 3], y: &[[f64; 3]; 3]| {
        let mut r = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                r[i][j] = (0..3).map(|k| x[i][k] * y[k][j]).sum();
            }
        }
        r
    };
    let b = a.map(|r| r.map(|v| v * scale));
    let mut e = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut term = e;
    for n in 1..=16 {
        term = mul(&term, &b).map(|r| r.map(|v| v / n as f64));
        for i in 0..3 {
            for j in 0..3 {
                e[i][j] += term[i][j];
            }
        }
    }
    for _ in 0..s {
        e = mul(&e, &e);
    }
    e
}

/// One rotor step over H of M z̈ = f_ext + f₀ + K (z − z_k) + C (ż − v_k) − c_r ż, exact
/// (K = C = 0: the force held constant).
fn rotor_step(z: f64, v: f64, h: f64, c_r: f64, f0: f64, k: f64, c: f64) -> (f64, f64) {
    // State (z − z_k, v) with the affine term in a third component.
    let a = [
        [0.0, h, 0.0],
        [k / M * h, (c - c_r) / M * h, (F_EXT + f0 - c * v) / M * h],
        [0.0, 0.0, 0.0],
    ];
    let e = expm3(a);
    let (dz, v1) = (e[0][1] * v + e[0][2], e[1][1] * v + e[1][2]);
    (z + dz, v1)
}

struct Linear {
    z_eq: f64,
    k: f64,
    c_c: f64,
    omega: f64,
    zeta: f64,
    c_r: f64,
}

fn linearize() -> Linear {
    let mut sim = Simulation::new(&scene()).unwrap();
    let j = sim.reaction_jacobian().unwrap();
    let k = -j.dfdx[2][2];
    let c_c = -j.dfdv[2][2];
    let omega = (k / M).sqrt();
    let c_r = 2.0 * ZETA_ROTOR * M * omega;
    Linear {
        z_eq: sim.journal().x[2],
        k,
        c_c,
        omega,
        zeta: (c_r + c_c) / (2.0 * M * omega),
        c_r,
    }
}

/// Runs the coupled system for `periods` rotor periods at macro step `h` from a 10 nm offset;
/// returns the ratio of the largest |z − z_eq| over the last two periods to that over the first
/// two (> 1: growing). `jacobian`: linearly implicit coupling with the interface Jacobian.
fn run(lin: &Linear, h: f64, periods: f64, jacobian: bool) -> f64 {
    let mut sim = Simulation::new(&scene()).unwrap();
    let j0 = sim.journal();
    let mut o = vec![0.0; sim.output_table().len()];
    let (mut z, mut v) = (lin.z_eq + 1e-8, 0.0);
    let period = std::f64::consts::TAU / lin.omega;
    let n = (periods * period / h).ceil() as usize;
    let n_edge = ((2.0 * period / h).ceil() as usize).max(1);
    let (mut first, mut last) = (0.0_f64, 0.0_f64);
    for step in 0..n {
        let t = step as f64 * h;
        // Master at t_k: the rotor's displacement and velocity to the bearing, the bearing's
        // reaction (direct feedthrough) back.
        sim.set_journal(Journal {
            x: [j0.x[0], j0.x[1], z],
            v: [0.0, 0.0, v],
        })
        .unwrap();
        sim.outputs(&mut o);
        let f = o[out::BEARING_F_Z];
        assert!(f.is_finite());
        let (k, c) = if jacobian {
            let jac = sim.reaction_jacobian().unwrap();
            (jac.dfdx[2][2], jac.dfdv[2][2])
        } else {
            (0.0, 0.0)
        };
        // Jacobi: both advance from the values at t_k.
        let (z1, v1) = rotor_step(z, v, h, lin.c_r, f, k, c);
        sim.advance(t + h).unwrap();
        (z, v) = (z1, v1);
        let a = (z - lin.z_eq).abs();
        if !a.is_finite() || a > 1e-5 {
            return f64::INFINITY; // diverged (beyond the linear range)
        }
        if step < n_edge {
            first = first.max(a);
        }
        if step >= n - n_edge {
            last = last.max(a);
        }
    }
    last / first
}

/// T7: co-simulation step sweep against a 1-DOF rotor. Criteria: with explicit Jacobi coupling
/// and the bearing force held constant over the macro step H, the observed stability boundary
/// (bisection on H, motion mode, lumped level) lies within 15 % of ωH = 4ζ (ω from the
/// directional-derivative stiffness, ζ the rotor's plus the contact's damping ratio); with the
/// interface Jacobian (linearly implicit coupling) the run decays at 20× that boundary and at
/// H = 1 ms.
#[test]
fn t7_cosim_step_sweep_constant_force_boundary_is_4_zeta_and_jacobian_coupling_is_stable() {
    let lin = linearize();
    // The L1 stiffness for comparison (the linearization above is at the same point).
    let h_theory = 4.0 * lin.zeta / lin.omega;
    eprintln!(
        "k = {:.4e} N/m, c_contact = {:.1} N s/m, ω = {:.0} rad/s, ζ = {:.4} (rotor {ZETA_ROTOR} + contact {:.4}), 4ζ/ω = {:.3} µs",
        lin.k,
        lin.c_c,
        lin.omega,
        lin.zeta,
        lin.c_c / (2.0 * M * lin.omega),
        h_theory * 1e6
    );
    assert!(lin.k > 1e8 && lin.k < 1e9, "bearing stiffness {:e}", lin.k);
    // 25 rotor periods: the growth or decay per period near the boundary is a few percent.
    let periods = 25.0;
    let stable = |h: f64| run(&lin, h, periods, false) < 1.0;
    let (mut lo, mut hi) = (0.5 * h_theory, 2.0 * h_theory);
    assert!(
        stable(lo),
        "constant-force coupling unstable at H = 4ζ/(2ω)"
    );
    assert!(!stable(hi), "constant-force coupling stable at H = 2·4ζ/ω");
    for _ in 0..10 {
        let mid = 0.5 * (lo + hi);
        if stable(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let h_obs = 0.5 * (lo + hi);
    let ratio = h_obs / h_theory;
    eprintln!(
        "observed boundary H = {:.3} µs, ωH = {:.4}, 4ζ = {:.4}: ratio {ratio:.3}",
        h_obs * 1e6,
        lin.omega * h_obs,
        4.0 * lin.zeta
    );
    assert!(
        (ratio - 1.0).abs() < 0.15,
        "observed ωH = {:.4} vs 4ζ = {:.4}",
        lin.omega * h_obs,
        4.0 * lin.zeta
    );
    // With the interface Jacobian: stable at 20× the boundary and at H = 1 ms (ωH ≈ 13).
    for h in [20.0 * h_theory, 1e-3] {
        let g = run(
            &lin,
            h,
            periods.max(40.0 * h / (std::f64::consts::TAU / lin.omega)),
            true,
        );
        eprintln!(
            "interface Jacobian: H = {:.1} µs (ωH = {:.2}): amplitude ratio {g:.3e}",
            h * 1e6,
            lin.omega * h
        );
        assert!(g < 1.0, "linearly implicit coupling grew at H = {h} s: {g}");
        // and the constant-force coupling blows up there
        assert!(run(&lin, h, periods, false) > 1.0);
    }
}
