//! `raceway spectrum`: amplitude spectrum, Welch PSD or envelope spectrum of one CSV column,
//! with the top peaks and a search at the expected fault frequencies.

use raceway::signal::{
    amplitude_spectrum, envelope, envelope_spectrum, harmonics, peak_near, read_csv_column,
    sidebands, top_peaks, welch_psd, write_spectrum_csv, Peak, SampledSignal, SignalError,
    Spectrum, SpectrumKind, WelchConfig, Window,
};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Shown by `raceway spectrum --help`: the JSON schema.
const JSON_HELP: &str = "\
Expected frequencies come from --expect NAME=HZ (repeatable) or, without --expect, from the \
sidecar file <CSV>.json if it exists: {\"shaft_hz\": f, \"fault_frequencies\": {\"bpfo\": f, \
\"bpfi\": f, \"ftf\": f, \"bsf\": f, \"two_bsf\": f, ...}} (non-numeric entries are ignored). \
--shaft-hz overrides the sidecar's shaft_hz.

JSON output (--json), stable keys; a value that does not exist is null:
  file, signal            input file and column
  analysis                \"amplitude\", \"psd\", \"envelope\" or \"envelope_psd\"
  value_kind              \"amplitude\" (signal units) or \"psd\" (units^2/Hz)
  window                  window name
  fs_hz, n_samples        sampling rate, samples analysed (after --skip)
  t0_s, duration_s        time of the first analysed sample, analysed duration
  resolution_hz           bin spacing
  segment_len             samples per FFT block (Welch segment or whole record)
  band_hz                 [lo, hi] envelope band or null
  fmax_hz                 spectrum cut-off (Nyquist if no --fmax)
  tolerance_pct           search tolerance around expected frequencies
  metadata                sidecar file used, or null
  shaft_hz                shaft rate used for sidebands, or null
  top_peaks[]             {freq_hz, value, amplitude, prominence}, largest first
  expected[]              {name, expected_hz, found_hz, value, amplitude, prominence,
                           significant, rel_error, sidebands[], harmonics[]}
    sidebands[]           {order (-2,-1,1,2), expected_hz, found_hz, amplitude, prominence}
    harmonics[]           {order (1..N), expected_hz, found_hz, amplitude, prominence};
                          expected_hz = order * found_hz of the fundamental if found
freq/found_hz are refined to sub-bin precision; amplitude is the amplitude of the sinusoid \
that gives the peak (scalloping loss undone); value is the refined peak height in value_kind \
units; prominence is the peak over the local median as an amplitude ratio (>= 3, about 10 dB, \
means a real peak, and significant = prominence >= 3); rel_error = (found_hz - expected_hz) / expected_hz.";

/// Spectrum, Welch PSD or envelope spectrum of one column of a simulator CSV.
///
/// Prints the largest peaks and, for each expected frequency, the peak found within the
/// tolerance, its amplitude, prominence and relative frequency error, the sidebands at
/// ±1, ±2 shaft rates and the harmonics. The JSON keys are listed at the end of `--help`.
#[derive(clap::Args)]
#[command(after_long_help = JSON_HELP)]
pub struct Args {
    /// CSV file with a `time` column and one column per output (as written by `simulate`)
    pub csv: PathBuf,
    /// Column to analyse
    #[arg(long, default_value = "pedestal.a.z")]
    pub signal: String,
    /// Analyse the envelope (Hilbert transform) instead of the signal itself
    #[arg(long)]
    pub envelope: bool,
    /// Band-pass the signal to [LO, HI] Hz before taking the envelope
    #[arg(long, num_args = 2, value_names = ["LO", "HI"], requires = "envelope")]
    pub band: Option<Vec<f64>>,
    /// Welch PSD (units²/Hz) instead of the amplitude spectrum of the whole record
    #[arg(long)]
    pub welch: bool,
    /// Welch segment length in samples (clamped to the record length)
    #[arg(long, default_value_t = 4096, requires = "welch")]
    pub segment: usize,
    /// Welch segment overlap as a fraction in [0, 1)
    #[arg(long, default_value_t = 0.5, requires = "welch")]
    pub overlap: f64,
    /// Window: rectangular, hann, hamming or blackman-harris
    #[arg(long, default_value = "hann", value_parser = parse_window)]
    pub window: Window,
    /// Drop the first S seconds (start-up transient)
    #[arg(long, value_name = "S", default_value_t = 0.0)]
    pub skip: f64,
    /// Ignore the spectrum above F Hz (peaks and --out)
    #[arg(long, value_name = "F")]
    pub fmax: Option<f64>,
    /// Expected frequency to look for, e.g. bpfo=980.4 (repeatable; replaces the sidecar's)
    #[arg(long = "expect", value_name = "NAME=HZ", value_parser = parse_expect)]
    pub expect: Vec<(String, f64)>,
    /// Shaft rate in Hz for the sidebands at ±1, ±2 shaft rates (default: sidecar shaft_hz)
    #[arg(long, value_name = "F")]
    pub shaft_hz: Option<f64>,
    /// Search tolerance around each expected frequency, in percent of it
    #[arg(long, value_name = "PCT", default_value_t = 2.0)]
    pub tol: f64,
    /// Number of largest peaks to list
    #[arg(long, value_name = "N", default_value_t = 5)]
    pub top: usize,
    /// Number of harmonics (including the fundamental) to report per expected frequency
    #[arg(long, value_name = "N", default_value_t = 3)]
    pub harmonics: usize,
    /// Print JSON instead of text (keys: see --help)
    #[arg(long)]
    pub json: bool,
    /// Write the spectrum as CSV (freq_hz,amplitude or freq_hz,psd)
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

fn parse_window(s: &str) -> Result<Window, String> {
    s.parse::<Window>().map_err(|e| e.to_string())
}

fn parse_expect(s: &str) -> Result<(String, f64), String> {
    let (name, hz) = s
        .split_once('=')
        .ok_or_else(|| format!("expected NAME=HZ (e.g. bpfo=980.4), got '{s}'"))?;
    let name = name.trim();
    let hz: f64 = hz
        .trim()
        .parse()
        .map_err(|_| format!("'{hz}' in '{s}' is not a number"))?;
    if name.is_empty() || !(hz.is_finite() && hz > 0.0) {
        return Err(format!(
            "expected NAME=HZ with a name and a frequency > 0, got '{s}'"
        ));
    }
    Ok((name.to_string(), hz))
}

/// Prominence (amplitude ratio over the local median) from which a peak counts as present.
const SIGNIFICANT: f64 = 3.0;

/// One peak as reported.
#[derive(Serialize)]
struct PeakOut {
    freq_hz: f64,
    value: f64,
    amplitude: f64,
    prominence: f64,
}

impl From<&Peak> for PeakOut {
    fn from(p: &Peak) -> Self {
        PeakOut {
            freq_hz: p.freq,
            value: p.value,
            amplitude: p.amplitude,
            prominence: p.prominence,
        }
    }
}

/// A sideband or harmonic as reported.
#[derive(Serialize)]
struct LineOut {
    order: i32,
    expected_hz: f64,
    found_hz: Option<f64>,
    amplitude: Option<f64>,
    prominence: Option<f64>,
}

impl LineOut {
    fn new(order: i32, expected_hz: f64, peak: Option<&Peak>) -> Self {
        LineOut {
            order,
            expected_hz,
            found_hz: peak.map(|p| p.freq),
            amplitude: peak.map(|p| p.amplitude),
            prominence: peak.map(|p| p.prominence),
        }
    }
}

/// The search result for one expected frequency.
#[derive(Serialize)]
struct ExpectedOut {
    name: String,
    expected_hz: f64,
    found_hz: Option<f64>,
    value: Option<f64>,
    amplitude: Option<f64>,
    prominence: Option<f64>,
    significant: bool,
    rel_error: Option<f64>,
    sidebands: Vec<LineOut>,
    harmonics: Vec<LineOut>,
}

/// The whole report (`--json`).
#[derive(Serialize)]
struct Report {
    file: String,
    signal: String,
    analysis: &'static str,
    value_kind: &'static str,
    window: &'static str,
    fs_hz: f64,
    n_samples: usize,
    t0_s: f64,
    duration_s: f64,
    resolution_hz: f64,
    segment_len: usize,
    band_hz: Option<[f64; 2]>,
    fmax_hz: f64,
    tolerance_pct: f64,
    metadata: Option<String>,
    shaft_hz: Option<f64>,
    top_peaks: Vec<PeakOut>,
    expected: Vec<ExpectedOut>,
}

/// Expected frequencies and shaft rate from the sidecar file.
#[derive(Default)]
struct Metadata {
    shaft_hz: Option<f64>,
    faults: Vec<(String, f64)>,
}

fn sidecar_path(csv: &Path) -> PathBuf {
    let mut s = csv.as_os_str().to_os_string();
    s.push(".json");
    PathBuf::from(s)
}

fn positive(v: &serde_json::Value) -> Option<f64> {
    v.as_f64().filter(|f| f.is_finite() && *f > 0.0)
}

fn read_metadata(path: &Path) -> Result<Metadata, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read metadata '{}': {e}", path.display()))?;
    let v: serde_json::Value = serde_json::from_str(&text)
        .map_err(|e| format!("cannot parse metadata '{}': {e}", path.display()))?;
    let obj = v
        .as_object()
        .ok_or_else(|| format!("metadata '{}' is not a JSON object", path.display()))?;
    let mut faults: Vec<(String, f64)> = obj
        .get("fault_frequencies")
        .and_then(|f| f.as_object())
        .map(|m| {
            m.iter()
                .filter_map(|(k, v)| positive(v).map(|f| (k.clone(), f)))
                .collect()
        })
        .unwrap_or_default();
    faults.sort_by(|a, b| a.1.total_cmp(&b.1));
    Ok(Metadata {
        shaft_hz: obj.get("shaft_hz").and_then(positive),
        faults,
    })
}

fn check_args(args: &Args) -> Result<(), String> {
    if !(args.tol.is_finite() && args.tol > 0.0) {
        return Err(format!("--tol must be a percentage > 0, got {}", args.tol));
    }
    if let Some(f) = args.fmax {
        if !(f.is_finite() && f > 0.0) {
            return Err(format!("--fmax must be > 0 Hz, got {f}"));
        }
    }
    if let Some(f) = args.shaft_hz {
        if !(f.is_finite() && f > 0.0) {
            return Err(format!("--shaft-hz must be > 0 Hz, got {f}"));
        }
    }
    Ok(())
}

/// Computes the requested spectrum of the loaded signal.
fn compute(
    args: &Args,
    sig: &SampledSignal,
    band: Option<(f64, f64)>,
) -> Result<Spectrum, SignalError> {
    let x = &sig.values;
    let welch_cfg = WelchConfig {
        segment_len: args.segment.min(x.len()),
        overlap: args.overlap,
        window: args.window,
    };
    match (args.envelope, args.welch) {
        (false, false) => amplitude_spectrum(x, sig.fs, args.window),
        (false, true) => welch_psd(x, sig.fs, &welch_cfg),
        (true, false) => envelope_spectrum(x, sig.fs, band, args.window),
        (true, true) => welch_psd(&envelope(x, sig.fs, band)?, sig.fs, &welch_cfg),
    }
}

/// Runs `raceway spectrum`.
pub fn run(args: Args) -> Result<(), String> {
    check_args(&args)?;
    let band = args.band.as_ref().map(|b| (b[0], b[1]));
    let sig = read_csv_column(&args.csv, &args.signal, args.skip).map_err(|e| match e {
        SignalError::TooFewSamples { needed, got } => format!(
            "'{}': too few samples in column '{}' after skipping {} s: {got} left, at least \
             {needed} needed",
            args.csv.display(),
            args.signal,
            args.skip
        ),
        SignalError::MissingColumn { .. } => format!("'{}': {e}", args.csv.display()),
        other => other.to_string(),
    })?;
    let mut spec = compute(&args, &sig, band).map_err(|e| e.to_string())?;
    if let Some(f) = args.fmax {
        spec.truncate(f);
    }

    let meta_path = sidecar_path(&args.csv);
    let (meta, meta_used) = if meta_path.is_file() {
        (read_metadata(&meta_path)?, Some(meta_path))
    } else {
        (Metadata::default(), None)
    };
    let expected = if args.expect.is_empty() {
        meta.faults.clone()
    } else {
        args.expect.clone()
    };
    let shaft_hz = args.shaft_hz.or(meta.shaft_hz);
    let tol = args.tol / 100.0;

    let expected_out: Vec<ExpectedOut> = expected
        .iter()
        .map(|(name, f)| {
            let peak = peak_near(&spec, *f, tol * f);
            let sb = match (shaft_hz, peak.as_ref()) {
                (Some(shaft), Some(p)) => sidebands(&spec, p.freq, shaft, 2, tol * shaft)
                    .iter()
                    .map(|s| LineOut::new(s.order, s.expected_hz, s.peak.as_ref()))
                    .collect(),
                _ => Vec::new(),
            };
            // Harmonics of a found line are searched at multiples of its refined frequency,
            // which is accurate to a fraction of a bin (< 0.1 bin, so < 0.1·k bins at order
            // k): ±(2 + 0.1·k) bins keep other lines out of the window. Without a fundamental
            // the full tolerance per order applies.
            let base = peak.as_ref().map_or(*f, |p| p.freq);
            let harm = match peak.as_ref() {
                Some(p) => (1..=args.harmonics)
                    .map(|k| {
                        let tol_k = (2.0 + 0.1 * k as f64) * spec.resolution();
                        peak_near(&spec, k as f64 * p.freq, tol_k)
                    })
                    .collect(),
                None => harmonics(&spec, base, args.harmonics, tol * f),
            }
            .iter()
            .enumerate()
            .map(|(i, p)| LineOut::new(i as i32 + 1, (i + 1) as f64 * base, p.as_ref()))
            .collect();
            ExpectedOut {
                name: name.clone(),
                expected_hz: *f,
                found_hz: peak.map(|p| p.freq),
                value: peak.map(|p| p.value),
                amplitude: peak.map(|p| p.amplitude),
                prominence: peak.map(|p| p.prominence),
                significant: peak.is_some_and(|p| p.is_significant(SIGNIFICANT)),
                rel_error: peak.map(|p| p.rel_error(*f)),
                sidebands: sb,
                harmonics: harm,
            }
        })
        .collect();

    let analysis = match (args.envelope, args.welch) {
        (false, false) => "amplitude",
        (false, true) => "psd",
        (true, false) => "envelope",
        (true, true) => "envelope_psd",
    };
    let report = Report {
        file: args.csv.display().to_string(),
        signal: args.signal.clone(),
        analysis,
        value_kind: spec.kind.name(),
        window: spec.window.name(),
        fs_hz: sig.fs,
        n_samples: sig.values.len(),
        t0_s: sig.t0,
        duration_s: sig.duration(),
        resolution_hz: spec.resolution(),
        segment_len: spec.segment_len,
        band_hz: band.map(|(lo, hi)| [lo, hi]),
        fmax_hz: spec.freq.last().copied().unwrap_or(0.0),
        tolerance_pct: args.tol,
        metadata: meta_used.map(|p| p.display().to_string()),
        shaft_hz,
        top_peaks: top_peaks(&spec, args.top)
            .iter()
            .map(PeakOut::from)
            .collect(),
        expected: expected_out,
    };

    if let Some(out) = &args.out {
        write_spectrum_csv(out, &spec).map_err(|e| e.to_string())?;
    }
    if args.json {
        let text = serde_json::to_string_pretty(&report)
            .map_err(|e| format!("cannot format JSON: {e}"))?;
        println!("{text}");
    } else {
        print_text(&report, spec.kind);
    }
    Ok(())
}

/// Prominence for text output: one decimal, or exponent notation when huge.
fn fmt_prom(v: f64) -> String {
    if v.is_finite() && v < 1e4 {
        format!("{v:.1}")
    } else {
        format!("{v:.1e}")
    }
}

fn fmt_opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map_or_else(|| "-".to_string(), f)
}

fn print_text(r: &Report, kind: SpectrumKind) {
    let what = match r.analysis {
        "amplitude" => "amplitude spectrum".to_string(),
        "psd" => "Welch PSD".to_string(),
        "envelope" => "envelope spectrum".to_string(),
        _ => "Welch PSD of the envelope".to_string(),
    };
    let band = r
        .band_hz
        .map_or(String::new(), |[lo, hi]| format!(" (band {lo}-{hi} Hz)"));
    println!(
        "{} [{}]: {what}{band}, {} window",
        r.file, r.signal, r.window
    );
    println!(
        "  fs {} Hz, {} samples from t = {} s ({:.4} s), resolution {:.4} Hz, up to {:.1} Hz",
        r.fs_hz, r.n_samples, r.t0_s, r.duration_s, r.resolution_hz, r.fmax_hz
    );
    let units = match kind {
        SpectrumKind::Amplitude => "",
        SpectrumKind::PowerDensity => "  (value in units^2/Hz)",
    };
    println!("top peaks:{units}");
    println!(
        "  {:>12}  {:>11}  {:>11}  {:>10}",
        "freq [Hz]", "amplitude", "value", "prominence"
    );
    for p in &r.top_peaks {
        println!(
            "  {:>12.3}  {:>11.4e}  {:>11.4e}  {:>10}",
            p.freq_hz,
            p.amplitude,
            p.value,
            fmt_prom(p.prominence)
        );
    }
    if r.expected.is_empty() {
        println!("no expected frequencies (use --expect NAME=HZ or a <CSV>.json sidecar)");
        return;
    }
    let shaft = r
        .shaft_hz
        .map_or("no shaft rate".to_string(), |s| format!("shaft {s} Hz"));
    let source = r
        .metadata
        .as_ref()
        .map_or(String::new(), |m| format!(", metadata {m}"));
    println!(
        "expected frequencies (tolerance ±{} %, {shaft}{source}):",
        r.tolerance_pct
    );
    println!(
        "  {:<10} {:>12}  {:>12}  {:>9}  {:>11}  {:>10}",
        "name", "expected", "found [Hz]", "error", "amplitude", "prominence"
    );
    println!("  (* = not significant: prominence below {SIGNIFICANT})");
    for e in &r.expected {
        println!(
            "  {:<10} {:>12.3}  {:>12}  {:>9}  {:>11}  {:>10}{}",
            e.name,
            e.expected_hz,
            fmt_opt(e.found_hz, |v| format!("{v:.3}")),
            fmt_opt(e.rel_error, |v| format!("{:+.3}%", 100.0 * v)),
            fmt_opt(e.amplitude, |v| format!("{v:.4e}")),
            fmt_opt(e.prominence, fmt_prom),
            if e.significant { "" } else { " *" },
        );
        if !e.sidebands.is_empty() {
            let sb: Vec<String> = e
                .sidebands
                .iter()
                .map(|s| {
                    format!(
                        "{:+}: {}",
                        s.order,
                        fmt_opt(s.amplitude, |v| format!("{v:.3e}"))
                    )
                })
                .collect();
            println!("  {:<10} sidebands (× shaft) {}", "", sb.join("  "));
        }
        if e.harmonics.len() > 1 {
            let h: Vec<String> = e
                .harmonics
                .iter()
                .skip(1)
                .map(|s| {
                    format!(
                        "{}×: {} Hz {}",
                        s.order,
                        fmt_opt(s.found_hz, |v| format!("{v:.2}")),
                        fmt_opt(s.amplitude, |v| format!("{v:.3e}"))
                    )
                })
                .collect();
            println!("  {:<10} harmonics {}", "", h.join("  "));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn expect_parser() {
        assert_eq!(parse_expect("bpfo=980.4"), Ok(("bpfo".to_string(), 980.4)));
        assert!(parse_expect("bpfo").is_err());
        assert!(parse_expect("bpfo=abc").is_err());
        assert!(parse_expect("=3").is_err());
        assert!(parse_expect("x=-1").is_err());
    }

    #[test]
    fn sidecar_is_csv_name_plus_json() {
        assert_eq!(
            sidecar_path(Path::new("runs/out.csv")),
            PathBuf::from("runs/out.csv.json")
        );
    }
}
