//! `JeffcottRotor`: a Jeffcott rotor with one bearing station, shipped as an FMI 2.0
//! Co-Simulation FMU built with the generic `fmi2` shell, to couple with the `BallBearing`
//! FMU (motion mode) in a co-simulation master.
//!
//! - [`jeffcott`]: the physics (plain Rust, no FMI);
//! - [`fmu`]: the [`fmi2::FmuModel`] and the variable table.
//!
//! It depends on the `fmi2` shell and the `raceway-solver` integration engine only, not on
//! the bearing library.

pub mod fmu;
pub mod jeffcott;
pub mod tlm;

fmi2::export_fmi2!(crate::fmu::JeffcottRotor);
