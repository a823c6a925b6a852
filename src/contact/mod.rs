//! Ball–race contact laws: the Hertz normal law and the lubricant traction law.

pub mod hertz;
pub mod traction;
