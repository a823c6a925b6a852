//! Signal analysis against closed forms: amplitudes and frequencies of sinusoids, Parseval for
//! the Welch PSD, envelope of AM signals and of a resonance excited by an impulse train,
//! sidebands, prominence, CSV reading and error handling.

use raceway::signal::{
    amplitude_spectrum, bandpass, dominant_peak, envelope, envelope_spectrum, harmonics, peak_near,
    read_csv_column, sidebands, top_peaks, welch_psd, SignalError, Spectrum, WelchConfig, Window,
};
use std::f64::consts::PI;

/// Deterministic xorshift64* generator with Box–Muller normals (no external crates).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        ((v >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

fn sines(fs: f64, n: usize, dc: f64, tones: &[(f64, f64, f64)]) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let t = i as f64 / fs;
            dc + tones
                .iter()
                .map(|(a, f, ph)| a * (2.0 * PI * f * t + ph).cos())
                .sum::<f64>()
        })
        .collect()
}

fn variance(x: &[f64]) -> f64 {
    let m = x.iter().sum::<f64>() / x.len() as f64;
    x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / x.len() as f64
}

#[test]
fn on_bin_sinusoid_amplitude_is_exact_for_every_window() {
    // 8192 samples at 8192 Hz: 1 Hz bins, 100 Hz and 1000 Hz on bin centres; DC offset removed.
    let (fs, n) = (8192.0, 8192);
    let x = sines(fs, n, 5.0, &[(1.5, 100.0, 0.3), (0.25, 1000.0, 1.0)]);
    for w in Window::ALL {
        let s = amplitude_spectrum(&x, fs, w).unwrap();
        assert_eq!(s.len(), n / 2 + 1);
        assert!((s.resolution() - 1.0).abs() < 1e-12);
        assert!((s.value[100] - 1.5).abs() < 1e-9, "{w}: {}", s.value[100]);
        assert!(
            (s.value[1000] - 0.25).abs() < 1e-9,
            "{w}: {}",
            s.value[1000]
        );
        assert!(s.value[0] < 1e-9, "{w}: mean not removed: {}", s.value[0]);
    }
}

#[test]
fn off_bin_sum_of_sinusoids_hann_amplitude_1pct_frequency_01_bin() {
    // 1 s at 10 kHz (1 Hz bins); tones at 0.37, 0.5 (worst case) and 0.21 bin off centre.
    let (fs, n) = (10_000.0, 10_000);
    let tones = [(1.0, 123.37, 0.0), (0.5, 1000.5, 1.0), (0.25, 2345.21, 2.0)];
    let x = sines(fs, n, 3.0, &tones);
    let s = amplitude_spectrum(&x, fs, Window::Hann).unwrap();
    let df = s.resolution();
    for (a, f, _) in tones {
        // The raw bin shows the scalloping loss (up to 15 % for Hann at half a bin) ...
        let raw = s.value[s.bin_of(f).unwrap()];
        let p = peak_near(&s, f, 5.0).unwrap();
        // ... which the refined peak undoes.
        assert!(
            rel(p.amplitude, a) < 0.01,
            "f {f}: A {} vs {a}",
            p.amplitude
        );
        assert!(p.amplitude >= raw);
        assert!(((p.freq - f) / df).abs() < 0.1, "f {f}: found {}", p.freq);
    }
    // The three tones are the three largest peaks, in amplitude order.
    let top = top_peaks(&s, 3);
    let found: Vec<f64> = top.iter().map(|p| p.freq).collect();
    assert!((found[0] - 123.37).abs() < 0.1 && (found[1] - 1000.5).abs() < 0.1);
    assert!((found[2] - 2345.21).abs() < 0.1);
}

#[test]
fn refinement_is_window_matched_for_hamming_and_blackman_harris() {
    let (fs, n) = (4096.0, 4096);
    for w in [Window::Hamming, Window::BlackmanHarris, Window::Hann] {
        for frac in [0.0, 0.1, 0.25, 0.4, 0.5, 0.77] {
            let f = 300.0 + frac;
            let x = sines(fs, n, 0.0, &[(2.0, f, 0.7)]);
            let s = amplitude_spectrum(&x, fs, w).unwrap();
            let p = peak_near(&s, f, 3.0).unwrap();
            assert!((p.freq - f).abs() < 0.02, "{w} {f}: {}", p.freq);
            assert!(rel(p.amplitude, 2.0) < 0.005, "{w} {f}: {}", p.amplitude);
        }
    }
}

#[test]
fn window_kernel_closed_form_matches_direct_dtft() {
    let n = 2048;
    for w in Window::ALL {
        let c = w.coefficients(n);
        let sum: f64 = c.iter().sum();
        assert!(rel(w.coherent_gain(n), w.cosine_coefficients()[0]) < 1e-12);
        for delta in [0.0, 0.25, 0.5, 0.9, 1.5] {
            let (re, im) = c.iter().enumerate().fold((0.0, 0.0), |(re, im), (i, v)| {
                let ph = -2.0 * PI * delta * i as f64 / n as f64;
                (re + v * ph.cos(), im + v * ph.sin())
            });
            let direct = (re * re + im * im).sqrt() / sum;
            assert!(
                (w.gain_at_offset(delta) - direct).abs() < 1e-4,
                "{w} δ={delta}: {} vs {direct}",
                w.gain_at_offset(delta)
            );
        }
    }
    // Textbook values: Hann ENBW 1.5 bins, scalloping −1.42 dB.
    assert!((Window::Hann.enbw_bins(n) - 1.5).abs() < 1e-9);
    assert!((20.0 * Window::Hann.gain_at_offset(0.5).log10() + 1.42).abs() < 0.01);
}

#[test]
fn welch_white_noise_integrates_to_variance_for_every_window() {
    let sigma = 2.0;
    let fs = 1000.0;
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let x: Vec<f64> = (0..1 << 18).map(|_| sigma * rng.normal()).collect();
    for w in Window::ALL {
        let cfg = WelchConfig {
            segment_len: 1024,
            overlap: 0.5,
            window: w,
        };
        let s = welch_psd(&x, fs, &cfg).unwrap();
        let total = s.band_power(0.0, fs / 2.0);
        assert!(rel(total, sigma * sigma) < 0.05, "{w}: ∫PSD = {total}");
        // Flat at the one-sided white level 2σ²/fs.
        let level = 2.0 * sigma * sigma / fs;
        let mid = &s.value[10..500];
        let mean = mid.iter().sum::<f64>() / mid.len() as f64;
        assert!(rel(mean, level) < 0.05, "{w}: level {mean} vs {level}");
    }
}

#[test]
fn welch_sinusoid_power_appears_in_its_peak() {
    let fs = 1000.0;
    let a = 3.0;
    let f = 123.4;
    let mut rng = Rng(42);
    let x: Vec<f64> = sines(fs, 1 << 16, 1.0, &[(a, f, 0.2)])
        .iter()
        .map(|v| v + 0.1 * rng.normal())
        .collect();
    let s = welch_psd(&x, fs, &WelchConfig::default()).unwrap();
    let df = s.resolution();
    let p_peak = s.band_power(f - 5.0 * df, f + 5.0 * df);
    assert!(rel(p_peak, a * a / 2.0) < 0.02, "peak power {p_peak}");
    // Parseval over the whole band.
    assert!(rel(s.band_power(0.0, fs), variance(&x)) < 0.02);
    // The peak finder converts the PSD peak back to the sinusoid amplitude.
    let p = peak_near(&s, f, 2.0).unwrap();
    assert!(rel(p.amplitude, a) < 0.02, "amplitude {}", p.amplitude);
    assert!((p.freq - f).abs() < 0.1 * df);
}

#[test]
fn hilbert_envelope_recovers_am_frequency_and_depth() {
    // Carrier 5 kHz, modulation 100 Hz, depth 0.3 and 0.8; off-bin-free 1 s at 50 kHz.
    let (fs, n) = (50_000.0, 50_000);
    for depth in [0.3, 0.8] {
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                2.0 * (1.0 + depth * (2.0 * PI * 100.0 * t).cos()) * (2.0 * PI * 5000.0 * t).sin()
            })
            .collect();
        for band in [None, Some((4000.0, 6000.0))] {
            let env = envelope(&x, fs, band).unwrap();
            let mean = env.iter().sum::<f64>() / n as f64;
            assert!(rel(mean, 2.0) < 0.01, "envelope mean {mean}");
            let s = envelope_spectrum(&x, fs, band, Window::Hann).unwrap();
            let p = dominant_peak(&s, 10.0, 1000.0).unwrap();
            assert!(rel(p.freq, 100.0) < 0.02, "modulation {}", p.freq);
            let d = p.amplitude / mean;
            assert!(rel(d, depth) < 0.02, "depth {d} vs {depth} (band {band:?})");
        }
    }
}

/// A 5.9 kHz resonance (ζ = 3 %) struck by unit impulses every 1/f0 s, plus noise.
fn impulse_train(fs: f64, n: usize, f0: f64) -> Vec<f64> {
    let fr = 5900.0;
    let zeta: f64 = 0.03;
    let wn = 2.0 * PI * fr;
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let mut rng = Rng(7);
    (0..n)
        .map(|i| {
            let t = i as f64 / fs;
            let k_last = (t * f0).floor() as i64;
            // Responses older than ~8 periods have decayed below 1e-6.
            let ring: f64 = (k_last - 8..=k_last)
                .filter(|k| *k >= 0)
                .map(|k| {
                    let tau = t - k as f64 / f0;
                    (-zeta * wn * tau).exp() * (wd * tau).sin()
                })
                .sum();
            ring + 0.05 * rng.normal()
        })
        .collect()
}

#[test]
fn impulse_train_envelope_peak_at_f0_with_harmonics() {
    let f0 = 980.4;
    let (fs, n) = (51_200.0, 51_200);
    let x = impulse_train(fs, n, f0);
    let s = envelope_spectrum(&x, fs, Some((4000.0, 8000.0)), Window::Hann).unwrap();
    let p = peak_near(&s, f0, 0.05 * f0).unwrap();
    assert!(rel(p.freq, f0) < 0.005, "envelope peak {} vs {f0}", p.freq);
    assert!(p.is_significant(10.0), "prominence {}", p.prominence);
    // The largest envelope-spectrum line is the fundamental.
    let top = top_peaks(&s, 1);
    assert!(rel(top[0].freq, f0) < 0.005, "top {}", top[0].freq);
    let h = harmonics(&s, p.freq, 3, 0.01 * f0);
    for (k, hk) in h.iter().enumerate() {
        let hk = hk.expect("harmonic inside the spectrum");
        let fk = (k + 1) as f64 * f0;
        assert!(
            rel(hk.freq, fk) < 0.005,
            "harmonic {}: {} vs {fk}",
            k + 1,
            hk.freq
        );
        assert!(
            hk.is_significant(5.0),
            "harmonic {}: {}",
            k + 1,
            hk.prominence
        );
    }
    // The raw spectrum peaks at the harmonic of f0 nearest the resonance (6·f0 = 5882 Hz).
    let raw = amplitude_spectrum(&x, fs, Window::Hann).unwrap();
    let r = dominant_peak(&raw, 1000.0, 20_000.0).unwrap();
    assert!(rel(r.freq, 6.0 * f0) < 0.005, "raw peak {}", r.freq);
    // A noise-only region of the envelope spectrum has no prominent peak.
    let q = peak_near(&s, 1.5 * f0, 20.0).unwrap();
    assert!(!q.is_significant(3.0), "noise prominence {}", q.prominence);
}

#[test]
fn am_sidebands_at_plus_minus_shaft_rate() {
    // BPFI-like carrier 1329 Hz modulated by the shaft rate 165 Hz, depth 0.4: sidebands of
    // amplitude 0.2 at 1164 and 1494 Hz, nothing at ±2·165 Hz.
    let (fs, n) = (20_000.0, 40_000);
    let x: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / fs;
            (1.0 + 0.4 * (2.0 * PI * 165.0 * t).cos()) * (2.0 * PI * 1329.0 * t).cos()
        })
        .collect();
    let s = amplitude_spectrum(&x, fs, Window::Hann).unwrap();
    let c = peak_near(&s, 1329.0, 10.0).unwrap();
    assert!(rel(c.amplitude, 1.0) < 0.01 && (c.freq - 1329.0).abs() < 0.05);
    let sb = sidebands(&s, c.freq, 165.0, 2, 3.0);
    assert_eq!(
        sb.iter().map(|b| b.order).collect::<Vec<_>>(),
        vec![-2, -1, 1, 2]
    );
    for b in &sb {
        let p = b.peak.unwrap();
        if b.order.abs() == 1 {
            assert!(
                rel(p.amplitude, 0.2) < 0.02,
                "order {}: {}",
                b.order,
                p.amplitude
            );
            assert!(
                (p.freq - b.expected_hz).abs() < 0.05,
                "order {}: {}",
                b.order,
                p.freq
            );
            assert!(p.is_significant(100.0));
        } else {
            assert!(p.amplitude < 1e-3, "order {}: {}", b.order, p.amplitude);
        }
    }
}

#[test]
fn search_next_to_a_strong_line_ignores_its_flank() {
    // 5 Hz bins; a strong tone at 1001 Hz. Searching 1008 ± 3 Hz covers only its falling flank.
    let (fs, n) = (5_000.0, 1_000);
    let strong = sines(fs, n, 0.0, &[(1.0, 1001.0, 0.0)]);
    let s = amplitude_spectrum(&strong, fs, Window::Hann).unwrap();
    assert!(peak_near(&s, 1008.0, 3.0).is_none());
    assert!(dominant_peak(&s, 1004.0, 1012.0).is_none());
    // A weak line that is really there is found.
    let both = sines(fs, n, 0.0, &[(1.0, 1001.0, 0.0), (0.05, 1030.0, 0.0)]);
    let s = amplitude_spectrum(&both, fs, Window::Hann).unwrap();
    let p = peak_near(&s, 1030.0, 3.0).unwrap();
    assert!(
        (p.freq - 1030.0).abs() < 0.5 && rel(p.amplitude, 0.05) < 0.05,
        "{p:?}"
    );
}

#[test]
fn bandpass_keeps_only_the_band() {
    let (fs, n) = (10_000.0, 10_000);
    let x = sines(fs, n, 1.0, &[(1.0, 200.0, 0.0), (1.0, 2000.0, 0.5)]);
    let y = bandpass(&x, fs, 1000.0, 3000.0).unwrap();
    let expect = sines(fs, n, 0.0, &[(1.0, 2000.0, 0.5)]);
    let err = y
        .iter()
        .zip(&expect)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-9, "max error {err}");
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let x = vec![1.0; 100];
    let short = vec![1.0; 3];
    assert!(matches!(
        amplitude_spectrum(&short, 1.0, Window::Hann),
        Err(SignalError::TooFewSamples { got: 3, .. })
    ));
    assert!(amplitude_spectrum(&[], 1.0, Window::Hann).is_err());
    assert!(amplitude_spectrum(&x, 0.0, Window::Hann).is_err());
    assert!(amplitude_spectrum(&x, f64::NAN, Window::Hann).is_err());
    let mut nan = x.clone();
    nan[17] = f64::NAN;
    assert_eq!(
        amplitude_spectrum(&nan, 1.0, Window::Hann),
        Err(SignalError::NonFinite { index: 17 })
    );
    let cfg = |segment_len, overlap| WelchConfig {
        segment_len,
        overlap,
        window: Window::Hann,
    };
    assert!(welch_psd(&x, 1.0, &cfg(200, 0.5)).is_err());
    assert!(welch_psd(&x, 1.0, &cfg(2, 0.5)).is_err());
    assert!(welch_psd(&x, 1.0, &cfg(50, 1.0)).is_err());
    assert!(welch_psd(&x, 1.0, &cfg(50, -0.1)).is_err());
    assert!(welch_psd(&x, 1.0, &cfg(50, 0.0)).is_ok());
    assert!(envelope_spectrum(&x, 100.0, Some((30.0, 20.0)), Window::Hann).is_err());
    assert!(envelope_spectrum(&x, 100.0, Some((60.0, 80.0)), Window::Hann).is_err());
    assert!(envelope_spectrum(&x, 100.0, Some((10.1, 10.2)), Window::Hann).is_err());
    assert!(envelope_spectrum(&x, 100.0, Some((10.0, 1e9)), Window::Hann).is_ok());
    assert!("hann".parse::<Window>().is_ok() && "kaiser".parse::<Window>().is_err());
    // Peak searches outside the spectrum or with nonsense input give None, not a panic.
    let s: Spectrum = amplitude_spectrum(&x, 100.0, Window::Hann).unwrap();
    assert!(peak_near(&s, 1000.0, 1.0).is_none());
    assert!(peak_near(&s, f64::NAN, 1.0).is_none());
    assert!(peak_near(&s, -5.0, 1.0).is_none());
    assert!(dominant_peak(&s, 40.0, 30.0).is_none());
    assert!(top_peaks(&s, 3).is_empty(), "a constant has no peaks");
    assert_eq!(
        harmonics(&s, 20.0, 4, 1.0)
            .iter()
            .filter(|h| h.is_none())
            .count(),
        2
    );
}

fn temp_csv(name: &str, text: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("raceway-signal-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn csv_column_with_fs_detection_and_skip() {
    // Time printed with 6 decimals (rounding up to 0.05 intervals): still uniform.
    let fs = 20_000.0;
    let mut text = String::from("time,pedestal.a.y,pedestal.a.z\n");
    for i in 0..400 {
        let t = i as f64 / fs;
        text += &format!("{t:.6},{},{}\n", -(i as f64), i as f64);
    }
    let path = temp_csv("ok.csv", &text);
    let sig = read_csv_column(&path, "pedestal.a.z", 0.0).unwrap();
    assert!(rel(sig.fs, fs) < 1e-9 && sig.values.len() == 400 && sig.skipped == 0);
    let sig = read_csv_column(&path, "pedestal.a.z", 0.005).unwrap();
    assert_eq!(sig.skipped, 100);
    assert_eq!(sig.values[0], 100.0);
    assert!((sig.t0 - 0.005).abs() < 1e-9);
    assert!(matches!(
        read_csv_column(&path, "pedestal.a.z", 0.5),
        Err(SignalError::TooFewSamples { .. })
    ));
    assert!(read_csv_column(&path, "pedestal.a.z", -1.0).is_err());
}

#[test]
fn csv_errors_are_clear() {
    let path = temp_csv("cols.csv", "time,a,b\n0,1,2\n0.1,1,2\n");
    let e = read_csv_column(&path, "pedestal.a.z", 0.0).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("pedestal.a.z") && msg.contains("time, a, b"),
        "{msg}"
    );
    assert!(matches!(e, SignalError::MissingColumn { .. }));

    // One missing sample in the middle: non-uniform.
    let mut text = String::from("time,x\n");
    for i in (0..100).filter(|i| *i != 50) {
        text += &format!("{},{}\n", i as f64 * 1e-3, i);
    }
    let path = temp_csv("gap.csv", &text);
    let e = read_csv_column(&path, "x", 0.0).unwrap_err();
    assert!(matches!(e, SignalError::NonUniformSampling(_)), "{e}");
    assert!(e.to_string().contains("uniform"), "{e}");

    // Repeated time stamp.
    let path = temp_csv(
        "dup.csv",
        "time,x\n0,1\n1,1\n1,1\n2,1\n3,1\n4,1\n5,1\n6,1\n7,1\n",
    );
    let e = read_csv_column(&path, "x", 0.0).unwrap_err();
    assert!(e.to_string().contains("does not increase"), "{e}");

    // A non-numeric cell names its line and column.
    let path = temp_csv("bad.csv", "time,x\n0,1\n1,oops\n");
    let e = read_csv_column(&path, "x", 0.0).unwrap_err().to_string();
    assert!(
        e.contains("line 3") && e.contains("'x'") && e.contains("oops"),
        "{e}"
    );

    let missing = std::env::temp_dir().join("raceway-signal-test-does-not-exist.csv");
    let e = read_csv_column(&missing, "x", 0.0).unwrap_err().to_string();
    assert!(e.contains("cannot read"), "{e}");
}
