//! Work counters and the serializable solver state.
//!
//! Floating-point fields of [`IntegratorState`] are serialized as their IEEE-754 bit patterns
//! (`u64`), so a round trip through any serde format (JSON included) is bit-exact.

use super::method::Method;

/// Work counters, cumulative since construction (or as restored from a snapshot).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations (all of them: stages, FSAL, initial step, dense output).
    pub rhs_evals: u64,
    /// Events handled.
    pub events: u64,
    /// Accepted steps that Hairer's stiffness detection flags as limited by stability
    /// (`h·ρ` above the method's boundary; DOPRI5 always, DOP853 when the dense output is
    /// built; 0 for methods without detection). A diagnostic, it does not change the stepping.
    #[serde(default)]
    pub stiff_steps: u64,
    /// Size of the last accepted step.
    pub h_last: f64,
    /// Smallest accepted step (0 before the first step).
    pub h_min_used: f64,
    /// Largest accepted step.
    pub h_max_used: f64,
}

impl Stats {
    pub(crate) fn record_accepted(&mut self, h: f64) {
        if self.steps == 0 || h < self.h_min_used {
            self.h_min_used = h;
        }
        if h > self.h_max_used {
            self.h_max_used = h;
        }
        self.h_last = h;
        self.steps += 1;
    }
}

/// Full solver state: restoring it into an integrator with the same method, dimension and options
/// continues bit-identically.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct IntegratorState {
    /// Method the state belongs to.
    pub method: Method,
    /// Current time.
    #[serde(with = "bits")]
    pub t: f64,
    /// Current state.
    #[serde(with = "bits_vec")]
    pub y: Vec<f64>,
    /// Proposed next step size (0: not yet chosen).
    #[serde(with = "bits")]
    pub h_next: f64,
    /// FSAL stage `f(t, y)` (meaningful only when `fsal_valid`).
    #[serde(with = "bits_vec")]
    pub fsal: Vec<f64>,
    /// Whether `fsal` holds `f(t, y)`.
    pub fsal_valid: bool,
    /// PI-controller memory (previous error, Hairer's `facold`).
    #[serde(with = "bits")]
    pub err_old: f64,
    /// Whether the previous attempt was rejected.
    pub last_rejected: bool,
    /// Events that fired at the current time (their sign is treated as 0 when restarting).
    pub event_mask: Vec<bool>,
    /// Work counters.
    #[serde(with = "stats_bits")]
    pub stats: Stats,
}

mod bits {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_u64(x.to_bits())
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        u64::deserialize(d).map(f64::from_bits)
    }
}

mod bits_vec {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(x: &[f64], s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(x.iter().map(|v| v.to_bits()))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
        Vec::<u64>::deserialize(d).map(|v| v.into_iter().map(f64::from_bits).collect())
    }
}

mod stats_bits {
    use super::Stats;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    #[derive(Serialize, Deserialize)]
    struct Raw {
        steps: u64,
        rejected: u64,
        rhs_evals: u64,
        events: u64,
        #[serde(default)]
        stiff_steps: u64,
        h_last: u64,
        h_min_used: u64,
        h_max_used: u64,
    }

    pub fn serialize<S: Serializer>(x: &Stats, s: S) -> Result<S::Ok, S::Error> {
        Raw {
            steps: x.steps,
            rejected: x.rejected,
            rhs_evals: x.rhs_evals,
            events: x.events,
            stiff_steps: x.stiff_steps,
            h_last: x.h_last.to_bits(),
            h_min_used: x.h_min_used.to_bits(),
            h_max_used: x.h_max_used.to_bits(),
        }
        .serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Stats, D::Error> {
        let r = Raw::deserialize(d)?;
        Ok(Stats {
            steps: r.steps,
            rejected: r.rejected,
            rhs_evals: r.rhs_evals,
            events: r.events,
            stiff_steps: r.stiff_steps,
            h_last: f64::from_bits(r.h_last),
            h_min_used: f64::from_bits(r.h_min_used),
            h_max_used: f64::from_bits(r.h_max_used),
        })
    }
}
