//! The ball-level models' building blocks, exposed for white-box tests and research probes
//! (`studies/`): the state layouts, the balls' steady-rotation solve, the strip traction sums,
//! the ball-to-ball contact, the cage ([`cage`]: its constants, pockets and land), the start
//! angle of the balls, and one ball–race contact's normal stage ([`evaluate_normal_at`] from a
//! ball's [`groove_pos`], with the race constants of [`race_const`], run under
//! [`with_avx2`] as the models run it). Running a simulation needs none of it; it follows the
//! models' implementation and changes with it.

pub use super::balls::ball_ball::{ball_ball_stiffness, BallBall, PairContact};
pub use super::balls::ball_contact::{
    evaluate_normal_at, groove_pos, strip_sums, BallKin, ContactOut, GroovePos, Law, RaceConst,
    RingPose, SlipField, Strips, TractionBatch,
};
pub use super::balls::cage;
pub use super::balls::core::{choose_theta_start, race_const};
pub use super::balls::layout;
pub use super::full::steady::{steady_rotation, Orbit, SteadyBalls, SteadyError, SteadyReport};
pub use super::reduced::L3_STRIPS;
pub use crate::vecmath::with_avx2;
