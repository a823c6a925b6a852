//! What a BallBearing FMU is made from: its base scene, whose values are the parameters' and
//! inputs' start values and the fixed configuration. Without a scene resource it is the
//! default scene on the FMU's bearing (`resources/bearing.toml`); with one
//! (`resources/scene.toml`, packed by `raceway fmu --scene` and `fmu-build --scene`) it is that
//! scene, whose text's SHA-256 is written into the model description, so that the GUID changes
//! with any change of the resource and an FMU whose XML and resources disagree refuses to
//! instantiate.

use crate::variables::{params, table_for, Access, Config};
use fmi2::Start;
use raceway::{BearingFile, Scene, Simulation};
use std::path::Path;

/// Name of the scene resource inside the FMU's `resources/`.
pub const SCENE_RESOURCE: &str = "scene.toml";

/// The base of an FMU: its scene and, when it comes from a scene resource, the SHA-256 (hex)
/// of the resource's text.
#[derive(Debug, Clone, PartialEq)]
pub struct Base {
    /// The base scene (its bearing is the FMU's).
    pub scene: Scene,
    /// SHA-256 of the scene resource's text, or `None` without a scene resource.
    pub scene_digest: Option<String>,
}

impl Base {
    /// The FMU without a scene resource: the default scene on `bearing`.
    pub fn default_for(bearing: &BearingFile) -> Self {
        Self {
            scene: Config::default_for(bearing).scene,
            scene_digest: None,
        }
    }

    /// The FMU's bearing.
    pub fn bearing(&self) -> &BearingFile {
        &self.scene.bearing
    }

    /// The base of the FMU whose scene resource has `text` (read from `origin`, its bearing
    /// path relative to `dir`) and whose bearing resource is `bearing`. Refused, with a message
    /// naming `origin` and the field: a scene the library refuses, one whose bearing is not
    /// `bearing`, a value an FMU parameter cannot hold as its start value, and a scene that
    /// cannot be simulated as given (overlapping spalls, a ball beyond the bearing's, a spall
    /// or a distributed defect at a level that does not carry it).
    pub fn from_scene_text(
        text: &str,
        origin: &str,
        dir: Option<&Path>,
        bearing: &BearingFile,
    ) -> Result<Self, String> {
        let invalid = |m: String| {
            if m.contains(origin) {
                format!("invalid scene resource: {m}")
            } else {
                format!("invalid scene resource {origin}: {m}")
            }
        };
        let scene = Scene::from_toml_str(text, origin, dir).map_err(|e| invalid(e.to_string()))?;
        if scene.bearing != *bearing {
            return Err(invalid(format!(
                "bearing: the scene's bearing '{}' is not the FMU's bearing '{}' \
                 (resources/bearing.toml); the scene resource must say bearing = \"bearing.toml\", \
                 as `raceway fmu --scene` writes it",
                scene.bearing.name, bearing.name
            )));
        }
        let cfg = Config::from_scene(&scene);
        // Every parameter holds the scene's value as its start value (an FMU Integer cannot
        // hold a seed above 2^31 - 1, for instance).
        for r in params() {
            if let Access::Param { get, set } = r.access {
                let mut again = cfg.clone();
                let v = get(&cfg);
                if set(&mut again, v).is_err() || again != cfg {
                    return Err(invalid(format!(
                        "{}: the scene's value cannot be the start value of the FMU parameter \
                         {} (read back as {v})",
                        r.name, r.name
                    )));
                }
            }
        }
        // Start values within the variables' declared ranges (the model description would be
        // invalid, and the shell would refuse the value when set).
        for e in table_for(&scene) {
            let v = &e.var;
            let x = match v.start {
                Start::Real(x) => x,
                Start::Integer(i) => f64::from(i),
                _ => continue,
            };
            let below = v.min.is_some_and(|lo| x < lo);
            let above = v.max.is_some_and(|hi| x > hi);
            if below || above || !x.is_finite() {
                return Err(invalid(format!(
                    "{}: the scene's value {x} is outside the FMU variable's range [{}, {}]",
                    v.name,
                    v.min.map_or("-inf".into(), |x| x.to_string()),
                    v.max.map_or("+inf".into(), |x| x.to_string())
                )));
            }
        }
        // The scene as the FMU will simulate it must build (the checks that need the bearing's
        // geometry and the level: overlaps, ball numbers, what each level carries).
        Simulation::new(&cfg.scene_with_spalls()).map_err(|e| invalid(e.to_string()))?;
        Ok(Self {
            scene,
            scene_digest: Some(digest(text)),
        })
    }
}

/// SHA-256 of `text`, in hex.
pub fn digest(text: &str) -> String {
    fmi2::sha256::sha256(text.as_bytes())
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// Reads `resources/scene.toml` of the FMU whose bearing is `bearing`: the base it makes, or
/// without a scene resource the default scene on the bearing.
pub fn load_scene(resource_dir: Option<&Path>, bearing: &BearingFile) -> Result<Base, String> {
    if let Some(dir) = resource_dir {
        let p = dir.join(SCENE_RESOURCE);
        if p.is_file() {
            let text = std::fs::read_to_string(&p)
                .map_err(|e| format!("cannot read {}: {e}", p.display()))?;
            return Base::from_scene_text(&text, &p.display().to_string(), Some(dir), bearing);
        }
    }
    Ok(Base::default_for(bearing))
}
