//! Bearing description files (TOML, docs/scenes.md#bearing-files) and the presets shipped with raceway.
//!
//! A file has the sections `[bearing]`, `[material]`, `[contact]`, `[traction]`,
//! `[inner_ring]`, `[pedestal]`, `[defect]`, `[lubrication]` and `[cage]`. Only `[bearing]` is
//! required; the other sections default to the paper's Table-1 values, a missing `[lubrication]`
//! means no lubricant film (the paper's model), and `[cage]` takes the values derived from the
//! bearing's geometry (docs/model.md#cage-defaults). Unknown keys are refused, and every value is
//! checked by [`BearingFile::validate`], whose error names the field and the rule it broke.

use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;

/// A configuration error that names the offending field (`section.key`) and the rule.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigError {
    /// Dotted path of the field, e.g. `bearing.f_inner`; empty when the file is unreadable.
    pub field: String,
    /// What is wrong, in words.
    pub message: String,
}

impl ConfigError {
    /// An error on the field `field` (`section.key`) with the rule it broke.
    pub fn new(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{}: {}", self.field, self.message)
        }
    }
}

impl std::error::Error for ConfigError {}

/// `[bearing]`: the geometry of the bearing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BearingSection {
    /// Number of balls.
    pub z: u32,
    /// Ball diameter D \[m\].
    pub ball_diameter: f64,
    /// Pitch diameter dm \[m\].
    pub pitch_diameter: f64,
    /// Free (nominal) contact angle α0 \[deg\].
    pub contact_angle_free_deg: f64,
    /// Inner groove curvature factor f_i (groove radius = f_i·D), > 0.5.
    pub f_inner: f64,
    /// Outer groove curvature factor f_o, > 0.5.
    pub f_outer: f64,
    /// Play along the contact line s0 ≥ 0 \[m\].
    #[serde(default)]
    pub clearance: f64,
}

/// `[material]`: balls and rings (one steel).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E \[Pa\].
    pub youngs_modulus: f64,
    /// Poisson's ratio ν (dimensionless).
    pub poisson: f64,
    /// Density \[kg/m³\].
    pub density: f64,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            youngs_modulus: 208e9,
            poisson: 0.3,
            density: 7850.0,
        }
    }
}

/// How the Hertz constant is computed (docs/model.md#hertz, #c5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HertzMethod {
    /// Exact elliptic-integral solution (default).
    Exact,
    /// Hamrock–Brewe curve fits.
    HamrockBrewe,
}

/// `[contact]`: normal contact law.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSection {
    /// Ball–race normal damping [N s/m].
    pub c_br: f64,
    /// How the Hertz constants are computed.
    pub hertz_method: HertzMethod,
    /// Optional override of the inner Hertz constant [N/m^1.5]; computed when absent.
    #[serde(rename = "K_inner", default, skip_serializing_if = "Option::is_none")]
    pub k_inner: Option<f64>,
    /// Optional override of the outer Hertz constant [N/m^1.5]; computed when absent.
    #[serde(rename = "K_outer", default, skip_serializing_if = "Option::is_none")]
    pub k_outer: Option<f64>,
    /// Strips along the contact ellipse's major axis (docs/model.md#c7; default 8: with equal strips the
    /// quadrature error of the traction force stays below 1 % of κm·Q in 99 % of the contact
    /// states of the S2 scene, 1.3 % at worst, see `studies/strip_study.rs`).
    pub n_strips: u32,
    /// Quadrature of the traction over the major axis (docs/model.md#c7).
    #[serde(default)]
    pub strip_rule: StripRule,
}

/// Most traction strips `contact.n_strips` may ask for (the strip tables of the ball-level
/// models have this many entries).
pub const MAX_STRIPS: usize = 32;

/// Quadrature rule of the strip traction over the contact ellipse's major axis (docs/model.md#strips, #c7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum StripRule {
    /// `n_strips` equal strips, slip at each strip centre, exact Hertz line-load weights.
    #[default]
    Equal,
    /// `n_strips`-point Gauss rule for the line-load weight 1 − s² (Gauss–Jacobi α = β = 1).
    Gauss,
}

impl Default for ContactSection {
    fn default() -> Self {
        Self {
            c_br: 20.0,
            hertz_method: HertzMethod::Exact,
            k_inner: None,
            k_outer: None,
            n_strips: 8,
            strip_rule: StripRule::Equal,
        }
    }
}

/// Shape of the traction curve (docs/model.md#traction).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum TractionLaw {
    /// κ(u) = (A + B u) e^(−C u) + D (docs/model.md#c8, default).
    #[default]
    Adore,
    /// Piecewise linear, C⁰ only: for comparison.
    Piecewise,
}

/// `[traction]`: the lubricant traction curve from four physical numbers (docs/model.md#c8).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TractionSection {
    /// Shape of the curve.
    #[serde(default)]
    pub law: TractionLaw,
    /// Traction coefficient at zero slip (dimensionless).
    pub kappa_0: f64,
    /// Maximum traction coefficient (dimensionless).
    pub kappa_max: f64,
    /// Slip speed of the maximum [m/s].
    pub u_max: f64,
    /// Traction coefficient at large slip (dimensionless).
    pub kappa_inf: f64,
}

impl Default for TractionSection {
    fn default() -> Self {
        Self {
            law: TractionLaw::Adore,
            kappa_0: 0.0,
            kappa_max: 0.08,
            u_max: 0.5,
            kappa_inf: 0.05,
        }
    }
}

/// `[inner_ring]`: mass and inertias (docs/model.md#c12).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InnerRing {
    /// Mass of the inner ring with what turns with it \[kg\].
    pub mass: f64,
    /// Polar moment of inertia about the ring axis \[kg m²\].
    #[serde(rename = "I_polar")]
    pub i_polar: f64,
    /// Diametral moment of inertia (tilt) \[kg m²\].
    #[serde(rename = "I_diam")]
    pub i_diam: f64,
}

impl Default for InnerRing {
    fn default() -> Self {
        Self {
            mass: 0.50,
            i_polar: 3.97e-4,
            i_diam: 2.24e-4,
        }
    }
}

/// `[pedestal]`: the 2-DOF support including the outer ring (docs/model.md#c3, #c12).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pedestal {
    /// Mass of the pedestal with the outer ring \[kg\].
    pub mass: f64,
    /// Support stiffness in y \[N/m\].
    pub k_y: f64,
    /// Support stiffness in z \[N/m\].
    pub k_z: f64,
    /// Support damping in y [N s/m].
    pub c_y: f64,
    /// Support damping in z [N s/m].
    pub c_z: f64,
}

impl Default for Pedestal {
    fn default() -> Self {
        Self {
            mass: 0.55,
            k_y: 15e6,
            k_z: 15e6,
            c_y: 1800.0,
            c_z: 1800.0,
        }
    }
}

/// Defect model mode (docs/model.md#spall-drop / #spall-point-mode).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum DefectMode {
    /// Finite-size ball resting on the edges (rolling-ball filter, default).
    #[default]
    Finite,
    /// Paper-literal: the profile depth under the nominal contact point.
    Point,
}

/// Length over which the compliance is blended past a defect edge (docs/model.md#c9).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum BlendLength {
    /// The string `"b"`: the contact ellipse's semi-minor axis.
    Named(BlendName),
    /// An explicit length \[m\]; 0 is the paper's abrupt change.
    Metres(f64),
}

/// The named blend lengths of a bearing file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum BlendName {
    /// `"b"`: the contact ellipse's semi-minor axis at the running load.
    #[serde(rename = "b")]
    SemiMinorAxis,
}

/// Abrupt by default (decision D2, docs/model.md#d2: the paper's eq. 20).
impl Default for BlendLength {
    fn default() -> Self {
        BlendLength::Metres(0.0)
    }
}

/// `[defect]`: how spalls are modelled on this bearing (their size and place are in the scene).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DefectDefaults {
    /// How the spall's drop is computed.
    #[serde(default)]
    pub mode: DefectMode,
    /// Edge radius r_e used in the edge Hertz constant (eq. 20) \[m\].
    pub edge_radius: f64,
    /// Length over which the compliance is blended past an edge.
    #[serde(default)]
    pub blend_length: BlendLength,
}

impl Default for DefectDefaults {
    fn default() -> Self {
        Self {
            mode: DefectMode::Finite,
            edge_radius: 0.1e-3,
            blend_length: BlendLength::default(),
        }
    }
}

/// `[lubrication]`: the lubricant at the ball–race contacts (docs/model.md#film). Absent: no
/// film (the paper's model: constant contact damping `contact.c_br`). The oil is given either
/// by its kinematic viscosities at 40 °C and 100 °C (an ISO VG data sheet) with the operating
/// temperature and density, converted by the ASTM D341 (Walther) relation, or directly by its
/// dynamic viscosity at the operating temperature.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LubricationSection {
    /// Kinematic viscosity at 40 °C \[mm²/s\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscosity_40: Option<f64>,
    /// Kinematic viscosity at 100 °C \[mm²/s\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub viscosity_100: Option<f64>,
    /// Operating temperature of the oil in the contacts \[°C\].
    #[serde(default = "default_oil_temperature")]
    pub temperature: f64,
    /// Density of the oil at the operating temperature \[kg/m³\].
    #[serde(default = "default_oil_density")]
    pub density: f64,
    /// Dynamic viscosity at the operating temperature \[Pa s\] (instead of the two kinematic
    /// viscosities, the temperature and the density).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamic_viscosity: Option<f64>,
    /// Pressure–viscosity coefficient α \[1/Pa\].
    #[serde(default = "default_pressure_viscosity")]
    pub pressure_viscosity: f64,
    /// Composite rms roughness σ = √(σ_ball² + σ_race²) \[m\]: the least film thickness the
    /// film's stiffness and damping use (below it the contact is in mixed lubrication).
    #[serde(default = "default_roughness")]
    pub roughness: f64,
}

fn default_oil_temperature() -> f64 {
    40.0
}

fn default_oil_density() -> f64 {
    870.0
}

fn default_pressure_viscosity() -> f64 {
    2.0e-8
}

fn default_roughness() -> f64 {
    0.1e-6
}

impl LubricationSection {
    /// Checks every value; the error names the field (`lubrication.<key>`) and the rule.
    pub fn validate(&self) -> Result<(), ConfigError> {
        // Small and large numbers in exponent form (1e-8, not 0.00000001).
        let num = |v: f64| {
            if v != 0.0 && !(1e-3..1e5).contains(&v.abs()) {
                format!("{v:e}")
            } else {
                format!("{v}")
            }
        };
        let range = |field: &str, v: f64, lo: f64, hi: f64, unit: &str| {
            check_finite(field, v)?;
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(ConfigError::new(
                    field,
                    format!(
                        "{} {unit} must lie in [{}, {}] {unit}",
                        num(v),
                        num(lo),
                        num(hi)
                    ),
                ))
            }
        };
        match (
            self.dynamic_viscosity,
            self.viscosity_40,
            self.viscosity_100,
        ) {
            (Some(eta), None, None) => {
                range("lubrication.dynamic_viscosity", eta, 1e-4, 100.0, "Pa s")?;
            }
            (Some(_), _, _) => {
                return Err(ConfigError::new(
                    "lubrication.dynamic_viscosity",
                    "give either dynamic_viscosity or viscosity_40 and viscosity_100, not both",
                ))
            }
            (None, Some(n40), Some(n100)) => {
                range("lubrication.viscosity_40", n40, 2.0, 1e5, "mm²/s")?;
                range("lubrication.viscosity_100", n100, 2.0, 1e5, "mm²/s")?;
                if n100 >= n40 {
                    return Err(ConfigError::new(
                        "lubrication.viscosity_100",
                        format!(
                            "{n100} mm²/s must be below viscosity_40 ({n40} mm²/s): oil thins as it warms"
                        ),
                    ));
                }
                range(
                    "lubrication.temperature",
                    self.temperature,
                    -40.0,
                    200.0,
                    "°C",
                )?;
                range("lubrication.density", self.density, 500.0, 2000.0, "kg/m³")?;
            }
            (None, None, _) => return Err(ConfigError::new(
                "lubrication.viscosity_40",
                "missing: give viscosity_40 and viscosity_100 (mm²/s), or dynamic_viscosity (Pa s)",
            )),
            (None, Some(_), None) => {
                return Err(ConfigError::new(
                    "lubrication.viscosity_100",
                    "missing: the Walther relation needs viscosity_40 and viscosity_100 (mm²/s)",
                ))
            }
        }
        range(
            "lubrication.pressure_viscosity",
            self.pressure_viscosity,
            1e-9,
            1e-7,
            "1/Pa",
        )?;
        range("lubrication.roughness", self.roughness, 1e-10, 1e-5, "m")?;
        Ok(())
    }
}

/// How the cage is guided (`[cage] guidance`, docs/model.md#cage).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum CageGuidance {
    /// By the balls: only the pocket contacts hold the cage (default).
    #[default]
    Balls,
    /// By a land of the inner ring: the cage's bore rides on it beyond the land clearance.
    InnerLand,
    /// By a land of the outer ring: the cage's outside rides in it beyond the land clearance.
    OuterLand,
}

impl CageGuidance {
    /// The name in bearing files.
    pub fn name(self) -> &'static str {
        match self {
            CageGuidance::Balls => "balls",
            CageGuidance::InnerLand => "inner_land",
            CageGuidance::OuterLand => "outer_land",
        }
    }
}

/// `[cage]`: the cage of the ball-level models (docs/model.md#cage). Every key is optional; a
/// key left out takes the value derived from the bearing's geometry
/// (docs/model.md#cage-defaults), and so does the whole section when it is absent. Whether a
/// simulation has a cage at all is the scene's choice (`[full] cage`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct CageSection {
    /// Mass of the cage \[kg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
    /// Polar moment of inertia of the cage about the bearing axis \[kg m²\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<f64>,
    /// Young's modulus of the cage material \[Pa\] (enters the derived pocket stiffness).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub youngs_modulus: Option<f64>,
    /// Poisson's ratio of the cage material (enters the derived pocket stiffness).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson: Option<f64>,
    /// Diametral pocket clearance: pocket diameter minus the ball diameter \[m\]; a ball
    /// moves ± half of it along the orbit before it touches a pocket face.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pocket_clearance: Option<f64>,
    /// Hertz constant of the ball–pocket contact, P = K δ^{3/2} [N/m^1.5].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pocket_stiffness: Option<f64>,
    /// Damping of the ball–pocket contact on its approach rate [N s/m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pocket_damping: Option<f64>,
    /// Friction coefficient on the pocket face (dimensionless).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pocket_friction: Option<f64>,
    /// How the cage is guided.
    #[serde(default)]
    pub guidance: CageGuidance,
    /// Land guidance: radial clearance between the cage and the guiding land \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub land_clearance: Option<f64>,
    /// Land guidance: radius of the guiding surface \[m\] (the land's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub land_radius: Option<f64>,
    /// Land guidance: Hertz-type constant of the cage–land contact, N = K δ^{3/2} [N/m^1.5].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub land_stiffness: Option<f64>,
    /// Land guidance: damping of the cage–land contact [N s/m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub land_damping: Option<f64>,
    /// Land guidance: friction coefficient between cage and land (dimensionless).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub land_friction: Option<f64>,
}

/// A whole bearing description file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BearingFile {
    /// Human-readable name.
    #[serde(default)]
    pub name: String,
    /// `[bearing]`: the geometry.
    pub bearing: BearingSection,
    /// `[material]`: the steel of balls and rings.
    #[serde(default)]
    pub material: Material,
    /// `[contact]`: the normal contact law and the traction strips.
    #[serde(default)]
    pub contact: ContactSection,
    /// `[traction]`: the lubricant traction curve.
    #[serde(default)]
    pub traction: TractionSection,
    /// `[inner_ring]`: mass and inertias of the inner ring.
    #[serde(default)]
    pub inner_ring: InnerRing,
    /// `[pedestal]`: the support of the outer ring.
    #[serde(default)]
    pub pedestal: Pedestal,
    /// `[defect]`: how spalls are modelled on this bearing.
    #[serde(default)]
    pub defect: DefectDefaults,
    /// `[lubrication]`: the lubricant film at the ball–race contacts (None: no film).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lubrication: Option<LubricationSection>,
    /// `[cage]`: the cage of the ball-level models (derived from the geometry where absent).
    #[serde(default, skip_serializing_if = "CageSection::is_empty")]
    pub cage: CageSection,
}

impl CageSection {
    /// True when no key is given (the section is absent or empty).
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }
}

/// The presets shipped in `presets/`: (name, TOML text).
pub const PRESETS: &[(&str, &str)] = &[
    (
        "niu2014-table1",
        include_str!("../presets/niu2014-table1.toml"),
    ),
    ("cwru-6205-de", include_str!("../presets/cwru-6205-de.toml")),
    ("cwru-6203-fe", include_str!("../presets/cwru-6203-fe.toml")),
    ("ims-za2115", include_str!("../presets/ims-za2115.toml")),
];

/// Name of the default preset (the paper's Table-1 bearing).
pub const DEFAULT_PRESET: &str = "niu2014-table1";

fn check_finite(field: &str, v: f64) -> Result<(), ConfigError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(ConfigError::new(
            field,
            format!("{v} is not a finite number"),
        ))
    }
}

fn check_positive(field: &str, v: f64) -> Result<(), ConfigError> {
    check_finite(field, v)?;
    if v > 0.0 {
        Ok(())
    } else {
        Err(ConfigError::new(field, format!("{v} must be > 0")))
    }
}

fn check_non_negative(field: &str, v: f64) -> Result<(), ConfigError> {
    check_finite(field, v)?;
    if v >= 0.0 {
        Ok(())
    } else {
        Err(ConfigError::new(field, format!("{v} must be ≥ 0")))
    }
}

impl BearingFile {
    /// Parses a TOML text and validates it. `origin` names the source in messages.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, ConfigError> {
        let file: BearingFile = toml::from_str(text).map_err(|e| {
            // toml's message carries the key and the line; keep it whole.
            let msg = e.message().to_string();
            let field = field_from_toml_error(&msg, e.span(), text);
            ConfigError::new(field, format!("{origin}: {}", e.to_string().trim_end()))
        })?;
        file.validate()?;
        Ok(file)
    }

    /// Loads a preset by name, or a TOML file by path.
    pub fn load(preset_or_path: &str) -> Result<Self, ConfigError> {
        if let Some((_, text)) = PRESETS.iter().find(|(n, _)| *n == preset_or_path) {
            return Self::from_toml_str(text, preset_or_path);
        }
        let path = Path::new(preset_or_path);
        let text = std::fs::read_to_string(path).map_err(|e| {
            let names: Vec<&str> = PRESETS.iter().map(|(n, _)| *n).collect();
            ConfigError::new(
                "",
                format!(
                    "'{preset_or_path}' is neither a preset ({}) nor a readable file: {e}",
                    names.join(", ")
                ),
            )
        })?;
        Self::from_toml_str(&text, preset_or_path)
    }

    /// The default bearing (Table 1 of the paper).
    pub fn default_preset() -> Self {
        Self::load(DEFAULT_PRESET).expect("the default preset is valid")
    }

    /// Checks every value; the error names the field and the rule it broke.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let b = &self.bearing;
        if b.z < 3 {
            return Err(ConfigError::new(
                "bearing.z",
                format!("{} balls: a bearing needs at least 3 balls", b.z),
            ));
        }
        if b.z > 200 {
            return Err(ConfigError::new(
                "bearing.z",
                format!("{} balls: at most 200 are supported", b.z),
            ));
        }
        check_positive("bearing.ball_diameter", b.ball_diameter)?;
        check_positive("bearing.pitch_diameter", b.pitch_diameter)?;
        if b.ball_diameter >= b.pitch_diameter {
            return Err(ConfigError::new(
                "bearing.ball_diameter",
                format!(
                    "D = {} m must be smaller than the pitch diameter dm = {} m (bearing.pitch_diameter; D ≥ dm is impossible)",
                    b.ball_diameter, b.pitch_diameter
                ),
            ));
        }
        // Balls must fit around the pitch circle without overlapping.
        let pitch_gap = b.pitch_diameter * (std::f64::consts::PI / b.z as f64).sin();
        if b.ball_diameter >= pitch_gap {
            return Err(ConfigError::new(
                "bearing.z",
                format!(
                    "{} balls of D = {} m (bearing.ball_diameter) overlap on a pitch circle of {} m (bearing.pitch_diameter; need D < dm·sin(π/z) = {:.4e} m)",
                    b.z, b.ball_diameter, b.pitch_diameter, pitch_gap
                ),
            ));
        }
        check_finite("bearing.contact_angle_free_deg", b.contact_angle_free_deg)?;
        if !(0.0..80.0).contains(&b.contact_angle_free_deg) {
            return Err(ConfigError::new(
                "bearing.contact_angle_free_deg",
                format!("{}° must lie in [0, 80)", b.contact_angle_free_deg),
            ));
        }
        for (field, f) in [
            ("bearing.f_inner", b.f_inner),
            ("bearing.f_outer", b.f_outer),
        ] {
            check_finite(field, f)?;
            if f <= 0.5 {
                return Err(ConfigError::new(
                    field,
                    format!("{f} must be > 0.5 (f ≤ 0.5: the groove radius f·D would not exceed the ball radius)"),
                ));
            }
            if f > 1.0 {
                return Err(ConfigError::new(
                    field,
                    format!("{f} must be ≤ 1.0 (a groove flatter than that is not a ball-bearing groove)"),
                ));
            }
        }
        check_non_negative("bearing.clearance", b.clearance)?;
        if b.clearance > 0.1 * b.ball_diameter {
            return Err(ConfigError::new(
                "bearing.clearance",
                format!("{} m exceeds 10 % of the ball diameter", b.clearance),
            ));
        }

        let m = &self.material;
        check_positive("material.youngs_modulus", m.youngs_modulus)?;
        check_finite("material.poisson", m.poisson)?;
        if !(m.poisson > -1.0 && m.poisson < 0.5) {
            return Err(ConfigError::new(
                "material.poisson",
                format!("{} must lie in (−1, 0.5)", m.poisson),
            ));
        }
        check_positive("material.density", m.density)?;

        let c = &self.contact;
        check_non_negative("contact.c_br", c.c_br)?;
        if let Some(k) = c.k_inner {
            check_positive("contact.K_inner", k)?;
        }
        if let Some(k) = c.k_outer {
            check_positive("contact.K_outer", k)?;
        }
        let max = MAX_STRIPS as u32;
        if !(1..=max).contains(&c.n_strips) {
            return Err(ConfigError::new(
                "contact.n_strips",
                format!("{} must lie in 1..={max}", c.n_strips),
            ));
        }

        let t = &self.traction;
        check_non_negative("traction.kappa_0", t.kappa_0)?;
        check_positive("traction.kappa_max", t.kappa_max)?;
        check_positive("traction.u_max", t.u_max)?;
        check_non_negative("traction.kappa_inf", t.kappa_inf)?;
        if t.kappa_max < t.kappa_0 || t.kappa_max < t.kappa_inf {
            return Err(ConfigError::new(
                "traction.kappa_max",
                format!(
                    "{} must be ≥ kappa_0 ({}) and ≥ kappa_inf ({}): it is the curve's maximum",
                    t.kappa_max, t.kappa_0, t.kappa_inf
                ),
            ));
        }
        if t.kappa_max > 1.0 {
            return Err(ConfigError::new(
                "traction.kappa_max",
                format!(
                    "{} exceeds 1: not a lubricated traction coefficient",
                    t.kappa_max
                ),
            ));
        }

        let r = &self.inner_ring;
        check_positive("inner_ring.mass", r.mass)?;
        check_positive("inner_ring.I_polar", r.i_polar)?;
        check_positive("inner_ring.I_diam", r.i_diam)?;

        let p = &self.pedestal;
        check_positive("pedestal.mass", p.mass)?;
        check_positive("pedestal.k_y", p.k_y)?;
        check_positive("pedestal.k_z", p.k_z)?;
        check_non_negative("pedestal.c_y", p.c_y)?;
        check_non_negative("pedestal.c_z", p.c_z)?;

        let d = &self.defect;
        check_positive("defect.edge_radius", d.edge_radius)?;
        if let BlendLength::Metres(l) = d.blend_length {
            check_non_negative("defect.blend_length", l)?;
        }
        if let Some(l) = &self.lubrication {
            l.validate()?;
        }
        self.validate_cage()
    }

    /// The `[cage]` checks of [`BearingFile::validate`].
    fn validate_cage(&self) -> Result<(), ConfigError> {
        let c = &self.cage;
        let b = &self.bearing;
        let opt = |field: &str, v: Option<f64>, check: fn(&str, f64) -> Result<(), ConfigError>| {
            v.map_or(Ok(()), |v| check(field, v))
        };
        opt("cage.mass", c.mass, check_positive)?;
        opt("cage.inertia", c.inertia, check_positive)?;
        opt("cage.youngs_modulus", c.youngs_modulus, check_positive)?;
        if let Some(nu) = c.poisson {
            check_finite("cage.poisson", nu)?;
            if !(nu > -1.0 && nu < 0.5) {
                return Err(ConfigError::new(
                    "cage.poisson",
                    format!("{nu} must lie in (−1, 0.5)"),
                ));
            }
        }
        opt("cage.pocket_clearance", c.pocket_clearance, check_positive)?;
        if let Some(cp) = c.pocket_clearance {
            // The pockets' webs: the pocket diameter D + c_p must leave a web on the pitch circle.
            let room =
                b.pitch_diameter * (std::f64::consts::PI / b.z as f64).sin() - b.ball_diameter;
            if cp >= room {
                return Err(ConfigError::new(
                    "cage.pocket_clearance",
                    format!(
                        "{cp} m leaves no web between the pockets: the pockets (D + clearance) \
                         must be narrower than the ball spacing dm·sin(π/z) = {:.4e} m",
                        b.pitch_diameter * (std::f64::consts::PI / b.z as f64).sin()
                    ),
                ));
            }
        }
        opt("cage.pocket_stiffness", c.pocket_stiffness, check_positive)?;
        opt("cage.pocket_damping", c.pocket_damping, check_non_negative)?;
        opt("cage.land_clearance", c.land_clearance, check_positive)?;
        opt("cage.land_radius", c.land_radius, check_positive)?;
        opt("cage.land_stiffness", c.land_stiffness, check_positive)?;
        opt("cage.land_damping", c.land_damping, check_non_negative)?;
        for (field, mu) in [
            ("cage.pocket_friction", c.pocket_friction),
            ("cage.land_friction", c.land_friction),
        ] {
            if let Some(mu) = mu {
                check_non_negative(field, mu)?;
                if mu > 1.0 {
                    return Err(ConfigError::new(
                        field,
                        format!("{mu} exceeds 1: not a lubricated friction coefficient"),
                    ));
                }
            }
        }
        let land_keys = [
            ("cage.land_clearance", c.land_clearance),
            ("cage.land_radius", c.land_radius),
            ("cage.land_stiffness", c.land_stiffness),
            ("cage.land_damping", c.land_damping),
            ("cage.land_friction", c.land_friction),
        ];
        let r_pitch = 0.5 * b.pitch_diameter;
        match c.guidance {
            CageGuidance::Balls => {
                if let Some((field, _)) = land_keys.iter().find(|(_, v)| v.is_some()) {
                    return Err(ConfigError::new(
                        *field,
                        "applies to a land-guided cage only: set cage.guidance = \"inner_land\" \
                         or \"outer_land\" (with guidance = \"balls\" only the pockets hold the \
                         cage)",
                    ));
                }
            }
            CageGuidance::InnerLand => {
                if let Some(r) = c.land_radius.filter(|&r| r >= r_pitch) {
                    return Err(ConfigError::new(
                        "cage.land_radius",
                        format!(
                            "{r} m: an inner-ring land lies inside the pitch circle (radius \
                             {r_pitch} m)"
                        ),
                    ));
                }
            }
            CageGuidance::OuterLand => {
                if let Some(r) = c.land_radius.filter(|&r| r <= r_pitch) {
                    return Err(ConfigError::new(
                        "cage.land_radius",
                        format!(
                            "{r} m: an outer-ring land lies outside the pitch circle (radius \
                             {r_pitch} m)"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Serializes back to TOML (used to ship the bearing inside an FMU).
    pub fn to_toml_string(&self) -> String {
        toml::to_string(self).expect("a bearing file serializes")
    }
}

/// Best-effort extraction of the offending key from a toml error, so the message names a field
/// even for type errors and unknown keys.
fn field_from_toml_error(msg: &str, span: Option<std::ops::Range<usize>>, text: &str) -> String {
    let span: Option<usize> = span.map(|s| s.start);
    if let Some(rest) = msg.strip_prefix("unknown field `") {
        if let Some(end) = rest.find('`') {
            let key = &rest[..end];
            // An unknown section is reported at its own header.
            let own_header = span.and_then(|p| {
                let p = p.min(text.len());
                let start = text[..p].rfind('\n').map_or(0, |i| i + 1);
                text[start..].lines().next().and_then(header_name)
            });
            if own_header.as_deref() == Some(key) {
                return key.to_string();
            }
            return match section_at(span, text) {
                Some(sec) => format!("{sec}.{key}"),
                None => key.to_string(),
            };
        }
    }
    if let Some(rest) = msg.strip_prefix("missing field `") {
        if let Some(end) = rest.find('`') {
            let key = &rest[..end];
            return match section_at(span, text) {
                Some(sec) => format!("{sec}.{key}"),
                None => key.to_string(),
            };
        }
    }
    // Type errors: name the key on the offending line.
    if let Some(start) = span {
        let line_start = text[..start.min(text.len())]
            .rfind('\n')
            .map(|i| i + 1)
            .unwrap_or(0);
        let line = &text[line_start..];
        let line = line.lines().next().unwrap_or("");
        if let Some(eq) = line.find('=') {
            let key = line[..eq].trim();
            if !key.is_empty() && !key.starts_with('[') {
                return match section_at(Some(start), text) {
                    Some(sec) => format!("{sec}.{key}"),
                    None => key.to_string(),
                };
            }
        }
    }
    section_at(span, text).unwrap_or_default()
}

/// The `[section]` header in force at byte offset `pos` (the line holding `pos` included, since
/// toml reports a table's missing keys at its header). Trailing comments are ignored.
fn section_at(pos: Option<usize>, text: &str) -> Option<String> {
    let pos = pos?.min(text.len());
    let line_end = text[pos..].find('\n').map_or(text.len(), |i| pos + i);
    text[..line_end].lines().rev().find_map(header_name)
}

/// `Some("name")` when the line is a `[name]` table header (not an array of tables).
fn header_name(line: &str) -> Option<String> {
    let t = line.split('#').next().unwrap_or("").trim();
    (t.starts_with('[') && t.ends_with(']') && !t.starts_with("[["))
        .then(|| t.trim_matches(|c| c == '[' || c == ']').trim().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_loads() {
        for (name, _) in PRESETS {
            let b = BearingFile::load(name).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert!(b.bearing.z >= 3);
        }
    }

    #[test]
    fn unknown_preset_or_file_lists_presets() {
        let e = BearingFile::load("no-such-bearing").unwrap_err();
        assert!(e.message.contains("niu2014-table1"), "{e}");
    }
}
