//! Ball–race contact laws: the Hertz normal law ([`HertzContact`]), the lubricant traction law
//! ([`TractionCurve`]), the lubricant film's thickness, stiffness and damping ([`FilmContact`])
//! and the spall that changes the contact where a ball meets it ([`Defect`]).

mod film;
mod hertz;
mod traction;

pub use crate::defect::{ContactKind, Defect, DefectContact, DropNode, SpallSummary};
pub use film::{walther_viscosity, FilmContact, FilmState, Lubricant, HC_W_EXP, SERIES_RATIO};
pub use hertz::{HertzContact, HertzSolution};
pub use traction::TractionCurve;
