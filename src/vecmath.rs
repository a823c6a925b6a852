//! Elementary functions for the right-hand sides' batches, written so that a loop of them
//! vectorises, and a run-time dispatch that compiles such a loop for AVX2 where the processor
//! has it.
//!
//! [`exp`] and [`sin_cos`] (below |x| = 10⁶) are fixed sequences of IEEE-754 additions,
//! multiplications, divisions, comparisons and bit operations, with no fused multiply–add and
//! no call: the compiler may not reorder or contract them (Rust does not contract `a * b + c`),
//! so a lane of a vector gives the same bits as the scalar call, on any processor. A result
//! therefore does not depend on whether [`with_avx2`] took the AVX2 path. Both are within one
//! unit in the last place of the C library's (their tests sweep the range).

/// 1/ln 2.
const LOG2E: f64 = std::f64::consts::LOG2_E;
/// 1.5·2⁵²: adding it rounds a number of magnitude below 2⁵¹ to the nearest integer, which
/// then sits in the low bits of the sum.
const SHIFT: f64 = 6_755_399_441_055_744.0;
/// ln 2 in two parts (fdlibm's): the high part's low 20 bits are zero, so n·LN2_HI is exact for
/// |n| < 2²⁰ and x − n·LN2_HI is exact near n ln 2.
const LN2_HI: f64 = f64::from_bits(0x3FE6_2E42_FEE0_0000); // 0.6931471803691238
const LN2_LO: f64 = f64::from_bits(0x3DEA_39EF_3579_3C76); // 1.9082149292705877e-10
/// Inputs are clamped to this range before the reduction: e^−746 rounds to 0 and e^710
/// overflows, so the clamp changes no result and keeps n within the exponent's range.
const X_MIN: f64 = -746.0;
const X_MAX: f64 = 710.0;

/// Taylor coefficients 1/k! of e^r, k = 2 … 13 (k = 0, 1 are 1).
const C: [f64; 12] = [
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
    1.0 / 40320.0,
    1.0 / 362_880.0,
    1.0 / 3_628_800.0,
    1.0 / 39_916_800.0,
    1.0 / 479_001_600.0,
    1.0 / 6_227_020_800.0,
];

/// e^x for every finite or infinite x (NaN gives NaN), within one unit in the last place of the
/// C library's `exp`.
///
/// x = n ln 2 + r with n the nearest integer to x/ln 2 and |r| ≤ ln 2 / 2; e^r by its Taylor
/// polynomial of degree 13 (truncation below 5e-18 relative); 2ⁿ applied as two factors
/// 2^⌊n/2⌋ 2^(n−⌊n/2⌋), each a normal number, so that results in the subnormal range round
/// once more but do not flush to zero.
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    // NaN fails both comparisons and passes through.
    let x = x.clamp(X_MIN, X_MAX);
    let (n, ni) = nearest(x * LOG2E);
    let r = (x - n * LN2_HI) - n * LN2_LO;
    // e^r = 1 + (r + r² P(r)), P by Estrin's scheme: independent pairs combined by r², r⁴, r⁸,
    // a chain of 4 multiply–adds instead of Horner's 12 (the loops of it are latency-bound).
    let r2 = r * r;
    let r4 = r2 * r2;
    let r8 = r4 * r4;
    let pair = |k: usize| C[k] + C[k + 1] * r;
    let a0 = pair(0) + pair(2) * r2;
    let a1 = pair(4) + pair(6) * r2;
    let a2 = pair(8) + pair(10) * r2;
    let p = 1.0 + (r + r2 * ((a0 + a1 * r4) + a2 * r8));
    let n1 = ni >> 1;
    let n2 = ni - n1;
    let two = |m: i64| f64::from_bits(((m + 1023) as u64) << 52);
    p * two(n1) * two(n2)
}

/// The integer nearest to y (|y| < 2⁵¹), as a float and as an integer: adding [`SHIFT`]
/// rounds y into the sum's low bits, which are then SHIFT's bits plus n (one unit in the last
/// place of the sum is 1).
#[inline(always)]
fn nearest(y: f64) -> (f64, i64) {
    let k = y + SHIFT;
    (
        k - SHIFT,
        (k.to_bits() as i64).wrapping_sub(SHIFT.to_bits() as i64),
    )
}

/// 2/π.
const INV_PIO2: f64 = std::f64::consts::FRAC_2_PI;
/// π/2 in three parts (fdlibm's): the first two have 33 significant bits, so n times them is
/// exact for |n| < 2²⁰; with the third, 118 bits of π/2.
const PIO2_1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000); // 1.5707963267341256
const PIO2_2: f64 = f64::from_bits(0x3DD0_B461_1A60_0000); // 6.077100506303966e-11
const PIO2_2T: f64 = f64::from_bits(0x3BA3_198A_2E03_7073); // 2.0222662487959506e-21
/// Below this |x| the reduction above is exact to 2⁻¹⁰⁰ or so; beyond it [`sin_cos`] calls the
/// C library.
const SIN_COS_LIMIT: f64 = 1e6;
/// Minimax coefficients of sin and cos on [−π/4, π/4] (fdlibm's __kernel_sin, __kernel_cos).
const S1: f64 = f64::from_bits(0xBFC5_5555_5555_5549); // -0.16666666666666632
const S2: f64 = f64::from_bits(0x3F81_1111_1110_F8A6); // 0.00833333333332249
const S3: f64 = f64::from_bits(0xBF2A_01A0_19C1_61D5); // -0.0001984126982985795
const S4: f64 = f64::from_bits(0x3EC7_1DE3_57B1_FE7D); // 2.7557313707070068e-06
const S5: f64 = f64::from_bits(0xBE5A_E5E6_8A2B_9CEB); // -2.5050760253406863e-08
const S6: f64 = f64::from_bits(0x3DE5_D93A_5ACF_D57C); // 1.58969099521155e-10
const C1: f64 = f64::from_bits(0x3FA5_5555_5555_554C); // 0.0416666666666666
const C2: f64 = f64::from_bits(0xBF56_C16C_16C1_5177); // -0.001388888888887411
const C3: f64 = f64::from_bits(0x3EFA_01A0_19CB_1590); // 2.480158728947673e-05
const C4: f64 = f64::from_bits(0xBE92_7E4F_809C_52AD); // -2.7557314351390663e-07
const C5: f64 = f64::from_bits(0x3E21_EE9E_BDB4_B1C4); // 2.087572321298175e-09
const C6: f64 = f64::from_bits(0xBDA8_FAE9_BE88_38D4); // -1.1359647557788195e-11

/// (sin x, cos x), each within one unit in the last place of the C library's, for |x| < 10⁶
/// by plain IEEE operations (so that a loop of it vectorises, [`sin_cos_into`]) and by the C
/// library beyond.
///
/// x = n π/2 + (y0 + y1) with n the nearest integer to 2x/π and the remainder as a sum of two
/// doubles (Cody–Waite with π/2 in three parts, as fdlibm's medium range); sin and cos of the
/// remainder by fdlibm's kernels on [−π/4, π/4]; the quadrant n mod 4 picks and signs them.
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if x.is_nan() || x.abs() >= SIN_COS_LIMIT {
        return x.sin_cos();
    }
    sin_cos_reduced(x)
}

/// [`sin_cos`] for |x| < 10⁶, without the branch to the C library.
#[inline(always)]
fn sin_cos_reduced(x: f64) -> (f64, f64) {
    let (n, ni) = nearest(x * INV_PIO2);
    // x − n π/2 as y0 + y1: the first two products are exact, the error of the subtraction is
    // recovered and the third part added to it.
    let t = x - n * PIO2_1;
    let w = n * PIO2_2;
    let r = t - w;
    let w = n * PIO2_2T - ((t - r) - w);
    let y0 = r - w;
    let y1 = (r - y0) - w;
    // Kernels (fdlibm) on the remainder y0 + y1.
    let z = y0 * y0;
    let zz = z * z;
    let rs = S2 + z * (S3 + z * S4) + z * zz * (S5 + z * S6);
    let v = z * y0;
    let sn = y0 - ((z * (0.5 * y1 - v * rs) - y1) - v * S1);
    let rc = z * (C1 + z * (C2 + z * C3)) + zz * zz * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let wc = 1.0 - hz;
    let cs = wc + (((1.0 - wc) - hz) + (z * rc - y0 * y1));
    let q = ni & 3;
    let (s, c) = if q & 1 == 0 { (sn, cs) } else { (cs, sn) };
    let s = if q & 2 == 0 { s } else { -s };
    let c = if (q + 1) & 2 == 0 { c } else { -c };
    (s, c)
}

/// [`sin_cos`] of every element of `x` into `sin` and `cos` (the first `x.len()` of each), four
/// at a time where the processor has AVX2, with the same bits as the scalar call.
///
/// # Panics
/// When `sin` or `cos` is shorter than `x`.
#[inline(always)]
pub fn sin_cos_into(x: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    let (sin, cos) = (&mut sin[..x.len()], &mut cos[..x.len()]);
    if x.iter().all(|v| v.abs() < SIN_COS_LIMIT) {
        with_avx2(
            #[inline(always)]
            || {
                for ((x, s), c) in x.iter().zip(sin.iter_mut()).zip(cos.iter_mut()) {
                    (*s, *c) = sin_cos_reduced(*x);
                }
            },
        )
    } else {
        for ((x, s), c) in x.iter().zip(sin.iter_mut()).zip(cos.iter_mut()) {
            (*s, *c) = sin_cos(*x);
        }
    }
}

/// Whether this processor runs the AVX2 versions (detected once by the standard library).
#[inline]
fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// `*v = f(*v)` for every element, compiled for AVX2 where the processor has it (four lanes)
/// and for the baseline instruction set elsewhere. `f` must be a sequence of plain IEEE
/// operations (as [`exp`] is) for the two to give the same bits; it is inlined into the loop.
#[inline(always)]
pub fn map_in_place(v: &mut [f64], f: impl Fn(f64) -> f64) {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        // SAFETY: the processor has AVX2 (checked just above), the only requirement of
        // `map_avx2`'s target feature.
        unsafe { map_avx2(v, f) };
        return;
    }
    v.iter_mut().for_each(|x| *x = f(*x));
}

/// [`map_in_place`]'s loop compiled with AVX2 enabled. (Written as [`with_avx2`] of the loop,
/// the compiler does not inline `f` into it: the full level's RHS then cost 1.4× as much,
/// `scripts/compare_rhs.sh`.)
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn map_avx2(v: &mut [f64], f: impl Fn(f64) -> f64) {
    v.iter_mut().for_each(|x| *x = f(*x));
}

/// Runs `f`, compiled for AVX2 where the processor has it: the code inlined into `f` (what is
/// `#[inline(always)]`) may then use four-lane vectors and the three-operand encodings. The
/// same IEEE operations give the same bits either way (no contraction into fused
/// multiply–adds, which AVX2 does not enable).
#[inline(always)]
pub fn with_avx2<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        // SAFETY: the processor has AVX2 (checked just above), the only requirement of
        // `run_avx2`'s target feature.
        return unsafe { run_avx2(f) };
    }
    f()
}

/// [`with_avx2`]'s call compiled with AVX2 enabled.
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn run_avx2<R>(f: impl FnOnce() -> R) -> R {
    f()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Distance in units in the last place between two finite numbers of the same sign.
    fn ulps(a: f64, b: f64) -> u64 {
        (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs()
    }

    /// Against the C library's exp (correctly rounded in all but rare cases): within 1 ulp over
    /// a dense sweep of the normal range, and the edges.
    #[test]
    fn exp_matches_libm() {
        let mut worst = (0u64, 0.0);
        let n = 2_000_000;
        for i in 0..=n {
            let x = -708.0 + 1417.0 * i as f64 / n as f64;
            let d = ulps(exp(x), x.exp());
            if d > worst.0 {
                worst = (d, x);
            }
        }
        // Small arguments, where the reduction is trivial and the polynomial is all.
        for i in 0..=n {
            let x = -1.0 + 2.0 * i as f64 / n as f64;
            let d = ulps(exp(x), x.exp());
            if d > worst.0 {
                worst = (d, x);
            }
        }
        assert!(worst.0 <= 1, "{} ulp at x = {}", worst.0, worst.1);
        assert_eq!(exp(0.0), 1.0);
        assert_eq!(exp(-0.0), 1.0);
        assert_eq!(exp(f64::NEG_INFINITY), 0.0);
        assert_eq!(exp(-746.0), 0.0);
        assert_eq!(exp(-1e300), 0.0);
        assert_eq!(exp(f64::INFINITY), f64::INFINITY);
        assert_eq!(exp(709.8), f64::INFINITY);
        assert!(exp(f64::NAN).is_nan());
        // Subnormal results: relative error of a subnormal is its ulp over its size.
        for x in [-709.0, -720.0, -740.0, -745.0] {
            let (a, b) = (exp(x), x.exp());
            assert!(ulps(a, b) <= 1, "x = {x}: {a:e} against {b:e}");
        }
        // The largest finite result.
        let x = 709.78;
        assert!(ulps(exp(x), x.exp()) <= 2);
    }

    /// Against the C library's sin and cos: within 1 ulp (or 1e-16 absolute near a zero)
    /// over a dense sweep of (−10⁶, 10⁶) and of (−4, 4), and the C library's own beyond.
    #[test]
    fn sin_cos_matches_libm() {
        let mut worst = (0u64, 0.0);
        let mut check = |x: f64| {
            let (s, c) = sin_cos(x);
            let (ls, lc) = x.sin_cos();
            for (a, b) in [(s, ls), (c, lc)] {
                if (a - b).abs() > 1e-16 || a.signum() != b.signum() {
                    let d = ulps(a, b);
                    if d > worst.0 {
                        worst = (d, x);
                    }
                }
            }
        };
        let n = 1_000_000;
        for i in 0..=n {
            check(-4.0 + 8.0 * i as f64 / n as f64);
            check(-999_999.0 + 1_999_998.0 * i as f64 / n as f64);
        }
        // Near multiples of π/2, where the remainder cancels.
        for k in 1..2000 {
            let x = k as f64 * std::f64::consts::FRAC_PI_2;
            for d in [-2, -1, 0, 1, 2] {
                check(f64::from_bits((x.to_bits() as i64 + d) as u64));
            }
        }
        assert!(worst.0 <= 1, "{} ulp at x = {}", worst.0, worst.1);
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        for x in [1e6, -3e7, 1e300, f64::INFINITY, f64::NAN] {
            let (a, b) = (sin_cos(x), x.sin_cos());
            assert_eq!(
                (a.0.to_bits(), a.1.to_bits()),
                (b.0.to_bits(), b.1.to_bits())
            );
        }
    }

    /// The vector loop gives the scalar function's bits, inside and beyond the direct range.
    #[test]
    fn sin_cos_into_is_the_scalar_function() {
        for top in [1e5, 2e6] {
            let xs: Vec<f64> = (0..1003)
                .map(|i| -top + 2.0 * top * i as f64 / 1003.0)
                .collect();
            let (mut s, mut c) = (vec![0.0; 1010], vec![0.0; 1010]);
            sin_cos_into(&xs, &mut s, &mut c);
            for (i, x) in xs.iter().enumerate() {
                let (a, b) = sin_cos(*x);
                assert_eq!(
                    (a.to_bits(), b.to_bits()),
                    (s[i].to_bits(), c[i].to_bits()),
                    "x = {x}"
                );
            }
        }
    }

    /// The vector loop gives the scalar function's bits.
    #[test]
    fn map_is_the_scalar_function() {
        let xs: Vec<f64> = (0..1003).map(|i| -700.0 + 1.3961 * i as f64).collect();
        let mut v = xs.clone();
        map_in_place(&mut v, exp);
        for (x, y) in xs.iter().zip(&v) {
            assert_eq!(exp(*x).to_bits(), y.to_bits(), "x = {x}");
        }
    }
}
