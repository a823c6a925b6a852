//! Judging the points (classes, bounds, neighbour flags) and writing the CSV and the markdown
//! summary.

use super::grid::{self, GridPoint, Scales};
use super::point::Measured;
use raceway::Fidelity;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

/// What became of one point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Class {
    /// Ran to the end; every delivered output finite and within the bounds.
    Ok,
    /// Stopped with a `SimError` (or a setup error): a clear message, no outputs after it.
    Error,
    /// Ran past the wall-time limit: the watchdog killed it.
    Hang,
    /// The worker died without a result (a panic or a signal).
    Crash,
    /// Delivered outputs (at t = 0 or from a successful step) that are non-finite or outside
    /// the bounds.
    Garbage,
}

impl Class {
    pub const ALL: [Class; 5] = [
        Class::Ok,
        Class::Error,
        Class::Garbage,
        Class::Hang,
        Class::Crash,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Class::Ok => "ok",
            Class::Error => "error",
            Class::Hang => "hang",
            Class::Crash => "crash",
            Class::Garbage => "garbage",
        }
    }

    /// Classes that fail the envelope (non-zero exit status).
    pub fn fails(self) -> bool {
        matches!(self, Class::Hang | Class::Crash | Class::Garbage)
    }
}

/// The raw result of a worker.
#[derive(Debug, Clone)]
pub enum Raw {
    Done(Box<Measured>),
    Hang,
    Crash(String),
}

/// The bounds a point must keep to be `ok`, and the thresholds of the flags (documented in the
/// summary, with the data behind the margins).
#[derive(Debug, Clone, Copy)]
pub struct Bounds {
    /// Relative numerical margin around the loaded balls' race-control range of the cage ratio
    /// with finite contacts ([`super::point::ellipse_range`]) at the caged levels (kinematic,
    /// quasi-static, lumped).
    pub cage_margin: f64,
    /// The same at the reduced and full levels, whose balls orbit freely (no cage): their mean
    /// over the run's second half carries the start transient and the unloaded balls' orbits.
    pub cage_margin_free: f64,
    /// Largest |cage.speed| at a shaft at rest, as a fraction of the limiting speed (nothing
    /// drives the balls; what moves them is the start transient).
    pub rest_cage: f64,
    /// Kinematic and quasi-static levels: largest |bearing.F + load| over |load|.
    pub static_force_tol: f64,
    /// Dynamic levels: largest |bearing.F| over |load| + the balls' centrifugal forces at Ω.
    pub force_factor: f64,
    /// Largest contact deflection allowed for in the ring-displacement bound, over D.
    pub deflection_over_d: f64,
    /// Largest peak Hertz pressure \[Pa\]: the model's own limit, beyond which `raceway static`
    /// refuses a load ([`raceway::MAX_CONTACT_PRESSURE`]).
    pub pressure_limit: f64,
    /// Neighbour flags: the cage ratio's change between neighbours beyond what the
    /// race-control range itself moves, relative, at the levels with the traction's cage speed
    /// (kinematic, quasi-static, lumped) and at the levels with free balls (reduced, full).
    pub jump_traction: f64,
    pub jump_balls: f64,
    /// Level flag: a level's cage ratio relative to the median of the levels at the point.
    pub level_outlier: f64,
    /// Start flag (dynamic levels): |bearing.F + load| at t = 0 over |load|.
    pub start_balance: f64,
    /// Largest |ring.x − its held place| of a located ring \[m\].
    pub located_tol: f64,
}

impl Default for Bounds {
    fn default() -> Self {
        Self {
            cage_margin: 0.001,
            cage_margin_free: 0.01,
            rest_cage: 1e-3,
            static_force_tol: 1e-3,
            force_factor: 5.0,
            deflection_over_d: raceway::load_distribution::MAX_DEFLECTION_OVER_D,
            pressure_limit: raceway::MAX_CONTACT_PRESSURE,
            jump_traction: 0.01,
            jump_balls: 0.05,
            level_outlier: 0.05,
            start_balance: 0.1,
            located_tol: 1e-9,
        }
    }
}

impl Bounds {
    /// Largest inner-ring displacement relative to the outer ring \[m\]: the groove-centre
    /// distance can grow from B·D to at most B·D plus two contact deflections, and its
    /// direction can turn by at most 180°, so the ring moves at most 2 B D + 2 δ_max.
    pub fn ring(&self, s: &Scales) -> f64 {
        (2.0 * s.b_total + 2.0 * self.deflection_over_d) * s.d
    }

    /// Largest force a dynamic level may put on the ring or the pedestal \[N\]: `force_factor`
    /// × (the load + the balls' centrifugal forces at the shaft speed; spall impacts and the
    /// start transient load the rings dynamically, and at speed the impacts scale with the
    /// centrifugal forces, not with the load).
    pub fn force(&self, s: &Scales, load: f64, omega: f64) -> f64 {
        self.force_factor * (load + s.centrifugal(omega))
    }

    /// The cage margin of a level.
    pub fn margin(&self, level: Fidelity) -> f64 {
        if matches!(level, Fidelity::Reduced | Fidelity::Full) {
            self.cage_margin_free
        } else {
            self.cage_margin
        }
    }

    /// The neighbour threshold of a level.
    pub fn jump(&self, level: Fidelity) -> f64 {
        if matches!(level, Fidelity::Reduced | Fidelity::Full) {
            self.jump_balls
        } else {
            self.jump_traction
        }
    }
}

/// A judged point.
#[derive(Debug, Clone)]
pub struct Outcome {
    pub class: Class,
    pub wall: f64,
    pub measured: Option<Measured>,
    /// The error, the garbage reasons, or what the watchdog saw.
    pub message: String,
    pub flags: Vec<String>,
    /// cage.speed / Ω (NaN at rest or without a result).
    pub cage_ratio: f64,
    /// Relative distance of the cage ratio outside the race-control range with finite contacts
    /// (0 inside): what the bound checks.
    pub excursion: f64,
    /// The same outside the point-contact range (for information).
    pub plain_excursion: f64,
}

/// The axial force on the ring \[N\]: Fa, or for a located ring the reaction of its location
/// from L1 (the load the bearing then carries axially).
fn axial_load(p: &GridPoint, m: &Measured) -> f64 {
    m.l1.as_ref().map_or(p.spec.fa, |l| l.reaction)
}

fn is_static(level: Fidelity) -> bool {
    matches!(level, Fidelity::Kinematic | Fidelity::QuasiStatic)
}

/// Relative distance of `r` outside [lo, hi] (0 inside, NaN without a range).
pub fn excursion(r: f64, lo: f64, hi: f64) -> f64 {
    if !(lo.is_finite() && hi.is_finite() && r.is_finite()) {
        f64::NAN
    } else if r < lo {
        (lo - r) / lo
    } else if r > hi {
        (r - hi) / hi
    } else {
        0.0
    }
}

/// Judges one point against the bounds.
pub fn classify(p: &GridPoint, s: &Scales, raw: &Raw, wall: f64, b: &Bounds) -> Outcome {
    let mut o = Outcome {
        class: Class::Ok,
        wall,
        measured: None,
        message: String::new(),
        flags: Vec::new(),
        cage_ratio: f64::NAN,
        excursion: f64::NAN,
        plain_excursion: f64::NAN,
    };
    let m = match raw {
        Raw::Hang => {
            o.class = Class::Hang;
            o.message = format!("no result within the wall-time limit ({wall:.0} s): killed");
            return o;
        }
        Raw::Crash(msg) => {
            o.class = Class::Crash;
            o.message = msg.clone();
            return o;
        }
        Raw::Done(m) => m.as_ref(),
    };
    o.measured = Some(m.clone());
    let omega = p.spec.speed_rpm * std::f64::consts::PI / 30.0;
    let mut bad: Vec<String> = Vec::new();
    let e = &m.ok;
    if let Some((i, t)) = e.nonfinite {
        let names = raceway::output_table(s.z);
        let name = names.get(i).map(|v| v.name.as_str()).unwrap_or("?");
        bad.push(format!("{name} not finite at t = {t:.6} s"));
    }
    // The cage: inside (0, Ω) at every sample, its mean inside the widened race-control range.
    if e.samples > 0 {
        if omega > 0.0 {
            o.cage_ratio = m.cage_speed / omega;
            if !(e.cage_min > 0.0 && e.cage_max < omega) {
                bad.push(format!(
                    "cage.speed {:.6e} … {:.6e} rad/s outside (0, Ω = {omega:.4} rad/s)",
                    e.cage_min, e.cage_max
                ));
            }
            if let Some(l1) = &m.l1 {
                o.excursion = excursion(o.cage_ratio, l1.ell_lo, l1.ell_hi);
                o.plain_excursion = excursion(o.cage_ratio, l1.rc_lo, l1.rc_hi);
                let margin = b.margin(p.level);
                if o.excursion > margin {
                    bad.push(format!(
                        "cage ratio {:.5} outside the finite contacts' race-control range [{:.5}, {:.5}] by {:.2} % (margin {:.1} %)",
                        o.cage_ratio,
                        l1.ell_lo,
                        l1.ell_hi,
                        100.0 * o.excursion,
                        100.0 * margin
                    ));
                }
                // A traction level that returns L1's outer-race control has fallen back.
                if matches!(
                    p.level,
                    Fidelity::Kinematic | Fidelity::QuasiStatic | Fidelity::Lumped
                ) && ((m.cage_model / omega) - l1.orc_ratio).abs() <= 1e-9 * l1.orc_ratio
                {
                    o.flags.push("fallback_orc".into());
                }
            }
        } else {
            let rest = b.rest_cage * s.n_lim * std::f64::consts::PI / 30.0;
            if !(e.cage_min.abs() <= rest && e.cage_max.abs() <= rest) {
                bad.push(format!(
                    "cage.speed {:.3e} … {:.3e} rad/s with the shaft at rest (bound ±{rest:.3e})",
                    e.cage_min, e.cage_max
                ));
            }
        }
        let fa = axial_load(p, m);
        let load = fa.hypot(p.spec.fr);
        let force = b.force(s, load, omega);
        if let Some(held) = m.l1.as_ref().and_then(|l| l.held) {
            let [lo, hi] = e.ring_x;
            let off = (lo - held).abs().max((hi - held).abs());
            if off.is_nan() || off > b.located_tol {
                bad.push(format!(
                    "located ring.x {lo:.6e} … {hi:.6e} m, held at {held:.6e} m (bound ± {:.0e} m)",
                    b.located_tol
                ));
            }
        }
        if is_static(p.level) {
            if e.max_f_dev > b.static_force_tol * load + 1e-6 {
                bad.push(format!(
                    "|bearing.F + load| up to {:.4e} N at a static level (load {load:.1} N)",
                    e.max_f_dev
                ));
            }
        } else {
            if e.max_f > force {
                bad.push(format!(
                    "|bearing.F| up to {:.4e} N (bound {force:.4e} N: {} × (load {load:.1} N + centrifugal))",
                    e.max_f, b.force_factor
                ));
            }
            let f0 = m.f_start;
            let dev0 = (f0[0] + fa).hypot(f0[1]).hypot(f0[2] - p.spec.fr);
            // Healthy scenes only: a ball inside the spall at t = 0 unbalances any start.
            if !p.spec.spall && dev0 > b.start_balance * load {
                o.flags.push("off_balance_start".into());
            }
        }
        let ring = b.ring(s);
        if e.max_ring > ring {
            bad.push(format!(
                "inner ring {:.4e} m from the outer ring (bound {ring:.3e} m)",
                e.max_ring
            ));
        }
        // The static levels put the pedestal at load/k; the bound is the dynamic one for all.
        let ped = force / p.k_pedestal;
        if e.max_ped > ped {
            bad.push(format!(
                "pedestal displaced {:.4e} m (bound {ped:.3e} m: the force bound over k)",
                e.max_ped
            ));
        }
        let p_lim = b.pressure_limit;
        if m.max_pressure > p_lim {
            bad.push(format!(
                "peak Hertz pressure {:.0} MPa (bound {:.0} MPa)",
                m.max_pressure / 1e6,
                p_lim / 1e6
            ));
        }
    }
    if !bad.is_empty() {
        o.class = Class::Garbage;
        o.message = bad.join("; ");
        if let Some(err) = &m.error {
            o.message.push_str(&format!("; then: {err}"));
        }
    } else if let Some(err) = &m.error {
        o.class = Class::Error;
        o.message = err.clone();
    }
    o
}

/// A line along the speed axis: bearing, level code, load case, pedestal, spall.
type LineKey<'a> = (usize, i32, usize, &'a str, bool);

/// Adds the neighbour and level flags: a cage ratio that jumps between neighbours along the
/// speed axis (same level, load, pedestal, spall) by more than the race-control range moves
/// plus the level's threshold, between pedestals or spall on/off at the same speed (L1, and so
/// the range, depends on neither), or a level far from the median of the levels at the point.
pub fn flag_neighbours(points: &[GridPoint], outcomes: &mut [Outcome], b: &Bounds) {
    let ratio = |i: usize| {
        let o = &outcomes[i];
        (o.class == Class::Ok && o.cage_ratio.is_finite() && o.cage_ratio > 0.0)
            .then_some(o.cage_ratio)
    };
    let range = |i: usize| {
        let l1 = outcomes[i].measured.as_ref()?.l1.as_ref()?;
        (l1.rc_lo.is_finite() && l1.rc_hi.is_finite()).then_some((l1.rc_lo, l1.rc_hi))
    };
    let rel = |a: f64, c: f64| (a - c).abs() / (0.5 * (a + c));
    // Same level, load, pedestal, spall: along the speed axis.
    let mut by_line: BTreeMap<LineKey, Vec<(usize, usize)>> = BTreeMap::new();
    // Same level, load, speed: across pedestals and spall states.
    let mut by_point: BTreeMap<(usize, i32, usize, usize), Vec<usize>> = BTreeMap::new();
    // Same physical point: across levels.
    let mut by_levels: BTreeMap<(usize, usize, usize, &str, bool), Vec<usize>> = BTreeMap::new();
    for (i, p) in points.iter().enumerate() {
        let is = p.i_speed.unwrap_or(usize::MAX);
        by_line
            .entry((
                p.bearing,
                p.level.code(),
                p.i_load,
                p.pedestal,
                p.spec.spall,
            ))
            .or_default()
            .push((is, i));
        by_point
            .entry((p.bearing, p.level.code(), p.i_load, is))
            .or_default()
            .push(i);
        by_levels
            .entry((p.bearing, p.i_load, is, p.pedestal, p.spec.spall))
            .or_default()
            .push(i);
    }
    let mut pending: Vec<(usize, String)> = Vec::new();
    for line in by_line.values_mut() {
        line.sort();
        for w in line.windows(2) {
            let ((sa, a), (sb, c)) = (w[0], w[1]);
            if sa == usize::MAX || sb != sa + 1 {
                continue;
            }
            // What the race-control range itself moves between the two speeds (centrifugal
            // forces turn the contact angles) is allowed on top of the threshold.
            let shift = match (range(a), range(c)) {
                (Some((la, ha)), Some((lc, hc))) => (la - lc).abs().max((ha - hc).abs()),
                _ => 0.0,
            };
            if let (Some(ra), Some(rc)) = (ratio(a), ratio(c)) {
                let jump = b.jump(points[a].level);
                if (ra - rc).abs() > shift + jump * 0.5 * (ra + rc) {
                    pending.push((a, "jump_speed".into()));
                    pending.push((c, "jump_speed".into()));
                }
            }
        }
    }
    for group in by_point.values() {
        for (k, &a) in group.iter().enumerate() {
            for &c in &group[k + 1..] {
                let (pa, pc) = (&points[a], &points[c]);
                let what = if pa.pedestal != pc.pedestal && pa.spec.spall == pc.spec.spall {
                    "jump_pedestal"
                } else if pa.pedestal == pc.pedestal && pa.spec.spall != pc.spec.spall {
                    "jump_spall"
                } else {
                    continue;
                };
                if let (Some(ra), Some(rc)) = (ratio(a), ratio(c)) {
                    if rel(ra, rc) > b.jump(pa.level) {
                        pending.push((a, what.into()));
                        pending.push((c, what.into()));
                    }
                }
            }
        }
    }
    for group in by_levels.values() {
        let mut rs: Vec<f64> = group.iter().filter_map(|&i| ratio(i)).collect();
        if rs.len() < 3 {
            continue;
        }
        rs.sort_by(f64::total_cmp);
        let med = rs[rs.len() / 2];
        for &i in group {
            if let Some(r) = ratio(i) {
                if (r - med).abs() / med > b.level_outlier {
                    pending.push((i, "level_outlier".into()));
                }
            }
        }
    }
    for (i, f) in pending {
        if !outcomes[i].flags.contains(&f) {
            outcomes[i].flags.push(f);
        }
    }
}

/// Replaces the numbers in a message by `#`, so that messages differing only in values group.
pub fn pattern(msg: &str) -> String {
    let mut out = String::with_capacity(msg.len());
    let mut chars = msg.chars().peekable();
    let mut prev_alnum = false;
    while let Some(c) = chars.next() {
        let starts_number = c.is_ascii_digit()
            || ((c == '-' || c == '.') && chars.peek().is_some_and(|d| d.is_ascii_digit()));
        if starts_number && !prev_alnum {
            let mut last = c;
            while let Some(&d) = chars.peek() {
                let exp_sign = (d == '-' || d == '+') && last == 'e';
                if d.is_ascii_digit() || d == '.' || d == 'e' || exp_sign {
                    last = d;
                    chars.next();
                } else {
                    break;
                }
            }
            out.push('#');
            prev_alnum = false;
        } else {
            prev_alnum = c.is_alphanumeric() || c == '_';
            out.push(c);
        }
    }
    // A message that names a point repeats it: keep the first 160 characters.
    if out.chars().count() > 160 {
        out = out.chars().take(160).collect::<String>() + "…";
    }
    out
}

/// A number with 6 significant digits, trailing zeros dropped (the table is committed: full
/// precision would double its size for digits nobody reads).
fn csv_f(x: f64) -> String {
    csv_digits(x, 6)
}

/// A number with `n` significant digits, trailing zeros dropped, in exponent form outside
/// [1e-4, 10^n).
fn csv_digits(x: f64, n: i32) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    if x == 0.0 {
        return "0".into();
    }
    let trim = |s: &str| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s.to_string()
        }
    };
    let e = x.abs().log10().floor() as i32;
    if (-4..n).contains(&e) {
        trim(&format!("{:.*}", (n - 1 - e).max(0) as usize, x))
    } else {
        let s = format!("{:.*e}", (n - 1) as usize, x);
        match s.split_once('e') {
            Some((m, ex)) => format!("{}e{ex}", trim(m)),
            None => s,
        }
    }
}

/// A measured output (force, displacement, pressure) with 4 significant digits.
fn csv_m(x: f64) -> String {
    csv_digits(x, 4)
}

/// Longest message in the CSV (characters): the summary has each kind in full.
const CSV_MESSAGE: usize = 200;

/// Writes one row per point to `path` and L1's reference once per operating point to
/// `l1_path`. The table is committed: columns that follow from others or from the summary
/// (speed fractions, durations, cage speeds in rad/s, the excursions, the pedestal's name) are
/// left out, L1's reference is the same at every level, pedestal and spall state of an
/// operating point, measured outputs have 4 digits, and messages are cut at [`CSV_MESSAGE`]
/// characters (the whole table stays near 2 MB).
pub fn write_csv(
    path: &Path,
    l1_path: &Path,
    points: &[GridPoint],
    outcomes: &[Outcome],
    scales: &[Scales],
) -> Result<(), String> {
    let mut w = csv::Writer::from_path(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let head = [
        "bearing",
        "level",
        "speed_rpm",
        "load_case",
        "fa",
        "fr",
        "k_pedestal",
        "spall",
        "class",
        "flags",
        "wall_s",
        "t_stop",
        "cage_ratio",
        "bearing_fx",
        "bearing_fz",
        "start_force_dev",
        "max_force_dev",
        "max_force",
        "max_ring_um",
        "max_pedestal_um",
        "max_pressure_mpa",
        "steps",
        "message",
    ];
    w.write_record(head).map_err(|e| e.to_string())?;
    for (p, o) in points.iter().zip(outcomes) {
        let m = o.measured.as_ref();
        let num = |f: &dyn Fn(&Measured) -> f64| m.map_or(String::new(), |m| csv_m(f(m)));
        let dynamic = |f: &dyn Fn(&Measured) -> f64| {
            if is_static(p.level) {
                String::new()
            } else {
                num(f)
            }
        };
        let message: String = if o.message.chars().count() > CSV_MESSAGE {
            o.message.chars().take(CSV_MESSAGE).collect::<String>() + "…"
        } else {
            o.message.clone()
        };
        let row = vec![
            scales[p.bearing].name.clone(),
            p.level.name().to_string(),
            csv_digits(p.spec.speed_rpm, 5),
            p.load.to_string(),
            csv_digits(p.spec.fa, 5),
            csv_digits(p.spec.fr, 5),
            csv_f(p.k_pedestal),
            (p.spec.spall as u8).to_string(),
            o.class.name().to_string(),
            o.flags.join(" "),
            format!("{:.3}", o.wall),
            m.filter(|m| m.error.is_some())
                .map_or(String::new(), |m| csv_f(m.t_reached)),
            if m.is_some() {
                csv_f(o.cage_ratio)
            } else {
                String::new()
            },
            num(&|m| m.f_end[0]),
            num(&|m| m.f_end[2]),
            dynamic(&|m| {
                let f = m.f_start;
                (f[0] + axial_load(p, m))
                    .hypot(f[1])
                    .hypot(f[2] - p.spec.fr)
            }),
            if is_static(p.level) {
                num(&|m| m.ok.max_f_dev)
            } else {
                String::new()
            },
            num(&|m| m.ok.max_f),
            num(&|m| m.ok.max_ring * 1e6),
            num(&|m| m.ok.max_ped * 1e6),
            num(&|m| m.max_pressure / 1e6),
            m.map_or(String::new(), |m| m.steps.to_string()),
            message,
        ];
        w.write_record(&row).map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())?;

    // L1 once per operating point: the first level's (not the lumped one's, whose located
    // reaction is L1's at rest).
    let mut w =
        csv::Writer::from_path(l1_path).map_err(|e| format!("{}: {e}", l1_path.display()))?;
    w.write_record([
        "bearing",
        "speed_rpm",
        "load_case",
        "fa",
        "fr",
        "loaded_balls",
        "rc_lo",
        "rc_hi",
        "ell_lo",
        "ell_hi",
        "l1_cage_ratio",
        "axial_reaction",
        "l1_error",
    ])
    .map_err(|e| e.to_string())?;
    let mut seen = std::collections::BTreeSet::new();
    let lumped = |p: &&GridPoint| p.level == Fidelity::Lumped;
    let others = points.iter().zip(outcomes).filter(|(p, _)| !lumped(p));
    let last = points.iter().zip(outcomes).filter(|(p, _)| lumped(p));
    for (p, o) in others.chain(last) {
        let Some(m) = o.measured.as_ref() else {
            continue;
        };
        if !seen.insert((p.bearing, p.i_load, p.spec.speed_rpm.to_bits())) {
            continue;
        }
        let l = m.l1.as_ref();
        let lnum =
            |f: &dyn Fn(&super::point::L1Ref) -> f64| l.map_or(String::new(), |l| csv_f(f(l)));
        w.write_record([
            scales[p.bearing].name.clone(),
            csv_digits(p.spec.speed_rpm, 5),
            p.load.to_string(),
            csv_digits(p.spec.fa, 5),
            csv_digits(p.spec.fr, 5),
            l.map_or(String::new(), |l| l.loaded.to_string()),
            lnum(&|l| l.rc_lo),
            lnum(&|l| l.rc_hi),
            lnum(&|l| l.ell_lo),
            lnum(&|l| l.ell_hi),
            lnum(&|l| l.orc_ratio),
            l.and_then(|l| l.held.map(|_| csv_m(l.reaction)))
                .unwrap_or_default(),
            m.l1_error.clone().unwrap_or_default(),
        ])
        .map_err(|e| e.to_string())?;
    }
    w.flush().map_err(|e| e.to_string())
}

fn point_label(p: &GridPoint, s: &Scales) -> String {
    format!(
        "{} {} {:.0} rpm, Fa {:.0} N, Fr {:.0} N ({}), k {:e} N/m ({}), spall {}",
        s.name,
        p.level.name(),
        p.spec.speed_rpm,
        p.spec.fa,
        p.spec.fr,
        p.load,
        p.k_pedestal,
        p.pedestal,
        if p.spec.spall { "on" } else { "off" }
    )
}

fn md_escape(s: &str) -> String {
    s.replace('|', "\\|").replace('\n', " ")
}

/// The kinds of bound a garbage message names (its reasons up to their first number).
fn garbage_kind(message: &str) -> String {
    let mut kinds: Vec<String> = message
        .split("; ")
        .filter(|part| !part.starts_with("then:"))
        .map(|part| {
            let pat = pattern(part);
            pat.split('#').next().unwrap_or("").trim().to_string()
        })
        .collect();
    kinds.dedup();
    kinds.join(" + ")
}

/// Indices grouped by a key, the largest groups first.
fn group_by(idx: &[usize], key: impl Fn(usize) -> String) -> Vec<(String, Vec<usize>)> {
    let mut groups: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    for &i in idx {
        groups.entry(key(i)).or_default().push(i);
    }
    let mut g: Vec<(String, Vec<usize>)> = groups.into_iter().collect();
    g.sort_by_key(|c| std::cmp::Reverse(c.1.len()));
    g
}

/// Up to `n` of the points, the first of each (bearing, level) first.
fn examples(points: &[GridPoint], idx: &[usize], n: usize) -> Vec<usize> {
    let mut seen = Vec::new();
    let mut picked = Vec::new();
    for &i in idx {
        let key = (points[i].bearing, points[i].level.code());
        if !seen.contains(&key) {
            seen.push(key);
            picked.push(i);
        }
    }
    for &i in idx {
        if picked.len() >= n {
            break;
        }
        if !picked.contains(&i) {
            picked.push(i);
        }
    }
    picked.truncate(n);
    picked
}

/// The levels among the points, in ladder order.
fn levels_of(points: &[GridPoint], idx: &[usize]) -> String {
    let mut lv: Vec<Fidelity> = idx.iter().map(|&i| points[i].level).collect();
    lv.sort_by_key(|l| l.code());
    lv.dedup();
    lv.iter().map(|l| l.name()).collect::<Vec<_>>().join(", ")
}

/// Percentile `q` in [0, 1] of sorted values.
fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// Everything the summary needs besides the points.
pub struct Context<'a> {
    pub command: String,
    pub revision: Option<String>,
    pub quick: bool,
    pub time_limit: f64,
    pub jobs: usize,
    pub total_wall: f64,
    pub scales: &'a [Scales],
    pub levels: &'a [Fidelity],
    pub bounds: Bounds,
}

/// One row per level: how many points lie inside, below and above a range of the cage ratio,
/// the 99th percentile and the largest excursion and where (`of` gives a point's excursion and
/// the range).
fn excursion_table(
    s: &mut String,
    cx: &Context,
    points: &[GridPoint],
    outcomes: &[Outcome],
    of: impl Fn(&Outcome, &super::point::L1Ref) -> (f64, f64, f64),
) {
    let _ = writeln!(
        s,
        "| level | points | inside | least headroom inside | below min | above max | 99th pct excursion | max excursion | worst point |\n|---|---|---|---|---|---|---|---|---|"
    );
    for &lv in cx.levels {
        let mut ex: Vec<(f64, usize)> = Vec::new();
        let (mut below, mut above) = (0, 0);
        // The smallest relative distance of an inside point to the nearer end of its range.
        let mut headroom = f64::INFINITY;
        for (i, (p, o)) in points.iter().zip(outcomes).enumerate() {
            let Some(m) = &o.measured else { continue };
            let Some(l1) = &m.l1 else { continue };
            let (e, lo, hi) = of(o, l1);
            if p.level != lv
                || p.spec.speed_rpm <= 0.0
                || m.error.is_some()
                || m.ok.nonfinite.is_some()
                || !e.is_finite()
            {
                continue;
            }
            if o.cage_ratio < lo {
                below += 1;
            } else if o.cage_ratio > hi {
                above += 1;
            } else {
                headroom = headroom.min(((o.cage_ratio - lo) / lo).min((hi - o.cage_ratio) / hi));
            }
            ex.push((e, i));
        }
        if ex.is_empty() {
            continue;
        }
        ex.sort_by(|a, c| a.0.total_cmp(&c.0));
        let vals: Vec<f64> = ex.iter().map(|e| e.0).collect();
        let worst = ex
            .last()
            .filter(|e| e.0 > 0.0)
            .map(|e| {
                let (_, lo, hi) = outcomes[e.1]
                    .measured
                    .as_ref()
                    .and_then(|m| m.l1.as_ref())
                    .map_or((0.0, f64::NAN, f64::NAN), |l| of(&outcomes[e.1], l));
                format!(
                    "{}: {:.5} against [{lo:.5}, {hi:.5}]",
                    point_label(&points[e.1], &cx.scales[points[e.1].bearing]),
                    outcomes[e.1].cage_ratio
                )
            })
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {:.3} % | {} | {} | {:.3} % | {:.3} % | {} |",
            lv.name(),
            vals.len(),
            vals.len() - below - above,
            100.0 * headroom,
            below,
            above,
            100.0 * percentile(&vals, 0.99),
            100.0 * vals.last().copied().unwrap_or(f64::NAN),
            md_escape(&worst)
        );
    }
}

/// The located-ring points per level: how far ring.x left its place and bearing.F.x against
/// L1's reaction of the location.
fn located_section(s: &mut String, cx: &Context, points: &[GridPoint], outcomes: &[Outcome]) {
    if !points.iter().any(|p| p.spec.located) {
        return;
    }
    let _ = writeln!(s, "\n## Located ring\n");
    let _ = writeln!(
        s,
        "The points with the ring located axially, per level: classes; over those that delivered outputs, the largest \
         |ring.x − its held place| (bound {:.0e} m) and the range of −bearing.F.x over L1's axial reaction R of the \
         location at the point's speed (at the static levels bearing.F.x = −R; the lumped level has no centrifugal ball \
         forces, and its R is L1's at rest; the dynamic levels ring after the start and carry the spall's impacts). bearing.F.x is finite at every delivered sample wherever the class is ok.\n",
        cx.bounds.located_tol
    );
    let _ = writeln!(
        s,
        "| level | points | ok | error | garbage | hang | crash | max \\|ring.x − held\\| [m] | −F.x/R min | −F.x/R max | R range [N] |\n|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for &lv in cx.levels {
        let idx: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].level == lv && points[i].spec.located)
            .collect();
        if idx.is_empty() {
            continue;
        }
        let count = |c: Class| idx.iter().filter(|&&i| outcomes[i].class == c).count();
        let (mut off, mut lo, mut hi) = (0.0_f64, f64::INFINITY, f64::NEG_INFINITY);
        let (mut r_lo, mut r_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for &i in &idx {
            let Some(m) = &outcomes[i].measured else {
                continue;
            };
            let Some(l1) = &m.l1 else { continue };
            let Some(held) = l1.held else { continue };
            if m.ok.samples == 0 || m.ok.ring_x[0] > m.ok.ring_x[1] {
                continue;
            }
            off = off
                .max((m.ok.ring_x[0] - held).abs())
                .max((m.ok.ring_x[1] - held).abs());
            lo = lo.min(-m.ok.fx[1] / l1.reaction);
            hi = hi.max(-m.ok.fx[0] / l1.reaction);
            r_lo = r_lo.min(l1.reaction);
            r_hi = r_hi.max(l1.reaction);
        }
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {:.1e} | {:.3} | {:.3} | {:.0} … {:.0} |",
            lv.name(),
            idx.len(),
            count(Class::Ok),
            count(Class::Error),
            count(Class::Garbage),
            count(Class::Hang),
            count(Class::Crash),
            off,
            lo,
            hi,
            r_lo,
            r_hi
        );
    }
}

/// Why the cage margins are what they are (from the full grid's data).
const MARGIN_WHY: &str = "the range's ends are exact evaluations at the sampled angles (\"sampling\" \
     below: how much 9 samples per angle instead of 3 change any ball's range over the grid), and the kinematic, \
     quasi-static and lumped levels' cage speed is solved to 1e-9 of the shaft speed: 0.1 % covers their numerics. \
     The reduced and full levels have no cage: each ball orbits at its own rate, their mean over the run's second \
     half (2 ms) still carries the start transient, and the balls L1 leaves unloaded are not in the range at all; 1 % \
     for them. Neither margin decides a point of this grid: \"least headroom inside\" below is how close the cage \
     ratios come to the ends of their ranges.";

/// The markdown summary.
pub fn markdown(cx: &Context, points: &[GridPoint], outcomes: &[Outcome]) -> String {
    let b = &cx.bounds;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Operating envelope: hangs, garbage and errors over a grid\n"
    );
    let _ = writeln!(s, "Made by:\n\n```sh\n{}\n```\n", cx.command);
    let _ = writeln!(
        s,
        "(`cargo run --release -- {}` from the repository root{}; {} points in {:.0} s wall on \
         {} worker processes at a time; every point is a row of `envelope.csv` beside this file, and L1's reference \
         at each operating point a row of `envelope-l1.csv`: \"Tables\" at the end says what their columns hold.)\n",
        cx.command.trim_start_matches("raceway "),
        cx.revision
            .as_ref()
            .map(|r| format!(", at revision {r}"))
            .unwrap_or_default(),
        points.len(),
        cx.total_wall,
        cx.jobs
    );
    let fails: usize = outcomes.iter().filter(|o| o.class.fails()).count();
    let _ = writeln!(
        s,
        "**{}**: {} of {} points hang, crash or return garbage with Ok.\n",
        if fails == 0 { "PASS" } else { "FAIL" },
        fails,
        points.len()
    );

    // What was run.
    let _ = writeln!(s, "## The grid\n");
    let _ = writeln!(
        s,
        "Every point is one scene run through the library (`Simulation::new`, then \
         `advance_sampled` in communication steps of 1 ms, 0.5 ms at the reduced and full levels, \
         each with its own step budget as an FMU master's `fmi2DoStep`), in its own worker \
         process (`raceway envelope --run-point`) so that the watchdog can kill a point that \
         runs past {:.0} s of wall time and record it as a hang. Outputs are checked at t = 0 \
         and at 51.2 kHz in every step that returned Ok.\n",
        cx.time_limit
    );
    let ax = grid::axes(cx.quick);
    let speeds: Vec<String> = ax.speeds.iter().map(|f| format!("{f}")).collect();
    let _ = writeln!(
        s,
        "- Levels and simulated time: {}.",
        cx.levels
            .iter()
            .map(|l| format!("{} {} ms", l.name(), grid::duration(*l) * 1e3))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        s,
        "- Speed: {} × the limiting speed n_lim = dm·n / dm with dm·n = {:.1e} mm·rpm \
         (the usual ceiling of oil-lubricated ball bearings; the paper's 9900 rpm on the Table-1 \
         bearing is dm·n = 0.69e6).",
        speeds.join(", "),
        grid::DMN_LIMIT
    );
    // The largest static equivalent load P0/C0 of the load cases on the bearings run.
    let p0_max = cx
        .scales
        .iter()
        .flat_map(|sc| {
            ax.loads
                .iter()
                .map(|l| sc.rating.equivalent_load(l.fa, l.fr))
        })
        .fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "- Loads: fractions of the basic static load rating C0 of ISO 76 as the library computes it \
         (`limits::StaticRating`, the one C0 that `raceway static` prints: C0 = f0·Z·D²·cos α0 with f0 from the \
         standard's table over D cos α0 / dm; P0 = C0 is where the most heavily loaded contact reaches {:.0} MPa). \
         The table below also gives the peak Hertz pressure at ISO's ball load for P0 = C0, Q = {}·C0/(Z cos α0), \
         with each bearing's own curvatures: below {:.0} MPa where the grooves conform more closely than the \
         standard's 0.52 D and 0.53 D. Light {}, medium {}, heavy {} C0; the static equivalent load \
         P0 = max(X0 Fr + Y0 Fa, Fr) of the heaviest case is {:.2} C0, well inside the rating. Nothing here approaches the model's pressure \
         limit of {:.0} MPa (`limits::MAX_CONTACT_PRESSURE`, about P0 = 3.2 C0, beyond which `raceway static` \
         refuses a load); it is the pressure bound below, and \"Headroom\" shows how close the grid comes.",
        raceway::RATING_PRESSURE / 1e6,
        grid::STRIBECK,
        raceway::RATING_PRESSURE / 1e6,
        grid::LIGHT,
        grid::MEDIUM,
        grid::HEAVY,
        p0_max,
        raceway::MAX_CONTACT_PRESSURE / 1e6
    );
    let _ = writeln!(
        s,
        "- Pedestal stiffness k_y = k_z: the preset's{}.",
        if cx.quick {
            format!(", soft {:e} N/m", grid::K_SOFT)
        } else {
            format!(
                ", soft {:e} N/m, stiff {:e} N/m",
                grid::K_SOFT,
                grid::K_STIFF
            )
        }
    );
    let _ = writeln!(
        s,
        "- Spall: {}the default scene's outer-race spall scaled to the ball (width {:.4}·D, depth \
         {:.4}·D, at the load-zone centre θ0 = π; 1.0 × 0.2 mm on the Table-1 bearing).",
        if cx.quick { "on: " } else { "off, and on: " },
        grid::SPALL_WIDTH_OVER_D,
        grid::SPALL_DEPTH_OVER_D
    );
    let _ = writeln!(
        s,
        "- Mounting: the inner ring free axially (the axial load Fa acts on it), and for the angular-contact \
         bearings (α0 > 0) the pure-radial cases once more with the ring located axially (`[mounting] axial = \
         \"located\"`, held where Fa = 0 puts it: its unloaded place), as a shaft shoulder holds it. On a free ring \
         those cases stay in the grid: an angular-contact bearing cannot carry a pure radial load there, and the \
         points must stop with a clear error."
    );
    if !cx.quick && cx.scales.iter().any(|s| s.source == "niu2014-table1") {
        let _ = writeln!(
            s,
            "- Besides the grid, issue 17's own points on the Table-1 bearing (spall off and on): {}.",
            grid::ISSUE17
                .iter()
                .map(|(rpm, fa, fr, k, _)| format!(
                    "{rpm} rpm Fa {fa} N Fr {fr} N{}",
                    k.map(|k| format!(" k {k:e} N/m")).unwrap_or_default()
                ))
                .collect::<Vec<_>>()
                .join("; ")
        );
    }
    let _ = writeln!(
        s,
        "\n| bearing | Z | D [mm] | dm [mm] | α0 [°] | B | C0 [N] | f0 | p0 at C0 [MPa] | n_lim [rpm] | k_preset [N/m] |\n|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for sc in cx.scales {
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} | {:.3} | {:.2} | {:.3} | {:.0} | {:.2} | {:.0} | {:.0} | {:e} |",
            sc.name,
            sc.z,
            sc.d * 1e3,
            sc.dm * 1e3,
            sc.alpha0_deg,
            sc.b_total,
            sc.c0,
            sc.f0,
            sc.p0_at_c0 / 1e6,
            sc.n_lim,
            sc.k_preset
        );
    }
    let _ = writeln!(
        s,
        "\n| load case | what | Fa/C0 | Fr/C0 | inner ring axially |\n|---|---|---|---|---|"
    );
    for lc in ax.loads {
        // Rounded to 6 decimals: 1.0625 × 0.1 prints as 0.10625, not 0.10625000000000001.
        let r6 = |x: f64| (x * 1e6).round() / 1e6;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            lc.name,
            lc.what,
            r6(lc.fa),
            r6(lc.fr),
            if lc.located {
                "located"
            } else {
                "free (Fa acts)"
            }
        );
    }

    // The classes and the bounds.
    let _ = writeln!(s, "\n## Classes and bounds\n");
    let _ = writeln!(
        s,
        "- **ok**: ran to the end; every output delivered with Ok is finite and within the bounds below.\n\
         - **error**: stopped with a clear `SimError` (message recorded); nothing out of bounds was delivered before it.\n\
         - **garbage**: Ok, but an output at t = 0 or in a step that returned Ok is non-finite or out of bounds (a later error is appended to the message).\n\
         - **hang**: no result within {:.0} s of wall time; the worker was killed.\n\
         - **crash**: the worker died without a result (a panic or a signal).\n\n\
         Hang, crash and garbage fail the envelope (non-zero exit status).\n",
        cx.time_limit
    );
    let _ = writeln!(
        s,
        "Bounds (the reasons in brackets):\n\n\
         - cage.speed in (0, Ω) at every sample at Ω > 0 (a cage cannot stand still, run backwards or outrun the shaft); at Ω = 0, |cage.speed| ≤ {:.0e} × the limiting speed at every sample (nothing drives the balls; what moves them is the start transient).\n\
         - Its mean over the run's second half, as a ratio ω_c/Ω, inside the race-control range of the loaded balls with finite contacts, widened by a numerical margin of {:.1} % at the kinematic, quasi-static and lumped levels and {:.1} % at the reduced and full levels. The range: for each ball L1 loads at the point, its outer-race-control and inner-race-control cage ratios (`fault_frequencies::outer_race_control`, `fault_frequencies::inner_race_control_cage_ratio`) with its pure-rolling points anywhere across its two contact ellipses. A contact's semi-major axis a (`HertzContact::semi_axes` at the ball's load) lies across the track in the plane of the contact angle, so a rolling point s from the centre rolls at the contact angle shifted by s/R (R the ball radius): α_i and α_o each go over ±a/R (sampled at the ends and the middle), and the range is [min, max] over the loaded balls. Kinematics alone allows nothing outside it: a cage ratio beyond it has a ball rolling outside its contacts. The margins cover what the range's construction leaves out, from the data (\"Cage speed against the race-control range\" below): {}\n\
         - Kinematic and quasi-static levels (static balance): |bearing.F + load| ≤ {:.0e}·|load| + 1 µN.\n\
         - Lumped, reduced, full: |bearing.F| ≤ {}·(|load| + Z·m_b·(dm/2)·Ω²) (spall impacts and the start transient load the rings dynamically; at speed the impacts scale with the balls' centrifugal forces, not with the load; \"Headroom\" below has the largest values over the grid).\n\
         - Inner ring relative to the outer ring (ring.x, ring.y − pedestal.y, ring.z − pedestal.z): ≤ (2B + 2·{})·D (the groove-centre distance grows from B·D by at most two contact deflections of {}·D, L1's own limit, and turns at most half a turn).\n\
         - Pedestal displacement ≤ the force bound above over k.\n\
         - Peak Hertz pressure of the largest contact forces ≤ {:.0} MPa (the model's own limit, `limits::MAX_CONTACT_PRESSURE`: gross plastic deformation of the races beyond it, where elastic Hertz contacts no longer describe them).\n\n\
         Flags (they do not change the class):\n\n\
         - `jump_speed`: an ok point's cage ratio differs from its ok neighbour along the speed axis (same level, load, pedestal, spall) by more than the race-control range itself moves plus {:.0} % (kinematic, quasi-static, lumped: one cage speed from the traction solve) or {:.0} % (reduced, full: a 4-ms mean of free balls).\n\
         - `jump_pedestal`, `jump_spall`: the same between pedestals, or spall on and off, at the same speed (L1, and so the range, depends on neither; the traction solve runs on the healthy bearing).\n\
         - `level_outlier`: a level's cage ratio more than {:.0} % from the median of the levels at the same point (needs three ok levels).\n\
         - `off_balance_start` (lumped, reduced, full): |bearing.F + load| at t = 0 above {:.0} % of the load on the healthy bearing: the level does not start at its own equilibrium (with the spall, a ball inside it at t = 0 unbalances any start).\n\
         - `fallback_orc`: a traction level (kinematic, quasi-static, lumped) whose cage speed equals L1's outer-race control to 1e-9 (a silent fallback).\n",
        b.rest_cage,
        100.0 * b.cage_margin,
        100.0 * b.cage_margin_free,
        MARGIN_WHY,
        b.static_force_tol,
        b.force_factor,
        b.deflection_over_d,
        b.deflection_over_d,
        b.pressure_limit / 1e6,
        100.0 * b.jump_traction,
        100.0 * b.jump_balls,
        100.0 * b.level_outlier,
        100.0 * b.start_balance
    );

    // Counts per bearing and level.
    let _ = writeln!(s, "## Results per bearing and level\n");
    let _ = writeln!(
        s,
        "| bearing | level | points | ok | error | garbage | hang | crash | flagged | median wall [s] | max wall [s] |\n|---|---|---|---|---|---|---|---|---|---|---|"
    );
    let mut totals = [0usize; 5];
    for (ib, sc) in cx.scales.iter().enumerate() {
        for &lv in cx.levels {
            let idx: Vec<usize> = (0..points.len())
                .filter(|&i| points[i].bearing == ib && points[i].level == lv)
                .collect();
            if idx.is_empty() {
                continue;
            }
            let count = |c: Class| idx.iter().filter(|&&i| outcomes[i].class == c).count();
            let flagged = idx
                .iter()
                .filter(|&&i| !outcomes[i].flags.is_empty())
                .count();
            let mut walls: Vec<f64> = idx.iter().map(|&i| outcomes[i].wall).collect();
            walls.sort_by(f64::total_cmp);
            let cs: Vec<usize> = Class::ALL.iter().map(|&c| count(c)).collect();
            for (t, c) in totals.iter_mut().zip(&cs) {
                *t += c;
            }
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} | {:.2} |",
                sc.name,
                lv.name(),
                idx.len(),
                cs[0],
                cs[1],
                cs[2],
                cs[3],
                cs[4],
                flagged,
                percentile(&walls, 0.5),
                walls.last().copied().unwrap_or(f64::NAN)
            );
        }
    }
    let _ = writeln!(
        s,
        "| **all** | | **{}** | **{}** | **{}** | **{}** | **{}** | **{}** | **{}** | | |",
        points.len(),
        totals[0],
        totals[1],
        totals[2],
        totals[3],
        totals[4],
        outcomes.iter().filter(|o| !o.flags.is_empty()).count()
    );

    // Flags.
    let flag_names = [
        "jump_speed",
        "jump_pedestal",
        "jump_spall",
        "level_outlier",
        "off_balance_start",
        "fallback_orc",
    ];
    let _ = writeln!(s, "\n## Flags per level\n");
    let _ = writeln!(
        s,
        "| level | {} |\n|---|{}",
        flag_names.join(" | "),
        "---|".repeat(flag_names.len())
    );
    for &lv in cx.levels {
        let cells: Vec<String> = flag_names
            .iter()
            .map(|f| {
                (0..points.len())
                    .filter(|&i| points[i].level == lv && outcomes[i].flags.iter().any(|g| g == f))
                    .count()
                    .to_string()
            })
            .collect();
        let _ = writeln!(s, "| {} | {} |", lv.name(), cells.join(" | "));
    }

    // The cage speed against both ranges, from the data.
    let _ = writeln!(s, "\n## Cage speed against the race-control range\n");
    let _ = writeln!(
        s,
        "Over the points that ran to the end at Ω > 0 with finite outputs (whatever else their class), how far the \
         cage ratio lies outside the loaded balls' race-control range (relative; 0 = inside), per level. First the \
         range with finite contacts, which the bound checks (margin {:.1} % at the kinematic, quasi-static and \
         lumped levels, {:.1} % at the reduced and full levels):\n",
        100.0 * b.cage_margin,
        100.0 * b.cage_margin_free
    );
    excursion_table(&mut s, cx, points, outcomes, |o, l| {
        (o.excursion, l.ell_lo, l.ell_hi)
    });
    let sampling = outcomes
        .iter()
        .filter_map(|o| o.measured.as_ref()?.l1.as_ref().map(|l| l.ell_check))
        .fold(0.0, f64::max);
    let _ = writeln!(
        s,
        "\nSampling: with 9 samples of each contact angle across its ellipse instead of 3, no loaded ball's range over \
         the grid moves by more than {sampling:.1e} (relative)."
    );
    // How wide the two ranges are, relative to their middle, over the points at speed.
    let mut widths: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    for (p, o) in points.iter().zip(outcomes) {
        let Some(l) = o.measured.as_ref().and_then(|m| m.l1.as_ref()) else {
            continue;
        };
        if p.spec.speed_rpm > 0.0 && l.ell_hi.is_finite() && l.rc_hi.is_finite() {
            widths[0].push((l.ell_hi - l.ell_lo) / (0.5 * (l.ell_hi + l.ell_lo)));
            widths[1].push((l.rc_hi - l.rc_lo) / (0.5 * (l.rc_hi + l.rc_lo)));
        }
    }
    for w in widths.iter_mut() {
        w.sort_by(f64::total_cmp);
    }
    let _ = writeln!(
        s,
        "\nWidth: the range with finite contacts spans {:.1} % of its middle at the median point at speed ({:.1} % to \
         {:.1} %; the point-contact range {:.2} % at the median, up to {:.1} %): wide enough that it catches a cage \
         ratio no rolling of the loaded balls can make, not a deviation of a few per cent. Those show in the table \
         below and in the flags.",
        100.0 * percentile(&widths[0], 0.5),
        100.0 * widths[0].first().copied().unwrap_or(f64::NAN),
        100.0 * widths[0].last().copied().unwrap_or(f64::NAN),
        100.0 * percentile(&widths[1], 0.5),
        100.0 * widths[1].last().copied().unwrap_or(f64::NAN)
    );
    let _ = writeln!(
        s,
        "\nFor information, the same against the point-contact range (each ball's two race controls at its L1 contact \
         angles, no ellipse):\n"
    );
    excursion_table(&mut s, cx, points, outcomes, |o, l| {
        (o.plain_excursion, l.rc_lo, l.rc_hi)
    });

    // How close the points come to the other bounds.
    let _ = writeln!(s, "\n## Headroom\n");
    let _ = writeln!(
        s,
        "The largest value of each bounded output over the points with finite outputs (ok or garbage), as a \
         fraction of its bound (above 1: out of bounds), with the point where it occurs; `force / load` is the \
         largest |bearing.F| over the load alone at the dynamic levels.\n"
    );
    let _ = writeln!(
        s,
        "| level | force / bound | force / load | ring / bound | pedestal / bound | pressure / bound |\n|---|---|---|---|---|---|"
    );
    for &lv in cx.levels {
        let mut worst = [(f64::NEG_INFINITY, usize::MAX); 5];
        for (i, (p, o)) in points.iter().zip(outcomes).enumerate() {
            let Some(m) = &o.measured else { continue };
            if p.level != lv || m.ok.nonfinite.is_some() || m.ok.samples == 0 {
                continue;
            }
            let sc = &cx.scales[p.bearing];
            let load = axial_load(p, m).hypot(p.spec.fr);
            let omega = p.spec.speed_rpm * std::f64::consts::PI / 30.0;
            let force = b.force(sc, load, omega);
            let vals = [
                if is_static(p.level) {
                    m.ok.max_f_dev / (b.static_force_tol * load + 1e-6)
                } else {
                    m.ok.max_f / force
                },
                if is_static(p.level) {
                    f64::NAN
                } else {
                    m.ok.max_f / load
                },
                m.ok.max_ring / b.ring(sc),
                m.ok.max_ped / (force / p.k_pedestal),
                m.max_pressure / b.pressure_limit,
            ];
            for (w, v) in worst.iter_mut().zip(vals) {
                if v > w.0 {
                    *w = (v, i);
                }
            }
        }
        let cell = |w: (f64, usize)| {
            if w.1 == usize::MAX {
                "–".to_string()
            } else {
                format!(
                    "{:.3} ({})",
                    w.0,
                    md_escape(&point_label(&points[w.1], &cx.scales[points[w.1].bearing]))
                )
            }
        };
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            lv.name(),
            if is_static(lv) {
                format!("{} (the balance)", cell(worst[0]))
            } else {
                cell(worst[0])
            },
            cell(worst[1]),
            cell(worst[2]),
            cell(worst[3]),
            cell(worst[4])
        );
    }

    located_section(&mut s, cx, points, outcomes);

    // Errors, grouped by message pattern.
    let _ = writeln!(s, "\n## Errors by message\n");
    let errors: Vec<usize> = (0..points.len())
        .filter(|&i| outcomes[i].class == Class::Error)
        .collect();
    if errors.is_empty() {
        let _ = writeln!(s, "None.");
    } else {
        let _ = writeln!(
            s,
            "| message (numbers as #) | levels | points | example |\n|---|---|---|---|"
        );
        for (pat, g) in group_by(&errors, |i| pattern(&outcomes[i].message)) {
            let i = g[0];
            let _ = writeln!(
                s,
                "| {} | {} | {} | {}: {} |",
                md_escape(&pat),
                levels_of(points, &g),
                g.len(),
                md_escape(&point_label(&points[i], &cx.scales[points[i].bearing])),
                md_escape(&outcomes[i].message)
            );
        }
    }

    // Failing points, grouped by what went wrong.
    for class in [Class::Hang, Class::Crash, Class::Garbage] {
        let idx: Vec<usize> = (0..points.len())
            .filter(|&i| outcomes[i].class == class)
            .collect();
        let _ = writeln!(s, "\n## {} ({})\n", class.name(), idx.len());
        if idx.is_empty() {
            let _ = writeln!(s, "None.");
            continue;
        }
        let groups = group_by(&idx, |i| {
            if class == Class::Garbage {
                garbage_kind(&outcomes[i].message)
            } else {
                points[i].level.name().to_string()
            }
        });
        let _ = writeln!(
            s,
            "| what | levels | points | examples (one per bearing and level, up to 6) |\n|---|---|---|---|"
        );
        for (key, g) in groups {
            let ex: Vec<String> = examples(points, &g, 6)
                .into_iter()
                .map(|i| {
                    format!(
                        "{}: {}",
                        point_label(&points[i], &cx.scales[points[i].bearing]),
                        outcomes[i].message
                    )
                })
                .collect();
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} |",
                md_escape(&key),
                levels_of(points, &g),
                g.len(),
                md_escape(&ex.join("<br>"))
            );
        }
    }

    // Flagged points, grouped by flag.
    let flagged: Vec<usize> = (0..points.len())
        .filter(|&i| !outcomes[i].flags.is_empty())
        .collect();
    let _ = writeln!(s, "\n## Flagged points ({})\n", flagged.len());
    if flagged.is_empty() {
        let _ = writeln!(s, "None.");
    } else {
        let _ = writeln!(
            s,
            "| flag | levels | points | examples (one per bearing and level, up to 6: cage ratio; L1's race-control range) |\n|---|---|---|---|"
        );
        let mut by_flag: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
        for &i in &flagged {
            for f in &outcomes[i].flags {
                by_flag.entry(f.as_str()).or_default().push(i);
            }
        }
        for (flag, g) in by_flag {
            let ex: Vec<String> = examples(points, &g, 6)
                .into_iter()
                .map(|i| {
                    let o = &outcomes[i];
                    let range = o
                        .measured
                        .as_ref()
                        .and_then(|m| m.l1.as_ref())
                        .map(|l| format!("[{:.5}, {:.5}]", l.rc_lo, l.rc_hi))
                        .unwrap_or_default();
                    format!(
                        "{}: {:.5}; {range}",
                        point_label(&points[i], &cx.scales[points[i].bearing]),
                        o.cage_ratio
                    )
                })
                .collect();
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} |",
                flag,
                levels_of(points, &g),
                g.len(),
                md_escape(&ex.join("<br>"))
            );
        }
    }

    // The slowest points.
    let mut slow: Vec<usize> = (0..points.len()).collect();
    slow.sort_by(|&a, &c| outcomes[c].wall.total_cmp(&outcomes[a].wall));
    let _ = writeln!(s, "\n## Slowest points\n");
    let _ = writeln!(s, "| point | class | wall [s] | steps |\n|---|---|---|---|");
    for &i in slow.iter().take(10) {
        let o = &outcomes[i];
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {} |",
            md_escape(&point_label(&points[i], &cx.scales[points[i].bearing])),
            o.class.name(),
            o.wall,
            o.measured
                .as_ref()
                .map(|m| m.steps.to_string())
                .unwrap_or_default()
        );
    }
    let _ = writeln!(s, "\n## Tables\n");
    let _ = writeln!(
        s,
        "`envelope.csv`, one row per point: the point (bearing, level, speed_rpm, load_case, fa and fr [N], \
         k_pedestal [N/m], spall 0/1), its class and flags, wall_s (the worker's wall time), t_stop (the simulated time \
         where an error stopped it; empty: it ran to the end), cage_ratio (the mean cage.speed/Ω over the second half), \
         bearing_fx and bearing_fz at the end [N], start_force_dev (|bearing.F + load| at t = 0 [N], dynamic levels), \
         max_force_dev (the largest |bearing.F + load| [N], static levels), max_force (the largest |bearing.F| [N]), \
         max_ring_um and max_pedestal_um (the largest ring displacement relative to the outer ring and pedestal \
         displacement [µm]), max_pressure_mpa (the peak Hertz pressure of the largest contact forces), steps (integrator \
         steps, rejected ones included) and the message (cut at {CSV_MESSAGE} characters; each kind is in full above). \
         Measured outputs have 4 significant digits, ratios 6.\n\n\
         `envelope-l1.csv`, one row per operating point (bearing, speed, load case): L1's loaded balls, the \
         point-contact race-control range rc_lo … rc_hi, the finite contacts' range ell_lo … ell_hi (the bound), L1's \
         own cage ratio (outer-race control, weighted by the inner loads), a located ring's axial reaction [N] and L1's \
         error where it has none."
    );
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::envelope::point::{Extremes, L1Ref};
    use raceway::Bearing;

    fn setup(level: Fidelity) -> (GridPoint, Scales) {
        let b = Bearing::load("niu2014-table1").unwrap();
        let s = Scales::new("niu2014-table1", &b);
        let mut p = grid::build(std::slice::from_ref(&s), &[level], true)
            .into_iter()
            .find(|p| p.spec.speed_rpm > 0.0)
            .unwrap();
        p.spec.fa = 4000.0;
        p.spec.fr = 1000.0;
        p.spec.speed_rpm = 9900.0;
        (p, s)
    }

    /// A sound measurement at the default scene's point: cage 70 Hz of a 165 Hz shaft.
    fn sound() -> Measured {
        let omega = 9900.0 * std::f64::consts::PI / 30.0;
        let w = 0.424 * omega;
        let mut ok = Extremes {
            samples: 10,
            max_f_dev: 0.01,
            max_f: 4123.0,
            max_ring: 25e-6,
            max_ped: 7e-5,
            max_qi: 700.0,
            max_qo: 800.0,
            cage_sum: 5.0 * w,
            cage_n: 5,
            cage_min: w,
            cage_max: w,
            ..Extremes::default()
        };
        ok.nonfinite = None;
        Measured {
            stage: "done".into(),
            t_reached: 0.1,
            ok,
            cage_speed: w,
            cage_model: w,
            f_end: [-4000.0, 0.0, 1000.0],
            max_pressure: 2.0e9,
            l1: Some(L1Ref {
                rc_lo: 0.420,
                rc_hi: 0.428,
                ell_lo: 0.400,
                ell_hi: 0.450,
                ell_check: 0.0,
                orc_ratio: 0.4268,
                loaded: 14,
                held: None,
                reaction: 4000.0,
            }),
            ..Measured::default()
        }
    }

    #[test]
    fn a_sound_point_is_ok_and_garbage_is_caught() {
        let (p, s) = setup(Fidelity::Kinematic);
        let b = Bounds::default();
        let judge = |m: Measured| classify(&p, &s, &Raw::Done(Box::new(m)), 0.01, &b);
        let ok = judge(sound());
        assert_eq!(ok.class, Class::Ok, "{}", ok.message);
        assert!(ok.flags.is_empty(), "{:?}", ok.flags);

        // Issue 17's cage speed of 7.7e22 rad/s with exit status 0.
        let mut m = sound();
        m.cage_speed = 7.7e22;
        m.ok.cage_max = 7.7e22;
        let g = judge(m);
        assert_eq!(g.class, Class::Garbage);
        assert!(g.message.contains("cage.speed"), "{}", g.message);

        // A NaN output.
        let mut m = sound();
        m.ok.nonfinite = Some((out_index("bearing.F.z"), 0.002));
        let g = judge(m);
        assert_eq!(g.class, Class::Garbage);
        assert!(
            g.message.contains("bearing.F.z not finite"),
            "{}",
            g.message
        );

        // A 1e9 N load's metre-scale ring displacement.
        let mut m = sound();
        m.ok.max_ring = 0.5;
        assert_eq!(judge(m).class, Class::Garbage);

        // A static level whose bearing force is not the load.
        let mut m = sound();
        m.ok.max_f_dev = 2.2e16;
        assert_eq!(judge(m).class, Class::Garbage);

        // Outside the point-contact range but inside the finite contacts' range: ok; 0.05 %
        // beyond the latter passes the 0.1 % margin, 1 % does not.
        for (ratio, class) in [
            (0.44, Class::Ok),
            (0.45 * 1.0005, Class::Ok),
            (0.45 * 1.01, Class::Garbage),
            (0.40 / 1.01, Class::Garbage),
        ] {
            let mut m = sound();
            let w = ratio * 9900.0 * std::f64::consts::PI / 30.0;
            m.cage_speed = w;
            (m.ok.cage_min, m.ok.cage_max) = (w, w);
            let o = judge(m);
            assert_eq!(o.class, class, "ratio {ratio}: {}", o.message);
        }

        // A located ring that leaves its place.
        let mut m = sound();
        m.l1.as_mut().unwrap().held = Some(0.0);
        m.ok.ring_x = [0.0, 0.0];
        assert_eq!(judge(m.clone()).class, Class::Ok);
        m.ok.ring_x = [-2e-6, 0.0];
        let g = judge(m);
        assert_eq!(g.class, Class::Garbage);
        assert!(g.message.contains("located ring.x"), "{}", g.message);

        // A traction level at L1's outer-race-control speed: a silent fallback.
        let mut m = sound();
        m.cage_model = 0.4268 * 9900.0 * std::f64::consts::PI / 30.0;
        assert!(judge(m).flags.contains(&"fallback_orc".to_string()));

        // An error is an error; an error after garbage is garbage.
        let mut m = sound();
        m.error = Some("integration failed at t = 0.001 s: step size collapsed".into());
        assert_eq!(judge(m.clone()).class, Class::Error);
        m.ok.max_ring = 0.5;
        assert_eq!(judge(m).class, Class::Garbage);

        assert_eq!(classify(&p, &s, &Raw::Hang, 60.0, &b).class, Class::Hang);
    }

    fn out_index(name: &str) -> usize {
        raceway::output_table(14)
            .iter()
            .position(|o| o.name == name)
            .unwrap()
    }

    #[test]
    fn dynamic_levels_get_the_force_bound_not_the_balance() {
        let (p, s) = setup(Fidelity::Full);
        let b = Bounds::default();
        let mut m = sound();
        m.ok.max_f_dev = 3000.0; // a spall impact
        m.ok.max_f = 7000.0;
        let o = classify(&p, &s, &Raw::Done(Box::new(m.clone())), 0.1, &b);
        assert_eq!(o.class, Class::Ok, "{}", o.message);
        m.ok.max_f = 1e6;
        let o = classify(&p, &s, &Raw::Done(Box::new(m)), 0.1, &b);
        assert_eq!(o.class, Class::Garbage);
    }

    #[test]
    fn neighbour_jumps_and_level_outliers_are_flagged() {
        let b = Bearing::load("niu2014-table1").unwrap();
        let s = Scales::new("niu2014-table1", &b);
        let levels = [Fidelity::Kinematic, Fidelity::QuasiStatic, Fidelity::Lumped];
        let points = grid::build(std::slice::from_ref(&s), &levels, true);
        let mut outcomes: Vec<Outcome> = points
            .iter()
            .map(|p| Outcome {
                class: Class::Ok,
                wall: 0.0,
                measured: None,
                message: String::new(),
                flags: vec![],
                cage_ratio: if p.spec.speed_rpm > 0.0 {
                    0.42
                } else {
                    f64::NAN
                },
                excursion: 0.0,
                plain_excursion: 0.0,
            })
            .collect();
        // One lumped point 20 % off: it jumps along speed and spall? (spall is on only in the
        // quick grid) and away from the other two levels.
        let k = points
            .iter()
            .position(|p| p.level == Fidelity::Lumped && p.i_speed == Some(2))
            .unwrap();
        outcomes[k].cage_ratio = 0.5;
        flag_neighbours(&points, &mut outcomes, &Bounds::default());
        assert!(outcomes[k].flags.contains(&"jump_speed".to_string()));
        assert!(outcomes[k].flags.contains(&"level_outlier".to_string()));
        assert!(outcomes[k].flags.contains(&"jump_pedestal".to_string()));
        let flagged = outcomes.iter().filter(|o| !o.flags.is_empty()).count();
        // k, its speed neighbour, its pedestal twin.
        assert_eq!(flagged, 3, "{flagged}");
    }

    #[test]
    fn csv_numbers_have_six_or_four_digits() {
        assert_eq!(csv_f(14285.714285714286), "14285.7");
        assert_eq!(csv_f(0.42672781803746), "0.426728");
        assert_eq!(csv_f(-13816.995), "-13817");
        assert_eq!(csv_f(3.0724666e-6), "3.07247e-6");
        assert_eq!(csv_f(2.2e16), "2.2e16");
        assert_eq!(csv_f(1e9), "1e9");
        assert_eq!(csv_m(2.974_56e-6), "2.975e-6");
        assert_eq!(csv_m(14285.714), "1.429e4");
        assert_eq!(csv_m(-345.4), "-345.4");
        assert_eq!(csv_f(0.1), "0.1");
        assert_eq!(csv_f(f64::NAN), "NaN");
    }

    #[test]
    fn message_patterns_drop_the_numbers() {
        assert_eq!(
            pattern("integration failed at t = 0.000123 s: step size 2.000e-15 s fell below"),
            "integration failed at t = # s: step size # s fell below"
        );
        assert_eq!(
            pattern("L1 failed at (4000, 0, -1000) N"),
            "L1 failed at (#, #, #) N"
        );
    }
}
