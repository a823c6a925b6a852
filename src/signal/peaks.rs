//! Peak picking on a [`Spectrum`]: sub-bin refinement, expected frequencies, harmonics,
//! sidebands and a prominence test.
//!
//! **Refinement.** For a peak at bin `k` the ratio of the larger neighbour to the peak bin is
//! matched to the window's own kernel, `G(1 − δ) / G(δ)` (see [`Window::gain_at_offset`]), by
//! bisection for the offset `δ ∈ [0, ½]` bins. For an isolated sinusoid this is exact up to
//! `O(1/N)` for every window (unlike plain parabolic interpolation, which is biased by up to
//! ~0.1 bin for Hann). The peak height is then divided by `G(δ)`, which undoes the window's
//! scalloping loss, so an off-bin sinusoid of amplitude `A` is reported with amplitude `A`.
//!
//! **Prominence.** The ratio of the peak bin to the median of the bins within
//! ±[`PROMINENCE_HALF_WIDTH`] bins, excluding the peak's own main lobe. It is an amplitude ratio
//! for both spectrum kinds (for a PSD, the square root of the power ratio), so `20·log10` of it
//! is the peak's height above the local floor in dB. A value of about 3 or more (≈ 10 dB) says a
//! peak is really there; a value near 1 says the "peak" is noise.

use super::spectrum::{Spectrum, SpectrumKind};
use super::window::Window;

/// Half-width in bins of the neighbourhood whose median is the reference of the prominence.
pub const PROMINENCE_HALF_WIDTH: usize = 25;

/// A spectral peak.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// Index of the largest bin.
    pub bin: usize,
    /// Refined (sub-bin) frequency in Hz.
    pub freq: f64,
    /// Refined peak height in the spectrum's units (scalloping loss undone).
    pub value: f64,
    /// Amplitude of the sinusoid that would give this peak, in signal units. Equal to `value`
    /// for an amplitude spectrum; `sqrt(2 · value · ENBW · Δf)` for a PSD.
    pub amplitude: f64,
    /// Peak bin over the local median, as an amplitude ratio (see the module docs); NaN if the
    /// spectrum is too short to have a neighbourhood, infinite if the neighbourhood is all zero.
    pub prominence: f64,
}

impl Peak {
    /// True if the prominence is at least `min_ratio` (e.g. 3.0 ≈ 10 dB above the floor).
    pub fn is_significant(&self, min_ratio: f64) -> bool {
        self.prominence >= min_ratio
    }

    /// Relative error `(freq − expected) / expected` of the refined frequency.
    pub fn rel_error(&self, expected: f64) -> f64 {
        (self.freq - expected) / expected
    }
}

/// A sideband found next to a peak.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sideband {
    /// Order `k` (negative below the centre): the sideband is expected at `centre + k·spacing`.
    pub order: i32,
    /// Expected frequency in Hz.
    pub expected_hz: f64,
    /// Largest bin near the expected frequency, if that lies inside the spectrum.
    pub peak: Option<Peak>,
}

/// Bin values as amplitudes (square root of a PSD).
fn amp(s: &Spectrum, k: usize) -> f64 {
    match s.kind {
        SpectrumKind::Amplitude => s.value[k],
        SpectrumKind::PowerDensity => s.value[k].max(0.0).sqrt(),
    }
}

/// Sub-bin offset `δ ∈ [0, ½]` towards the larger neighbour, from the neighbour/peak ratio `r`.
fn offset_from_ratio(window: Window, r: f64) -> f64 {
    let ratio = |d: f64| window.gain_at_offset(1.0 - d) / window.gain_at_offset(d);
    let r = r.clamp(0.0, 1.0);
    if r <= ratio(0.0) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0_f64, 0.5_f64);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if ratio(mid) < r {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Median of `v` (the mean of the two middle values for an even count); `None` when empty.
pub fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// Prominence of bin `bin`: its amplitude over the median amplitude of the bins within
/// ±`half_width` bins, excluding the main lobe (±[`Window::main_lobe_half_width`] bins).
/// NaN if `bin` is out of range or no reference bin is left.
pub fn prominence(s: &Spectrum, bin: usize, half_width: usize) -> f64 {
    if bin >= s.len() {
        return f64::NAN;
    }
    let lobe = s.window.main_lobe_half_width();
    let lo = bin.saturating_sub(half_width).max(1);
    let hi = (bin + half_width).min(s.len() - 1);
    let reference: Vec<f64> = (lo..=hi)
        .filter(|j| j.abs_diff(bin) > lobe)
        .map(|j| amp(s, j))
        .collect();
    match median(reference) {
        None => f64::NAN,
        Some(m) if m > 0.0 => amp(s, bin) / m,
        Some(_) => {
            if amp(s, bin) > 0.0 {
                f64::INFINITY
            } else {
                f64::NAN
            }
        }
    }
}

/// The peak at bin `bin`, refined to sub-bin frequency and corrected height (see the module
/// docs). Bins at either end of the spectrum are not refined. None if `bin` is out of range.
pub fn refine(s: &Spectrum, bin: usize) -> Option<Peak> {
    if bin >= s.len() {
        return None;
    }
    let df = s.resolution();
    let a0 = amp(s, bin);
    let mut delta = 0.0;
    if bin > 0 && bin + 1 < s.len() && a0 > 0.0 {
        let (left, right) = (amp(s, bin - 1), amp(s, bin + 1));
        let (side, r) = if right >= left {
            (1.0, right / a0)
        } else {
            (-1.0, left / a0)
        };
        delta = side * offset_from_ratio(s.window, r);
    }
    let gain = s.window.gain_at_offset(delta);
    let corrected_amp = if gain > 0.0 { a0 / gain } else { a0 };
    let (value, amplitude) = match s.kind {
        SpectrumKind::Amplitude => (corrected_amp, corrected_amp),
        SpectrumKind::PowerDensity => {
            let v = corrected_amp * corrected_amp;
            let enbw = s.window.enbw_bins(s.segment_len);
            (v, (2.0 * v * enbw * df).sqrt())
        }
    };
    Some(Peak {
        bin,
        freq: (bin as f64 + delta) * df,
        value,
        amplitude,
        prominence: prominence(s, bin, PROMINENCE_HALF_WIDTH),
    })
}

/// True if bin `k` is not smaller than its neighbours (a peak, not the shoulder of one).
fn is_local_max(s: &Spectrum, k: usize) -> bool {
    let v = s.value[k];
    (k == 0 || s.value[k - 1] <= v) && (k + 1 >= s.len() || s.value[k + 1] <= v)
}

/// Index of the largest local maximum among bins `k_lo..=k_hi` (clamped to the spectrum, DC
/// excluded). Bins on the flank of a larger peak outside the range are not local maxima, so a
/// search next to a strong line does not return that line's shoulder.
fn argmax(s: &Spectrum, k_lo: usize, k_hi: usize) -> Option<usize> {
    let k_lo = k_lo.max(1);
    let k_hi = k_hi.min(s.len().checked_sub(1)?);
    (k_lo..=k_hi)
        .filter(|&k| is_local_max(s, k))
        .max_by(|a, b| s.value[*a].total_cmp(&s.value[*b]))
}

/// The largest peak (local maximum) within `f_expected ± tol_hz` (the window is widened to at
/// least ±1 bin), refined. DC is never returned. None if the window holds no local maximum
/// (e.g. only the flank of a stronger line next to it), lies outside the spectrum, or the
/// inputs are not finite and positive.
pub fn peak_near(s: &Spectrum, f_expected: f64, tol_hz: f64) -> Option<Peak> {
    if s.is_empty() || !(f_expected.is_finite() && f_expected > 0.0 && tol_hz.is_finite()) {
        return None;
    }
    let df = s.resolution();
    let tol = tol_hz.abs().max(df);
    let lo = f_expected - tol;
    let hi = f_expected + tol;
    if hi < df || lo > s.freq[s.len() - 1] {
        return None;
    }
    let k_lo = (lo.max(0.0) / df).ceil() as usize;
    let k_hi = (hi / df).floor() as usize;
    refine(s, argmax(s, k_lo, k_hi)?)
}

/// The largest peak (local maximum) with `lo ≤ f ≤ hi` Hz, DC excluded, refined. None if the
/// band holds no local maximum.
pub fn dominant_peak(s: &Spectrum, lo: f64, hi: f64) -> Option<Peak> {
    if s.is_empty() || lo.is_nan() || hi.is_nan() || hi < lo {
        return None;
    }
    let df = s.resolution();
    let k_lo = (lo.max(0.0) / df).ceil() as usize;
    let k_hi = (hi.min(s.freq[s.len() - 1]) / df).floor();
    if k_hi < 0.0 || (k_hi as usize) < k_lo {
        return None;
    }
    refine(s, argmax(s, k_lo, k_hi as usize)?)
}

/// Harmonics `1·f0 … n·f0`: element `k − 1` is the largest peak within `k·f0 ± k·tol_hz` (the
/// tolerance grows with the order because an error in `f0` does), or None outside the spectrum.
pub fn harmonics(s: &Spectrum, f0: f64, n: usize, tol_hz: f64) -> Vec<Option<Peak>> {
    (1..=n)
        .map(|k| peak_near(s, k as f64 * f0, k as f64 * tol_hz))
        .collect()
}

/// Sidebands at `centre ± k·spacing`, `k = 1..=orders`, ordered `−orders … −1, 1 … orders`; each
/// is the largest peak within `tol_hz` of its expected frequency (None if that is ≤ 0 or beyond
/// the spectrum).
pub fn sidebands(
    s: &Spectrum,
    centre_hz: f64,
    spacing_hz: f64,
    orders: usize,
    tol_hz: f64,
) -> Vec<Sideband> {
    let k_max = orders.min(i32::MAX as usize) as i32;
    (-k_max..=k_max)
        .filter(|k| *k != 0)
        .map(|order| {
            let expected_hz = centre_hz + order as f64 * spacing_hz;
            Sideband {
                order,
                expected_hz,
                peak: peak_near(s, expected_hz, tol_hz),
            }
        })
        .collect()
}

/// The `n` largest local maxima (each the largest bin within its window's main-lobe half-width),
/// refined and sorted by decreasing height. DC and the bins inside its main lobe (`k ≤`
/// [`Window::main_lobe_half_width`], which hold leakage of the removed mean) are skipped.
pub fn top_peaks(s: &Spectrum, n: usize) -> Vec<Peak> {
    let len = s.len();
    let lobe = s.window.main_lobe_half_width();
    let mut maxima: Vec<usize> = (lobe + 1..len)
        .filter(|&k| {
            let v = s.value[k];
            v > 0.0
                && (k.saturating_sub(lobe).max(1)..=(k + lobe).min(len - 1)).all(|j| {
                    // Strictly larger than earlier bins, not smaller than later ones: a plateau
                    // yields one maximum.
                    (j < k && s.value[j] < v) || (j >= k && s.value[j] <= v)
                })
        })
        .collect();
    maxima.sort_by(|a, b| s.value[*b].total_cmp(&s.value[*a]));
    maxima
        .into_iter()
        .take(n)
        .filter_map(|k| refine(s, k))
        .collect()
}
