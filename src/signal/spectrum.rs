//! One-sided spectra: the [`Spectrum`] container and the amplitude spectrum.

use super::window::Window;
use super::{check_input, mean, SignalError, MIN_SAMPLES};
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;

/// What the values of a [`Spectrum`] mean.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpectrumKind {
    /// Amplitude spectrum in signal units: a sinusoid `A·cos(2πft)` centred on a bin gives `A`.
    Amplitude,
    /// One-sided power spectral density in units²/Hz: `Σ value · Δf` is the variance.
    PowerDensity,
}

impl SpectrumKind {
    /// `"amplitude"` or `"psd"` (used in JSON and CSV headers).
    pub fn name(self) -> &'static str {
        match self {
            SpectrumKind::Amplitude => "amplitude",
            SpectrumKind::PowerDensity => "psd",
        }
    }
}

/// A one-sided spectrum on the uniform grid `freq[k] = k · fs / segment_len`, `k = 0..`.
///
/// Besides the two data vectors it records how it was computed, which the peak finder needs to
/// refine peaks to sub-bin precision and to undo the window's scalloping loss.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectrum {
    /// Bin frequencies in Hz (uniform, starting at 0).
    pub freq: Vec<f64>,
    /// Bin values: amplitude in signal units, or PSD in units²/Hz (see `kind`).
    pub value: Vec<f64>,
    /// Meaning of `value`.
    pub kind: SpectrumKind,
    /// Window applied to each transformed block.
    pub window: Window,
    /// Length of each transformed block in samples (the whole signal, or a Welch segment).
    pub segment_len: usize,
    /// Sampling rate of the analysed signal in Hz.
    pub fs: f64,
}

impl Spectrum {
    /// Bin spacing `fs / segment_len` in Hz.
    pub fn resolution(&self) -> f64 {
        self.fs / self.segment_len as f64
    }

    /// Number of bins.
    pub fn len(&self) -> usize {
        self.value.len()
    }

    /// True if the spectrum has no bins.
    pub fn is_empty(&self) -> bool {
        self.value.is_empty()
    }

    /// Index of the bin nearest to `f` Hz, clamped to the spectrum (None if empty or `f` NaN).
    pub fn bin_of(&self, f: f64) -> Option<usize> {
        if self.is_empty() || !f.is_finite() {
            return None;
        }
        let k = (f / self.resolution()).round();
        Some(k.clamp(0.0, (self.len() - 1) as f64) as usize)
    }

    /// Drops every bin above `fmax` Hz (keeps at least bin 0).
    pub fn truncate(&mut self, fmax: f64) {
        let keep = self.freq.iter().take_while(|f| **f <= fmax).count().max(1);
        self.freq.truncate(keep);
        self.value.truncate(keep);
    }

    /// Power (variance) in the band `[lo, hi]` Hz.
    ///
    /// For a PSD this is `Σ value · Δf` over the bins in the band. For an amplitude spectrum it
    /// is `Σ (value²/2) / ENBW` (ENBW in bins), exact for well separated tones and for white
    /// noise on average (bin 0, which holds `|mean|`, is counted as `value²`).
    pub fn band_power(&self, lo: f64, hi: f64) -> f64 {
        let df = self.resolution();
        let enbw = self.window.enbw_bins(self.segment_len);
        self.freq
            .iter()
            .zip(&self.value)
            .enumerate()
            .filter(|(_, (f, _))| **f >= lo && **f <= hi)
            .map(|(k, (_, v))| match self.kind {
                SpectrumKind::PowerDensity => v * df,
                SpectrumKind::Amplitude if k == 0 => v * v,
                SpectrumKind::Amplitude => v * v / 2.0 / enbw,
            })
            .sum()
    }
}

/// One-sided amplitude spectrum of `x` sampled at `fs` Hz, with the mean removed and `window`
/// applied over the whole record.
///
/// Scaling: `value[k] = 2 |X[k]| / Σw` (`|X[k]| / Σw` at DC and at Nyquist), so a sinusoid of
/// amplitude `A` on a bin centre gives `value = A` for every window (amplitude correction by
/// the coherent gain). Off-centre tones lose up to the window's scalloping loss, which
/// [`refine`](super::refine) undoes. Resolution is `fs / x.len()`; bins run from 0 to `fs/2`.
///
/// Errors: fewer than [`MIN_SAMPLES`] samples, non-finite samples, or `fs ≤ 0`.
pub fn amplitude_spectrum(x: &[f64], fs: f64, window: Window) -> Result<Spectrum, SignalError> {
    let mut planner = FftPlanner::new();
    amplitude_spectrum_with(&mut planner, x, fs, window)
}

/// [`amplitude_spectrum`] with a caller-supplied planner (so plans are shared within a call).
pub(crate) fn amplitude_spectrum_with(
    planner: &mut FftPlanner<f64>,
    x: &[f64],
    fs: f64,
    window: Window,
) -> Result<Spectrum, SignalError> {
    check_input(x, fs, MIN_SAMPLES)?;
    let n = x.len();
    let w = window.coefficients(n);
    let sum_w: f64 = w.iter().sum();
    let m = mean(x);
    let mut buf: Vec<Complex64> = x
        .iter()
        .zip(&w)
        .map(|(v, wi)| Complex64::new((v - m) * wi, 0.0))
        .collect();
    planner.plan_fft_forward(n).process(&mut buf);
    let half = n / 2;
    let df = fs / n as f64;
    let mut freq = Vec::with_capacity(half + 1);
    let mut value = Vec::with_capacity(half + 1);
    for (k, xk) in buf.iter().take(half + 1).enumerate() {
        let single = k == 0 || (n.is_multiple_of(2) && k == half);
        let scale = if single { 1.0 } else { 2.0 };
        freq.push(k as f64 * df);
        value.push(scale * xk.norm() / sum_w);
    }
    Ok(Spectrum {
        freq,
        value,
        kind: SpectrumKind::Amplitude,
        window,
        segment_len: n,
        fs,
    })
}
