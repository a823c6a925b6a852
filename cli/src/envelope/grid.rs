//! The envelope grid: the bearing's scales (limiting speed, static load rating) and the operating
//! points built from them.

use raceway::{Bearing, Fidelity, StaticRating};
use serde::{Deserialize, Serialize};

/// Limiting speed criterion: dm·n \[mm·rpm\] (pitch diameter in mm times shaft speed in rpm).
/// 1.0e6 is the usual ceiling of oil-lubricated ball bearings without special cooling; the
/// paper's 9900 rpm on the Table-1 bearing (dm = 70 mm) is 0.69e6.
pub const DMN_LIMIT: f64 = 1.0e6;

/// ISO 76's load of the most heavily loaded ball at P0 = C0: Q_max = 5 C0/(Z cos α0)
/// (Stribeck's 4.37 for zero play, rounded up for the play).
pub const STRIBECK: f64 = 5.0;

/// Loads as fractions of C0: light, medium, heavy.
pub const LIGHT: f64 = 0.01;
pub const MEDIUM: f64 = 0.1;
pub const HEAVY: f64 = 0.4;

/// Soft and stiff pedestal (support) stiffness \[N/m\], besides the preset's own.
pub const K_SOFT: f64 = 5e6;
pub const K_STIFF: f64 = 1e9;

/// The default scene's outer-race spall (1.0 × 0.2 mm on a 12.7 mm ball), as fractions of the
/// ball diameter, centred in the load zone (θ0 = π).
pub const SPALL_WIDTH_OVER_D: f64 = 1.0 / 12.7;
pub const SPALL_DEPTH_OVER_D: f64 = 0.2 / 12.7;

/// Speeds as fractions of the limiting speed.
const SPEEDS_FULL: [f64; 8] = [0.0, 0.05, 0.15, 0.3, 0.45, 0.6, 0.8, 1.0];
const SPEEDS_QUICK: [f64; 3] = [0.0, 0.5, 1.0];

/// One load case: Fa and Fr as fractions of C0, and how the inner ring is held axially.
#[derive(Debug, Clone, Copy)]
pub struct LoadCase {
    pub name: &'static str,
    pub what: &'static str,
    pub fa: f64,
    pub fr: f64,
    /// The ring axially located (`[mounting] axial = "located"`, at its unloaded place since
    /// Fa = 0); run on angular-contact bearings only (α0 > 0), where a free ring cannot carry
    /// a pure radial load (those points stay in the grid as clear errors).
    pub located: bool,
}

const fn load(name: &'static str, what: &'static str, fa: f64, fr: f64) -> LoadCase {
    LoadCase {
        name,
        what,
        fa,
        fr,
        located: false,
    }
}

const fn located(name: &'static str, what: &'static str, fr: f64) -> LoadCase {
    LoadCase {
        name,
        what,
        fa: 0.0,
        fr,
        located: true,
    }
}

const LOADS_FULL: [LoadCase; 17] = [
    load("axial-light", "pure axial, light", LIGHT, 0.0),
    load("axial-heavy", "pure axial, heavy", HEAVY, 0.0),
    load("radial-light", "pure radial, light", 0.0, LIGHT),
    load("radial-heavy", "pure radial, heavy", 0.0, HEAVY),
    load(
        "mostly-axial",
        "Fr = Fa/4 (the default scene's ratio), medium",
        MEDIUM,
        0.25 * MEDIUM,
    ),
    load("half-radial", "Fr = Fa/2, medium", MEDIUM, 0.5 * MEDIUM),
    load("below-equal", "Fr = 0.9 Fa, medium", MEDIUM, 0.9 * MEDIUM),
    load("equal-light", "Fr = Fa, light", LIGHT, LIGHT),
    load("equal", "Fr = Fa, medium", MEDIUM, MEDIUM),
    load(
        "near-equal",
        "Fr = 1.0625 Fa (issue 17's 4250/4000), medium",
        MEDIUM,
        1.0625 * MEDIUM,
    ),
    load("above-equal", "Fr = 1.25 Fa, medium", MEDIUM, 1.25 * MEDIUM),
    load("equal-heavy", "Fr = Fa, heavy", HEAVY, HEAVY),
    load("double-radial", "Fr = 2 Fa, medium", 0.5 * MEDIUM, MEDIUM),
    load(
        "partial-zone",
        "Fr = 4 Fa (partial load zone, issue 17's 4000/1000), medium",
        0.25 * MEDIUM,
        MEDIUM,
    ),
    load(
        "partial-zone-heavy",
        "Fr = 40 Fa (light axial, heavy radial)",
        LIGHT,
        HEAVY,
    ),
    located(
        "radial-light-located",
        "pure radial, light, ring located axially (α0 > 0 only)",
        LIGHT,
    ),
    located(
        "radial-heavy-located",
        "pure radial, heavy, ring located axially (α0 > 0 only)",
        HEAVY,
    ),
];

const LOADS_QUICK: [LoadCase; 5] = [
    LOADS_FULL[1],
    LOADS_FULL[3],
    LOADS_FULL[9],
    LOADS_FULL[13],
    LOADS_FULL[16],
];

/// Simulated time per level \[s\]: enough for a few ball passes at the cheap levels, a few
/// milliseconds (several ball-pass periods at speed) at the per-ball levels.
pub fn duration(level: Fidelity) -> f64 {
    match level {
        Fidelity::Kinematic | Fidelity::QuasiStatic => 0.1,
        Fidelity::Lumped => 0.02,
        Fidelity::Reduced | Fidelity::Full => 0.004,
    }
}

/// Communication step of the runs \[s\] (each one an advance with its own step budget, as an
/// FMU master's fmi2DoStep).
pub fn comm_step(level: Fidelity) -> f64 {
    match level {
        Fidelity::Reduced | Fidelity::Full => 5e-4,
        _ => 1e-3,
    }
}

/// The bearing's scales.
#[derive(Debug, Clone)]
pub struct Scales {
    /// Preset name or file path as given.
    pub source: String,
    /// Display name (the file's `name`, else the source).
    pub name: String,
    pub z: usize,
    pub d: f64,
    pub dm: f64,
    pub alpha0_deg: f64,
    /// Total curvature B = f_i + f_o − 1.
    pub b_total: f64,
    /// Ball mass \[kg\].
    pub ball_mass: f64,
    /// Static load rating C0 \[N\] ([`StaticRating`], ISO 76: f0 from the standard's table).
    pub c0: f64,
    /// The rating with its factors X0, Y0 of the static equivalent load.
    pub rating: StaticRating,
    /// ISO 76's factor f0 = C0/(Z D² cos α0), D in mm.
    pub f0: f64,
    /// Peak Hertz pressure \[Pa\] of ISO 76's ball load at P0 = C0, Q = 5 C0/(Z cos α0), with
    /// this bearing's own curvatures (ISO's 4200 MPa assumes groove radii of 0.52 D and 0.53 D).
    pub p0_at_c0: f64,
    /// Limiting speed DMN_LIMIT/dm \[rpm\].
    pub n_lim: f64,
    /// The preset's pedestal stiffness (k_z) \[N/m\].
    pub k_preset: f64,
}

impl Scales {
    /// The balls' centrifugal forces at a shaft speed `omega` \[rad/s\], summed:
    /// Z·m_b·(dm/2)·Ω² (with the cage at the shaft speed, an upper bound).
    pub fn centrifugal(&self, omega: f64) -> f64 {
        self.z as f64 * self.ball_mass * 0.5 * self.dm * omega * omega
    }

    pub fn new(source: &str, b: &Bearing) -> Self {
        let cos_a = b.alpha0.cos();
        let rating = StaticRating::of(b);
        let c0 = rating.c0;
        let d_mm = b.d * 1e3;
        let q_c0 = STRIBECK * c0 / (b.z as f64 * cos_a);
        let p0_at_c0 = b
            .hertz_inner
            .peak_pressure(q_c0)
            .max(b.hertz_outer.peak_pressure(q_c0));
        Self {
            source: source.to_string(),
            name: if b.file.name.is_empty() {
                source.to_string()
            } else {
                b.file.name.clone()
            },
            z: b.z,
            d: b.d,
            dm: b.dm,
            alpha0_deg: b.alpha0.to_degrees(),
            b_total: b.b_total,
            ball_mass: b.ball_mass,
            c0,
            rating,
            f0: c0 / (b.z as f64 * d_mm * d_mm * cos_a),
            p0_at_c0,
            n_lim: DMN_LIMIT / (b.dm * 1e3),
            k_preset: b.file.pedestal.k_z,
        }
    }
}

/// What one point runs (sent to the worker process as JSON).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PointSpec {
    /// Preset name or bearing file path.
    pub bearing: String,
    /// Fidelity level name.
    pub level: String,
    pub speed_rpm: f64,
    /// Axial load along +x \[N\].
    pub fa: f64,
    /// Radial load along −z \[N\].
    pub fr: f64,
    /// Pedestal stiffness k_y = k_z \[N/m\]; `None` keeps the preset's.
    pub k_pedestal: Option<f64>,
    /// The outer-race spall on or off.
    pub spall: bool,
    /// The inner ring axially located (`[mounting] axial = "located"`, default offset).
    #[serde(default)]
    pub located: bool,
    /// Simulated time \[s\].
    pub duration: f64,
    /// Test hook: the worker sleeps instead of running (exercises the watchdog).
    #[serde(default)]
    pub stall: bool,
}

/// One point of the grid with where it sits (for the neighbour checks and the tables).
#[derive(Debug, Clone)]
pub struct GridPoint {
    pub spec: PointSpec,
    /// Index of the bearing in the run's list of bearings.
    pub bearing: usize,
    pub level: Fidelity,
    /// Index along the speed axis; `None` for the issue-17 points off the grid.
    pub i_speed: Option<usize>,
    /// Load-case name and index.
    pub load: &'static str,
    pub i_load: usize,
    /// Pedestal name ("preset", "soft", "stiff") and stiffness \[N/m\].
    pub pedestal: &'static str,
    pub k_pedestal: f64,
}

/// The grid's axes (for the documentation).
pub struct Axes {
    pub speeds: &'static [f64],
    pub loads: &'static [LoadCase],
}

pub fn axes(quick: bool) -> Axes {
    if quick {
        Axes {
            speeds: &SPEEDS_QUICK,
            loads: &LOADS_QUICK,
        }
    } else {
        Axes {
            speeds: &SPEEDS_FULL,
            loads: &LOADS_FULL,
        }
    }
}

/// Points of issue 17 on the Table-1 bearing, run at every level besides the grid:
/// (speed rpm, Fa N, Fr N, pedestal k or None for the preset's, name).
pub const ISSUE17: [(f64, f64, f64, Option<f64>, &str); 6] = [
    (4000.0, 4000.0, 4250.0, None, "issue17-4000rpm-fr4250"),
    (5376.0, 4000.0, 3913.5, None, "issue17-5376rpm-fr3913.5"),
    (7140.0, 4000.0, 3000.0, None, "issue17-7140rpm-fr3000"),
    (9900.0, 1000.0, 4000.0, None, "issue17-partial-zone"),
    (9900.0, 4000.0, 1000.0, Some(5e6), "issue17-soft-pedestal"),
    (9900.0, 4000.0, 1000.0, Some(7e6), "issue17-pedestal-7e6"),
];

/// Every point of the grid for the bearings and levels, in a fixed order.
pub fn build(scales: &[Scales], levels: &[Fidelity], quick: bool) -> Vec<GridPoint> {
    let ax = axes(quick);
    let mut points = Vec::new();
    for (ib, s) in scales.iter().enumerate() {
        let pedestals: Vec<(&'static str, Option<f64>)> = if quick {
            vec![("preset", None), ("soft", Some(K_SOFT))]
        } else {
            vec![
                ("preset", None),
                ("soft", Some(K_SOFT)),
                ("stiff", Some(K_STIFF)),
            ]
        };
        for &level in levels {
            for (il, lc) in ax.loads.iter().enumerate() {
                if lc.located && s.alpha0_deg <= 0.0 {
                    continue;
                }
                for &(pname, k) in &pedestals {
                    for spall in [false, true] {
                        if quick && !spall {
                            continue;
                        }
                        for (is, &frac) in ax.speeds.iter().enumerate() {
                            points.push(GridPoint {
                                spec: PointSpec {
                                    bearing: s.source.clone(),
                                    level: level.name().to_string(),
                                    speed_rpm: frac * s.n_lim,
                                    fa: lc.fa * s.c0,
                                    fr: lc.fr * s.c0,
                                    k_pedestal: k,
                                    spall,
                                    located: lc.located,
                                    duration: duration(level),
                                    stall: false,
                                },
                                bearing: ib,
                                level,
                                i_speed: Some(is),
                                load: lc.name,
                                i_load: il,
                                pedestal: pname,
                                k_pedestal: k.unwrap_or(s.k_preset),
                            });
                        }
                    }
                }
            }
            // The issue's own points, on its bearing only.
            if s.source == "niu2014-table1" && !quick {
                for (i, &(rpm, fa, fr, k, name)) in ISSUE17.iter().enumerate() {
                    for spall in [false, true] {
                        points.push(GridPoint {
                            spec: PointSpec {
                                bearing: s.source.clone(),
                                level: level.name().to_string(),
                                speed_rpm: rpm,
                                fa,
                                fr,
                                k_pedestal: k,
                                spall,
                                located: false,
                                duration: duration(level),
                                stall: false,
                            },
                            bearing: ib,
                            level,
                            i_speed: None,
                            load: name,
                            i_load: ax.loads.len() + i,
                            pedestal: if k.is_some() { "custom" } else { "preset" },
                            k_pedestal: k.unwrap_or(s.k_preset),
                        });
                    }
                }
            }
        }
    }
    points
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_load_scale_is_the_librarys_static_rating() {
        // One C0 in every document: the library's ISO 76 rating. At ISO's ball load for
        // P0 = C0 the presets' own contacts stay below 4200 MPa (their grooves conform more
        // closely than the standard's 0.52/0.53 D) and above half of it.
        for (name, _) in raceway::PRESETS {
            let b = Bearing::load(name).unwrap();
            let s = Scales::new(name, &b);
            assert_eq!(s.c0, StaticRating::of(&b).c0, "{name}");
            assert!(s.f0 > 9.4 && s.f0 < 16.5, "{name}: f0 = {}", s.f0);
            assert!(
                s.p0_at_c0 > 0.5 * raceway::RATING_PRESSURE
                    && s.p0_at_c0 <= raceway::RATING_PRESSURE,
                "{name}: {} Pa",
                s.p0_at_c0
            );
            assert!(
                s.n_lim > 10_000.0 && s.n_lim < 40_000.0,
                "{name}: {}",
                s.n_lim
            );
        }
    }

    #[test]
    fn grid_sizes() {
        let b = Bearing::load("niu2014-table1").unwrap();
        let s = vec![Scales::new("niu2014-table1", &b)];
        let levels = [Fidelity::Kinematic, Fidelity::Full];
        // 17 loads (2 of them located) × 3 pedestals × 2 spall states × 8 speeds + 6 issue
        // points × 2, per level.
        assert_eq!(build(&s, &levels, false).len(), 2 * (816 + 12));
        // The quick grid's load cases.
        let names: Vec<&str> = axes(true).loads.iter().map(|l| l.name).collect();
        assert_eq!(
            names,
            [
                "axial-heavy",
                "radial-heavy",
                "near-equal",
                "partial-zone",
                "radial-heavy-located"
            ]
        );
        // 5 loads × 2 pedestals × spall × 3 speeds per level.
        let quick = build(&s, &levels, true);
        assert_eq!(quick.len(), 2 * 30);
        assert_eq!(quick.iter().filter(|p| p.spec.located).count(), 2 * 6);
        // A deep-groove bearing carries a pure radial load on a free ring: no located points.
        let b = Bearing::load("cwru-6205-de").unwrap();
        let s = vec![Scales::new("cwru-6205-de", &b)];
        let quick = build(&s, &levels, true);
        assert_eq!(quick.len(), 2 * 24);
        assert!(quick.iter().all(|p| !p.spec.located));
    }
}
