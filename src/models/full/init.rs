//! Initial state of the full model from the quasi-static solution (spec §7).

use super::layout::*;
use super::FullModel;
use crate::defect::Defect;
use crate::geometry::{Bearing, Race};

use crate::simulation::{Inputs, SimError};
use std::f64::consts::TAU;

/// A representative ball load for the spall's blend length "b": the mean load of a ball carrying
/// the axial load or the peak load of the radial load zone (Stribeck), at least 10 N.
pub fn reference_ball_load(bearing: &Bearing, inputs: &Inputs) -> f64 {
    let z = bearing.z as f64;
    let axial = inputs.fx.abs() / (z * bearing.alpha0.sin().max(0.1));
    let radial = 5.0 * inputs.fy.hypot(inputs.fz) / z;
    axial.max(radial).max(10.0)
}

/// Ball 0's start azimuth: 0 (where L1 puts it), or an offset when that puts a ball within
/// θ_e + 0.02 rad of the spall (§7 step 4).
pub fn choose_theta_start(z: usize, defect: Option<&Defect>) -> f64 {
    let Some(d) = defect else { return 0.0 };
    let clear = d.half_angle() + 0.02;
    let spacing = TAU / z as f64;
    let theta0 = match d.ring() {
        Race::Outer | Race::Inner => d.theta0(),
    };
    [0.0, 0.5 * spacing, 0.25 * spacing, 0.75 * spacing]
        .into_iter()
        .find(|&s| {
            (0..z).all(|j| crate::defect::wrap(s + spacing * j as f64 - theta0).abs() > clear)
        })
        .unwrap_or(0.5 * spacing)
}

/// Fills `m.y0` and the reference cage ratio from L1 at the model's inputs (`l1`, if given,
/// must be the L1 solution at those inputs; otherwise it is solved here).
pub fn initial_state(
    m: &mut FullModel,
    bearing: &Bearing,
    l1: Option<&crate::quasi_static::QuasiStatic>,
) -> Result<(), SimError> {
    let inputs = m.inputs;
    let solved;
    let qs = match l1 {
        Some(qs) => qs,
        None => {
            solved = super::super::solve_l1(
                bearing,
                &inputs,
                "the quasi-static (L1) start of the full model",
            )?;
            &solved
        }
    };
    let lay = m.lay;
    let y = &mut m.y0;
    y.iter_mut().for_each(|v| *v = 0.0);
    // Common cage speed: mean ω_c of the loaded balls (§7 step 1).
    let loaded: Vec<_> = qs.loaded_balls().collect();
    let omega_c = if inputs.shaft_speed > 0.0 {
        if loaded.is_empty() {
            qs.cage_speed
        } else {
            loaded.iter().map(|b| b.cage_speed).sum::<f64>() / loaded.len() as f64
        }
    } else {
        0.0
    };
    if inputs.shaft_speed > 0.0 {
        m.cage_ratio = omega_c / inputs.shaft_speed;
    }
    let p = lay.pedestal();
    let yp0 = inputs.fy / m.k_py;
    let zp0 = inputs.fz / m.k_pz;
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
    Ok(())
}

/// Newton statistics of [`settle_ball_rotation`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SettleReport {
    /// Balls whose rotation was solved (loaded balls with traction).
    pub solved: usize,
    /// Newton iterations taken.
    pub iterations: usize,
    /// Largest scaled residual at the end (θ̈/θ̇² and |ω̇ − θ̇ e_x × ω|/(θ̇ |ω|)).
    pub residual: f64,
    /// Mean orbital rate θ̇ of the solved balls [rad/s] (0 if none).
    pub mean_orbital_rate: f64,
}

/// The steady rotation of every ball under the strip traction: the orbital rate θ̇ and the
/// angular velocity ω (inertial) at which, with the ball's position, the rings and the pedestal
/// held at `y`, the traction leaves the ball no orbital acceleration (θ̈ = 0) and its angular
/// velocity only turns with the orbit (ω̇ = θ̇ e_x × ω: constant in the frame that rotates with
/// the ball, the gyroscopic moment J θ̇ e_x × ω supplied by the traction). This is the state
/// the balls of the full model settle to within ≈ 20 ms from the L1 start (their spin axis
/// turns from the outer-race-control attitude to the one the traction sets); L3 takes its
/// fixed attitude from it.
///
/// Four unknowns and four equations per ball, solved by Newton with a finite-difference
/// Jacobian and step halving; the balls are independent (the rings are held), so each Jacobian
/// column is one right-hand side for all balls. Balls without contact keep their rates. Needs
/// `m` built with traction and its modes set (`update_mode`) at `y`; updates the ball rates
/// in `y`. `tol` bounds the scaled residual (1e-12: round-off; 1e-9 moves the rates by ≈ 1e-9).
pub fn settle_ball_rotation(m: &mut FullModel, y: &mut [f64], tol: f64) -> SettleReport {
    use crate::models::Model;
    let lay = m.lay;
    let z = m.z;
    let n = y.len();
    let idx = |j: usize| {
        let b = lay.ball(j);
        [b + BW, b + BOM, b + BOM + 1, b + BOM + 2]
    };
    let residual = |m: &mut FullModel, y: &[f64], d: &mut [f64], r: &mut [[f64; 4]]| {
        m.rhs(0.0, y, d);
        for (j, rj) in r.iter_mut().enumerate() {
            let b = lay.ball(j);
            let w = y[b + BW];
            let om = [y[b + BOM], y[b + BOM + 1], y[b + BOM + 2]];
            // θ̇ e_x × ω = θ̇ (0, −ω_z, ω_y).
            *rj = [
                d[b + BW],
                d[b + BOM],
                d[b + BOM + 1] + w * om[2],
                d[b + BOM + 2] - w * om[1],
            ];
        }
    };
    let scale_of = |y: &[f64], j: usize| {
        let b = lay.ball(j);
        let w = y[b + BW].abs().max(1.0);
        let om = (y[b + BOM].powi(2) + y[b + BOM + 1].powi(2) + y[b + BOM + 2].powi(2))
            .sqrt()
            .max(1.0);
        [w * w, w * om, w * om, w * om]
    };
    let norm = |r: &[f64; 4], s: &[f64; 4]| {
        r.iter()
            .zip(s)
            .map(|(a, b)| (a / b).abs())
            .fold(0.0, f64::max)
    };
    let mut d = vec![0.0; n];
    let mut r0 = vec![[0.0; 4]; z];
    let mut rk = vec![[0.0; 4]; z];
    // Only balls in contact with traction respond to their rates.
    let active: Vec<bool> = (0..z)
        .map(|j| {
            let (ci, co) = m.ball_contacts(y, j);
            ci.q > 0.0 && co.q > 0.0
        })
        .collect();
    let mut iterations = 0;
    residual(m, y, &mut d, &mut r0);
    let mut jac = vec![[[0.0; 4]; 4]; z];
    let mut h = vec![0.0; z];
    for _ in 0..30 {
        let before: Vec<f64> = (0..z).map(|j| norm(&r0[j], &scale_of(y, j))).collect();
        let worst = (0..z)
            .filter(|&j| active[j])
            .map(|j| before[j])
            .fold(0.0, f64::max);
        if worst < tol {
            break;
        }
        // A fresh Jacobian every iteration, column k for every ball at once (a chord iteration
        // that keeps it was measured slower: 12 iterations instead of 6 from L1).
        for k in 0..4 {
            for j in 0..z {
                let i = idx(j)[k];
                h[j] = 1e-7 * (y[i].abs() + y[idx(j)[0]].abs()).max(1.0);
                y[i] += h[j];
            }
            residual(m, y, &mut d, &mut rk);
            for j in 0..z {
                y[idx(j)[k]] -= h[j];
                for row in 0..4 {
                    jac[j][row][k] = (rk[j][row] - r0[j][row]) / h[j];
                }
            }
        }
        iterations += 1;
        let steps: Vec<Option<[f64; 4]>> = (0..z)
            .map(|j| {
                if !active[j] {
                    return None;
                }
                solve4(jac[j], r0[j]).map(|s| s.map(|v| -v))
            })
            .collect();
        // Step halving per ball until its scaled residual does not grow.
        let mut lambda = vec![1.0; z];
        let mut done = vec![false; z];
        let mut current = false;
        for _ in 0..12 {
            for j in 0..z {
                if let Some(s) = steps[j] {
                    if !done[j] {
                        for (k, &i) in idx(j).iter().enumerate() {
                            y[i] += lambda[j] * s[k];
                        }
                    }
                }
            }
            residual(m, y, &mut d, &mut rk);
            let mut again = false;
            for j in 0..z {
                let Some(s) = steps[j] else { continue };
                if done[j] {
                    continue;
                }
                if norm(&rk[j], &scale_of(y, j)) <= before[j] || lambda[j] < 1e-3 {
                    done[j] = true;
                } else {
                    for (k, &i) in idx(j).iter().enumerate() {
                        y[i] -= lambda[j] * s[k];
                    }
                    lambda[j] *= 0.5;
                    again = true;
                }
            }
            if !again {
                // rk belongs to the accepted state.
                current = true;
                break;
            }
        }
        if current {
            std::mem::swap(&mut r0, &mut rk);
        } else {
            residual(m, y, &mut d, &mut r0);
        }
    }
    let residual = (0..z)
        .filter(|&j| active[j])
        .map(|j| norm(&r0[j], &scale_of(y, j)))
        .fold(0.0, f64::max);
    let solved = active.iter().filter(|&&a| a).count();
    let sum: f64 = (0..z).filter(|&j| active[j]).map(|j| y[idx(j)[0]]).sum();
    SettleReport {
        solved,
        iterations,
        residual,
        mean_orbital_rate: if solved > 0 { sum / solved as f64 } else { 0.0 },
    }
}

/// Solves a 4×4 system by Gaussian elimination with partial pivoting (None if singular).
fn solve4(mut a: [[f64; 4]; 4], mut b: [f64; 4]) -> Option<[f64; 4]> {
    for c in 0..4 {
        let p = (c..4).max_by(|&i, &k| a[i][c].abs().total_cmp(&a[k][c].abs()))?;
        if a[p][c].abs() < 1e-300 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        let pivot = a[c];
        for r in c + 1..4 {
            let f = a[r][c] / pivot[c];
            for (ark, pk) in a[r][c..].iter_mut().zip(&pivot[c..]) {
                *ark -= f * pk;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 4];
    for c in (0..4).rev() {
        let s: f64 = (c + 1..4).map(|k| a[c][k] * x[k]).sum();
        x[c] = (b[c] - s) / a[c][c];
    }
    Some(x)
}
