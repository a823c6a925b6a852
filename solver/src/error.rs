//! Integration failures.

use super::method::Method;

/// What limited the step size at the attempt after which it fell below the minimum. Components
/// are indices into the state vector (the integrator knows nothing about what they mean; a
/// caller that does names them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StepLimit {
    /// The local error estimate: largest in `component`, where it is `ratio` times the
    /// component's tolerance (atol + rtol·|y|).
    Error { component: usize, ratio: f64 },
    /// The right-hand side gave a non-finite value (NaN or ∞) in the derivative of `component`,
    /// at the stage at time `t` of the attempt, from a finite stage state (the first such
    /// stage, so the source rather than its spread).
    NonFiniteDerivative { component: usize, t: f64 },
    /// The trial state became non-finite in `component` with finite derivatives (overflow).
    NonFiniteState { component: usize },
    /// No attempt at this step size (the step would not move the time).
    Unknown,
}

/// Why an integration call failed. After any error the integrator stays at the last accepted step.
#[derive(Clone, Debug, PartialEq)]
pub enum SolverError {
    /// The controller asked for a step below the minimum step size (stall).
    StepSizeUnderflow {
        /// Time of the last accepted step.
        t: f64,
        /// The step size that fell below the minimum.
        h: f64,
        /// The minimum step size there ([`crate::Options::h_min`], relative above 1 s).
        h_min: f64,
        /// What limited the last attempt.
        limit: StepLimit,
    },
    /// The right-hand side at the current (accepted) state, or with a fixed step the new state,
    /// is not finite, and no smaller step can cure it.
    NonFinite {
        /// Time of the last accepted step.
        t: f64,
        /// First non-finite component.
        component: usize,
        /// True: the derivative f(t, y) at the accepted state; false: the new state of a fixed
        /// step.
        derivative: bool,
    },
    /// The step budget ([`crate::Options::max_steps`]) of one call was exhausted.
    StepBudget {
        /// Time of the last accepted step.
        t: f64,
        /// Steps attempted (accepted and rejected) in the call.
        steps: u64,
    },
    /// Steps end in events again and again, a few steps apart (Zeno behaviour,
    /// [`crate::Options::chatter_events`]).
    Chattering {
        /// Time of the last event.
        t: f64,
        /// The event function of the last event.
        index: usize,
        /// Steps with events in the run.
        events: u32,
        /// At most this many accepted steps lay between two of them
        /// ([`crate::Options::chatter_steps`]).
        steps: u64,
        /// Time from the first event of the run to the last.
        span: f64,
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
        f.write_str(&self.describe(&|i| format!("state component {i}")))
    }
}

impl SolverError {
    /// The message, with state components called `name(i)` (a caller that knows what they
    /// are names them; [`std::fmt::Display`] says "state component i").
    pub fn describe(&self, name: &dyn Fn(usize) -> String) -> String {
        self.describe_with_events(name, &|i| format!("event function {i}"))
    }

    /// [`SolverError::describe`], with event functions called `event(i)` as well.
    pub fn describe_with_events(
        &self,
        name: &dyn Fn(usize) -> String,
        event: &dyn Fn(usize) -> String,
    ) -> String {
        match self {
            SolverError::StepSizeUnderflow { t, h, h_min, limit } => {
                let base = format!(
                    "step size {h:.3e} s fell below the minimum {h_min:.1e} s at t = {t} s"
                );
                match limit {
                    StepLimit::Error { component, ratio } => format!(
                        "{base}: the error estimate of {} is {ratio:.3e} times its tolerance at \
                         the last step size tried",
                        name(*component)
                    ),
                    StepLimit::NonFiniteDerivative { component, t } => format!(
                        "{base}: the right-hand side gives a non-finite value (NaN or ∞) in the \
                         derivative of {} (first at t = {t} s), at every step size tried",
                        name(*component)
                    ),
                    StepLimit::NonFiniteState { component } => format!(
                        "{base}: {} overflows to a non-finite value at every step size tried",
                        name(*component)
                    ),
                    StepLimit::Unknown => base,
                }
            }
            SolverError::NonFinite {
                t,
                component,
                derivative: true,
            } => format!(
                "the right-hand side is not finite (NaN or ∞) in the derivative of {} at the \
                 accepted state at t = {t} s",
                name(*component)
            ),
            SolverError::NonFinite {
                t,
                component,
                derivative: false,
            } => format!(
                "{} became non-finite (NaN or ∞) in the fixed step from t = {t} s",
                name(*component)
            ),
            SolverError::StepBudget { t, steps } => format!(
                "step budget exhausted: {steps} steps attempted in one call, stopped at t = {t} s"
            ),
            SolverError::Chattering {
                t,
                index,
                events,
                steps,
                span,
            } => format!(
                "events chatter at t = {t} s: {events} steps in a row ended in an event, in \
                 {span:.3e} s, each within {steps} steps of the one before, the last at {} \
                 (Zeno behaviour: the integration would creep on at a few steps per event). A \
                 stiffness, damping or mass parameter is probably far outside the physical range",
                event(*index)
            ),
            SolverError::InvalidOptions(msg) => format!("invalid solver options: {msg}"),
            SolverError::InvalidTarget { t, t_end } => format!(
                "cannot integrate from t = {t} s to t_end = {t_end} s (only finite, forward \
                 targets are supported)"
            ),
            SolverError::DimensionMismatch { expected, found } => {
                format!("dimension mismatch: integrator has {expected} states, got {found}")
            }
            SolverError::StateMismatch(msg) => format!("cannot restore solver state: {msg}"),
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
            h_min: 1e-14,
            limit: StepLimit::Error {
                component: 7,
                ratio: 12.5,
            },
        };
        let s = e.to_string();
        assert!(
            s.contains("3.100e-15") && s.contains("0.0123") && s.contains("component 7"),
            "{s}"
        );
        let e = SolverError::NonFinite {
            t: 1.0,
            component: 3,
            derivative: true,
        };
        assert!(e.to_string().contains("component 3"));
    }
}
