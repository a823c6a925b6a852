//! L0: kinematic fault frequencies and the race-control cage-speed ratios (docs/model.md#l0).
//!
//! Two flavours:
//! - pure rolling at one contact angle α (the textbook formulas, [`fault_frequencies`]);
//! - loaded angles α_i ≠ α_o under Jones' outer-race control ([`outer_race_control`],
//!   [`loaded_frequencies`], [`frequencies_from_cage`]); inner-race control bounds the cage
//!   speed from the other side ([`inner_race_control_cage_ratio`], [`rolling_cage_ratio`]).
//!
//! The outer ring is fixed and the shaft (inner ring) turns at `fs` Hz. All frequencies are in
//! Hz; angles are in radians.

use crate::geometry::Bearing;
use serde::Serialize;

/// Kinematic frequencies of a bearing at one shaft speed \[Hz\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FaultFrequencies {
    /// Shaft (inner-ring) rotation frequency fs.
    pub shaft: f64,
    /// Fundamental train (cage) frequency.
    pub ftf: f64,
    /// Ball pass frequency, outer race: z·FTF.
    pub bpfo: f64,
    /// Ball pass frequency, inner race: z(fs − FTF).
    pub bpfi: f64,
    /// Ball spin frequency relative to the cage.
    pub bsf: f64,
    /// Twice the ball spin frequency (a ball defect strikes both races once per spin turn).
    pub two_bsf: f64,
}

/// Pure-rolling kinematic frequencies at one contact angle `alpha` \[rad\] for a shaft speed
/// `speed_hz` \[Hz\] (docs/model.md#l0):
/// `FTF = (fs/2)(1 − γ)`, `BPFO = z·FTF`, `BPFI = (z fs/2)(1 + γ)`,
/// `BSF = (dm/2D) fs (1 − γ²)`, with `γ = D cos α / dm`.
pub fn fault_frequencies(b: &Bearing, speed_hz: f64, alpha: f64) -> FaultFrequencies {
    let gamma = b.gamma(alpha);
    let ftf = 0.5 * speed_hz * (1.0 - gamma);
    let bsf = b.dm / (2.0 * b.d) * speed_hz * (1.0 - gamma * gamma);
    from_ftf_bsf(b, speed_hz, ftf, bsf)
}

/// All frequencies from the cage (FTF) and ball-spin (BSF) frequencies [Hz].
fn from_ftf_bsf(b: &Bearing, speed_hz: f64, ftf: f64, bsf: f64) -> FaultFrequencies {
    let z = b.z as f64;
    FaultFrequencies {
        shaft: speed_hz,
        ftf,
        bpfo: z * ftf,
        bpfi: z * (speed_hz - ftf),
        bsf,
        two_bsf: 2.0 * bsf,
    }
}

/// Ball kinematics under Jones' outer-race control (outer ring fixed, no spin at the outer
/// contact, pure rolling at both contacts).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RaceControl {
    /// Cage (ball orbital) speed over shaft speed, ω_c/Ω = FTF/fs.
    pub cage_ratio: f64,
    /// Ball spin speed in the cage frame over shaft speed, ω_R/Ω (negative for Ω > 0).
    pub spin_ratio: f64,
    /// Ball attitude angle β \[rad\]: the spin axis is `ê_s = cos β e_x − sin β e_r`.
    pub beta: f64,
}

impl RaceControl {
    /// Unit spin axis `ê_s = (cos β, −sin β)` on (e_x, e_r) of the ball's azimuth.
    pub fn spin_axis(&self) -> [f64; 2] {
        [self.beta.cos(), -self.beta.sin()]
    }
}

/// Outer-race control kinematics for loaded contact angles `alpha_i`, `alpha_o` \[rad\]
/// (docs/model.md#l0, Jones):
/// 1. `tan β = sin α_o/(cos α_o + D/dm)`;
/// 2. `g = (D/2) sin α_o cos(α_i − β)/sin(α_o − β)`, `h = dm/2 − (D/2) cos α_i`;
/// 3. `ω_c/Ω = h/(g + h)`;
/// 4. `ω_R/Ω = −(ω_c/Ω) sin α_o / sin(α_o − β)`.
///
/// Reduces to `(1 − γ)/2` when α_i = α_o. At α_o = 0 (where `sin(α_o − β)` vanishes with
/// `sin α_o`) the limit `sin α_o / sin(α_o − β) → 1 + (dm/D) cos α_o` (over cos β = 1) is used.
pub fn outer_race_control(b: &Bearing, alpha_i: f64, alpha_o: f64) -> RaceControl {
    let eps = b.d / b.dm;
    let (so, co) = alpha_o.sin_cos();
    let beta = so.atan2(co + eps);
    // sin α_o / sin(α_o − β) = (cos α_o + ε)/(ε cos β): the identity follows from tan β and is
    // regular at α_o = 0, where both sines vanish.
    let ratio = (co + eps) / (eps * beta.cos());
    // g = (D/2) cos(α_i − β) · sin α_o / sin(α_o − β)
    let g = 0.5 * b.d * (alpha_i - beta).cos() * ratio;
    let h = 0.5 * b.dm - 0.5 * b.d * alpha_i.cos();
    let cage_ratio = h / (g + h);
    RaceControl {
        cage_ratio,
        spin_ratio: -cage_ratio * ratio,
        beta,
    }
}

/// Cage speed over shaft speed, ω_c/Ω, for pure rolling at both contacts with the ball's spin
/// axis at attitude `beta` (outer ring fixed; Harris, Rolling Bearing Analysis, the ball-speed
/// relations with the attitude angle):
/// `ω_c/Ω = 1 / (1 + [(1 + γ' cos α_o)(cos α_i + tan β sin α_i)] / [(1 − γ' cos α_i)(cos α_o +
/// tan β sin α_o)])`, γ' = D/dm. With β of [`outer_race_control`] it is its cage ratio.
pub fn rolling_cage_ratio(b: &Bearing, alpha_i: f64, alpha_o: f64, beta: f64) -> f64 {
    let g = b.d / b.dm;
    let tb = beta.tan();
    let num = (1.0 + g * alpha_o.cos()) * (alpha_i.cos() + tb * alpha_i.sin());
    let den = (1.0 - g * alpha_i.cos()) * (alpha_o.cos() + tb * alpha_o.sin());
    1.0 / (1.0 + num / den)
}

/// Inner-race control: no spin at the inner contact, `tan β = sin α_i/(cos α_i − D/dm)`; the
/// cage ratio of pure rolling at that attitude ([`rolling_cage_ratio`]). With
/// [`outer_race_control`] it bounds the kinematic cage speeds of a ball between its two
/// race-control limits.
pub fn inner_race_control_cage_ratio(b: &Bearing, alpha_i: f64, alpha_o: f64) -> f64 {
    let (si, ci) = alpha_i.sin_cos();
    let beta = si.atan2(ci - b.d / b.dm);
    rolling_cage_ratio(b, alpha_i, alpha_o, beta)
}

/// Frequencies from a cage ratio ω_c/Ω and a spin ratio ω_R/Ω (e.g. from L1):
/// `FTF = ratio·fs`, `BPFO = z·FTF`, `BPFI = z(fs − FTF)`, `BSF = |ω_R/Ω|·fs`.
pub fn frequencies_from_cage(
    b: &Bearing,
    speed_hz: f64,
    cage_ratio: f64,
    spin_ratio: f64,
) -> FaultFrequencies {
    from_ftf_bsf(
        b,
        speed_hz,
        cage_ratio * speed_hz,
        spin_ratio.abs() * speed_hz,
    )
}

/// Outer-race-control frequencies for loaded angles `alpha_i`, `alpha_o` \[rad\] at `speed_hz`.
/// BSF is the ball's spin speed in the cage frame, |ω_R|/2π.
pub fn loaded_frequencies(
    b: &Bearing,
    speed_hz: f64,
    alpha_i: f64,
    alpha_o: f64,
) -> FaultFrequencies {
    let rc = outer_race_control(b, alpha_i, alpha_o);
    frequencies_from_cage(b, speed_hz, rc.cage_ratio, rc.spin_ratio)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rolling_ratio_at_the_outer_control_attitude_is_outer_control() {
        // Two derivations of the same kinematics: Jones' g/h form and Harris' attitude form.
        let b = Bearing::load("niu2014-table1").unwrap();
        for (ai, ao) in [
            (30.0_f64, 30.0_f64),
            (43.5, 25.4),
            (31.2, 30.9),
            (10.0, 40.0),
        ] {
            let (ai, ao) = (ai.to_radians(), ao.to_radians());
            let rc = outer_race_control(&b, ai, ao);
            let r = rolling_cage_ratio(&b, ai, ao, rc.beta);
            assert!(
                (r - rc.cage_ratio).abs() < 1e-13,
                "{r} vs {}",
                rc.cage_ratio
            );
            // Equal angles: both controls are pure rolling, (1 − γ)/2.
            if ai == ao {
                let irc = inner_race_control_cage_ratio(&b, ai, ao);
                assert!((irc - 0.5 * (1.0 - b.gamma(ai))).abs() < 1e-13);
            }
        }
    }

    #[test]
    fn loaded_formula_reduces_to_pure_rolling() {
        let b = Bearing::load("niu2014-table1").unwrap();
        for deg in [0.0_f64, 15.0, 30.0, 40.0] {
            let a = deg.to_radians();
            let rc = outer_race_control(&b, a, a);
            assert!((rc.cage_ratio - 0.5 * (1.0 - b.gamma(a))).abs() < 1e-14);
        }
    }
}
