//! The sweep-level error.

use std::fmt;

/// A sweep-level error (bad sweep file, unusable output folder); failed runs are not errors.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepError(pub String);

impl SweepError {
    /// An error with a message.
    pub fn new(m: impl Into<String>) -> Self {
        Self(m.into())
    }
}

impl fmt::Display for SweepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SweepError {}
