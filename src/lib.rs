//! raceway: dynamics of high-speed angular-contact ball bearings with localized raceway defects
//! (Niu, Cao, He, Li, ASME J. Manuf. Sci. Eng. 136 (2014) 041015), shipped as an FMI 2.0
//! Co-Simulation FMU.
//!
//! Pipeline, one module per stage:
//! - [`config`]: bearing description files and presets;
//! - [`geometry`]: derived geometry shared by every fidelity level;
//! - [`contact`]: Hertz law ([`contact::hertz`]) and lubricant traction ([`contact::traction`]);
//! - [`defect`]: the spall (added deflection, force direction, Hertz change);
//! - [`kinematics`]: L0 fault frequencies;
//! - [`quasi_static`]: L1 Jones–Harris load distribution and stiffness;
//! - [`models`]: the dynamic models (L2 lumped, ...) as [`solver::System`]s;
//! - [`solver`]: the explicit Runge–Kutta engine (knows nothing about bearings);
//! - [`scene`] and [`simulation`]: what to simulate and the stepping object shared by CLI and FMU;
//! - [`signal`]: spectra, Welch PSD, envelope analysis;
//! - [`fmi`]: the FMI 2.0 Co-Simulation shell around [`simulation::Simulation`].

pub mod config;
pub mod contact;
pub mod defect;
pub mod fmi;
pub mod geometry;
pub mod kinematics;
pub mod limits;
pub mod models;
pub mod operating;
pub mod quasi_static;
pub mod scene;
pub mod signal;
pub mod simulation;
pub mod solver;
pub mod sweep;
