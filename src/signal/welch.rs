//! Welch's averaged-periodogram power spectral density.

use super::spectrum::{Spectrum, SpectrumKind};
use super::window::Window;
use super::{check_input, mean, SignalError, MIN_SAMPLES};
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;

/// Settings of [`welch_psd`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WelchConfig {
    /// Samples per segment (sets the resolution `fs / segment_len`); at least [`MIN_SAMPLES`].
    pub segment_len: usize,
    /// Overlap of consecutive segments as a fraction of `segment_len`, in `[0, 1)`.
    pub overlap: f64,
    /// Window applied to every segment.
    pub window: Window,
}

impl Default for WelchConfig {
    /// 4096-sample Hann segments with 50 % overlap.
    fn default() -> Self {
        WelchConfig {
            segment_len: 4096,
            overlap: 0.5,
            window: Window::Hann,
        }
    }
}

/// One-sided Welch PSD of `x` (sampled at `fs` Hz) in units²/Hz.
///
/// Each segment has its own mean removed, is windowed and transformed; the periodograms
/// `|X[k]|² / (fs Σw²)` are averaged and doubled except at DC and Nyquist. With this density
/// scaling `Σ value · Δf` equals the mean segment variance (Parseval), whatever the window, and
/// a sinusoid of amplitude `A` contributes `A²/2` to the integral over its peak. Trailing
/// samples that do not fill a segment are ignored.
///
/// Errors: `segment_len` below [`MIN_SAMPLES`] or above `x.len()`, overlap outside `[0, 1)`,
/// non-finite samples, `fs ≤ 0`.
pub fn welch_psd(x: &[f64], fs: f64, config: &WelchConfig) -> Result<Spectrum, SignalError> {
    let mut planner = FftPlanner::new();
    welch_psd_with(&mut planner, x, fs, config)
}

/// [`welch_psd`] with a caller-supplied planner.
pub(crate) fn welch_psd_with(
    planner: &mut FftPlanner<f64>,
    x: &[f64],
    fs: f64,
    config: &WelchConfig,
) -> Result<Spectrum, SignalError> {
    let len = config.segment_len;
    if len < MIN_SAMPLES {
        return Err(SignalError::InvalidParameter(format!(
            "Welch segment length must be at least {MIN_SAMPLES} samples, got {len}"
        )));
    }
    if !(config.overlap >= 0.0 && config.overlap < 1.0) {
        return Err(SignalError::InvalidParameter(format!(
            "Welch overlap must be a fraction in [0, 1), got {}",
            config.overlap
        )));
    }
    check_input(x, fs, len)?;
    let step = (len - (config.overlap * len as f64).round() as usize).max(1);
    let w = config.window.coefficients(len);
    let sum_w2: f64 = w.iter().map(|v| v * v).sum();
    let fft = planner.plan_fft_forward(len);
    let mut scratch = vec![Complex64::new(0.0, 0.0); fft.get_inplace_scratch_len()];
    let mut buf = vec![Complex64::new(0.0, 0.0); len];
    let half = len / 2;
    let mut acc = vec![0.0; half + 1];
    let mut segments = 0usize;
    let mut start = 0usize;
    while start + len <= x.len() {
        let seg = &x[start..start + len];
        let m = mean(seg);
        for ((b, v), wi) in buf.iter_mut().zip(seg).zip(&w) {
            *b = Complex64::new((v - m) * wi, 0.0);
        }
        fft.process_with_scratch(&mut buf, &mut scratch);
        for (a, xk) in acc.iter_mut().zip(&buf) {
            *a += xk.norm_sqr();
        }
        segments += 1;
        start += step;
    }
    let norm = 1.0 / (fs * sum_w2 * segments as f64);
    let df = fs / len as f64;
    let freq = (0..=half).map(|k| k as f64 * df).collect();
    let value = acc
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let single = k == 0 || (len.is_multiple_of(2) && k == half);
            a * norm * if single { 1.0 } else { 2.0 }
        })
        .collect();
    Ok(Spectrum {
        freq,
        value,
        kind: SpectrumKind::PowerDensity,
        window: config.window,
        segment_len: len,
        fs,
    })
}
