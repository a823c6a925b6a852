//! `JeffcottRotor`: a Jeffcott rotor with one bearing station, shipped as an FMI 2.0
//! Co-Simulation FMU built with raceway's generic FMI shell, to couple with the `BallBearing`
//! FMU (motion mode) in a co-simulation master.
//!
//! - [`jeffcott`]: the physics (plain Rust, no FMI);
//! - [`fmu`]: the [`raceway::fmi::shell::FmuModel`] and the variable table.
//!
//! The shared library exports the `fmi2*` functions of this model only: it links raceway
//! without the `ballbearing-fmu` feature, which gates the BallBearing's exports.

pub mod fmu;
pub mod jeffcott;

raceway::export_fmi2!(crate::fmu::JeffcottRotor);
