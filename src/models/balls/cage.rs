//! The cage of the ball-level models (full L4, reduced L3; docs/model.md#cage): a rigid ring
//! that turns about the bearing axis and moves in y and z (6 states: its angle, as a deviation
//! χ from the reference cage angle ψ, the centre's y and z, and their rates), with a pocket per
//! ball and, by choice, guided by the balls or by a land of either ring. After the Gupta-type
//! cage models (P. K. Gupta, J. Lubr. Technol. 101 (1979) 312–318; *Advanced Dynamics of Rolling
//! Elements*, 1984, ch. 5 and 6), reduced to the motion in the radial plane:
//!
//! - **Pocket** j is centred at the cage angle `φ_j = ψ + χ + θ_start + 2πj/z`, dm/2 from the
//!   cage's centre `c`. The ball's offset from it along the orbit is
//!   `u_j = (r_b − c)·e_θ(φ_j)` and, for a ball-riding cage (guidance `balls`: its pockets
//!   centre it), radially `w_j = (r_b − c)·e_r(φ_j) − dm/2` (a land-guided cage's cylindrical
//!   pocket leaves the radial motion free: `w_j = 0`). Beyond half the diametral pocket
//!   clearance `c_p` the ball presses the pocket's wall: `δ = √(u_j² + w_j²) − c_p/2`,
//!   `n = (u_j e_θ + w_j e_r)/√(u_j² + w_j²)` (from the ball's centre to the wall),
//!   `P = max(0, K_p δ^{3/2} + c_pd δ̇)` with δ̇ the rate of √(u_j² + w_j²), the pocket turning
//!   with the cage. The ball feels `−P n` and
//!   the friction of the wall `−μ_p P v_t/√(v_t² + v_0²) t` opposing the slip v_t of its surface
//!   against the wall at `r_b + R n` along `t = e_x × n`, the wall's direction in the radial
//!   plane (the cage has no axial freedom: the slip's axial part, whose friction the cage could
//!   only pass to ground, is left out; v_0 = [`FRICTION_SPEED`] rounds Coulomb's law at rest),
//!   with its moment about the ball's centre; the cage the reaction at that point (its force
//!   and its moment about the cage axis).
//! - **Land** (guidance `inner_land` / `outer_land`): the cage's centre relative to the guiding
//!   ring's, `e = c − c_ring`, beyond the radial land clearance c_l touches the land:
//!   `δ = |e| − c_l`, `N = max(0, K_l δ^{3/2} + c_ld δ̇)` pushes the cage back along −e/|e|, at
//!   its guided surface on the side of e (outer land) or opposite (inner land), with the
//!   land's friction `μ_l N` opposing the circumferential slip of the cage's surface against
//!   the land's (the inner land turns with the shaft); the ring takes the reaction.
//!
//! Both laws are C¹ at first touch (δ^{3/2}); the damping's jump at touch is left to the error
//! controller, without event functions. No allocation after [`Cage::new`].

use super::ball_contact::{add, cross, dot, scale, sub, RingPose, V3};
use super::pass::BallFrame;
use crate::config::CageGuidance;
use crate::contact::{HertzContact, HertzSolution};
use crate::geometry::Bearing;
use std::f64::consts::TAU;

/// Derived cage mass as a fraction of the balls' total mass (docs/model.md#cage-defaults: a
/// machined brass cage of the Table-1 bearing, an annulus 0.3 D thick and D wide less its
/// pockets, weighs 0.28 of its balls).
pub const MASS_FRACTION: f64 = 0.3;
/// Derived diametral pocket clearance as a fraction of the ball diameter (Gupta-type models
/// use 1–3 %).
pub const POCKET_CLEARANCE_FRACTION: f64 = 0.02;
/// Derived cage material: machined brass, Young's modulus \[Pa\].
pub const BRASS_YOUNGS_MODULUS: f64 = 105e9;
/// Derived cage material: machined brass, Poisson's ratio.
pub const BRASS_POISSON: f64 = 0.34;
/// Derived friction coefficient of the pocket faces and of the land (lubricated sliding).
pub const FRICTION: f64 = 0.1;
/// Derived radial land clearance as a fraction of the diametral pocket clearance: a quarter,
/// so that the land, not the pockets (which let the cage move c_p/2), guides the cage.
pub const LAND_CLEARANCE_FRACTION: f64 = 0.25;
/// Derived land radius: the pitch radius ± this fraction of D (outer land +, inner land −).
pub const LAND_OFFSET: f64 = 0.3;
/// Slip speed that rounds Coulomb friction at rest, μ N v/√(v² + v_0²) \[m/s\].
pub const FRICTION_SPEED: f64 = 0.01;

/// The cage's constants, from the bearing file's `[cage]` with the derived values where a key
/// is absent (docs/model.md#cage-defaults).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CageParams {
    /// Mass \[kg\].
    pub mass: f64,
    /// Polar moment of inertia \[kg m²\].
    pub inertia: f64,
    /// Diametral pocket clearance \[m\].
    pub pocket_clearance: f64,
    /// Hertz constant of the ball–pocket contact [N/m^1.5].
    pub pocket_stiffness: f64,
    /// Ball–pocket damping [N s/m].
    pub pocket_damping: f64,
    /// Pocket friction coefficient.
    pub pocket_friction: f64,
    /// Guidance.
    pub guidance: CageGuidance,
    /// Radial land clearance \[m\].
    pub land_clearance: f64,
    /// Radius of the guiding land \[m\].
    pub land_radius: f64,
    /// Hertz-type constant of the cage–land contact [N/m^1.5].
    pub land_stiffness: f64,
    /// Cage–land damping [N s/m].
    pub land_damping: f64,
    /// Land friction coefficient.
    pub land_friction: f64,
}

/// Hertz constant of a ball of diameter `d` (modulus `e_ball`, Poisson `nu_ball`) in a
/// cylindrical pocket of diameter d + `clearance` (modulus `e_cage`, Poisson `nu_cage`)
/// [N/m^1.5]: curvature sums 2/d along the pocket's axis and 2/d − 2/(d + clearance) around it
/// (a conformal contact), the reduced modulus of the two materials.
pub fn pocket_stiffness(
    d: f64,
    clearance: f64,
    e_ball: f64,
    nu_ball: f64,
    e_cage: f64,
    nu_cage: f64,
) -> f64 {
    let e_star = 1.0 / ((1.0 - nu_ball * nu_ball) / e_ball + (1.0 - nu_cage * nu_cage) / e_cage);
    // HertzContact takes E′ with Q = K δ^{3/2}, K = (2/3) E′ √r for a sphere on a flat of the
    // same steel (E′ = 2 E*).
    HertzContact::new(
        2.0 / d,
        2.0 / d - 2.0 / (d + clearance),
        2.0 * e_star,
        HertzSolution::Exact,
    )
    .stiffness
}

impl CageParams {
    /// The cage of `bearing` (its file's `[cage]`, the rest derived).
    pub fn of(bearing: &Bearing) -> Self {
        let c = &bearing.file.cage;
        let m = &bearing.file.material;
        let d = bearing.d;
        let r_pitch = 0.5 * bearing.dm;
        let mass = c
            .mass
            .unwrap_or(MASS_FRACTION * bearing.z as f64 * bearing.ball_mass);
        let pocket_clearance = c.pocket_clearance.unwrap_or(POCKET_CLEARANCE_FRACTION * d);
        let pocket_k = c.pocket_stiffness.unwrap_or_else(|| {
            pocket_stiffness(
                d,
                pocket_clearance,
                m.youngs_modulus,
                m.poisson,
                c.youngs_modulus.unwrap_or(BRASS_YOUNGS_MODULUS),
                c.poisson.unwrap_or(BRASS_POISSON),
            )
        });
        let offset = LAND_OFFSET * d;
        Self {
            mass,
            inertia: c.inertia.unwrap_or(mass * r_pitch * r_pitch),
            pocket_clearance,
            pocket_stiffness: pocket_k,
            pocket_damping: c.pocket_damping.unwrap_or(bearing.file.contact.c_br),
            pocket_friction: c.pocket_friction.unwrap_or(FRICTION),
            guidance: c.guidance,
            land_clearance: c
                .land_clearance
                .unwrap_or(LAND_CLEARANCE_FRACTION * pocket_clearance),
            land_radius: c.land_radius.unwrap_or(match c.guidance {
                CageGuidance::InnerLand => r_pitch - offset,
                _ => r_pitch + offset,
            }),
            land_stiffness: c.land_stiffness.unwrap_or(pocket_k),
            land_damping: c.land_damping.unwrap_or(bearing.file.contact.c_br),
            land_friction: c.land_friction.unwrap_or(FRICTION),
        }
    }
}

/// The cage's pose and motion: the angle of pocket 0's centre, the centre and the rates.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CagePose {
    /// Angle of pocket 0's centre, ψ + χ + θ_start \[rad\].
    pub angle: f64,
    /// Centre (0, y, z) \[m\].
    pub c: V3,
    /// Angular rate ω_c about +x [rad/s].
    pub w: f64,
    /// Centre velocity (0, ẏ, ż) [m/s].
    pub v: V3,
}

/// One ball–pocket contact of an evaluation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PocketContact {
    /// The ball's offset from the pocket centre along the orbit, (r_b − c)·e_θ(φ_j) \[m\].
    pub offset: f64,
    /// Its radial offset (r_b − c)·e_r(φ_j) − dm/2 (ball guidance; 0 for a land-guided cage's
    /// cylindrical pocket) \[m\].
    pub radial: f64,
    /// Overlap with the pocket's wall, √(offset² + radial²) − c_p/2 \[m\] (≤ 0: free in the
    /// pocket).
    pub delta: f64,
    /// Normal force P ≥ 0 \[N\].
    pub p: f64,
    /// Unit normal from the ball's centre to the wall, (offset e_θ + radial e_r)/√(…).
    pub n: V3,
    /// Force on the ball, normal and friction \[N\].
    pub f: V3,
    /// Moment on the ball about its centre [N m].
    pub m: V3,
    /// Point of contact (on the ball's surface) \[m\].
    pub at: V3,
}

/// The cage–land contact of an evaluation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LandContact {
    /// Overlap |c − c_ring| − c_l \[m\] (≤ 0: free).
    pub delta: f64,
    /// Normal force N ≥ 0 \[N\].
    pub n: f64,
    /// Force on the cage, normal and friction \[N\].
    pub f: V3,
    /// Point of contact \[m\].
    pub at: V3,
}

/// The cage: its constants and the last evaluation (see the module documentation).
#[derive(Debug, Clone)]
pub struct Cage {
    /// The constants.
    pub params: CageParams,
    /// Number of balls.
    z: usize,
    /// Ball radius \[m\].
    ball_radius: f64,
    /// Radius of the pockets' centres from the cage's centre, dm/2 \[m\].
    pitch_radius: f64,
    /// Per ball, the last evaluation's pocket contact.
    pub pockets: Vec<PocketContact>,
    /// The last evaluation's land contact (default without land guidance).
    pub land: LandContact,
}

/// What the cage does in one evaluation besides the balls' forces ([`Cage::pockets`]): its
/// accelerations and the land's reaction on the guiding ring.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CageResult {
    /// Angular acceleration ω̇_c [rad/s²].
    pub w_dot: f64,
    /// Acceleration of the centre (0, ÿ, z̈) [m/s²].
    pub a: V3,
    /// Force of the cage on the inner ring (inner land) \[N\].
    pub on_inner: V3,
    /// Its moment about the inner ring's centre [N m].
    pub inner_moment: V3,
    /// Force of the cage on the outer ring (outer land) \[N\].
    pub on_outer: V3,
}

/// e_θ(φ) and e_r(φ) (docs/model.md#frames).
#[inline(always)]
fn triad(phi: f64) -> (V3, V3) {
    let (s, c) = phi.sin_cos();
    ([0.0, -c, -s], [0.0, -s, c])
}

/// Smoothed Coulomb factor v/√(|v|² + v_0²) of a slip vector's magnitude squared.
#[inline(always)]
fn coulomb(v2: f64) -> f64 {
    1.0 / (v2 + FRICTION_SPEED * FRICTION_SPEED).sqrt()
}

impl Cage {
    /// The cage of `bearing` for its z balls.
    pub fn new(bearing: &Bearing) -> Self {
        Self {
            params: CageParams::of(bearing),
            z: bearing.z,
            ball_radius: bearing.ball_radius(),
            pitch_radius: 0.5 * bearing.dm,
            pockets: vec![PocketContact::default(); bearing.z],
            land: LandContact::default(),
        }
    }

    /// The contact of the ball at `p` (velocity `v`, angular velocity `omega`) with the pocket
    /// centred at the cage angle `phi` of the cage `pose`.
    #[inline(always)]
    pub fn pocket(&self, pose: &CagePose, phi: f64, p: V3, v: V3, omega: V3) -> PocketContact {
        let k = &self.params;
        let (et, er) = triad(phi);
        let q = sub(p, pose.c);
        let offset = dot(q, et);
        // A ball-riding cage's pocket holds the ball radially too (it centres the cage); a
        // land-guided cage's cylindrical pocket only along the orbit.
        let radial = if k.guidance == CageGuidance::Balls {
            dot(q, er) - self.pitch_radius
        } else {
            0.0
        };
        let len = offset.hypot(radial);
        let delta = len - 0.5 * k.pocket_clearance;
        if delta <= 0.0 {
            return PocketContact {
                offset,
                radial,
                delta,
                ..Default::default()
            };
        }
        let dv = sub(v, pose.v);
        // Rates of the offsets: e_θ and e_r turn with the cage (de_r/dφ = e_θ, de_θ/dφ = −e_r).
        let offset_rate = dot(dv, et) - pose.w * dot(q, er);
        let radial_rate = if radial != 0.0 {
            dot(dv, er) + pose.w * offset
        } else {
            0.0
        };
        let rate = (offset * offset_rate + radial * radial_rate) / len;
        let pn = (k.pocket_stiffness * delta * delta.sqrt() + k.pocket_damping * rate).max(0.0);
        let n = add(scale(et, offset / len), scale(er, radial / len));
        let r_cp = scale(n, self.ball_radius);
        let at = add(p, r_cp);
        let mut f = scale(n, -pn);
        let mut m = [0.0; 3];
        if pn > 0.0 && k.pocket_friction > 0.0 {
            // Slip of the ball's surface against the face at the contact point.
            let v_ball = add(v, cross(omega, r_cp));
            let v_face = add(
                pose.v,
                scale([0.0, -(at[2] - pose.c[2]), at[1] - pose.c[1]], pose.w),
            );
            let rel = sub(v_ball, v_face);
            // The slip on the face in the radial plane: the cage has no axial freedom, so the
            // friction's axial part (which it could only pass to ground) is left out.
            let t = [0.0, -n[2], n[1]];
            let vt = scale(t, dot(rel, t));
            let ff = scale(vt, -k.pocket_friction * pn * coulomb(dot(vt, vt)));
            f = add(f, ff);
            m = cross(r_cp, ff);
        }
        PocketContact {
            offset,
            radial,
            delta,
            p: pn,
            n,
            f,
            m,
            at,
        }
    }

    /// The cage–land contact of the cage `pose` with the guiding ring `ring` (centre, velocity
    /// and spin), `side` +1 for an outer land (contact on the side of the cage's offset) and
    /// −1 for an inner land.
    #[inline(always)]
    pub fn land_contact(&self, pose: &CagePose, ring: &RingPose, side: f64) -> LandContact {
        let k = &self.params;
        let e = [0.0, pose.c[1] - ring.p[1], pose.c[2] - ring.p[2]];
        let dist = dot(e, e).sqrt();
        let delta = dist - k.land_clearance;
        if delta <= 0.0 {
            return LandContact {
                delta,
                ..Default::default()
            };
        }
        let u = scale(e, 1.0 / dist);
        let rate = dot(u, sub(pose.v, ring.v));
        let nf = (k.land_stiffness * delta * delta.sqrt() + k.land_damping * rate).max(0.0);
        // The cage's guided surface (its outside for an outer land, its bore for an inner one).
        let r_surface = k.land_radius - side * k.land_clearance;
        let at = add(pose.c, scale(u, side * r_surface));
        let mut f = scale(u, -nf);
        if nf > 0.0 && k.land_friction > 0.0 {
            let t = [0.0, -u[2], u[1]];
            let turn =
                |w: f64, centre: V3| scale([0.0, -(at[2] - centre[2]), at[1] - centre[1]], w);
            let v_cage = add(pose.v, turn(pose.w, pose.c));
            let v_land = add(ring.v, turn(ring.spin, ring.p));
            let vs = dot(sub(v_cage, v_land), t);
            f = add(f, scale(t, -k.land_friction * nf * vs * coulomb(vs * vs)));
        }
        LandContact {
            delta,
            n: nf,
            f,
            at,
        }
    }

    /// Evaluates every pocket and the land for the cage `pose`, the balls' frames and the rings
    /// (inner, outer); fills [`Cage::pockets`] and [`Cage::land`] and returns the cage's
    /// accelerations and the land's reaction.
    #[inline]
    pub fn evaluate(
        &mut self,
        pose: &CagePose,
        frames: &[BallFrame],
        inner: &RingPose,
        outer: &RingPose,
    ) -> CageResult {
        let spacing = TAU / self.z as f64;
        let mut f_cage = [0.0; 3];
        let mut m_cage = 0.0;
        for (j, frame) in frames.iter().enumerate().take(self.z) {
            let kin = &frame.0;
            let pc = self.pocket(
                pose,
                pose.angle + spacing * j as f64,
                kin.p,
                kin.v,
                kin.omega,
            );
            if pc.p > 0.0 {
                // The reaction −f at the contact point.
                f_cage = sub(f_cage, pc.f);
                m_cage -= cross(sub(pc.at, pose.c), pc.f)[0];
            }
            self.pockets[j] = pc;
        }
        let mut r = CageResult::default();
        let land = match self.params.guidance {
            CageGuidance::Balls => LandContact::default(),
            CageGuidance::InnerLand => self.land_contact(pose, inner, -1.0),
            CageGuidance::OuterLand => self.land_contact(pose, outer, 1.0),
        };
        if land.n > 0.0 {
            f_cage = add(f_cage, land.f);
            m_cage += cross(sub(land.at, pose.c), land.f)[0];
            match self.params.guidance {
                CageGuidance::InnerLand => {
                    r.on_inner = scale(land.f, -1.0);
                    r.inner_moment = cross(sub(land.at, inner.p), r.on_inner);
                }
                _ => r.on_outer = scale(land.f, -1.0),
            }
        }
        self.land = land;
        // The cage has no axial freedom: the axial forces go to ground.
        r.a = [
            0.0,
            f_cage[1] / self.params.mass,
            f_cage[2] / self.params.mass,
        ];
        r.w_dot = m_cage / self.params.inertia;
        r
    }

    /// Elastic potential of the pockets and the land at the last evaluation \[J\].
    pub fn potential(&self) -> f64 {
        let e = |k: f64, d: f64| {
            if d > 0.0 {
                0.4 * k * d * d * d.sqrt()
            } else {
                0.0
            }
        };
        self.pockets
            .iter()
            .map(|p| e(self.params.pocket_stiffness, p.delta))
            .sum::<f64>()
            + e(self.params.land_stiffness, self.land.delta)
    }
}
