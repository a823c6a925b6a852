//! Classic 4th-order Runge–Kutta (fixed step only; cubic Hermite dense output).

use crate::tableau::Tableau;

/// Classic RK4.
pub static RK4: Tableau = Tableau {
    name: "rk4",
    order: 4,
    stages: 4,
    fsal: false,
    c: &[0.0, 0.5, 0.5, 1.0, 1.0],
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0], &[]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    e: &[],
    e3: &[],
    err_order: 3,
    beta_scale: 0.75,
    stiff_bound: 0.0,
    dense: &[],
};
