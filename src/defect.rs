//! Localized raceway defect (spall): added deflection, force direction and Hertz change
//! (docs/model.md#spall, paper eqs. 13–20, docs/model.md#c9 and #c10).
//!
//! The spall is a transverse band across the whole groove (docs/model.md#c9): width `w_d` along the track,
//! depth `h_d`, a quadratic floor `d(y) = h_d [1 − (2y/w_d)²]` and two sharp corners at
//! `y = ±w_d/2`. [`DefectSpec`] is what a scene file gives; [`Defect`] is the precomputed form
//! that the dynamic models query at run time with [`Defect::probe`] (allocation-free, a few
//! `sqrt`s).
//!
//! Conventions:
//! - angles follow C1 (docs/model.md#c1) (θ about +x); the ball-to-defect angle `θ_bd = wrap(θ_br − θ_d0 [− φ])`
//!   is positive when the ball is ahead of the defect centre in +θ (docs/model.md#c10);
//! - the along-track coordinate `y_b` (ball) and `y_q` (contact point) are arc lengths from the
//!   defect centre, positive in +θ;
//! - the drop `g ≥ 0` is how far the ball centre can move toward the defective race, so the
//!   overlap there becomes `δ′ = (δ − g) cos θ_dd` (eq. 13);
//! - the C9 (docs/model.md#c9) blend makes K depend on y_b; the contact potential (2/5)K(y_b)δ′^{5/2} then also
//!   pushes along the track ([`DefectContact::dk_dy`]), which the full model applies so that a
//!   pass over the spall does not create energy. The blend (default ℓ_b = b) and the paper's
//!   abrupt change (ℓ_b = 0, which creates (2/5)(K_groove − K′)δ^{5/2} at each exit) give
//!   different impact forces when a ball reaches the exit still deep in the edge contact; the
//!   paper's Sec. 3.4 trend at 10 000 rpm appears only with ℓ_b = 0 (docs/sweeps.md);
//! - `θ_dd` is the tilt of the true contact normal from the intact normal in the rolling plane,
//!   positive when the contact point lies ahead of the ball in +θ (eq. 17–19); the unit vector
//!   from the ball centre to the contact is `n_q = cos θ_dd n + sin θ_dd c2`.

use crate::config::{BlendLength, ConfigError, DefectMode, HertzMethod};
use crate::contact::{HertzContact, HertzSolution};
use crate::geometry::{Bearing, Race};
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// Number of points of the precomputed drop table over |y_b| ≤ w_d/2 (docs/model.md#spall-drop).
pub const TABLE_POINTS: usize = 2001;

/// Width and depth above this are not a bearing spall (a sanity bound; the bearing-dependent
/// bound `w_d < D` is checked by [`Defect::new`]) \[m\].
pub const MAX_SIZE: f64 = 0.1;

/// Grid points of the coarse scan for the floor minimum at set-up.
const SCAN_POINTS: usize = 400;

/// How far past an edge, in blend lengths ℓ_b, a frozen in-zone law continues the C9 (docs/model.md#c9) blend
/// linearly (a step that overshoots the located edge by more sees the groove side's limit).
pub const FROZEN_OVERSHOOT: f64 = 0.2;

/// Maps an angle to (−π, π] (docs/model.md#conventions), also for large arguments such as φ = Ωt.
/// NaN stays NaN.
#[inline]
pub fn wrap(x: f64) -> f64 {
    if x > -PI && x <= PI {
        return x;
    }
    let mut y = PI - (PI - x).rem_euclid(TAU);
    if y <= -PI {
        y += TAU;
    }
    y
}

/// Where a spall is: on a raceway, or on a ball (docs/model.md#ball-spall).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Site {
    /// The inner raceway.
    Inner,
    /// The outer raceway.
    Outer,
    /// Ball k, numbered from 1 (ball 1 is the first ball of the layout, at azimuth θ_start).
    Ball(usize),
}

impl Site {
    /// The raceway, or None for a ball.
    pub fn race(self) -> Option<Race> {
        match self {
            Site::Inner => Some(Race::Inner),
            Site::Outer => Some(Race::Outer),
            Site::Ball(_) => None,
        }
    }

    /// The `ring` key's word: `inner`, `outer` or `ball`.
    pub fn name(self) -> &'static str {
        match self {
            Site::Inner => "inner",
            Site::Outer => "outer",
            Site::Ball(_) => "ball",
        }
    }
}

impl From<Race> for Site {
    fn from(r: Race) -> Self {
        match r {
            Race::Inner => Site::Inner,
            Race::Outer => Site::Outer,
        }
    }
}

/// A spall as a scene gives it: where, width and depth \[m\], and its angle θ_d0 \[rad\]. On a
/// race, θ_d0 is the centre's azimuth (C1 (docs/model.md#c1) convention; for the inner ring at
/// shaft angle φ = 0). On a ball, it is the centre's angle on the ball's rolling circle at
/// t = 0, from the point midway between the ball's two contacts in the direction of its spin
/// (0: a quarter turn before it meets the outer race; docs/model.md#ball-spall).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "RawSpec", into = "RawSpec")]
pub struct DefectSpec {
    /// The defective ring or ball (`ring = "inner" | "outer" | "ball"`, with `ball = k` for a
    /// ball).
    pub ring: Site,
    /// Width w_d along the track \[m\].
    pub width: f64,
    /// Depth h_d of the floor's deepest point \[m\].
    pub depth: f64,
    /// Angle θ_d0 of the defect centre \[rad\] (default 0; see [`DefectSpec`]).
    pub theta0: f64,
}

/// The `ring` key's words.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum RingWord {
    Inner,
    Outer,
    Ball,
}

/// A `[defect]` table as written: `ring` a word, `ball` only with `ring = "ball"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawSpec {
    ring: RingWord,
    width: f64,
    depth: f64,
    #[serde(default)]
    theta0: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    ball: Option<i64>,
}

/// The site of a `ring` word and a `ball` number; the error names the field.
pub(crate) fn site_of(ring: RingWord, ball: Option<i64>) -> Result<Site, ConfigError> {
    match (ring, ball) {
        (RingWord::Ball, Some(k)) if k >= 1 => Ok(Site::Ball(k as usize)),
        (RingWord::Ball, Some(k)) => Err(ConfigError::new(
            "defect.ball",
            format!("{k} is not a ball number (balls are numbered from 1)"),
        )),
        (RingWord::Ball, None) => Err(ConfigError::new(
            "defect.ball",
            "ring = \"ball\" needs the ball's number, e.g. ball = 1",
        )),
        (RingWord::Inner, None) => Ok(Site::Inner),
        (RingWord::Outer, None) => Ok(Site::Outer),
        (r, Some(k)) => Err(ConfigError::new(
            "defect.ball",
            format!(
                "ball = {k} is only for a spall on a ball (ring = \"ball\"), not with ring = \"{}\"",
                if r == RingWord::Inner { "inner" } else { "outer" }
            ),
        )),
    }
}

/// The `ring` word and `ball` number of a site.
pub(crate) fn words_of(site: Site) -> (RingWord, Option<i64>) {
    match site {
        Site::Inner => (RingWord::Inner, None),
        Site::Outer => (RingWord::Outer, None),
        Site::Ball(k) => (RingWord::Ball, Some(k as i64)),
    }
}

impl TryFrom<RawSpec> for DefectSpec {
    type Error = String;
    fn try_from(r: RawSpec) -> Result<Self, String> {
        Ok(DefectSpec {
            ring: site_of(r.ring, r.ball).map_err(|e| e.to_string())?,
            width: r.width,
            depth: r.depth,
            theta0: r.theta0,
        })
    }
}

impl From<DefectSpec> for RawSpec {
    fn from(d: DefectSpec) -> Self {
        let (ring, ball) = words_of(d.ring);
        RawSpec {
            ring,
            width: d.width,
            depth: d.depth,
            theta0: d.theta0,
            ball,
        }
    }
}

impl DefectSpec {
    /// Checks the values on their own (fields `defect.width`, `defect.depth`, `defect.theta0`):
    /// finite, width and depth > 0 and below 0.1 m. [`Defect::new`] adds the check
    /// against the bearing (w_d < D).
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (field, v) in [("defect.width", self.width), ("defect.depth", self.depth)] {
            if !v.is_finite() {
                return Err(ConfigError::new(
                    field,
                    format!("{v} is not a finite number"),
                ));
            }
            if v <= 0.0 {
                return Err(ConfigError::new(field, format!("{v} m must be > 0")));
            }
            if v >= MAX_SIZE {
                return Err(ConfigError::new(
                    field,
                    format!("{v} m is not a bearing spall (must be < {MAX_SIZE} m)"),
                ));
            }
        }
        if !self.theta0.is_finite() {
            return Err(ConfigError::new(
                "defect.theta0",
                format!("{} is not a finite angle", self.theta0),
            ));
        }
        Ok(())
    }
}

/// A spall's error with its field renamed for entry `k` of several: `defect.width` becomes
/// `defect[k].width` (k from 0, the `[[defect]]` entry); unchanged with one spall (`several`
/// false), so that a one-spall scene reports exactly what it always did.
pub fn indexed_error(e: ConfigError, k: usize, several: bool) -> ConfigError {
    match e.field.strip_prefix("defect.") {
        Some(rest) if several => ConfigError::new(format!("defect[{k}].{rest}"), e.message),
        _ => e,
    }
}

/// Precomputes the raceway spalls of a scene's list with their modes ([`Defect::with_mode`]
/// each, see [`crate::Scene::spalls`]; spalls on balls are skipped, `crate::ball_spall` builds
/// them); errors name each spall by its place `k` in the whole list (`defect[k].field` when
/// there are several). Two on the same ring whose angular extents [θ_d0 − θ_e, θ_d0 + θ_e]
/// intersect are refused with a message naming both (the ball-level and lumped models let
/// each ball meet one spall per race at a time).
pub fn build_races(
    specs: &[(&DefectSpec, Option<DefectMode>)],
    bearing: &Bearing,
    reference_load: f64,
) -> Result<Vec<Defect>, ConfigError> {
    let several = specs.len() > 1;
    let mut all = Vec::new();
    let mut places = Vec::new();
    for (k, &(s, mode)) in specs.iter().enumerate() {
        if s.ring.race().is_none() {
            continue;
        }
        all.push(
            Defect::with_mode(s, bearing, reference_load, mode)
                .map_err(|e| indexed_error(e, k, several))?,
        );
        places.push(k);
    }
    check_overlaps(
        all.iter()
            .zip(&places)
            .map(|(d, &k)| (k, d.ring(), d.theta0(), d.half_angle())),
    )?;
    Ok(all)
}

/// Refuses two spalls `(k, ring, θ_d0, θ_e)` on the same ring whose angular extents intersect
/// (|wrap(θ_a − θ_b)| < θ_ea + θ_eb); the error names both entries, `defect[a]` and `defect[b]`
/// (`k`, the entry's place in the scene's list).
pub fn check_overlaps(
    spalls: impl IntoIterator<Item = (usize, Race, f64, f64)>,
) -> Result<(), ConfigError> {
    let spalls: Vec<(usize, Race, f64, f64)> = spalls.into_iter().collect();
    for (i, &(b, rb, tb, eb)) in spalls.iter().enumerate() {
        for &(a, ra, ta, ea) in &spalls[..i] {
            let gap = wrap(ta - tb).abs();
            if ra == rb && gap < ea + eb {
                return Err(ConfigError::new(
                    format!("defect[{b}]"),
                    format!(
                        "the {ring}-race spalls defect[{a}] (theta0 = {ta} rad, half angle \
                         {ea:.6} rad) and defect[{b}] (theta0 = {tb} rad, half angle {eb:.6} rad) \
                         overlap: their centres are {gap:.6} rad apart, less than the sum of \
                         their half angles {:.6} rad",
                        ea + eb,
                        ring = ra.name()
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Which feature of the spall carries the ball.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ContactKind {
    /// One of the sharp edges at y = ±w_d/2 (edge radius r_e in the Hertz constant).
    Corner,
    /// The quadratic floor (only for spalls shallower than the geometric limit).
    Floor,
    /// Paper-literal "point" mode: the profile under the nominal contact point.
    Profile,
}

/// The state of one ball–spall contact at one ball position (all SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DefectContact {
    /// Along-track position of the ball centre from the defect centre, + in +θ \[m\].
    pub y_b: f64,
    /// Drop g ≥ 0 of the ball centre toward the defective race \[m\].
    pub g: f64,
    /// dg/dy_b \[-\] (= −tan θ_dd: negative where the ball climbs out toward +θ).
    pub dg_dy: f64,
    /// Tilt θ_dd of the contact normal, + when the contact point lies ahead of the ball \[rad\].
    pub theta_dd: f64,
    /// Along-track position of the contact point from the defect centre \[m\].
    pub y_q: f64,
    /// Which feature carries the ball.
    pub kind: ContactKind,
    /// Hertz constant to use [N/m^1.5]: the edge constant K′ of `kind`, blended in compliance
    /// with the groove constant over ℓ_b past each edge (docs/model.md#c9).
    pub k_edge: f64,
    /// The edge constant K′ of `kind` without blending [N/m^1.5].
    pub k_unblended: f64,
    /// d(k_edge)/dy_b \[N/m^2.5\]: nonzero inside the blend length ℓ_b of an edge. The contact
    /// potential (2/5)K(y_b)δ′^{5/2} then also pushes along the track with
    /// −(2/5)δ′^{5/2} dK/dy_b; without that force the blend would create energy (C9 (docs/model.md#c9) note).
    pub dk_dy: f64,
}

impl DefectContact {
    /// Overlap on the tilted normal `δ′ = (δ − g) cos θ_dd` from the intact-groove overlap δ
    /// (eq. 13, docs/model.md#spall-drop); ≤ 0 means the contact is open.
    #[inline]
    pub fn deflection(&self, delta: f64) -> f64 {
        (delta - self.g) * self.theta_dd.cos()
    }

    /// Approach rate `δ̇′ = cos θ_dd (δ̇ − g′(y_b) ẏ_b)` from the intact-groove rate δ̇ and the
    /// along-track ball speed ẏ_b (see [`Defect::along_track_rate`]).
    #[inline]
    pub fn deflection_rate(&self, delta_dot: f64, y_b_dot: f64) -> f64 {
        (delta_dot - self.dg_dy * y_b_dot) * self.theta_dd.cos()
    }
}

/// One node of the precomputed drop table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DropNode {
    /// Ball position y_b \[m\].
    pub y_b: f64,
    /// Drop g(y_b) \[m\] (exact minimum of the rolling-ball filter; point mode: d(y_b)).
    pub g: f64,
    /// Contact location y_q \[m\].
    pub y_q: f64,
    /// Contact type.
    pub kind: ContactKind,
    /// Profile depth at the contact, d(y_q) \[m\].
    d_q: f64,
    /// Unblended edge constant K′ of this contact [N/m^1.5].
    pub k: f64,
    /// Its compliance K′^(−2/3).
    c: f64,
}

/// A spall's azimuthal position and extent and its largest drop ([`Defect::summary`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpallSummary {
    ring: Race,
    theta0: f64,
    theta_e: f64,
    max_drop: f64,
}

impl SpallSummary {
    /// The defective ring.
    pub fn ring(&self) -> Race {
        self.ring
    }

    /// Spall centre azimuth θ_d0 \[rad\], wrapped to (−π, π].
    pub fn theta0(&self) -> f64 {
        self.theta0
    }

    /// Half angle θ_e of the spall on the track \[rad\].
    pub fn half_angle(&self) -> f64 {
        self.theta_e
    }

    /// Largest drop of the ball centre over the spall \[m\].
    pub fn max_drop(&self) -> f64 {
        self.max_drop
    }
}

/// A spall precomputed for one bearing: geometry, the drop table and the edge Hertz constants.
#[derive(Debug, Clone)]
pub struct Defect {
    ring: Race,
    width: f64,
    depth: f64,
    theta0: f64,
    mode: DefectMode,
    /// Ball radius R.
    r: f64,
    half_width: f64,
    r_d1: f64,
    r_d2: f64,
    theta_e: f64,
    g_max: f64,
    max_drop: f64,
    edge_radius: f64,
    corner: HertzContact,
    blend_length: f64,
    k_groove: f64,
    c_groove: f64,
    inv_dy: f64,
    nodes: Vec<DropNode>,
}

impl Defect {
    /// Precomputes a spall on `bearing` (docs/model.md#spall).
    ///
    /// The bearing's `[defect]` section gives the mode (finite/point), the edge radius r_e and
    /// the blend length ℓ_b: `"b"` is the semi-minor axis of the defective race's contact
    /// ellipse at `reference_load` \[N\] (which must then be > 0), a number is metres, 0 is the
    /// paper's abrupt change. The edge Hertz constants use the bearing's Hertz method.
    ///
    /// Errors name the field: `defect.width` / `defect.depth` / `defect.theta0` (see
    /// [`DefectSpec::validate`]; also `w_d < D`), `defect.edge_radius`, `defect.blend_length`.
    pub fn new(
        spec: &DefectSpec,
        bearing: &Bearing,
        reference_load: f64,
    ) -> Result<Defect, ConfigError> {
        Self::build(spec, bearing, reference_load, true, None)
    }

    /// [`Defect::new`] in `mode` instead of the bearing's `[defect] mode` (None: the bearing's),
    /// for a spall of several that has its own (`mode` of a `[[defect]]` entry).
    pub fn with_mode(
        spec: &DefectSpec,
        bearing: &Bearing,
        reference_load: f64,
        mode: Option<DefectMode>,
    ) -> Result<Defect, ConfigError> {
        Self::build(spec, bearing, reference_load, true, mode)
    }

    /// The spall's azimuthal extent and largest drop without the drop table (the kinematic
    /// level needs nothing else, and the table is most of a short run's set-up). Validates and
    /// fails like [`Defect::new`]; the drop is the rolling-ball filter at the spall centre,
    /// where the symmetric profile lets the ball sink deepest (a test checks it against the
    /// table's largest drop).
    pub fn summary(
        spec: &DefectSpec,
        bearing: &Bearing,
        reference_load: f64,
    ) -> Result<SpallSummary, ConfigError> {
        Self::summary_with_mode(spec, bearing, reference_load, None)
    }

    /// [`Defect::summary`] in `mode` (None: the bearing's), as [`Defect::with_mode`].
    pub fn summary_with_mode(
        spec: &DefectSpec,
        bearing: &Bearing,
        reference_load: f64,
        mode: Option<DefectMode>,
    ) -> Result<SpallSummary, ConfigError> {
        let d = Self::build(spec, bearing, reference_load, false, mode)?;
        Ok(SpallSummary {
            ring: d.ring,
            theta0: d.theta0,
            theta_e: d.theta_e,
            max_drop: d.max_drop,
        })
    }

    /// [`Defect::new`]; without `table` the drop table stays empty (only for [`Defect::summary`]);
    /// `mode` overrides the bearing's.
    fn build(
        spec: &DefectSpec,
        bearing: &Bearing,
        reference_load: f64,
        table: bool,
        mode: Option<DefectMode>,
    ) -> Result<Defect, ConfigError> {
        spec.validate()?;
        let Some(race) = spec.ring.race() else {
            return Err(ConfigError::new(
                "defect.ring",
                "a spall on a ball is not a raceway spall (crate::ball_spall builds it)",
            ));
        };
        let d_ball = bearing.d;
        let r = 0.5 * d_ball;
        if !(d_ball.is_finite() && d_ball > 0.0 && bearing.dm.is_finite() && bearing.dm > d_ball) {
            return Err(ConfigError::new(
                "bearing.ball_diameter",
                "the bearing geometry is invalid (need 0 < D < dm)",
            ));
        }
        if spec.width >= d_ball {
            return Err(ConfigError::new(
                "defect.width",
                format!(
                    "{} m must be smaller than the ball diameter D = {} m (the finite-ball model \
                     needs the ball to span the spall)",
                    spec.width, d_ball
                ),
            ));
        }
        let defaults = &bearing.file.defect;
        let mode = mode.unwrap_or(defaults.mode);
        let edge_radius = defaults.edge_radius;
        if !(edge_radius.is_finite() && edge_radius > 0.0) {
            return Err(ConfigError::new(
                "defect.edge_radius",
                format!("{edge_radius} must be a finite number > 0"),
            ));
        }
        let blend_length = match defaults.blend_length {
            BlendLength::Named(_) => {
                if !(reference_load.is_finite() && reference_load > 0.0) {
                    return Err(ConfigError::new(
                        "defect.blend_length",
                        format!(
                            "\"b\" (the semi-minor axis) needs a finite reference load > 0, \
                             got {reference_load} N"
                        ),
                    ));
                }
                bearing.hertz(race).semi_axes(reference_load).1
            }
            BlendLength::Metres(l) => {
                if !(l.is_finite() && l >= 0.0) {
                    return Err(ConfigError::new(
                        "defect.blend_length",
                        format!("{l} m must be a finite number ≥ 0"),
                    ));
                }
                l
            }
        };
        let k_groove = bearing.k(race);
        if !(k_groove.is_finite() && k_groove > 0.0) {
            return Err(ConfigError::new(
                format!("contact.K_{}", race.name()),
                format!("groove Hertz constant {k_groove} must be finite and > 0"),
            ));
        }
        let solution = match bearing.file.contact.hertz_method {
            HertzMethod::Exact => HertzSolution::Exact,
            HertzMethod::HamrockBrewe => HertzSolution::HamrockBrewe,
        };
        let e_prime = bearing.e_prime;

        // docs/model.md#spall-half-angle: half angle on the track (eq. 15); upper sign outer, lower sign inner.
        let cos_b = bearing.alpha0.cos();
        let sign = match race {
            Race::Outer => 1.0,
            Race::Inner => -1.0,
        };
        let r_d1 = bearing.dm / (2.0 * cos_b) + sign * r;
        let r_d2 = 0.5 * bearing.dm + sign * r * cos_b;
        let half_width = 0.5 * spec.width;
        let theta_e = (r_d1 / r_d2) * (half_width / r_d1).asin();

        // docs/model.md#spall-edge-stiffness: edge (corner) constant, ρ_II = (+1/r_e rolling, 0 transverse).
        let corner = HertzContact::new(
            2.0 / d_ball + 1.0 / edge_radius,
            2.0 / d_ball,
            e_prime,
            solution,
        );
        let g_max = r - (r * r - half_width * half_width).sqrt();

        let geo = Profile {
            r,
            half_width,
            depth: spec.depth,
        };
        let n = TABLE_POINTS;
        let dy = spec.width / (n - 1) as f64;
        // Without `table` (Defect::summary) no node is built.
        let count = if table { n } else { 0 };
        let mut nodes: Vec<DropNode> = Vec::with_capacity(count);
        for i in 0..count {
            let y_b = if i == n - 1 {
                half_width
            } else {
                -half_width + i as f64 * dy
            };
            // The profile is symmetric about the spall centre, so the finite-ball nodes of the
            // right half are the mirror images of the left half's (the same drop, the contact
            // point mirrored), equal to a direct solve up to rounding; this halves the set-up.
            let mirror = n - 1 - i;
            if mode == DefectMode::Finite && mirror < i {
                let m: DropNode = nodes[mirror];
                let node = DropNode {
                    y_b,
                    y_q: -m.y_q,
                    ..m
                };
                nodes.push(node);
                continue;
            }
            let node = match mode {
                DefectMode::Finite => {
                    let (g, y_q, kind) = geo.rolling_ball(y_b);
                    let k = match kind {
                        ContactKind::Corner => corner.stiffness,
                        _ => {
                            // Concave floor: ρ_II(rolling) = −1/r_floor at the contact point,
                            // clamped so that the rolling-plane sum stays ≥ 0.2·(4/D).
                            let sum1 = (2.0 / d_ball - geo.curvature(y_q)).max(0.8 / d_ball);
                            HertzContact::new(sum1, 2.0 / d_ball, e_prime, solution).stiffness
                        }
                    };
                    DropNode {
                        y_b,
                        g,
                        y_q,
                        kind,
                        d_q: geo.depth_at(y_q),
                        k,
                        c: k.powf(-2.0 / 3.0),
                    }
                }
                DefectMode::Point => {
                    // Paper-literal: |r_d| from the parabola, used as convex (eq. 20).
                    let sum1 = 2.0 / d_ball + geo.curvature(y_b);
                    let k = HertzContact::new(sum1, 2.0 / d_ball, e_prime, solution).stiffness;
                    DropNode {
                        y_b,
                        g: geo.depth_at(y_b),
                        y_q: y_b,
                        kind: ContactKind::Profile,
                        d_q: geo.depth_at(y_b),
                        k,
                        c: k.powf(-2.0 / 3.0),
                    }
                }
            };
            nodes.push(node);
        }
        let max_drop = if table {
            nodes.iter().map(|n| n.g).fold(0.0, f64::max)
        } else {
            match mode {
                DefectMode::Finite => geo.rolling_ball(0.0).0,
                DefectMode::Point => geo.depth_at(0.0),
            }
        };
        Ok(Defect {
            ring: race,
            width: spec.width,
            depth: spec.depth,
            theta0: wrap(spec.theta0),
            mode,
            r,
            half_width,
            r_d1,
            r_d2,
            theta_e,
            g_max,
            max_drop,
            edge_radius,
            corner,
            blend_length,
            k_groove,
            c_groove: k_groove.powf(-2.0 / 3.0),
            inv_dy: 1.0 / dy,
            nodes,
        })
    }

    /// The defective ring.
    pub fn ring(&self) -> Race {
        self.ring
    }

    /// Width w_d \[m\].
    pub fn width(&self) -> f64 {
        self.width
    }

    /// Depth h_d \[m\].
    pub fn depth(&self) -> f64 {
        self.depth
    }

    /// Centre angle θ_d0, wrapped to (−π, π] \[rad\].
    pub fn theta0(&self) -> f64 {
        self.theta0
    }

    /// Finite-ball or paper-literal point model.
    pub fn mode(&self) -> DefectMode {
        self.mode
    }

    /// Half-angle θ_e of the defect on the track (eq. 15) \[rad\].
    pub fn half_angle(&self) -> f64 {
        self.theta_e
    }

    /// r_d1 = dm/(2 cos α0) ± D/2: track radius of curvature in the inclined profile plane \[m\].
    pub fn r_d1(&self) -> f64 {
        self.r_d1
    }

    /// r_d2 = dm/2 ± (D/2) cos α0: radius of the contact circle \[m\].
    pub fn r_d2(&self) -> f64 {
        self.r_d2
    }

    /// Geometric limit of the drop of a finite ball, R − √(R² − w_d²/4) \[m\] (depth-independent).
    pub fn g_max(&self) -> f64 {
        self.g_max
    }

    /// Largest drop this defect produces in its mode \[m\]: min(g_max, floor) for the finite ball,
    /// h_d in point mode.
    pub fn max_drop(&self) -> f64 {
        self.max_drop
    }

    /// Edge radius r_e \[m\].
    pub fn edge_radius(&self) -> f64 {
        self.edge_radius
    }

    /// Hertz solution of a ball on a corner of radius r_e (eq. 20): K′ and the semi-axis factors
    /// (major axis transverse) of the edge contact.
    pub fn corner_hertz(&self) -> &HertzContact {
        &self.corner
    }

    /// Edge (corner) Hertz constant K′ [N/m^1.5] (5.81e9 for r_e = 0.1 mm, Table-1 ball).
    pub fn k_corner(&self) -> f64 {
        self.corner.stiffness
    }

    /// Blend length ℓ_b \[m\] (0: abrupt change).
    pub fn blend_length(&self) -> f64 {
        self.blend_length
    }

    /// Groove Hertz constant of the defective race used by [`Defect::probe`] [N/m^1.5].
    pub fn k_groove(&self) -> f64 {
        self.k_groove
    }

    /// The precomputed drop table (2001 nodes from −w_d/2 to +w_d/2).
    pub fn table(&self) -> &[DropNode] {
        &self.nodes
    }

    /// Profile depth below the intact surface, d(y) = h_d[1 − (2y/w_d)²] for |y| < w_d/2, else 0.
    #[inline]
    pub fn depth_at(&self, y: f64) -> f64 {
        let s = 2.0 * y / self.width;
        if s.abs() < 1.0 {
            self.depth * (1.0 - s * s)
        } else {
            0.0
        }
    }

    /// Radius of curvature of the floor parabola at y, `|r_d| = (1 + d′²)^(3/2)/|d″|` \[m\]
    /// (used convex in point mode, concave for floor contacts; 2.83 mm at the edge of a
    /// 2.0 × 0.5 mm spall).
    pub fn profile_radius(&self, y: f64) -> f64 {
        let k2 = 8.0 * self.depth / (self.width * self.width);
        let slope = k2 * y;
        (1.0 + slope * slope).powf(1.5) / k2
    }

    /// Ball-to-defect angle (eq. 14, docs/model.md#c10) from the ball azimuth θ_br in the ring frame and the
    /// shaft angle φ: `wrap(θ_br − θ_d0 − φ)` for an inner-ring defect (it spins with the
    /// shaft), `wrap(θ_br − θ_d0)` for an outer-ring defect (φ ignored) \[rad\].
    #[inline]
    pub fn theta_bd(&self, theta_br: f64, phi: f64) -> f64 {
        match self.ring {
            Race::Outer => wrap(theta_br - self.theta0),
            Race::Inner => wrap(theta_br - self.theta0 - wrap(phi)),
        }
    }

    /// Along-track coordinate of the ball, `y_b = r_d1 sin(θ_bd r_d2/r_d1)` \[m\] (docs/model.md#ball-to-defect).
    #[inline]
    pub fn along_track(&self, theta_bd: f64) -> f64 {
        self.r_d1 * (theta_bd * self.r_d2 / self.r_d1).sin()
    }

    /// Along-track speed ẏ_b = r_d2 cos(θ_bd r_d2/r_d1) θ̇_bd \[m/s\].
    #[inline]
    pub fn along_track_rate(&self, theta_bd: f64, theta_bd_dot: f64) -> f64 {
        self.r_d2 * (theta_bd * self.r_d2 / self.r_d1).cos() * theta_bd_dot
    }

    /// The θ_bd whose along-track coordinate is `y` \[rad\] (the inverse of
    /// [`Defect::along_track`] for |y| < r_d1; clamped to the track's quarter turn beyond).
    #[inline]
    pub fn theta_at_track(&self, y: f64) -> f64 {
        self.r_d1 / self.r_d2 * (y / self.r_d1).clamp(-1.0, 1.0).asin()
    }

    /// Signed distance to the zone boundary in angle, θ_e − |θ_bd| \[rad\]: positive inside the
    /// defect zone. Its root is the edge-crossing event (docs/model.md#step-budget).
    #[inline]
    pub fn zone_margin(&self, theta_bd: f64) -> f64 {
        self.theta_e - theta_bd.abs()
    }

    /// The run-time query: the ball–spall contact at ball-to-defect angle `theta_bd`, or `None`
    /// outside the zone |θ_bd| < θ_e (one comparison, so far-away balls cost nothing; NaN gives
    /// `None`). Allocation-free.
    #[inline]
    pub fn probe(&self, theta_bd: f64) -> Option<DefectContact> {
        let a = theta_bd.abs();
        if a.is_nan() || a >= self.theta_e {
            return None;
        }
        self.contact_at(self.along_track(theta_bd))
    }

    /// The ball–spall contact at along-track ball position `y_b` \[m\], or `None` for
    /// |y_b| ≥ w_d/2 (or NaN).
    ///
    /// Finite mode: the contact candidates stored at the two table nodes around y_b (a corner,
    /// or a floor point) are evaluated exactly at y_b, `g = d(y_q) + R − √(R² − (y_q − y_b)²)`,
    /// and the lowest is taken. This equals the table at the nodes, is exact for corner
    /// contacts, has the kink at y_b = 0 exactly, and keeps g, dg/dy = −tan θ_dd and θ_dd
    /// consistent (a straight linear interpolation of y_q would smear the corner switch over a
    /// table cell). Point mode: closed forms of the parabola, K′ interpolated linearly.
    #[inline]
    pub fn contact_at(&self, y_b: f64) -> Option<DefectContact> {
        self.contact_with_blend(y_b, None)
    }

    /// `y_b`, or the nearest point strictly inside the zone (|y_b| < w_d/2) when `y_b` lies on
    /// an edge or past it. A model that holds a ball in the zone between two stops evaluates
    /// the in-zone law there: the stop at the edge rounds either way, and the intact law at a
    /// stage a round-off outside would be a jump of the Hertz constant inside the step (the
    /// abrupt edge, D2).
    #[inline]
    pub fn clamp_into_zone(&self, y_b: f64) -> f64 {
        if y_b.abs() >= self.half_width {
            // The largest double below the half width (> 0): the edge, from inside.
            f64::from_bits(self.half_width.to_bits() - 1).copysign(y_b)
        } else {
            y_b
        }
    }

    /// [`Defect::contact_at`] with the blend region frozen: `Some(true)` evaluates the C9 (docs/model.md#c9)
    /// compliance blend (continued linearly past ℓ_b), `Some(false)` the unblended edge
    /// constant, `None` decides by the position (|y_b| > w_d/2 − ℓ_b: blend). The blend's
    /// boundary is a kink of K and a jump of dK/dy_b; a model that locates it as a state event
    /// freezes the side inside each step.
    ///
    /// A frozen blend (`Some`) also freezes the zone: past an edge (|y_b| ≥ w_d/2) the
    /// in-zone law is continued smoothly (the corner contact, the blend and its along-track
    /// force) instead of returning `None`. At the edge K is continuous but dK/dy_b is not (the
    /// blend's along-track force −(2/5)δ′^{5/2} dK/dy_b drops to 0 outside), so a model that
    /// locates the edge as a state event must not see that jump inside a step. `None` keeps
    /// the position's answer (`None` outside the zone).
    #[inline]
    pub fn contact_with_blend(&self, y_b: f64, blend: Option<bool>) -> Option<DefectContact> {
        let a = y_b.abs();
        if a.is_nan() || (a >= self.half_width && blend.is_none()) {
            return None;
        }
        let t = (y_b + self.half_width) * self.inv_dy;
        let i = (t as usize).min(self.nodes.len() - 2);
        let (n0, n1) = (&self.nodes[i], &self.nodes[i + 1]);
        let (g, dg_dy, theta_dd, y_q, kind, k, c) = match self.mode {
            DefectMode::Finite => {
                let r2 = self.r * self.r;
                let mut best: Option<(f64, f64, f64, &DropNode)> = None;
                for node in [n0, n1] {
                    if let Some((_, _, _, b)) = best {
                        if b.y_q == node.y_q {
                            continue;
                        }
                    }
                    let x = node.y_q - y_b;
                    let s2 = r2 - x * x;
                    if s2 <= 0.0 {
                        continue;
                    }
                    let s = s2.sqrt();
                    let g = node.d_q + self.r - s;
                    if best.is_none_or(|(bg, _, _, _)| g < bg) {
                        best = Some((g, x, s, node));
                    }
                }
                match best {
                    Some((g, x, s, node)) => {
                        (g, -x / s, x.atan2(s), node.y_q, node.kind, node.k, node.c)
                    }
                    None => {
                        // Unreachable for w_d < D; fall back on the nearest corner.
                        let y_q = self.half_width.copysign(y_b);
                        let x = y_q - y_b;
                        let s = (r2 - x * x).max(0.0).sqrt();
                        let k = self.corner.stiffness;
                        (
                            self.r - s,
                            if s > 0.0 { -x / s } else { 0.0 },
                            x.atan2(s),
                            y_q,
                            ContactKind::Corner,
                            k,
                            k.powf(-2.0 / 3.0),
                        )
                    }
                }
            }
            DefectMode::Point => {
                let w2 = self.width * self.width;
                let slope = -8.0 * self.depth * y_b / w2; // d′(y_b)
                let f = (t - i as f64).clamp(0.0, 1.0);
                let c = n0.c + f * (n1.c - n0.c);
                let k = 1.0 / (c * c.sqrt());
                (
                    self.depth_at(y_b),
                    slope,
                    (-slope).atan(),
                    y_b,
                    ContactKind::Profile,
                    k,
                    c,
                )
            }
        };
        Some(DefectContact {
            y_b,
            g,
            dg_dy,
            theta_dd,
            y_q,
            kind,
            k_edge: self.blend(y_b, c, self.c_groove, k, blend),
            k_unblended: k,
            dk_dy: self.blend_slope(y_b, c, self.c_groove, blend),
        })
    }

    /// The Hertz constant at ball position `y_b` for a race whose intact-groove constant is
    /// `k_groove` [N/m^1.5]: `k_groove` outside the defect; inside, the compliance K^(−2/3) runs
    /// linearly from the groove value at each edge to the edge constant K′ of the current
    /// contact after ℓ_b of travel (docs/model.md#spall-edge-stiffness, #c9); ℓ_b = 0 switches abruptly.
    pub fn hertz_constant(&self, y_b: f64, k_groove: f64) -> f64 {
        match self.contact_at(y_b) {
            None => k_groove,
            Some(c) => self.blend(
                y_b,
                c.k_unblended.powf(-2.0 / 3.0),
                k_groove.powf(-2.0 / 3.0),
                c.k_unblended,
                None,
            ),
        }
    }

    /// dK/dy_b of [`Defect::blend`] (the edge constant itself is taken as constant within a
    /// table cell): inside ℓ_b of an edge the compliance c = c_g + (s/ℓ_b)(c_e − c_g), s =
    /// w_d/2 − |y_b|, so dK/dy_b = −(3/2) c^(−5/2) dc/dy_b with dc/dy_b = −sign(y_b)(c_e − c_g)/ℓ_b.
    #[inline]
    fn blend_slope(&self, y_b: f64, c_edge: f64, c_groove: f64, frozen: Option<bool>) -> f64 {
        let s = self.half_width - y_b.abs();
        if !self.in_blend(s, frozen)
            || s / self.blend_length <= self.blend_floor(frozen, c_edge, c_groove)
        {
            return 0.0;
        }
        let c = c_groove + (s / self.blend_length) * (c_edge - c_groove);
        let dc = -y_b.signum() * (c_edge - c_groove) / self.blend_length;
        -1.5 * dc / (c * c * c.sqrt())
    }

    /// Whether the compliance blend applies at distance `s` from the nearest edge: s < ℓ_b, or
    /// the frozen side (never for ℓ_b = 0).
    #[inline]
    fn in_blend(&self, s: f64, frozen: Option<bool>) -> bool {
        match frozen {
            None => s < self.blend_length,
            Some(b) => b && self.blend_length > 0.0,
        }
    }

    /// Lower limit of the blend fraction s/ℓ_b: 0 (the groove constant at the edge) by
    /// position; with the blend frozen on, the blend continues linearly past the edge (the
    /// zone is frozen too, see [`Defect::contact_with_blend`]) down to −[`FROZEN_OVERSHOOT`],
    /// or less where the compliance would fall below half the groove's.
    #[inline]
    fn blend_floor(&self, frozen: Option<bool>, c_edge: f64, c_groove: f64) -> f64 {
        match frozen {
            Some(true) if c_edge > c_groove => {
                -FROZEN_OVERSHOOT.min(0.5 * c_groove / (c_edge - c_groove))
            }
            Some(true) => -FROZEN_OVERSHOOT,
            _ => 0.0,
        }
    }

    /// Blend-boundary event function of a ball at ball-to-defect angle `theta_bd`:
    /// (w_d/2 − |y_b|) − ℓ_b inside the zone, −ℓ_b outside it (continuous at the edges, so only
    /// the blend boundaries are roots); constant 1 for ℓ_b = 0 (no blend region).
    #[inline]
    pub fn blend_margin(&self, theta_bd: f64) -> f64 {
        if self.blend_length <= 0.0 {
            return 1.0;
        }
        let s = if self.zone_margin(theta_bd) > 0.0 {
            (self.half_width - self.along_track(theta_bd).abs()).max(0.0)
        } else {
            0.0
        };
        s - self.blend_length
    }

    /// Compliance blend; `c_edge`, `c_groove` are K^(−2/3), `k_edge` = c_edge^(−3/2).
    #[inline]
    fn blend(
        &self,
        y_b: f64,
        c_edge: f64,
        c_groove: f64,
        k_edge: f64,
        frozen: Option<bool>,
    ) -> f64 {
        let s = self.half_width - y_b.abs();
        if !self.in_blend(s, frozen) {
            return k_edge;
        }
        let f = (s / self.blend_length).max(self.blend_floor(frozen, c_edge, c_groove));
        let c = c_groove + f * (c_edge - c_groove);
        1.0 / (c * c.sqrt())
    }
}

/// Set-up geometry of the profile in the rolling plane.
struct Profile {
    r: f64,
    half_width: f64,
    depth: f64,
}

impl Profile {
    fn depth_at(&self, y: f64) -> f64 {
        let s = y / self.half_width;
        if s.abs() < 1.0 {
            self.depth * (1.0 - s * s)
        } else {
            0.0
        }
    }

    /// Curvature |d″|/(1 + d′²)^(3/2) of the parabola at y [1/m].
    fn curvature(&self, y: f64) -> f64 {
        let k2 = 2.0 * self.depth / (self.half_width * self.half_width); // |d″|
        let slope = k2 * y;
        k2 / (1.0 + slope * slope).powf(1.5)
    }

    /// Height of the ball centre drop if it touches the profile at y: d(y) + R − √(R² − (y−y_b)²).
    fn drop_via(&self, y: f64, y_b: f64) -> f64 {
        let x = y - y_b;
        self.depth_at(y) + self.r - (self.r * self.r - x * x).max(0.0).sqrt()
    }

    /// Rolling-ball filter at y_b (docs/model.md#spall-drop): (g, y_q, kind) by a scan and golden-section
    /// refinement over the reachable part of the spall; the corners win ties.
    fn rolling_ball(&self, y_b: f64) -> (f64, f64, ContactKind) {
        let hw = self.half_width;
        let lo = (y_b - self.r).max(-hw);
        let hi = (y_b + self.r).min(hw);
        let mut best = (f64::INFINITY, y_b, ContactKind::Corner);
        for corner in [-hw, hw] {
            if (corner - y_b).abs() <= self.r {
                let g = self.drop_via(corner, y_b);
                if g < best.0 {
                    best = (g, corner, ContactKind::Corner);
                }
            }
        }
        // Interior scan for the floor.
        let h = (hi - lo) / SCAN_POINTS as f64;
        let mut k_best = 0;
        let mut f_best = f64::INFINITY;
        for k in 1..SCAN_POINTS {
            let f = self.drop_via(lo + k as f64 * h, y_b);
            if f < f_best {
                f_best = f;
                k_best = k;
            }
        }
        if k_best > 0 && f_best < best.0 {
            let (mut a, mut b) = (lo + (k_best - 1) as f64 * h, lo + (k_best + 1) as f64 * h);
            let inv_phi = 0.5 * (5.0_f64.sqrt() - 1.0);
            let mut x1 = b - inv_phi * (b - a);
            let mut x2 = a + inv_phi * (b - a);
            let mut f1 = self.drop_via(x1, y_b);
            let mut f2 = self.drop_via(x2, y_b);
            for _ in 0..100 {
                if b - a < 1e-15 * (1.0 + hw) {
                    break;
                }
                if f1 < f2 {
                    b = x2;
                    x2 = x1;
                    f2 = f1;
                    x1 = b - inv_phi * (b - a);
                    f1 = self.drop_via(x1, y_b);
                } else {
                    a = x1;
                    x1 = x2;
                    f1 = f2;
                    x2 = a + inv_phi * (b - a);
                    f2 = self.drop_via(x2, y_b);
                }
            }
            let y = 0.5 * (a + b);
            let f = self.drop_via(y, y_b);
            if f < best.0 {
                best = (f, y, ContactKind::Floor);
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_maps_into_half_open_interval() {
        assert_eq!(wrap(PI), PI);
        assert!((wrap(-PI) - PI).abs() < 1e-15);
        assert!((wrap(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap(7.0) - (7.0 - TAU)).abs() < 1e-15);
        assert!((wrap(-7.0) - (-7.0 + TAU)).abs() < 1e-15);
        let big = 1.0e4 + 0.25;
        let w = wrap(big);
        assert!(w > -PI && w <= PI && ((big - w) / TAU - ((big - w) / TAU).round()).abs() < 1e-9);
        assert!(wrap(-1e-300) <= PI && wrap(-1e-300) > -PI);
        assert!(wrap(f64::NAN).is_nan());
        for x in [-10.0, -PI, 0.0, PI, 3.5, 1e5] {
            let w = wrap(x);
            assert!(w > -PI && w <= PI, "wrap({x}) = {w}");
        }
    }
    /// `clamp_into_zone` leaves a point inside the zone alone and takes one on or past an edge
    /// to the last double inside it, on its own side, where the in-zone law holds (the edge
    /// contact) and `contact_at` is not `None`.
    #[test]
    fn clamp_into_zone_keeps_the_inside_and_takes_the_rest_to_the_edge_from_inside() {
        let b = Bearing::load("niu2014-table1").unwrap();
        let spec = DefectSpec {
            ring: Race::Outer.into(),
            width: 1.0e-3,
            depth: 0.2e-3,
            theta0: 0.0,
        };
        let d = Defect::new(&spec, &b, 400.0).unwrap();
        let hw: f64 = 0.5e-3;
        for y in [0.0, -0.3e-3, 0.49e-3, -0.4999999e-3] {
            assert_eq!(d.clamp_into_zone(y).to_bits(), y.to_bits());
        }
        let inside = f64::from_bits(hw.to_bits() - 1);
        for y in [hw, 1.0e-3, hw + 1e-18, -hw, -2.0e-3, f64::INFINITY] {
            let c = d.clamp_into_zone(y);
            assert_eq!(c, inside.copysign(y), "{y}");
            assert!(c.abs() < hw);
            assert!(
                d.contact_at(y).is_none() && d.contact_at(c).is_some(),
                "{y}"
            );
        }
        assert!(d.clamp_into_zone(f64::NAN).is_nan());
    }

    #[test]
    fn mirrored_half_of_the_drop_table_equals_a_direct_solve() {
        // The right half of the table is mirrored from the left (set-up cost); check it against
        // the rolling-ball filter solved directly at those nodes, for a spall whose floor is
        // reached (wide, shallow) and one where only the corners are.
        let b = Bearing::load("niu2014-table1").unwrap();
        for (width, depth) in [(4.0e-3, 0.05e-3), (1.0e-3, 0.2e-3)] {
            let spec = DefectSpec {
                ring: Race::Outer.into(),
                width,
                depth,
                theta0: 0.0,
            };
            let d = Defect::new(&spec, &b, 400.0).unwrap();
            let geo = Profile {
                r: 0.5 * b.d,
                half_width: 0.5 * width,
                depth,
            };
            let mut floors = 0;
            for node in d.nodes.iter().skip(TABLE_POINTS / 2) {
                let (g, y_q, kind) = geo.rolling_ball(node.y_b);
                assert!(
                    (node.g - g).abs() < 1e-12,
                    "y_b {}: g {} vs {g}",
                    node.y_b,
                    node.g
                );
                assert!(
                    (node.y_q - y_q).abs() < 1e-9,
                    "y_b {}: y_q {} vs {y_q}",
                    node.y_b,
                    node.y_q
                );
                assert_eq!(node.kind, kind, "y_b {}", node.y_b);
                floors += usize::from(kind == ContactKind::Floor);
            }
            assert_eq!(floors > 0, width > 2.0e-3, "floor contacts: {floors}");
        }
    }

    #[test]
    fn summary_matches_the_full_table() {
        // The summary's drop (rolling-ball filter at the centre) is the table's largest drop, for
        // corner-only and floor spalls, both rings, both modes; the extent is the same.
        let b = Bearing::load("niu2014-table1").unwrap();
        let mut point = b.clone();
        point.file.defect.mode = DefectMode::Point;
        for bearing in [&b, &point] {
            for ring in [Race::Outer, Race::Inner] {
                for (width, depth) in [
                    (0.3e-3, 0.1e-3),
                    (1.0e-3, 0.2e-3),
                    (4.0e-3, 0.05e-3),
                    (8.0e-3, 0.5e-3),
                ] {
                    let spec = DefectSpec {
                        ring: ring.into(),
                        width,
                        depth,
                        theta0: 1.0,
                    };
                    let d = Defect::new(&spec, bearing, 400.0).unwrap();
                    let s = Defect::summary(&spec, bearing, 400.0).unwrap();
                    assert!(
                        (s.max_drop() - d.max_drop()).abs() <= 1e-9 * d.max_drop(),
                        "{ring:?} {width} x {depth}: {} vs {}",
                        s.max_drop(),
                        d.max_drop()
                    );
                    assert_eq!(
                        (s.ring(), s.theta0(), s.half_angle()),
                        (d.ring(), d.theta0(), d.half_angle())
                    );
                }
            }
        }
        let bad = DefectSpec {
            ring: Race::Outer.into(),
            width: 20e-3,
            depth: 0.1e-3,
            theta0: 0.0,
        };
        assert_eq!(
            Defect::summary(&bad, &b, 400.0).unwrap_err().field,
            Defect::new(&bad, &b, 400.0).unwrap_err().field
        );
    }

    #[test]
    fn blend_slope_matches_finite_differences_of_the_hertz_constant() {
        let mut f = crate::config::BearingFile::default_preset();
        f.defect.blend_length =
            crate::config::BlendLength::Named(crate::config::BlendName::SemiMinorAxis);
        let b = Bearing::new(&f).unwrap();
        let spec = DefectSpec {
            ring: Race::Outer.into(),
            width: 2.0e-3,
            depth: 0.5e-3,
            theta0: 0.0,
        };
        let d = Defect::new(&spec, &b, 400.0).unwrap();
        let kg = b.k(Race::Outer);
        let lb = d.blend_length();
        assert!(lb > 0.0);
        for y in [
            -1.0e-3 + 0.3 * lb,
            -1.0e-3 + 0.8 * lb,
            1.0e-3 - 0.5 * lb,
            0.5e-3,
        ] {
            let h = 1e-9;
            let fd = (d.hertz_constant(y + h, kg) - d.hertz_constant(y - h, kg)) / (2.0 * h);
            let c = d.contact_at(y).unwrap();
            let tol = 1e-5 * (fd.abs() + kg / lb);
            assert!((c.dk_dy - fd).abs() < tol, "y {y}: {} vs {fd}", c.dk_dy);
        }
    }
}
