//! Signal analysis of simulated (or measured) vibration signals for bearing-fault signatures.
//!
//! Everything here works on uniformly sampled real signals `x: &[f64]` with sampling rate `fs`
//! in Hz and returns one-sided spectra as a [`Spectrum`]:
//! - windows: [`Window`] (Rectangular, Hann, Hamming and 4-term Blackman–Harris), with the gains
//!   used to scale spectra so that amplitudes and powers come out in physical units;
//! - the windowed, amplitude-corrected one-sided amplitude spectrum ([`amplitude_spectrum`]): a
//!   sinusoid of amplitude `A` gives a peak of height `A`;
//! - Welch's averaged periodogram ([`welch_psd`]), a one-sided power spectral density in
//!   units²/Hz whose integral is the signal variance (Parseval);
//! - FFT band-pass ([`bandpass`]), analytic signal by the FFT Hilbert transform
//!   ([`analytic_signal`]), envelope ([`envelope()`]) and envelope spectrum
//!   ([`envelope_spectrum`]);
//! - peak picking with sub-bin refinement matched to the window shape ([`top_peaks`],
//!   [`refine`]), harmonics, sidebands and a prominence test (peak over local median);
//! - reading one column of a simulator CSV (with sampling-rate detection and a uniform-sampling
//!   check, [`read_csv_column`]) and writing a spectrum as CSV ([`write_spectrum_csv`]).
//!
//! No function panics on bad input: problems are returned as [`SignalError`]. There is no
//! global state; FFT plans are made by one `rustfft::FftPlanner` per call and reused within it.

mod common;
mod csvio;
mod envelope;
mod peaks;
mod spectrum;
mod welch;
mod window;

pub(crate) use common::{check_input, mean};
pub use common::{SignalError, MIN_SAMPLES};
pub use csvio::{push_sci10, read_csv_column, read_csv_header, write_spectrum_csv, SampledSignal};
pub use envelope::{analytic_signal, bandpass, envelope, envelope_spectrum};
pub use peaks::{
    dominant_peak, harmonics, median, peak_near, prominence, refine, sidebands, top_peaks, Peak,
    Sideband,
};
pub use spectrum::{amplitude_spectrum, Spectrum, SpectrumKind};
pub use welch::{welch_psd, WelchConfig};
pub use window::Window;
