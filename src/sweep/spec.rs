//! The sweep file: base scene, axes, what to keep, and the expansion into runs.

use super::SweepError;
use crate::defect::{DefectSpec, Site};
use crate::scene::{Fidelity, Scene};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One value of an axis: a number or a word (ring and fidelity names).
#[derive(Debug, Clone, PartialEq)]
pub enum AxisValue {
    /// A number (TOML integers are converted to `f64`).
    Num(f64),
    /// A word, e.g. `"outer"` for `defect.ring` or `"lumped"` for `fidelity`.
    Text(String),
}

impl AxisValue {
    /// The canonical text of the value: the shortest round-trip decimal of a number, or the
    /// word itself. Run ids hash this text and results.csv stores it.
    pub fn canonical(&self) -> String {
        match self {
            AxisValue::Num(v) => format!("{v:?}"),
            AxisValue::Text(s) => s.clone(),
        }
    }
}

/// What a key accepts.
#[derive(Debug, Clone, Copy, PartialEq)]
enum KeyKind {
    /// A number.
    Number,
    /// `defect.ring`: none/outer/inner/ball or the FMU codes 0/1/2/3.
    Ring,
    /// `fidelity`: a level name or its code 0..4.
    Fidelity,
    /// `lumped.seed`: an integer ≥ 0, or `"run"` (derived from the run id).
    Seed,
    /// `defect.blend_length`: a length in metres, or `"b"` (the contact ellipse's semi-minor
    /// axis), as in the bearing file.
    Blend,
    /// An on/off switch (`full.cage`): true or false (TOML booleans, or 1 and 0).
    Switch,
}

/// The keys an axis may sweep, with what they accept.
const KEYS: &[(&str, KeyKind)] = &[
    ("defect.ring", KeyKind::Ring),
    ("defect.ball", KeyKind::Number),
    ("defect.width", KeyKind::Number),
    ("defect.depth", KeyKind::Number),
    ("defect.theta0", KeyKind::Number),
    ("defect.blend_length", KeyKind::Blend),
    ("operating.speed_rpm", KeyKind::Number),
    ("operating.fa", KeyKind::Number),
    ("operating.fr", KeyKind::Number),
    ("operating.fy", KeyKind::Number),
    ("fidelity", KeyKind::Fidelity),
    ("full.cage", KeyKind::Switch),
    ("lumped.seed", KeyKind::Seed),
    ("lumped.slip_jitter", KeyKind::Number),
    ("noise.rms", KeyKind::Number),
    ("output.duration", KeyKind::Number),
    ("output.sample_rate", KeyKind::Number),
    ("output.skip", KeyKind::Number),
    ("solver.rtol", KeyKind::Number),
    ("solver.pi_beta", KeyKind::Number),
];

/// The keys an axis may sweep (also accepted in `[set]`).
pub fn known_keys() -> Vec<&'static str> {
    KEYS.iter().map(|(k, _)| *k).collect()
}

/// `defect[k].field` (one spall of several, k from 0 in `[[defect]]` order) as (k, field),
/// for the fields `ring`, `width`, `depth` and `theta0`.
pub fn indexed_defect_key(key: &str) -> Option<(usize, &str)> {
    let rest = key.strip_prefix("defect[")?;
    let (k, field) = rest.split_once("].")?;
    let k = k.parse().ok()?;
    ["ring", "ball", "width", "depth", "theta0"]
        .contains(&field)
        .then_some((k, field))
}

fn key_kind(key: &str) -> Result<KeyKind, SweepError> {
    if let Some((_, field)) = indexed_defect_key(key) {
        return Ok(if field == "ring" {
            KeyKind::Ring
        } else {
            KeyKind::Number
        });
    }
    KEYS.iter()
        .find(|(k, _)| *k == key)
        .map(|(_, kind)| *kind)
        .ok_or_else(|| {
            SweepError::new(format!(
                "unknown sweep key '{key}'; known keys: {}",
                known_keys().join(", ")
            ))
        })
}

/// The defect a ring value asks for: `None` = healthy.
fn parse_ring(key: &str, v: &AxisValue) -> Result<Option<Site>, String> {
    match v {
        AxisValue::Text(s) if s == "none" || s == "healthy" => Ok(None),
        AxisValue::Text(s) if s == "outer" => Ok(Some(Site::Outer)),
        AxisValue::Text(s) if s == "inner" => Ok(Some(Site::Inner)),
        AxisValue::Text(s) if s == "ball" => Ok(Some(Site::Ball(1))),
        AxisValue::Num(c) if *c == 0.0 => Ok(None),
        AxisValue::Num(c) if *c == 1.0 => Ok(Some(Site::Outer)),
        AxisValue::Num(c) if *c == 2.0 => Ok(Some(Site::Inner)),
        AxisValue::Num(c) if *c == 3.0 => Ok(Some(Site::Ball(1))),
        other => Err(format!(
            "{key} = {}: expected none, outer, inner, ball (or the codes 0, 1, 2, 3)",
            other.canonical()
        )),
    }
}

/// The site a ring value gives a spall now at `old`: a ball spall keeps its ball's number (the
/// ring value `ball` says ball 1 only for a spall that was not on a ball).
fn keep_ball(old: Site, new: Site) -> Site {
    match (old, new) {
        (Site::Ball(n), Site::Ball(_)) => Site::Ball(n),
        _ => new,
    }
}

/// A ball number (`defect.ball`): an integer ≥ 1.
fn parse_ball(key: &str, x: f64) -> Result<usize, String> {
    if x >= 1.0 && x.fract() == 0.0 && x < 1e6 {
        Ok(x as usize)
    } else {
        Err(format!(
            "{key} = {x}: expected a ball number (an integer ≥ 1)"
        ))
    }
}

/// An on/off value: `true`/`false` (a TOML boolean arrives as that word) or 1/0.
fn parse_switch(key: &str, v: &AxisValue) -> Result<bool, String> {
    match v {
        AxisValue::Text(s) if s == "true" => Ok(true),
        AxisValue::Text(s) if s == "false" => Ok(false),
        AxisValue::Num(c) if *c == 1.0 => Ok(true),
        AxisValue::Num(c) if *c == 0.0 => Ok(false),
        other => Err(format!(
            "{key} = {}: expected true or false (or 1, 0)",
            other.canonical()
        )),
    }
}

fn parse_fidelity(key: &str, v: &AxisValue) -> Result<Fidelity, String> {
    let f = match v {
        AxisValue::Text(s) => Fidelity::from_name(s),
        AxisValue::Num(c) if c.fract() == 0.0 && c.abs() < 100.0 => Fidelity::from_code(*c as i32),
        AxisValue::Num(_) => None,
    };
    f.ok_or_else(|| {
        format!(
            "{key} = {}: expected kinematic, quasi_static, lumped, reduced, full (or 0..4)",
            v.canonical()
        )
    })
}

/// Checks that a value has the kind its key needs (a sweep-file error, not a failed run) and
/// returns it in canonical form: rings and levels as names (`1` → `outer`, `2` → `lumped`), so
/// equal settings give equal run ids.
fn normalize(key: &str, v: &AxisValue) -> Result<AxisValue, SweepError> {
    let kind = key_kind(key)?;
    let r = match kind {
        KeyKind::Number => match v {
            AxisValue::Num(_) => Ok(v.clone()),
            AxisValue::Text(s) => Err(format!("{key} = \"{s}\": expected a number")),
        },
        KeyKind::Ring => {
            parse_ring(key, v).map(|r| AxisValue::Text(r.map_or("none", |r| r.name()).to_string()))
        }
        KeyKind::Fidelity => parse_fidelity(key, v).map(|f| AxisValue::Text(f.name().into())),
        KeyKind::Switch => parse_switch(key, v).map(|b| AxisValue::Text(b.to_string())),
        KeyKind::Seed => match v {
            AxisValue::Num(_) => Ok(v.clone()),
            AxisValue::Text(s) if s == "run" => Ok(v.clone()),
            AxisValue::Text(s) => Err(format!(
                "{key} = \"{s}\": expected an integer or \"run\" (a seed derived from the run id)"
            )),
        },
        KeyKind::Blend => match v {
            AxisValue::Num(_) => Ok(v.clone()),
            AxisValue::Text(s) if s == "b" => Ok(v.clone()),
            AxisValue::Text(s) => Err(format!(
                "{key} = \"{s}\": expected a length in metres (0 = abrupt) or \"b\" (the contact \
                 ellipse's semi-minor axis)"
            )),
        },
    };
    r.map_err(SweepError::new)
}

/// An axis of the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The swept key, e.g. `defect.width`.
    pub key: String,
    /// Its values, in order.
    pub values: Vec<AxisValue>,
}

/// Which quantities every run records (the `[keep]` table).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Keep {
    /// Output analysed for the signal metrics (default `pedestal.a.z`).
    #[serde(default = "default_signal")]
    pub signal: String,
    /// Envelope band-pass \[Hz\] (default 2000–12000 Hz, clamped to Nyquist).
    #[serde(default = "default_band")]
    pub band: [f64; 2],
    /// Envelope-spectrum amplitudes at FTF, BPFO and BPFI and their harmonics.
    #[serde(default = "yes")]
    pub envelope_peaks: bool,
    /// Number of harmonics of each fault frequency (1 = the fundamental only).
    #[serde(default = "default_harmonics")]
    pub harmonics: usize,
    /// Relative search tolerance of each envelope peak (default 0.03 = ±3 %).
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// RMS of the (mean-removed) signal.
    #[serde(default = "yes")]
    pub rms: bool,
    /// Kurtosis E\[x⁴\]/E\[x²\]² of the mean-removed signal (3 for Gaussian noise).
    #[serde(default = "yes")]
    pub kurtosis: bool,
    /// Crest factor max|x|/RMS of the mean-removed signal.
    #[serde(default = "yes")]
    pub crest_factor: bool,
    /// Largest ball–race normal force after the skipped transient, both races and per race, and
    /// `impact_q_median`: the median over ball passes of the largest force on the defective race.
    #[serde(default = "yes")]
    pub max_contact_force: bool,
    /// Write the analysed signal of each run to `signals/run-<index>-<id>.csv`.
    #[serde(default)]
    pub raw_signal: bool,
}

fn yes() -> bool {
    true
}
fn default_signal() -> String {
    "pedestal.a.z".into()
}
fn default_band() -> [f64; 2] {
    [2000.0, 12000.0]
}
fn default_harmonics() -> usize {
    3
}
fn default_tolerance() -> f64 {
    0.03
}

impl Default for Keep {
    fn default() -> Self {
        toml::from_str("").expect("all keep fields have defaults")
    }
}

/// The sweep file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepFile {
    #[serde(default)]
    name: String,
    /// Path of the base scene, relative to the sweep file.
    #[serde(default)]
    base: Option<String>,
    /// Inline base scene (the scene-file format).
    #[serde(default)]
    scene: Option<toml::Table>,
    /// Fixed values applied to every run (same keys as the axes).
    #[serde(default)]
    set: BTreeMap<String, toml::Value>,
    #[serde(default)]
    axes: BTreeMap<String, toml::Value>,
    #[serde(default)]
    keep: Keep,
}

/// One run of the grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Position in the grid (axes in alphabetical key order, the last one fastest).
    pub index: usize,
    /// Stable id: FNV-1a 64 of the canonical `key=value;...` text of the parameters, in hex.
    pub id: String,
    /// The swept parameters of this run, in axis order.
    pub params: Vec<(String, AxisValue)>,
}

/// A parsed sweep: base scene, fixed values, axes and what to keep.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// Name of the study (informational).
    pub name: String,
    /// The base scene every run starts from.
    pub base: Scene,
    /// Fixed values applied before the axis values.
    pub set: Vec<(String, AxisValue)>,
    /// The axes, sorted by key.
    pub axes: Vec<Axis>,
    /// What every run records.
    pub keep: Keep,
}

/// The dotted key at the line a TOML parse error names (`line N`) in `text`: the last table
/// header above it and the key on that line.
fn scene_key_at(text: &str, error: &str) -> Option<String> {
    let after = error.split("line ").nth(1)?;
    let n: usize = after
        .split(|c: char| !c.is_ascii_digit())
        .next()?
        .parse()
        .ok()?;
    let lines: Vec<&str> = text.lines().collect();
    let line = lines.get(n.checked_sub(1)?)?;
    let key = line
        .split_once('=')
        .map(|(k, _)| k.trim().trim_matches('"'))?;
    let table = lines[..n - 1]
        .iter()
        .rev()
        .find(|l| l.trim_start().starts_with('['))
        .map(|l| l.trim().trim_matches(|c| c == '[' || c == ']').to_string());
    Some(match table {
        Some(t) => format!("{t}.{key}"),
        None => key.to_string(),
    })
}

/// FNV-1a, 64 bit: a tiny, fully specified hash (stable across Rust versions and machines).
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= u64::from(*b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

fn value_of(key: &str, v: &toml::Value) -> Result<AxisValue, SweepError> {
    match v {
        toml::Value::Float(f) => Ok(AxisValue::Num(*f)),
        toml::Value::Integer(i) => Ok(AxisValue::Num(*i as f64)),
        toml::Value::String(s) => Ok(AxisValue::Text(s.clone())),
        toml::Value::Boolean(b) => Ok(AxisValue::Text(b.to_string())),
        other => Err(SweepError::new(format!(
            "{key}: {other} is neither a number nor a word"
        ))),
    }
}

fn num_field(key: &str, t: &toml::Table, field: &str) -> Result<Option<f64>, SweepError> {
    match t.get(field) {
        None => Ok(None),
        Some(toml::Value::Float(f)) if f.is_finite() => Ok(Some(*f)),
        Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
        Some(other) => Err(SweepError::new(format!(
            "axes.{key}.{field} = {other}: expected a finite number"
        ))),
    }
}

/// Values of an axis: a list, or a range `{ start, stop, num }` (inclusive, evenly spaced) or
/// `{ start, stop, step }` (start + k·step up to stop, inclusive within 1e-9 step).
fn axis_values(key: &str, v: &toml::Value) -> Result<Vec<AxisValue>, SweepError> {
    let values = match v {
        toml::Value::Array(items) => items
            .iter()
            .map(|x| value_of(key, x))
            .collect::<Result<Vec<_>, _>>()?,
        toml::Value::Table(t) => {
            for k in t.keys() {
                if !["start", "stop", "num", "step"].contains(&k.as_str()) {
                    return Err(SweepError::new(format!(
                        "axes.{key}: unknown range field '{k}' (use start, stop and num or step)"
                    )));
                }
            }
            let start = num_field(key, t, "start")?;
            let stop = num_field(key, t, "stop")?;
            let (Some(start), Some(stop)) = (start, stop) else {
                return Err(SweepError::new(format!(
                    "axes.{key}: a range needs start and stop"
                )));
            };
            match (num_field(key, t, "num")?, num_field(key, t, "step")?) {
                (Some(n), None) => {
                    if !(n >= 1.0 && n.fract() == 0.0 && n <= 1e6) {
                        return Err(SweepError::new(format!(
                            "axes.{key}.num = {n}: expected an integer ≥ 1"
                        )));
                    }
                    let n = n as usize;
                    if n == 1 {
                        vec![AxisValue::Num(start)]
                    } else {
                        (0..n)
                            .map(|k| {
                                let s = k as f64 / (n - 1) as f64;
                                AxisValue::Num(if k == n - 1 {
                                    stop
                                } else {
                                    start + (stop - start) * s
                                })
                            })
                            .collect()
                    }
                }
                (None, Some(step)) => {
                    if !(step != 0.0 && (stop - start) / step >= 0.0) {
                        return Err(SweepError::new(format!(
                            "axes.{key}.step = {step}: must be non-zero and lead from start to stop"
                        )));
                    }
                    let count = ((stop - start) / step + 1e-9).floor();
                    if count > 1e6 {
                        return Err(SweepError::new(format!(
                            "axes.{key}: more than a million values"
                        )));
                    }
                    (0..=count as usize)
                        .map(|k| AxisValue::Num(start + k as f64 * step))
                        .collect()
                }
                _ => {
                    return Err(SweepError::new(format!(
                        "axes.{key}: give exactly one of num and step"
                    )))
                }
            }
        }
        other => vec![value_of(key, other)?],
    };
    if values.is_empty() {
        return Err(SweepError::new(format!("axes.{key}: no values")));
    }
    let values = values
        .iter()
        .map(|v| normalize(key, v))
        .collect::<Result<Vec<_>, _>>()?;
    for (i, a) in values.iter().enumerate() {
        if let AxisValue::Num(x) = a {
            if !x.is_finite() {
                return Err(SweepError::new(format!("axes.{key}: {x} is not finite")));
            }
        }
        if values[..i].iter().any(|b| b.canonical() == a.canonical()) {
            return Err(SweepError::new(format!(
                "axes.{key}: value {} appears twice",
                a.canonical()
            )));
        }
    }
    Ok(values)
}

impl Sweep {
    /// Reads a sweep file; `base` and scene-relative bearing paths are relative to its folder.
    pub fn load(path: &Path) -> Result<Self, SweepError> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SweepError::new(format!("cannot read {}: {e}", path.display())))?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Self::from_toml_str(&text, &path.display().to_string(), &dir)
    }

    /// Parses a sweep from TOML text; `dir` resolves relative paths.
    pub fn from_toml_str(text: &str, origin: &str, dir: &Path) -> Result<Self, SweepError> {
        let file: SweepFile = toml::from_str(text)
            .map_err(|e| SweepError::new(format!("{origin}: {}", e.to_string().trim_end())))?;
        let base = match (&file.base, &file.scene) {
            (Some(_), Some(_)) => {
                return Err(SweepError::new(format!(
                    "{origin}: give either base = \"scene.toml\" or an inline [scene], not both"
                )))
            }
            (None, None) => {
                return Err(SweepError::new(format!(
                    "{origin}: no base scene: add base = \"path/to/scene.toml\" or a [scene] table"
                )))
            }
            (Some(p), None) => {
                let p: PathBuf = dir.join(p);
                Scene::load(&p).map_err(|e| SweepError::new(format!("base scene: {e}")))?
            }
            (None, Some(t)) => {
                let text = toml::to_string(t).map_err(|e| SweepError::new(e.to_string()))?;
                Scene::from_toml_str(&text, &format!("{origin} [scene]"), Some(dir)).map_err(
                    |e| {
                        // A parse error points into the re-serialized table: name the key.
                        let at = scene_key_at(&text, &e.to_string())
                            .map(|k| format!(" (at scene.{k})"))
                            .unwrap_or_default();
                        SweepError::new(format!("[scene]{at}: {e}"))
                    },
                )?
            }
        };
        let mut set = Vec::new();
        for (k, v) in &file.set {
            let v = normalize(k, &value_of(k, v)?)?;
            set.push((k.clone(), v));
        }
        let mut axes = Vec::new();
        for (k, v) in &file.axes {
            key_kind(k)?;
            axes.push(Axis {
                key: k.clone(),
                values: axis_values(k, v)?,
            });
        }
        let keep = file.keep;
        if !(keep.band[0] >= 0.0 && keep.band[1] > keep.band[0]) {
            return Err(SweepError::new(format!(
                "keep.band = {:?}: expected [lo, hi] with 0 ≤ lo < hi",
                keep.band
            )));
        }
        if !(keep.tolerance > 0.0 && keep.tolerance < 0.5) {
            return Err(SweepError::new("keep.tolerance must lie in (0, 0.5)"));
        }
        if keep.harmonics > 20 {
            return Err(SweepError::new("keep.harmonics must be ≤ 20"));
        }
        let z = crate::geometry::Bearing::new(&base.bearing)
            .map(|b| b.z)
            .map_err(|e| SweepError::new(format!("base scene bearing: {e}")))?;
        let names: Vec<String> = crate::simulation::output_table(z)
            .into_iter()
            .map(|o| o.name)
            .collect();
        if !names.contains(&keep.signal) {
            return Err(SweepError::new(format!(
                "keep.signal = '{}' is not an output; outputs: {}",
                keep.signal,
                names.join(", ")
            )));
        }
        let sweep = Sweep {
            name: file.name,
            base,
            set,
            axes,
            keep,
        };
        // A defect key without any defect would be silently ignored: refuse it.
        let has_defect = sweep.base.defect.is_some()
            || sweep
                .set
                .iter()
                .any(|(k, v)| k == "defect.ring" && parse_ring(k, v).ok().flatten().is_some())
            || sweep.axes.iter().any(|a| a.key == "defect.ring");
        if !has_defect {
            let swept = sweep
                .axes
                .iter()
                .map(|a| a.key.as_str())
                .chain(sweep.set.iter().map(|(k, _)| k.as_str()))
                .find(|k| k.starts_with("defect."));
            if let Some(k) = swept {
                return Err(SweepError::new(format!(
                    "{k} is swept but the base scene has no defect: add a [defect] to the scene \
                     or a defect.ring axis"
                )));
            }
        }
        Ok(sweep)
    }

    /// Number of runs of the grid (the product of the axis lengths; 1 without axes).
    pub fn len(&self) -> usize {
        self.axes.iter().map(|a| a.values.len()).product()
    }

    /// True if the grid is empty (never: a grid without axes has one run).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The runs of the grid, in index order.
    pub fn runs(&self) -> Vec<Run> {
        let n = self.len();
        (0..n)
            .map(|index| {
                let mut rem = index;
                let mut params = vec![(String::new(), AxisValue::Num(0.0)); self.axes.len()];
                for (i, a) in self.axes.iter().enumerate().rev() {
                    let k = rem % a.values.len();
                    rem /= a.values.len();
                    params[i] = (a.key.clone(), a.values[k].clone());
                }
                let id = run_id(&params);
                Run { index, id, params }
            })
            .collect()
    }

    /// The scene of a run and its measurement-noise RMS, or why the values are impossible.
    pub fn scene_for(&self, run: &Run) -> Result<(Scene, f64), String> {
        let mut scene = self.base.clone();
        let mut noise = 0.0;
        // The defect is assembled from the base (or the defaults of the default scene) and
        // created or removed by defect.ring.
        let template = self.base.defect.clone().unwrap_or(DefectSpec {
            ring: Site::Outer,
            width: 1.0e-3,
            depth: 0.2e-3,
            theta0: std::f64::consts::PI,
        });
        let mut defect = template;
        let mut present = self.base.defect.is_some();
        // The second and later spalls of a [[defect]] base scene (keys defect[k].field).
        let mut more = self.base.more_defects.clone();
        // Ball numbers (`defect.ball`, `defect[k].ball`) apply once the rings are set: to a
        // spall on a ball only (a ring axis may mix raceway and ball spalls).
        let mut balls: Vec<(usize, usize)> = Vec::new();
        for (key, v) in self.set.iter().chain(run.params.iter()) {
            let num = || match v {
                AxisValue::Num(x) => Ok(*x),
                AxisValue::Text(s) => Err(format!("{key} = \"{s}\": expected a number")),
            };
            if let Some((k, field)) = indexed_defect_key(key) {
                let n = usize::from(self.base.defect.is_some()) + more.len();
                let spec = match k {
                    0 if present => &mut defect,
                    _ if k >= 1 && k < n => &mut more[k - 1],
                    _ => {
                        return Err(format!(
                            "{key}: the base scene has {n} spall(s) (defect[0] .. defect[{}])",
                            n.max(1) - 1
                        ))
                    }
                };
                match field {
                    "ring" => match parse_ring(key, v)? {
                        Some(r) => spec.ring = keep_ball(spec.ring, r),
                        None => {
                            return Err(format!(
                                "{key} = none: one spall of several cannot be removed (sweep \
                                 defect.ring = none for a healthy bearing)"
                            ))
                        }
                    },
                    "ball" => balls.push((k, parse_ball(key, num()?)?)),
                    "width" => spec.width = num()?,
                    "depth" => spec.depth = num()?,
                    _ => spec.theta0 = num()?,
                }
                continue;
            }
            match key.as_str() {
                "defect.ring" => match parse_ring(key, v)? {
                    Some(r) => {
                        defect.ring = keep_ball(defect.ring, r);
                        present = true;
                    }
                    None => present = false,
                },
                "defect.ball" => balls.push((0, parse_ball(key, num()?)?)),
                "defect.width" => defect.width = num()?,
                "defect.depth" => defect.depth = num()?,
                "defect.theta0" => defect.theta0 = num()?,
                // C9 (docs/model.md#c9) edge-stiffness blend length [m] of the bearing's [defect] table (0 = the
                // paper's abrupt change of the Hertz constant).
                "defect.blend_length" => {
                    scene.bearing.defect.blend_length = match v {
                        AxisValue::Text(_) => crate::config::BlendLength::Named(
                            crate::config::BlendName::SemiMinorAxis,
                        ),
                        AxisValue::Num(_) => crate::config::BlendLength::Metres(num()?),
                    }
                }
                "operating.speed_rpm" => {
                    scene.operating.shaft_speed = crate::operating::rpm_to_rad_s(num()?)
                }
                "operating.fa" => scene.operating.fx = num()?,
                "operating.fr" => scene.operating.fz = -num()?,
                "operating.fy" => scene.operating.fy = num()?,
                "fidelity" => scene.fidelity = parse_fidelity(key, v)?,
                "full.cage" => scene.full.cage = parse_switch(key, v)?,
                "lumped.seed" if *v == AxisValue::Text("run".into()) => {
                    // Derived from the run's parameters: distinct per run, independent of threads.
                    scene.lumped.seed = fnv1a64(format!("seed:{}", run.id).as_bytes()) >> 11;
                }
                "lumped.seed" => {
                    let s = num()?;
                    if !(s >= 0.0 && s.fract() == 0.0 && s < 9.0e15) {
                        return Err(format!("lumped.seed = {s}: expected an integer ≥ 0"));
                    }
                    scene.lumped.seed = s as u64;
                }
                "lumped.slip_jitter" => scene.lumped.slip_jitter = num()?,
                "noise.rms" => {
                    noise = num()?;
                    if !(noise >= 0.0 && noise.is_finite()) {
                        return Err(format!("noise.rms = {noise}: must be ≥ 0"));
                    }
                }
                "output.duration" => scene.output.duration = num()?,
                "output.sample_rate" => scene.output.sample_rate = num()?,
                "output.skip" => scene.output.skip = num()?,
                "solver.rtol" => scene.solver.rtol = num()?,
                "solver.pi_beta" => scene.solver.pi_beta = num()?,
                other => return Err(format!("unknown sweep key '{other}'")),
            }
        }
        for (k, n) in balls {
            let spec = if k == 0 {
                Some(&mut defect)
            } else {
                more.get_mut(k - 1)
            };
            if let Some(spec) = spec {
                if let Site::Ball(_) = spec.ring {
                    spec.ring = Site::Ball(n);
                }
            }
        }
        scene.defect = present.then_some(defect);
        if present {
            scene.more_defects = more;
        } else {
            scene.more_defects.clear();
            scene.defect_modes.clear();
        }
        scene.validate().map_err(|e| e.to_string())?;
        if scene.output.skip >= scene.output.duration {
            return Err(format!(
                "output.skip = {} s leaves nothing of output.duration = {} s to analyse",
                scene.output.skip, scene.output.duration
            ));
        }
        Ok((scene, noise))
    }
}

/// The run id of a parameter list: FNV-1a 64 of `key=value;...` in hex (16 digits).
pub fn run_id(params: &[(String, AxisValue)]) -> String {
    let text: String = params
        .iter()
        .map(|(k, v)| format!("{k}={};", v.canonical()))
        .collect();
    format!("{:016x}", fnv1a64(text.as_bytes()))
}
