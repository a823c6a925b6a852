//! raceway: dynamics of high-speed angular-contact ball bearings with localized raceway defects
//! (Niu, Cao, He, Li, ASME J. Manuf. Sci. Eng. 136 (2014) 041015), shipped as an FMI 2.0
//! Co-Simulation FMU.
//!
//! Pipeline, one module per stage:
//! - [`config`]: bearing description files and presets;
//! - [`geometry`]: derived geometry shared by every fidelity level;
//! - [`contact`]: Hertz law ([`contact::hertz`]) and lubricant traction ([`contact::traction`]);
//! - [`defect`]: the spall (added deflection, force direction, Hertz change);
//! - [`fault_frequencies`]: L0 fault frequencies;
//! - [`load_distribution`]: L1 Jones–Harris load distribution and stiffness;
//! - [`models`]: the dynamic models (L2 lumped, ...) as [`solver::System`]s;
//! - [`solver`]: the explicit Runge–Kutta engine (the `raceway-solver` crate; knows nothing
//!   about bearings);
//! - [`scene`] and [`simulation`]: what to simulate and the stepping object shared by CLI and FMU;
//! - [`signal`]: spectra, Welch PSD, envelope analysis.
//!
//! The FMI 2.0 Co-Simulation FMU around [`simulation::Simulation`] is the `ballbearing-fmu`
//! crate (`fmu/`), built on the generic `fmi2` crate.

pub mod config;
pub mod contact;
pub mod defect;
pub mod fault_frequencies;
pub mod geometry;
pub mod limits;
pub mod load_distribution;
pub mod models;
pub mod operating;
pub mod scene;
pub mod signal;
pub mod simulation;
pub mod sweep;

/// The integration engine, re-exported so `raceway::solver::…` paths keep working.
pub use raceway_solver as solver;
