//! The cage speed of the levels with kinematic balls (kinematic, quasi-static, lumped): the
//! caged balance of the strip traction on the full model's balls, or L1's outer-race control.

use super::full::{steady, FullModel, FullOptions};
use super::model::{Model, SimError};
use super::start::operating_point;
use crate::geometry::Bearing;
use crate::operating::OperatingPoint;

/// Cage speed [rad/s] of the levels with kinematic balls at a positive shaft speed, from the L1
/// solution `qs` at `inputs`: the traction solve ([`traction_cage_speed`], started from
/// `previous`, a cage-to-shaft ratio solved nearby, for continuation along a ramp) or L1's
/// outer-race control, as `cage` selects. An operating point where the traction has no
/// equilibrium is an error naming it (never a silent switch to outer-race control).
pub fn kinematic_levels_cage_speed(
    bearing: &Bearing,
    inputs: &OperatingPoint,
    qs: &crate::load_distribution::QuasiStatic,
    cage: crate::scene::CageSpeed,
    previous: Option<f64>,
) -> Result<f64, SimError> {
    match cage {
        crate::scene::CageSpeed::Traction => {
            traction_cage_speed(bearing, inputs, Some(qs), previous)
        }
        crate::scene::CageSpeed::OuterRaceControl => Ok(qs.cage_speed),
    }
}

/// Cage speed [rad/s] at which the strip traction drives the balls of a caged bearing: the
/// common orbital rate at which the traction's orbital torques on the balls cancel, each ball
/// in its steady spin ([`steady::steady_rotation`], [`steady::Orbit::Caged`]), on
/// the healthy bearing at `inputs` with the ring and pedestal at the L1 start, the tilt held
/// (`l1`, if given, must be the L1 solution at `inputs`). `ratio`, a cage-to-shaft speed ratio
/// solved nearby, starts the search (else L1's outer-race control). 0 at zero speed. An error
/// names the operating point and the reason when there is no equilibrium.
pub fn traction_cage_speed(
    bearing: &Bearing,
    inputs: &OperatingPoint,
    l1: Option<&crate::load_distribution::QuasiStatic>,
    ratio: Option<f64>,
) -> Result<f64, SimError> {
    if inputs.shaft_speed <= 0.0 {
        return Ok(0.0);
    }
    let options = FullOptions {
        traction: true,
        lock_tilt: true,
        ..FullOptions::default()
    };
    let mut m = FullModel::healthy(bearing, inputs, options, l1)?;
    let mut y = vec![0.0; m.dim()];
    m.initial_state(&mut y);
    m.update_mode(0.0, &y);
    let guess = ratio.map(|r| r * inputs.shaft_speed);
    steady::steady_rotation(&mut m, &mut y, steady::Orbit::Caged, guess)
        .map(|r| r.cage_speed)
        .map_err(|e| {
            SimError::Input(format!(
                "the traction cage speed at {}: {e}",
                operating_point(inputs)
            ))
        })
}
