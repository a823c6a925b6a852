//! The ball-level models' building blocks, exposed for white-box tests and research probes
//! (`studies/`): the state layouts, the balls' steady-rotation solve, the strip traction sums,
//! the ball-to-ball contact, the cage ([`cage`]: its constants, pockets and land) and the start
//! angle of the balls. Running a simulation needs none of it; it follows the
//! models' implementation and changes with it.

pub use super::balls::ball_ball::{ball_ball_stiffness, BallBall, PairContact};
pub use super::balls::ball_contact::{strip_sums, SlipField, Strips, TractionBatch};
pub use super::balls::cage;
pub use super::balls::core::choose_theta_start;
pub use super::balls::layout;
pub use super::full::steady::{steady_rotation, Orbit, SteadyBalls, SteadyError, SteadyReport};
pub use super::reduced::L3_STRIPS;
