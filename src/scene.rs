//! Scenes: what to simulate (bearing, operating point, defect, fidelity, solver, outputs).
//!
//! A scene file is TOML:
//!
//! ```toml
//! name = "sec3.5-outer"
//! bearing = "niu2014-table1"      # preset name, or a path relative to the scene file
//! fidelity = "lumped"             # kinematic | quasi_static | lumped | reduced | full
//!
//! [operating]
//! speed_rpm = 9900.0
//! fa = 4000.0                     # N, along +x on the inner ring
//! fr = 1000.0                     # N, radial, applied along −z (load.Fz = −fr)
//!
//! [defect]                        # optional: no table, no spall
//! ring = "outer"
//! width = 1.0e-3
//! depth = 0.2e-3
//! theta0 = 3.1416                 # rad, C1 (docs/model.md#c1) convention (π = load-zone centre)
//!
//!                                 # or any number of spalls: [[defect]] tables
//!                                 # (docs/scenes.md#several-spalls)
//! [solver]
//! method = "dop853"
//! rtol = 1e-6
//!
//! [output]
//! duration = 0.2
//! sample_rate = 51200.0
//! skip = 0.02                     # transient excluded from spectra
//! ```
//!
//! Optional tables: `[pulse]` (impact test, docs/model.md#c14), `[lumped]` (resonator, slip jitter, seed, and
//! `cage_speed = "traction" | "outer_race_control"` for the kinematic, quasi-static and lumped
//! levels),
//! `[full]` (traction on/off, inner-ring tilt held, the cage on/off at the reduced and full
//! levels) and `[coupling]` (`mode = "force"`, the
//! default: loads in, the inner ring integrated inside; or `"motion"`: the journal's
//! displacement and velocity in, the bearing's reaction out, see [`CouplingMode`]), and
//! `[mounting]` (`axial = "load"`, the default: Fa acts on the inner ring; or `"located"`: the
//! ring is held axially at `axial_offset`, by default where the start's Fa puts it, so that an
//! angular-contact bearing carries a pure radial load; see [`Mounting`]), and the distributed
//! defects `[waviness]` ([`WavinessSpec`]) and `[roughness]` ([`RoughnessSpec`]).

use crate::config::{BearingFile, ConfigError, DefectMode};
use crate::defect::DefectSpec;
use crate::operating::OperatingPoint;
use crate::roughness::RoughnessSpec;
use crate::waviness::WavinessSpec;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Fidelity level ("model no more than a scene needs"): the key of a level's row in
/// [`crate::models::levels::LEVELS`], which gives its name, FMU code and constructor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Fidelity {
    /// L0s: kinematic impulse-train signal generator.
    Kinematic,
    /// L1: quasi-static load distribution, no dynamics.
    QuasiStatic,
    /// L2: lumped inner ring + pedestal with kinematic balls.
    #[default]
    Lumped,
    /// L3: per-ball reduced dynamic model.
    Reduced,
    /// L4: the paper's full model.
    Full,
}

/// The `[operating]` table of a scene file: speed in rpm, loads as the paper states them. It
/// becomes an [`OperatingPoint`] (SI) as the file is read.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct OperatingTable {
    /// Shaft speed \[rpm\].
    speed_rpm: f64,
    /// Axial load along +x \[N\].
    #[serde(default)]
    fa: f64,
    /// Radial load \[N\], applied along −z.
    #[serde(default)]
    fr: f64,
    /// Extra load along +y \[N\].
    #[serde(default)]
    fy: f64,
}

impl From<OperatingTable> for OperatingPoint {
    fn from(t: OperatingTable) -> Self {
        OperatingPoint {
            fy: t.fy,
            ..OperatingPoint::from_rpm(t.speed_rpm, t.fa, t.fr)
        }
    }
}

/// Integration method names of the scene and the FMU (codes 0, 1, 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum MethodName {
    /// Runge–Kutta–Fehlberg 4(5).
    Rkf45,
    /// Dormand–Prince 5(4).
    Dopri5,
    /// Dormand–Prince 8(5,3) (default).
    #[default]
    Dop853,
}

impl MethodName {
    /// The FMU's integer code (0, 1, 2).
    pub fn code(self) -> i32 {
        match self {
            MethodName::Rkf45 => 0,
            MethodName::Dopri5 => 1,
            MethodName::Dop853 => 2,
        }
    }
    /// The method of an FMU code; None for an unknown code.
    pub fn from_code(code: i32) -> Option<Self> {
        Some(match code {
            0 => MethodName::Rkf45,
            1 => MethodName::Dopri5,
            2 => MethodName::Dop853,
            _ => return None,
        })
    }
    /// The method's name in scene files (`rkf45`, `dopri5`, `dop853`).
    pub fn name(self) -> &'static str {
        match self {
            MethodName::Rkf45 => "rkf45",
            MethodName::Dopri5 => "dopri5",
            MethodName::Dop853 => "dop853",
        }
    }
    /// The method of a scene-file name; None for an unknown name.
    pub fn from_name(s: &str) -> Option<Self> {
        [MethodName::Rkf45, MethodName::Dopri5, MethodName::Dop853]
            .into_iter()
            .find(|m| m.name() == s)
    }
}

/// Solver settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSettings {
    /// Integration method.
    #[serde(default)]
    pub method: MethodName,
    /// Relative tolerance; absolute tolerances are rtol × each state's nominal value.
    #[serde(default = "default_rtol")]
    pub rtol: f64,
    /// Step budget per advance (communication step) before the run is declared stalled.
    #[serde(default = "default_max_steps")]
    pub max_steps: u64,
    /// β of the PI step-size controller, in [0, 0.2]; 0 (default) is the I-controller. β = 0.08
    /// keeps the reduced and full levels on the reference trajectory at loose tolerances
    /// (rtol 1e-4: 0 of 5 trajectories left it at the full level, 4 of 5 with β = 0) for
    /// about 25 % more RHS evaluations at equal rtol (docs/research/step-control-strays.md).
    #[serde(default)]
    pub pi_beta: f64,
}

/// Smallest accepted relative tolerance. Below it the error estimate is dominated by round-off:
/// measured on the default scene (lumped, DOP853) rtol 1e-16 still runs at normal cost, 1e-18
/// crawls with 1e-9 s steps (7761 wall s per simulated s) instead of failing.
pub const MIN_RTOL: f64 = 1e-14;

/// Largest accepted β of the PI step-size controller (`solver.pi_beta`; 0 is the I-controller).
pub const MAX_PI_BETA: f64 = 0.2;

/// Why [`MIN_RTOL`] exists (for error messages).
pub const RTOL_FLOOR_WHY: &str =
    "the smallest relative tolerance double precision can honour here (below it the integrator crawls on round-off instead of failing)";

fn default_rtol() -> f64 {
    1e-6
}
fn default_max_steps() -> u64 {
    2_000_000
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            method: MethodName::default(),
            rtol: default_rtol(),
            max_steps: default_max_steps(),
            pi_beta: 0.0,
        }
    }
}

/// Output sampling of a CLI run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSettings {
    /// Simulated time \[s\].
    #[serde(default = "default_duration")]
    pub duration: f64,
    /// Output sample rate \[Hz\].
    #[serde(default = "default_sample_rate")]
    pub sample_rate: f64,
    /// Initial transient excluded from spectra \[s\] (docs/model.md#initial-state: 20 ms).
    #[serde(default = "default_skip")]
    pub skip: f64,
}

fn default_duration() -> f64 {
    0.2
}
fn default_sample_rate() -> f64 {
    51200.0
}
fn default_skip() -> f64 {
    0.02
}

impl Default for OutputSettings {
    fn default() -> Self {
        Self {
            duration: default_duration(),
            sample_rate: default_sample_rate(),
            skip: default_skip(),
        }
    }
}

/// The impact-test pulse (docs/model.md#c14): a triangle on the pedestal.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pulse {
    /// Peak force \[N\] (applied along −z).
    pub peak: f64,
    /// Total duration \[s\] (peak at half of it).
    pub duration: f64,
    /// Start time \[s\].
    pub t0: f64,
}

impl Pulse {
    /// Force along −z at time t \[N\] (a positive number).
    pub fn force(&self, t: f64) -> f64 {
        let s = (t - self.t0) / self.duration;
        if (0.0..=1.0).contains(&s) {
            self.peak * (1.0 - (2.0 * s - 1.0).abs())
        } else {
            0.0
        }
    }

    /// The first corner of the triangle (start, peak, end) after `t` (by more than 1e-15 s),
    /// where the force has a kink: a known-time stop for the integrators.
    pub fn next_kink(&self, t: f64) -> Option<f64> {
        [
            self.t0,
            self.t0 + 0.5 * self.duration,
            self.t0 + self.duration,
        ]
        .into_iter()
        .filter(|&tp| tp > t + 1e-15)
        .reduce(f64::min)
    }
}

/// A high-frequency resonator on the pedestal in z (L2 option, docs/model.md#l2).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Resonator {
    /// Natural frequency \[Hz\].
    pub frequency: f64,
    /// Damping ratio.
    pub damping_ratio: f64,
    /// Mass \[kg\].
    pub mass: f64,
}

/// Options of the lumped (L2) model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct LumpedOptions {
    /// Optional resonator; none by default.
    #[serde(default)]
    pub resonator: Option<Resonator>,
    /// Standard deviation of the random slip of each ball, as a fraction of the ball spacing,
    /// redrawn every cage revolution (Sawalhi–Randall); 0 = none.
    #[serde(default)]
    pub slip_jitter: f64,
    /// Seed of the slip jitter.
    #[serde(default)]
    pub seed: u64,
    /// Cage speed of the kinematic, quasi-static and lumped levels (their balls roll at it).
    #[serde(default)]
    pub cage_speed: CageSpeed,
}

/// Where the cage speed of the levels with kinematic balls comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum CageSpeed {
    /// The traction's caged balance: the common orbital rate at which the strip traction's
    /// orbital torques on the balls cancel, each ball in its steady spin
    /// ([`crate::models::traction_cage_speed`]). Default.
    #[default]
    Traction,
    /// L1's outer-race control (docs/model.md#l0, #l2, the textbook kinematics at the loaded angles).
    OuterRaceControl,
}

impl CageSpeed {
    /// The FMU parameter code: 0 traction, 1 outer-race control.
    pub fn code(self) -> i32 {
        match self {
            CageSpeed::Traction => 0,
            CageSpeed::OuterRaceControl => 1,
        }
    }

    /// The variant of an FMU parameter code.
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            0 => Some(CageSpeed::Traction),
            1 => Some(CageSpeed::OuterRaceControl),
            _ => None,
        }
    }
}

/// Options of the full (L4) model, table `[full]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FullSettings {
    /// Strip traction on (default) or frictionless contacts.
    #[serde(default = "yes")]
    pub traction: bool,
    /// Hold the inner-ring tilt at zero, as L1 does (default, decision D1 (docs/model.md#d1): a
    /// ring pressed on a shaft does not rock on its own; the spectra then match the paper's).
    /// Off, the ring tilts with the shaft's tilt inertia and tilt stiffness below.
    #[serde(default = "yes")]
    pub lock_tilt: bool,
    /// Free tilt only: the shaft's diametral moment of inertia about the bearing that the ring
    /// carries in addition to its own \[kg m²\] (default 0.21, docs/model.md#d1).
    #[serde(default = "shaft_tilt_inertia")]
    pub shaft_tilt_inertia: f64,
    /// Free tilt only: the shaft's tilt stiffness about the bearing (the other bearing, the
    /// shaft's bending) \[N m/rad\] (default 3.2e7, docs/model.md#d1).
    #[serde(default = "tilt_stiffness")]
    pub tilt_stiffness: f64,
    /// A cage at the reduced and full levels (default; docs/model.md#cage, its constants from
    /// the bearing file's `[cage]`). Off is the paper's cage-less bearing (docs/model.md#c11):
    /// the balls keep their spacing by their own dynamics and touch each other when they drift
    /// together (docs/model.md#ball-ball); the scenes that reproduce the paper say so.
    #[serde(default = "yes")]
    pub cage: bool,
}

/// Default shaft tilt inertia \[kg m²\]: a Ø40 mm, 400 mm steel shaft (3.9 kg) pivoting about
/// its far end, m L²/3 (docs/model.md#d1).
pub const SHAFT_TILT_INERTIA: f64 = 0.21;
/// Default tilt stiffness \[N m/rad\]: the other bearing, 2e8 N/m radially, 0.4 m away, k L²
/// (docs/model.md#d1).
pub const TILT_STIFFNESS: f64 = 3.2e7;

fn shaft_tilt_inertia() -> f64 {
    SHAFT_TILT_INERTIA
}

fn tilt_stiffness() -> f64 {
    TILT_STIFFNESS
}

fn yes() -> bool {
    true
}

impl Default for FullSettings {
    fn default() -> Self {
        Self {
            traction: true,
            lock_tilt: true,
            shaft_tilt_inertia: SHAFT_TILT_INERTIA,
            tilt_stiffness: TILT_STIFFNESS,
            cage: true,
        }
    }
}

/// How the bearing is cut from the shaft (scene table `[coupling]`, FMU parameter `coupling`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CouplingMode {
    /// Loads in (`load.F*`), the inner ring integrated inside (code 0, the default).
    #[default]
    Force,
    /// The journal's (inner-ring centre's) displacement and velocity in, the bearing's reaction
    /// on the journal out; the loads only set the quasi-static start (code 1).
    Motion,
}

impl CouplingMode {
    /// The FMU's integer code.
    pub fn code(self) -> i32 {
        match self {
            CouplingMode::Force => 0,
            CouplingMode::Motion => 1,
        }
    }

    /// The mode of an FMU code; None for an unknown code.
    pub fn from_code(code: i32) -> Option<Self> {
        match code {
            0 => Some(CouplingMode::Force),
            1 => Some(CouplingMode::Motion),
            _ => None,
        }
    }

    /// The mode's name in scene files (`force`, `motion`).
    pub fn name(self) -> &'static str {
        match self {
            CouplingMode::Force => "force",
            CouplingMode::Motion => "motion",
        }
    }

    /// The mode of a scene-file name; None for an unknown name.
    pub fn from_name(s: &str) -> Option<Self> {
        [CouplingMode::Force, CouplingMode::Motion]
            .into_iter()
            .find(|m| m.name() == s)
    }
}

/// The `[coupling]` table as written (the mode is checked by name in [`Scene::from_toml_str`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CouplingFile {
    #[serde(default = "default_coupling_mode")]
    mode: String,
}

fn default_coupling_mode() -> String {
    "force".into()
}

impl Default for CouplingFile {
    fn default() -> Self {
        Self {
            mode: default_coupling_mode(),
        }
    }
}

/// Where the bearing description comes from in a scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum BearingRef {
    /// Preset name or path.
    Named(String),
    /// Inline description.
    Inline(Box<BearingFile>),
}

/// How the inner ring is held along the shaft axis (table `[mounting]`, FMU parameter
/// `ring.axial`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Mounting {
    /// `load` (default): the axial load Fa acts on the ring, which finds its own axial position;
    /// `located`: the ring is held axially (pressed against a shaft shoulder), the bearing takes
    /// whatever axial force the radial load needs, and `bearing.F.x` is that axial reaction.
    #[serde(default)]
    pub axial: AxialMount,
    /// Located ring: its axial displacement \[m\] from the unloaded, centred position (+x is the
    /// way an axial load Fa > 0 pushes it; 0: the balls just touch both grooves). By default
    /// where the start's axial load Fa alone puts it (a preload; 0 without Fa).
    #[serde(default)]
    pub axial_offset: Option<f64>,
}

/// The inner ring's axial boundary condition ([`Mounting::axial`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum AxialMount {
    /// The axial load acts on the ring (force-controlled axially).
    #[default]
    Load,
    /// The ring's axial displacement is held.
    Located,
}

/// A scene file as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    #[serde(default)]
    name: String,
    #[serde(default = "default_bearing")]
    bearing: BearingRef,
    #[serde(default)]
    fidelity: Fidelity,
    operating: OperatingTable,
    #[serde(default)]
    defect: Option<Spalls>,
    #[serde(default)]
    solver: SolverSettings,
    #[serde(default)]
    output: OutputSettings,
    #[serde(default)]
    pulse: Option<Pulse>,
    #[serde(default)]
    lumped: LumpedOptions,
    #[serde(default)]
    full: FullSettings,
    #[serde(default)]
    coupling: CouplingFile,
    #[serde(default)]
    mounting: Mounting,
    #[serde(default)]
    waviness: Option<WavinessSpec>,
    #[serde(default)]
    roughness: Option<RoughnessSpec>,
}

/// The scene file's `defect` key: one table `[defect]` (one spall, as always) or an array of
/// tables `[[defect]]` (any number of spalls). A parse error inside the array names the entry,
/// `defect[k]: ...` (k from 0).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
enum Spalls {
    /// `[defect]`.
    One(DefectSpec),
    /// `[[defect]]`.
    Many(Vec<SpallEntry>),
}

/// One entry of a `[[defect]]` array: a [`DefectSpec`] and, optionally, its own mode.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct SpallEntry {
    ring: crate::defect::RingWord,
    width: f64,
    depth: f64,
    #[serde(default)]
    theta0: f64,
    /// The ball's number with `ring = "ball"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    ball: Option<i64>,
    /// `"finite"` or `"point"`; absent: the bearing's `[defect] mode`.
    #[serde(default)]
    mode: Option<DefectMode>,
}

impl<'de> Deserialize<'de> for Spalls {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = Spalls;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a table [defect] or an array of tables [[defect]]")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Spalls, A::Error> {
                DefectSpec::deserialize(serde::de::value::MapAccessDeserializer::new(map))
                    .map(Spalls::One)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Spalls, A::Error> {
                let mut all = Vec::new();
                loop {
                    match seq.next_element::<SpallEntry>() {
                        Ok(Some(s)) => all.push(s),
                        Ok(None) => return Ok(Spalls::Many(all)),
                        Err(e) => {
                            return Err(serde::de::Error::custom(format!(
                                "defect[{}]: {e}",
                                all.len()
                            )))
                        }
                    }
                }
            }
        }
        d.deserialize_any(V)
    }
}

fn default_bearing() -> BearingRef {
    BearingRef::Named(crate::config::DEFAULT_PRESET.to_string())
}

/// A resolved scene: everything a [`crate::simulation::Simulation`] needs.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The scene's name (for reports and output headers).
    pub name: String,
    /// The bearing, resolved from the file's preset name or path.
    pub bearing: BearingFile,
    /// The fidelity level to simulate at.
    pub fidelity: Fidelity,
    /// Shaft speed and loads (the file's `[operating]` table, in SI units).
    pub operating: OperatingPoint,
    /// The spall (table `[defect]`), or the first of several (`[[defect]]`, entry 0); None for
    /// a healthy bearing.
    pub defect: Option<DefectSpec>,
    /// The second and later spalls of a `[[defect]]` array (entries 1, 2, ...); empty with one
    /// spall or none, and only allowed with a first one in `defect`. [`Scene::defects`] lists
    /// them all.
    pub more_defects: Vec<DefectSpec>,
    /// Each spall's own mode, in the order of [`Scene::defects`] (the `mode` key of a
    /// `[[defect]]` entry): None, or no entry at all (the `[defect]` table, an empty list),
    /// takes the bearing's `[defect] mode`.
    pub defect_modes: Vec<Option<DefectMode>>,
    /// Integration method and tolerances (table `[solver]`).
    pub solver: SolverSettings,
    /// Duration, sampling and output selection (table `[output]`).
    pub output: OutputSettings,
    /// Optional force pulse on the pedestal (table `[pulse]`).
    pub pulse: Option<Pulse>,
    /// Options of the lumped level (table `[lumped]`).
    pub lumped: LumpedOptions,
    /// Options of the ball-level models (table `[full]`).
    pub full: FullSettings,
    /// Force (default) or motion coupling (table `[coupling]`, key `mode`).
    pub coupling: CouplingMode,
    /// How the inner ring is held axially (table `[mounting]`).
    pub mounting: Mounting,
    /// Harmonic waviness of races and balls, off-size balls (table `[waviness]`); None: none.
    pub waviness: Option<WavinessSpec>,
    /// Random roughness of the race tracks (table `[roughness]`); None: smooth tracks.
    pub roughness: Option<RoughnessSpec>,
}

impl Scene {
    /// The default scene: Table-1 bearing, 9900 rpm, Fa 4000 N, Fr 1000 N, outer-race spall
    /// 1.0 × 0.2 mm at the load-zone centre, lumped level.
    pub fn default_scene() -> Self {
        Self::from_toml_str(DEFAULT_SCENE, "default scene", None).expect("default scene is valid")
    }

    /// A healthy scene on a bearing at an operating point.
    pub fn healthy(bearing: BearingFile, operating: OperatingPoint) -> Self {
        Self {
            name: "healthy".into(),
            bearing,
            fidelity: Fidelity::default(),
            operating,
            defect: None,
            more_defects: Vec::new(),
            defect_modes: Vec::new(),
            solver: SolverSettings::default(),
            output: OutputSettings::default(),
            pulse: None,
            lumped: LumpedOptions::default(),
            full: FullSettings::default(),
            coupling: CouplingMode::Force,
            mounting: Mounting::default(),
            waviness: None,
            roughness: None,
        }
    }

    /// Reads a scene file; bearing paths are relative to the file's folder.
    pub fn load(path: &Path) -> Result<Self, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            ConfigError::new("", format!("cannot read scene {}: {e}", path.display()))
        })?;
        Self::from_toml_str(&text, &path.display().to_string(), path.parent())
    }

    /// Parses a scene from TOML text.
    pub fn from_toml_str(
        text: &str,
        origin: &str,
        dir: Option<&Path>,
    ) -> Result<Self, ConfigError> {
        let file: SceneFile = toml::from_str(text)
            .map_err(|e| ConfigError::new("", format!("{origin}: {}", e.to_string().trim_end())))?;
        let bearing = match file.bearing {
            BearingRef::Inline(b) => {
                b.validate()?;
                *b
            }
            BearingRef::Named(name) => {
                let is_preset = crate::config::PRESETS.iter().any(|(n, _)| *n == name);
                // An unreadable file is the scene's `bearing` key's error.
                let named = |e: ConfigError| match e.field.is_empty() {
                    true => ConfigError::new("bearing", format!("{origin}: {}", e.message)),
                    false => e,
                };
                if is_preset {
                    BearingFile::load(&name)?
                } else {
                    let p = match dir {
                        Some(d) => d.join(&name),
                        None => name.into(),
                    };
                    BearingFile::load(&p.to_string_lossy()).map_err(named)?
                }
            }
        };
        let coupling = CouplingMode::from_name(&file.coupling.mode).ok_or_else(|| {
            ConfigError::new(
                "coupling.mode",
                format!(
                    "{origin}: '{}' is not a coupling mode; valid: 'force' (loads in), 'motion' (journal displacement and velocity in)",
                    file.coupling.mode
                ),
            )
        })?;
        let (defect, more_defects, defect_modes) = match file.defect {
            None => (None, Vec::new(), Vec::new()),
            Some(Spalls::One(d)) => (Some(d), Vec::new(), Vec::new()),
            Some(Spalls::Many(all)) => {
                // Modes only when an entry has one: a list of Nones is the bearing's mode for
                // all, which an empty list says (one entry then equals the [defect] table).
                let modes: Vec<Option<DefectMode>> = all.iter().map(|e| e.mode).collect();
                let modes = if modes.iter().any(Option::is_some) {
                    modes
                } else {
                    Vec::new()
                };
                let several = all.len() > 1;
                let mut specs = Vec::with_capacity(all.len());
                for (k, e) in all.into_iter().enumerate() {
                    let ring = crate::defect::site_of(e.ring, e.ball)
                        .map_err(|err| crate::defect::indexed_error(err, k, several))?;
                    specs.push(DefectSpec {
                        ring,
                        width: e.width,
                        depth: e.depth,
                        theta0: e.theta0,
                    });
                }
                let mut specs = specs.into_iter();
                let first = specs.next();
                (first, specs.collect(), modes)
            }
        };
        let scene = Scene {
            name: file.name,
            bearing,
            fidelity: file.fidelity,
            operating: file.operating.into(),
            defect,
            more_defects,
            defect_modes,
            solver: file.solver,
            output: file.output,
            pulse: file.pulse,
            lumped: file.lumped,
            full: file.full,
            coupling,
            mounting: file.mounting,
            waviness: file.waviness,
            roughness: file.roughness,
        };
        scene.validate()?;
        Ok(scene)
    }

    /// Every spall of the scene, in file order: `defect`, then `more_defects`.
    pub fn defects(&self) -> impl Iterator<Item = &DefectSpec> + '_ {
        self.defect.iter().chain(self.more_defects.iter())
    }

    /// Every spall with its own mode (None: the bearing's `[defect] mode`), in file order.
    pub fn spalls(&self) -> impl Iterator<Item = (&DefectSpec, Option<DefectMode>)> + '_ {
        self.defects()
            .enumerate()
            .map(|(k, d)| (d, self.defect_modes.get(k).copied().flatten()))
    }

    /// Number of spalls.
    pub fn n_defects(&self) -> usize {
        self.defects().count()
    }

    /// Replaces the spalls: the first becomes `defect`, the rest `more_defects` (none: healthy);
    /// their modes are the bearing's (`defect_modes` cleared).
    pub fn set_defects(&mut self, mut all: Vec<DefectSpec>) {
        self.defect_modes.clear();
        if all.is_empty() {
            self.defect = None;
            self.more_defects.clear();
        } else {
            self.defect = Some(all.remove(0));
            self.more_defects = all;
        }
    }

    /// Checks every value of the scene (the bearing is validated separately).
    pub fn validate(&self) -> Result<(), ConfigError> {
        let finite = |field: &str, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(ConfigError::new(
                    field,
                    format!("{v} is not a finite number"),
                ))
            }
        };
        let positive = |field: &str, v: f64| {
            finite(field, v)?;
            if v > 0.0 {
                Ok(())
            } else {
                Err(ConfigError::new(field, format!("{v} must be > 0")))
            }
        };
        finite("operating.speed_rpm", self.operating.shaft_speed)?;
        if self.operating.shaft_speed < 0.0 {
            return Err(ConfigError::new(
                "operating.speed_rpm",
                "must be ≥ 0 (the shaft turns about +x)",
            ));
        }
        finite("operating.fa", self.operating.fx)?;
        finite("operating.fr", self.operating.fz)?;
        finite("operating.fy", self.operating.fy)?;
        match (self.mounting.axial, self.mounting.axial_offset) {
            (_, Some(d)) if !d.is_finite() => {
                return Err(ConfigError::new(
                    "mounting.axial_offset",
                    format!("{d} is not a finite number"),
                ))
            }
            (AxialMount::Load, Some(_)) => {
                return Err(ConfigError::new(
                    "mounting.axial_offset",
                    "applies to a located ring only: set mounting.axial = \"located\" (with \
                     axial = \"load\" the axial load Fa sets the ring's axial position)",
                ))
            }
            (AxialMount::Located, _) if self.coupling == CouplingMode::Motion => {
                return Err(ConfigError::new(
                    "mounting.axial",
                    "a located ring is a force-coupling setting: in coupling mode 'motion' the \
                     journal's axial displacement is an input already",
                ))
            }
            _ => {}
        }
        for (field, v) in [
            ("full.shaft_tilt_inertia", self.full.shaft_tilt_inertia),
            ("full.tilt_stiffness", self.full.tilt_stiffness),
        ] {
            finite(field, v)?;
            if v < 0.0 {
                return Err(ConfigError::new(field, format!("{v} must be ≥ 0")));
            }
        }
        positive("solver.rtol", self.solver.rtol)?;
        if self.solver.rtol >= 0.1 {
            return Err(ConfigError::new("solver.rtol", "must be < 0.1"));
        }
        if self.solver.rtol < MIN_RTOL {
            return Err(ConfigError::new(
                "solver.rtol",
                format!(
                    "{} is below {MIN_RTOL:e}, {RTOL_FLOOR_WHY}",
                    self.solver.rtol
                ),
            ));
        }
        if self.solver.max_steps == 0 {
            return Err(ConfigError::new("solver.max_steps", "must be ≥ 1"));
        }
        if !(0.0..=MAX_PI_BETA).contains(&self.solver.pi_beta) {
            return Err(ConfigError::new(
                "solver.pi_beta",
                format!(
                    "{} must be in [0, {MAX_PI_BETA}] (0: I-controller; 0.04–0.08: PI controller)",
                    self.solver.pi_beta
                ),
            ));
        }
        positive("output.duration", self.output.duration)?;
        positive("output.sample_rate", self.output.sample_rate)?;
        finite("output.skip", self.output.skip)?;
        if self.output.skip < 0.0 {
            return Err(ConfigError::new("output.skip", "must be ≥ 0"));
        }
        if let Some(p) = &self.pulse {
            finite("pulse.peak", p.peak)?;
            positive("pulse.duration", p.duration)?;
            finite("pulse.t0", p.t0)?;
        }
        if let Some(r) = &self.lumped.resonator {
            positive("lumped.resonator.frequency", r.frequency)?;
            finite("lumped.resonator.damping_ratio", r.damping_ratio)?;
            if r.damping_ratio < 0.0 {
                return Err(ConfigError::new(
                    "lumped.resonator.damping_ratio",
                    "must be ≥ 0",
                ));
            }
            positive("lumped.resonator.mass", r.mass)?;
        }
        finite("lumped.slip_jitter", self.lumped.slip_jitter)?;
        if !(0.0..0.5).contains(&self.lumped.slip_jitter) {
            return Err(ConfigError::new(
                "lumped.slip_jitter",
                "must lie in [0, 0.5) (a fraction of the ball spacing)",
            ));
        }
        if self.defect.is_none() && !self.more_defects.is_empty() {
            return Err(ConfigError::new(
                "defect",
                format!(
                    "{} later spall(s) but no first one (Scene::defect is None)",
                    self.more_defects.len()
                ),
            ));
        }
        if self.defect_modes.len() > self.n_defects() {
            return Err(ConfigError::new(
                "defect",
                format!(
                    "{} spall modes for {} spall(s)",
                    self.defect_modes.len(),
                    self.n_defects()
                ),
            ));
        }
        let several = !self.more_defects.is_empty();
        for (k, d) in self.defects().enumerate() {
            d.validate()
                .map_err(|e| crate::defect::indexed_error(e, k, several))?;
        }
        if let Some(w) = &self.waviness {
            w.validate()?;
        }
        if let Some(r) = &self.roughness {
            r.validate()?;
        }
        Ok(())
    }
}

/// The default scene's TOML text (also shipped in the FMU's resources).
pub const DEFAULT_SCENE: &str = include_str!("../examples/scenes/default.toml");
