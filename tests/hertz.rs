//! Hertz point contact against docs/model.md#hertz table (independent numpy/scipy computation).

use raceway::contact::{HertzContact, HertzSolution};
use raceway::{race_curvatures, Bearing, Race};

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

fn contact(b: &Bearing, race: Race, alpha_deg: f64, sol: HertzSolution) -> HertzContact {
    let (r1, r2) = race_curvatures(race, b.d, b.dm, alpha_deg.to_radians(), b.f(race));
    HertzContact::new(2.0 / b.d + r1, 2.0 / b.d + r2, b.e_prime, sol)
}

#[test]
fn table1_curvature_sums() {
    let b = Bearing::load("niu2014-table1").unwrap();
    let i = contact(&b, Race::Inner, 30.0, HertzSolution::Exact);
    let o = contact(&b, Race::Outer, 30.0, HertzSolution::Exact);
    assert!((i.inv_rx - 186.84).abs() < 0.01 && (i.inv_ry - 4.59).abs() < 0.01);
    assert!((o.inv_rx - 136.10).abs() < 0.01 && (o.inv_ry - 6.06).abs() < 0.01);
    assert!((i.inv_rx / i.inv_ry - 40.7).abs() < 0.05);
    assert!((o.inv_rx / o.inv_ry - 22.5).abs() < 0.05);
}

#[test]
fn table1_exact_constants_and_ellipticity() {
    let b = Bearing::load("niu2014-table1").unwrap();
    assert!(rel(b.k_inner, 3.608e10) < 1e-3, "K_i = {:e}", b.k_inner);
    assert!(rel(b.k_outer, 3.408e10) < 1e-3, "K_o = {:e}", b.k_outer);
    assert!((b.hertz_inner.ellipticity - 10.68).abs() < 0.01);
    assert!((b.hertz_outer.ellipticity - 7.44).abs() < 0.01);
    assert!(
        rel(b.k_series(), 1.239e10) < 1e-3,
        "K_n = {:e}",
        b.k_series()
    );
    // Harris' δ* at 30°.
    assert!((b.hertz_inner.harris_delta_star() - 0.5712).abs() < 5e-4);
    assert!((b.hertz_outer.harris_delta_star() - 0.6552).abs() < 5e-4);
    // Weak dependence on α (docs/model.md#c5).
    for (deg, ki, ko) in [(33.0, 3.611e10, 3.406e10), (36.0, 3.614e10, 3.403e10)] {
        let i = contact(&b, Race::Inner, deg, HertzSolution::Exact);
        let o = contact(&b, Race::Outer, deg, HertzSolution::Exact);
        assert!(rel(i.stiffness, ki) < 1e-3 && rel(o.stiffness, ko) < 1e-3);
    }
}

#[test]
fn table1_hamrock_brewe() {
    let b = Bearing::load("niu2014-table1").unwrap();
    let i = contact(&b, Race::Inner, 30.0, HertzSolution::HamrockBrewe);
    let o = contact(&b, Race::Outer, 30.0, HertzSolution::HamrockBrewe);
    assert!(rel(i.stiffness, 3.693e10) < 1e-3, "{:e}", i.stiffness);
    assert!(rel(o.stiffness, 3.431e10) < 1e-3, "{:e}", o.stiffness);
    assert!((i.ellipticity - 10.93).abs() < 0.01 && (o.ellipticity - 7.48).abs() < 0.01);
}

#[test]
fn table1_semi_axes_and_peak_pressure() {
    let b = Bearing::load("niu2014-table1").unwrap();
    let (a, bb) = b.hertz_inner.semi_axes(673.0);
    assert!((a - 1.50e-3).abs() < 0.005e-3, "a_i = {a}");
    assert!((bb - 0.141e-3).abs() < 0.0005e-3, "b_i = {bb}");
    // docs/model.md#ref-hertz prints 1.51 GPa, but its own a and b give 3Q/(2πab) = 1.519 GPa at 673 N:
    // the printed value is truncated, so check p0 against the closed form of those a, b.
    let p0_from_spec_axes = 3.0 * 673.0 / (2.0 * std::f64::consts::PI * 1.50e-3 * 0.141e-3);
    assert!(rel(b.hertz_inner.peak_pressure(673.0), p0_from_spec_axes) < 0.005);
    assert!((b.hertz_inner.peak_pressure(673.0) - 1.51e9).abs() < 0.01e9);
    let (a, bb) = b.hertz_outer.semi_axes(721.0);
    assert!((a - 1.34e-3).abs() < 0.005e-3, "a_o = {a}");
    assert!((bb - 0.180e-3).abs() < 0.0005e-3, "b_o = {bb}");
    assert!((b.hertz_outer.peak_pressure(721.0) - 1.43e9).abs() < 0.005e9);
    // Q = K δ^{3/2} is consistent with the deflection helper.
    let q = 500.0;
    let d = b.hertz_outer.deflection(q);
    assert!(rel(b.hertz_outer.stiffness * d.powf(1.5), q) < 1e-12);
}
