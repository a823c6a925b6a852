//! What four lanes can gain on the ball levels' per-ball contact stage (issue 24, item 1;
//! docs/research/vector-rhs.md#soa-bound): the normal stage of one intact ball–race contact
//! (the ball's place in the groove, the approach and its rate, the Hertz force with damping, the
//! contact frame and the slip field that the strip traction takes), timed three ways on the same
//! inputs, all compiled for AVX2 as the models' RHS is:
//!
//! - `scalar`: the library's [`groove_pos`] and [`evaluate_normal_at`] per contact, as the
//!   models call them;
//! - `soa`: the same operations in the same order over a structure of arrays (one array per
//!   field, one loop over the contacts of a ring, no branches), the best case of a
//!   structure-of-arrays rewrite: the compiler runs it four contacts per vector;
//! - `soa+gather`: `soa` with the ball kinematics gathered from the per-ball structures into the
//!   arrays first and the results scattered back into the per-contact ones, as a rewrite that
//!   keeps the models' state layout would have to.
//!
//! The `soa` results are checked bit for bit against `scalar` before timing. Inputs: the
//! default bearing's z balls on both grooves at an overlap of 2–7 µm, orbiting at the cage speed
//! of 9900 rpm with a spin, both rings slightly displaced and tilted (every contact loaded, so
//! the scalar code takes its full path as in a loaded RHS). Each figure is the fastest of 200
//! batches of about 2 ms (the host is shared).
//!
//! `cargo run --release -p raceway-studies --bin soa_contact`

use raceway::models::internals::{
    evaluate_normal_at, groove_pos, race_const, with_avx2, BallKin, ContactOut, Law, RaceConst,
    RingPose, SlipField,
};
use raceway::{Bearing, Race, DEFAULT_PRESET};
use std::hint::black_box;
use std::time::Instant;

type V3 = [f64; 3];

/// One contact as the models hold it: the contact, and the slip field and frame of a loaded one.
type Contact = (ContactOut, Option<(SlipField, [V3; 3])>);

/// One ring's contacts as a structure of arrays: inputs (ball kinematics) and outputs.
#[derive(Clone, Default)]
struct Soa {
    p: [Vec<f64>; 3],
    v: [Vec<f64>; 3],
    w: [Vec<f64>; 3],
    delta: Vec<f64>,
    q: Vec<f64>,
    f: [Vec<f64>; 3],
    qn: [Vec<f64>; 3],
    qn_ring: [Vec<f64>; 3],
    n: [Vec<f64>; 3],
    c1: [Vec<f64>; 3],
    c2: [Vec<f64>; 3],
    /// a, z0, a1, a2, b1, b2, s of the slip field.
    sf: [Vec<f64>; 7],
}

impl Soa {
    /// Arrays for `m` contacts, padded to a multiple of 4.
    fn new(m: usize) -> Self {
        let m = m.div_ceil(4) * 4;
        let v3 = || [vec![0.0; m], vec![0.0; m], vec![0.0; m]];
        Self {
            p: v3(),
            v: v3(),
            w: v3(),
            delta: vec![0.0; m],
            q: vec![0.0; m],
            f: v3(),
            qn: v3(),
            qn_ring: v3(),
            n: v3(),
            c1: v3(),
            c2: v3(),
            sf: std::array::from_fn(|_| vec![0.0; m]),
        }
    }

    /// The balls' kinematics into the input arrays (the padding repeats the first ball).
    fn gather(&mut self, balls: &[BallKin]) {
        let pad = self.p[0].len();
        for (i, b) in balls
            .iter()
            .chain(std::iter::repeat_n(&balls[0], pad - balls.len()))
            .enumerate()
        {
            for k in 0..3 {
                self.p[k][i] = b.p[k];
                self.v[k][i] = b.v[k];
                self.w[k][i] = b.omega[k];
            }
        }
    }

    /// The results into per-contact structures, as the models use them.
    fn scatter(&self, out: &mut [Contact]) {
        for (i, (c, l)) in out.iter_mut().enumerate() {
            let at = |a: &[Vec<f64>; 3]| [a[0][i], a[1][i], a[2][i]];
            c.delta = self.delta[i];
            c.q = self.q[i];
            c.q_raw = self.q[i];
            c.f = at(&self.f);
            c.qn = at(&self.qn);
            c.qn_ring = at(&self.qn_ring);
            let s = |k: usize| self.sf[k][i];
            *l = Some((
                SlipField {
                    q: self.q[i],
                    a: s(0),
                    rs: 0.0,
                    z0: s(1),
                    a1: s(2),
                    a2: s(3),
                    b1: s(4),
                    b2: s(5),
                    s: s(6),
                },
                [at(&self.n), at(&self.c1), at(&self.c2)],
            ));
        }
    }
}

/// Four lanes of f64; each operation is the scalar one lane by lane (the compiler packs them
/// into one AVX2 instruction).
#[derive(Clone, Copy)]
struct F4([f64; 4]);

macro_rules! lanes {
    ($tr:ident, $f:ident, $op:tt) => {
        impl std::ops::$tr for F4 {
            type Output = F4;
            #[inline(always)]
            fn $f(self, o: F4) -> F4 {
                let (a, b) = (self.0, o.0);
                F4([a[0] $op b[0], a[1] $op b[1], a[2] $op b[2], a[3] $op b[3]])
            }
        }
    };
}
lanes!(Add, add, +);
lanes!(Sub, sub, -);
lanes!(Mul, mul, *);
lanes!(Div, div, /);

impl F4 {
    #[inline(always)]
    fn splat(x: f64) -> F4 {
        F4([x; 4])
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> F4 {
        let a = self.0;
        F4([f(a[0]), f(a[1]), f(a[2]), f(a[3])])
    }
    #[inline(always)]
    fn load(a: &[f64], i: usize) -> F4 {
        F4([a[i], a[i + 1], a[i + 2], a[i + 3]])
    }
    #[inline(always)]
    fn store(self, a: &mut [f64], i: usize) {
        a[i..i + 4].copy_from_slice(&self.0);
    }
}

type W3 = [F4; 3];

#[inline(always)]
fn cross4(a: W3, c: W3) -> W3 {
    [
        a[1] * c[2] - a[2] * c[1],
        a[2] * c[0] - a[0] * c[2],
        a[0] * c[1] - a[1] * c[0],
    ]
}

#[inline(always)]
fn dot4(a: W3, c: W3) -> F4 {
    a[0] * c[0] + a[1] * c[1] + a[2] * c[2]
}

#[inline(always)]
fn add4(a: W3, c: W3) -> W3 {
    [a[0] + c[0], a[1] + c[1], a[2] + c[2]]
}

#[inline(always)]
fn sub4(a: W3, c: W3) -> W3 {
    [a[0] - c[0], a[1] - c[1], a[2] - c[2]]
}

#[inline(always)]
fn splat3(v: V3) -> W3 {
    [F4::splat(v[0]), F4::splat(v[1]), F4::splat(v[2])]
}

/// The normal stage of [`evaluate_normal_at`] under the closed law, intact race, no film, for
/// the first `m` contacts of `s` with one ring (its arrays padded to a multiple of 4), four
/// contacts at a time: the same IEEE operations in the same order, without branches. (One
/// square root serves δ^{1/2} and |δ|^{1/2}: √δ where δ > 0, the same bits.)
#[inline(always)]
fn soa_kernel(s: &mut Soa, m: usize, ring: &RingPose, race: &RaceConst, radius: f64, damping: f64) {
    let b = splat3(ring.beta);
    let br = splat3(ring.beta_rate);
    let to_ring = |v: W3| sub4(v, cross4(b, v));
    let to_inertial = |v: W3| add4(v, cross4(b, v));
    // RingPose::omega: the ring's x axis in inertial components times the spin, plus the tilt rates.
    let omega_r = {
        let xr = add4(splat3([1.0, 0.0, 0.0]), cross4(b, splat3([1.0, 0.0, 0.0])));
        let sp = F4::splat(ring.spin);
        add4([xr[0] * sp, xr[1] * sp, xr[2] * sp], br)
    };
    let (rp, rv) = (splat3(ring.p), splat3(ring.v));
    let (xg, rg, e) = (F4::splat(race.xg), F4::splat(race.rg), F4::splat(race.e));
    let (k, ak) = (F4::splat(race.k), F4::splat(race.a_star * race.k_cbrt));
    let (c, rs2) = (F4::splat(damping), F4::splat(race.rs * race.rs));
    let (r2, cap) = (
        F4::splat(radius * radius),
        F4::splat(0.9 * radius.min(race.rs)),
    );
    let zero = F4::splat(0.0);
    let mut i = 0;
    while i < m {
        let ld = |a: &[Vec<f64>; 3]| [F4::load(&a[0], i), F4::load(&a[1], i), F4::load(&a[2], i)];
        let (p, v, w) = (ld(&s.p), ld(&s.v), ld(&s.w));
        let rbr = sub4(p, rp);
        let rr = to_ring(rbr);
        let rho = (rr[1] * rr[1] + rr[2] * rr[2]).map(f64::sqrt);
        let (ey, ez) = (rr[1] / rho, rr[2] / rho);
        let bx = rr[0] - xg;
        let brad = rho - rg;
        let l = (bx * bx + brad * brad).map(f64::sqrt);
        let (n1, n3) = (bx / l, brad / l);
        let delta = l - e;
        let n_r = [n1, n3 * ey, n3 * ez];
        let n = to_inertial(n_r);
        let c2 = to_inertial([zero, ez.map(|x| -x), ey]);
        let gc = to_inertial([xg, rg * ey, rg * ez]);
        let v_gc = add4(rv, cross4(br, gc));
        let ddelta = dot4(n, sub4(v, v_gc));
        let sa = delta.map(|d| d.abs().sqrt());
        let sd = F4(std::array::from_fn(|l| {
            if delta.0[l] > 0.0 {
                sa.0[l]
            } else {
                0.0
            }
        }));
        let q = k * delta * sa + c * ddelta;
        let mq = q.map(|x| -x);
        delta.store(&mut s.delta, i);
        q.store(&mut s.q, i);
        for d in 0..3 {
            (n[d] * mq).store(&mut s.f[d], i);
            (n[d] * q).store(&mut s.qn[d], i);
            (n_r[d] * q).store(&mut s.qn_ring[d], i);
        }
        let c1 = cross4(c2, n);
        let a = F4(std::array::from_fn(|l| (ak.0[l] * sd.0[l]).min(cap.0[l])));
        let w0 = sub4(sub4(v, rv), cross4(omega_r, rbr));
        let dw = sub4(w, omega_r);
        a.store(&mut s.sf[0], i);
        ((r2 - a * a).map(f64::sqrt) - (rs2 - a * a).map(f64::sqrt)).store(&mut s.sf[1], i);
        dot4(c1, w0).store(&mut s.sf[2], i);
        dot4(c2, w0).store(&mut s.sf[3], i);
        dot4(dw, c2).store(&mut s.sf[4], i);
        dot4(dw, c1).store(&mut s.sf[5], i);
        dot4(dw, n).store(&mut s.sf[6], i);
        for d in 0..3 {
            n[d].store(&mut s.n[d], i);
            c1[d].store(&mut s.c1[d], i);
            c2[d].store(&mut s.c2[d], i);
        }
        i += 4;
    }
}

/// A ball centre in the ring frame's (axial, radial) plane at distances `r1` and `r2` from the
/// inner and outer groove centres `a` and `c` (the intersection nearer the outer ring's side).
fn between(a: (f64, f64), c: (f64, f64), r1: f64, r2: f64) -> (f64, f64) {
    let (dx, dr) = (c.0 - a.0, c.1 - a.1);
    let d = (dx * dx + dr * dr).sqrt();
    let along = (r1 * r1 - r2 * r2 + d * d) / (2.0 * d);
    let h = (r1 * r1 - along * along).max(0.0).sqrt();
    let (ux, ur) = (dx / d, dr / d);
    (a.0 + along * ux - h * ur, a.1 + along * ur + h * ux)
}

/// Fastest of `batches` timed batches of `reps` calls of `f`, in ns per call.
fn fastest(batches: usize, reps: usize, mut f: impl FnMut()) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..batches {
        let t = Instant::now();
        for _ in 0..reps {
            f();
        }
        best = best.min(t.elapsed().as_secs_f64() * 1e9 / reps as f64);
    }
    best
}

fn main() {
    let bearing = Bearing::load(DEFAULT_PRESET).expect("the default bearing");
    let z = bearing.z;
    let radius = 0.5 * bearing.d;
    let damping = bearing.file.contact.c_br;
    let races = [
        race_const(&bearing, Race::Inner),
        race_const(&bearing, Race::Outer),
    ];
    let rings = [
        RingPose {
            p: [2e-7, 1e-7, -1.5e-7],
            v: [1e-4, -2e-4, 3e-4],
            beta: [0.0, 1e-5, -2e-5],
            beta_rate: [0.0, 1e-3, 2e-3],
            spin: 9900.0 * std::f64::consts::PI / 30.0,
        },
        RingPose {
            p: [0.0, 5e-8, -1e-7],
            v: [0.0, 1e-4, -1e-4],
            beta: [0.0; 3],
            beta_rate: [0.0; 3],
            spin: 0.0,
        },
    ];
    // Ball centres: overlap 2–7 µm on both grooves, azimuths evenly spaced; orbit at the
    // cage's rate with a small radial velocity, and a spin.
    let cage = 0.42 * rings[0].spin;
    let balls: Vec<BallKin> = (0..z)
        .map(|j| {
            let th = 2.0 * std::f64::consts::PI * j as f64 / z as f64;
            let overlap = 2e-6 + 5e-6 * j as f64 / z as f64;
            let (x, rho) = between(
                (races[0].xg, races[0].rg),
                (races[1].xg, races[1].rg),
                races[0].e + overlap,
                races[1].e + overlap,
            );
            let p = [x, -rho * th.sin(), rho * th.cos()];
            let v = [1e-3, -cage * p[2] + 1e-3 * th.cos(), cage * p[1]];
            BallKin {
                p,
                v,
                omega: [150.0 + j as f64, 2000.0 * th.cos(), -1800.0 * th.sin()],
            }
        })
        .collect();
    let m = z;
    // Scalar reference.
    let scalar = |out: &mut Vec<Contact>| {
        for (r, (ring, race)) in rings.iter().zip(&races).enumerate() {
            for (j, kin) in balls.iter().enumerate() {
                let g = groove_pos(kin.p, ring, race);
                let slot = &mut out[r * m + j];
                slot.1 = evaluate_normal_at(
                    &g,
                    kin,
                    ring,
                    race,
                    radius,
                    damping,
                    None,
                    None,
                    Law::Closed,
                    true,
                    &mut slot.0,
                );
            }
        }
    };
    let mut out_s = vec![(ContactOut::default(), None); 2 * m];
    with_avx2(|| scalar(&mut out_s));
    let mut soa = [Soa::new(m), Soa::new(m)];
    for s in soa.iter_mut() {
        s.gather(&balls);
    }
    with_avx2(|| {
        for r in 0..2 {
            soa_kernel(&mut soa[r], m, &rings[r], &races[r], radius, damping)
        }
    });
    let mut out_v = vec![(ContactOut::default(), None); 2 * m];
    for r in 0..2 {
        soa[r].scatter(&mut out_v[r * m..(r + 1) * m]);
    }
    // Bit for bit: every field the kernel computes.
    // Every value the kernel computes, in one list per contact.
    let values = |c: &Contact| -> Vec<u64> {
        let (out, loaded) = c;
        let (sf, frame) = loaded.expect("loaded: a slip field");
        let fields = [
            out.delta, out.q, out.q_raw, sf.a, sf.z0, sf.a1, sf.a2, sf.b1, sf.b2, sf.s,
        ];
        let vectors = [out.f, out.qn, out.qn_ring, frame[0], frame[1], frame[2]];
        fields
            .iter()
            .chain(vectors.iter().flatten())
            .map(|v| v.to_bits())
            .collect()
    };
    let mut checked = 0;
    for (i, (a, b)) in out_s.iter().zip(&out_v).enumerate() {
        assert!(a.0.q > 0.0, "contact {i} is loaded");
        let left = values(a);
        assert_eq!(left, values(b), "contact {i}");
        checked += left.len();
    }
    println!(
        "{} contacts ({z} balls × 2 races), {checked} values: the structure of arrays gives the scalar code's bits",
        2 * m
    );
    // About 2 ms per batch.
    let reps = 2000;
    let t_scalar = with_avx2(|| {
        fastest(200, reps, || {
            black_box(&balls);
            scalar(black_box(&mut out_s));
        })
    }) / (2 * m) as f64;
    let t_soa = with_avx2(|| {
        fastest(200, reps, || {
            for r in 0..2 {
                let s = black_box(&mut soa[r]);
                soa_kernel(s, m, &rings[r], &races[r], radius, damping)
            }
        })
    }) / (2 * m) as f64;
    let t_gather = with_avx2(|| {
        fastest(200, reps, || {
            for r in 0..2 {
                let s = &mut soa[r];
                s.gather(black_box(&balls));
                soa_kernel(s, m, &rings[r], &races[r], radius, damping);
                s.scatter(black_box(&mut out_v[r * m..(r + 1) * m]));
            }
        })
    }) / (2 * m) as f64;
    println!("ns per contact (fastest of 200 batches of {reps} evaluations of all contacts):");
    println!("  scalar      {t_scalar:.2}");
    println!(
        "  soa         {t_soa:.2}   ({:.2}× faster than scalar)",
        t_scalar / t_soa
    );
    println!(
        "  soa+gather  {t_gather:.2}   ({:.2}× faster than scalar)",
        t_scalar / t_gather
    );
}
