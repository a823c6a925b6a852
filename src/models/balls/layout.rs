//! State layout of the ball-level models: the full model's (docs/model.md#state) and the reduced model's
//! ([`Layout::reduced`]), which shares its offsets. The full model's, with deflection-scale states as deviations
//! (docs/model.md#integrator): ball radius relative to the pitch radius, ball azimuth relative to a reference
//! cage angle ψ that turns at a constant rate.
//!
//! Per ball j (9 states from `9 j`): x, r − dm/2, θ − (ψ + θ_start + 2πj/z), ẋ, ṙ, θ̇, ω_x, ω_y, ω_z.
//! Then the inner ring (10): x, y, z, ẋ, ẏ, ż, β_y, β_z, β̇_y, β̇_z; the pedestal (4):
//! y_p, z_p, ẏ_p, ż_p; and two angles: the reference cage angle ψ and the shaft angle φ
//! (integrated from the inputs so that a speed change keeps them continuous). A model with a
//! cage (docs/model.md#cage) has 6 more at the end: the cage angle's deviation χ from ψ, the
//! cage centre's y and z, the cage's angular rate ω_c and the centre's ẏ, ż. A scene with spalls
//! on balls (docs/model.md#ball-spall) has 3 more per such spall after those: the unit vector
//! from the ball's centre to the spall's centre, inertial components x, y, z; one with ball
//! waviness 3 more per ball after those: a reference direction fixed on the ball.

/// States per ball.
pub const PER_BALL: usize = 9;
// Offsets inside a ball's block.
/// Offset of the ball's axial position x \[m\].
pub const BX: usize = 0;
/// Offset of the ball's radial position relative to the pitch radius, r − dm/2 \[m\].
pub const BR: usize = 1;
/// Offset of the ball's azimuth relative to its reference cage angle \[rad\].
pub const BTH: usize = 2;
/// Offset of the ball's axial velocity ẋ \[m/s\].
pub const BVX: usize = 3;
/// Offset of the ball's radial velocity ṙ \[m/s\].
pub const BVR: usize = 4;
/// Offset of the ball's orbital rate θ̇ \[rad/s\].
pub const BW: usize = 5;
/// Offset of the ball's spin ω_x (then ω_y, ω_z) \[rad/s\]; the reduced model's spin rate ω_s.
pub const BOM: usize = 6;

// Offsets inside the inner-ring block.
/// Offset of the inner ring's position x (then y, z) \[m\].
pub const RX: usize = 0;
/// Offset of the inner ring's velocity ẋ (then ẏ, ż) \[m/s\].
pub const RV: usize = 3;
/// Offset of the inner ring's tilt β_y \[rad\].
pub const RBY: usize = 6;
/// Offset of the inner ring's tilt β_z \[rad\].
pub const RBZ: usize = 7;
/// Offset of the inner ring's tilt rate β̇_y \[rad/s\].
pub const RWY: usize = 8;
/// Offset of the inner ring's tilt rate β̇_z \[rad/s\].
pub const RWZ: usize = 9;

// Offsets inside the pedestal block.
/// Offset of the pedestal's displacement y_p \[m\].
pub const PY: usize = 0;
/// Offset of the pedestal's displacement z_p \[m\].
pub const PZ: usize = 1;
/// Offset of the pedestal's velocity ẏ_p \[m/s\].
pub const PVY: usize = 2;
/// Offset of the pedestal's velocity ż_p \[m/s\].
pub const PVZ: usize = 3;

// Offsets inside the cage block.
/// Offset of the cage angle's deviation χ from the reference cage angle ψ \[rad\].
pub const CA: usize = 0;
/// Offset of the cage centre's y (then z) \[m\].
pub const CY: usize = 1;
/// Offset of the cage's angular rate ω_c \[rad/s\].
pub const CW: usize = 3;
/// Offset of the cage centre's ẏ (then ż) \[m/s\].
pub const CV: usize = 4;
/// States of the cage block.
pub const CAGE_STATES: usize = 6;

/// States of the reduced model's ball block: the full model's x, r, θ, ẋ, ṙ, θ̇ and one spin
/// rate ω_s at `BOM`.
pub const REDUCED_PER_BALL: usize = 7;
/// States of the full model's inner-ring block (translation and tilt).
pub const RING_STATES: usize = 10;
/// States of the reduced model's inner-ring block (translation only).
pub const REDUCED_RING_STATES: usize = 6;

/// Index arithmetic for a bearing with `z` balls, `per_ball` states per ball and `ring_len`
/// states in the inner-ring block (the full model's [`Layout::full`], the reduced model's
/// [`Layout::reduced`]).
#[derive(Debug, Clone, Copy)]
pub struct Layout {
    /// Number of balls.
    pub z: usize,
    /// States per ball.
    pub per_ball: usize,
    /// States of the inner-ring block.
    pub ring_len: usize,
    /// The model has a cage (the cage block at the end).
    pub cage: bool,
    /// Number of spalls on balls (3 direction states each, after the cage block).
    pub ball_spalls: usize,
    /// Each ball has a reference direction on its surface (3 states each, after the spalls'),
    /// for ball waviness.
    pub ball_refs: bool,
}

impl Layout {
    /// The full model's layout (see the module documentation).
    pub fn full(z: usize) -> Self {
        Self {
            z,
            per_ball: PER_BALL,
            ring_len: RING_STATES,
            cage: false,
            ball_spalls: 0,
            ball_refs: false,
        }
    }
    /// The reduced model's layout: per ball j (7 states from `7 j`) x, r, θ, ẋ, ṙ, θ̇, ω_s;
    /// the inner ring (6): x, y, z, ẋ, ẏ, ż; then the pedestal and the two angles as in the
    /// full model.
    pub fn reduced(z: usize) -> Self {
        Self {
            z,
            per_ball: REDUCED_PER_BALL,
            ring_len: REDUCED_RING_STATES,
            cage: false,
            ball_spalls: 0,
            ball_refs: false,
        }
    }
    /// This layout with (or without) the cage block.
    pub fn with_cage(self, cage: bool) -> Self {
        Self { cage, ..self }
    }
    /// This layout with the direction states of `n` spalls on balls.
    pub fn with_ball_spalls(self, n: usize) -> Self {
        Self {
            ball_spalls: n,
            ..self
        }
    }
    /// First of the three direction states of spall `s` on a ball (meaningful when
    /// `s` < [`Layout::ball_spalls`]).
    #[inline(always)]
    pub fn spall_dir(&self, s: usize) -> usize {
        self.pedestal() + 6 + if self.cage { CAGE_STATES } else { 0 } + 3 * s
    }
    /// This layout with (or without) each ball's reference direction.
    pub fn with_ball_refs(self, on: bool) -> Self {
        Self {
            ball_refs: on,
            ..self
        }
    }
    /// First of the three reference-direction states of ball j (meaningful when
    /// [`Layout::ball_refs`]).
    #[inline(always)]
    pub fn ball_ref(&self, j: usize) -> usize {
        self.spall_dir(self.ball_spalls) + 3 * j
    }
    /// First state of ball j.
    #[inline(always)]
    pub fn ball(&self, j: usize) -> usize {
        self.per_ball * j
    }
    /// First state of the inner ring.
    #[inline(always)]
    pub fn ring(&self) -> usize {
        self.per_ball * self.z
    }
    /// First state of the pedestal.
    #[inline(always)]
    pub fn pedestal(&self) -> usize {
        self.per_ball * self.z + self.ring_len
    }
    /// Reference cage angle ψ.
    #[inline(always)]
    pub fn psi(&self) -> usize {
        self.pedestal() + 4
    }
    /// Shaft angle φ.
    #[inline(always)]
    pub fn phi(&self) -> usize {
        self.pedestal() + 5
    }
    /// First state of the cage block (meaningful when [`Layout::cage`]).
    #[inline(always)]
    pub fn cage_block(&self) -> usize {
        self.pedestal() + 6
    }
    /// Number of states.
    #[inline(always)]
    pub fn dim(&self) -> usize {
        self.ball_ref(if self.ball_refs { self.z } else { 0 })
    }
}

/// Name of the state at `offset` in ball j's block (j from 0; counted from 1 in the name, as in
/// the outputs), for failure messages: the offsets `BX` … `BW` of this layout, then the full
/// model's ω_x, ω_y, ω_z, or `spin` for a model with one spin rate there.
pub fn ball_state_name(j: usize, offset: usize, spin: &[&str]) -> String {
    let what = match offset {
        BX => "axial position x",
        BR => "radial position r (from the pitch circle)",
        BTH => "orbital angle θ (from its place in the cage)",
        BVX => "axial velocity ẋ",
        BVR => "radial velocity ṙ",
        BW => "orbital rate θ̇",
        k => spin.get(k - BOM).copied().unwrap_or("state"),
    };
    format!("ball {} {what}", j + 1)
}

/// Name of the state at `offset` in the inner-ring block (`RX`, `RV` and, in the full model,
/// the tilt `RBY` … `RWZ`).
pub fn ring_state_name(offset: usize) -> String {
    let axis = ["x", "y", "z"];
    match offset {
        0..=2 => format!("inner-ring displacement along {}", axis[offset - RX]),
        3..=5 => format!("inner-ring velocity along {}", axis[offset - RV]),
        RBY => "inner-ring tilt β_y".into(),
        RBZ => "inner-ring tilt β_z".into(),
        RWY => "inner-ring tilt rate β̇_y".into(),
        RWZ => "inner-ring tilt rate β̇_z".into(),
        k => format!("inner-ring state {k}"),
    }
}

/// Name of the state at `offset` in the pedestal block.
pub fn pedestal_state_name(offset: usize) -> String {
    match offset {
        PY => "pedestal displacement along y".into(),
        PZ => "pedestal displacement along z".into(),
        PVY => "pedestal velocity along y".into(),
        PVZ => "pedestal velocity along z".into(),
        k => format!("pedestal state {k}"),
    }
}

/// Name of the state at `offset` in the cage block.
pub fn cage_state_name(offset: usize) -> String {
    match offset {
        CA => "cage angle χ (from the reference cage angle ψ)".into(),
        1 => "cage centre displacement along y".into(),
        2 => "cage centre displacement along z".into(),
        CW => "cage angular rate ω_c".into(),
        4 => "cage centre velocity along y".into(),
        5 => "cage centre velocity along z".into(),
        k => format!("cage state {k}"),
    }
}
