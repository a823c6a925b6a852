//! Runge–Kutta–Fehlberg 4(5), propagating the 4th-order solution as in Fehlberg's paper
//! (and in the bearing paper); cubic Hermite dense output.

use crate::tableau::Tableau;

const B4: [f64; 6] = [
    25.0 / 216.0,
    0.0,
    1408.0 / 2565.0,
    2197.0 / 4104.0,
    -1.0 / 5.0,
    0.0,
];
const B5: [f64; 6] = [
    16.0 / 135.0,
    0.0,
    6656.0 / 12825.0,
    28561.0 / 56430.0,
    -9.0 / 50.0,
    2.0 / 55.0,
];

/// Fehlberg 4(5), 4th-order propagation.
pub static RKF45: Tableau = Tableau {
    name: "rkf45",
    order: 4,
    stages: 6,
    fsal: false,
    c: &[0.0, 0.25, 3.0 / 8.0, 12.0 / 13.0, 1.0, 0.5, 1.0],
    a: &[
        &[],
        &[0.25],
        &[3.0 / 32.0, 9.0 / 32.0],
        &[1932.0 / 2197.0, -7200.0 / 2197.0, 7296.0 / 2197.0],
        &[439.0 / 216.0, -8.0, 3680.0 / 513.0, -845.0 / 4104.0],
        &[
            -8.0 / 27.0,
            2.0,
            -3544.0 / 2565.0,
            1859.0 / 4104.0,
            -11.0 / 40.0,
        ],
        &[],
    ],
    b: &B4,
    e: &[
        B4[0] - B5[0],
        B4[1] - B5[1],
        B4[2] - B5[2],
        B4[3] - B5[3],
        B4[4] - B5[4],
        B4[5] - B5[5],
    ],
    e3: &[],
    err_order: 4,
    beta_scale: 0.75,
    stiff_bound: 0.0,
    dense: &[],
};
