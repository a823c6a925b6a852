//! Dynamic models of the fidelity ladder, all behind one [`Model`] trait so that the
//! [`Simulation`](crate::simulation::Simulation), the CLI and the FMU never depend on a level.
//!
//! A model is a first-order ODE `y' = f(t, y)` with piecewise-constant inputs, plus
//! known-time discontinuities ("stops", e.g. a ball reaching a defect edge when ball motion is
//! prescribed) at which the integrator must land and the model may switch a frozen discrete
//! mode (docs/model.md#events).
//!
//! - [`model`](Model): the interface, with the errors ([`SimError`]; the inputs are a
//!   [`crate::operating::OperatingPoint`]);
//!   [`out`]: the output vector's layout;
//! - [`levels`]: the registry of levels (names, codes, constructors) and [`build`];
//! - [`balls`]: what the ball-level models (reduced, full) share, in one struct they contain
//!   ([`balls::BallCore`]);
//! - one module per level: [`kinematic`] (L0), [`quasi_static`] (L1), [`lumped`] (L2),
//!   [`reduced`] (L3), [`full`] (L4);
//! - shared by the levels: the L1 start ([`solve_l1`], [`held_axial`]), the cage speed of the
//!   levels with kinematic balls ([`traction_cage_speed`]), the quasi-static reaction to a
//!   prescribed journal motion ([`motion`]).
//!
//! This module only declares and re-exports: every item lives in a submodule, so that the
//! levels and the interface can be layered (tests/module_cycles.rs).

pub(crate) mod balls;
mod cage;
pub(crate) mod full;
pub mod internals;
mod kinematic;
pub(crate) mod levels;
mod lumped;
mod model;
pub(crate) mod motion;
pub mod out;
mod quasi_static;
mod reduced;
mod start;

pub use crate::simulation::ModelSystem;
pub(crate) use cage::kinematic_levels_cage_speed;
pub use cage::traction_cage_speed;
pub use full::{FullModel, FullOptions};
pub use kinematic::KinematicModel;
pub use levels::{build, Constructor, Level, LEVELS};
pub use lumped::LumpedModel;
pub use model::{Model, ReactionJacobian, RingStates, SimError};
pub use out::{output_table, OutputInfo};
pub use quasi_static::QuasiStaticModel;
pub use reduced::{ReducedModel, ReducedOptions};
pub(crate) use start::operating_point;
pub use start::{held_axial, solve_l1, solve_l1_held};
