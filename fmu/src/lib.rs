//! The FMI 2.0 Co-Simulation FMU `BallBearing`: raceway's [`Simulation`] behind the generic
//! [`fmi2`] shell. The cdylib exports the `fmi2*` C entry points.
//!
//! - [`variables`]: the BallBearing variable table (one row per variable: the one source of
//!   truth for the runtime, modelDescription.xml and the documentation);
//! - [`ballbearing`]: the [`fmi2::FmuModel`] of the bearing (scene + simulation);
//! - [`docs`]: documentation/index.html from the table;
//! - [`description`]: identifier, default experiment, modelDescription.xml and the GUID.
//!
//! The shared library is generic: the bearing is read at `fmi2Instantiate` from
//! `resources/bearing.toml` and the base scene from `resources/scene.toml` when there is one
//! ([`base`]), and the GUID is a hash of the model description generated for them, so an FMU
//! whose XML and resources disagree refuses to instantiate.
//!
//! [`Simulation`]: raceway::Simulation

pub mod ballbearing;
pub mod base;
pub mod description;
pub mod docs;
pub mod variables;

pub use description::{
    guid, guid_for, model_description_xml, model_description_xml_for, model_info, model_info_for,
    DEFAULT_START_TIME, DEFAULT_STEP_SIZE, DEFAULT_STOP_TIME, DEFAULT_TOLERANCE, MODEL_IDENTIFIER,
};

fmi2::export_fmi2!(ballbearing::BallBearing);
