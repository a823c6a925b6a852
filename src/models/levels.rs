//! The registry of fidelity levels: one row per level in [`LEVELS`] with everything the library
//! knows about it (scene and CLI name, the FMU's integer code, the ladder label, one line on
//! what it computes, and the constructor). [`Fidelity`]'s names and codes and [`build`] read
//! this table.
//!
//! Adding a level: write its model in one file under `models/` (a [`Model`]), add its variant
//! to [`Fidelity`] (the key a scene names it by) and its row here.

use super::model::{Model, SimError};
use super::{full, kinematic, lumped, quasi_static, reduced};
use crate::geometry::Bearing;
use crate::operating::OperatingPoint;
use crate::scene::{Fidelity, Scene};

/// Builds a level's model for a scene at the start's inputs.
pub type Constructor = fn(&Scene, &Bearing, &OperatingPoint) -> Result<Box<dyn Model>, SimError>;

/// One fidelity level.
#[derive(Clone, Copy)]
pub struct Level {
    /// The scene's key for the level.
    pub fidelity: Fidelity,
    /// Name in scene files, on the command line and in snapshots (the serde name of
    /// [`Fidelity`]).
    pub name: &'static str,
    /// The FMU's integer code (the level number of the ladder).
    pub code: i32,
    /// Label on the fidelity ladder ("L0" … "L4").
    pub label: &'static str,
    /// What the level computes, in one line.
    pub summary: &'static str,
    /// Whether the level carries the distributed defects (scene tables `[waviness]` and
    /// `[roughness]`, docs/model.md#distributed); the others refuse a scene that has them.
    pub distributed: bool,
    /// Whether the level carries spalls on balls (`ring = "ball"`, docs/model.md#ball-spall);
    /// the others refuse a scene that has one.
    pub ball_spalls: bool,
    /// Why the level is deprecated, when it is: it still runs, with a warning naming this
    /// reason (the [`crate::Simulation`]'s first warning), and leaves the ladder in a later
    /// version.
    pub deprecated: Option<&'static str>,
    /// Builds the level's model.
    pub build: Constructor,
}

/// Every level, in the order of the ladder.
pub const LEVELS: &[Level] = &[
    Level {
        fidelity: Fidelity::Kinematic,
        name: "kinematic",
        code: 0,
        label: "L0",
        summary: "Kinematic signal generator: impulse trains at the fault frequencies of the \
                  traction's cage speed (L1 with the balls' steady spin, the caged balance of \
                  their orbital torques); no dynamics",
        distributed: false,
        ball_spalls: true,
        deprecated: None,
        build: |s, b, i| Ok(Box::new(kinematic::KinematicModel::new(s, b, i)?)),
    },
    Level {
        fidelity: Fidelity::QuasiStatic,
        name: "quasi_static",
        code: 1,
        label: "L1",
        summary: "Quasi-static Jones–Harris load distribution and bearing stiffness at the \
                  current inputs; no dynamics",
        distributed: false,
        ball_spalls: false,
        deprecated: None,
        build: |s, b, i| Ok(Box::new(quasi_static::QuasiStaticModel::new(s, b, i)?)),
    },
    Level {
        fidelity: Fidelity::Lumped,
        name: "lumped",
        code: 2,
        label: "L2",
        summary: "Lumped dynamics: inner ring and pedestal (outer ring) with kinematic balls, \
                  Hertz contacts and the spall; the default",
        distributed: true,
        ball_spalls: true,
        deprecated: None,
        build: |s, b, i| Ok(Box::new(lumped::LumpedModel::new(s, b, i)?)),
    },
    Level {
        fidelity: Fidelity::Reduced,
        name: "reduced",
        code: 3,
        label: "L3",
        summary: "Reduced per-ball dynamics: every ball with its own orbit (x, r, θ) and one \
                  spin rate about a fixed attitude axis, inner ring translations, pedestal; the \
                  full model's Hertz contacts, spall and strip traction (4 strips); ball flight \
                  and impacts with a fixed spin axis",
        distributed: true,
        ball_spalls: true,
        deprecated: Some(
            "it takes the full level's steps (its balls keep their 29 kHz motion between the \
             races) at nearly the full level's right-hand side, so it costs 0.8 to 0.9 of the \
             full level while being less accurate: it is no rung of the ladder",
        ),
        build: |s, b, i| Ok(Box::new(reduced::ReducedModel::new(s, b, i)?)),
    },
    Level {
        fidelity: Fidelity::Full,
        name: "full",
        code: 4,
        label: "L4",
        summary: "The paper's full model (ball, cage and ring dynamics with lubricant traction)",
        distributed: true,
        ball_spalls: true,
        deprecated: None,
        build: |s, b, i| {
            let options = full::FullOptions {
                traction: s.full.traction,
                lock_tilt: s.full.lock_tilt,
                shaft_tilt_inertia: s.full.shaft_tilt_inertia,
                tilt_stiffness: s.full.tilt_stiffness,
            };
            Ok(Box::new(full::FullModel::with_options(s, b, i, options)?))
        },
    },
];

/// The row of level `f`.
pub fn level(f: Fidelity) -> &'static Level {
    LEVELS
        .iter()
        .find(|l| l.fidelity == f)
        .expect("every Fidelity has its row in models::levels::LEVELS")
}

/// The levels' names in ladder order, comma-separated (for messages that list the choices).
pub fn level_names() -> String {
    names_of(|_| true)
}

/// The names of the levels that have `what`, in ladder order, comma-separated.
fn names_of(what: impl Fn(&Level) -> bool) -> String {
    let names: Vec<&str> = LEVELS.iter().filter(|l| what(l)).map(|l| l.name).collect();
    names.join(", ")
}

/// Builds the model of the scene's fidelity level.
pub fn build(
    scene: &Scene,
    bearing: &Bearing,
    inputs: &OperatingPoint,
) -> Result<Box<dyn Model>, SimError> {
    let row = level(scene.fidelity);
    let waviness = scene.waviness.as_ref().is_some_and(|w| !w.is_empty());
    let roughness = scene.roughness.as_ref().is_some_and(|r| !r.is_empty());
    if !row.distributed && (waviness || roughness) {
        let what = match (waviness, roughness) {
            (true, true) => "[waviness] and [roughness]",
            (true, false) => "[waviness]",
            _ => "[roughness]",
        };
        return Err(SimError::Unsupported(format!(
            "the {} level ({}) does not carry the scene's {what}; levels that do: {}",
            row.name,
            row.label,
            names_of(|l| l.distributed)
        )));
    }
    if !row.ball_spalls {
        if let Some(k) = scene.defects().position(|d| d.ring.race().is_none()) {
            let entry = if scene.n_defects() > 1 {
                format!("defect[{k}]")
            } else {
                "defect".into()
            };
            return Err(SimError::Unsupported(format!(
                "the {} level ({}) does not carry a spall on a ball ({entry}, ring = \"ball\"); \
                 levels that do: {}",
                row.name,
                row.label,
                names_of(|l| l.ball_spalls)
            )));
        }
    }
    (row.build)(scene, bearing, inputs)
}

/// The warning a run of a deprecated level starts with, naming the reason and the levels to
/// use instead; `None` for a level that is not deprecated.
pub fn deprecation_warning(f: Fidelity) -> Option<String> {
    let row = level(f);
    let why = row.deprecated?;
    // The dynamic levels that remain (L2 and up), the highest first.
    let instead: Vec<String> = LEVELS
        .iter()
        .filter(|l| l.deprecated.is_none() && l.code >= 2)
        .rev()
        .map(|l| format!("\"{}\" ({})", l.name, l.code))
        .collect();
    Some(format!(
        "fidelity \"{}\" ({}, FMU fidelity = {}) is deprecated and will be removed in a later \
         version: {why}; use {} instead",
        row.name,
        row.label,
        row.code,
        instead.join(" or ")
    ))
}

impl Fidelity {
    /// The FMU's integer code (the level number L0..L4).
    pub fn code(self) -> i32 {
        level(self).code
    }

    /// The level of an FMU integer code.
    pub fn from_code(code: i32) -> Option<Self> {
        LEVELS.iter().find(|l| l.code == code).map(|l| l.fidelity)
    }

    /// The level's name in scene files and on the command line.
    pub fn name(self) -> &'static str {
        level(self).name
    }

    /// The level of a name.
    pub fn from_name(s: &str) -> Option<Self> {
        LEVELS.iter().find(|l| l.name == s).map(|l| l.fidelity)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_row_names_its_level_as_scene_files_do_and_codes_are_unique() {
        for (k, l) in LEVELS.iter().enumerate() {
            let parsed: Fidelity = serde_json::from_str(&format!("\"{}\"", l.name)).unwrap();
            assert_eq!(parsed, l.fidelity, "row {k}: {}", l.name);
            assert_eq!(
                serde_json::to_string(&l.fidelity).unwrap(),
                format!("\"{}\"", l.name)
            );
            assert_eq!(LEVELS.iter().filter(|m| m.code == l.code).count(), 1);
            assert_eq!(
                LEVELS.iter().filter(|m| m.fidelity == l.fidelity).count(),
                1
            );
        }
    }
}
