//! Strip rules of the traction quadrature over the contact ellipse's major axis (docs/model.md#strips,
//! C7 (docs/model.md#c7)): load weights, exactness of the Gauss rule for the Hertz line load 1 − s², and the
//! strip sums against closed forms and a fine reference.

use raceway::contact::TractionCurve;
use raceway::models::internals::{strip_sums, SlipField, Strips, TractionBatch};
use raceway::{TractionSection, MAX_STRIPS};

/// ∫_{−1}^{1} (3/4)(1 − s²) s^p ds.
fn moment(p: usize) -> f64 {
    if p % 2 == 1 {
        0.0
    } else {
        0.75 * (2.0 / (p as f64 + 1.0) - 2.0 / (p as f64 + 3.0))
    }
}

fn rule_sum(st: &Strips, p: usize) -> f64 {
    (0..st.n).map(|k| st.w[k] * st.s[k].powi(p as i32)).sum()
}

#[test]
fn weights_are_symmetric_and_carry_the_whole_load() {
    for n in 1..=MAX_STRIPS {
        for st in [Strips::new(n), Strips::gauss(n)] {
            assert_eq!(st.n, n);
            assert!((rule_sum(&st, 0) - 1.0).abs() < 1e-14, "n {n}: Σw");
            for k in 0..n {
                assert_eq!(st.s[n - 1 - k], -st.s[k]);
                assert_eq!(st.w[n - 1 - k], st.w[k]);
                assert!(st.w[k] > 0.0 && st.s[k].abs() < 1.0);
                if k > 0 {
                    assert!(st.s[k] > st.s[k - 1], "n {n}: nodes ordered");
                }
            }
        }
    }
}

#[test]
fn gauss_rule_is_exact_to_degree_2n_minus_1_and_not_beyond() {
    for n in 1..=16 {
        let st = Strips::gauss(n);
        for p in 0..2 * n {
            let e = rule_sum(&st, p) - moment(p);
            assert!(e.abs() < 1e-13, "n {n}, s^{p}: error {e:e}");
        }
        // Degree 2n (even) is the first the rule misses (by ∫w π_n², π_n the monic orthogonal
        // polynomial: about 4^(−n), far above round-off up to n = 16).
        let e = rule_sum(&st, 2 * n) - moment(2 * n);
        assert!(e.abs() > 1e-11, "n {n}: s^{} exact? {e:e}", 2 * n);
    }
    // n = 2: nodes ±1/√5 (zeros of P′_3 = (15 s² − 3)/2), weights ½.
    let st = Strips::gauss(2);
    assert!((st.s[1] - 0.2f64.sqrt()).abs() < 1e-15);
    assert!((st.w[0] - 0.5).abs() < 1e-15);
}

#[test]
fn equal_strips_weigh_the_hertz_line_load_of_each_strip() {
    // Strip k of n covers (−1 + 2k/n, −1 + 2(k+1)/n); its load is ∫(3/4)(1 − s²) over it.
    let n = 10;
    let st = Strips::new(n);
    for k in 0..n {
        let (lo, hi) = (
            -1.0 + 2.0 * k as f64 / n as f64,
            -1.0 + 2.0 * (k + 1) as f64 / n as f64,
        );
        let w = 0.75 * ((hi - lo) - (hi.powi(3) - lo.powi(3)) / 3.0);
        assert!((st.w[k] - w).abs() < 1e-15);
        assert!((st.s[k] - 0.5 * (lo + hi)).abs() < 1e-15);
    }
}

fn curve() -> TractionCurve {
    TractionCurve::new(&TractionSection::default()).unwrap()
}

#[test]
fn uniform_slip_gives_q_kappa_for_every_rule() {
    // No rotation of ball against race: the slip is the same at every strip, so the force is
    // −Q κ(|u|) u/|u| (docs/model.md#forces) whatever the weights, as long as they sum to 1.
    let c = curve();
    let sf = SlipField {
        q: 700.0,
        a: 1.2e-3,
        rs: 6.44e-3,
        z0: -2e-4,
        a1: 0.03,
        a2: -0.4,
        ..Default::default()
    };
    let u = sf.a1.hypot(sf.a2);
    let f = -sf.q * c.kappa(u) / u;
    for st in [Strips::new(10), Strips::gauss(6), Strips::new(3)] {
        let r = strip_sums(&c, &st, &sf);
        assert!((r[0] - f * sf.a1).abs() < 1e-12 * sf.q);
        assert!((r[1] - f * sf.a2).abs() < 1e-12 * sf.q);
    }
}

/// Reference: 2000 equal panels of 3-point Gauss–Legendre on the full integrand.
fn reference(c: &TractionCurve, sf: &SlipField) -> [f64; 5] {
    let g = 0.6f64.sqrt();
    let panels = 2000;
    let h = 2.0 / panels as f64;
    let mut r = [0.0; 5];
    for p in 0..panels {
        let mid = -1.0 + (p as f64 + 0.5) * h;
        for (x, wx) in [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)] {
            let s = mid + 0.5 * h * x;
            let (zeta, u1, u2) = sf.at(s);
            let gq = -sf.q * 0.5 * h * wx * 0.75 * (1.0 - s * s) * c.kappa_over_u(u1.hypot(u2));
            r[0] += gq * u1;
            r[1] += gq * u2;
            r[2] += sf.a * s * gq * u2;
            r[3] += zeta * gq * u1;
            r[4] += zeta * gq * u2;
        }
    }
    r
}

#[test]
fn strip_sums_converge_on_a_spinning_contact() {
    // An outer contact of the S2 run (Q ≈ 500 N): spin slip |s|·a ≈ 0.45 m/s, several times
    // the slip at the centre, so u2 changes sign twice across the ellipse (pure-rolling lines).
    let c = curve();
    let sf = SlipField {
        q: 500.0,
        a: 1.1e-3,
        rs: 6.48e-3,
        z0: -1.0e-4,
        a1: 0.02,
        a2: 0.05,
        b1: -3.0,
        b2: 40.0,
        s: -420.0,
    };
    let r = reference(&c, &sf);
    let err = |st: &Strips| {
        let x = strip_sums(&c, st, &sf);
        (x[0] - r[0]).hypot(x[1] - r[1]) / (c.kappa_max * sf.q)
    };
    let e: Vec<f64> = [4, 8, 16, 32]
        .iter()
        .map(|&n| err(&Strips::new(n)))
        .collect();
    let g: Vec<f64> = [4, 8, 16, 32]
        .iter()
        .map(|&n| err(&Strips::gauss(n)))
        .collect();
    eprintln!("equal {e:?}\ngauss {g:?}");
    // Both converge; equal strips at about second order.
    for v in [&e, &g] {
        assert!(v[3] < 0.2 * v[1] && v[3] < 1e-3, "{v:?}");
    }
    assert!(e[3] < e[2] && e[2] < e[1] && e[1] < e[0], "{e:?}");
}

#[test]
fn strip_sums_equal_the_plain_sum_over_strips() {
    // The kernel pairs mirrored strips; check it against the plain per-strip sum of docs/model.md#forces
    // (F_k = −Q w_k κ(|u_k|) u_k/|u_k|, moments ξ_k f2, ζ_k f1, ζ_k f2) for odd and even n.
    let c = curve();
    let sf = SlipField {
        q: 800.0,
        a: 0.9e-3,
        rs: 6.44e-3,
        z0: -1.5e-4,
        a1: -0.07,
        a2: 0.2,
        b1: 5.0,
        b2: -60.0,
        s: 380.0,
    };
    for n in 1..=MAX_STRIPS {
        for st in [Strips::new(n), Strips::gauss(n)] {
            let mut r = [0.0; 5];
            for k in 0..n {
                let (zeta, u1, u2) = sf.at(st.s[k]);
                let u = u1.hypot(u2);
                let g = -sf.q * st.w[k] * c.kappa(u) / u;
                r[0] += g * u1;
                r[1] += g * u2;
                r[2] += sf.a * st.s[k] * g * u2;
                r[3] += zeta * g * u1;
                r[4] += zeta * g * u2;
            }
            let x = strip_sums(&c, &st, &sf);
            let scale = [1.0, 1.0, sf.a, sf.rs, sf.rs];
            for i in 0..5 {
                let e = (x[i] - r[i]).abs() / (c.kappa_max * sf.q * scale[i]);
                assert!(e < 1e-13, "n {n}, sum {i}: {} vs {} ({e:e})", x[i], r[i]);
            }
        }
    }
}

#[test]
fn a_batch_of_contacts_gives_each_contact_its_own_strip_sums_bit_for_bit() {
    // The RHS queues every loaded contact in a TractionBatch; its sums must be exactly those
    // of strip_sums one contact at a time (the models' results may not depend on batching).
    // Contacts with slips from sticking (u → 0: the series branch of the law) to gross sliding.
    let c = curve();
    let contacts: Vec<SlipField> = (0..9)
        .map(|i| {
            let x = i as f64;
            SlipField {
                q: 50.0 + 300.0 * x,
                a: (0.3 + 0.1 * x) * 1e-3,
                rs: 6.44e-3,
                z0: -1e-5 * x,
                a1: if i == 0 { 0.0 } else { 0.02 * (x - 4.0) },
                a2: if i == 0 { 1e-9 } else { 0.5 * (x - 3.0) },
                b1: 3.0 - x,
                b2: 20.0 * (x - 5.0),
                s: 100.0 * x,
            }
        })
        .collect();
    let frame = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut batch = TractionBatch::new(contacts.len());
    for n in 1..=MAX_STRIPS {
        for st in [Strips::new(n), Strips::gauss(n)] {
            // Every other contact, queued in reverse: the slot names, not the order, identify it.
            batch.clear();
            let queued: Vec<usize> = (0..contacts.len()).rev().step_by(2).collect();
            for &k in &queued {
                batch.push(k, contacts[k], frame);
            }
            let mut seen = Vec::new();
            batch.run(&c, &st, |slot, _, sums| {
                let one = strip_sums(&c, &st, &contacts[slot]);
                for i in 0..5 {
                    assert_eq!(
                        sums[i].to_bits(),
                        one[i].to_bits(),
                        "n {n}, contact {slot}, sum {i}: {} vs {}",
                        sums[i],
                        one[i]
                    );
                }
                seen.push(slot);
            });
            assert_eq!(seen, queued, "n {n}: every queued contact once, in order");
        }
    }
}
