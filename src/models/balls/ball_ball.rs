//! Ball-to-ball contact of the cage-less ball-level models (full L4, reduced L3;
//! docs/model.md#ball-ball). Without a cage nothing but the balls' own dynamics keeps them
//! apart (docs/model.md#c11); over a long run the balls of a partial load zone drift against
//! each other. Neighbours j and j + 1 (mod z) touch through a Hertz point contact of two
//! spheres of diameter D ([`HertzContact`], circular: `K = (2/3) E′ √(D/4)`), with the
//! ball–race damping c_br on the approach rate, acting along the line between the ball centres:
//!
//! `δ = D − |p_{j+1} − p_j|`, `n = (p_{j+1} − p_j)/|p_{j+1} − p_j|`,
//! `δ̇ = −n·(v_{j+1} − v_j)`, `Q = max(0, K δ^{3/2} + c δ̇)` for δ > 0, else 0;
//! `−Q n` on ball j, `+Q n` on ball j + 1.
//!
//! The force passes through both centres (no moment, no friction between the balls). The
//! elastic part is C¹ at δ = 0, as at the races; the damping's jump c δ̇ at first touch is
//! left to the error controller (no event functions: the balls touch rarely, and the ball–race
//! switches are located already). Nothing here allocates after [`BallBall::new`].

use super::ball_contact::{dot, scale, sub, BallKin, V3};
use super::pass::BallFrame;
use crate::contact::{HertzContact, HertzSolution};

/// Hertz constant of two steel spheres of diameter `d` and reduced modulus
/// `e_prime` = E/(1 − ν²) [N/m^1.5]: the circular contact of [`HertzContact`] with the
/// curvature sum 4/d in both planes (equal to `(2/3) E′ √(d/4)`).
pub fn ball_ball_stiffness(d: f64, e_prime: f64) -> f64 {
    HertzContact::new(4.0 / d, 4.0 / d, e_prime, HertzSolution::Exact).stiffness
}

/// One ball–ball contact: overlap, its rate, the normal force and the unit vector from the
/// first ball's centre to the second's.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairContact {
    /// Overlap δ = D − distance \[m\] (≤ 0: apart).
    pub delta: f64,
    /// Approach rate δ̇ \[m/s\].
    pub delta_rate: f64,
    /// Normal force Q ≥ 0 \[N\] (on the second ball along +n, on the first along −n).
    pub q: f64,
    /// Unit vector from the first centre to the second.
    pub n: V3,
}

/// The ball-to-ball contacts of z balls (see the module documentation).
#[derive(Debug, Clone)]
pub struct BallBall {
    /// Hertz constant [N/m^1.5].
    pub k: f64,
    /// Damping on the approach rate [N s/m].
    pub c: f64,
    /// Centre distance at first touch, the ball diameter D \[m\].
    pub d: f64,
    /// Per pair (j, j + 1 mod z), the last evaluation's contact.
    pub pairs: Vec<PairContact>,
    /// Per ball, the last evaluation's force from both neighbours \[N\] (valid when
    /// [`BallBall::evaluate`] returned true).
    pub force: Vec<V3>,
}

impl BallBall {
    /// The contacts of `z` balls of diameter `d`, reduced modulus `e_prime`, damping `c`.
    pub fn new(z: usize, d: f64, e_prime: f64, c: f64) -> Self {
        Self {
            k: ball_ball_stiffness(d, e_prime),
            c,
            d,
            pairs: vec![PairContact::default(); z],
            force: vec![[0.0; 3]; z],
        }
    }

    /// The contact of ball `a` with ball `b` (b the next one along the orbit).
    #[inline(always)]
    pub fn pair(&self, a: &BallKin, b: &BallKin) -> PairContact {
        self.pair_at(a.p, a.v, b.p, b.v)
    }

    /// The contact of a ball at `pa` moving at `va` with one at `pb` moving at `vb`.
    #[inline(always)]
    pub fn pair_at(&self, pa: V3, va: V3, pb: V3, vb: V3) -> PairContact {
        let r = sub(pb, pa);
        let dist = dot(r, r).sqrt();
        let delta = self.d - dist;
        let n = scale(r, 1.0 / dist);
        let delta_rate = -dot(n, sub(vb, va));
        let q = if delta > 0.0 {
            (self.k * delta * delta.sqrt() + self.c * delta_rate).max(0.0)
        } else {
            0.0
        };
        PairContact {
            delta,
            delta_rate,
            q,
            n,
        }
    }

    /// Evaluates every neighbour pair of the balls' frames; returns whether any pair presses
    /// (then [`BallBall::force`] holds each ball's force, else it is stale and zero force is
    /// meant).
    #[inline]
    pub fn evaluate(&mut self, frames: &[BallFrame]) -> bool {
        let z = self.pairs.len();
        let mut any = false;
        for j in 0..z {
            let next = if j + 1 == z { 0 } else { j + 1 };
            let p = self.pair(&frames[j].0, &frames[next].0);
            any |= p.q > 0.0;
            self.pairs[j] = p;
        }
        if any {
            self.force.iter_mut().for_each(|f| *f = [0.0; 3]);
            for j in 0..z {
                let p = self.pairs[j];
                if p.q > 0.0 {
                    let next = if j + 1 == z { 0 } else { j + 1 };
                    let f = scale(p.n, p.q);
                    self.force[j] = sub(self.force[j], f);
                    let g = &mut self.force[next];
                    *g = [g[0] + f[0], g[1] + f[1], g[2] + f[2]];
                }
            }
        }
        any
    }

    /// Elastic potential (2/5) K δ^{5/2} of a pair at overlap δ \[J\] (0 apart).
    #[inline]
    pub fn potential(&self, delta: f64) -> f64 {
        if delta > 0.0 {
            0.4 * self.k * delta * delta * delta.sqrt()
        } else {
            0.0
        }
    }

    /// Smallest centre distance of neighbours in the last evaluation minus D \[m\] (negative:
    /// overlap).
    pub fn min_gap(&self) -> f64 {
        self.pairs
            .iter()
            .map(|p| -p.delta)
            .fold(f64::INFINITY, f64::min)
    }
}
