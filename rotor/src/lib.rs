//! `JeffcottRotor`: a Jeffcott rotor with one bearing station, shipped as an FMI 2.0
//! Co-Simulation FMU built with the generic `fmi2` shell, to couple with the `BallBearing`
//! FMU in a co-simulation master, in one of two coupling modes (FMU parameter `coupling`):
//!
//! - 0, force: the rotor owns the journal and takes the bearing force as input (the
//!   BallBearing in motion mode); value exchange at the stiff contact, stable only at small
//!   communication steps or with the interface Jacobian;
//! - 1, tlm: the rotor is cut at the compliant shaft, which becomes a transmission line of
//!   delay `tlm.delay` (the communication step) simulated inside the rotor; the journal's mass
//!   is the BallBearing's (its coupling mode tlm). Stable at any step, error second order in
//!   the step (the line's parasitic mass `k_s T²`) plus the delayed shaft damper's first-order
//!   `c_s T`.
//!
//! Modules:
//!
//! - [`jeffcott`]: the physics (plain Rust, no FMI): [`jeffcott::Rotor`] (force mode) and
//!   [`jeffcott::TlmRotor`] (the disk on the line, tlm mode);
//! - [`tlm`]: the transmission line (its waves, history and per-step computations);
//! - [`fmu`]: the [`fmi2::FmuModel`] and the variable table.
//!
//! It depends on the `fmi2` shell and the `raceway-solver` integration engine only, not on
//! the bearing library.

pub mod fmu;
pub mod jeffcott;
pub mod tlm;

fmi2::export_fmi2!(crate::fmu::JeffcottRotor);
