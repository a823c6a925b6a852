//! One ball–race contact of the ball-level models (full and reduced): geometry with changing contact angle (docs/model.md#contact-geometry),
//! Hertz force with contact damping (docs/model.md#c6), the spall's three effects (docs/model.md#spall-drop, #spall-direction, #spall-edge-stiffness) and strip
//! traction (docs/model.md#strips, #slip, #traction, #forces). Everything is scalar arithmetic on fixed-size arrays (no allocation).

use crate::config::{StripRule, MAX_STRIPS};
use crate::contact::{FilmContact, TractionCurve};
use crate::defect::Defect;

/// A 3-vector in inertial components.
pub type V3 = [f64; 3];

#[inline(always)]
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

#[inline(always)]
pub fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Pose and motion of a ring (docs/model.md#frames: small tilts, non-spinning frame, spin rate separate).
#[derive(Debug, Clone, Copy)]
pub struct RingPose {
    /// Centre r_r \[m\].
    pub p: V3,
    /// Centre velocity [m/s].
    pub v: V3,
    /// Tilt vector β = (0, β_y, β_z) \[rad\].
    pub beta: V3,
    /// Tilt rates (0, β̇_y, β̇_z) [rad/s].
    pub beta_rate: V3,
    /// Spin rate about the ring axis [rad/s] (0 for the outer ring).
    pub spin: f64,
}

impl RingPose {
    /// Ring-frame components of an inertial vector: `T_ir v = v − β × v`.
    #[inline(always)]
    pub fn to_ring(self, v: V3) -> V3 {
        sub(v, cross(self.beta, v))
    }

    /// Inertial components of a ring-frame vector: `T_ir^T v = v + β × v`.
    #[inline(always)]
    pub fn to_inertial(self, v: V3) -> V3 {
        add(v, cross(self.beta, v))
    }

    /// Total angular velocity `Ω x_r + β̇` [rad/s].
    #[inline(always)]
    pub fn omega(&self) -> V3 {
        let xr = self.to_inertial([1.0, 0.0, 0.0]);
        add(scale(xr, self.spin), self.beta_rate)
    }

    /// Ball azimuth θ_br in the ring frame (eq. 3) of a ball at `p`.
    #[inline]
    pub fn azimuth(&self, p: V3) -> f64 {
        let r = self.to_ring(sub(p, self.p));
        (-r[1]).atan2(r[2])
    }
}

/// Per-race constants of the contact law.
#[derive(Debug, Clone, Copy)]
pub struct RaceConst {
    /// Groove-centre circle: axial offset x_g in the ring frame \[m\] (docs/model.md#geometry).
    pub xg: f64,
    /// Groove-centre circle: radius R_g in the ring frame \[m\].
    pub rg: f64,
    /// (f − ½) D: distance groove centre – ball centre at first touch \[m\].
    pub e: f64,
    /// Hertz constant [N/m^1.5].
    pub k: f64,
    /// K^{1/3} (so that a = a* K^{1/3} δ^{1/2} needs no cube root per evaluation).
    pub k_cbrt: f64,
    /// Semi-major axis factor a* (a = a* Q^{1/3}).
    pub a_star: f64,
    /// Deformed-surface radius R_s = 2fD/(2f + 1) \[m\] (docs/model.md#c7).
    pub rs: f64,
    /// The lubricant film (docs/model.md#film): with it the Hertz force is scaled by the film in
    /// series and the film damping replaces the constant contact damping; None: the paper's law.
    pub film: Option<FilmContact>,
}

/// Strip layout (docs/model.md#c7): centres s_k = ξ_k/a and Hertzian weights w_k (Σ w_k = 1).
#[derive(Debug, Clone, Copy)]
pub struct Strips {
    /// Number of strips in use (the first `n` entries of `s` and `w`).
    pub n: usize,
    /// Strip centres s_k = ξ_k/a ∈ [−1, 1] (dimensionless).
    pub s: [f64; MAX_STRIPS],
    /// Strip weights w_k (dimensionless, Σ w_k = 1).
    pub w: [f64; MAX_STRIPS],
}

impl Strips {
    /// `n` equal strips over (−a, a), clamped to 1..=MAX_STRIPS; exactly symmetric
    /// (s_{n−1−k} = −s_k, w_{n−1−k} = w_k, the middle strip of an odd n at 0).
    pub fn new(n: usize) -> Self {
        let n = n.clamp(1, MAX_STRIPS);
        let mut s = [0.0; MAX_STRIPS];
        let mut w = [0.0; MAX_STRIPS];
        let prim = |x: f64| 0.75 * (x - x * x * x / 3.0);
        for k in 0..n.div_ceil(2) {
            let lo = -1.0 + 2.0 * k as f64 / n as f64;
            let hi = lo + 2.0 / n as f64;
            let mid = if 2 * k + 1 == n { 0.0 } else { 0.5 * (lo + hi) };
            s[k] = mid;
            w[k] = prim(hi) - prim(lo);
            s[n - 1 - k] = -mid;
            w[n - 1 - k] = w[k];
        }
        Self { n, s, w }
    }

    /// `n`-point Gauss rule for the Hertz line-load weight 1 − s² on (−1, 1) (Gauss–Jacobi
    /// with α = β = 1), clamped to 1..=MAX_STRIPS: exact for slip fields whose traction is a
    /// polynomial of degree ≤ 2n − 1 in s. The nodes are the zeros of P′_{n+1} (the interior
    /// Gauss–Lobatto points) and `w_k = (3/4)(1 − s_k²) · 2/((n + 1)(n + 2) P_{n+1}(s_k)²)`,
    /// so that Σ w_k = 1 as for [`Strips::new`]. Exactly symmetric like [`Strips::new`].
    pub fn gauss(n: usize) -> Self {
        let n = n.clamp(1, MAX_STRIPS);
        let m = n + 1;
        // (P_m(x), P′_m(x)) by the three-term recurrence; |x| < 1.
        let legendre = |x: f64| {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=m {
                let kf = k as f64;
                let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
                p0 = p1;
                p1 = p2;
            }
            // P′_m = m (x P_m − P_{m−1}) / (x² − 1).
            (p1, m as f64 * (x * p1 - p0) / (x * x - 1.0))
        };
        let mut s = [0.0; MAX_STRIPS];
        let mut w = [0.0; MAX_STRIPS];
        let mf = m as f64;
        for k in 0..n.div_ceil(2) {
            let x = if 2 * k + 1 == n {
                0.0
            } else {
                // Start from the Chebyshev–Lobatto point; Newton on P′_m with
                // P″_m = (2x P′_m − m(m + 1) P_m)/(1 − x²) (Legendre's equation).
                let mut x = -(std::f64::consts::PI * (k as f64 + 1.0) / mf).cos();
                for _ in 0..100 {
                    let (p, dp) = legendre(x);
                    let dx = dp * (1.0 - x * x) / (2.0 * x * dp - mf * (mf + 1.0) * p);
                    x -= dx;
                    if dx.abs() < 1e-16 {
                        break;
                    }
                }
                x
            };
            let (p, _) = legendre(x);
            let wk = 0.75 * (1.0 - x * x) * 2.0 / (mf * (mf + 1.0) * p * p);
            s[k] = x;
            w[k] = wk;
            s[n - 1 - k] = -x;
            w[n - 1 - k] = wk;
        }
        Self { n, s, w }
    }

    /// The strip layout of a [`StripRule`] with `n` nodes.
    pub fn with_rule(rule: StripRule, n: usize) -> Self {
        match rule {
            StripRule::Equal => Self::new(n),
            StripRule::Gauss => Self::gauss(n),
        }
    }
}

/// Ball kinematics (inertial).
#[derive(Debug, Clone, Copy)]
pub struct BallKin {
    /// Centre \[m\].
    pub p: V3,
    /// Centre velocity [m/s].
    pub v: V3,
    /// Angular velocity [rad/s].
    pub omega: V3,
}

/// A spall on this race, seen by this ball in this interval (the half is frozen).
#[derive(Debug, Clone, Copy)]
pub struct DefectView<'a> {
    pub defect: &'a Defect,
    /// −1 / +1: the half of the spall (sign of y_b) frozen for this interval.
    pub side: f64,
    /// Shaft angle φ \[rad\] (for an inner-ring spall).
    pub phi: f64,
    /// θ̇_bd: the ball's angular speed relative to the spall [rad/s].
    pub theta_bd_rate: f64,
    /// Semi-major axis factor a* of the edge contact.
    pub a_star: f64,
    /// Frozen side of the edge-constant blend (see [`Defect::contact_with_blend`]); `None`
    /// decides by the position.
    pub blend: Option<bool>,
    /// A spall on the ball (docs/model.md#ball-spall): the θ_bd of `defect`'s drop table at
    /// which its along-track coordinate is the ball's over the spall, and its rate (then
    /// `phi` and `theta_bd_rate` are not used). None: a raceway spall, placed by the ball's
    /// azimuth.
    pub on_ball: Option<(f64, f64)>,
}

impl ContactOut {
    /// Contact angle α (eq. 5) of the intact groove \[rad\] for a race of sign `s_k`.
    pub fn alpha(&self, sign: f64) -> f64 {
        (sign * self.bx).atan2(sign * self.br)
    }
}

/// Result of one contact evaluation.
#[derive(Debug, Clone, Copy, Default)]
pub struct ContactOut {
    /// Normal force Q \[N\] (≥ 0 except under [`Law::Closed`] past a loss of contact).
    pub q: f64,
    /// Unclamped force K δ′|δ′|^{1/2} + c δ̇′ \[N\] where δ′ > 0 or the law is closed, else 0
    /// (the contact event function is min(δ′, q_raw/S)).
    pub q_raw: f64,
    /// Elastic overlap on the (possibly tilted) normal \[m\] (≤ 0: open).
    pub delta: f64,
    /// Hertz constant used [N/m^1.5].
    pub k: f64,
    /// Force on the ball \[N\].
    pub f: V3,
    /// Moment on the ball about its centre [N m].
    pub m: V3,
    /// Normal force on the ring, Q n \[N\] (inertial components).
    pub qn: V3,
    /// The same with the normal in ring-frame components: its moment arm × this is the exact
    /// generalised force conjugate to the small tilt angles (keeps the tilt conservative).
    pub qn_ring: V3,
    /// Ball centre relative to the groove centre in the ring's (axial, radial) plane: axial \[m\].
    pub bx: f64,
    /// The same, radial \[m\].
    pub br: f64,
    /// True when the spall altered this contact.
    pub in_defect: bool,
}

/// Normal-force law of one contact evaluation.
///
/// The physical law is [`Law::Clamped`]: Q = max(0, K δ^{3/2} + c δ̇) for δ > 0, else 0. Its
/// switches (the damping jump c δ̇ when a contact closes, the clamp when it opens) are not
/// smooth in the state, so the full model locates them as state events and evaluates a frozen
/// law inside each step: [`Law::Closed`] (the unclamped force, continued smoothly past the
/// loss of contact) or [`Law::Open`] (no normal force). Between the located switches the
/// frozen law equals the clamped one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Law {
    /// max(0, K δ^{3/2} + c δ̇) for δ > 0, else 0.
    Clamped,
    /// In contact: K δ|δ|^{1/2} + c δ̇ (may turn negative past a loss of contact).
    Closed,
    /// Out of contact: Q = 0 (the along-track force of a blended edge constant, a potential
    /// force of the overlap, still acts while δ′ > 0, as under the clamped law).
    Open,
}

/// Evaluates one ball–race contact. `damping` is c_br; `traction` None = frictionless.
#[inline]
pub fn evaluate(
    ball: &BallKin,
    ring: &RingPose,
    race: &RaceConst,
    ball_radius: f64,
    damping: f64,
    traction: Option<(&TractionCurve, &Strips)>,
    defect: Option<DefectView<'_>>,
) -> ContactOut {
    evaluate_law(
        ball,
        ring,
        race,
        ball_radius,
        damping,
        traction,
        defect,
        None,
        Law::Clamped,
    )
}

/// [`evaluate`] with an explicit normal-force [`Law`] and the distributed defects' added
/// approach `added` (δ, δ̇) \[m, m/s\] (docs/model.md#distributed).
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn evaluate_law(
    ball: &BallKin,
    ring: &RingPose,
    race: &RaceConst,
    ball_radius: f64,
    damping: f64,
    traction: Option<(&TractionCurve, &Strips)>,
    defect: Option<DefectView<'_>>,
    added: Option<(f64, f64)>,
    law: Law,
) -> ContactOut {
    let (mut out, loaded) = evaluate_normal(
        ball,
        ring,
        race,
        ball_radius,
        damping,
        defect,
        added,
        law,
        traction.is_some(),
    );
    let (Some((curve, strips)), Some((sf, frame))) = (traction, loaded) else {
        return out;
    };
    apply_traction(&mut out, &frame, strip_sums(curve, strips, &sf));
    out
}

/// Adds the strip sums `[f1, f2, Σ ξ f2, Σ ζ f1, Σ ζ f2]` of a loaded contact with frame
/// (n, c1, c2) to its force and moment on the ball ([`evaluate_law`]'s last step, also the
/// one of a [`TractionBatch`]).
#[inline(always)]
pub fn apply_traction(out: &mut ContactOut, frame: &[V3; 3], sums: [f64; 5]) {
    let [n, c1, c2] = *frame;
    let [f1, f2, mxi2, mze1, mze2] = sums;
    out.f = add(out.f, add(scale(c1, f1), scale(c2, f2)));
    // r_cp × F_k = ξ f2 n + ζ f1 c2 − ζ f2 c1 (c1 × c2 = n, n × c1 = c2, n × c2 = −c1).
    out.m = add(scale(n, mxi2), sub(scale(c2, mze1), scale(c1, mze2)));
}

/// The slip field of one contact where it carries a normal force (diagnostics: the input of
/// the strip quadrature, e.g. to compare strip rules on states of a running simulation).
#[allow(clippy::too_many_arguments)]
pub fn slip_field_law(
    ball: &BallKin,
    ring: &RingPose,
    race: &RaceConst,
    ball_radius: f64,
    damping: f64,
    defect: Option<DefectView<'_>>,
    added: Option<(f64, f64)>,
    law: Law,
) -> Option<SlipField> {
    evaluate_normal(
        ball,
        ring,
        race,
        ball_radius,
        damping,
        defect,
        added,
        law,
        true,
    )
    .1
    .map(|(sf, _)| sf)
}

/// Everything of [`evaluate_law`] but the traction: the contact with its normal force, and,
/// with `slip` and where Q ≠ 0, the slip field and the contact frame (n, c1, c2) that the
/// traction needs ([`strip_sums`] and [`apply_traction`], or a [`TractionBatch`]).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn evaluate_normal(
    ball: &BallKin,
    ring: &RingPose,
    race: &RaceConst,
    ball_radius: f64,
    damping: f64,
    defect: Option<DefectView<'_>>,
    added: Option<(f64, f64)>,
    law: Law,
    slip: bool,
) -> (ContactOut, Option<(SlipField, [V3; 3])>) {
    let mut out = ContactOut::default();
    let loaded = evaluate_normal_at(
        &groove_pos(ball.p, ring, race),
        ball,
        ring,
        race,
        ball_radius,
        damping,
        defect,
        added,
        law,
        slip,
        &mut out,
    );
    (out, loaded)
}

/// Where a ball centre sits in a ring's groove: the start of every contact evaluation
/// (docs/model.md#contact-geometry), which depends on no spall and no law. The ball centre relative to the ring centre
/// in inertial (`rbr`) and ring-frame (`rr`) components, its distance ρ from the ring axis and
/// the radial unit vector's ring-frame components (e_y, e_z), and its offset (b_x, b_r) from
/// the groove-centre circle with length l and direction (n1, n3) = (b_x, b_r)/l.
#[derive(Debug, Clone, Copy, Default)]
pub struct GroovePos {
    /// Ball centre relative to the ring centre, inertial components \[m\].
    pub rbr: V3,
    /// The same in ring-frame components \[m\].
    pub rr: V3,
    /// Distance ρ from the ring axis \[m\].
    pub rho: f64,
    /// Radial unit vector, ring-frame y component.
    pub ey: f64,
    /// Radial unit vector, ring-frame z component.
    pub ez: f64,
    /// Axial offset b_x from the groove-centre circle \[m\].
    pub bx: f64,
    /// Radial offset b_r from the groove-centre circle \[m\].
    pub br: f64,
    /// Offset length l = |(b_x, b_r)| \[m\].
    pub l: f64,
    /// Direction of the offset, axial: b_x / l.
    pub n1: f64,
    /// Direction of the offset, radial: b_r / l.
    pub n3: f64,
}

/// The [`GroovePos`] of a ball centre `p` in a ring's groove. The models' staged contacts
/// (`ContactPass`) compute it for every contact of an RHS evaluation before the rest of the
/// contacts ([`evaluate_normal_at`]), so that the square roots and divisions of different
/// contacts overlap instead of heading each contact's chain.
#[inline(always)]
pub fn groove_pos(p: V3, ring: &RingPose, race: &RaceConst) -> GroovePos {
    let rbr = sub(p, ring.p);
    let rr = ring.to_ring(rbr);
    let rho = (rr[1] * rr[1] + rr[2] * rr[2]).sqrt();
    let (ey, ez) = (rr[1] / rho, rr[2] / rho);
    let bx = rr[0] - race.xg;
    let br = rho - race.rg;
    let l = (bx * bx + br * br).sqrt();
    GroovePos {
        rbr,
        rr,
        rho,
        ey,
        ez,
        bx,
        br,
        l,
        n1: bx / l,
        n3: br / l,
    }
}

/// `evaluate_normal` from the ball's [`GroovePos`] in this ring (which must be
/// [`groove_pos`] of `ball.p`, `ring` and `race`), writing the contact into `out` (the RHS's
/// own slot, so that the 150-byte contact is not built on the stack and copied there) and
/// returning the slip field and frame of a loaded contact.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn evaluate_normal_at(
    g: &GroovePos,
    ball: &BallKin,
    ring: &RingPose,
    race: &RaceConst,
    ball_radius: f64,
    damping: f64,
    defect: Option<DefectView<'_>>,
    added: Option<(f64, f64)>,
    law: Law,
    slip: bool,
    out: &mut ContactOut,
) -> Option<(SlipField, [V3; 3])> {
    let GroovePos {
        rbr,
        rr,
        rho,
        ey,
        ez,
        bx,
        br,
        l,
        n1,
        n3,
    } = *g;
    let mut delta = l - race.e;
    // Waviness, roughness, an off-size ball: their added approach (docs/model.md#distributed).
    if let Some((a, _)) = added {
        delta += a;
    }
    *out = ContactOut {
        delta,
        bx,
        br,
        k: race.k,
        ..Default::default()
    };
    let open =
        |d: f64| law != Law::Closed && d.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater);
    if open(delta) {
        return None;
    }
    let mut n_r = [n1, n3 * ey, n3 * ez];
    let c2_r = [0.0, -ez, ey];
    let mut n = ring.to_inertial(n_r);
    let mut c2 = ring.to_inertial(c2_r);
    // Approach rate against the groove-centre point (spin does not move the groove).
    let gc = ring.to_inertial([race.xg, race.rg * ey, race.rg * ez]);
    let v_gc = add(ring.v, cross(ring.beta_rate, gc));
    let mut ddelta = dot(n, sub(ball.v, v_gc));
    if let Some((_, a_rate)) = added {
        ddelta += a_rate;
    }
    let mut k = race.k;
    let mut k_cbrt = race.k_cbrt;
    let mut a_star = race.a_star;
    let mut rs = race.rs;
    let (mut track_gain, mut dk_dy) = (0.0, 0.0);
    let c2_track = c2;
    if let Some(dv) = defect {
        let (tbd, tbd_rate) = match dv.on_ball {
            Some(at) => at,
            None => {
                let theta_br = (-rr[1]).atan2(rr[2]);
                (dv.defect.theta_bd(theta_br, dv.phi), dv.theta_bd_rate)
            }
        };
        let mut y_b = dv.defect.along_track(tbd);
        if y_b * dv.side <= 0.0 {
            y_b = dv.side * 1e-15;
        }
        if let Some(c) = dv.defect.contact_with_blend(y_b, dv.blend) {
            let y_rate = dv.defect.along_track_rate(tbd, tbd_rate);
            // dy_b per metre of ball-centre travel along the track direction c2 (a spall on
            // the ball moves with its spin, not with the centre: its blend's along-track
            // force is not applied, docs/model.md#ball-spall).
            if dv.on_ball.is_none() {
                track_gain = dv.defect.along_track_rate(tbd, 1.0) / rho;
            }
            dk_dy = c.dk_dy;
            delta = c.deflection(delta);
            ddelta = c.deflection_rate(ddelta, y_rate);
            k = c.k_edge;
            k_cbrt = k.cbrt();
            let (st, ct) = c.theta_dd.sin_cos();
            n_r = add(scale(n_r, ct), scale(c2_r, st));
            let nq = add(scale(n, ct), scale(c2, st));
            c2 = sub(scale(c2, ct), scale(n, st));
            n = nq;
            a_star = dv.a_star;
            rs = 2.0 * ball_radius;
            out.in_defect = true;
            out.delta = delta;
            out.k = k;
            if open(delta) {
                return None;
            }
        }
    }
    // δ > 0 here except under the frozen closed law past a loss of contact (then √ of 0).
    let sd = delta.max(0.0).sqrt();
    // |δ|^½: the same √δ where δ > 0 (one square root), so δ|δ|^½ equals δ·√δ bit for bit.
    let sa = if delta > 0.0 { sd } else { delta.abs().sqrt() };
    let q_raw = match race.film {
        None => k * delta * sa + damping * ddelta,
        Some(film) => {
            // docs/model.md#film: the film's thickness at the Hertz load and the entraining
            // speed, its stiffness in series with Hertz, its damping on the approach rate.
            let u = entraining_speed(ball, ring, rbr, ball_radius, n, c2);
            let (h, c_f) = film.law(k * delta.max(0.0) * sd, u);
            FilmContact::series_factor(delta, h) * k * delta * sa + c_f * ddelta
        }
    };
    let q = match law {
        Law::Clamped => q_raw.max(0.0),
        Law::Closed => q_raw,
        Law::Open => 0.0,
    };
    out.q_raw = q_raw;
    out.q = q;
    out.f = scale(n, -q);
    if dk_dy != 0.0 && delta > 0.0 {
        // Along-track force of the blended edge stiffness: −∂/∂y [(2/5) K(y) δ′^{5/2}] (docs/model.md#c9),
        // through the ball centre (a potential force), reaction on the ring.
        let f_track = -0.4 * dk_dy * delta * delta * sd * track_gain;
        out.f = add(out.f, scale(c2_track, f_track));
    }
    out.qn = scale(n, q);
    out.qn_ring = scale(n_r, q);
    if q == 0.0 || !slip {
        return None;
    }
    let c1 = cross(c2, n);
    // a = a* Q_e^{1/3} = a* K^{1/3} δ^{1/2}.
    let a = (a_star * k_cbrt * sd).min(0.9 * ball_radius.min(rs));
    let sf = slip_field(ball, ring, rbr, q, a, rs, ball_radius, n, c1, c2);
    Some((sf, [n, c1, c2]))
}

/// Entraining (mean rolling) speed u = ½ |(u_ball + u_race)·c2| of a contact with normal n and
/// rolling direction c2 \[m/s\]: the surface velocities of ball and race at the contact point
/// `R n` from the ball centre, each relative to the contact point, which turns with the ball's
/// orbit about the shaft axis (docs/model.md#film). Pure rolling gives both the same speed.
#[inline(always)]
pub fn entraining_speed(
    ball: &BallKin,
    ring: &RingPose,
    rbr: V3,
    ball_radius: f64,
    n: V3,
    c2: V3,
) -> f64 {
    let p = ball.p;
    let orbit = (p[1] * ball.v[2] - p[2] * ball.v[1]) / (p[1] * p[1] + p[2] * p[2]);
    let rc = scale(n, ball_radius);
    // Contact-point velocity: the ball centre's plus the orbit's turn of the offset R n.
    let v_cp = add(ball.v, cross([orbit, 0.0, 0.0], rc));
    let u_ball = sub(add(ball.v, cross(ball.omega, rc)), v_cp);
    let u_race = sub(add(ring.v, cross(ring.omega(), add(rbr, rc))), v_cp);
    0.5 * dot(add(u_ball, u_race), c2).abs()
}

/// Slip of a loaded contact along its major axis, in contact-frame components (docs/model.md#strips, #slip): the
/// input of the strip quadrature. At s = ξ/a the deformed-surface point is
/// `ζ(ξ) = √(R_s² − ξ²) + z0` along n, and the slip of the ball against the race is
/// `u1 = a1 + ζ b1` (transverse, c1) and `u2 = a2 + ξ s − ζ b2` (rolling direction, c2).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SlipField {
    /// Normal force Q \[N\].
    pub q: f64,
    /// Semi-major axis a \[m\].
    pub a: f64,
    /// Deformed-surface radius R_s \[m\].
    pub rs: f64,
    /// ζ offset `√(R² − a²) − √(R_s² − a²)` \[m\].
    pub z0: f64,
    /// Slip of the ball centre against the race, c1 component [m/s].
    pub a1: f64,
    /// Slip of the ball centre against the race, c2 component [m/s].
    pub a2: f64,
    /// Relative angular velocity ω_b − ω_r on c2 [rad/s].
    pub b1: f64,
    /// Relative angular velocity ω_b − ω_r on c1 [rad/s].
    pub b2: f64,
    /// Relative angular velocity ω_b − ω_r on n (spin) [rad/s].
    pub s: f64,
}

impl SlipField {
    /// (ζ, u1, u2) at s = ξ/a ∈ [−1, 1].
    #[inline(always)]
    pub fn at(&self, s: f64) -> (f64, f64, f64) {
        let xi = self.a * s;
        let zeta = (self.rs * self.rs - xi * xi).sqrt() + self.z0;
        (
            zeta,
            self.a1 + zeta * self.b1,
            self.a2 + xi * self.s - zeta * self.b2,
        )
    }
}

/// The slip field of a loaded contact with frame (n, c1, c2) and semi-major axis a.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn slip_field(
    ball: &BallKin,
    ring: &RingPose,
    rbr: V3,
    q: f64,
    a: f64,
    rs: f64,
    ball_radius: f64,
    n: V3,
    c1: V3,
    c2: V3,
) -> SlipField {
    let omega_r = ring.omega();
    let w0 = sub(sub(ball.v, ring.v), cross(omega_r, rbr));
    let dw = sub(ball.omega, omega_r);
    SlipField {
        q,
        a,
        rs,
        z0: (ball_radius * ball_radius - a * a).sqrt() - (rs * rs - a * a).sqrt(),
        a1: dot(c1, w0),
        a2: dot(c2, w0),
        b1: dot(dw, c2),
        b2: dot(dw, c1),
        s: dot(dw, n),
    }
}

/// Strip sums of one contact (docs/model.md#forces): `[f1, f2, Σ ξ f2, Σ ζ f1, Σ ζ f2]`, the traction force on
/// the ball in (c1, c2) components and the three moment sums.
#[inline(always)]
pub fn strip_sums(curve: &TractionCurve, strips: &Strips, sf: &SlipField) -> [f64; 5] {
    // The strips are symmetric (s_{n−1−k} = −s_k, w_{n−1−k} = w_k), so a mirrored pair shares
    // ζ, the transverse slip u1 = a1 + ζ b1 and u2 up to the sign of ξ s: pair p holds strip p
    // (ξ_p = a s_p) and strip n−1−p (−ξ_p); an odd n has its middle strip at ξ = 0. The slips,
    // the traction law (one exp per strip) and the sums run in separate passes over fixed-size
    // arrays, so that the independent strips overlap instead of waiting on the call.
    const HALF: usize = MAX_STRIPS / 2;
    let nst = strips.n;
    let np = nst / 2;
    let mut zeta = [0.0; HALF + 1];
    let mut u1 = [0.0; HALF + 1];
    let mut u2p = [0.0; HALF + 1];
    let mut u2m = [0.0; HALF];
    let mut kp = [0.0; HALF + 1];
    let mut km = [0.0; HALF];
    for p in 0..nst.div_ceil(2) {
        let (z, v1, vp, vm) = pair_slip(sf, strips, p);
        (zeta[p], u1[p], u2p[p]) = (z, v1, vp);
        if p < np {
            u2m[p] = vm;
        }
    }
    for p in 0..nst.div_ceil(2) {
        let v = u1[p] * u1[p];
        kp[p] = (v + u2p[p] * u2p[p]).sqrt();
        if p < np {
            km[p] = (v + u2m[p] * u2m[p]).sqrt();
        }
    }
    for k in kp.iter_mut().take(nst.div_ceil(2)) {
        *k = curve.kappa_over_u(*k);
    }
    for k in km.iter_mut().take(np) {
        *k = curve.kappa_over_u(*k);
    }
    sum_strips(sf.q, sf.a, strips, &zeta, &u1, &u2p, &u2m, &kp, &km)
}

/// Slips of strip pair p of a contact: ζ, the transverse slip u1 and the rolling slips u2 at
/// +ξ_p and at −ξ_p (the first pass of [`strip_sums`]).
#[inline(always)]
fn pair_slip(sf: &SlipField, strips: &Strips, p: usize) -> (f64, f64, f64, f64) {
    strip_slip(
        sf.a * strips.s[p],
        [sf.rs, sf.z0, sf.a1, sf.a2, sf.b1, sf.b2, sf.s],
    )
}

/// [`pair_slip`] at ξ = `xi` from the slip field's (R_s, z0, a1, a2, b1, b2, s): the one copy
/// of its operations, which [`TractionBatch`] runs across contacts.
#[inline(always)]
fn strip_slip(xi: f64, [rs, z0, a1, a2, b1, b2, s]: [f64; 7]) -> (f64, f64, f64, f64) {
    let z = (rs * rs - xi * xi).sqrt() + z0;
    let t = xi * s;
    let zb2 = z * b2;
    (z, a1 + z * b1, (a2 + t) - zb2, (a2 - t) - zb2)
}

/// What strip pair p adds to a contact's five sums ([`sum_strips`]): `qw` = −Q w_p, `a_s` =
/// a s_p, the pair's ζ, u1, u2 at ±ξ and κ(u)/u at ±ξ. The one copy of these operations, which
/// [`TractionBatch`] runs across contacts.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn pair_terms(
    qw: f64,
    a_s: f64,
    zeta: f64,
    u1: f64,
    u2p: f64,
    u2m: f64,
    kp: f64,
    km: f64,
) -> [f64; 5] {
    let (gp, gm) = (qw * kp, qw * km);
    let g1 = (gp + gm) * u1;
    let (g2p, g2m) = (gp * u2p, gm * u2m);
    [
        g1,
        g2p + g2m,
        a_s * (g2p - g2m),
        zeta * g1,
        zeta * (g2p + g2m),
    ]
}

/// What an odd rule's middle strip (ξ = 0) adds to a contact's sums (f1, f2, Σ ζ f1, Σ ζ f2):
/// `g` = −Q w κ(u)/u.
#[inline(always)]
fn middle_terms(g: f64, zeta: f64, u1: f64, u2: f64) -> [f64; 4] {
    let (g1, g2) = (g * u1, g * u2);
    [g1, g2, zeta * g1, zeta * g2]
}

/// The last pass of [`strip_sums`]: the traction sums of one contact from the slips of its
/// strip pairs (pair p: ζ, u1, u2 at +ξ_p and −ξ_p, κ(u)/u at both) and, for an odd rule, the
/// middle strip at index n/2 (ξ = 0: no spin moment).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn sum_strips(
    q: f64,
    a: f64,
    strips: &Strips,
    zeta: &[f64],
    u1: &[f64],
    u2p: &[f64],
    u2m: &[f64],
    kp: &[f64],
    km: &[f64],
) -> [f64; 5] {
    let np = strips.n / 2;
    let (mut f1, mut f2, mut mxi2, mut mze1, mut mze2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for p in 0..np {
        let d = pair_terms(
            -q * strips.w[p],
            a * strips.s[p],
            zeta[p],
            u1[p],
            u2p[p],
            u2m[p],
            kp[p],
            km[p],
        );
        f1 += d[0];
        f2 += d[1];
        mxi2 += d[2];
        mze1 += d[3];
        mze2 += d[4];
    }
    if strips.n % 2 == 1 {
        let d = middle_terms(-q * strips.w[np] * kp[np], zeta[np], u1[np], u2p[np]);
        f1 += d[0];
        f2 += d[1];
        mze1 += d[2];
        mze2 += d[3];
    }
    [f1, f2, mxi2, mze1, mze2]
}

/// The strip traction of many contacts, computed together.
///
/// The contacts of one RHS evaluation are independent, but each contact's traction is a chain
/// of dependent square roots and an `exp` per strip ([`strip_sums`]): one contact at a time,
/// the processor waits on each link. Here every loaded contact of the evaluation is queued
/// ([`TractionBatch::push`], after `evaluate_normal`) and [`TractionBatch::run`] does each
/// stage of [`strip_sums`] for all of them in one pass over flat arrays laid out pair by pair
/// (strip pair p of contact c at `p·n + c`, n the contacts queued): each pass runs across the
/// contacts, four lanes at a time where the processor has AVX2, and each contact's sums still
/// add its strips in strip order. Every value is computed by the same operations in the same
/// order as [`strip_sums`], so the sums are bit for bit the same. The buffers are sized once
/// ([`TractionBatch::new`]); queuing and running never allocate.
#[derive(Debug, Clone, Default)]
pub struct TractionBatch {
    len: usize,
    slot: Vec<usize>,
    frame: Vec<[V3; 3]>,
    /// The queued slip fields, one array per field (contact c at c).
    q: Vec<f64>,
    a: Vec<f64>,
    rs: Vec<f64>,
    z0: Vec<f64>,
    a1: Vec<f64>,
    a2: Vec<f64>,
    b1: Vec<f64>,
    b2: Vec<f64>,
    spin: Vec<f64>,
    /// Per strip pair and contact (pair p of contact c at `p·n + c`; h = ⌈strips/2⌉ pairs of
    /// the rule in use, an odd rule's middle strip the last): ζ, u1, u2 of the strip at +ξ and
    /// at −ξ.
    zeta: Vec<f64>,
    u1: Vec<f64>,
    u2p: Vec<f64>,
    u2m: Vec<f64>,
    /// The slip speeds, then κ(u)/u, of the strips at +ξ (the first `h·n`) and at −ξ (the
    /// next `h·n`): one slice for [`TractionCurve::kappa_over_u_in_place`].
    kappa: Vec<f64>,
    /// Each contact's five sums ([`strip_sums`]), one array per sum.
    sums: [Vec<f64>; 5],
}

/// Strip pairs per contact at most (an odd rule's middle strip is the last "pair", whose −ξ
/// half is unused).
const PAIRS: usize = MAX_STRIPS / 2 + 1;

impl TractionBatch {
    /// A batch for up to `contacts` contacts per run.
    pub fn new(contacts: usize) -> Self {
        let v = |k: usize| vec![0.0; k * contacts * PAIRS];
        let c = || vec![0.0; contacts];
        Self {
            len: 0,
            slot: vec![0; contacts],
            frame: vec![[[0.0; 3]; 3]; contacts],
            q: c(),
            a: c(),
            rs: c(),
            z0: c(),
            a1: c(),
            a2: c(),
            b1: c(),
            b2: c(),
            spin: c(),
            zeta: v(1),
            u1: v(1),
            u2p: v(1),
            u2m: v(1),
            kappa: v(2),
            sums: [c(), c(), c(), c(), c()],
        }
    }

    /// Empties the queue.
    #[inline]
    pub fn clear(&mut self) {
        self.len = 0;
    }

    /// Queues a loaded contact (the slip field and frame `evaluate_normal` returned for it);
    /// `slot` is the caller's name for it, handed back by [`TractionBatch::run`].
    ///
    /// # Panics
    /// When more contacts are queued than [`TractionBatch::new`] was sized for.
    #[inline(always)]
    pub fn push(&mut self, slot: usize, sf: SlipField, frame: [V3; 3]) {
        let i = self.len;
        self.slot[i] = slot;
        self.frame[i] = frame;
        self.q[i] = sf.q;
        self.a[i] = sf.a;
        self.rs[i] = sf.rs;
        self.z0[i] = sf.z0;
        self.a1[i] = sf.a1;
        self.a2[i] = sf.a2;
        self.b1[i] = sf.b1;
        self.b2[i] = sf.b2;
        self.spin[i] = sf.s;
        self.len = i + 1;
    }

    /// The strip sums of every queued contact, as [`strip_sums`] gives them; calls
    /// `each(slot, frame, sums)` for each in the order queued.
    #[inline]
    pub fn run(
        &mut self,
        curve: &TractionCurve,
        strips: &Strips,
        mut each: impl FnMut(usize, &[V3; 3], [f64; 5]),
    ) {
        let n = self.len;
        self.stages(curve, strips);
        for c in 0..n {
            let sums = [
                self.sums[0][c],
                self.sums[1][c],
                self.sums[2][c],
                self.sums[3][c],
                self.sums[4][c],
            ];
            each(self.slot[c], &self.frame[c], sums);
        }
    }

    /// The passes of [`TractionBatch::run`] up to the sums, compiled for AVX2 where the
    /// processor has it.
    fn stages(&mut self, curve: &TractionCurve, strips: &Strips) {
        crate::vecmath::with_avx2(
            #[inline(always)]
            || self.stages_body(curve, strips),
        )
    }

    #[inline(always)]
    fn stages_body(&mut self, curve: &TractionCurve, strips: &Strips) {
        let n = self.len;
        let h = strips.n.div_ceil(2);
        let m = n * h;
        let np = strips.n / 2;
        // Each input cut to the n contacts, so that the loops below need no bounds checks and
        // vectorise.
        let (q, a, rs, z0) = (&self.q[..n], &self.a[..n], &self.rs[..n], &self.z0[..n]);
        let (a1, a2, b1, b2) = (&self.a1[..n], &self.a2[..n], &self.b1[..n], &self.b2[..n]);
        let spin = &self.spin[..n];
        // Slips of every strip (the first pass of strip_sums, pair_slip's operations).
        for p in 0..h {
            let r = p * n..(p + 1) * n;
            let sp = strips.s[p];
            let (zeta, u1) = (&mut self.zeta[r.clone()], &mut self.u1[r.clone()]);
            let (u2p, u2m) = (&mut self.u2p[r.clone()], &mut self.u2m[r]);
            for c in 0..n {
                let field = [rs[c], z0[c], a1[c], a2[c], b1[c], b2[c], spin[c]];
                (zeta[c], u1[c], u2p[c], u2m[c]) = strip_slip(a[c] * sp, field);
            }
        }
        // Slip speeds, then κ(u)/u, over all strips of all contacts at once (an odd rule's
        // unused −ξ half of the middle strip included: it is never summed).
        let (kp, km) = self.kappa[..2 * m].split_at_mut(m);
        for (((kp, km), u1), (u2p, u2m)) in kp
            .iter_mut()
            .zip(km.iter_mut())
            .zip(&self.u1[..m])
            .zip(self.u2p[..m].iter().zip(&self.u2m[..m]))
        {
            let v = u1 * u1;
            *kp = (v + u2p * u2p).sqrt();
            *km = (v + u2m * u2m).sqrt();
        }
        curve.kappa_over_u_in_place(&mut self.kappa[..2 * m]);
        // Sums, each contact's in strip order (sum_strips's operations).
        let [f1, f2, mxi2, mze1, mze2] = &mut self.sums;
        let (f1, f2, mxi2) = (&mut f1[..n], &mut f2[..n], &mut mxi2[..n]);
        let (mze1, mze2) = (&mut mze1[..n], &mut mze2[..n]);
        for v in [&mut *f1, &mut *f2, &mut *mxi2, &mut *mze1, &mut *mze2] {
            v.fill(0.0);
        }
        let (kp, km) = self.kappa[..2 * m].split_at(m);
        for p in 0..np {
            let (w, sp) = (strips.w[p], strips.s[p]);
            let r = p * n..(p + 1) * n;
            let (zeta, u1) = (&self.zeta[r.clone()], &self.u1[r.clone()]);
            let (u2p, u2m) = (&self.u2p[r.clone()], &self.u2m[r.clone()]);
            let (kp, km) = (&kp[r.clone()], &km[r]);
            for c in 0..n {
                let d = pair_terms(
                    -q[c] * w,
                    a[c] * sp,
                    zeta[c],
                    u1[c],
                    u2p[c],
                    u2m[c],
                    kp[c],
                    km[c],
                );
                f1[c] += d[0];
                f2[c] += d[1];
                mxi2[c] += d[2];
                mze1[c] += d[3];
                mze2[c] += d[4];
            }
        }
        if strips.n % 2 == 1 {
            let r = np * n..(np + 1) * n;
            let w = strips.w[np];
            let (zeta, u1, u2p) = (
                &self.zeta[r.clone()],
                &self.u1[r.clone()],
                &self.u2p[r.clone()],
            );
            let kp = &kp[r];
            for c in 0..n {
                let d = middle_terms(-q[c] * w * kp[c], zeta[c], u1[c], u2p[c]);
                f1[c] += d[0];
                f2[c] += d[1];
                mze1[c] += d[2];
                mze2[c] += d[3];
            }
        }
    }
}

/// A 3×3 matrix, rows first.
pub type M3 = [[f64; 3]; 3];

/// Linearization of the normal force Q n that the contact puts on the ring, with respect to the
/// ring's centre position and velocity (ball, tilt and tilt rate held), for an intact contact
/// (`None` when the spall alters it: the caller differentiates that one numerically).
/// Traction is not included; a lubricated contact (docs/model.md#film) is `None` too. With rr = T(r_b − r_r), n_r the ring-frame normal, N = ∂n_r/∂rr =
/// (Π − n_r n_rᵀ)/l + (n₃/ρ) e_φ e_φᵀ (Π the ball's axial–radial plane, e_φ the azimuthal
/// direction: the normal turns with the groove) and w = v_b − v_gc:
///
/// ```text
///   ∂δ/∂r_r = −nᵀ,  ∂δ̇/∂r_r = −[wᵀ Tᵀ N − nᵀ [β̇×] Tᵀ (R_g/ρ) e_φ e_φᵀ] T,  ∂δ̇/∂v_r = −nᵀ,
///   ∂(Q n)/∂r_r = n (1.5 K δ^½ ∂δ/∂r_r + c ∂δ̇/∂r_r) − Q Tᵀ N T,  ∂(Q n)/∂v_r = −c n nᵀ.
/// ```
pub fn ring_translation_jacobian(
    ball: &BallKin,
    ring: &RingPose,
    race: &RaceConst,
    ball_radius: f64,
    damping: f64,
    defect: Option<DefectView<'_>>,
) -> Option<(M3, M3)> {
    let c = evaluate(ball, ring, race, ball_radius, damping, None, defect);
    if c.in_defect || race.film.is_some() {
        return None;
    }
    let zero = [[0.0; 3]; 3];
    if c.q <= 0.0 || c.delta <= 0.0 {
        return Some((zero, zero));
    }
    let rbr = sub(ball.p, ring.p);
    let rr = ring.to_ring(rbr);
    let rho = (rr[1] * rr[1] + rr[2] * rr[2]).sqrt();
    let (ey, ez) = (rr[1] / rho, rr[2] / rho);
    let (bx, br) = (rr[0] - race.xg, rho - race.rg);
    let l = (bx * bx + br * br).sqrt();
    let n_r = [bx / l, br / l * ey, br / l * ez];
    let n = ring.to_inertial(n_r);
    let e_rho = [0.0, ey, ez];
    let e_phi = [0.0, -ez, ey];
    let ex = [1.0, 0.0, 0.0];
    // N = ∂n_r/∂rr.
    let mut nm = zero;
    for i in 0..3 {
        for j in 0..3 {
            let pi = ex[i] * ex[j] + e_rho[i] * e_rho[j];
            nm[i][j] = (pi - n_r[i] * n_r[j]) / l + br / l / rho * e_phi[i] * e_phi[j];
        }
    }
    // T and Tᵀ as matrices: T v = v − β × v.
    let tmat = |transpose: bool| {
        let mut m = zero;
        for (j, col) in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
            .into_iter()
            .enumerate()
        {
            let v = if transpose {
                ring.to_inertial(col)
            } else {
                ring.to_ring(col)
            };
            for i in 0..3 {
                m[i][j] = v[i];
            }
        }
        m
    };
    let (t, tt) = (tmat(false), tmat(true));
    let mul = |a: &M3, b: &M3| {
        let mut r = zero;
        for i in 0..3 {
            for j in 0..3 {
                r[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        r
    };
    let ttn = mul(&tt, &nm); // ∂n/∂rr
    let gc = ring.to_inertial([race.xg, race.rg * ey, race.rg * ez]);
    let v_gc = add(ring.v, cross(ring.beta_rate, gc));
    let w = sub(ball.v, v_gc);
    // Row vector ∂δ̇/∂rr = wᵀ Tᵀ N + nᵀ ∂w/∂rr, ∂w/∂rr = −[β̇×] Tᵀ (R_g/ρ) e_φ e_φᵀ.
    let tt_ephi = ring.to_inertial(e_phi);
    let bxe = cross(ring.beta_rate, tt_ephi);
    let n_bxe = dot(n, bxe);
    let mut dd_rr = [0.0; 3];
    for (j, d) in dd_rr.iter_mut().enumerate() {
        *d = (0..3).map(|i| w[i] * ttn[i][j]).sum::<f64>() - n_bxe * race.rg / rho * e_phi[j];
    }
    let k = c.k;
    let stiff = 1.5 * k * c.delta.sqrt();
    // Chain to the ring position: ∂rr/∂r_r = −T.
    let mut dfdx = zero;
    let mut dfdv = zero;
    let q_ttnt = mul(&ttn, &t);
    for j in 0..3 {
        let dd_p = -(0..3).map(|m| dd_rr[m] * t[m][j]).sum::<f64>();
        let ddelta_p = -n[j];
        let dq = stiff * ddelta_p + damping * dd_p;
        for i in 0..3 {
            dfdx[i][j] = n[i] * dq - c.q * q_ttnt[i][j];
            dfdv[i][j] = -damping * n[i] * n[j];
        }
    }
    Some((dfdx, dfdv))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ball of radius R at azimuth θ on the pitch radius r (contact angle 0), orbiting at ω_c
    /// and spinning about e_x so that it rolls without slip on a race whose contact point is
    /// `side` R from its centre (+1 outer, −1 inner) and which turns at `spin`: the entraining
    /// speed is the race's surface speed relative to the orbiting contact point.
    fn rolling(side: f64, spin: f64) -> f64 {
        let (r, rb, wc, theta) = (0.035, 0.00635, 440.0, 0.7_f64);
        let (s, c) = theta.sin_cos();
        let (er, et) = ([0.0, -s, c], [0.0, -c, -s]);
        // Radius of the contact point, and the race's surface speed relative to the contact
        // point along e_θ: (Ω − ω_c) rc.
        let rc = r + side * rb;
        let rel = (spin - wc) * rc;
        // Pure rolling: the ball's surface at the contact moves with the race's, so
        // ω_s e_x × (side R e_r) = (Ω rc − r ω_c) e_θ.
        let ws = (spin * rc - r * wc) / (side * rb);
        let ball = BallKin {
            p: scale(er, r),
            v: scale(et, r * wc),
            omega: [ws, 0.0, 0.0],
        };
        let ring = RingPose {
            p: [0.0; 3],
            v: [0.0; 3],
            beta: [0.0; 3],
            beta_rate: [0.0; 3],
            spin,
        };
        let n = scale(er, side);
        let u = entraining_speed(&ball, &ring, ball.p, rb, n, et);
        assert!(
            (u - rel.abs()).abs() < 1e-12 * rel.abs(),
            "u = {u}, race surface relative to the contact {rel}"
        );
        u
    }

    #[test]
    fn entraining_speed_of_pure_rolling_is_the_race_speed_relative_to_the_contact() {
        // Outer race fixed: u = ω_c (r + R); inner race at Ω: u = (Ω − ω_c)(r − R).
        let uo = rolling(1.0, 0.0);
        assert!((uo - 440.0 * (0.035 + 0.00635)).abs() < 1e-9);
        let ui = rolling(-1.0, 1036.0);
        assert!((ui - (1036.0 - 440.0) * (0.035 - 0.00635)).abs() < 1e-9);
    }
}
