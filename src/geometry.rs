//! Derived bearing geometry shared by every fidelity level (docs/model.md#geometry, #hertz).
//!
//! [`Bearing`] is built once from a validated [`BearingFile`]: it holds the geometry in SI units,
//! the groove curvature-centre circles, the ball mass and inertia, and the Hertz constants of the
//! inner, outer and series contacts.

use crate::config::{BearingFile, ConfigError, HertzMethod};
use crate::contact::{FilmContact, HertzContact, HertzSolution, Lubricant};
use std::f64::consts::PI;

/// Which raceway.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Race {
    /// The inner raceway (on the ring that turns with the shaft).
    Inner,
    /// The outer raceway (on the ring held by the pedestal).
    Outer,
}

impl Race {
    /// The race's name as written in scene files and outputs (`inner`, `outer`).
    pub fn name(self) -> &'static str {
        match self {
            Race::Inner => "inner",
            Race::Outer => "outer",
        }
    }
}

/// Principal curvatures of a race at the contact point, (rolling direction, transverse) [1/m]
/// (docs/model.md#hertz; convex positive, concave negative).
pub fn race_curvatures(race: Race, d: f64, dm: f64, alpha: f64, f: f64) -> (f64, f64) {
    let gamma = d * alpha.cos() / dm;
    match race {
        Race::Inner => ((2.0 / d) * gamma / (1.0 - gamma), -1.0 / (f * d)),
        Race::Outer => (-(2.0 / d) * gamma / (1.0 + gamma), -1.0 / (f * d)),
    }
}

/// The bearing in SI units with everything derived that the solvers need.
#[derive(Debug, Clone)]
pub struct Bearing {
    /// The description it was built from.
    pub file: BearingFile,
    /// Number of balls.
    pub z: usize,
    /// Ball diameter D \[m\].
    pub d: f64,
    /// Pitch diameter dm \[m\].
    pub dm: f64,
    /// Free contact angle α0 \[rad\].
    pub alpha0: f64,
    /// Inner groove curvature factor f_i (groove radius = f_i·D).
    pub f_inner: f64,
    /// Outer groove curvature factor f_o (groove radius = f_o·D).
    pub f_outer: f64,
    /// Total curvature B = f_i + f_o − 1.
    pub b_total: f64,
    /// Play along the contact line s0 \[m\].
    pub clearance: f64,
    /// Reduced modulus E′ = E/(1−ν²) \[Pa\].
    pub e_prime: f64,
    /// Ball mass \[kg\].
    pub ball_mass: f64,
    /// Ball moment of inertia m D²/10 [kg m²].
    pub ball_inertia: f64,
    /// Hertz solution of the inner contact at α0.
    pub hertz_inner: HertzContact,
    /// Hertz solution of the outer contact at α0.
    pub hertz_outer: HertzContact,
    /// Hertz constant of the inner contact used by the models [N/m^1.5] (the file's override
    /// if given).
    pub k_inner: f64,
    /// Hertz constant of the outer contact used by the models [N/m^1.5] (the file's override
    /// if given).
    pub k_outer: f64,
    /// The lubricant film of the (inner, outer) contacts; None without a `[lubrication]`
    /// section (docs/model.md#film).
    pub film: Option<(FilmContact, FilmContact)>,
}

/// Peak Hertz pressure at which [`contact_damping_limit`] takes the contact stiffness: ISO 76's
/// rating pressure (`limits::RATING_PRESSURE`, a test checks they agree) \[Pa\].
const DAMPING_REFERENCE_PRESSURE: f64 = 4.2e9;

/// How many times the critical damping of a ball on its contacts `contact.c_br` may be.
pub const MAX_CONTACT_DAMPING_RATIO: f64 = 100.0;

/// Critical damping 2√(k m) of a ball of mass `ball_mass` on its two contacts in series, with the
/// linearized stiffness k = 1.5 K^{2/3} Q^{1/3} at the ball load Q where the more loaded contact
/// reaches ISO 76's rating pressure, 4200 MPa (the stiffest a rated load makes it) \[N s/m\].
pub fn critical_contact_damping(races: [(&HertzContact, f64); 2], ball_mass: f64) -> f64 {
    // p0 = 1.5 Q / (π a b) with a b ∝ Q^{2/3}: Q at the pressure, for each race.
    let q_at = |h: &HertzContact| {
        let (a, b) = h.semi_axes(1.0);
        let p_unit = 1.5 / (PI * a * b);
        (DAMPING_REFERENCE_PRESSURE / p_unit).powi(3)
    };
    let q = q_at(races[0].0).min(q_at(races[1].0));
    let compliance: f64 = races.iter().map(|(_, k)| k.powf(-2.0 / 3.0)).sum();
    let k_series = compliance.powf(-1.5);
    let k_lin = 1.5 * k_series.powf(2.0 / 3.0) * q.cbrt();
    2.0 * (k_lin * ball_mass).sqrt()
}

/// `contact.c_br` at most [`MAX_CONTACT_DAMPING_RATIO`] × [`critical_contact_damping`]: beyond it
/// the damping is no bearing's (the literature's is 0.25…2.5e-5 × the contact stiffness, about the
/// critical damping), and the models crawl (a 1e9 N s/m damping makes the lumped level step at
/// 3e-10 s; 8.6e10 makes its contacts chatter).
fn check_contact_damping(
    c_br: f64,
    races: [(&HertzContact, f64); 2],
    ball_mass: f64,
) -> Result<(), ConfigError> {
    let c_crit = critical_contact_damping(races, ball_mass);
    if c_br <= MAX_CONTACT_DAMPING_RATIO * c_crit {
        return Ok(());
    }
    Err(ConfigError::new(
        "contact.c_br",
        format!(
            "{c_br} N s/m is {:.3e} times the critical damping of a ball on its contacts \
             (2√(k m) = {c_crit:.4} N s/m at the stiffness of a rated load); at most \
             {MAX_CONTACT_DAMPING_RATIO} times ({:.4} N s/m) is accepted: a damping far beyond \
             critical is no bearing's, and the integration would crawl",
            c_br / c_crit,
            MAX_CONTACT_DAMPING_RATIO * c_crit
        ),
    ))
}

impl Bearing {
    /// Builds the derived geometry; the file is validated first.
    pub fn new(file: &BearingFile) -> Result<Self, ConfigError> {
        file.validate()?;
        let b = &file.bearing;
        let m = &file.material;
        let d = b.ball_diameter;
        let dm = b.pitch_diameter;
        let alpha0 = b.contact_angle_free_deg.to_radians();
        let e_prime = m.youngs_modulus / (1.0 - m.poisson * m.poisson);
        let solution = match file.contact.hertz_method {
            HertzMethod::Exact => HertzSolution::Exact,
            HertzMethod::HamrockBrewe => HertzSolution::HamrockBrewe,
        };
        let hertz = |race: Race, f: f64| -> Result<HertzContact, ConfigError> {
            let (r1, r2) = race_curvatures(race, d, dm, alpha0, f);
            let sum1 = 2.0 / d + r1;
            let sum2 = 2.0 / d + r2;
            if !(sum1 > 0.0 && sum2 > 0.0) {
                return Err(ConfigError::new(
                    format!("bearing.f_{}", race.name()),
                    "the groove conforms more closely than the ball: curvature sum ≤ 0",
                ));
            }
            Ok(HertzContact::new(sum1, sum2, e_prime, solution))
        };
        let hertz_inner = hertz(Race::Inner, b.f_inner)?;
        let hertz_outer = hertz(Race::Outer, b.f_outer)?;
        let ball_mass = m.density * PI * d.powi(3) / 6.0;
        let k_inner = file.contact.k_inner.unwrap_or(hertz_inner.stiffness);
        let k_outer = file.contact.k_outer.unwrap_or(hertz_outer.stiffness);
        check_contact_damping(
            file.contact.c_br,
            [(&hertz_inner, k_inner), (&hertz_outer, k_outer)],
            ball_mass,
        )?;
        let film = match &file.lubrication {
            Some(l) => {
                let lub = Lubricant::new(l)?;
                Some((
                    FilmContact::new(&hertz_inner, lub),
                    FilmContact::new(&hertz_outer, lub),
                ))
            }
            None => None,
        };
        Ok(Self {
            film,
            file: file.clone(),
            z: b.z as usize,
            d,
            dm,
            alpha0,
            f_inner: b.f_inner,
            f_outer: b.f_outer,
            b_total: b.f_inner + b.f_outer - 1.0,
            clearance: b.clearance,
            e_prime,
            ball_mass,
            ball_inertia: ball_mass * d * d / 10.0,
            k_inner,
            k_outer,
            hertz_inner,
            hertz_outer,
        })
    }

    /// Loads a preset or a file and builds the geometry.
    pub fn load(preset_or_path: &str) -> Result<Self, ConfigError> {
        Self::new(&BearingFile::load(preset_or_path)?)
    }

    /// Ball radius R = D/2 \[m\].
    pub fn ball_radius(&self) -> f64 {
        0.5 * self.d
    }

    /// γ = D cos α / dm.
    pub fn gamma(&self, alpha: f64) -> f64 {
        self.d * alpha.cos() / self.dm
    }

    /// Ball spin angle per orbital angle of a ball in pure rolling on the fixed outer race at
    /// the nominal contact angle, (dm/D)(1 + γ_0): the spin of the kinematic balls (ball
    /// waviness, spalls on balls).
    pub fn kinematic_spin_per_orbit(&self) -> f64 {
        self.dm / self.d * (1.0 + self.gamma(self.alpha0))
    }

    /// Groove curvature factor of a race.
    pub fn f(&self, race: Race) -> f64 {
        match race {
            Race::Inner => self.f_inner,
            Race::Outer => self.f_outer,
        }
    }

    /// Hertz constant of a race [N/m^1.5].
    pub fn k(&self, race: Race) -> f64 {
        match race {
            Race::Inner => self.k_inner,
            Race::Outer => self.k_outer,
        }
    }

    /// The lubricant film of a race's contacts (None without a `[lubrication]` section).
    pub fn film(&self, race: Race) -> Option<&FilmContact> {
        self.film.as_ref().map(|(i, o)| match race {
            Race::Inner => i,
            Race::Outer => o,
        })
    }

    /// Hertz solution of a race (at α0).
    pub fn hertz(&self, race: Race) -> &HertzContact {
        match race {
            Race::Inner => &self.hertz_inner,
            Race::Outer => &self.hertz_outer,
        }
    }

    /// Series constant of both contacts of one ball, K_n = (K_i^{−2/3} + K_o^{−2/3})^{−3/2}.
    pub fn k_series(&self) -> f64 {
        (self.k_inner.powf(-2.0 / 3.0) + self.k_outer.powf(-2.0 / 3.0)).powf(-1.5)
    }

    /// Groove curvature-centre circle of a race in the ring frame: (axial offset x_g, radius R_g)
    /// \[m\] (docs/model.md#geometry). With play s0 the inner circle moves *toward* the outer one along the
    /// contact line, so the unloaded groove-centre distance is B·D − s0: the balls are free until
    /// the rings have moved s0. (Moving it "outward", as first written, would make s0 an interference.)
    pub fn groove_centre(&self, race: Race) -> (f64, f64) {
        let (s, c) = self.alpha0.sin_cos();
        match race {
            Race::Inner => {
                let e = (self.f_inner - 0.5) * self.d - self.clearance;
                (e * s, 0.5 * self.dm + e * c)
            }
            Race::Outer => {
                let e = (self.f_outer - 0.5) * self.d;
                (-e * s, 0.5 * self.dm - e * c)
            }
        }
    }

    /// Unloaded distance between the two groove centres, B·D − s0 \[m\]: a ball touches both
    /// races (zero total approach) when the distance is B·D.
    pub fn groove_centre_distance(&self) -> f64 {
        self.b_total * self.d - self.clearance
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table1() -> Bearing {
        Bearing::load("niu2014-table1").unwrap()
    }

    #[test]
    fn clearance_is_play_not_interference() {
        let mut f = crate::config::BearingFile::load("niu2014-table1").unwrap();
        f.bearing.clearance = 10e-6;
        let b = Bearing::new(&f).unwrap();
        let (xi, ri) = b.groove_centre(Race::Inner);
        let (xo, ro) = b.groove_centre(Race::Outer);
        let dist = (xi - xo).hypot(ri - ro);
        // Total approach |A| − B·D is −s0 unloaded: a gap.
        assert!((dist - b.b_total * b.d + 10e-6).abs() < 1e-15);
        assert!((b.groove_centre_distance() - dist).abs() < 1e-15);
    }

    #[test]
    fn groove_centres_are_bd_apart_along_the_free_contact_line() {
        let b = table1();
        let (xi, ri) = b.groove_centre(Race::Inner);
        let (xo, ro) = b.groove_centre(Race::Outer);
        let (dx, dr) = (xi - xo, ri - ro);
        assert!(((dx * dx + dr * dr).sqrt() - b.b_total * b.d).abs() < 1e-15);
        assert!((dx.atan2(dr) - b.alpha0).abs() < 1e-12);
    }

    #[test]
    fn ball_mass_and_inertia_match_spec() {
        let b = table1();
        assert!((b.ball_mass - 8.419e-3).abs() < 5e-6, "{}", b.ball_mass);
        assert!(
            (b.ball_inertia - 1.358e-7).abs() < 5e-10,
            "{}",
            b.ball_inertia
        );
    }
}
