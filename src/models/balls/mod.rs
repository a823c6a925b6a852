//! What the ball-level models (full L4, reduced L3) share: the state layout ([`layout`]), one
//! ball–race contact ([`ball_contact`]: geometry, Hertz, the spall, strip traction), the
//! contacts between neighbouring balls of a cage-less model ([`ball_ball`]), the cage
//! ([`cage`]: pockets, guidance, its equations of motion), the staged
//! contacts of one right-hand side ([`pass`]), the frozen modes and their switches
//! ([`switches`]), and the [`BallCore`] struct that holds all of it for a model.

pub mod ball_ball;
pub mod ball_contact;
pub mod cage;
pub mod core;
pub mod layout;
pub mod pass;
pub mod switches;

pub(crate) use self::core::forward_to_ball_core;
pub use self::core::{BallCore, BallSpin};
