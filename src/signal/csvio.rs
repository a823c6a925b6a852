//! Reading one signal column from a simulator CSV and writing spectra as CSV.
//!
//! The simulator writes a header row `time,<output>,<output>,...` (e.g. `pedestal.a.z`) and one
//! row per output instant with a constant output interval. The sampling rate is taken from the
//! time column, and a time column that is not uniform (variable-step output, gaps, repeated
//! instants) is refused: every spectral method here assumes uniform sampling.

use super::spectrum::Spectrum;
use super::{SignalError, MIN_SAMPLES};
use std::io::Write;
use std::path::Path;

/// Name of the time column (matched case-insensitively, surrounding blanks ignored).
pub const TIME_COLUMN: &str = "time";

/// Largest deviation of a time stamp from the uniform grid, as a fraction of the interval,
/// that is still accepted as rounding of printed time values.
pub const UNIFORM_TOLERANCE: f64 = 0.25;

/// A uniformly sampled signal read from a file.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledSignal {
    /// Column name.
    pub name: String,
    /// Samples (after the skipped transient).
    pub values: Vec<f64>,
    /// Sampling rate in Hz, `(n − 1) / (t_last − t_first)` over the whole file.
    pub fs: f64,
    /// Time of the first kept sample in s.
    pub t0: f64,
    /// Number of samples skipped at the start.
    pub skipped: usize,
}

impl SampledSignal {
    /// Duration `len / fs` of the kept samples in s.
    pub fn duration(&self) -> f64 {
        self.values.len() as f64 / self.fs
    }
}

fn reader(path: &Path) -> Result<csv::Reader<std::fs::File>, SignalError> {
    csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_path(path)
        .map_err(|e| SignalError::Io(format!("cannot read '{}': {e}", path.display())))
}

fn headers(rdr: &mut csv::Reader<std::fs::File>, path: &Path) -> Result<Vec<String>, SignalError> {
    let h = rdr.headers().map_err(|e| {
        SignalError::Io(format!(
            "cannot read the header of '{}': {e}",
            path.display()
        ))
    })?;
    let names: Vec<String> = h.iter().map(str::to_string).collect();
    if names.iter().all(|s| s.is_empty()) {
        return Err(SignalError::Io(format!(
            "'{}' is empty or has no header row",
            path.display()
        )));
    }
    Ok(names)
}

/// The column names of a CSV file's header row, in file order.
pub fn read_csv_header(path: &Path) -> Result<Vec<String>, SignalError> {
    let mut rdr = reader(path)?;
    headers(&mut rdr, path)
}

/// Reads column `column` of the CSV file `path`, dropping the samples before
/// `t_first + skip_s` seconds (start-up transient).
///
/// Errors, all with user-facing messages: unreadable file; no `time` column; missing
/// `column` ([`SignalError::MissingColumn`] lists the available ones); a cell that is not a
/// finite number (row and column are named); non-increasing or non-uniform time
/// ([`SignalError::NonUniformSampling`], tolerance `UNIFORM_TOLERANCE` (0.25) of the interval);
/// `skip_s` negative or NaN; fewer than [`MIN_SAMPLES`] samples left.
pub fn read_csv_column(
    path: &Path,
    column: &str,
    skip_s: f64,
) -> Result<SampledSignal, SignalError> {
    if !(skip_s.is_finite() && skip_s >= 0.0) {
        return Err(SignalError::InvalidParameter(format!(
            "the skipped duration must be finite and >= 0 s, got {skip_s}"
        )));
    }
    let mut rdr = reader(path)?;
    let names = headers(&mut rdr, path)?;
    let i_time = names
        .iter()
        .position(|n| n.eq_ignore_ascii_case(TIME_COLUMN))
        .ok_or_else(|| {
            SignalError::Io(format!(
                "'{}' has no '{TIME_COLUMN}' column; columns: {}",
                path.display(),
                names.join(", ")
            ))
        })?;
    let i_col =
        names
            .iter()
            .position(|n| n == column)
            .ok_or_else(|| SignalError::MissingColumn {
                column: column.to_string(),
                available: names.clone(),
            })?;

    let mut time = Vec::new();
    let mut values = Vec::new();
    for (row, rec) in rdr.records().enumerate() {
        // Line numbers as an editor shows them: the header is line 1.
        let line = row + 2;
        let rec =
            rec.map_err(|e| SignalError::Io(format!("'{}' line {line}: {e}", path.display())))?;
        let cell = |i: usize, name: &str| -> Result<f64, SignalError> {
            let text = rec.get(i).unwrap_or("");
            match text.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(SignalError::Io(format!(
                    "'{}' line {line}, column '{name}': '{text}' is not a finite number",
                    path.display()
                ))),
            }
        };
        time.push(cell(i_time, &names[i_time])?);
        values.push(cell(i_col, column)?);
    }
    let n = time.len();
    if n < MIN_SAMPLES {
        return Err(SignalError::TooFewSamples {
            needed: MIN_SAMPLES,
            got: n,
        });
    }
    let dt = check_uniform(&time)?;
    let t_first = time[0];
    let skipped = time
        .iter()
        .take_while(|t| **t < t_first + skip_s - 1e-6 * dt)
        .count();
    let kept = n - skipped;
    if kept < MIN_SAMPLES {
        return Err(SignalError::TooFewSamples {
            needed: MIN_SAMPLES,
            got: kept,
        });
    }
    values.drain(..skipped);
    Ok(SampledSignal {
        name: column.to_string(),
        values,
        fs: 1.0 / dt,
        t0: time[skipped],
        skipped,
    })
}

/// Checks that `time` (at least 2 values) is increasing and on a uniform grid; returns the
/// interval.
fn check_uniform(time: &[f64]) -> Result<f64, SignalError> {
    let n = time.len();
    if let Some(i) = (1..n).find(|&i| time[i] <= time[i - 1]) {
        return Err(SignalError::NonUniformSampling(format!(
            "time does not increase at row {} (t = {} s after t = {} s)",
            i + 1,
            time[i],
            time[i - 1]
        )));
    }
    let dt = (time[n - 1] - time[0]) / (n - 1) as f64;
    let (worst, dev) = time
        .iter()
        .enumerate()
        .map(|(i, t)| (i, (t - (time[0] + i as f64 * dt)).abs() / dt))
        .fold((0, 0.0), |acc, x| if x.1 > acc.1 { x } else { acc });
    if dev > UNIFORM_TOLERANCE {
        return Err(SignalError::NonUniformSampling(format!(
            "sample {} at t = {} s is {:.2} intervals off the uniform grid of mean interval \
             {dt:e} s (tolerance {UNIFORM_TOLERANCE}); spectra need a constant output \
             interval, so resample the signal or simulate with a fixed output step",
            worst + 1,
            time[worst],
            dev
        )));
    }
    Ok(dt)
}

/// Writes `spectrum` to `path` as CSV with header `freq_hz,amplitude` or `freq_hz,psd`.
pub fn write_spectrum_csv(path: &Path, spectrum: &Spectrum) -> Result<(), SignalError> {
    let err =
        |e: std::io::Error| SignalError::Io(format!("cannot write '{}': {e}", path.display()));
    let file = std::fs::File::create(path).map_err(err)?;
    let mut w = std::io::BufWriter::new(file);
    writeln!(w, "freq_hz,{}", spectrum.kind.name()).map_err(err)?;
    for (f, v) in spectrum.freq.iter().zip(&spectrum.value) {
        writeln!(w, "{f},{v:e}").map_err(err)?;
    }
    w.flush().map_err(err)
}

/// Appends `v` to `buf` as `format!("{v:.9e}")` would (ten significant digits, Rust's exponent
/// style: `-1.234567890e-5`, `0.000000000e0`), about 4× faster: the simulator's CSV writer
/// formats millions of values per simulated second, and the exact-precision path of
/// `core::fmt` cost more than the lumped model's integration.
///
/// The digits come from the shortest round-trip representation (`ryu`), rounded half up to ten
/// significant digits. That equals rounding the exact binary value except where the shortest
/// digits end in exactly `5` at the eleventh place (a double rounding; `tests/csv_format.rs`
/// counts such differences over random values: 1 in 2 million). Non-finite and subnormal values
/// are written by `core::fmt` itself.
pub fn push_sci10(buf: &mut Vec<u8>, v: f64) {
    const DIGITS: usize = 10;
    if !v.is_finite() || (v != 0.0 && v.abs() < f64::MIN_POSITIVE) {
        // Non-finite, or subnormal (whose shortest digits can be fewer than ten true ones).
        buf.extend_from_slice(format!("{v:.9e}").as_bytes());
        return;
    }
    // The text is assembled here and appended once: "-d.ddddddddde-ddd" is at most 17 bytes.
    let mut out = [0u8; 24];
    let mut k = 0;
    if v.is_sign_negative() {
        out[k] = b'-';
        k += 1;
    }
    if v == 0.0 {
        buf.extend_from_slice(&out[..k]);
        buf.extend_from_slice(b"0.000000000e0");
        return;
    }
    let mut rb = ryu::Buffer::new();
    let s = rb.format_finite(v.abs()).as_bytes();
    // ryu's output ("123.45", "0.00012", "1.2345e-7", "1e21"): the significant digits, the
    // number of mantissa digits before the point, and the exponent after an 'e'.
    let mut digits = [0u8; 24];
    let mut n = 0;
    let mut int_digits: Option<i32> = None;
    let mut skipped_leading = 0i32;
    let mut exp10 = 0i32;
    let mut i = 0;
    while i < s.len() {
        let c = s[i];
        i += 1;
        match c {
            b'.' => int_digits = Some(n as i32 + skipped_leading),
            b'e' => {
                let neg = s.get(i) == Some(&b'-');
                if neg {
                    i += 1;
                }
                for &d in &s[i..] {
                    exp10 = exp10 * 10 + (d - b'0') as i32;
                }
                if neg {
                    exp10 = -exp10;
                }
                break;
            }
            b'0' if n == 0 => skipped_leading += 1,
            _ => {
                if n < digits.len() {
                    digits[n] = c - b'0';
                    n += 1;
                }
            }
        }
    }
    let int_digits = int_digits.unwrap_or(n as i32 + skipped_leading);
    // The first significant digit stands at 10^(int_digits − skipped_leading − 1 + exp10).
    let mut e = int_digits - skipped_leading - 1 + exp10;
    if n > DIGITS {
        n = DIGITS;
        if digits[DIGITS] >= 5 {
            let mut j = DIGITS;
            loop {
                if j == 0 {
                    // 9.999999999|5 → 1.000000000 × 10^(e+1).
                    digits[0] = 1;
                    e += 1;
                    break;
                }
                j -= 1;
                if digits[j] == 9 {
                    digits[j] = 0;
                } else {
                    digits[j] += 1;
                    break;
                }
            }
        }
    }
    digits[n..DIGITS].fill(0);
    out[k] = b'0' + digits[0];
    out[k + 1] = b'.';
    k += 2;
    for &d in &digits[1..DIGITS] {
        out[k] = b'0' + d;
        k += 1;
    }
    out[k] = b'e';
    k += 1;
    if e < 0 {
        out[k] = b'-';
        k += 1;
    }
    let a = e.unsigned_abs();
    if a >= 100 {
        out[k] = b'0' + (a / 100) as u8;
        k += 1;
    }
    if a >= 10 {
        out[k] = b'0' + (a / 10 % 10) as u8;
        k += 1;
    }
    out[k] = b'0' + (a % 10) as u8;
    k += 1;
    buf.extend_from_slice(&out[..k]);
}
