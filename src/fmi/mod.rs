//! The FMI 2.0 Co-Simulation shell around [`crate::simulation::Simulation`].
//!
//! - [`bindings`]: the FMI 2.0 C types, written locally;
//! - [`shell`]: the generic instance, state machine, checks, logging and FMU-state format,
//!   over the [`shell::FmuModel`] trait;
//! - [`exports`]: the `#[no_mangle] fmi2*` entry points ([`crate::export_fmi2!`]);
//! - [`codec`], [`sha256`], [`uri`]: byte format, GUID hash, resource-location parsing.

pub mod bindings;
pub mod codec;
pub mod exports;
pub mod sha256;
pub mod shell;
pub mod uri;

#[cfg(test)]
mod toy;
