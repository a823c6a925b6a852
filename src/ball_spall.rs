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
