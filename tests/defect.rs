//! Spall model against docs/model.md#spall and #verification (independent numpy/scipy values and closed forms).

use raceway::contact::{ContactKind, Defect};
use raceway::contact::{HertzContact, HertzSolution};
use raceway::{Bearing, BearingFile, BlendLength, BlendName, DefectMode, DefectSpec, Race};
use std::f64::consts::PI;

const MM: f64 = 1e-3;
const UM: f64 = 1e-6;
/// A running load for ℓ_b = b [N].
const Q_REF: f64 = 700.0;

fn table1() -> Bearing {
    Bearing::load("niu2014-table1").unwrap()
}

fn bearing_with(edit: impl FnOnce(&mut BearingFile)) -> Bearing {
    let mut f = BearingFile::default_preset();
    edit(&mut f);
    Bearing::new(&f).unwrap()
}

/// The Table-1 bearing with the C9 blend over the semi-minor axis (`blend_length = "b"`; the
/// default is the abrupt edge, D2).
fn blended() -> Bearing {
    bearing_with(|f| f.defect.blend_length = BlendLength::Named(BlendName::SemiMinorAxis))
}

fn blended_defect(ring: Race, width: f64, depth: f64) -> Defect {
    Defect::new(&spec(ring, width, depth), &blended(), Q_REF).unwrap()
}

fn spec(ring: Race, width: f64, depth: f64) -> DefectSpec {
    DefectSpec {
        ring: ring.into(),
        width,
        depth,
        theta0: 0.0,
    }
}

fn defect(ring: Race, width: f64, depth: f64) -> Defect {
    Defect::new(&spec(ring, width, depth), &table1(), Q_REF).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

#[test]
fn half_angle_table_of_spec_4_2() {
    for (w, outer, inner) in [
        (1.0, 0.01235, 0.01695),
        (2.0, 0.02469, 0.03390),
        (3.0, 0.03704, 0.05086),
    ] {
        let o = defect(Race::Outer, w * MM, 0.2 * MM);
        let i = defect(Race::Inner, w * MM, 0.2 * MM);
        assert!(
            (o.half_angle() - outer).abs() < 5e-6,
            "outer {w} mm: {}",
            o.half_angle()
        );
        assert!(
            (i.half_angle() - inner).abs() < 5e-6,
            "inner {w} mm: {}",
            i.half_angle()
        );
        // θ_e ≈ w_d/(2 r_d2): to about 1e-4 relative for 1 mm only (docs/model.md#spall-half-angle);
        // the asin term makes it (w_d/2)²/(6 r_d1²) ≈ 3.2e-4 for 3 mm on the inner race.
        for d in [&o, &i] {
            let x = 0.5 * w * MM / d.r_d1();
            let err = rel(d.half_angle(), 0.5 * w * MM / d.r_d2());
            assert!(err < 4e-4 && (err - x * x / 6.0).abs() < 1e-6, "{err}");
        }
    }
}

#[test]
fn track_radii_of_spec_4_2() {
    let o = defect(Race::Outer, 2.0 * MM, 0.5 * MM);
    let i = defect(Race::Inner, 2.0 * MM, 0.5 * MM);
    assert!((o.r_d2() - 40.50 * MM).abs() < 0.005 * MM, "{}", o.r_d2());
    assert!((i.r_d2() - 29.50 * MM).abs() < 0.005 * MM, "{}", i.r_d2());
    // Tabulated as 46.77 / 34.07 mm; the formula gives 46.7645 / 34.0645 mm.
    assert!((o.r_d1() - 46.77 * MM).abs() < 0.01 * MM, "{}", o.r_d1());
    assert!((i.r_d1() - 34.07 * MM).abs() < 0.01 * MM, "{}", i.r_d1());
    // r_d1 = r_d2 / cos β (docs/model.md#spall-half-angle), β = α0 = 30°.
    let c = 30f64.to_radians().cos();
    assert!((o.r_d1() - o.r_d2() / c).abs() < 1e-15);
    assert!((i.r_d1() - i.r_d2() / c).abs() < 1e-15);
}

#[test]
fn along_track_coordinate_and_zone() {
    let d = defect(Race::Outer, 2.0 * MM, 0.5 * MM);
    let te = d.half_angle();
    // At the zone edge the ball sits on the corner: y_b = w_d/2.
    assert!((d.along_track(te) - 1.0 * MM).abs() < 1e-15);
    assert!((d.along_track(-te) + 1.0 * MM).abs() < 1e-15);
    assert!(rel(d.along_track(1e-3), d.r_d2() * 1e-3) < 1e-6);
    assert!(d.probe(te * (1.0 + 1e-9)).is_none());
    assert!(d.probe(-te * (1.0 + 1e-9)).is_none());
    assert!(d.probe(te + 0.011).is_none());
    assert!(d.probe(f64::NAN).is_none());
    assert!(d.probe(te * (1.0 - 1e-6)).is_some());
    assert!(d.zone_margin(0.5 * te) > 0.0 && d.zone_margin(1.5 * te) < 0.0);
    // Entry and exit: no drop at the edges (continuity with the intact groove).
    let c = d.probe(te * (1.0 - 1e-9)).unwrap();
    assert!(c.g < 1e-12 && c.theta_dd.abs() < 1e-6);
    // Rate: ẏ_b = r_d2 cos(θ r_d2/r_d1) θ̇.
    let h = 1e-7;
    let fd = (d.along_track(0.01 + h) - d.along_track(0.01 - h)) / (2.0 * h);
    assert!(rel(d.along_track_rate(0.01, 1.0), fd) < 1e-8);
}

#[test]
fn ball_to_defect_angle_outer_fixed_inner_spinning() {
    let b = table1();
    let mut s = spec(Race::Outer, 1.0 * MM, 0.2 * MM);
    s.theta0 = PI;
    let o = Defect::new(&s, &b, Q_REF).unwrap();
    assert!((o.theta_bd(PI + 0.01, 123.0) - 0.01).abs() < 1e-12);
    assert!((o.theta_bd(-PI + 0.01, 0.0) - 0.01).abs() < 1e-12, "wraps");
    s.ring = Race::Inner.into();
    s.theta0 = 0.5;
    let i = Defect::new(&s, &b, Q_REF).unwrap();
    // φ = Ω t after many revolutions.
    let phi = 2.0 * PI * 1000.0 + 0.25;
    assert!((i.theta_bd(0.8, phi) - 0.05).abs() < 1e-9);
    assert!((i.theta_bd(0.8, 0.0) - 0.3).abs() < 1e-15);
}

#[test]
fn geometric_limit_of_the_drop() {
    for (w, g) in [(2.0, 79.2), (1.0, 19.7), (3.0, 179.7)] {
        let d = defect(Race::Outer, w * MM, 0.5 * MM);
        assert!(
            (d.g_max() - g * UM).abs() < 0.05 * UM,
            "{w} mm: {}",
            d.g_max()
        );
        // The deepest point of the ball path is the centre, g = g_max (depth ≫ limit).
        assert!((d.max_drop() - d.g_max()).abs() < 1e-15);
        let c = d.contact_at(0.0).unwrap();
        assert!((c.g - d.g_max()).abs() < 1e-15);
    }
}

#[test]
fn corner_contact_angle_and_slope() {
    let d = defect(Race::Outer, 2.0 * MM, 0.5 * MM);
    let r = 0.5 * 12.7 * MM;
    let hw = 1.0 * MM;
    let mut n = 0;
    for k in -99..=99 {
        let y_b = k as f64 * 0.01 * MM + 0.3e-6; // off the nodes
        let c = d.contact_at(y_b).unwrap();
        assert_eq!(c.kind, ContactKind::Corner);
        // The nearer corner carries the ball: the trailing one (ahead) once past the centre.
        let y_c = if y_b > 0.0 { hw } else { -hw };
        assert_eq!(c.y_q, y_c);
        let theta = ((y_c - y_b) / r).asin();
        assert!((c.theta_dd - theta).abs() < 1e-12, "y_b {y_b}");
        assert!(if y_b > 0.0 {
            c.theta_dd > 0.0
        } else {
            c.theta_dd < 0.0
        });
        assert!((c.g - (r - (r * r - (y_c - y_b).powi(2)).sqrt())).abs() < 1e-15);
        // Spec eq. 17 form: θ_dd = atan2(y_q − y_b, R − g + d(y_q)).
        let t2 = (c.y_q - y_b).atan2(r - c.g + d.depth_at(c.y_q));
        assert!((c.theta_dd - t2).abs() < 1e-12);
        // dg/dy_b against a central difference of the run-time g itself.
        let h = 1e-9;
        let fd = (d.contact_at(y_b + h).unwrap().g - d.contact_at(y_b - h).unwrap().g) / (2.0 * h);
        assert!(
            (c.dg_dy - fd).abs() < 1e-6,
            "y_b {y_b}: {} vs {fd}",
            c.dg_dy
        );
        assert!((c.dg_dy + c.theta_dd.tan()).abs() < 1e-12);
        n += 1;
    }
    assert_eq!(n, 199);
    // Inner-ring spall: same geometry in the rolling plane.
    let i = defect(Race::Inner, 2.0 * MM, 0.5 * MM);
    let c = i.contact_at(0.4 * MM).unwrap();
    assert!((c.theta_dd - (0.6 * MM / r).asin()).abs() < 1e-12);
}

#[test]
fn drop_is_continuous_with_a_kink_at_the_centre() {
    let d = defect(Race::Outer, 2.0 * MM, 0.5 * MM);
    let r = 0.5 * 12.7 * MM;
    let hw = 1.0 * MM;
    let max_slope = hw / (r * r - hw * hw).sqrt();
    let n = 20_000;
    let mut prev = d.contact_at(-hw * (1.0 - 1e-12)).unwrap().g;
    for k in 1..n {
        let y = -hw + 2.0 * hw * k as f64 / n as f64;
        let g = d.contact_at(y).unwrap().g;
        let step = 2.0 * hw / n as f64;
        assert!(
            (g - prev).abs() <= max_slope * step * (1.0 + 1e-9) + 1e-18,
            "jump at {y}"
        );
        prev = g;
    }
    // Kink: left slope +max_slope, right slope −max_slope.
    let h = 1e-8;
    let g0 = d.contact_at(0.0).unwrap().g;
    let left = (g0 - d.contact_at(-h).unwrap().g) / h;
    let right = (d.contact_at(h).unwrap().g - g0) / h;
    assert!(rel(left, max_slope) < 1e-5 && rel(-right, max_slope) < 1e-5);
    assert!(d.contact_at(-h).unwrap().theta_dd < 0.0 && d.contact_at(h).unwrap().theta_dd > 0.0);
    // The table holds 2001 nodes from −w/2 to +w/2.
    let t = d.table();
    assert_eq!(t.len(), 2001);
    assert_eq!(t[0].y_b, -hw);
    assert_eq!(t[2000].y_b, hw);
    assert!(t[1000].y_b.abs() < 1e-18);
}

/// Independent brute-force rolling-ball filter on a fine grid.
fn brute_force_drop(y_b: f64, w: f64, h: f64, r: f64) -> f64 {
    let hw = 0.5 * w;
    let n = 200_000;
    let mut best = f64::INFINITY;
    for k in 0..=n {
        let y = -hw + w * k as f64 / n as f64;
        let x = y - y_b;
        if x.abs() > r {
            continue;
        }
        let s = 2.0 * y / w;
        let depth = if s.abs() < 1.0 {
            h * (1.0 - s * s)
        } else {
            0.0
        };
        best = best.min(depth + r - (r * r - x * x).sqrt());
    }
    best
}

#[test]
fn depth_has_no_effect_beyond_the_geometric_limit() {
    let reference = defect(Race::Outer, 2.0 * MM, 0.5 * MM);
    for depth in [0.1, 0.2, 1.0, 5.0] {
        let d = defect(Race::Outer, 2.0 * MM, depth * MM);
        for (a, b) in d.table().iter().zip(reference.table()) {
            assert_eq!(a.g, b.g, "depth {depth} mm at y_b {}", a.y_b);
            assert_eq!(a.kind, ContactKind::Corner);
        }
        for k in -50..50 {
            let y = k as f64 * 0.0199 * MM;
            assert_eq!(d.contact_at(y), reference.contact_at(y));
        }
    }
}

#[test]
fn exact_floor_threshold_is_slightly_above_the_geometric_limit() {
    // docs/model.md#spall-drop: the floor "can win only when h_d < R − √(R² − w²/4)" (79.2 µm for 2 mm).
    // At y_b = 0 the floor beats the corner as long as the floor slope at the corner, 4h/w, is
    // below the ball's, (w/2)/√(R² − w²/4): h_d < (w²/8)/√(R² − w²/4) = 79.7 µm.
    let r: f64 = 0.5 * 12.7 * MM;
    let hw: f64 = 1.0 * MM;
    let h_star = hw * hw / 2.0 / (r * r - hw * hw).sqrt();
    assert!((h_star - 79.735 * UM).abs() < 0.001 * UM);
    let below = defect(Race::Outer, 2.0 * MM, 0.999 * h_star);
    let above = defect(Race::Outer, 2.0 * MM, 1.001 * h_star);
    assert!(below.depth() > below.g_max());
    assert_eq!(below.contact_at(0.0).unwrap().kind, ContactKind::Floor);
    assert!(below.max_drop() < below.g_max());
    assert_eq!(above.contact_at(0.0).unwrap().kind, ContactKind::Corner);
    assert_eq!(above.max_drop(), above.g_max());
}

#[test]
fn shallow_spall_lets_the_ball_reach_the_floor() {
    let r = 0.5 * 12.7 * MM;
    let (w, h) = (2.0 * MM, 0.03 * MM); // h_d < 79.2 µm
    let d = defect(Race::Outer, w, h);
    assert!(d.max_drop() < d.g_max() && d.max_drop() <= h);
    let c = d.contact_at(0.0).unwrap();
    assert_eq!(c.kind, ContactKind::Floor);
    for y_b in [-0.9, -0.5, -0.123, 0.0, 0.3, 0.77, 0.95] {
        let y_b = y_b * MM;
        let c = d.contact_at(y_b).unwrap();
        let bf = brute_force_drop(y_b, w, h, r);
        assert!((c.g - bf).abs() < 2e-10, "y_b {y_b}: {} vs {bf}", c.g);
        // θ_dd = atan2(y_q − y_b, R − g + d(y_q)) holds for floor contacts too.
        let t2 = (c.y_q - y_b).atan2(r - c.g + d.depth_at(c.y_q));
        assert!((c.theta_dd - t2).abs() < 1e-9, "y_b {y_b}");
        // The floor is concave: K′ lies below the ball-on-flat value, above zero.
        if c.kind == ContactKind::Floor {
            assert!(c.k_unblended > 0.0 && c.k_unblended.is_finite());
        }
    }
    // Near the edges the corners still carry the ball.
    assert_eq!(d.contact_at(-0.99 * MM).unwrap().kind, ContactKind::Corner);
}

#[test]
fn edge_hertz_constant_against_spec_table() {
    for (re, k) in [
        (0.05, 5.36e9),
        (0.10, 5.81e9),
        (0.25, 6.53e9),
        (0.50, 7.20e9),
        (1.00, 7.98e9),
    ] {
        let b = bearing_with(|f| f.defect.edge_radius = re * MM);
        let d = Defect::new(&spec(Race::Outer, 2.0 * MM, 0.5 * MM), &b, Q_REF).unwrap();
        assert!(
            rel(d.k_corner(), k) < 5e-3,
            "r_e {re} mm: K′ = {:e}",
            d.k_corner()
        );
    }
    let d = defect(Race::Outer, 2.0 * MM, 0.5 * MM);
    // 0.17·K_o (docs/model.md#spall-edge-stiffness).
    assert!((d.k_corner() / table1().k_outer - 0.17).abs() < 0.005);
    // Major axis transverse (the edge is flat across the track).
    assert!(d.corner_hertz().major_along_second);
}

#[test]
fn compliance_blend_over_the_semi_minor_axis() {
    let b = table1();
    let d = blended_defect(Race::Outer, 2.0 * MM, 0.5 * MM);
    let k_g = b.k_outer;
    let k_e = d.k_corner();
    let lb = b.hertz_outer.semi_axes(Q_REF).1;
    assert!((d.blend_length() - lb).abs() < 1e-18);
    assert!(lb > 0.1 * MM && lb < 0.2 * MM, "b = {lb}"); // "about 0.15 mm"
    let hw = 1.0 * MM;
    for sign in [-1.0, 1.0] {
        // At the edge: the groove value.
        let at_edge = d.hertz_constant(sign * (hw - 1e-12), k_g);
        assert!(rel(at_edge, k_g) < 1e-6, "{at_edge:e}");
        // After ℓ_b of travel and beyond: K′.
        assert!(rel(d.hertz_constant(sign * (hw - lb), k_g), k_e) < 1e-12);
        assert!(rel(d.hertz_constant(sign * (hw - 2.0 * lb), k_g), k_e) < 1e-12);
        // Halfway: the mean compliance.
        let half = d.hertz_constant(sign * (hw - 0.5 * lb), k_g);
        let c = 0.5 * (k_g.powf(-2.0 / 3.0) + k_e.powf(-2.0 / 3.0));
        assert!(rel(half, c.powf(-1.5)) < 1e-12);
        // probe() uses the same blend with the race's groove K.
        let te = d.half_angle();
        let c = d.probe(sign * te * 0.999_999).unwrap();
        assert!(rel(c.k_edge, k_g) < 1e-3 && c.k_unblended == k_e);
    }
    // Outside the spall: the groove constant.
    assert_eq!(d.hertz_constant(1.5 * MM, k_g), k_g);
    // Abrupt option (ℓ_b = 0): K′ as soon as the ball is in.
    let b0 = bearing_with(|f| f.defect.blend_length = BlendLength::Metres(0.0));
    let d0 = Defect::new(&spec(Race::Outer, 2.0 * MM, 0.5 * MM), &b0, 0.0).unwrap();
    assert_eq!(d0.hertz_constant(hw - 1e-12, k_g), d0.k_corner());
    assert_eq!(
        d0.probe(0.999 * d0.half_angle()).unwrap().k_edge,
        d0.k_corner()
    );
}

/// At a spall edge the C9 (docs/model.md#c9) blend gives K its groove value but not its slope: inside, the blend's
/// along-track force −(2/5)δ′^{5/2} dK/dy_b acts with dK/dy_b = (3/2) c_g^{−5/2} (c_e − c_g)/ℓ_b
/// (c = K^{−2/3}); outside there is none. The models locate the edge as a state event, so the
/// frozen in-zone law (blend frozen on) must continue smoothly past the edge instead of
/// dropping to the intact law inside a step (which made DOP853 stall at rtol 1e-12 at the
/// exit edge of the reduced model, studies/stall_probe.rs).
#[test]
fn frozen_zone_law_continues_smoothly_past_the_edges() {
    let b = table1();
    let d = blended_defect(Race::Outer, 1.0 * MM, 0.2 * MM);
    let (k_g, k_e, lb) = (b.k_outer, d.k_corner(), d.blend_length());
    let (c_g, c_e) = (k_g.powf(-2.0 / 3.0), k_e.powf(-2.0 / 3.0));
    let slope = 1.5 * (c_e - c_g) / lb / c_g.powf(2.5);
    let hw = 0.5 * MM;
    let eps = 1e-12;
    for sign in [-1.0, 1.0] {
        let inside = d.contact_with_blend(sign * (hw - eps), Some(true)).unwrap();
        let past = d
            .contact_with_blend(sign * (hw + eps), Some(true))
            .expect("the frozen law continues past the edge");
        // The slope at the edge against the closed form (it points into the zone: K falls
        // toward the edge constant as the ball moves in).
        assert!(
            rel(inside.dk_dy, sign * slope) < 1e-6,
            "{:e} vs {:e}",
            inside.dk_dy,
            sign * slope
        );
        // Value and slope continue across the edge (a jump would be O(1)).
        assert!(rel(past.dk_dy, inside.dk_dy) < 1e-6, "{:e}", past.dk_dy);
        assert!(rel(past.k_edge, inside.k_edge) < 1e-6 && rel(past.k_edge, k_g) < 1e-6);
        assert!((past.g - inside.g).abs() < 1e-15 && past.g.abs() < 1e-15);
        assert!((past.theta_dd - inside.theta_dd).abs() < 1e-8);
        assert_eq!(past.kind, ContactKind::Corner);
        // Far past the edge the continuation stops at a positive compliance.
        let far = d
            .contact_with_blend(sign * (hw + 0.5 * MM), Some(true))
            .unwrap();
        assert!(far.k_edge.is_finite() && far.k_edge > 0.0 && far.dk_dy == 0.0);
        // By position (not frozen) the zone ends at the edge, as before.
        assert!(d.contact_with_blend(sign * (hw + eps), None).is_none());
        assert!(d.contact_at(sign * (hw + eps)).is_none());
    }
}

#[test]
fn point_mode_is_the_paper_literal_profile() {
    let b = bearing_with(|f| f.defect.mode = DefectMode::Point);
    let (w, h) = (2.0 * MM, 0.5 * MM);
    let d = Defect::new(&spec(Race::Outer, w, h), &b, Q_REF).unwrap();
    // |r_d| = 2.83 mm at the edge, w²/(8h) = 1.0 mm at the bottom.
    assert!((d.profile_radius(0.5 * w) - 2.83 * MM).abs() < 0.005 * MM);
    assert!((d.profile_radius(0.0) - 1.0 * MM).abs() < 1e-15);
    for y_b in [-0.95, -0.4, 0.0, 0.25, 0.7] {
        let y_b = y_b * MM;
        let c = d.contact_at(y_b).unwrap();
        assert_eq!(c.kind, ContactKind::Profile);
        let s = 2.0 * y_b / w;
        assert!((c.g - h * (1.0 - s * s)).abs() < 1e-18);
        // Profile slope: the surface rises ahead of the ball past the centre → θ_dd > 0.
        assert!((c.theta_dd - (8.0 * h * y_b / (w * w)).atan()).abs() < 1e-15);
        assert!((c.dg_dy + c.theta_dd.tan()).abs() < 1e-12);
        // K′ from the parabola's radius used as convex (eq. 20).
        let rd = d.profile_radius(y_b);
        let e = HertzContact::new(
            2.0 / b.d + 1.0 / rd,
            2.0 / b.d,
            b.e_prime,
            HertzSolution::Exact,
        );
        assert!(rel(c.k_unblended, e.stiffness) < 1e-3, "y_b {y_b}");
    }
    // The point model sees the full depth (the finite ball cannot).
    assert!((d.max_drop() - h).abs() < 1e-15);
}

#[test]
fn deflection_helpers() {
    let d = defect(Race::Outer, 2.0 * MM, 0.5 * MM);
    let c = d.contact_at(0.5 * MM).unwrap();
    let delta = 100.0 * UM;
    assert!((c.deflection(delta) - (delta - c.g) * c.theta_dd.cos()).abs() < 1e-18);
    // Running load ~7 µm overlap: the ball loses contact in the spall (docs/model.md#spall-drop).
    assert!(d.contact_at(0.0).unwrap().deflection(7.0 * UM) < 0.0);
    let rate = c.deflection_rate(0.01, 2.0);
    assert!((rate - (0.01 - c.dg_dy * 2.0) * c.theta_dd.cos()).abs() < 1e-15);
}

#[test]
fn invalid_defects_name_the_field() {
    let b = table1();
    let cases: Vec<(DefectSpec, &str)> = vec![
        (spec(Race::Outer, 0.0, 0.2 * MM), "defect.width"),
        (spec(Race::Outer, -MM, 0.2 * MM), "defect.width"),
        (spec(Race::Outer, f64::NAN, 0.2 * MM), "defect.width"),
        (spec(Race::Outer, f64::INFINITY, 0.2 * MM), "defect.width"),
        (spec(Race::Outer, 13.0 * MM, 0.2 * MM), "defect.width"), // ≥ D
        (spec(Race::Outer, 1.0 * MM, 0.0), "defect.depth"),
        (spec(Race::Outer, 1.0 * MM, f64::NAN), "defect.depth"),
        (
            DefectSpec {
                theta0: f64::INFINITY,
                ..spec(Race::Outer, 1.0 * MM, 0.2 * MM)
            },
            "defect.theta0",
        ),
    ];
    for (s, field) in cases {
        let e = Defect::new(&s, &b, Q_REF).unwrap_err();
        assert_eq!(e.field, field, "{s:?}: {e}");
        assert!(e.to_string().starts_with(field));
    }
    // ℓ_b = "b" needs a reference load.
    let e = Defect::new(&spec(Race::Outer, 1.0 * MM, 0.2 * MM), &blended(), 0.0).unwrap_err();
    assert_eq!(e.field, "defect.blend_length", "{e}");
    // Serde: unknown keys refused, theta0 defaults to 0.
    let s: DefectSpec = toml::from_str("ring = \"inner\"\nwidth = 1e-3\ndepth = 2e-4\n").unwrap();
    assert_eq!(s.ring, Race::Inner.into());
    assert_eq!(s.theta0, 0.0);
    assert!(toml::from_str::<DefectSpec>(
        "ring = \"outer\"\nwidth = 1e-3\ndepth = 2e-4\nlength = 1\n"
    )
    .is_err());
    assert!(toml::from_str::<DefectSpec>("ring = \"cage\"\nwidth = 1e-3\ndepth = 2e-4\n").is_err());
}
