//! Envelope analysis: FFT band-pass, analytic signal (Hilbert transform by FFT), envelope and
//! envelope spectrum.
//!
//! The band-pass and the Hilbert transform share one forward and one inverse FFT: the spectrum
//! of the signal is multiplied by `2` on the positive-frequency bins inside the band, `1` at DC
//! and Nyquist (if inside the band) and `0` elsewhere. The inverse transform is the analytic
//! signal of the band-passed signal; its real part is the band-passed signal and its modulus the
//! envelope. The filter is a brick wall (no transition band), and like every FFT method it
//! treats the record as periodic, so the first and last few periods of the lowest band
//! frequency may show wrap-around effects.

use super::spectrum::{amplitude_spectrum_with, Spectrum};
use super::window::Window;
use super::{check_input, mean, SignalError, MIN_SAMPLES};
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;

/// Validates a pass band `[lo, hi]` Hz for sampling rate `fs` and `n` samples; returns the
/// inclusive bin range it covers (with `hi` clamped to Nyquist).
fn band_bins(band: (f64, f64), fs: f64, n: usize) -> Result<(usize, usize), SignalError> {
    let (lo, hi) = band;
    let nyquist = fs / 2.0;
    if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi > lo) {
        return Err(SignalError::InvalidParameter(format!(
            "band must satisfy 0 <= LO < HI (finite), got [{lo}, {hi}] Hz"
        )));
    }
    if lo >= nyquist {
        return Err(SignalError::InvalidParameter(format!(
            "band lower edge {lo} Hz is at or above the Nyquist frequency {nyquist} Hz"
        )));
    }
    let df = fs / n as f64;
    let k_lo = (lo / df).ceil() as usize;
    let k_hi = ((hi.min(nyquist) / df).floor() as usize).min(n / 2);
    if k_lo > k_hi {
        return Err(SignalError::InvalidParameter(format!(
            "band [{lo}, {hi}] Hz contains no frequency bin (resolution {df} Hz); widen it or \
             use a longer record"
        )));
    }
    Ok((k_lo, k_hi))
}

/// Analytic signal of `x`, optionally band-passed to `band` Hz first, with a given planner.
fn analytic_with(
    planner: &mut FftPlanner<f64>,
    x: &[f64],
    fs: f64,
    band: Option<(f64, f64)>,
) -> Result<Vec<Complex64>, SignalError> {
    check_input(x, fs, MIN_SAMPLES)?;
    let n = x.len();
    let (k_lo, k_hi) = match band {
        Some(b) => band_bins(b, fs, n)?,
        None => (0, n / 2),
    };
    let mut buf: Vec<Complex64> = x.iter().map(|v| Complex64::new(*v, 0.0)).collect();
    planner.plan_fft_forward(n).process(&mut buf);
    let half = n / 2;
    for (k, b) in buf.iter_mut().enumerate() {
        let single = k == 0 || (n.is_multiple_of(2) && k == half);
        let gain = if k > half || k < k_lo || k > k_hi {
            0.0
        } else if single {
            1.0
        } else {
            2.0
        };
        *b *= gain / n as f64;
    }
    planner.plan_fft_inverse(n).process(&mut buf);
    Ok(buf)
}

/// Analytic signal `x + i·H{x}` of `x` by the FFT Hilbert transform (the record is treated as
/// periodic). Errors: fewer than [`MIN_SAMPLES`] samples or non-finite samples.
pub fn analytic_signal(x: &[f64]) -> Result<Vec<Complex64>, SignalError> {
    let mut planner = FftPlanner::new();
    analytic_with(&mut planner, x, 1.0, None)
}

/// Brick-wall FFT band-pass of `x` (sampled at `fs` Hz) keeping `lo ≤ f ≤ hi` (`hi` is clamped
/// to Nyquist; DC is kept only if `lo = 0`).
/// Errors: bad band (`lo < 0`, `hi ≤ lo`, `lo ≥ fs/2`, no bin inside), or bad input.
pub fn bandpass(x: &[f64], fs: f64, lo: f64, hi: f64) -> Result<Vec<f64>, SignalError> {
    let mut planner = FftPlanner::new();
    Ok(analytic_with(&mut planner, x, fs, Some((lo, hi)))?
        .iter()
        .map(|z| z.re)
        .collect())
}

/// Envelope `|x_a(t)|` of `x` after removing its mean and, if `band` is given, band-passing it
/// to `[lo, hi]` Hz. The mean of the envelope is kept (the modulation depth of an AM signal is
/// the envelope's oscillation amplitude divided by this mean).
pub fn envelope(x: &[f64], fs: f64, band: Option<(f64, f64)>) -> Result<Vec<f64>, SignalError> {
    let mut planner = FftPlanner::new();
    envelope_with(&mut planner, x, fs, band)
}

fn envelope_with(
    planner: &mut FftPlanner<f64>,
    x: &[f64],
    fs: f64,
    band: Option<(f64, f64)>,
) -> Result<Vec<f64>, SignalError> {
    check_input(x, fs, MIN_SAMPLES)?;
    let m = mean(x);
    let centred: Vec<f64> = x.iter().map(|v| v - m).collect();
    Ok(analytic_with(planner, &centred, fs, band)?
        .iter()
        .map(|z| z.norm())
        .collect())
}

/// Envelope spectrum: the one-sided amplitude spectrum (mean removed, `window` applied, see
/// [`super::amplitude_spectrum`]) of [`envelope`]`(x, fs, band)`. Bearing faults show up as
/// peaks at the fault frequency and its harmonics, independent of the resonance carrying them.
/// One planner serves the three FFTs (all of length `x.len()`).
pub fn envelope_spectrum(
    x: &[f64],
    fs: f64,
    band: Option<(f64, f64)>,
    window: Window,
) -> Result<Spectrum, SignalError> {
    let mut planner = FftPlanner::new();
    let env = envelope_with(&mut planner, x, fs, band)?;
    amplitude_spectrum_with(&mut planner, &env, fs, window)
}
