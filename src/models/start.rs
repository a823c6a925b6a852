//! The quasi-static (L1) start every level takes, and the operating point in messages.

use super::model::SimError;
use crate::geometry::Bearing;
use crate::operating::OperatingPoint;
use crate::scene::{AxialMount, Scene};

/// L1 (quasi-static) solution at the given inputs; every level starts from it (docs/model.md#initial-state). A failure
/// names the operating point and says why, prefixed by what needed the solution.
pub fn solve_l1(
    bearing: &Bearing,
    inputs: &OperatingPoint,
    purpose: &str,
) -> Result<crate::load_distribution::QuasiStatic, SimError> {
    solve_l1_held(bearing, inputs, None, purpose)
}

/// [`solve_l1`] with the inner ring held axially at `held` \[m\] when given (a located ring:
/// `inputs.fx` does not act, see [`crate::load_distribution::solve_located`]).
pub fn solve_l1_held(
    bearing: &Bearing,
    inputs: &OperatingPoint,
    held: Option<f64>,
    purpose: &str,
) -> Result<crate::load_distribution::QuasiStatic, SimError> {
    match held {
        None => crate::load_distribution::solve(bearing, inputs),
        Some(d) => crate::load_distribution::solve_located(bearing, inputs, d),
    }
    .map_err(|e| {
        let held = held.map_or(String::new(), |d| {
            format!(", inner ring located at {:.4} µm axially", d * 1e6)
        });
        SimError::Input(format!(
            "{purpose} failed at {}{held}: {e}",
            operating_point(inputs)
        ))
    })
}

/// The axial displacement at which the scene's inner ring is held (None: the axial load acts,
/// [`crate::scene::Mounting`]): the given offset, or where the start's axial load alone puts
/// the ring at the start's speed (0 without one).
pub fn held_axial(
    scene: &Scene,
    bearing: &Bearing,
    inputs: &OperatingPoint,
) -> Result<Option<f64>, SimError> {
    match (scene.mounting.axial, scene.mounting.axial_offset) {
        (AxialMount::Load, _) => Ok(None),
        (AxialMount::Located, Some(d)) => Ok(Some(d)),
        (AxialMount::Located, None) if inputs.fx == 0.0 => Ok(Some(0.0)),
        (AxialMount::Located, None) => {
            let preload = OperatingPoint {
                fy: 0.0,
                fz: 0.0,
                ..*inputs
            };
            let qs = solve_l1(
                bearing,
                &preload,
                "the preload of the located inner ring (the start's axial load alone)",
            )?;
            Ok(Some(qs.delta_axial))
        }
    }
}

/// The operating point for messages: "shaft.speed = … rad/s (… rpm), load = (…, …, …) N".
pub fn operating_point(inputs: &OperatingPoint) -> String {
    format!(
        "shaft.speed = {:.3} rad/s ({:.1} rpm), load = ({}, {}, {}) N",
        inputs.shaft_speed,
        inputs.shaft_speed * 30.0 / std::f64::consts::PI,
        inputs.fx,
        inputs.fy,
        inputs.fz
    )
}
