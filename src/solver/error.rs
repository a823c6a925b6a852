//! Integration failures.

use super::method::Method;

/// Why an integration call failed. After any error the integrator stays at the last accepted step.
#[derive(Clone, Debug, PartialEq)]
pub enum SolverError {
    /// The controller asked for a step below the minimum step size (stall).
    StepSizeUnderflow {
        /// Time of the last accepted step.
        t: f64,
        /// The step size that fell below the minimum.
        h: f64,
    },
    /// The right-hand side (or, with a fixed step, the new state) is not finite and no smaller
    /// step can cure it.
    NonFinite {
        /// Time of the last accepted step.
        t: f64,
        /// First non-finite component.
        component: usize,
    },
    /// The step budget ([`crate::solver::Options::max_steps`]) of one call was exhausted.
    StepBudget {
        /// Time of the last accepted step.
        t: f64,
        /// Steps attempted (accepted and rejected) in the call.
        steps: u64,
    },
    /// The options (or a setter's argument, or the initial state) are invalid.
    InvalidOptions(String),
    /// The requested end time lies before the current time or is not finite.
    InvalidTarget {
        /// Current time.
        t: f64,
        /// Requested end time.
        t_end: f64,
    },
    /// The system's dimension differs from the integrator's.
    DimensionMismatch {
        /// Dimension of the integrator.
        expected: usize,
        /// Dimension that was supplied.
        found: usize,
    },
    /// A snapshot does not fit this integrator (method or dimension differs, or it is corrupt).
    StateMismatch(String),
}

impl std::fmt::Display for SolverError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SolverError::StepSizeUnderflow { t, h } => write!(
                f,
                "step size {h:.3e} s fell below the minimum at t = {t} s \
                 (stiff or discontinuous right-hand side?)"
            ),
            SolverError::NonFinite { t, component } => write!(
                f,
                "state component {component} became non-finite (NaN or infinite) at t = {t} s \
                 and no smaller step could avoid it"
            ),
            SolverError::StepBudget { t, steps } => write!(
                f,
                "step budget exhausted: {steps} steps attempted in one call, stopped at t = {t} s"
            ),
            SolverError::InvalidOptions(msg) => write!(f, "invalid solver options: {msg}"),
            SolverError::InvalidTarget { t, t_end } => write!(
                f,
                "cannot integrate from t = {t} s to t_end = {t_end} s (only finite, \
                 forward targets are supported)"
            ),
            SolverError::DimensionMismatch { expected, found } => write!(
                f,
                "dimension mismatch: integrator has {expected} states, got {found}"
            ),
            SolverError::StateMismatch(msg) => write!(f, "cannot restore solver state: {msg}"),
        }
    }
}

impl std::error::Error for SolverError {}

impl SolverError {
    pub(crate) fn method_mismatch(expected: Method, found: Method) -> Self {
        SolverError::StateMismatch(format!(
            "snapshot was taken with method {found}, integrator uses {expected}"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_are_clear() {
        let e = SolverError::StepSizeUnderflow {
            t: 0.0123,
            h: 3.1e-15,
        };
        let s = e.to_string();
        assert!(s.contains("3.100e-15") && s.contains("0.0123"), "{s}");
        let e = SolverError::NonFinite {
            t: 1.0,
            component: 3,
        };
        assert!(e.to_string().contains("component 3"));
    }
}
