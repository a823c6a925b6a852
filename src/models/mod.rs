//! Dynamic models of the fidelity ladder, all behind one [`Model`] trait so that the
//! [`Simulation`](crate::simulation::Simulation), the CLI and the FMU never depend on a level.
//!
//! A model is a first-order ODE `y' = f(t, y)` with piecewise-constant inputs, plus
//! known-time discontinuities ("stops", e.g. a ball reaching a defect edge when ball motion is
//! prescribed) at which the integrator must land and the model may switch a frozen discrete
//! mode (spec `solvers.md`, "Events").

pub mod full;
pub mod kinematic;
pub mod lumped;
pub mod quasi_static_level;

use crate::geometry::Bearing;
use crate::scene::{Fidelity, Scene};
use crate::simulation::{Inputs, SimError};

/// L1 (quasi-static) solution at the given inputs; every level starts from it (spec §7). A failure
/// names the operating point and says why, prefixed by what needed the solution.
pub fn solve_l1(
    bearing: &Bearing,
    inputs: &Inputs,
    purpose: &str,
) -> Result<crate::quasi_static::QuasiStatic, SimError> {
    let case = crate::quasi_static::LoadCase {
        speed: inputs.shaft_speed,
        fa: inputs.fx,
        fy: inputs.fy,
        fz: inputs.fz,
    };
    crate::quasi_static::solve(bearing, &case).map_err(|e| {
        SimError::Input(format!(
            "{purpose} failed at shaft.speed = {:.3} rad/s, load = ({}, {}, {}) N: {e}",
            inputs.shaft_speed, inputs.fx, inputs.fy, inputs.fz
        ))
    })
}

/// Builds the model of the scene's fidelity level (one arm per level).
pub fn build(
    scene: &Scene,
    bearing: &Bearing,
    inputs: &Inputs,
) -> Result<Box<dyn Model>, SimError> {
    match scene.fidelity {
        Fidelity::Kinematic => Ok(Box::new(kinematic::KinematicModel::new(
            scene, bearing, inputs,
        )?)),
        Fidelity::QuasiStatic => Ok(Box::new(quasi_static_level::QuasiStaticModel::new(
            scene, bearing, inputs,
        )?)),
        Fidelity::Lumped => Ok(Box::new(lumped::LumpedModel::new(scene, bearing, inputs)?)),
        Fidelity::Full => Ok(Box::new(full::FullModel::with_options(
            scene,
            bearing,
            inputs,
            full::FullOptions {
                traction: scene.full.traction,
                lock_tilt: scene.full.lock_tilt,
            },
        )?)),
        other => Err(SimError::Unsupported(format!(
            "fidelity '{}' (code {}) is not available yet; available: 'lumped' (code 2)",
            other.name(),
            other.code()
        ))),
    }
}

/// One dynamic model of the ladder.
pub trait Model: Send {
    /// Number of first-order states.
    fn dim(&self) -> usize;

    /// Nominal magnitude of each state: the absolute tolerance is `rtol × nominal`.
    fn nominal(&self, out: &mut [f64]);

    /// The initial state at t = 0 (from L1 equilibrium, spec §7).
    fn initial_state(&self, y: &mut [f64]);

    /// New inputs, constant from time `t` on (state `y` at that time).
    fn set_inputs(&mut self, inputs: &Inputs, t: f64, y: &[f64]);

    /// Right-hand side; must not allocate.
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]);

    /// The first known discontinuity strictly after `t` and not after `t_max`, if any.
    fn next_stop(&self, t: f64, y: &[f64], t_max: f64) -> Option<f64>;

    /// Re-derives the frozen discrete mode for the interval that starts at `t` (called after
    /// every stop and every located event, and after inputs change).
    fn update_mode(&mut self, t: f64, y: &[f64]);

    /// Number of state-event functions (e.g. a free ball reaching a spall edge); 0 = none.
    /// Events are located on the dense output; the discrete mode stays frozen inside a step.
    fn n_events(&self) -> usize {
        0
    }

    /// Event functions g_i(t, y): a sign change inside a step is an event, after which
    /// [`Model::update_mode`] is called at the located time.
    fn events(&mut self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Fills the output vector (layout of [`crate::simulation::output_table`]).
    fn outputs(&mut self, t: f64, y: &[f64], out: &mut [f64]);

    /// Model quantities that are not states but must survive a save/restore.
    fn discrete_state(&self) -> Vec<f64> {
        Vec::new()
    }

    /// Restores what [`Model::discrete_state`] returned.
    fn set_discrete_state(&mut self, _s: &[f64]) -> Result<(), String> {
        Ok(())
    }

    /// The cage speed the model uses [rad/s] (for fault-frequency bookkeeping).
    fn cage_speed(&self) -> f64;

    /// True when ball j is inside the zone of the spall (|θ_bd| < θ_e) in the current discrete
    /// mode; false for levels without per-ball positions. Used to measure the paper's impact
    /// force (the largest contact force while the ball crosses the spall).
    fn in_spall_zone(&self, _j: usize) -> bool {
        false
    }
}
