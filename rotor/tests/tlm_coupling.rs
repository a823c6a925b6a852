//! Coupling mode tlm against the monolithic rotor: the disk on the transmission line, coupled
//! to a journal on a linear bearing the way a co-simulation master and the BallBearing FMU
//! would (Jacobi, one exchange per communication step), converges to the two-mass rotor on
//! that bearing: at second order in the delay without shaft damping, with the delayed
//! damper's first-order error on top with it; and it stays stable at a coarse delay.

use raceway_rotor::jeffcott::{Coupling, InterfaceForce, Rotor, RotorParams, TlmRotor};

/// Linear bearing: stiffness and damping in y and z.
const KB: f64 = 5.0e7;
const CB: f64 = 2000.0;

fn params() -> RotorParams {
    let w = 3000.0 * std::f64::consts::PI / 30.0;
    let mut p = RotorParams {
        speed_initial: w,
        speed_final: w,
        load: [0.0; 3],
        journal_c: 0.0,
        ..RotorParams::default()
    };
    // the journal starts in its static equilibrium on the bearing, carrying both masses
    p.journal0[2] = -(p.journal_mass + p.disk_mass) * p.gravity / KB;
    p
}

/// The monolithic reference: the force-mode rotor with the bearing's exact linear law through
/// the interface Jacobian, sampled every `dt` up to `t_end` (disk y, z).
fn monolithic(p: &RotorParams, dt: f64, t_end: f64) -> Vec<[f64; 2]> {
    let mut r = Rotor::new(p, 0.0, 1e-11).unwrap();
    let n = (t_end / dt).round() as usize;
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let y = r.state().to_vec();
        let mut iface = InterfaceForce::default();
        for a in 1..3 {
            iface.f[a] = -KB * y[a] - CB * y[3 + a];
            iface.k[a][a] = -KB;
            iface.c[a][a] = -CB;
        }
        r.set_interface(iface);
        r.advance((k + 1) as f64 * dt).unwrap();
        out.push([r.state()[6], r.state()[7]]);
    }
    out
}

/// The journal on the linear bearing, the bearing side of the coupling: per axis
/// `m_j a = −k_b x − c_b v − m_j g ẑ + c0 + (c1 − c0) s − Zc v` over a step, by RK4 with `sub`
/// steps.
struct Journal {
    x: [f64; 2],
    v: [f64; 2],
}

impl Journal {
    fn step(&mut self, p: &RotorParams, c0: [f64; 2], c1: [f64; 2], zc: f64, t: f64, sub: usize) {
        let h = t / sub as f64;
        let acc = |a: usize, s: f64, x: f64, v: f64| {
            let g = if a == 1 {
                p.journal_mass * p.gravity
            } else {
                0.0
            };
            (-KB * x - CB * v - g + c0[a] + (c1[a] - c0[a]) * s - zc * v) / p.journal_mass
        };
        for a in 0..2 {
            let (mut x, mut v) = (self.x[a], self.v[a]);
            for i in 0..sub {
                let s0 = i as f64 / sub as f64;
                let sm = (i as f64 + 0.5) / sub as f64;
                let s1 = (i + 1) as f64 / sub as f64;
                let (k1x, k1v) = (v, acc(a, s0, x, v));
                let (k2x, k2v) = (
                    v + 0.5 * h * k1v,
                    acc(a, sm, x + 0.5 * h * k1x, v + 0.5 * h * k1v),
                );
                let (k3x, k3v) = (
                    v + 0.5 * h * k2v,
                    acc(a, sm, x + 0.5 * h * k2x, v + 0.5 * h * k2v),
                );
                let (k4x, k4v) = (v + h * k3v, acc(a, s1, x + h * k3x, v + h * k3v));
                x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            }
            self.x[a] = x;
            self.v[a] = v;
        }
    }
}

/// The co-simulation with delay `t`, sampled every `dt` (a multiple of `t`) up to `t_end`.
fn cosimulation(p: &RotorParams, t: f64, dt: f64, t_end: f64) -> Vec<[f64; 2]> {
    let p = RotorParams {
        coupling: Coupling::Tlm,
        tlm_delay: t,
        ..p.clone()
    };
    let mut rotor = TlmRotor::new(&p, 0.0, 1e-11).unwrap();
    let mut journal = Journal {
        x: [p.journal0[1], p.journal0[2]],
        v: [0.0; 2],
    };
    let n = (t_end / t).round() as usize;
    let every = (dt / t).round() as usize;
    let mut out = Vec::new();
    for k in 0..n {
        // Jacobi: both read at t_k, then both step
        let o = rotor.outputs(journal.v);
        let vj = journal.v;
        rotor.step(vj, (k + 1) as f64 * t).unwrap();
        journal.step(&p, o.tlm_c0, o.tlm_c1, o.tlm_zc, t, 8);
        if (k + 1) % every == 0 {
            out.push([rotor.state()[0], rotor.state()[1]]);
        }
    }
    out
}

/// Largest deviation of the disk from the reference over the run, relative to the largest
/// excursion of the reference from its start.
fn relative_error(reference: &[[f64; 2]], run: &[[f64; 2]], start: [f64; 2]) -> f64 {
    assert_eq!(reference.len(), run.len());
    let mut err: f64 = 0.0;
    let mut amp: f64 = 0.0;
    for (r, c) in reference.iter().zip(run) {
        for a in 0..2 {
            err = err.max((r[a] - c[a]).abs());
            amp = amp.max((r[a] - start[a]).abs());
        }
    }
    err / amp
}

#[test]
fn without_shaft_damping_the_cosimulation_converges_at_second_order() {
    // the line's only error is its parasitic mass k_s T²
    let p = RotorParams {
        shaft_c: 0.0,
        ..params()
    };
    let (dt, t_end) = (1e-4, 0.05);
    let reference = monolithic(&p, dt, t_end);
    let start = [p.journal0[1], p.journal0[2] - p.disk_sag()];
    let coarse = relative_error(&reference, &cosimulation(&p, 1e-4, dt, t_end), start);
    let fine = relative_error(&reference, &cosimulation(&p, 1e-5, dt, t_end), start);
    assert!(coarse < 0.01, "T = 1e-4: error {coarse:e}");
    let ratio = coarse / fine;
    assert!(
        (70.0..140.0).contains(&ratio),
        "errors {coarse:e}, {fine:e}: ratio {ratio}"
    );
}

#[test]
fn with_shaft_damping_the_cosimulation_converges_with_the_delayed_damper_error() {
    // The damper acts across the line one delay apart, an error c_s T times the acceleration
    // (first order, a mass-like c_s T = 0.016 kg at T = 1e-4 s next to the line's
    // k_s T² = 0.02 kg): the convergence is second order at coarse delays and tends to first
    // order at fine ones.
    let p = params();
    let (dt, t_end) = (1e-4, 0.05);
    let reference = monolithic(&p, dt, t_end);
    let start = [p.journal0[1], p.journal0[2] - p.disk_sag()];
    let coarse = relative_error(&reference, &cosimulation(&p, 1e-4, dt, t_end), start);
    let fine = relative_error(&reference, &cosimulation(&p, 1e-5, dt, t_end), start);
    assert!(coarse < 0.006, "T = 1e-4: error {coarse:e}");
    assert!(fine < 1.5e-4, "T = 1e-5: error {fine:e}");
    let ratio = coarse / fine;
    assert!(ratio > 30.0, "errors {coarse:e}, {fine:e}: ratio {ratio}");
}

#[test]
fn the_cosimulation_is_stable_at_a_coarse_step() {
    // T = 1e-3 s is far beyond any value-exchange coupling at the contact (ω_b T ≈ 5); the
    // line stays passive, the orbit bounded near the reference's
    let p = params();
    let (dt, t_end) = (1e-3, 0.5);
    let reference = monolithic(&p, dt, t_end);
    let run = cosimulation(&p, 1e-3, dt, t_end);
    let start = [p.journal0[1], p.journal0[2] - p.disk_sag()];
    let amp = |v: &[[f64; 2]]| {
        v[v.len() / 2..]
            .iter()
            .map(|x| (x[0] - start[0]).hypot(x[1] - start[1]))
            .fold(0.0, f64::max)
    };
    let (a_ref, a_run) = (amp(&reference), amp(&run));
    assert!(
        a_run.is_finite() && a_run < 2.0 * a_ref,
        "{a_run:e} vs {a_ref:e}"
    );
}
