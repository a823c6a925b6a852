//! What every analysis shares: the error type, the smallest signal, the input check.

use std::fmt;

/// Smallest number of samples any analysis accepts.
pub const MIN_SAMPLES: usize = 8;

/// Everything that can go wrong in signal analysis; the `Display` text is meant for end users.
#[derive(Debug, Clone, PartialEq)]
pub enum SignalError {
    /// Fewer samples than the analysis needs.
    TooFewSamples {
        /// Number of samples required.
        needed: usize,
        /// Number of samples available.
        got: usize,
    },
    /// A parameter is out of its valid range (the text says which and why).
    InvalidParameter(String),
    /// The input contains NaN or infinity.
    NonFinite {
        /// Index of the first offending sample.
        index: usize,
    },
    /// A file could not be read or written, or is malformed.
    Io(String),
    /// The requested CSV column does not exist.
    MissingColumn {
        /// The column that was asked for.
        column: String,
        /// The columns the file does have, in file order.
        available: Vec<String>,
    },
    /// The time column is not uniformly sampled (the text gives the first offending sample).
    NonUniformSampling(String),
}

impl fmt::Display for SignalError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SignalError::TooFewSamples { needed, got } => {
                write!(
                    f,
                    "too few samples: {got} available, at least {needed} needed"
                )
            }
            SignalError::InvalidParameter(msg) => write!(f, "invalid parameter: {msg}"),
            SignalError::NonFinite { index } => {
                write!(
                    f,
                    "signal contains a non-finite value (NaN or inf) at sample {index}"
                )
            }
            SignalError::Io(msg) => write!(f, "{msg}"),
            SignalError::MissingColumn { column, available } => write!(
                f,
                "column '{column}' not found; available columns: {}",
                available.join(", ")
            ),
            SignalError::NonUniformSampling(msg) => write!(f, "non-uniform sampling: {msg}"),
        }
    }
}

impl std::error::Error for SignalError {}

/// Checks a signal and a sampling rate shared by all analyses.
pub(crate) fn check_input(x: &[f64], fs: f64, needed: usize) -> Result<(), SignalError> {
    if !(fs.is_finite() && fs > 0.0) {
        return Err(SignalError::InvalidParameter(format!(
            "sampling rate must be finite and > 0 Hz, got {fs}"
        )));
    }
    if x.len() < needed {
        return Err(SignalError::TooFewSamples {
            needed,
            got: x.len(),
        });
    }
    if let Some(index) = x.iter().position(|v| !v.is_finite()) {
        return Err(SignalError::NonFinite { index });
    }
    Ok(())
}

/// Arithmetic mean (0 for an empty slice).
pub(crate) fn mean(x: &[f64]) -> f64 {
    if x.is_empty() {
        0.0
    } else {
        x.iter().sum::<f64>() / x.len() as f64
    }
}
