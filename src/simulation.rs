//! The stepping object shared by the CLI and the FMU: scene → state → advance(to t) → outputs.
//!
//! A [`Simulation`] owns one dynamic [`Model`](crate::models::Model) (chosen by the scene's
//! fidelity) and one [`Integrator`](crate::solver::Integrator). Inputs (shaft speed, loads) may
//! change between advances; each change is a discontinuity for the integrator. Failures of the
//! integrator are returned as values and leave the simulation at its last good time.

use crate::config::ConfigError;
use crate::geometry::Bearing;
use crate::scene::Scene;
use std::fmt;

/// The continuous inputs (the FMU's `shaft.speed`, `load.Fx/Fy/Fz`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Inputs {
    /// Shaft (inner-ring) speed about +x [rad/s].
    pub shaft_speed: f64,
    /// External force on the inner ring [N] (Fx = Fa along +x, Fz = −Fr).
    pub fx: f64,
    pub fy: f64,
    pub fz: f64,
}

impl Inputs {
    /// The scene's operating point as inputs.
    pub fn from_scene(scene: &Scene) -> Self {
        Self {
            shaft_speed: scene.speed_rad_s(),
            fx: scene.operating.fa,
            fy: scene.operating.fy,
            fz: -scene.operating.fr,
        }
    }

    /// Rejects non-finite or impossible values, naming the input.
    pub fn check(&self) -> Result<(), SimError> {
        for (name, v) in [
            ("shaft.speed", self.shaft_speed),
            ("load.Fx", self.fx),
            ("load.Fy", self.fy),
            ("load.Fz", self.fz),
        ] {
            if !v.is_finite() {
                return Err(SimError::Input(format!(
                    "{name} = {v} is not a finite number"
                )));
            }
        }
        if self.shaft_speed < 0.0 {
            return Err(SimError::Input(format!(
                "shaft.speed = {} rad/s: the model supports speeds ≥ 0",
                self.shaft_speed
            )));
        }
        Ok(())
    }
}

/// What went wrong.
#[derive(Debug, Clone, PartialEq)]
pub enum SimError {
    /// A scene or bearing value is invalid.
    Config(ConfigError),
    /// An input is invalid (named in the message).
    Input(String),
    /// The integrator could not continue; the simulation stays at `t`, its last good time.
    Solver { t: f64, message: String },
    /// The requested feature is not available at this fidelity level.
    Unsupported(String),
    /// A saved state could not be restored.
    State(String),
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Config(e) => write!(f, "{e}"),
            SimError::Input(m) => write!(f, "invalid input: {m}"),
            SimError::Solver { t, message } => {
                write!(f, "integration failed at t = {t:.9} s: {message}")
            }
            SimError::Unsupported(m) => write!(f, "unsupported: {m}"),
            SimError::State(m) => write!(f, "cannot restore state: {m}"),
        }
    }
}

impl std::error::Error for SimError {}

impl From<ConfigError> for SimError {
    fn from(e: ConfigError) -> Self {
        SimError::Config(e)
    }
}

/// Name, unit and meaning of one output.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputInfo {
    pub name: String,
    pub unit: &'static str,
    pub description: String,
}

/// Index of each fixed output in the output vector; per-ball contact forces follow.
pub mod out {
    pub const PEDESTAL_A_Y: usize = 0;
    pub const PEDESTAL_A_Z: usize = 1;
    pub const PEDESTAL_Y: usize = 2;
    pub const PEDESTAL_Z: usize = 3;
    pub const PEDESTAL_V_Y: usize = 4;
    pub const PEDESTAL_V_Z: usize = 5;
    pub const RING_X: usize = 6;
    pub const RING_Y: usize = 7;
    pub const RING_Z: usize = 8;
    pub const BEARING_F_X: usize = 9;
    pub const BEARING_F_Y: usize = 10;
    pub const BEARING_F_Z: usize = 11;
    pub const FRICTION_TORQUE: usize = 12;
    pub const CAGE_SPEED: usize = 13;
    /// First of the z inner contact forces, then z outer ones.
    pub const CONTACT_START: usize = 14;
}

/// The outputs of a bearing with `z` balls, in output-vector order.
pub fn output_table(z: usize) -> Vec<OutputInfo> {
    let mut v: Vec<OutputInfo> = [
        ("pedestal.a.y", "m/s2", "Pedestal acceleration along y"),
        (
            "pedestal.a.z",
            "m/s2",
            "Pedestal acceleration along z (the paper's radial acceleration)",
        ),
        (
            "pedestal.y",
            "m",
            "Pedestal (outer ring) displacement along y",
        ),
        (
            "pedestal.z",
            "m",
            "Pedestal (outer ring) displacement along z",
        ),
        ("pedestal.v.y", "m/s", "Pedestal velocity along y"),
        ("pedestal.v.z", "m/s", "Pedestal velocity along z"),
        ("ring.x", "m", "Inner-ring displacement along x (axial)"),
        ("ring.y", "m", "Inner-ring displacement along y"),
        ("ring.z", "m", "Inner-ring displacement along z"),
        (
            "bearing.F.x",
            "N",
            "Force of the bearing on the shaft (inner ring) along x",
        ),
        (
            "bearing.F.y",
            "N",
            "Force of the bearing on the shaft (inner ring) along y",
        ),
        (
            "bearing.F.z",
            "N",
            "Force of the bearing on the shaft (inner ring) along z",
        ),
        (
            "torque.friction",
            "N.m",
            "Bearing friction (drive) torque; 0 at levels without traction (kinematic, lumped)",
        ),
        ("cage.speed", "rad/s", "Cage (mean ball orbital) speed"),
    ]
    .into_iter()
    .map(|(n, u, d)| OutputInfo {
        name: n.to_string(),
        unit: u,
        description: d.to_string(),
    })
    .collect();
    for race in ["inner", "outer"] {
        for j in 1..=z {
            v.push(OutputInfo {
                name: format!("contact.{race}.Q[{j}]"),
                unit: "N",
                description: format!("Normal contact force of ball {j} on the {race} race"),
            });
        }
    }
    v
}

/// Work counters of the integrator since the start (or the last reset).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WorkStats {
    pub steps: u64,
    pub rejected: u64,
    pub rhs_evals: u64,
}

/// One simulation run.
pub struct Simulation {
    scene: Scene,
    bearing: Bearing,
    inputs: Inputs,
    time: f64,
}

impl Simulation {
    /// Builds the model of the scene's fidelity and its initial state (from L1, spec §7).
    pub fn new(scene: &Scene) -> Result<Self, SimError> {
        scene.validate()?;
        let bearing = Bearing::new(&scene.bearing)?;
        Ok(Self {
            scene: scene.clone(),
            bearing,
            inputs: Inputs::from_scene(scene),
            time: 0.0,
        })
    }

    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    pub fn bearing(&self) -> &Bearing {
        &self.bearing
    }

    /// Current time [s].
    pub fn time(&self) -> f64 {
        self.time
    }

    pub fn inputs(&self) -> Inputs {
        self.inputs
    }

    /// Sets the inputs from now on (piecewise constant until the next change).
    pub fn set_inputs(&mut self, inputs: Inputs) -> Result<(), SimError> {
        inputs.check()?;
        self.inputs = inputs;
        Ok(())
    }

    /// Advances to exactly `t_end` (> current time).
    pub fn advance(&mut self, t_end: f64) -> Result<(), SimError> {
        Err(SimError::Unsupported(format!(
            "advance to {t_end}: dynamic models are not wired yet"
        )))
    }

    /// Advances to `t_end`, sampling the outputs every `dt`.
    pub fn advance_sampled(
        &mut self,
        t_end: f64,
        _dt: f64,
        _sample: &mut dyn FnMut(f64, &[f64]),
    ) -> Result<(), SimError> {
        self.advance(t_end)
    }

    /// The cage speed the model uses [rad/s].
    pub fn cage_speed(&self) -> f64 {
        0.0
    }

    /// The output table of this simulation.
    pub fn output_table(&self) -> Vec<OutputInfo> {
        output_table(self.bearing.z)
    }

    /// Fills `out` (length `output_table().len()`) with the outputs at the current time.
    pub fn outputs(&mut self, out: &mut [f64]) {
        out.iter_mut().for_each(|v| *v = 0.0);
    }

    /// Integrator work since the start.
    pub fn stats(&self) -> WorkStats {
        WorkStats::default()
    }

    /// A pointer-free snapshot from which [`Simulation::restore_state`] continues bit-identically.
    pub fn save_state(&self) -> Vec<u8> {
        Vec::new()
    }

    /// Restores a snapshot taken from a simulation of the same scene.
    pub fn restore_state(&mut self, _bytes: &[u8]) -> Result<(), SimError> {
        Err(SimError::State("not wired yet".into()))
    }
}
