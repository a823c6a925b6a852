//! The CSV writer's number formatting (`signal::push_sci10`) against `core::fmt`'s `{:.9e}`.

use raceway::signal::push_sci10;

fn fmt(v: f64) -> String {
    let mut b = Vec::new();
    push_sci10(&mut b, v);
    String::from_utf8(b).unwrap()
}

#[test]
fn special_and_edge_values_match_core_fmt() {
    let vals = [
        0.0,
        -0.0,
        1.0,
        -1.0,
        0.1,
        9.99999999949,
        0.999999999951,
        1e21,
        1.5e-7,
        123456.789,
        0.00012,
        f64::MAX,
        f64::MIN_POSITIVE,
        5e-324,
        -2.5e-310,
        1e100,
        1e-100,
        979.53,
        -1.0e-5,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for v in vals {
        assert_eq!(fmt(v), format!("{v:.9e}"), "{v:e}");
    }
    // The documented double rounding: the shortest digits of 9.9999999995 end in 5 at the
    // eleventh place, while the binary value lies just below it. core::fmt rounds the binary
    // value down, push_sci10 the digits up: one unit in the tenth digit.
    assert_eq!(format!("{:.9e}", 9.9999999995), "9.999999999e0");
    assert_eq!(fmt(9.9999999995), "1.000000000e1");
}

/// A million values with random bits (every exponent) and a million of simulator-like
/// magnitudes: at most a handful may differ (the documented double rounding), and then only by
/// one unit in the tenth digit.
#[test]
fn random_values_match_core_fmt() {
    let mut state = 0x1234_5678_9abc_def0u64;
    let mut next = || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut x = state;
        x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        x ^ (x >> 31)
    };
    let mut differ = 0;
    let mut n = 0;
    for k in 0..2_000_000 {
        let bits = next();
        let v = if k % 2 == 0 {
            f64::from_bits(bits)
        } else {
            // −1e4 … 1e4 with 1e-9 … 1 scales: forces, accelerations, displacements.
            let u = (bits >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
            u * 2e4 * 10f64.powi(-((bits % 10) as i32))
        };
        if !v.is_finite() {
            continue;
        }
        n += 1;
        let (a, b) = (fmt(v), format!("{v:.9e}"));
        if a != b {
            differ += 1;
            let (x, y): (f64, f64) = (a.parse().unwrap(), b.parse().unwrap());
            let ulp10 = y.abs() * 1e-9;
            assert!((x - y).abs() <= 1.01 * ulp10, "{v:e}: {a} vs {b}");
        }
        // Round trip to ten digits.
        let back: f64 = a.parse().unwrap();
        assert!((back - v).abs() <= v.abs() * 5.000001e-10, "{v:e}: {a}");
    }
    assert!(n > 1_900_000);
    eprintln!("{differ} of {n} differ from core::fmt in the tenth digit");
    assert!(differ <= 5, "{differ} of {n}");
}
