//! Tableau data of each method, one file per method.

pub mod dop853;
pub mod dopri5;
pub mod rk4;
pub mod rkf45;
