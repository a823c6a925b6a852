//! `raceway spectrum` on CSV files generated here: JSON report of known peaks, sidecar
//! metadata, spectrum CSV output and error messages.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("raceway-cli-spectrum-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `time,pedestal.a.y,pedestal.a.z` with `z = f(t)` (y = 0) at `fs` for `n` samples.
fn write_csv(name: &str, fs: f64, n: usize, f: impl Fn(f64) -> f64) -> PathBuf {
    let path = dir().join(name);
    let mut text = String::from("time,pedestal.a.y,pedestal.a.z\n");
    for i in 0..n {
        let t = i as f64 / fs;
        text += &format!("{t:.9},0,{:.9e}\n", f(t));
    }
    std::fs::write(&path, text).unwrap();
    path
}

fn run(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raceway"))
        .arg("spectrum")
        .args(args)
        .output()
        .expect("run raceway")
}

fn json(out: &Output) -> serde_json::Value {
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON on stdout")
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

#[test]
fn json_reports_expected_peak_frequency_and_amplitude() {
    // 2.0·sin(2π·980.4 t) + 0.5·sin(2π·3100 t) + offset, 0.1 s start-up junk that --skip drops.
    let fs = 25_600.0;
    let path = write_csv("tones.csv", fs, 28_160, |t| {
        let junk = if t < 0.1 { 50.0 } else { 0.0 };
        junk + 1.0 + 2.0 * (2.0 * PI * 980.4 * t).sin() + 0.5 * (2.0 * PI * 3100.0 * t).sin()
    });
    let out = run(&[
        path.to_str().unwrap(),
        "--signal",
        "pedestal.a.z",
        "--skip",
        "0.1",
        "--expect",
        "bpfo=980.4",
        "--expect",
        "other=3100",
        "--json",
    ]);
    let v = json(&out);
    assert_eq!(v["signal"], "pedestal.a.z");
    assert_eq!(v["analysis"], "amplitude");
    assert!(rel(num(&v["fs_hz"]), fs) < 1e-9);
    assert_eq!(v["n_samples"], 25_600);
    assert!((num(&v["t0_s"]) - 0.1).abs() < 1e-9);
    let top = &v["top_peaks"][0];
    assert!((num(&top["freq_hz"]) - 980.4).abs() < 0.1, "{top}");
    let e = &v["expected"][0];
    assert_eq!(e["name"], "bpfo");
    assert!(num(&e["rel_error"]).abs() < 1e-4, "{e}");
    assert!(rel(num(&e["found_hz"]), 980.4) < 1e-4, "{e}");
    assert!(rel(num(&e["amplitude"]), 2.0) < 0.01, "{e}");
    assert!(num(&e["prominence"]) > 100.0, "{e}");
    assert!(
        e["sidebands"].as_array().unwrap().is_empty(),
        "no shaft rate given"
    );
    let e2 = &v["expected"][1];
    assert!(rel(num(&e2["amplitude"]), 0.5) < 0.01, "{e2}");
}

#[test]
fn envelope_with_sidecar_metadata_finds_fault_and_shaft_sidebands() {
    // Envelope (1 + 0.5 cos a)(1 + 0.3 cos b) on a 6 kHz carrier, a = 2π·1329 t (BPFI),
    // b = 2π·164.8 t (shaft): envelope lines 0.5 at 1329 Hz and 0.075 at 1329 ± 164.8 Hz.
    let fs = 40_000.0;
    let path = write_csv("env.csv", fs, 40_000, |t| {
        (1.0 + 0.5 * (2.0 * PI * 1329.0 * t).cos())
            * (1.0 + 0.3 * (2.0 * PI * 164.8 * t).cos())
            * (2.0 * PI * 6000.0 * t).cos()
    });
    let meta = format!("{}.json", path.display());
    std::fs::write(
        &meta,
        r#"{"shaft_hz": 164.8, "fault_frequencies": {"bpfi": 1329.0, "ftf": 70.05, "note": "x"}}"#,
    )
    .unwrap();
    let out = run(&[
        path.to_str().unwrap(),
        "--envelope",
        "--band",
        "3000",
        "9000",
        "--fmax",
        "5000",
        "--json",
    ]);
    let v = json(&out);
    assert_eq!(v["analysis"], "envelope");
    assert_eq!(v["metadata"], meta.as_str());
    assert!(rel(num(&v["shaft_hz"]), 164.8) < 1e-12);
    assert!(num(&v["fmax_hz"]) <= 5000.0);
    let expected = v["expected"].as_array().unwrap();
    // Sorted by frequency; the non-numeric entry is ignored.
    let names: Vec<&str> = expected
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["ftf", "bpfi"]);
    let e = &expected[1];
    assert!(num(&e["rel_error"]).abs() < 0.003, "{e}");
    assert!(rel(num(&e["amplitude"]), 0.5) < 0.02, "{e}");
    // Harmonic 1 is the fundamental itself; 2·1329 Hz has no line (null or leakage only).
    assert_eq!(e["harmonics"][0]["found_hz"], e["found_hz"]);
    assert!(e["harmonics"][1]["amplitude"]
        .as_f64()
        .is_none_or(|a| a < 0.005));
    let sb = e["sidebands"].as_array().unwrap();
    assert_eq!(sb.len(), 4);
    for s in sb {
        let order = s["order"].as_i64().unwrap();
        if order.abs() == 1 {
            assert!(rel(num(&s["amplitude"]), 0.075) < 0.03, "{s}");
            assert!(
                (num(&s["found_hz"]) - num(&s["expected_hz"])).abs() < 0.2,
                "{s}"
            );
        } else {
            // No line at ±2 shaft rates: no local maximum there (null) or only leakage.
            assert!(s["amplitude"].as_f64().is_none_or(|a| a < 0.005), "{s}");
        }
    }
    // The shaft line itself is the second largest.
    let top = v["top_peaks"].as_array().unwrap();
    assert!((num(&top[1]["freq_hz"]) - 164.8).abs() < 0.1, "{top:?}");
    // --expect replaces the sidecar's list.
    let v = json(&run(&[
        path.to_str().unwrap(),
        "--envelope",
        "--expect",
        "shaft=164.8",
        "--json",
    ]));
    assert_eq!(v["expected"].as_array().unwrap().len(), 1);
    assert!(rel(num(&v["expected"][0]["amplitude"]), 0.3) < 0.02);
}

#[test]
fn welch_and_out_csv() {
    let fs = 10_000.0;
    let path = write_csv("welch.csv", fs, 50_000, |t| {
        3.0 * (2.0 * PI * 1250.0 * t).cos()
    });
    let csv_out = dir().join("psd.csv");
    let v = json(&run(&[
        path.to_str().unwrap(),
        "--welch",
        "--segment",
        "1000",
        "--expect",
        "tone=1250",
        "--json",
        "--out",
        csv_out.to_str().unwrap(),
    ]));
    assert_eq!(v["value_kind"], "psd");
    assert_eq!(v["segment_len"], 1000);
    assert!(rel(num(&v["resolution_hz"]), 10.0) < 1e-12);
    assert!(rel(num(&v["expected"][0]["amplitude"]), 3.0) < 0.01);
    let text = std::fs::read_to_string(&csv_out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("freq_hz,psd"));
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let (f, p) = l.split_once(',').unwrap();
            (f.parse().unwrap(), p.parse().unwrap())
        })
        .collect();
    assert_eq!(rows.len(), 501);
    // Parseval on the written PSD: A²/2 = 4.5.
    let power: f64 = rows.iter().map(|r| r.1 * 10.0).sum();
    assert!(rel(power, 4.5) < 0.01, "power {power}");
}

#[test]
fn text_output_lists_peaks_and_expected() {
    let path = write_csv("text.csv", 8192.0, 8192, |t| (2.0 * PI * 500.0 * t).sin());
    let out = run(&[
        path.to_str().unwrap(),
        "--expect",
        "x=500",
        "--shaft-hz",
        "50",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("top peaks") && text.contains("500.000"),
        "{text}"
    );
    assert!(text.contains("sidebands"), "{text}");
}

fn stderr_of(args: &[&str]) -> String {
    let out = run(args);
    assert!(!out.status.success(), "should fail: {args:?}");
    String::from_utf8(out.stderr).unwrap()
}

#[test]
fn missing_column_lists_available_columns() {
    let path = write_csv("cols.csv", 1000.0, 100, |t| t);
    let err = stderr_of(&[path.to_str().unwrap(), "--signal", "pedestal.a.x"]);
    assert!(err.contains("'pedestal.a.x' not found"), "{err}");
    assert!(err.contains("time, pedestal.a.y, pedestal.a.z"), "{err}");
}

#[test]
fn other_errors_are_clear() {
    let missing = Path::new("/nonexistent/raceway/out.csv");
    let err = stderr_of(&[missing.to_str().unwrap()]);
    assert!(
        err.contains("cannot read") && err.contains("out.csv"),
        "{err}"
    );

    let path = write_csv("short.csv", 1000.0, 20, |t| t);
    let err = stderr_of(&[path.to_str().unwrap(), "--skip", "0.015"]);
    assert!(err.contains("too few samples"), "{err}");

    let path = write_csv("ok.csv", 1000.0, 100, |t| t);
    let err = stderr_of(&[path.to_str().unwrap(), "--envelope", "--band", "600", "700"]);
    assert!(err.contains("Nyquist"), "{err}");

    let err = stderr_of(&[path.to_str().unwrap(), "--expect", "bpfo"]);
    assert!(err.contains("NAME=HZ"), "{err}");

    let err = stderr_of(&[path.to_str().unwrap(), "--band", "1", "2"]);
    assert!(err.contains("--envelope"), "{err}");

    let bad_meta = write_csv("badmeta.csv", 1000.0, 100, |t| t);
    std::fs::write(format!("{}.json", bad_meta.display()), "{not json").unwrap();
    let err = stderr_of(&[bad_meta.to_str().unwrap()]);
    assert!(err.contains("cannot parse metadata"), "{err}");
}
