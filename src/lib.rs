//! raceway: dynamics of high-speed angular-contact ball bearings with localized raceway defects
//! (Niu, Cao, He, Li, ASME J. Manuf. Sci. Eng. 136 (2014) 041015), shipped as an FMI 2.0
//! Co-Simulation FMU.
//!
//! # Public API
//!
//! The implementation modules are private; what a user needs is re-exported here, grouped by
//! what the user does:
//! - describe and run a simulation (crate root): a [`Scene`] (bearing, [`OperatingPoint`],
//!   [`DefectSpec`], [`Fidelity`], solver and output settings) stepped by a [`Simulation`],
//!   whose outputs are laid out by [`out`] and [`output_table`]; the bearing is a
//!   [`BearingFile`] (a preset or a TOML file, errors as [`ConfigError`]) turned into the
//!   derived [`Bearing`]; the static capacity check is [`StaticRating`] and [`peak_contact`];
//! - the quasi-static analyses: [`fault_frequencies`] (L0 fault frequencies and race-control
//!   cage ratios) and [`load_distribution`] (L1 Jones–Harris load distribution and stiffness);
//! - the dynamic models: [`models`] (the [`models::Model`] trait, the level registry, one type per
//!   level, and the state layouts for white-box tests in [`models::internals`]);
//! - the contact laws: [`contact`] (Hertz, lubricant traction, the lubricant film, the spall);
//! - analysis of the outputs: [`signal`] (spectra, Welch PSD, envelope analysis) and [`sweep`]
//!   (parameter sweeps run in parallel);
//! - the integration engine: [`solver`] (the `raceway-solver` crate; knows nothing about
//!   bearings).
//!
//! The FMI 2.0 Co-Simulation FMU around [`Simulation`] is the `ballbearing-fmu` crate (`fmu/`),
//! built on the generic `fmi2` crate.

#![warn(missing_docs)]

mod ball_spall;
mod config;
mod defect;
mod geometry;
mod limits;
mod operating;
mod roughness;
mod scene;
mod simulation;
mod vecmath;
mod waviness;

pub mod contact;
pub mod fault_frequencies;
pub mod load_distribution;
pub mod models;
pub mod signal;
pub mod sweep;

/// The integration engine (the `raceway-solver` crate): explicit Runge–Kutta methods, step
/// control, events and dense output.
pub use raceway_solver as solver;

/// The model version: the package version and a hash of the sources that compute a result
/// (this library, the solver crate, the presets). A sweep's table records it per study and, in
/// each row's key, per run.
pub const MODEL_VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    "+src.",
    env!("RACEWAY_SOURCE_HASH")
);

pub use config::{
    BearingFile, BearingSection, BlendLength, BlendName, CageGuidance, CageSection, ConfigError,
    ContactSection, DefectDefaults, DefectMode, HertzMethod, InnerRing, LubricationSection,
    Material, Pedestal, StripRule, TractionLaw, TractionSection, DEFAULT_PRESET, MAX_STRIPS,
    PRESETS,
};
pub use defect::{DefectSpec, Site};
pub use geometry::{
    critical_contact_damping, race_curvatures, Bearing, Race, MAX_CONTACT_DAMPING_RATIO,
};
pub use limits::{peak_contact, StaticRating, MAX_CONTACT_PRESSURE, RATING_PRESSURE};
pub use models::{
    out, output_table, output_table_for, output_table_with_cage, OutputInfo, SimError,
};
pub use operating::{rpm_to_rad_s, OperatingPoint, RingLoad};
pub use roughness::{track_radius, Roughness, RoughnessSpec, TrackField, TrackRoughness};
pub use scene::{
    AxialMount, BearingRef, CageSpeed, CouplingMode, Fidelity, FullSettings, LumpedOptions,
    MethodName, Mounting, OutputSettings, Pulse, Resonator, Scene, SolverSettings, DEFAULT_SCENE,
    MAX_PI_BETA, MIN_RTOL, RTOL_FLOOR_WHY,
};
pub use simulation::{model_exchange_capacity, Journal, Simulation, WorkStats};
pub use waviness::{Harmonic, Waviness, WavinessSpec};
