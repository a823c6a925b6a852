//! The model-description facts of the BallBearing FMU: identifier, default experiment, the
//! generated `modelDescription.xml` and its GUID.

use crate::base::Base;
use crate::variables;
use fmi2::xml;
use raceway::BearingFile;
use std::sync::Mutex;

/// `modelIdentifier` of the FMU.
pub const MODEL_IDENTIFIER: &str = "BallBearing";

/// Default experiment (also used by fmu-build's reference run).
pub const DEFAULT_START_TIME: f64 = 0.0;
pub const DEFAULT_STOP_TIME: f64 = 0.1;
pub const DEFAULT_TOLERANCE: f64 = 1e-6;
pub const DEFAULT_STEP_SIZE: f64 = 1e-4;

/// The model-description facts that are not variables, of the FMU without a scene resource.
pub fn model_info(bearing: &BearingFile) -> xml::ModelInfo {
    model_info_for(&Base::default_for(bearing))
}

/// The model-description facts that are not variables. With a scene resource the description
/// names the scene and the SHA-256 of its text (so the GUID covers the whole resource).
pub fn model_info_for(base: &Base) -> xml::ModelInfo {
    let bearing = base.bearing();
    let scene = match &base.scene_digest {
        None => String::new(),
        Some(d) => format!(
            "; base scene '{}' from resources/{} (SHA-256 {d})",
            base.scene.name,
            crate::base::SCENE_RESOURCE
        ),
    };
    let name = if bearing.name.is_empty() {
        "custom".to_string()
    } else {
        bearing.name.clone()
    };
    xml::ModelInfo {
        model_name: MODEL_IDENTIFIER.into(),
        model_identifier: MODEL_IDENTIFIER.into(),
        description: format!(
            "Angular-contact ball bearing with a localized raceway spall (Niu et al. 2014), bearing '{name}' with {} balls{scene}",
            bearing.bearing.z
        ),
        author: "raceway developers".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        license: env!("CARGO_PKG_LICENSE").into(),
        generation_tool: format!("raceway {}", env!("CARGO_PKG_VERSION")),
        start_time: DEFAULT_START_TIME,
        stop_time: DEFAULT_STOP_TIME,
        tolerance: DEFAULT_TOLERANCE,
        step_size: DEFAULT_STEP_SIZE,
        provides_directional_derivative: true,
        model_exchange: Some(raceway::model_exchange_capacity(bearing.bearing.z as usize).1),
        independent_outputs: Vec::new(),
        enumerations: variables::enumerations(),
    }
}

fn description_and_guid(base: &Base) -> (String, String) {
    let vars: Vec<fmi2::Variable> = variables::table_for(&base.scene)
        .into_iter()
        .map(|e| e.var)
        .collect();
    xml::model_description(&model_info_for(base), &vars)
}

/// The `modelDescription.xml` of the FMU built for `bearing` without a scene resource.
pub fn model_description_xml(bearing: &BearingFile) -> String {
    model_description_xml_for(&Base::default_for(bearing))
}

/// The `modelDescription.xml` of the FMU made from `base`.
pub fn model_description_xml_for(base: &Base) -> String {
    description_and_guid(base).0
}

/// The GUID of the FMU built for `bearing` without a scene resource.
pub fn guid(bearing: &BearingFile) -> String {
    guid_for(&Base::default_for(bearing))
}

/// The GUID of the FMU made from `base` (a hash of its model description). The GUIDs of the
/// last few bases are kept for the process: fmi2Instantiate checks the importer's GUID
/// against it every time, and making it writes and hashes the whole description.
pub fn guid_for(base: &Base) -> String {
    static KNOWN: Mutex<Vec<(Base, String)>> = Mutex::new(Vec::new());
    let mut known = KNOWN
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    if let Some((_, g)) = known.iter().find(|(b, _)| b == base) {
        return g.clone();
    }
    let g = description_and_guid(base).1;
    if known.len() == 8 {
        known.remove(0);
    }
    known.push((base.clone(), g.clone()));
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kept GUIDs are each bearing's own, asked in any order and past the number kept.
    #[test]
    fn kept_guids_are_each_bearings_own() {
        let presets: Vec<BearingFile> = raceway::PRESETS
            .iter()
            .map(|(n, _)| BearingFile::load(n).expect("preset"))
            .collect();
        let own: Vec<String> = presets
            .iter()
            .map(|b| description_and_guid(&Base::default_for(b)).1)
            .collect();
        assert!(own.windows(2).all(|w| w[0] != w[1]));
        for round in 0..3 {
            for (b, g) in presets.iter().zip(&own).rev() {
                assert_eq!(guid(b), *g, "round {round}");
            }
        }
        let mut other = presets[0].clone();
        for k in 0..10 {
            other.name = format!("variant {k}");
            assert_eq!(
                guid(&other),
                description_and_guid(&Base::default_for(&other)).1
            );
        }
        assert_eq!(guid(&presets[1]), own[1]);
    }
}
