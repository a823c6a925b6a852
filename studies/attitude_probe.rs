//! Mean spin-axis attitude of the full model's balls (diagnostic, not part of CI): runs L4 on a
//! scene and prints, per 5 ms window, the load-weighted mean attitude angle β of the balls'
//! spin vectors w = ω_b − θ̇ e_x (as L3 reads β from L1: β = atan2(−ê_s·e_r, ê_s·e_x) with
//! ê_s = −w/|w|), next to the L3 attitude. `cargo run --release -p raceway-studies --bin attitude_probe -- SCENE [duration] [lock]`
use raceway::models::internals::layout::{BOM, BTH, BW};
use raceway::models::Model;
use raceway::models::ReducedModel;
use raceway::models::{FullModel, FullOptions};
use raceway::solver::{AdvanceOutcome, Integrator, Method, Options};
use raceway::{Bearing, Scene};
use std::f64::consts::TAU;

use raceway::models::ModelSystem as Driver;

fn main() {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let scene = Scene::load(std::path::Path::new(&a[0])).unwrap();
    let duration: f64 = a.get(1).and_then(|v| v.parse().ok()).unwrap_or(0.05);
    let lock = a.get(2).is_some_and(|v| v == "lock");
    let bearing = Bearing::new(&scene.bearing).unwrap();
    let inputs = scene.operating;
    let l3 = ReducedModel::new(&scene, &bearing, &inputs).unwrap();
    println!(
        "L3 attitude β = {:.4}° (steady-rotation solve: {:?})",
        l3.attitude_angle().to_degrees(),
        l3.settle_report()
    );
    let mut m = FullModel::with_options(
        &scene,
        &bearing,
        &inputs,
        FullOptions {
            traction: true,
            lock_tilt: lock,
            ..FullOptions::default()
        },
    )
    .unwrap();
    let lay = m.layout();
    let n = m.dim();
    let mut y0 = vec![0.0; n];
    m.initial_state(&mut y0);
    let mut nom = vec![0.0; n];
    m.nominal(&mut nom);
    m.update_mode(0.0, &y0);
    let rtol = 1e-6;
    let mut integ = Integrator::new(
        Options::new(Method::Dop853, rtol, nom.iter().map(|v| v * rtol).collect()),
        0.0,
        &y0,
    )
    .unwrap();
    let z = scene.bearing.bearing.z as usize;
    let theta_start = raceway::models::internals::choose_theta_start(z, m.defect());
    let mut t_next: f64 = 0.005;
    while integ.t() < duration {
        let out = integ
            .advance_with_events(&mut Driver(&mut m), t_next.min(duration), None)
            .unwrap();
        if matches!(out, AdvanceOutcome::Stopped { .. }) {
            m.update_mode(integ.t(), integ.y());
            integ.discontinuity();
            continue;
        }
        let y = integ.y();
        let (mut sum, mut cnt) = (0.0, 0.0);
        for j in 0..z {
            let b = lay.ball(j);
            let theta = y[lay.psi()] + theta_start + TAU * j as f64 / z as f64 + y[b + BTH];
            let (s, c) = theta.sin_cos();
            let er = [0.0, -s, c];
            let w = [y[b + BOM] - y[b + BW], y[b + BOM + 1], y[b + BOM + 2]];
            let nrm = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
            let es = [-w[0] / nrm, -w[1] / nrm, -w[2] / nrm];
            let beta = (-(es[1] * er[1] + es[2] * er[2])).atan2(es[0]);
            sum += beta;
            cnt += 1.0;
        }
        println!(
            "t {:.3} ms: L4 mean β = {:.4}°",
            integ.t() * 1e3,
            (sum / cnt).to_degrees()
        );
        t_next += 0.005;
    }
}
