//! Ball–race contact laws: the Hertz normal law ([`HertzContact`]), the lubricant traction law
//! ([`TractionCurve`]) and the spall that changes both where a ball meets it ([`Defect`]).

mod hertz;
mod traction;

pub use crate::defect::{ContactKind, Defect, DefectContact, DropNode, SpallSummary};
pub use hertz::{HertzContact, HertzSolution};
pub use traction::TractionCurve;
