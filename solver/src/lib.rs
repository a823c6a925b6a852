//! Explicit Runge–Kutta integration engine (knows nothing about bearings).
//!
//! One generic, tableau-driven stepping engine ([`Integrator`]) runs every method of [`Method`]:
//! RKF45 (Fehlberg, propagating the 4th-order solution), DOPRI5 (FSAL, 4th-order dense output),
//! DOP853 (8th order, 7th-order dense output from three extra stages) and classic RK4 (fixed step
//! only). Features needed for co-simulation: stepping across calls with the retained step size and
//! FSAL stage, exact landing on communication points, event location on the dense output with a
//! frozen discrete mode, per-component tolerances, allocation-free stepping, serializable solver
//! state ([`IntegratorState`]) and work counters ([`Stats`]).
//!
//! Layout:
//! - [`system`]: the [`System`] / [`EventSystem`] traits implemented by models;
//! - [`method`], [`options`], [`error`]: configuration and failures;
//! - [`tableau`] and [`methods`]: Butcher tableaus as const data;
//! - [`controller`]: error norm, step-size controller, initial step;
//! - [`dense`]: dense output and [`StepView`];
//! - [`integrator`]: the stepping engine; [`events`]: event location;
//! - [`state`]: [`Stats`] and the serializable [`IntegratorState`].

pub mod controller;
pub mod dense;
pub mod error;
pub mod events;
pub mod integrator;
pub mod method;
pub mod methods;
pub mod options;
pub mod state;
pub mod system;
pub mod tableau;

pub use dense::{grid_points, StepView};
pub use error::{SolverError, StepLimit};
pub use integrator::{AdvanceOutcome, Checkpoint, Integrator};
pub use method::Method;
pub use options::Options;
pub use state::{IntegratorState, Stats};
pub use system::{EventAction, EventSystem, System};
pub use tableau::Tableau;
