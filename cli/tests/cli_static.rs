//! The `raceway static` and `raceway frequencies` commands, run as a user would; `static` on an
//! axially located ring against the library's solve.

use raceway::load_distribution::solve_located;
use raceway::{Bearing, OperatingPoint};
use serde_json::Value;
use std::process::{Command, Output};

fn raceway(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raceway"))
        .args(args)
        .output()
        .expect("the raceway binary runs")
}

fn json_of(args: &[&str]) -> Value {
    let out = raceway(args);
    assert!(
        out.status.success(),
        "raceway {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is JSON")
}

fn num(v: &Value, key: &str) -> f64 {
    v.get(key)
        .and_then(Value::as_f64)
        .unwrap_or_else(|| panic!("missing number '{key}' in {v}"))
}

fn rel_close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got / want - 1.0).abs() <= tol,
        "{what}: got {got:e}, want {want:e}"
    );
}

#[test]
fn static_json_table1_9900rpm() {
    let v = json_of(&[
        "static",
        "--bearing",
        "niu2014-table1",
        "--fa",
        "4000",
        "--fr",
        "1000",
        "--speed-rpm",
        "9900",
        "--json",
    ]);
    rel_close(num(&v, "delta_axial"), 22.34e-6, 5e-3, "delta_axial");
    rel_close(num(&v, "delta_radial"), 3.42e-6, 5e-3, "delta_radial");
    rel_close(-num(&v, "delta_z"), 3.42e-6, 5e-3, "delta_z");
    assert!(num(&v, "delta_y").abs() < 1e-12);
    let k = v["stiffness"].as_array().expect("stiffness matrix");
    assert_eq!(k.len(), 3);
    rel_close(k[0][0].as_f64().unwrap(), 2.46e8, 0.02, "K_aa");
    rel_close(k[2][2].as_f64().unwrap(), 2.88e8, 0.02, "K_rr");
    let balls = v["balls"].as_array().expect("balls");
    assert_eq!(balls.len(), 14);
    let qmax = balls.iter().map(|b| num(b, "q_inner")).fold(0.0, f64::max);
    rel_close(qmax, 672.9, 5e-3, "Q_i max");
    rel_close(num(&balls[7], "q_inner"), 672.9, 5e-3, "Q_i at θ = π");
    rel_close(
        num(&balls[7], "alpha_outer").to_degrees(),
        30.70,
        5e-3,
        "α_o at θ = π",
    );
    let f = &v["frequencies"];
    rel_close(num(f, "ftf"), 70.42, 5e-3, "FTF");
    // The load-weighted mean over the loaded balls (tests/load_distribution.rs, row 3).
    let (qsum, wsum) =
        balls
            .iter()
            .filter(|b| num(b, "q_inner") > 1e-6)
            .fold((0.0, 0.0), |(a, c), b| {
                (
                    a + num(b, "q_inner"),
                    c + num(b, "q_inner") * num(b, "cage_speed"),
                )
            });
    rel_close(
        num(f, "bpfo"),
        14.0 * wsum / qsum / std::f64::consts::TAU,
        1e-9,
        "BPFO",
    );
    assert!((num(f, "bpfo") - 985.3).abs() < 0.5);
    assert!((num(f, "bpfi") - 1324.7).abs() < 0.5);
    // The steady rotation under the traction: BPFO = 14 FTF within the paper's 980.4 Hz ± 0.3 %
    // (docs/model.md#ref-dynamic), where outer-race control is 0.6 % off.
    let w = num(&v, "traction_cage_speed");
    rel_close(
        14.0 * w / std::f64::consts::TAU,
        980.4,
        3e-3,
        "BPFO with traction",
    );
}

#[test]
fn static_json_pure_axial_at_rest() {
    let v = json_of(&["static", "--fa", "4000", "--fr", "0", "--json"]);
    rel_close(num(&v, "delta_axial"), 23.572e-6, 3e-5, "delta_axial");
    assert!(num(&v, "delta_radial") < 1e-12);
    for b in v["balls"].as_array().unwrap() {
        rel_close(num(b, "q_inner"), 530.86, 1e-5, "Q");
        rel_close(num(b, "alpha_inner").to_degrees(), 32.562, 2e-5, "α");
    }
}

#[test]
fn static_human_output_has_units() {
    let out = raceway(&[
        "static",
        "--fa",
        "4000",
        "--fr",
        "1000",
        "--speed-rpm",
        "9900",
    ]);
    assert!(out.status.success());
    let s = String::from_utf8(out.stdout).unwrap();
    for needle in ["µm", "Q_i [N]", "α_i [°]", "N/m", "BPFO", "Hz"] {
        assert!(s.contains(needle), "missing '{needle}' in\n{s}");
    }
}

#[test]
fn static_errors_are_explained() {
    let cases: [(&[&str], &str); 5] = [
        (&["static", "--fa", "0", "--fr", "0"], "no ball"),
        (&["static", "--fa", "0", "--fr", "1000"], "axial load"),
        (&["static", "--fa", "1e9", "--fr", "0"], "beyond"),
        (&["static", "--fa", "nan", "--fr", "0"], "--fa"),
        (
            &[
                "static",
                "--bearing",
                "no-such-bearing",
                "--fa",
                "1",
                "--fr",
                "0",
            ],
            "neither a preset",
        ),
    ];
    for (args, needle) in cases {
        let out = raceway(args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{args:?}: stderr {err}");
    }
}

#[test]
fn frequencies_json() {
    let v = json_of(&["frequencies", "--speed-rpm", "9900", "--json"]);
    assert!((num(&v, "shaft") - 165.0).abs() < 1e-12);
    assert!((num(&v, "ftf") - 69.537).abs() < 0.001);
    assert!((num(&v, "bpfo") - 973.52).abs() < 0.01);
    assert!((num(&v, "bpfi") - 1336.48).abs() < 0.01);
    assert!((num(&v, "bsf") - 443.50).abs() < 0.01);
    assert!((num(&v, "two_bsf") - 887.00).abs() < 0.02);
    let v = json_of(&[
        "frequencies",
        "--speed-rpm",
        "9900",
        "--contact-angle-deg",
        "33.57",
        "--json",
    ]);
    assert!((num(&v, "bpfo") - 980.40).abs() < 0.01);
    let v = json_of(&[
        "frequencies",
        "--bearing",
        "cwru-6205-de",
        "--speed-rpm",
        "60",
        "--json",
    ]);
    assert!((num(&v, "bpfo") - 3.5848).abs() < 5e-4);
    assert!((num(&v, "two_bsf") - 4.7135).abs() < 5e-4);
}

#[test]
fn frequencies_table_and_errors() {
    let out = raceway(&[
        "frequencies",
        "--bearing",
        "ims-za2115",
        "--speed-rpm",
        "2000",
    ]);
    assert!(out.status.success());
    let s = String::from_utf8(out.stdout).unwrap();
    for needle in ["FTF", "BPFO", "BPFI", "BSF", "2BSF", "Hz", "236.4"] {
        assert!(s.contains(needle), "missing '{needle}' in\n{s}");
    }
    let out = raceway(&[
        "frequencies",
        "--speed-rpm",
        "100",
        "--contact-angle-deg",
        "95",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--contact-angle-deg"));
}

/// The axially located inner ring (issue 17 item 5) through the CLI: the reaction it prints is
/// the library's, and `--axial-offset` with an axial load is refused.
#[test]
fn cli_static_locates_the_ring_with_axial_offset() {
    let o = raceway(&["static", "--fr", "2000", "--axial-offset", "0", "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["axially_located"], true);
    let r = v["axial_reaction"].as_f64().unwrap();
    let expect = solve_located(
        &Bearing::load("niu2014-table1").unwrap(),
        &OperatingPoint::from_rpm(0.0, 0.0, 2000.0),
        0.0,
    )
    .unwrap()
    .ring_force()[0];
    assert!((r - expect).abs() < 1e-9 * expect);
    let o = raceway(&[
        "static",
        "--fr",
        "2000",
        "--fa",
        "10",
        "--axial-offset",
        "0",
    ]);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("--axial-offset"));
}
