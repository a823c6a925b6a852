//! A spall on a ball (docs/model.md#ball-spall).
//!
//! The spall sits on the ball's rolling great circle and turns with the ball's spin: at the
//! levels with kinematic balls, the spin of pure rolling on the fixed outer race at the nominal
//! contact angle, ψ = ψ_0 + (dm/D)(1 + γ_0)·(orbital angle travelled), the same spin the ball
//! waviness uses. The two contacts of a ball lie on that circle half a turn apart: the spall
//! meets the outer race at ψ ≡ π/2 and the inner race at ψ ≡ −π/2, so it strikes twice per
//! spin revolution (2 × BSF).
//!
//! At each contact it has the three effects of a raceway spall, with the along-track position
//! of the contact point from the spall centre y = (D/2)·wrap(ψ − ψ_race): the finite-contact
//! drop g(y) and its rate, and the edge Hertz constant. Both come from the drop table of a
//! raceway spall of the same size on that race ([`Defect`], built once per race): the table
//! depends on the two surfaces only through the ball radius bridging the spall, as it does for
//! a raceway spall, so the same approximation holds (docs/model.md#ball-spall says what it
//! leaves out).
//!
//! The ball-level models (reduced, full) turn it with the ball's simulated rotation instead:
//! they integrate its direction on the ball and place it at each contact themselves
//! (`models::balls::core`), asking this spall only for its ball, θ0 and the drop tables.

use crate::config::{ConfigError, DefectMode};
use crate::defect::{wrap, Defect, DefectSpec, Site};
use crate::geometry::{Bearing, Race};
use std::f64::consts::FRAC_PI_2;

/// A spall on one ball, precomputed for a bearing.
#[derive(Debug, Clone)]
pub struct BallSpall {
    /// The ball's index from 0.
    ball: usize,
    /// Spin angle of the spall centre at t = 0, from midway between the contacts \[rad\].
    psi0: f64,
    /// Spin angle per orbital angle, (dm/D)(1 + γ_0).
    spin_per_orbit: f64,
    /// D/2 \[m\].
    radius: f64,
    /// Half the spall's extent in spin angle, (w_d/2)/(D/2) \[rad\].
    half_angle: f64,
    /// The drop tables and edge constants at the (outer, inner) contact.
    outer: Defect,
    inner: Defect,
}

impl BallSpall {
    /// Precomputes a spall on a ball (`spec.ring` must be [`Site::Ball`]) in `mode` (None: the
    /// bearing's). Errors name the field: `defect.ball` beyond the bearing's balls, and those of
    /// [`Defect::new`] (`defect.width` < D, ...).
    pub fn new(
        spec: &DefectSpec,
        bearing: &Bearing,
        reference_load: f64,
        mode: Option<DefectMode>,
    ) -> Result<Self, ConfigError> {
        let Site::Ball(number) = spec.ring else {
            return Err(ConfigError::new(
                "defect.ring",
                format!("'{}' is a raceway, not a ball", spec.ring.name()),
            ));
        };
        if number == 0 || number > bearing.z {
            return Err(ConfigError::new(
                "defect.ball",
                format!(
                    "{number} is not a ball of this bearing (balls 1 to {})",
                    bearing.z
                ),
            ));
        }
        let on = |race: Race| {
            Defect::with_mode(
                &DefectSpec {
                    ring: race.into(),
                    ..spec.clone()
                },
                bearing,
                reference_load,
                mode,
            )
        };
        let radius = 0.5 * bearing.d;
        Ok(Self {
            ball: number - 1,
            psi0: wrap(spec.theta0),
            spin_per_orbit: bearing.kinematic_spin_per_orbit(),
            radius,
            half_angle: 0.5 * spec.width / radius,
            outer: on(Race::Outer)?,
            inner: on(Race::Inner)?,
        })
    }

    /// The spalled ball's index (from 0).
    pub fn ball(&self) -> usize {
        self.ball
    }

    /// Spin angle of the spall centre at t = 0, θ0 wrapped to (−π, π] \[rad\].
    pub fn theta0(&self) -> f64 {
        self.psi0
    }

    /// Spin angle of the spall centre and its rate after the ball has orbited `orbit` \[rad\]
    /// at `orbit_rate` \[rad/s\] since the start.
    #[inline]
    pub fn spin(&self, orbit: f64, orbit_rate: f64) -> (f64, f64) {
        (
            self.psi0 + self.spin_per_orbit * orbit,
            self.spin_per_orbit * orbit_rate,
        )
    }

    /// Spin angle per orbital angle of the kinematic balls, (dm/D)(1 + γ_0).
    pub fn spin_per_orbit(&self) -> f64 {
        self.spin_per_orbit
    }

    /// Spin-angle offset of the spall centre from the contact with `race`, wrapped to
    /// (−π, π] \[rad\]: 0 when the centre is at the contact point, positive past it.
    #[inline]
    pub fn offset(&self, race: Race, psi: f64) -> f64 {
        match race {
            Race::Outer => wrap(psi - FRAC_PI_2),
            Race::Inner => wrap(psi + FRAC_PI_2),
        }
    }

    /// Half the spall's extent in spin angle, (w_d/2)/(D/2) \[rad\].
    pub fn half_angle(&self) -> f64 {
        self.half_angle
    }

    /// Along-track position of the contact point from the spall centre at spin offset `x`
    /// \[m\] (and, for a rate, `x_rate` in the same way).
    #[inline]
    pub fn along_track(&self, x: f64) -> f64 {
        self.radius * x
    }

    /// The spall as met by the contact with `race` (its drop table and edge constants).
    pub fn at(&self, race: Race) -> &Defect {
        match race {
            Race::Outer => &self.outer,
            Race::Inner => &self.inner,
        }
    }

    /// Spin offsets at which the force law has a kink: the edges, the centre and the end of
    /// the compliance blend past each edge.
    pub fn stop_offsets(&self) -> [Option<f64>; 5] {
        let d = &self.outer;
        let y_blend = 0.5 * d.width() - d.blend_length();
        let xb = (d.blend_length() > 0.0 && y_blend > 0.0).then(|| y_blend / self.radius);
        [
            Some(-self.half_angle),
            xb.map(|v| -v),
            Some(0.0),
            xb,
            Some(self.half_angle),
        ]
    }
}

/// The spalls on balls of a scene's list (raceway spalls skipped), each in its mode; errors
/// name each by its place `k` in the whole list (`defect[k].field` when there are several),
/// and two that overlap on one ball are refused.
pub fn build_all(
    specs: &[(&DefectSpec, Option<DefectMode>)],
    bearing: &Bearing,
    reference_load: f64,
) -> Result<Vec<BallSpall>, ConfigError> {
    let several = specs.len() > 1;
    let mut all = Vec::new();
    let mut places = Vec::new();
    for (k, &(s, mode)) in specs.iter().enumerate() {
        if s.ring.race().is_some() {
            continue;
        }
        all.push(
            BallSpall::new(s, bearing, reference_load, mode)
                .map_err(|e| crate::defect::indexed_error(e, k, several))?,
        );
        places.push(k);
    }
    let listed: Vec<(usize, &BallSpall)> = places.iter().copied().zip(&all).collect();
    check_overlaps(&listed)?;
    Ok(all)
}

/// Refuses two spalls on the same ball whose extents on its rolling circle intersect; the
/// error names both entries (`defect[a]`, `defect[b]`, indices into the scene's list).
pub fn check_overlaps(spalls: &[(usize, &BallSpall)]) -> Result<(), ConfigError> {
    for (b, &(kb, sb)) in spalls.iter().enumerate() {
        for &(ka, sa) in &spalls[..b] {
            let gap = wrap(sa.psi0 - sb.psi0).abs();
            if sa.ball == sb.ball && gap < sa.half_angle + sb.half_angle {
                return Err(ConfigError::new(
                    format!("defect[{kb}]"),
                    format!(
                        "the spalls defect[{ka}] and defect[{kb}] on ball {} overlap: their \
                         centres are {gap:.6} rad apart on its rolling circle, less than the \
                         sum of their half angles {:.6} rad",
                        sa.ball + 1,
                        sa.half_angle + sb.half_angle
                    ),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::{BearingFile, BlendLength};
    use std::f64::consts::{PI, TAU};

    /// The Table-1 bearing (D = 12.7 mm, dm = 70 mm, α0 = 30°, 14 balls) and a 1.0 × 0.2 mm
    /// spall on `ball` at θ0, with the bearing's blend length `blend` [m].
    fn spall(ball: usize, theta0: f64, blend: f64) -> Result<BallSpall, ConfigError> {
        let mut file = BearingFile::default_preset();
        file.defect.blend_length = BlendLength::Metres(blend);
        let b = Bearing::new(&file).unwrap();
        let spec = DefectSpec {
            ring: Site::Ball(ball),
            width: 1.0e-3,
            depth: 0.2e-3,
            theta0,
        };
        BallSpall::new(&spec, &b, 500.0, None)
    }

    #[test]
    fn geometry_on_the_rolling_circle() {
        let s = spall(3, 0.25, 0.0).unwrap();
        assert_eq!(s.ball(), 2);
        // Half extent (w/2)/(D/2) = 1.0/12.7 rad; along the track (D/2)·x.
        assert!((s.half_angle() - 1.0 / 12.7).abs() < 1e-12);
        assert!((s.along_track(0.01) - 6.35e-5).abs() < 1e-15);
        assert!((s.along_track(-0.02) + 1.27e-4).abs() < 1e-15);
        // Spin per orbit of pure rolling on the outer race: (dm/D)(1 + D cos α0/dm).
        let k = 70.0 / 12.7 * (1.0 + 12.7 * (PI / 6.0).cos() / 70.0);
        assert!(
            (s.spin_per_orbit() - k).abs() < 1e-12,
            "{}",
            s.spin_per_orbit()
        );
        let (psi, rate) = s.spin(2.0, 10.0);
        assert!((psi - (0.25 + 2.0 * k)).abs() < 1e-12 && (rate - 10.0 * k).abs() < 1e-12);
        // The outer contact at ψ = π/2, the inner at −π/2, wrapped to (−π, π].
        assert!((s.offset(Race::Outer, PI / 2.0 + 0.01) - 0.01).abs() < 1e-12);
        assert!((s.offset(Race::Outer, PI / 2.0 + 0.01 + 3.0 * TAU) - 0.01).abs() < 1e-9);
        assert!((s.offset(Race::Inner, -PI / 2.0 - 0.02) + 0.02).abs() < 1e-12);
        assert!((s.offset(Race::Inner, PI / 2.0) - PI).abs() < 1e-12);
        assert!((s.offset(Race::Outer, 0.0) + PI / 2.0).abs() < 1e-12);
        // The drop at the centre: the ball's circle over a spall narrower than its reach,
        // R − √(R² − w²/4) with R = D/2 (the floor at 0.2 mm is far below).
        let r: f64 = 6.35e-3;
        let g = r - (r * r - 0.25e-6).sqrt();
        for race in [Race::Outer, Race::Inner] {
            let c = s.at(race).contact_at(1e-12).unwrap();
            assert!((c.g - g).abs() < 1e-3 * g, "{race:?}: {} vs {g}", c.g);
            assert!(s.at(race).contact_at(0.51e-3).is_none());
        }
    }

    #[test]
    fn stops_at_the_edges_the_centre_and_the_blend_ends() {
        let h = 1.0 / 12.7;
        let s = spall(1, 0.0, 0.0).unwrap();
        assert_eq!(s.stop_offsets(), [Some(-h), None, Some(0.0), None, Some(h)]);
        let s = spall(1, 0.0, 0.1e-3).unwrap();
        let xb = 0.4e-3 / 6.35e-3;
        let got = s.stop_offsets();
        assert_eq!((got[0], got[2], got[4]), (Some(-h), Some(0.0), Some(h)));
        assert!((got[1].unwrap() + xb).abs() < 1e-12 && (got[3].unwrap() - xb).abs() < 1e-12);
        // A blend over the whole half width ends at the centre: no stop of its own.
        let s = spall(1, 0.0, 0.5e-3).unwrap();
        assert_eq!(s.stop_offsets(), [Some(-h), None, Some(0.0), None, Some(h)]);
    }

    #[test]
    fn a_ball_outside_the_bearing_or_a_raceway_site_is_refused() {
        let e = spall(15, 0.0, 0.0).unwrap_err();
        assert_eq!(e.field, "defect.ball");
        assert!(e.message.contains("balls 1 to 14"), "{e}");
        assert!(spall(14, 0.0, 0.0).is_ok());
        let file = BearingFile::default_preset();
        let b = Bearing::new(&file).unwrap();
        let spec = DefectSpec {
            ring: Site::Outer,
            width: 1.0e-3,
            depth: 0.2e-3,
            theta0: 0.0,
        };
        assert_eq!(
            BallSpall::new(&spec, &b, 500.0, None).unwrap_err().field,
            "defect.ring"
        );
    }

    #[test]
    fn two_spalls_on_one_ball_must_not_overlap() {
        let h = 1.0 / 12.7;
        let a = spall(2, 0.0, 0.0).unwrap();
        let near = spall(2, 1.99 * h, 0.0).unwrap();
        let apart = spall(2, 2.01 * h, 0.0).unwrap();
        let other = spall(3, 0.0, 0.0).unwrap();
        let e = check_overlaps(&[(0, &a), (4, &near)]).unwrap_err();
        assert_eq!(e.field, "defect[4]");
        assert!(
            e.message.contains("defect[0]") && e.message.contains("ball 2"),
            "{e}"
        );
        assert!(check_overlaps(&[(0, &a), (4, &apart)]).is_ok());
        assert!(check_overlaps(&[(0, &a), (1, &other)]).is_ok());
        // Across ±π: θ0 = π − 0.5h and −π + 0.5h are h apart.
        let p = spall(2, PI - 0.5 * h, 0.0).unwrap();
        let q = spall(2, -PI + 0.5 * h, 0.0).unwrap();
        assert!(check_overlaps(&[(0, &p), (1, &q)]).is_err());
    }
}
