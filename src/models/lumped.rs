//! L2: the lumped radial/axial model after Sawalhi & Randall (2008), docs/model.md#l2.
//!
//! Bodies: the inner ring with half the balls (x, y, z), the pedestal with the outer ring and the
//! other half of the balls (y, z), and an optional high-frequency resonator on the pedestal in z.
//! Balls are massless and move kinematically at the loaded cage speed from L1; each ball couples
//! the rings through the series Hertz constant of its two contacts and the contact damping (or,
//! with a `[lubrication]` section, the two lubricant films in series, docs/model.md#film).
//! A spall removes the finite-ball drop g(y_b) from the ball's approach and changes the Hertz
//! constant of its race (docs/model.md#spall). Waviness, off-size balls and track roughness add
//! their approach at each ball's azimuth (docs/model.md#distributed).
//!
//! Besides the mechanical states, the cage angle θ_c and the shaft angle φ are states (so that
//! speed changes between communication steps keep the balls and an inner-ring spall continuous).
//! Ball motion is prescribed, so the instants at which a ball crosses a spall edge or its centre
//! (where g has a kink) are known: they are reported as stops and the integrator lands on them,
//! with the half of the spall each ball is in frozen in between.

use super::Model;
use crate::ball_spall::BallSpall;
use crate::contact::FilmContact;
use crate::defect::{Defect, DefectContact};
use crate::geometry::{Bearing, Race};
use crate::load_distribution;
use crate::models::{out, SimError};
use crate::operating::{OperatingPoint, RingLoad};
use crate::roughness::Roughness;
use crate::scene::{CageSpeed, Pulse, Resonator, Scene};
use crate::waviness::Waviness;
use std::f64::consts::{PI, TAU};

// State layout.
const X: usize = 0;
const Y: usize = 1;
const Z: usize = 2;
const YP: usize = 3;
const ZP: usize = 4;
const VX: usize = 5;
const VY: usize = 6;
const VZ: usize = 7;
const VYP: usize = 8;
const VZP: usize = 9;
const CAGE: usize = 10;
const SHAFT: usize = 11;
const ZR: usize = 12;
const VZR: usize = 13;

/// One ball's approach: normal, Hertz constant and what the force and its linearization need.
#[derive(Debug, Clone, Copy)]
struct Approach {
    /// Normal n = (sin α, cos α e_r) with e_r = (0, e_ry, e_rz).
    sa: f64,
    ca: f64,
    ery: f64,
    erz: f64,
    /// Hertz constant used (the spall's modified one inside it) [N/m^1.5].
    k: f64,
    /// Approach δ [m], groove-centre distance |a| [m], the rates of a along e_x and e_r [m/s]
    /// and the ball's orbital rate θ̇ [rad/s].
    delta: f64,
    /// The unclamped contact force k·δ·|δ|^½ + c·δ̇ [N] ([`LumpedModel::unclamped_force`]).
    q_raw: f64,
    delta_rate: f64,
    len: f64,
    dax: f64,
    dar: f64,
    theta_rate: f64,
}

/// The lubricant films of a ball's two contacts in series (docs/model.md#film).
#[derive(Debug, Clone, Copy)]
struct LumpedFilm {
    inner: FilmContact,
    outer: FilmContact,
    /// Weights of the film dampers in series through the Hertz springs:
    /// c = c_i λ_o² + c_o λ_i², λ_k = K_k^{2/3}/(K_i^{2/3} + K_o^{2/3}).
    lam_inner: f64,
    lam_outer: f64,
    /// D/dm and dm/2 [m] for the entraining speeds.
    d_over_dm: f64,
    pitch_radius: f64,
}

impl LumpedFilm {
    /// Force k·φ·δ|δ|^½ + c δ̇ of a ball whose series Hertz constant is `k`, at approach `delta`
    /// and rate `delta_rate`, contact angle cosine `ca`, orbital rate `theta_rate` and shaft
    /// speed `shaft`: both films at the Hertz load Q = k δ^{3/2}, each at its race's pure-rolling
    /// entraining speed, their compliances added to the series Hertz one and their dampers
    /// combined through the Hertz springs.
    #[inline(always)]
    fn force(
        &self,
        k: f64,
        delta: f64,
        delta_rate: f64,
        ca: f64,
        theta_rate: f64,
        shaft: f64,
    ) -> f64 {
        let gamma = self.d_over_dm * ca;
        let u_outer = theta_rate * self.pitch_radius * (1.0 + gamma);
        let u_inner = (shaft - theta_rate) * self.pitch_radius * (1.0 - gamma);
        let dp = delta.max(0.0);
        let q = k * dp * dp.sqrt();
        let (h_i, c_i) = self.inner.law(q, u_inner);
        let (h_o, c_o) = self.outer.law(q, u_outer);
        let c = c_i * self.lam_outer * self.lam_outer + c_o * self.lam_inner * self.lam_inner;
        FilmContact::series_factor(delta, h_i + h_o) * k * delta * delta.abs().sqrt()
            + c * delta_rate
    }
}

/// Which part of the spall a ball is in; frozen inside an integration step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Zone {
    Outside,
    /// Between the entry edge and the centre (along-track coordinate of the ball's motion < 0).
    FirstHalf,
    /// Between the centre and the exit edge.
    SecondHalf,
}

/// The lumped model.
#[derive(Clone)]
pub struct LumpedModel {
    bearing: Bearing,
    z: usize,
    /// B·D − s0: unloaded distance of the groove centres [m].
    bd: f64,
    /// B·D: groove-centre distance at which a ball touches both races [m].
    bd_touch: f64,
    sin_a0: f64,
    cos_a0: f64,
    k_series: f64,
    c_b: f64,
    /// The lubricant films (None: the constant damping `c_b`).
    film: Option<LumpedFilm>,
    m1: f64,
    /// A force law on the ring added to `inputs`' load (force coupling).
    ring_load: Option<RingLoad>,
    m2: f64,
    k_py: f64,
    k_pz: f64,
    c_py: f64,
    c_pz: f64,
    resonator: Option<(f64, f64, f64)>, // (m_r, k_r, c_r)
    pulse: Option<Pulse>,
    /// The raceway spalls (docs/model.md#several-spalls): each ball checks each.
    defects: Vec<Defect>,
    /// The spalls on balls (docs/model.md#ball-spall): their ball checks them at both contacts.
    ball_spalls: Vec<BallSpall>,
    /// Harmonic waviness and off-size balls (docs/model.md#waviness).
    waviness: Option<Waviness>,
    /// Random track roughness (docs/model.md#roughness).
    roughness: Option<Roughness>,
    /// Slip jitter: standard deviation of each ball's position [rad] and the seed.
    jitter_sigma: f64,
    jitter_seed: u64,
    /// Azimuth of ball 0 at θ_c = 0 [rad].
    theta_start: f64,
    inputs: OperatingPoint,
    /// ω_c/Ω from L1 at the inputs of the last L1 solve, and those inputs.
    cage_ratio: f64,
    /// Where the cage speed comes from (`lumped.cage_speed`).
    cage: CageSpeed,
    l1_inputs: OperatingPoint,
    /// Static ring displacement relative to the outer ring from L1 at rest (for the initial
    /// state: this model has no centrifugal ball forces, see [`LumpedModel::new`]).
    ring_offset: [f64; 3],
    /// Spall zone of ball j for raceway spall k at `k * z + j` (z entries without one), then
    /// of ball spall s at its (outer, inner) contact at `ball_zones + 2 s + (0, 1)`.
    zones: Vec<Zone>,
    ball_zones: usize,
    /// Groove compliances K^(−2/3) of the (inner, outer) race without a spall.
    c_groove: [f64; 2],
    /// (sin, cos) of each ball's offset 2πj/z from ball 0.
    ball_offsets: Vec<(f64, f64)>,
    /// Contact mode of each ball, frozen inside a step once [`Model::update_mode`] has run
    /// (`modes_set`): loss and regain of contact are state events (see [`Model::events`]).
    in_contact: Vec<bool>,
    modes_set: bool,
    /// Balls whose contact event fired since the last mode update: their mode flips.
    fired: Vec<bool>,
    /// Coupling mode "motion": the ring translation is prescribed (zero acceleration).
    prescribed: bool,
    /// A located ring's held axial displacement \[m\] (its axial acceleration is zero).
    held_axial: Option<f64>,
    /// Force of the bearing on the inner ring at the last RHS evaluation [N].
    ring_force: [f64; 3],
    /// Each ball's normal force at the last RHS evaluation [N] (for the outputs).
    q_ball: Vec<f64>,
}

/// Balls per chunk of [`LumpedModel::approaches`].
const CHUNK: usize = 8;

/// Scale turning the unclamped contact force [N] into the length unit of the contact event
/// function [m] (any positive constant gives the same roots; this one makes both branches of
/// min(δ, F/K) comparable near a Hertz deflection of ~1 µm).
const EVENT_FORCE_SCALE: f64 = 1e8;

impl LumpedModel {
    /// Builds the model for a scene; the cage speed and the initial ring offset come from L1.
    pub fn new(
        scene: &Scene,
        bearing: &Bearing,
        inputs: &OperatingPoint,
    ) -> Result<Self, SimError> {
        let file = &bearing.file;
        let half_balls = 0.5 * bearing.z as f64 * bearing.ball_mass;
        let resonator = scene.lumped.resonator.as_ref().map(|r: &Resonator| {
            let w = TAU * r.frequency;
            (r.mass, r.mass * w * w, 2.0 * r.damping_ratio * r.mass * w)
        });
        let reference_load = reference_ball_load(bearing, inputs);
        let specs: Vec<_> = scene.spalls().collect();
        let defects = crate::defect::build_races(&specs, bearing, reference_load)?;
        let ball_spalls = crate::ball_spall::build_all(&specs, bearing, reference_load)?;
        let ball_zones = bearing.z * defects.len().max(1);
        let n_zones = ball_zones + 2 * ball_spalls.len();
        let mut m = Self {
            bearing: bearing.clone(),
            z: bearing.z,
            bd: bearing.groove_centre_distance(),
            bd_touch: bearing.b_total * bearing.d,
            sin_a0: bearing.alpha0.sin(),
            cos_a0: bearing.alpha0.cos(),
            k_series: bearing.k_series(),
            c_b: file.contact.c_br,
            film: bearing.film.map(|(inner, outer)| {
                let (ci, co) = (
                    bearing.k_inner.powf(2.0 / 3.0),
                    bearing.k_outer.powf(2.0 / 3.0),
                );
                LumpedFilm {
                    inner,
                    outer,
                    lam_inner: ci / (ci + co),
                    lam_outer: co / (ci + co),
                    d_over_dm: bearing.d / bearing.dm,
                    pitch_radius: 0.5 * bearing.dm,
                }
            }),
            m1: file.inner_ring.mass + half_balls,
            ring_load: None,
            m2: file.pedestal.mass + half_balls,
            k_py: file.pedestal.k_y,
            k_pz: file.pedestal.k_z,
            c_py: file.pedestal.c_y,
            c_pz: file.pedestal.c_z,
            resonator,
            pulse: scene.pulse.clone(),
            defects,
            ball_spalls,
            waviness: match &scene.waviness {
                Some(w) => Waviness::new(w, bearing)?,
                None => None,
            },
            roughness: match &scene.roughness {
                Some(r) => Roughness::new(r, bearing)?,
                None => None,
            },
            jitter_sigma: scene.lumped.slip_jitter * TAU / bearing.z as f64,
            jitter_seed: scene.lumped.seed,
            theta_start: 0.0,
            inputs: *inputs,
            cage_ratio: 0.0,
            cage: scene.lumped.cage_speed,
            l1_inputs: *inputs,
            ring_offset: [0.0; 3],
            zones: vec![Zone::Outside; n_zones],
            ball_zones,
            c_groove: [
                bearing.k_inner.powf(-2.0 / 3.0),
                bearing.k_outer.powf(-2.0 / 3.0),
            ],
            ball_offsets: (0..bearing.z)
                .map(|j| (TAU * j as f64 / bearing.z as f64).sin_cos())
                .collect(),
            in_contact: vec![true; bearing.z],
            modes_set: false,
            fired: vec![false; bearing.z],
            prescribed: false,
            // A located ring held where the start's axial load alone puts it: at rest, as this
            // model has no centrifugal ball forces (at speed they can move L1's ring out of
            // this model's contacts).
            held_axial: super::held_axial(
                scene,
                bearing,
                &OperatingPoint {
                    shaft_speed: 0.0,
                    ..*inputs
                },
            )?,
            ring_force: [0.0; 3],
            q_ball: vec![0.0; bearing.z],
        };
        m.theta_start = m.choose_theta_start();
        let qs = m.solve_l1(bearing, inputs)?;
        // The start: L1's ring at rest, which is this model's own equilibrium (no centrifugal
        // ball forces here). At speed they move L1's ring by tens of µm (−56 µm axially at
        // 14286 rpm under 345 N on the Table-1 bearing), far enough that no ball of this model
        // touched and the Newton refinement had nothing to work with.
        let rest = OperatingPoint {
            shaft_speed: 0.0,
            ..*inputs
        };
        let start = if inputs.shaft_speed > 0.0 {
            super::solve_l1_held(
                bearing,
                &rest,
                m.held_axial,
                "the quasi-static (L1) start at rest of the lumped level",
            )?
        } else {
            qs
        };
        m.ring_offset = [start.delta_axial, start.delta_y, start.delta_z];
        Ok(m)
    }

    /// Ball 0's start azimuth: 0, or half a spacing when that puts a ball near the spall
    /// (docs/model.md#initial-state: no ball within θ_e + 0.02 rad of a defect at the start).
    fn choose_theta_start(&self) -> f64 {
        if self.defects.is_empty() {
            return 0.0;
        }
        let spacing = TAU / self.z as f64;
        [0.0, 0.5 * spacing, 0.25 * spacing, 0.75 * spacing]
            .into_iter()
            .find(|&s| {
                self.defects.iter().all(|d| {
                    let clear = d.half_angle() + 0.02;
                    (0..self.z).all(|j| wrap(s + spacing * j as f64 - d.theta0()).abs() > clear)
                })
            })
            .unwrap_or(0.5 * spacing)
    }

    /// L1 at the given inputs and the cage-speed ratio from it (the traction solve starts from
    /// the last ratio, solved nearby along a ramp).
    fn solve_l1(
        &mut self,
        bearing: &Bearing,
        inputs: &OperatingPoint,
    ) -> Result<load_distribution::QuasiStatic, SimError> {
        let qs = super::solve_l1_held(
            bearing,
            inputs,
            self.held_axial,
            "the quasi-static (L1) operating point",
        )?;
        let previous = (self.cage_ratio > 0.0).then_some(self.cage_ratio);
        self.cage_ratio = if inputs.shaft_speed > 0.0 {
            super::kinematic_levels_cage_speed(bearing, inputs, &qs, self.cage, previous)?
                / inputs.shaft_speed
        } else {
            kinematic_cage_ratio(bearing, &qs)
        };
        self.l1_inputs = *inputs;
        Ok(qs)
    }

    /// Slip jitter of ball j in cage revolution n [rad] (deterministic in seed, ball, revolution).
    fn jitter_node(&self, j: usize, n: i64) -> f64 {
        if self.jitter_sigma == 0.0 {
            return 0.0;
        }
        let mut s = self
            .jitter_seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add((j as u64).wrapping_mul(0xD1B5_4A32_D192_ED03))
            .wrapping_add((n as u64).wrapping_mul(0x94D0_49BB_1331_11EB));
        let u1 = ((splitmix64(&mut s) >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
        let u2 = ((splitmix64(&mut s) >> 11) as f64) / (1u64 << 53) as f64;
        self.jitter_sigma * (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
    }

    /// Azimuth of ball j and its rate, at cage angle θ_c and cage rate ω_c.
    #[inline(always)]
    fn ball_angle(&self, j: usize, cage: f64, cage_rate: f64) -> (f64, f64) {
        let base = self.theta_start + TAU * j as f64 / self.z as f64 + cage;
        if self.jitter_sigma == 0.0 {
            return (base, cage_rate);
        }
        let rev = cage / TAU;
        let n = rev.floor();
        let s = rev - n;
        let (e0, e1) = (
            self.jitter_node(j, n as i64),
            self.jitter_node(j, n as i64 + 1),
        );
        (
            base + (1.0 - s) * e0 + s * e1,
            cage_rate * (1.0 + (e1 - e0) / TAU),
        )
    }

    fn cage_rate(&self) -> f64 {
        self.cage_ratio * self.inputs.shaft_speed
    }

    /// Ball-to-defect angle and its rate for ball angle θ (rate θ̇) at shaft angle φ.
    #[inline]
    fn theta_bd(&self, d: &Defect, theta: f64, theta_rate: f64, shaft: f64) -> (f64, f64) {
        match d.ring() {
            Race::Outer => (wrap(theta - d.theta0()), theta_rate),
            Race::Inner => (
                wrap(theta - d.theta0() - shaft),
                theta_rate - self.inputs.shaft_speed,
            ),
        }
    }

    /// Defect angles at which the force law has a kink: the edges ±θ_e, the centre (where the
    /// ball changes corners) and the end of the compliance blend ℓ_b past each edge.
    fn stop_angles(&self, d: &Defect) -> [Option<f64>; 5] {
        let te = d.half_angle();
        let y_blend = 0.5 * d.width() - d.blend_length();
        let tb = (d.blend_length() > 0.0 && y_blend > 0.0)
            .then(|| d.r_d1() / d.r_d2() * (y_blend / d.r_d1()).asin());
        [Some(-te), tb.map(|v| -v), Some(0.0), tb, Some(te)]
    }

    /// Round-off of a ball-to-defect angle computed from the cage and shaft angles at time t
    /// [rad]: the angles grow without bound (≈ 4400 rad after 10 s at 9900 rpm) and the time has
    /// an ulp of ≈ 1e-15 s there. Boundaries closer than this are the one a ball is standing on.
    fn angle_tol(t: f64, y: &[f64], rate: f64) -> f64 {
        let magnitude = y[CAGE].abs() + y[SHAFT].abs() + TAU;
        1e-12_f64.max(64.0 * f64::EPSILON * magnitude + 4.0 * f64::EPSILON * t.abs() * rate.abs())
    }

    /// Zone of a ball from its defect angle, looking in the direction of motion at boundaries
    /// (`tol` from [`Self::angle_tol`]).
    fn zone_of(te: f64, theta_bd: f64, rate: f64, tol: f64) -> Zone {
        // Position a hair ahead along the motion decides on which side of a boundary we are.
        let eps = tol * rate.signum();
        let a = theta_bd + if rate == 0.0 { 0.0 } else { eps };
        if a.abs() >= te {
            Zone::Outside
        } else if (a < 0.0) == (rate >= 0.0) {
            Zone::FirstHalf
        } else {
            Zone::SecondHalf
        }
    }

    /// Contact forces of all balls; calls `each(j, Q, sin α, cos α, e_ry, e_rz)`.
    #[inline]
    fn contacts(&self, t: f64, y: &[f64], mut each: impl FnMut(usize, f64, f64, f64, f64, f64)) {
        self.approaches(t, y, |j, a| {
            each(j, self.normal_force(j, a), a.sa, a.ca, a.ery, a.erz)
        });
    }

    /// Unclamped contact force k·δ·|δ|^½ + c·δ̇ [N]: the Hertz law with damping, continued
    /// smoothly to δ < 0 so that a frozen contact mode gives a smooth right-hand side.
    #[inline(always)]
    fn unclamped_force(&self, k: f64, delta: f64, delta_rate: f64) -> f64 {
        k * delta * delta.abs().sqrt() + self.c_b * delta_rate
    }

    /// Normal force of ball j. Before the modes are set (the static Newton start) the clamped
    /// law max(0, k δ^1.5 + c δ̇) for δ > 0; afterwards the frozen mode decides: in contact the
    /// unclamped force, out of contact 0. The switches are located as state events.
    #[inline(always)]
    fn normal_force(&self, j: usize, a: &Approach) -> f64 {
        if !self.modes_set {
            if a.delta > 0.0 {
                a.q_raw.max(0.0)
            } else {
                0.0
            }
        } else if self.in_contact[j] {
            a.q_raw
        } else {
            0.0
        }
    }

    /// Contact event function of a ball: min(δ, F/K) > 0 exactly where the clamped law has a
    /// positive force (δ > 0 and k δ^1.5 + c δ̇ > 0); it is continuous, so loss (F reaching 0)
    /// and regain (δ reaching 0 with the damping jump c δ̇, or F rising through 0) are roots.
    #[inline(always)]
    fn contact_event(a: &Approach) -> f64 {
        a.delta.min(a.q_raw / EVENT_FORCE_SCALE)
    }

    /// Approach of every ball; calls `each(j, approach)` in ball order.
    ///
    /// The balls go in chunks of [`CHUNK`]: first the approach of every ball of the chunk as if
    /// none were in the spall, in straight-line loops over fixed-size arrays (the compiler packs
    /// the square roots and divisions of neighbouring balls), then, ball by ball, the spall's
    /// change for the balls inside it and the call. Per ball the operations are those of a
    /// one-ball-at-a-time loop, in the same order.
    #[inline]
    fn approaches(&self, t: f64, y: &[f64], mut each: impl FnMut(usize, &Approach)) {
        let _ = t;
        let dx = y[X];
        let dy = y[Y] - y[YP];
        let dz = y[Z] - y[ZP];
        let vx = y[VX];
        let vy = y[VY] - y[VYP];
        let vz = y[VZ] - y[VZP];
        let cage_rate = self.cage_rate();
        // Without jitter the balls are equally spaced: one sin_cos for the cage, then a rotation
        // by each ball's fixed offset.
        let (s0, c0) = (self.theta_start + y[CAGE]).sin_cos();
        let equal_spacing = self.jitter_sigma == 0.0;
        // The axial part of the groove-centre distance is the same for every ball.
        let ax = self.bd * self.sin_a0 + dx;
        let ar0 = self.bd * self.cos_a0;
        let (k0, c_b) = (self.k_series, self.c_b);
        for base in (0..self.z).step_by(CHUNK) {
            let m = CHUNK.min(self.z - base);
            // Per ball of the chunk: (sin θ, cos θ), θ and θ̇ (θ only with jitter).
            let mut sn = [0.0; CHUNK];
            let mut cs = [1.0; CHUNK];
            let mut theta = [f64::NAN; CHUNK];
            let mut theta_rate = [cage_rate; CHUNK];
            if equal_spacing {
                for (i, (s, c)) in sn.iter_mut().zip(cs.iter_mut()).enumerate().take(m) {
                    let (sj, cj) = self.ball_offsets[base + i];
                    (*s, *c) = (s0 * cj + c0 * sj, c0 * cj - s0 * sj);
                }
            } else {
                for i in 0..m {
                    let (th, rate) = self.ball_angle(base + i, y[CAGE], cage_rate);
                    (sn[i], cs[i]) = th.sin_cos();
                    (theta[i], theta_rate[i]) = (th, rate);
                }
            }
            // e_r(θ) = (0, −sin θ, cos θ); de_r/dθ = e_θ = (0, −cos θ, −sin θ).
            let mut ar = [0.0; CHUNK];
            let mut dar = [0.0; CHUNK];
            let mut len = [0.0; CHUNK];
            let mut inv_len = [0.0; CHUNK];
            let mut delta = [0.0; CHUNK];
            let mut delta_rate = [0.0; CHUNK];
            let mut q_raw = [0.0; CHUNK];
            for i in 0..CHUNK {
                let (ery, erz) = (-sn[i], cs[i]);
                ar[i] = ar0 + dy * ery + dz * erz;
                dar[i] = vy * ery + vz * erz + (dy * (-cs[i]) + dz * (-sn[i])) * theta_rate[i];
                len[i] = (ax * ax + ar[i] * ar[i]).sqrt();
                inv_len[i] = 1.0 / len[i];
                delta[i] = len[i] - self.bd_touch;
                delta_rate[i] = (ax * vx + ar[i] * dar[i]) * inv_len[i];
                q_raw[i] = k0 * delta[i] * delta[i].abs().sqrt() + c_b * delta_rate[i];
            }
            for i in 0..m {
                let j = base + i;
                let (mut delta, mut delta_rate, mut k) = (delta[i], delta_rate[i], k0);
                // Each spall the ball is over: its drop and rate, and the defective race's
                // blended compliance (a ball meets at most one spall per race at a time).
                let mut c_race = self.c_groove;
                let mut hit = false;
                for (k, d) in self.defects.iter().enumerate() {
                    let zone = self.zones[k * self.z + j];
                    if zone != Zone::Outside {
                        let (theta, theta_rate) = if equal_spacing {
                            self.ball_angle(j, y[CAGE], cage_rate)
                        } else {
                            (theta[i], theta_rate[i])
                        };
                        let (tbd, tbd_rate) = self.theta_bd(d, theta, theta_rate, y[SHAFT]);
                        let y_b = d.along_track(tbd);
                        let y_rate = d.along_track_rate(tbd, tbd_rate);
                        if let Some(c) = Self::frozen_contact(d, zone, y_b, tbd_rate) {
                            delta -= c.g;
                            delta_rate -= c.dg_dy * y_rate;
                            c_race[usize::from(d.ring() == Race::Outer)] =
                                c.k_edge.powf(-2.0 / 3.0);
                            hit = true;
                        }
                    }
                }
                // A spall on this ball, at the contact it is over (its drop adds to a raceway
                // spall's there; the edge constant is the later one's).
                for (s, bs) in self.ball_spalls.iter().enumerate() {
                    if bs.ball() != j {
                        continue;
                    }
                    for (r, race) in [Race::Outer, Race::Inner].into_iter().enumerate() {
                        let zone = self.zones[self.ball_zones + 2 * s + r];
                        if zone == Zone::Outside {
                            continue;
                        }
                        let (theta, theta_rate) = if equal_spacing {
                            self.ball_angle(j, y[CAGE], cage_rate)
                        } else {
                            (theta[i], theta_rate[i])
                        };
                        let (psi, psi_rate) = bs.spin(self.orbit(j, theta), theta_rate);
                        let y_b = bs.along_track(bs.offset(race, psi));
                        let y_rate = bs.along_track(psi_rate);
                        if let Some(c) = Self::frozen_contact(bs.at(race), zone, y_b, psi_rate) {
                            delta -= c.g;
                            delta_rate -= c.dg_dy * y_rate;
                            c_race[usize::from(race == Race::Outer)] = c.k_edge.powf(-2.0 / 3.0);
                            hit = true;
                        }
                    }
                }
                if hit {
                    // Series constant with the defective races' blended compliances.
                    let c_sum = c_race[0] + c_race[1];
                    k = 1.0 / (c_sum * c_sum.sqrt());
                }
                let distributed = self.waviness.is_some() || self.roughness.is_some();
                if distributed {
                    // The distributed defects' added approach at the ball's azimuth.
                    let (theta, theta_rate) = if equal_spacing {
                        self.ball_angle(j, y[CAGE], cage_rate)
                    } else {
                        (theta[i], theta_rate[i])
                    };
                    let shaft_rate = self.inputs.shaft_speed;
                    if let Some(w) = &self.waviness {
                        let orbit = self.orbit(j, theta);
                        let (dd, dr) = w.added(j, theta, theta_rate, orbit, y[SHAFT], shaft_rate);
                        delta += dd;
                        delta_rate += dr;
                    }
                    if let Some(r) = &self.roughness {
                        let (dd, dr) = r.added(theta, theta_rate, y[SHAFT], shaft_rate);
                        delta += dd;
                        delta_rate += dr;
                    }
                }
                // The force once, at the final approach and constant (the chunk's own when
                // nothing changed them).
                let q_raw = if let Some(f) = &self.film {
                    f.force(
                        k,
                        delta,
                        delta_rate,
                        ar[i] * inv_len[i],
                        theta_rate[i],
                        self.inputs.shaft_speed,
                    )
                } else if hit || distributed {
                    self.unclamped_force(k, delta, delta_rate)
                } else {
                    q_raw[i]
                };
                each(
                    j,
                    &Approach {
                        sa: ax * inv_len[i],
                        ca: ar[i] * inv_len[i],
                        ery: -sn[i],
                        erz: cs[i],
                        k,
                        delta,
                        q_raw,
                        delta_rate,
                        len: len[i],
                        dax: vx,
                        dar: dar[i],
                        theta_rate: theta_rate[i],
                    },
                );
            }
        }
    }

    /// Re-derives the spall zone of every ball at (t, y).
    fn update_zones(&mut self, t: f64, y: &[f64]) {
        let cage_rate = self.cage_rate();
        for (k, d) in self.defects.iter().enumerate() {
            for j in 0..self.z {
                let (theta, theta_rate) = self.ball_angle(j, y[CAGE], cage_rate);
                let (tbd, rate) = self.theta_bd(d, theta, theta_rate, y[SHAFT]);
                self.zones[k * self.z + j] =
                    Self::zone_of(d.half_angle(), tbd, rate, Self::angle_tol(t, y, rate));
            }
        }
        for (s, bs) in self.ball_spalls.iter().enumerate() {
            let j = bs.ball();
            let (theta, theta_rate) = self.ball_angle(j, y[CAGE], cage_rate);
            let (psi, psi_rate) = bs.spin(self.orbit(j, theta), theta_rate);
            let tol = Self::angle_tol(t, y, psi_rate) * bs.spin_per_orbit();
            for (r, race) in [Race::Outer, Race::Inner].into_iter().enumerate() {
                self.zones[self.ball_zones + 2 * s + r] =
                    Self::zone_of(bs.half_angle(), bs.offset(race, psi), psi_rate, tol);
            }
        }
    }

    /// When an angle `x` moving at `rate` (≠ 0) next reaches one of `bounds` ahead in its
    /// direction of motion, not the one it is on (within `tol`): the time, or ∞ (angles wrap
    /// at 2π).
    fn next_boundary(t: f64, x: f64, rate: f64, tol: f64, bounds: &[Option<f64>]) -> f64 {
        let mut best = f64::INFINITY;
        for &b in bounds.iter().flatten() {
            let mut gap = (b - x) * rate.signum();
            if gap <= tol {
                gap += TAU;
            }
            // A stop that rounds to `t` would end the search (None): skip it instead.
            let stop = t + gap / rate.abs();
            if stop > t {
                best = best.min(stop);
            }
        }
        best
    }

    /// Orbital angle ball j at azimuth `theta` has travelled since the start [rad].
    #[inline(always)]
    fn orbit(&self, j: usize, theta: f64) -> f64 {
        theta - self.theta_start - TAU * j as f64 / self.z as f64
    }

    /// The contact of a ball over a spall in the frozen half `zone`, at along-track position
    /// `y_b` moving at `rate` (its sign: the direction of motion); the frozen half decides the
    /// branch at the kink y_b = 0: the first half lies behind the centre along the motion, the
    /// second ahead of it. A ball a round-off past an edge is taken at the edge from inside
    /// ([`Defect::clamp_into_zone`]): the zone is frozen until the next stop.
    #[inline(always)]
    fn frozen_contact(d: &Defect, zone: Zone, y_b: f64, rate: f64) -> Option<DefectContact> {
        let mut y_b = d.clamp_into_zone(y_b);
        let ahead = if rate >= 0.0 { 1.0 } else { -1.0 };
        let side = if zone == Zone::FirstHalf {
            -ahead
        } else {
            ahead
        };
        if y_b * side <= 0.0 {
            y_b = side * 1e-15;
        }
        d.contact_at(y_b)
    }

    /// Static equilibrium of the inner ring at t = 0 against the pedestal at its static deflection,
    /// refined by Newton from the L1 offset at rest so that the start is quiet.
    fn static_ring(&self, y: &mut [f64]) {
        let mut f = [0.0; 3];
        let residual = |m: &Self, y: &[f64], f: &mut [f64; 3]| {
            *f = [m.inputs.fx, m.inputs.fy, m.inputs.fz];
            m.contacts(0.0, y, |_, q, sa, ca, ery, erz| {
                f[0] -= q * sa;
                f[1] -= q * ca * ery;
                f[2] -= q * ca * erz;
            });
        };
        // A located ring keeps its axial place: only y and z are solved for.
        let held = self.held_axial.is_some();
        for _ in 0..50 {
            residual(self, y, &mut f);
            if held {
                f[0] = 0.0;
            }
            let norm = f.iter().map(|v| v.abs()).fold(0.0, f64::max);
            if norm < 1e-7 {
                break;
            }
            // Finite-difference Jacobian (3 × 3), solved by Cramer's rule.
            let mut jac = [[0.0; 3]; 3];
            let h = 1e-9;
            for (col, idx) in [X, Y, Z].into_iter().enumerate() {
                let save = y[idx];
                y[idx] = save + h;
                let mut fp = [0.0; 3];
                residual(self, y, &mut fp);
                y[idx] = save;
                for row in 0..3 {
                    jac[row][col] = (fp[row] - f[row]) / h;
                }
            }
            if held {
                jac[0] = [1.0, 0.0, 0.0];
                jac[1][0] = 0.0;
                jac[2][0] = 0.0;
            }
            let Some(step) = solve3(&jac, &f) else { break };
            for (i, idx) in [X, Y, Z].into_iter().enumerate() {
                y[idx] -= step[i].clamp(-1e-6, 1e-6);
            }
        }
    }
}

/// ω_c/Ω under outer-race control at the L1 contact angles (used at zero speed).
fn kinematic_cage_ratio(bearing: &Bearing, qs: &load_distribution::QuasiStatic) -> f64 {
    let loaded: Vec<_> = qs.balls.iter().filter(|b| b.q_inner > 0.0).collect();
    if loaded.is_empty() {
        return 0.5 * (1.0 - bearing.gamma(bearing.alpha0));
    }
    loaded
        .iter()
        .map(|b| {
            crate::fault_frequencies::outer_race_control(bearing, b.alpha_inner, b.alpha_outer)
                .cage_ratio
        })
        .sum::<f64>()
        / loaded.len() as f64
}

/// A representative ball load for the blend length "b" of the spall edge: the mean load of a
/// ball carrying the axial load, or the peak load of the radial load zone (Stribeck), at least 10 N.
fn reference_ball_load(bearing: &Bearing, inputs: &OperatingPoint) -> f64 {
    let z = bearing.z as f64;
    let axial = inputs.fx.abs() / (z * bearing.alpha0.sin().max(0.1));
    let radial = 5.0 * inputs.fy.hypot(inputs.fz) / z;
    axial.max(radial).max(10.0)
}

fn splitmix64(s: &mut u64) -> u64 {
    *s = s.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut x = *s;
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// Maps an angle to (−π, π].
#[inline]
pub fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(TAU);
    if r > PI {
        r - TAU
    } else {
        r
    }
}

fn solve3(a: &[[f64; 3]; 3], b: &[f64; 3]) -> Option<[f64; 3]> {
    let det = |m: &[[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    if !d.is_finite() || d.abs() < 1e-300 {
        return None;
    }
    let mut x = [0.0; 3];
    for (col, xc) in x.iter_mut().enumerate() {
        let mut m = *a;
        for row in 0..3 {
            m[row][col] = b[row];
        }
        *xc = det(&m) / d;
    }
    Some(x)
}

impl Model for LumpedModel {
    fn dim(&self) -> usize {
        if self.resonator.is_some() {
            14
        } else {
            12
        }
    }

    fn state_name(&self, i: usize) -> String {
        match i {
            X | Y | Z => format!("inner-ring displacement along {}", ["x", "y", "z"][i - X]),
            VX | VY | VZ => format!("inner-ring velocity along {}", ["x", "y", "z"][i - VX]),
            YP => "pedestal displacement along y".into(),
            ZP => "pedestal displacement along z".into(),
            VYP => "pedestal velocity along y".into(),
            VZP => "pedestal velocity along z".into(),
            CAGE => "cage angle θ_c".into(),
            SHAFT => "shaft angle φ".into(),
            ZR => "resonator displacement along z".into(),
            VZR => "resonator velocity along z".into(),
            _ => format!("state component {i}"),
        }
    }

    /// Whether any ball still carries load (a positive force under the clamped contact law).
    fn diagnose(&mut self, t: f64, y: &[f64]) -> Option<String> {
        let mut carrying = 0;
        self.approaches(t, y, |_, a| {
            if a.delta > 0.0 && a.q_raw > 0.0 {
                carrying += 1;
            }
        });
        (carrying == 0).then(|| {
            format!(
                "contact is lost at every ball (none of the {} balls presses on both races)",
                self.z
            )
        })
    }

    fn nominal(&self, out: &mut [f64]) {
        // Deflection-scale displacements 1e-5 m, vibration velocities 1e-2 m/s, angles 1 rad.
        for (i, v) in out.iter_mut().enumerate() {
            *v = match i {
                X | Y | Z | YP | ZP | ZR => 1e-5,
                VX | VY | VZ | VYP | VZP | VZR => 1e-2,
                _ => 1.0,
            };
        }
    }

    fn initial_state(&self, y: &mut [f64]) {
        y.iter_mut().for_each(|v| *v = 0.0);
        let yp = self.inputs.fy / self.k_py;
        let zp = self.inputs.fz / self.k_pz;
        y[YP] = yp;
        y[ZP] = zp;
        y[X] = self.ring_offset[0];
        y[Y] = yp + self.ring_offset[1];
        y[Z] = zp + self.ring_offset[2];
        if self.resonator.is_some() {
            y[ZR] = zp;
        }
        // Newton refinement of the ring position on this model's own contact law.
        self.static_ring(y);
    }

    fn set_inputs(&mut self, inputs: &OperatingPoint, _t: f64, _y: &[f64]) -> Result<(), SimError> {
        if self.prescribed {
            // Motion coupling: the simulation moves the L1 point (update_operating_point).
            self.inputs = *inputs;
            return Ok(());
        }
        // Re-solve L1 for the cage-speed ratio when the operating point has moved by more than
        // 2 % since the last solve (an operating point without equilibrium is an error).
        let old = self.l1_inputs;
        let load = |i: &OperatingPoint| (i.fx * i.fx + i.fy * i.fy + i.fz * i.fz).sqrt();
        let moved = (inputs.shaft_speed - old.shaft_speed).abs()
            > 0.02 * old.shaft_speed.abs().max(1.0)
            || load(&OperatingPoint {
                shaft_speed: 0.0,
                fx: inputs.fx - old.fx,
                fy: inputs.fy - old.fy,
                fz: inputs.fz - old.fz,
            }) > 0.02 * load(&old).max(1.0);
        if moved {
            let bearing = self.bearing.clone();
            self.solve_l1(&bearing, inputs)?;
        }
        self.inputs = *inputs;
        Ok(())
    }

    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let mut f_ring = [0.0; 3];
        let mut q_ball = std::mem::take(&mut self.q_ball);
        self.contacts(t, y, |j, q, sa, ca, ery, erz| {
            f_ring[0] -= q * sa;
            f_ring[1] -= q * ca * ery;
            f_ring[2] -= q * ca * erz;
            q_ball[j] = q;
        });
        self.q_ball = q_ball;
        self.ring_force = f_ring;
        let pulse = self.pulse.as_ref().map_or(0.0, |p| p.force(t));
        dydt[X] = y[VX];
        dydt[Y] = y[VY];
        dydt[Z] = y[VZ];
        dydt[YP] = y[VYP];
        dydt[ZP] = y[VZP];
        if self.prescribed {
            dydt[VX] = 0.0;
            dydt[VY] = 0.0;
            dydt[VZ] = 0.0;
        } else {
            let law = |k: usize, v: f64| self.ring_load.as_ref().map_or(0.0, |l| l.force(k, t, v));
            dydt[VX] = if self.held_axial.is_some() {
                0.0
            } else {
                (self.inputs.fx + law(0, y[VX]) + f_ring[0]) / self.m1
            };
            dydt[VY] = (self.inputs.fy + law(1, y[VY]) + f_ring[1]) / self.m1;
            dydt[VZ] = (self.inputs.fz + law(2, y[VZ]) + f_ring[2]) / self.m1;
        }
        let mut fpz = -f_ring[2] - self.k_pz * y[ZP] - self.c_pz * y[VZP] - pulse;
        if let Some((m_r, k_r, c_r)) = self.resonator {
            let f_r = k_r * (y[ZR] - y[ZP]) + c_r * (y[VZR] - y[VZP]);
            fpz += f_r;
            dydt[ZR] = y[VZR];
            dydt[VZR] = -f_r / m_r;
        }
        dydt[VYP] = (-f_ring[1] - self.k_py * y[YP] - self.c_py * y[VYP]) / self.m2;
        dydt[VZP] = fpz / self.m2;
        dydt[CAGE] = self.cage_rate();
        dydt[SHAFT] = self.inputs.shaft_speed;
    }

    fn next_stop(&self, t: f64, y: &[f64], t_max: f64) -> Option<f64> {
        let mut best = f64::INFINITY;
        let cage_rate = self.cage_rate();
        for d in &self.defects {
            let bounds = self.stop_angles(d);
            for j in 0..self.z {
                let (theta, theta_rate) = self.ball_angle(j, y[CAGE], cage_rate);
                let (tbd, rate) = self.theta_bd(d, theta, theta_rate, y[SHAFT]);
                if rate != 0.0 {
                    let tol = Self::angle_tol(t, y, rate);
                    best = best.min(Self::next_boundary(t, tbd, rate, tol, &bounds));
                }
            }
        }
        for bs in &self.ball_spalls {
            let j = bs.ball();
            let (theta, theta_rate) = self.ball_angle(j, y[CAGE], cage_rate);
            let (psi, rate) = bs.spin(self.orbit(j, theta), theta_rate);
            if rate != 0.0 {
                let tol = Self::angle_tol(t, y, rate) * bs.spin_per_orbit();
                let bounds = bs.stop_offsets();
                for race in [Race::Outer, Race::Inner] {
                    let x = bs.offset(race, psi);
                    best = best.min(Self::next_boundary(t, x, rate, tol, &bounds));
                }
            }
        }
        if self.jitter_sigma > 0.0 && cage_rate > 0.0 {
            // The jitter is linear within a cage revolution: land on revolution boundaries.
            let next_rev = ((y[CAGE] / TAU).floor() + 1.0) * TAU;
            let mut gap = next_rev - y[CAGE];
            if gap <= 1e-13 {
                gap += TAU;
            }
            best = best.min(t + gap / cage_rate);
        }
        if let Some(tp) = self.pulse.as_ref().and_then(|p| p.next_kink(t)) {
            best = best.min(tp);
        }
        (best <= t_max && best > t).then_some(best)
    }

    fn update_mode(&mut self, t: f64, y: &[f64]) {
        self.update_zones(t, y);
        // A ball whose contact event just fired switches mode (at the located state its event
        // function is within the location tolerance of 0, on either side). Every other ball
        // takes its mode from the sign of the event function (on an exact 0 the direction of
        // the approach decides: coming together is contact).
        let mut modes = std::mem::take(&mut self.in_contact);
        let was_set = self.modes_set;
        self.approaches(t, y, |j, a| {
            modes[j] = if was_set && self.fired[j] {
                !modes[j]
            } else {
                let g = Self::contact_event(a);
                g > 0.0 || (g == 0.0 && a.delta_rate > 0.0)
            };
        });
        self.in_contact = modes;
        self.fired.iter_mut().for_each(|f| *f = false);
        self.modes_set = true;
    }

    fn event_fired(&mut self, index: usize) {
        if let Some(f) = self.fired.get_mut(index) {
            *f = true;
        }
    }

    fn n_events(&self) -> usize {
        self.z
    }

    fn event_name(&self, i: usize) -> String {
        format!("the contact of ball {}", i + 1)
    }

    /// The contact events only switch a ball's mode: in contact the function is positive.
    fn mode_sign(&self, i: usize) -> Option<f64> {
        let on = *self.in_contact.get(i)?;
        self.modes_set.then_some(if on { 1.0 } else { -1.0 })
    }

    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        self.approaches(t, y, |j, a| {
            g[j] = Self::contact_event(a);
        });
    }

    fn outputs(&mut self, t: f64, y: &[f64], o: &mut [f64]) {
        let z = self.z;
        let mut dydt = [0.0; 14];
        let n = self.dim();
        self.rhs(t, y, &mut dydt[..n]);
        // The bearing force and the ball forces of this RHS evaluation.
        let f_ring = self.ring_force;
        let balls = out::has_ball_block(o, z);
        if balls {
            for (j, &q) in self.q_ball.iter().enumerate() {
                // Inside a step the frozen contact law may give a round-off-small negative
                // force just before a located loss of contact: report it as 0.
                o[out::CONTACT_START + j] = q.max(0.0);
                o[out::CONTACT_START + z + j] = q.max(0.0);
            }
        }
        o[out::PEDESTAL_A_Y] = dydt[VYP];
        o[out::PEDESTAL_A_Z] = dydt[VZP];
        o[out::PEDESTAL_Y] = y[YP];
        o[out::PEDESTAL_Z] = y[ZP];
        o[out::PEDESTAL_V_Y] = y[VYP];
        o[out::PEDESTAL_V_Z] = y[VZP];
        o[out::RING_X] = y[X];
        o[out::RING_Y] = y[Y];
        o[out::RING_Z] = y[Z];
        o[out::BEARING_F_X] = f_ring[0];
        o[out::BEARING_F_Y] = f_ring[1];
        o[out::BEARING_F_Z] = f_ring[2];
        o[out::FRICTION_TORQUE] = 0.0;
        o[out::CAGE_SPEED] = self.cage_rate();
        if !balls {
            return;
        }
        for j in 0..z {
            o[out::orbit_speed(z, j)] = self.ball_angle(j, y[CAGE], self.cage_rate()).1;
        }
        out::set_separation_flags(o, z);
    }

    fn discrete_state(&self) -> Vec<f64> {
        let i = &self.l1_inputs;
        vec![self.cage_ratio, i.shaft_speed, i.fx, i.fy, i.fz]
    }

    fn set_discrete_state(&mut self, s: &[f64]) -> Result<(), String> {
        if s.len() != 5 {
            return Err(format!("lumped model state has 5 values, got {}", s.len()));
        }
        self.cage_ratio = s[0];
        self.l1_inputs = OperatingPoint {
            shaft_speed: s[1],
            fx: s[2],
            fy: s[3],
            fz: s[4],
        };
        Ok(())
    }

    /// The L1 operating point (moved at the start of an advance in motion coupling) and the
    /// frozen modes: contact per ball, spall zone per ball, pending event flips.
    fn checkpoint(&self, b: &mut Vec<f64>) {
        let i = &self.l1_inputs;
        b.clear();
        b.extend_from_slice(&[self.cage_ratio, i.shaft_speed, i.fx, i.fy, i.fz]);
        b.extend_from_slice(&self.ring_offset);
        b.push(f64::from(u8::from(self.modes_set)));
        let flag = |on: bool| f64::from(u8::from(on));
        b.extend(self.in_contact.iter().map(|&c| flag(c)));
        b.extend(self.fired.iter().map(|&f| flag(f)));
        b.extend(self.zones.iter().map(|z| match z {
            Zone::Outside => 0.0,
            Zone::FirstHalf => 1.0,
            Zone::SecondHalf => 2.0,
        }));
    }

    fn rollback(&mut self, b: &[f64], _t: f64, _y: &[f64]) -> Result<(), String> {
        let z = self.z;
        let n = 9 + 2 * z + self.zones.len();
        if b.len() != n {
            return Err(format!("lumped checkpoint has {n} values, got {}", b.len()));
        }
        self.cage_ratio = b[0];
        self.l1_inputs = OperatingPoint {
            shaft_speed: b[1],
            fx: b[2],
            fy: b[3],
            fz: b[4],
        };
        self.ring_offset.copy_from_slice(&b[5..8]);
        self.modes_set = b[8] != 0.0;
        let (contact, rest) = b[9..].split_at(z);
        let (fired, zones) = rest.split_at(z);
        for (m, &v) in self.in_contact.iter_mut().zip(contact) {
            *m = v != 0.0;
        }
        for (f, &v) in self.fired.iter_mut().zip(fired) {
            *f = v != 0.0;
        }
        for (zone, &v) in self.zones.iter_mut().zip(zones) {
            *zone = match v as u8 {
                1 => Zone::FirstHalf,
                2 => Zone::SecondHalf,
                _ => Zone::Outside,
            };
        }
        Ok(())
    }

    fn cage_speed(&self) -> f64 {
        self.cage_rate()
    }

    fn ring_states(&self) -> Option<super::RingStates> {
        Some(super::RingStates {
            pos: [X, Y, Z],
            vel: [VX, VY, VZ],
        })
    }

    fn update_operating_point(&mut self, inputs: &OperatingPoint) -> Result<(), SimError> {
        let bearing = self.bearing.clone();
        self.solve_l1(&bearing, inputs).map(|_| ())
    }

    fn set_prescribed_ring(&mut self, on: bool) {
        self.prescribed = on;
    }

    fn set_ring_load(&mut self, law: Option<RingLoad>) -> bool {
        self.ring_load = law;
        true
    }

    /// Per closed contact (force on the ring f = −Q n, n = (sin α, cos α e_r), a the groove-
    /// centre vector, ȧ its rate, P = e_x e_xᵀ + e_r e_rᵀ the ball's plane, d the ring's
    /// displacement relative to the pedestal):
    ///
    /// ```text
    ///   ∂δ/∂d = nᵀ,   ∂δ̇/∂d = (ȧ − (n·ȧ) n)ᵀ/|a| + cos α θ̇ e_θᵀ,   ∂δ̇/∂v = nᵀ,
    ///   ∂Q/∂d = 1.5 K δ^½ nᵀ + c_b ∂δ̇/∂d,   ∂Q/∂v = c_b nᵀ,
    ///   ∂f/∂d = −n ∂Q/∂d − Q/|a| (P − n nᵀ),   ∂f/∂v = −c_b n nᵀ,
    /// ```
    ///
    /// with K the spall's modified series constant (and δ less the drop) for a ball in it.
    fn reaction_jacobian(&mut self, t: f64, y: &[f64]) -> Option<super::ReactionJacobian> {
        if self.film.is_some() {
            // The film's load- and speed-dependent law: central differences of the reaction.
            return None;
        }
        let mut jac = super::ReactionJacobian::default();
        let c_b = self.c_b;
        self.approaches(t, y, |j, c| {
            let q = self.normal_force(j, c);
            if q <= 0.0 || c.delta <= 0.0 {
                return;
            }
            let n = [c.sa, c.ca * c.ery, c.ca * c.erz];
            let er = [0.0, c.ery, c.erz];
            let ex = [1.0, 0.0, 0.0];
            let eth = [0.0, -c.erz, c.ery];
            let adot = [c.dax, c.dar * c.ery, c.dar * c.erz];
            let n_adot = n[0] * adot[0] + n[1] * adot[1] + n[2] * adot[2];
            let stiff = 1.5 * c.k * c.delta.sqrt();
            let geo = q / c.len;
            for col in 0..3 {
                let ddr_dd = (adot[col] - n_adot * n[col]) / c.len + c.ca * c.theta_rate * eth[col];
                let dq_dd = stiff * n[col] + c_b * ddr_dd;
                let dq_dv = c_b * n[col];
                for row in 0..3 {
                    let p = ex[row] * ex[col] + er[row] * er[col];
                    jac.dfdx[row][col] -= n[row] * dq_dd + geo * (p - n[row] * n[col]);
                    jac.dfdv[row][col] -= n[row] * dq_dv;
                }
            }
        });
        Some(jac)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    /// The scene's lumped model and its start state.
    fn at_start(scene: &Scene) -> (LumpedModel, Vec<f64>) {
        let b = Bearing::new(&scene.bearing).unwrap();
        let m = LumpedModel::new(scene, &b, &scene.operating).unwrap();
        let mut y = vec![0.0; m.dim()];
        m.initial_state(&mut y);
        (m, y)
    }

    /// A stop at the spall's entry edge rounds either way: a ball the stop put in the first
    /// half may sit a round-off outside the edge. It must take the in-zone law there (the
    /// abrupt edge's jump of the Hertz constant belongs to the stop), or the step after the
    /// stop sees the jump between its first stage and the others and is rejected over and over
    /// (about 18 times at half of the entries on the default scene before the fix). The
    /// right-hand side is then continuous from the stop on: ball 1's force and the ring's
    /// accelerations 1e-10 s along the motion differ by the motion, not by the jump.
    #[test]
    fn a_ball_held_in_the_zone_a_round_off_past_the_entry_edge_takes_the_in_zone_law() {
        let (mut m, mut y) = at_start(&Scene::default_scene());
        let n = m.dim();
        let d = m.defects[0].clone();
        assert_eq!(d.blend_length(), 0.0, "the default edge is abrupt (D2)");
        let rate = m.cage_rate();
        assert!(rate > 0.0);
        let tbd_of = |m: &LumpedModel, y: &[f64]| {
            let (theta, theta_rate) = m.ball_angle(0, y[CAGE], rate);
            m.theta_bd(&d, theta, theta_rate, y[SHAFT]).0
        };
        // Ball 1 onto the entry edge θ_bd = −θ_e, then back by round-offs until it lies on the
        // edge or outside it (|y_b| ≥ w/2).
        y[CAGE] += -d.half_angle() - tbd_of(&m, &y);
        let mut back = 0;
        while d.along_track(tbd_of(&m, &y)).abs() < 0.5 * d.width() {
            y[CAGE] -= y[CAGE].abs().max(1.0) * f64::EPSILON;
            back += 1;
            assert!(back < 1000, "the edge is a few round-offs away");
        }
        m.update_mode(0.0, &y);
        assert_eq!(m.zones[0], Zone::FirstHalf, "a hair ahead is inside");
        let mut f0 = vec![0.0; n];
        m.rhs(0.0, &y, &mut f0);
        let q0 = m.q_ball[0];
        let h = 1e-10;
        let y1: Vec<f64> = y.iter().zip(&f0).map(|(v, d)| v + h * d).collect();
        let mut f1 = vec![0.0; n];
        m.rhs(h, &y1, &mut f1);
        let q1 = m.q_ball[0];
        assert!(q0 > 100.0, "ball 1 is loaded ({q0} N)");
        assert!(
            (q1 - q0).abs() <= 1e-6 * q0,
            "ball 1's force jumps from {q0} N to {q1} N within {h} s"
        );
        // The accelerations on the scale of one ball's force on a 1 kg ring (the ring's are
        // the balance of fourteen such forces).
        for i in [VX, VY, VZ] {
            assert!(
                (f1[i] - f0[i]).abs() <= 1e-6 * q0,
                "ring acceleration {i}: {} against {}",
                f0[i],
                f1[i]
            );
        }
    }

    /// The same at the centre, where the drop has a kink and the frozen half picks its branch,
    /// for a ball moving against the along-track axis (an inner-race spall: θ_bd falls): a
    /// ball the centre stop put in the second half but that lies a round-off on the first
    /// half's side takes the second half's branch, so ball 1's approach rate is continuous from
    /// the stop on (the first half's branch there has the drop's slope of the other sign), and
    /// it is the climb out of the spall that the drop table gives past the centre.
    #[test]
    fn a_ball_moving_backwards_a_round_off_before_the_centre_takes_its_frozen_halfs_branch() {
        let mut scene = Scene::default_scene();
        scene.defect.as_mut().unwrap().ring = Race::Inner.into();
        let (mut m, mut y) = at_start(&scene);
        let n = m.dim();
        let d = m.defects[0].clone();
        let rate = m.cage_rate();
        let tbd_of = |m: &LumpedModel, y: &[f64]| {
            let (theta, theta_rate) = m.ball_angle(0, y[CAGE], rate);
            m.theta_bd(&d, theta, theta_rate, y[SHAFT])
        };
        assert!(
            tbd_of(&m, &y).1 < 0.0,
            "an inner-race spall passes the balls backwards"
        );
        // Ball 1 onto the centre θ_bd = 0 (the shaft angle moves the spall), then to a
        // round-off on the first half's side (θ_bd > 0 for this motion).
        y[SHAFT] += tbd_of(&m, &y).0;
        let mut back = 0;
        while tbd_of(&m, &y).0 <= 0.0 {
            y[SHAFT] -= y[SHAFT].abs().max(1.0) * f64::EPSILON;
            back += 1;
            assert!(back < 1000, "the centre is a few round-offs away");
        }
        m.update_mode(0.0, &y);
        assert_eq!(
            m.zones[0],
            Zone::SecondHalf,
            "a hair ahead is past the centre"
        );
        // Ball 1's approach rate, where the drop's slope enters (its force may be 0 here: the
        // ball hangs between the edges).
        let rate_of = |m: &LumpedModel, y: &[f64]| {
            let mut r = f64::NAN;
            m.approaches(0.0, y, |j, a| {
                if j == 0 {
                    r = a.delta_rate;
                }
            });
            r
        };
        let mut f0 = vec![0.0; n];
        m.rhs(0.0, &y, &mut f0);
        let h = 1e-10;
        let y1: Vec<f64> = y.iter().zip(&f0).map(|(v, d)| v + h * d).collect();
        let (r0, r1) = (rate_of(&m, &y), rate_of(&m, &y1));
        // Past the centre the ball climbs the front edge: the drop shrinks at |dg/dy| |ẏ_b|
        // (the drop table's slope just past the centre, the along-track speed), nearly all of
        // the approach rate (the rings' own motion adds a few per cent).
        let (tbd, tbd_rate) = tbd_of(&m, &y1);
        let y_b = d.along_track(tbd);
        assert!(y_b < 0.0, "y1 is past the centre ({y_b} m)");
        let climb =
            d.contact_at(y_b).unwrap().dg_dy.abs() * d.along_track_rate(tbd, tbd_rate).abs();
        assert!(
            (r1 - climb).abs() <= 0.1 * climb,
            "approach rate {r1} m/s, the climb alone {climb} m/s"
        );
        // Along the motion it changes by about 5e-6 m/s in that time (the drop's curvature at
        // the ball's speed over the spall); the other branch would be a jump of about
        // 2 |dg/dy| ẏ_b ≈ 3 m/s.
        assert!(
            (r1 - r0).abs() <= 1e-3,
            "ball 1's approach rate jumps from {r0} m/s to {r1} m/s within {h} s"
        );
    }
}
