//! Modes of the full model near feh (diagnostic for the Table-2 impact test, not part of CI):
//! settles the healthy Table-1 bearing (Fa, Fr 1000 N, inner-ring tilt held) for 30 ms, takes
//! the finite-difference Jacobian of the right-hand side there, and prints the eigenvalues
//! between 3 and 10 kHz with their damping. For the mode with the largest inner-ring z motion
//! it prints the eigenvector (inverse iteration): ring z, pedestal z and, over the loaded balls,
//! the RMS ball motion along and across the line of its outer contact, relative to ring z.
//!
//! `cargo run --release -p raceway-studies --bin modal_probe -- RPM [traction on|off] [FA]`
use nalgebra::{Complex, DMatrix, DVector};
use raceway::models::internals::layout::{BR, BX, PZ, RX};
use raceway::models::Model;
use raceway::models::ModelSystem;
use raceway::models::{FullModel, FullOptions};
use raceway::solver::{AdvanceOutcome, Integrator, Method, Options};
use raceway::{Bearing, Fidelity, Scene};
use std::f64::consts::TAU;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let rpm: f64 = a.first().and_then(|v| v.parse().ok()).unwrap_or(9900.0);
    let traction = a.get(1).is_none_or(|v| v == "on");
    let fa: f64 = a.get(2).and_then(|v| v.parse().ok()).unwrap_or(4000.0);
    let mut s = Scene::load(std::path::Path::new(
        "examples/scenes/impact-test-fa4000.toml",
    ))
    .unwrap();
    s.fidelity = Fidelity::Full;
    s.pulse = None;
    s.operating.shaft_speed = raceway::rpm_to_rad_s(rpm);
    s.operating.fx = fa;
    let bearing = Bearing::new(&s.bearing).unwrap();
    let inputs = s.operating;
    let opts = FullOptions {
        traction,
        lock_tilt: true,
        ..FullOptions::default()
    };
    let mut m = FullModel::with_options(&s, &bearing, &inputs, opts).unwrap();
    let n = m.dim();
    let mut y = vec![0.0; n];
    m.initial_state(&mut y);
    m.update_mode(0.0, &y);
    let mut nom = vec![0.0; n];
    m.nominal(&mut nom);
    let rtol = 1e-8;
    let mut integ = Integrator::new(
        Options::new(Method::Dop853, rtol, nom.iter().map(|v| v * rtol).collect()),
        0.0,
        &y,
    )
    .unwrap();
    let t_end = 0.03;
    while integ.t() < t_end {
        let out = integ
            .advance_with_events(&mut ModelSystem(&mut m), t_end, None)
            .unwrap();
        if matches!(out, AdvanceOutcome::Stopped { .. }) {
            m.update_mode(integ.t(), integ.y());
            integ.discontinuity();
        }
    }
    y.copy_from_slice(integ.y());
    let t = integ.t();
    m.update_mode(t, &y);
    // Central-difference Jacobian.
    let mut jac = DMatrix::<f64>::zeros(n, n);
    let (mut fp, mut fm) = (vec![0.0; n], vec![0.0; n]);
    for j in 0..n {
        let h = 1e-6 * nom[j].abs().max(1e-12);
        let save = y[j];
        y[j] = save + h;
        m.rhs(t, &y, &mut fp);
        y[j] = save - h;
        m.rhs(t, &y, &mut fm);
        y[j] = save;
        for i in 0..n {
            jac[(i, j)] = (fp[i] - fm[i]) / (2.0 * h);
        }
    }
    let lay = m.layout();
    let ring_z = lay.ring() + RX + 2;
    let ped_z = lay.pedestal() + PZ;
    let eig = jac.complex_eigenvalues();
    let mut modes: Vec<Complex<f64>> = eig
        .iter()
        .copied()
        .filter(|l| {
            let f = l.im / TAU;
            (3000.0..10_000.0).contains(&f) && l.re.abs() < 0.5 * l.im.abs()
        })
        .collect();
    modes.sort_by(|p, q| p.im.total_cmp(&q.im));
    println!(
        "rpm {rpm}, Fa {fa} N, traction {traction}, tilt held, at t = {:.0} ms: {} modes in 3–10 kHz",
        t * 1e3,
        modes.len()
    );
    let jc: DMatrix<Complex<f64>> = jac.map(|v| Complex::new(v, 0.0));
    let mut best: Option<(f64, Complex<f64>, DVector<Complex<f64>>)> = None;
    for l in &modes {
        // Inverse iteration at a shift just off the eigenvalue.
        let shift = *l * Complex::new(1.0 + 1e-9, 0.0);
        let a = &jc - DMatrix::<Complex<f64>>::identity(n, n) * shift;
        let lu = a.lu();
        let mut v = DVector::<Complex<f64>>::from_element(n, Complex::new(1.0, 0.0));
        for _ in 0..3 {
            if let Some(w) = lu.solve(&v) {
                let norm = w.norm();
                v = w / Complex::new(norm, 0.0);
            }
        }
        // Position part only, scaled by the nominal positions.
        let rz = v[ring_z].norm() / nom[ring_z];
        let pos: f64 = (0..n)
            .filter(|&i| i != lay.psi() && i != lay.phi())
            .map(|i| (v[i].norm() / nom[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        let share = rz / pos.max(1e-300);
        println!(
            "  {:8.1} Hz  ζ {:+.4}  ring-z share {:.3}",
            l.im / TAU,
            -l.re / l.norm(),
            share
        );
        if best.as_ref().is_none_or(|b| share > b.0) {
            best = Some((share, *l, v));
        }
    }
    let Some((_, l, v)) = best else { return };
    let rz = v[ring_z];
    let ratio = |c: Complex<f64>| (c / rz).norm();
    let nb = bearing.z;
    let (mut along, mut across, mut cnt) = (0.0, 0.0, 0.0);
    for j in 0..nb {
        let (_, co) = m.ball_contacts(&y, j);
        if co.q <= 0.0 {
            continue;
        }
        let b = lay.ball(j);
        // The outer contact's line in the ball's axial–radial plane: (bx, br) normalised.
        let len = (co.bx * co.bx + co.br * co.br).sqrt();
        let (nx, nr) = (co.bx / len, co.br / len);
        let (dx, dr) = (v[b + BX] / rz, v[b + BR] / rz);
        along += (dx * nx + dr * nr).norm_sqr();
        across += (dx * nr - dr * nx).norm_sqr();
        cnt += 1.0;
    }
    println!(
        "feh mode {:.1} Hz: pedestal z / ring z {:.3}; loaded balls (RMS, per unit ring z): along the outer contact line {:.3}, across it {:.3}",
        l.im / TAU,
        ratio(v[ped_z]),
        (along / cnt).sqrt(),
        (across / cnt).sqrt()
    );
}
