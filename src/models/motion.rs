//! Motion coupling at the levels without a dynamic inner ring (L0 kinematic, L1 quasi-static):
//! the bearing's reaction on a journal held at a prescribed displacement, from the
//! displacement-controlled quasi-static equilibrium of every ball
//! ([`crate::load_distribution::displacement_controlled`]) with the pedestal (outer ring) in series
//! on its support springs.
//!
//! Unknowns: the pedestal's static displacement p = (p_y, p_z). With u = x − (0, p_y, p_z) the
//! ring's displacement relative to the outer ring and F(u) the load that holds the ring there
//! (the balls push the outer ring with +F, the shaft with −F):
//!
//! ```text
//!   r(p) = K_p p − P F(x − Pᵀ p) = 0,        K_p = diag(k_py, k_pz),  P = rows y, z of I₃,
//! ```
//!
//! solved by Newton with J = K_p + P K Pᵀ (K = ∂F/∂u from the quasi-static solve). The
//! reaction on the journal is −F and its Jacobian, by the implicit-function theorem,
//!
//! ```text
//!   ∂(−F)/∂x = −K (I − Pᵀ (K_p + P K Pᵀ)⁻¹ P K),       ∂(−F)/∂v = 0 (no damping at L1).
//! ```

use super::ReactionJacobian;
use crate::geometry::Bearing;
use crate::load_distribution::{displacement_controlled, QuasiStatic};
use crate::models::SimError;

/// One solved journal position.
#[derive(Debug, Clone)]
pub struct QsReaction {
    /// Journal displacement and shaft speed it was solved for.
    pub x: [f64; 3],
    pub speed: f64,
    /// Pedestal (outer-ring) static displacement (y, z) \[m\].
    pub pedestal: [f64; 2],
    /// Load F that holds the ring (the bearing's force on the shaft is −F) \[N\].
    pub load: [f64; 3],
    /// Linearization of −F in the journal motion.
    pub jacobian: ReactionJacobian,
    /// The per-ball quasi-static state at the solution.
    pub solution: QuasiStatic,
}

/// The displacement-controlled quasi-static reaction with its last solution cached.
#[derive(Clone)]
pub struct QsMotion {
    bearing: Bearing,
    k_p: [f64; 2],
    warm: Vec<[f64; 2]>,
    last: Option<QsReaction>,
    /// The load the level currently runs on (set by the simulation when it hands one over).
    pub applied_load: [f64; 3],
}

fn inv2(m: [[f64; 2]; 2]) -> Option<[[f64; 2]; 2]> {
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    (det.is_finite() && det.abs() > 1e-300).then(|| {
        [
            [m[1][1] / det, -m[0][1] / det],
            [-m[1][0] / det, m[0][0] / det],
        ]
    })
}

impl QsMotion {
    pub fn new(bearing: &Bearing) -> Self {
        Self {
            bearing: bearing.clone(),
            k_p: [bearing.file.pedestal.k_y, bearing.file.pedestal.k_z],
            warm: Vec::new(),
            last: None,
            applied_load: [0.0; 3],
        }
    }

    /// The reaction at journal displacement `x` and shaft speed `speed` (cached: the same
    /// arguments return the last solution without work).
    pub fn solve(&mut self, speed: f64, x: [f64; 3]) -> Result<&QsReaction, SimError> {
        if self
            .last
            .as_ref()
            .is_some_and(|l| l.x == x && l.speed == speed)
        {
            return Ok(self.last.as_ref().expect("checked"));
        }
        let fail = |e: String| {
            SimError::Input(format!(
                "the quasi-static reaction at journal ({:e}, {:e}, {:e}) m, shaft.speed {speed} rad/s: {e}",
                x[0], x[1], x[2]
            ))
        };
        let mut p = self.last.as_ref().map_or([0.0; 2], |l| l.pedestal);
        let mut qs = None;
        for it in 0..40 {
            let u = [x[0], x[1] - p[0], x[2] - p[1]];
            let s = displacement_controlled(&self.bearing, speed, u, &mut self.warm)
                .map_err(|e| fail(e.to_string()))?;
            let f = s.ring_force();
            let r = [self.k_p[0] * p[0] - f[1], self.k_p[1] * p[1] - f[2]];
            let k = s.stiffness;
            let j = [
                [self.k_p[0] + k[1][1], k[1][2]],
                [k[2][1], self.k_p[1] + k[2][2]],
            ];
            let ji = inv2(j).ok_or_else(|| fail("singular pedestal equilibrium".into()))?;
            let dp = [
                -(ji[0][0] * r[0] + ji[0][1] * r[1]),
                -(ji[1][0] * r[0] + ji[1][1] * r[1]),
            ];
            // Newton converges quadratically: iterate to round-off (the reaction is
            // differentiated by the callers, so it must be smooth in x).
            let done = r[0].abs().max(r[1].abs()) <= 1e-11 * (1.0 + f[1].abs().max(f[2].abs()))
                || dp[0].abs().max(dp[1].abs()) <= 1e-17;
            let good = r[0].abs().max(r[1].abs()) <= 1e-6 * (1.0 + f[1].abs().max(f[2].abs()));
            if done || (it >= 8 && good) {
                qs = Some((s, ji));
                break;
            }
            p = [p[0] + dp[0], p[1] + dp[1]];
        }
        let Some((s, ji)) = qs else {
            return Err(fail(
                "the pedestal equilibrium did not converge in 40 iterations".into(),
            ));
        };
        // ∂(−F)/∂x = −K (I − Pᵀ J⁻¹ P K).
        let k = s.stiffness;
        let mut corr = [[0.0; 3]; 3]; // I − Pᵀ J⁻¹ P K
        for (a, row) in corr.iter_mut().enumerate() {
            row[a] = 1.0;
        }
        for a in 0..2 {
            for c in 0..3 {
                let pk = ji[a][0] * k[1][c] + ji[a][1] * k[2][c];
                corr[a + 1][c] -= pk;
            }
        }
        let mut dfdx = [[0.0; 3]; 3];
        for (i, row) in dfdx.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = -(0..3).map(|m| k[i][m] * corr[m][c]).sum::<f64>();
            }
        }
        self.last = Some(QsReaction {
            x,
            speed,
            pedestal: p,
            load: s.ring_force(),
            jacobian: ReactionJacobian {
                dfdx,
                dfdv: [[0.0; 3]; 3],
            },
            solution: s,
        });
        Ok(self.last.as_ref().expect("just set"))
    }
}
