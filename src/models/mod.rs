//! Dynamic models of the fidelity ladder, all behind one [`Model`] trait so that the
//! [`Simulation`](crate::simulation::Simulation), the CLI and the FMU never depend on a level.
//!
//! A model is a first-order ODE `y' = f(t, y)` with piecewise-constant inputs, plus
//! known-time discontinuities ("stops", e.g. a ball reaching a defect edge when ball motion is
//! prescribed) at which the integrator must land and the model may switch a frozen discrete
//! mode (docs/model.md#events).
//!
//! What it exposes:
//! - the interface: [`Model`], with its errors ([`SimError`]; the inputs are an
//!   [`OperatingPoint`](crate::OperatingPoint)) and the output vector's layout ([`out`],
//!   [`output_table`]);
//! - the registry of levels (names, codes, constructors): [`LEVELS`], [`Level`] and [`build`];
//! - one type per level: [`KinematicModel`] (L0), [`QuasiStaticModel`] (L1), [`LumpedModel`]
//!   (L2), [`ReducedModel`] (L3), [`FullModel`] (L4), and [`ModelSystem`], which drives any of
//!   them with the [`solver`](crate::solver);
//! - shared by the levels: the L1 start ([`solve_l1`], [`solve_l1_held`], [`held_axial`]) and
//!   the cage speed of the levels with kinematic balls ([`traction_cage_speed`]);
//! - the ball-level models' state layouts and building blocks, for white-box tests and research
//!   probes: [`internals`].
//!
//! In the source, the ball-level models (reduced, full) share `balls/` (one struct they contain,
//! `BallCore`); each level is one file (`kinematic.rs`, `quasi_static.rs`, `lumped.rs`,
//! `reduced.rs`, `full/`) registered in `levels.rs`; `motion.rs` is the quasi-static reaction to
//! a prescribed journal motion at the levels without ring states.
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
pub use levels::{build, deprecation_warning, level, level_names, Constructor, Level, LEVELS};
pub use lumped::LumpedModel;
pub use model::{CloneModel, ExchangeLimit, Model, ReactionJacobian, RingStates, SimError};
pub use out::{output_table, output_table_for, output_table_with_cage, OutputInfo};
pub use quasi_static::QuasiStaticModel;
pub use reduced::{ReducedModel, ReducedOptions};
pub(crate) use start::operating_point;
pub use start::{held_axial, solve_l1, solve_l1_held};
