//! `raceway envelope`, run as a user would (issue 17, item 6): the small grid over every preset
//! and level has no hang, crash or garbage; the watchdog turns a stalled point into a hang
//! without waiting for it; bad arguments are clear errors.

use std::path::PathBuf;
use std::process::{Command, Output};
use std::time::Instant;

fn raceway(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raceway"))
        .args(args)
        .output()
        .expect("the raceway binary runs")
}

fn out_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("raceway-envelope-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// The CSV's rows as (column → value) lookups.
fn rows(dir: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(dir.join("envelope.csv")).expect("envelope.csv");
    let head: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|x| x.unwrap().iter().map(String::from).collect())
        .collect();
    (head, rows)
}

fn col(head: &[String], name: &str) -> usize {
    head.iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

#[test]
fn quick_grid_has_no_hang_crash_or_garbage() {
    let dir = out_dir("quick");
    let d = dir.to_str().unwrap();
    let started = Instant::now();
    let out = raceway(&[
        "envelope",
        "--quick",
        "--all-presets",
        "--time-limit",
        "30",
        "--quiet",
        "--out",
        d,
    ]);
    let wall = started.elapsed().as_secs_f64();
    let summary = std::fs::read_to_string(dir.join("envelope.md")).unwrap_or_default();
    assert!(
        out.status.success(),
        "the quick envelope failed ({wall:.1} s): {}\n{summary}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (head, rows) = rows(&dir);
    // 4 presets × 5 levels × (4 loads × 2 pedestals × 3 speeds), and the pure radial load on a
    // located ring on the two angular-contact presets.
    assert_eq!(rows.len(), 4 * 5 * 24 + 2 * 5 * 6);
    let class = col(&head, "class");
    for r in &rows {
        assert!(
            ["ok", "error"].contains(&r[class].as_str()),
            "{r:?}\n{summary}"
        );
    }
    // Every level ran something to the end on every preset (the grid is not all errors).
    let (bearing, level) = (col(&head, "bearing"), col(&head, "level"));
    for preset in [
        "niu2014-table1",
        "cwru-6205-de",
        "cwru-6203-fe",
        "ims-za2115",
    ] {
        for lv in ["kinematic", "quasi_static", "lumped", "reduced", "full"] {
            let ok = rows
                .iter()
                .filter(|r| r[bearing] == preset && r[level] == lv && r[class] == "ok")
                .count();
            assert!(ok > 0, "{preset} {lv}: no point ran to the end\n{summary}");
        }
    }
    // The angular-contact presets refuse a pure radial load on a free ring with a clear error
    // and carry it on a located one, at every level.
    let load = col(&head, "load_case");
    for preset in ["niu2014-table1", "ims-za2115"] {
        let of = |case: &str| {
            rows.iter()
                .filter(|r| {
                    r[bearing] == preset && r[load] == case && r[col(&head, "speed_rpm")] != "0"
                })
                .map(|r| r[class].as_str())
                .collect::<Vec<_>>()
        };
        let free = of("radial-heavy");
        let located = of("radial-heavy-located");
        assert_eq!(located.len(), 5 * 4, "{preset}");
        assert!(free.iter().all(|&c| c == "error"), "{preset}: {free:?}");
        assert!(
            located.iter().all(|&c| c == "ok"),
            "{preset}: {located:?}\n{summary}"
        );
    }
    // L1's reference once per operating point.
    let l1 = csv::Reader::from_path(dir.join("envelope-l1.csv"))
        .expect("envelope-l1.csv")
        .records()
        .count();
    assert_eq!(l1, 4 * 4 * 3 + 2 * 3, "{l1}");
    // The summary starts with the command that made it.
    assert!(
        summary.contains("raceway envelope --quick --all-presets"),
        "{summary}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_watchdog_records_a_stalled_point_as_a_hang_and_fails() {
    let dir = out_dir("stall");
    let started = Instant::now();
    let out = raceway(&[
        "envelope",
        "--quick",
        "--levels",
        "quasi_static",
        "--debug-stall",
        "1",
        // The other points take milliseconds, but on a loaded host (the quick grid test runs
        // beside this one) some can be starved past 1 s.
        "--time-limit",
        "5",
        "--quiet",
        "--out",
        dir.to_str().unwrap(),
    ]);
    let wall = started.elapsed().as_secs_f64();
    // The stalled worker sleeps an hour: the grid must not wait for it.
    assert!(wall < 30.0, "{wall} s");
    assert!(!out.status.success(), "a hang must fail the envelope");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("1 hang"), "{err}");
    let (head, rows) = rows(&dir);
    let class = col(&head, "class");
    assert_eq!(rows[0][class], "hang");
    assert!(rows[1..].iter().all(|r| r[class] != "hang"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_arguments_are_clear_errors() {
    let dir = out_dir("bad");
    let d = dir.to_str().unwrap();
    for (args, want) in [
        (
            vec!["--levels", "warp"],
            "unknown level 'warp'; valid: kinematic",
        ),
        (vec!["--bearing", "no-such-bearing"], "no-such-bearing"),
        (vec!["--time-limit", "0"], "--time-limit 0"),
        (vec!["--cage-margin", "-1"], "--cage-margin -1"),
    ] {
        let mut a = vec!["envelope", "--quick", "--quiet", "--out", d];
        a.extend(&args);
        let out = raceway(&a);
        assert!(!out.status.success(), "{args:?} was accepted");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(want), "{args:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
