//! `raceway simulate --columns`, run as a user would: the chosen columns, in the order asked,
//! with the same text as in the full table; a bad column name is an error that names it.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn raceway(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raceway"))
        .args(args)
        .output()
        .expect("the raceway binary runs")
}

fn scene() -> String {
    format!(
        "{}/../examples/scenes/default.toml",
        env!("CARGO_MANIFEST_DIR")
    )
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("raceway-cli-simulate-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Header and rows of a CSV file.
fn table(path: &PathBuf) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (head, rows)
}

fn simulate(level: &str, out: &Path, extra: &[&str]) {
    let mut args = vec![
        "simulate",
        &scene(),
        "--fidelity",
        level,
        "--duration",
        "0.02",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]
    .into_iter()
    .map(String::from)
    .collect::<Vec<_>>();
    args.extend(extra.iter().map(|s| s.to_string()));
    let a: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = raceway(&a);
    assert!(
        o.status.success(),
        "raceway {a:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn chosen_columns_are_the_full_tables_columns() {
    for level in ["kinematic", "lumped"] {
        let all = tmp(&format!("{level}-all.csv"));
        simulate(level, &all, &[]);
        let (head, rows) = table(&all);
        for pick in [
            // Bearing-level only (the models skip the per-ball block) …
            vec!["bearing.F.z", "pedestal.a.z"],
            // … and with a per-ball column.
            vec!["pedestal.a.z", "contact.outer.Q[7]", "ball.separated[7]"],
        ] {
            let some = tmp(&format!("{level}-some.csv"));
            simulate(level, &some, &["--columns", &pick.join(",")]);
            let (h, r) = table(&some);
            let mut want = vec!["time"];
            want.extend(&pick);
            assert_eq!(h, want, "{level}: header");
            assert_eq!(r.len(), rows.len(), "{level}: rows");
            assert!(r.len() > 1000);
            let idx: Vec<usize> = want
                .iter()
                .map(|n| head.iter().position(|x| x == n).unwrap())
                .collect();
            for (a, b) in rows.iter().zip(&r) {
                let sel: Vec<&String> = idx.iter().map(|&i| &a[i]).collect();
                assert_eq!(sel, b.iter().collect::<Vec<_>>(), "{level}: {pick:?}");
            }
        }
    }
}

#[test]
fn a_bad_column_is_named_and_nothing_is_written() {
    let out = tmp("bad.csv");
    let _ = std::fs::remove_file(&out);
    for (cols, says) in [
        ("pedestal.a.z,pedestal.a.q", "unknown output 'pedestal.a.q'"),
        (
            "pedestal.a.z,pedestal.a.z",
            "'pedestal.a.z' is asked for twice",
        ),
    ] {
        let o = raceway(&[
            "simulate",
            &scene(),
            "--duration",
            "0.01",
            "--columns",
            cols,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(!o.status.success(), "{cols}: must fail");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(says), "{cols}: stderr {err}");
        assert!(!out.exists(), "{cols}: no file for a bad request");
    }
}

/// The column of `pedestal.a.z` in the simulation's outputs.
fn pedestal_a_z(sim: &raceway::Simulation) -> usize {
    sim.output_table()
        .iter()
        .position(|o| o.name == "pedestal.a.z")
        .expect("an output")
}

/// The CLI's run is the library's one advance over the whole duration, sample for sample, at
/// the default (lumped) and the full level: no step is cut at intermediate times (issue 21:
/// chunked advances left a comb at the chunk rate in the spectrum).
#[test]
fn the_run_is_one_undisturbed_advance() {
    for (level, fidelity) in [
        ("lumped", raceway::Fidelity::Lumped),
        ("full", raceway::Fidelity::Full),
    ] {
        let out = tmp(&format!("one-advance-{level}.csv"));
        simulate(level, &out, &["--columns", "pedestal.a.z"]);
        let (_, rows) = table(&out);
        let mut s = raceway::Scene::load(Path::new(&scene())).unwrap();
        s.fidelity = fidelity;
        s.output.duration = 0.02;
        let mut sim = raceway::Simulation::new(&s).unwrap();
        let k = pedestal_a_z(&sim);
        let mut lib = Vec::new();
        sim.advance_sampled(0.02, 1.0 / s.output.sample_rate, &mut |t, o| {
            lib.push((t, o[k]))
        })
        .unwrap();
        // The CSV's first row is t = 0 (written before the advance).
        assert_eq!(rows.len(), lib.len() + 1, "{level}");
        // Compared as the CSV writes them: time to 1 ns, values to 10 significant digits.
        for (row, (t, a)) in rows[1..].iter().zip(&lib) {
            assert_eq!(row[0], format!("{t:.9}"));
            let mut v = Vec::new();
            raceway::signal::push_sci10(&mut v, *a);
            assert_eq!(
                row[1],
                String::from_utf8(v).unwrap(),
                "{level}: pedestal.a.z at t = {t}"
            );
        }
    }
}

/// A run that fails (here its step budget runs out) says up to which time its outputs are in
/// the file, and the file holds exactly the whole rows up to that time.
#[test]
fn a_failed_run_keeps_whole_rows_up_to_the_time_it_names() {
    let text = std::fs::read_to_string(scene()).unwrap();
    let starved = tmp("starved.toml");
    let text = text.replace("rtol = 1e-6", "rtol = 1e-6\nmax_steps = 5");
    std::fs::write(&starved, text).unwrap();
    let out = tmp("starved.csv");
    let o = raceway(&[
        "simulate",
        starved.to_str().unwrap(),
        "--duration",
        "0.1",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("step budget exhausted"), "{err}");
    let named: f64 = err
        .split("the outputs up to t = ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no time named: {err}"));
    let (head, rows) = table(&out);
    assert!(rows.len() > 100, "{} rows", rows.len());
    assert!(rows.iter().all(|r| r.len() == head.len()));
    let last: f64 = rows.last().unwrap()[0].parse().unwrap();
    assert!((last - named).abs() < 1e-6, "{last} {named}");
    assert!(std::fs::read_to_string(&out).unwrap().ends_with('\n'));
}

/// `raceway simulate --fidelity reduced` runs and says on stderr, even with --quiet, that the
/// level is deprecated and which levels to use; the full level does not.
#[test]
fn the_deprecated_reduced_level_runs_with_a_warning() {
    for (level, warned) in [("reduced", true), ("full", false)] {
        let out = tmp(&format!("deprecated-{level}.csv"));
        let o = raceway(&[
            "simulate",
            &scene(),
            "--fidelity",
            level,
            "--duration",
            "0.0005",
            "--columns",
            "pedestal.a.z",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{level}: {err}");
        assert_eq!(
            err.contains(
                "raceway: warning: fidelity \"reduced\" (L3, FMU fidelity = 3) is deprecated"
            ),
            warned,
            "{level}: {err}"
        );
        assert_eq!(
            err.contains("use \"full\" (4) or \"lumped\" (2) instead"),
            warned
        );
        assert!(table(&out).1.len() > 10, "{level}: rows written");
    }
}

/// `raceway levels --json` lists the five levels in ladder order with the FMU codes of
/// docs/fmu.md, only the reduced level deprecated, with the reason `simulate` warns with; the
/// table says the same in words.
#[test]
fn levels_lists_the_registry_and_marks_the_deprecated_level() {
    let o = raceway(&["levels", "--json"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("JSON");
    let rows = v.as_array().expect("an array");
    let got: Vec<(&str, i64, bool)> = rows
        .iter()
        .map(|r| {
            (
                r["name"].as_str().unwrap(),
                r["code"].as_i64().unwrap(),
                !r["deprecated"].is_null(),
            )
        })
        .collect();
    assert_eq!(
        got,
        [
            ("kinematic", 0, false),
            ("quasi_static", 1, false),
            ("lumped", 2, false),
            ("reduced", 3, true),
            ("full", 4, false),
        ]
    );
    let why = rows[3]["deprecated"].as_str().unwrap();
    assert!(why.contains("no rung of the ladder"), "{why}");
    let warn = raceway(&[
        "simulate",
        &scene(),
        "--fidelity",
        "reduced",
        "--duration",
        "0.0002",
        "--columns",
        "pedestal.a.z",
        "--quiet",
        "--out",
        tmp("levels-reduced.csv").to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&warn.stderr).contains(why));
    let t = raceway(&["levels"]);
    let text = String::from_utf8_lossy(&t.stdout);
    assert!(t.status.success());
    assert_eq!(text.matches("[deprecated]").count(), 1, "{text}");
    assert!(
        text.contains("reduced (code 3, L3)  [deprecated]"),
        "{text}"
    );
}
