//! Initial state of the full model from the quasi-static solution (docs/model.md#initial-state).

use crate::geometry::{Bearing, Race};
use crate::models::balls::layout::*;
use crate::models::balls::BallCore;
use crate::models::{solve_l1_held, SimError};
use std::f64::consts::TAU;

/// Fills the full model's initial state `m.y0` and the reference cage ratio from L1 at the
/// model's inputs (`l1`, if given, must be the L1 solution at those inputs; otherwise it is
/// solved here), with the pedestal at rest when `centred`, else at its static deflection.
/// Returns each ball's orbital rate under L1's outer-race control.
pub fn initial_state(
    m: &mut BallCore,
    centred: bool,
    bearing: &Bearing,
    l1: Option<&crate::load_distribution::QuasiStatic>,
) -> Result<Vec<f64>, SimError> {
    let inputs = m.inputs;
    let solved;
    let qs = match l1 {
        Some(qs) => qs,
        None => {
            solved = solve_l1_held(
                bearing,
                &inputs,
                m.held_axial,
                "the quasi-static (L1) start of the full model",
            )?;
            &solved
        }
    };
    let lay = m.lay;
    let y = &mut m.y0;
    y.iter_mut().for_each(|v| *v = 0.0);
    // Common cage speed: L1's mean ω_c of the loaded balls (docs/model.md#initial-state step 1).
    let omega_c = if inputs.shaft_speed > 0.0 {
        qs.cage_speed
    } else {
        0.0
    };
    // Each loaded ball's own outer-race-control rate, where the steady-rotation solve starts.
    let l1_orbit = qs
        .balls
        .iter()
        .take(m.z)
        .map(|b| {
            if crate::load_distribution::is_loaded(b.q_inner) && inputs.shaft_speed > 0.0 {
                b.cage_speed
            } else {
                omega_c
            }
        })
        .collect();
    if inputs.shaft_speed > 0.0 {
        m.cage_ratio = omega_c / inputs.shaft_speed;
    }
    let p = lay.pedestal();
    // The pedestal at its static deflection, or at rest for a bearing taken on its own (the
    // traction solve: the balls orbit about the inertial axis, so a pedestal deflection would
    // put them on an orbit eccentric to the rings).
    let (yp0, zp0) = if centred {
        (0.0, 0.0)
    } else {
        (inputs.fy / m.k_py, inputs.fz / m.k_pz)
    };
    y[p + PY] = yp0;
    y[p + PZ] = zp0;
    let r = lay.ring();
    y[r + RX] = qs.delta_axial;
    y[r + RX + 1] = yp0 + qs.delta_y;
    y[r + RX + 2] = zp0 + qs.delta_z;
    let (xg, rg) = bearing.groove_centre(Race::Outer);
    for (j, ball) in qs.balls.iter().enumerate().take(m.z) {
        let b = lay.ball(j);
        let theta_ref = m.theta_start + TAU * j as f64 / m.z as f64;
        let (s, c) = theta_ref.sin_cos();
        let radial = rg + ball.x[1];
        let (py, pz) = (yp0 - radial * s, zp0 + radial * c);
        let theta = (-py).atan2(pz);
        y[b + BX] = xg + ball.x[0];
        y[b + BR] = py.hypot(pz) - m.pitch_radius;
        y[b + BTH] = crate::defect::wrap(theta - theta_ref);
        y[b + BW] = omega_c;
        // ω_b = ω_c e_x + ω_R ê_s, ê_s = cos β e_x − sin β e_r(θ).
        let (sb, cb) = ball.beta.sin_cos();
        let (st, ct) = theta.sin_cos();
        let er = [0.0, -st, ct];
        let wr = if inputs.shaft_speed > 0.0 {
            ball.spin_speed
        } else {
            0.0
        };
        y[b + BOM] = omega_c + wr * cb;
        y[b + BOM + 1] = -wr * sb * er[1];
        y[b + BOM + 2] = -wr * sb * er[2];
    }
    if lay.cage {
        // The cage (docs/model.md#cage-start): every pocket centred on its ball's place in the
        // reference cage (χ = 0), the centre on the balls' centroid, turning at the common
        // rate, at rest otherwise.
        let c = lay.cage_block();
        let z = m.z as f64;
        let (mut cy, mut cz) = (0.0, 0.0);
        for j in 0..m.z {
            let b = lay.ball(j);
            let theta = m.theta_start + TAU * j as f64 / z + y[b + BTH];
            let r = m.pitch_radius + y[b + BR];
            cy -= r * theta.sin() / z;
            cz += r * theta.cos() / z;
        }
        y[c + CA] = 0.0;
        y[c + CY] = cy;
        y[c + CY + 1] = cz;
        y[c + CW] = omega_c;
    }
    Ok(l1_orbit)
}
