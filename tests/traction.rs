//! Traction law against docs/model.md#traction / #verification (independent numpy/scipy values, docs/model.md#c8).

use raceway::contact::TractionCurve;
use raceway::{TractionLaw, TractionSection};

fn default_curve() -> TractionCurve {
    TractionCurve::new(&TractionSection::default()).expect("C8 defaults have a root")
}

#[test]
fn adore_coefficients_match_spec() {
    let c = default_curve();
    let (a, b, cc, d) = c.coefficients();
    assert!((a + 0.05).abs() < 1e-15, "A = {a}");
    assert!((d - 0.05).abs() < 1e-15, "D = {d}");
    assert!((b - 0.34522).abs() < 5e-6, "B = {b}");
    assert!((cc - 2.81560).abs() < 5e-6, "C = {cc}");
    // C = B/(A + B u_m) by construction.
    assert!((cc - b / (a + b * 0.5)).abs() < 1e-12);
}

#[test]
fn kappa_values_match_spec_table() {
    let c = default_curve();
    for (u, k) in [
        (0.1, 0.03832),
        (0.25, 0.06796),
        (0.5, 0.08),
        (1.0, 0.06767),
        (2.0, 0.05230),
        (10.0, 0.05000),
    ] {
        let got = c.kappa(u);
        assert!((got - k).abs() < 5e-6, "kappa({u}) = {got}, spec {k}");
    }
    assert!(c.kappa(0.0).abs() < 1e-15, "kappa_0 = 0");
    // Negative speeds are treated as |u|.
    assert_eq!(c.kappa(-0.25), c.kappa(0.25));
}

#[test]
fn initial_slope_matches_spec() {
    let c = default_curve();
    assert!(
        (c.dkappa_du0() - 0.486).abs() < 5e-4,
        "dκ/du(0) = {}",
        c.dkappa_du0()
    );
    // Against a finite difference of the law itself.
    let h = 1e-7;
    let fd = (c.kappa(h) - c.kappa(0.0)) / h;
    assert!((fd - c.dkappa_du0()).abs() < 1e-6, "fd {fd}");
}

#[test]
fn kappa_over_u_is_finite_and_continuous_at_zero() {
    let c = default_curve();
    let lim = c.dkappa_du0();
    assert!(c.kappa_over_u(0.0).is_finite());
    assert!((c.kappa_over_u(0.0) - lim).abs() < 1e-14);
    // Smooth approach through the series/closed-form switch and far below it.
    let mut prev = c.kappa_over_u(0.0);
    for k in 1..=400 {
        let u = 1e-9 * 1.05_f64.powi(k); // 1e-9 .. ~3e-1
        let r = c.kappa_over_u(u);
        assert!(r.is_finite());
        // Equals κ(u)/u wherever the division is well conditioned.
        if u > 1e-4 {
            assert!(
                (r - c.kappa(u) / u).abs() < 1e-9 * (1.0 + r),
                "u {u}: {r} vs {}",
                c.kappa(u) / u
            );
        }
        // κ/u is monotone decreasing on (0, u_m) for this curve and changes slowly.
        assert!(
            r <= prev + 1e-12 && prev - r < 0.1 * lim,
            "u {u}: {prev} -> {r}"
        );
        prev = r;
    }
    // Second-order accuracy near zero: κ/u ≈ κ'(0) + κ''(0) u/2.
    let u = 1e-6;
    assert!((c.kappa_over_u(u) - lim).abs() < 1e-5);
}

#[test]
fn maximum_is_at_u_max() {
    let c = default_curve();
    let (mut u_best, mut k_best) = (0.0, f64::MIN);
    for i in 0..=200_000 {
        let u = i as f64 * 1e-5; // 0 .. 2 m/s
        let k = c.kappa(u);
        if k > k_best {
            k_best = k;
            u_best = u;
        }
    }
    assert!((u_best - 0.5).abs() < 2e-4, "argmax {u_best}");
    assert!((k_best - 0.08).abs() < 1e-9, "max {k_best}");
    // And the plateau is reached from above.
    assert!(c.kappa(5.0) > 0.05 && c.kappa(5.0) - 0.05 < 1e-5);
}

#[test]
fn force_opposes_slip_with_magnitude_q_kappa() {
    let c = default_curve();
    let q = 700.0;
    let (u1, u2) = (0.3, -0.4); // |u| = 0.5
    let (f1, f2) = c.force(u1, u2, q);
    let mag = (f1 * f1 + f2 * f2).sqrt();
    assert!((mag - q * 0.08).abs() < 1e-9, "|F| = {mag}");
    assert!(f1 * u1 + f2 * u2 < 0.0, "force must oppose slip");
    assert!((f1 * u2 - f2 * u1).abs() < 1e-12, "force parallel to slip");
    assert_eq!(c.force(0.0, 0.0, q), (0.0, 0.0));
    // Linear regime near zero: F ≈ −Q κ'(0) u.
    let (g1, _) = c.force(1e-9, 0.0, q);
    assert!((g1 + q * c.dkappa_du0() * 1e-9).abs() < 1e-15);
}

#[test]
fn other_curves_keep_their_maximum_at_u_max() {
    // Baomaokuan/Bearing example (κ0 0, κm 0.05, κ∞ 0.036, u_m 1 m/s) and a κ0 > 0 curve.
    for (k0, km, um, kinf) in [(0.0, 0.05, 1.0, 0.036), (0.02, 0.1, 0.3, 0.04)] {
        let t = TractionSection {
            law: TractionLaw::Adore,
            kappa_0: k0,
            kappa_max: km,
            u_max: um,
            kappa_inf: kinf,
        };
        let c = TractionCurve::new(&t).unwrap();
        assert!((c.kappa(0.0) - k0).abs() < 1e-12);
        assert!((c.kappa(um) - km).abs() < 1e-12, "{}", c.kappa(um));
        let h = 1e-5 * um;
        assert!(c.kappa(um - h) < km && c.kappa(um + h) < km);
        assert!((c.kappa(1e3 * um) - kinf).abs() < 1e-9);
        assert!(c.kappa_over_u(0.0).is_finite());
    }
}

#[test]
fn no_root_names_kappa_max() {
    // κm = κ∞ = κ0: the maximum cannot sit at u_m.
    let t = TractionSection {
        law: TractionLaw::Adore,
        kappa_0: 0.05,
        kappa_max: 0.05,
        u_max: 0.5,
        kappa_inf: 0.05,
    };
    let e = TractionCurve::new(&t).unwrap_err();
    assert_eq!(e.field, "traction.kappa_max", "{e}");
    // A tiny u_m would need B > 100 s/m.
    let t = TractionSection {
        u_max: 1e-5,
        ..TractionSection::default()
    };
    let e = TractionCurve::new(&t).unwrap_err();
    assert_eq!(e.field, "traction.kappa_max", "{e}");
    // kappa_max below kappa_inf.
    let t = TractionSection {
        kappa_max: 0.04,
        ..TractionSection::default()
    };
    assert_eq!(
        TractionCurve::new(&t).unwrap_err().field,
        "traction.kappa_max"
    );
    // Non-finite input never panics.
    let t = TractionSection {
        u_max: f64::NAN,
        ..TractionSection::default()
    };
    assert_eq!(TractionCurve::new(&t).unwrap_err().field, "traction.u_max");
}

#[test]
fn piecewise_law() {
    let t = TractionSection {
        law: TractionLaw::Piecewise,
        ..TractionSection::default()
    };
    let c = TractionCurve::new(&t).unwrap();
    assert!((c.kappa(0.25) - 0.04).abs() < 1e-15);
    assert!((c.kappa(0.5) - 0.08).abs() < 1e-15);
    // Halfway from u_m to 10 u_m: halfway from κm to κ∞.
    assert!((c.kappa(2.75) - 0.065).abs() < 1e-12);
    assert!((c.kappa(5.0) - 0.05).abs() < 1e-15 && (c.kappa(100.0) - 0.05).abs() < 1e-15);
    assert!((c.kappa_over_u(0.0) - 0.16).abs() < 1e-15);
    assert!((c.dkappa_du0() - 0.16).abs() < 1e-15);
    assert!((c.kappa_over_u(2.75) - 0.065 / 2.75).abs() < 1e-15);
}
