//! Parameter sweeps: grid expansion, determinism across thread counts, resume after a kill,
//! failed runs recorded with their message, sweep-file errors.

use raceway::sweep::{self, canonical_rows, ExecOptions, OnChange, ResultsFile, Summary, Sweep};
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sweeps")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("raceway-sweep-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

fn parse(text: &str) -> Result<Sweep, sweep::SweepError> {
    Sweep::from_toml_str(text, "test", &scenes_dir())
}

/// 8 short lumped runs with measurement noise (seeded per run).
const SMALL: &str = r#"
base = "../scenes/default.toml"
[set]
"output.duration" = 0.05
"output.skip" = 0.01
[axes]
"defect.width" = [0.8e-3, 1.6e-3]
"operating.speed_rpm" = [6000, 9900]
"noise.rms" = [0.0, 20.0]
[keep]
harmonics = 2
"#;

fn run(sw: &Sweep, dir: &Path, jobs: usize) -> Summary {
    let opts = ExecOptions {
        jobs,
        ..ExecOptions::default()
    };
    sweep::execute(sw, dir, &opts).expect("sweep runs")
}

#[test]
fn grid_expansion_order_ranges_and_ids() {
    let sw = parse(
        r#"
base = "../scenes/default.toml"
[axes]
"operating.speed_rpm" = { start = 6000, stop = 9000, step = 1500 }
"defect.width" = { start = 1e-3, stop = 2e-3, num = 3 }
"defect.ring" = ["outer", "inner"]
"#,
    )
    .unwrap();
    assert_eq!(sw.len(), 3 * 3 * 2);
    let runs = sw.runs();
    // Alphabetical key order, last key fastest.
    let keys: Vec<&str> = runs[0].params.iter().map(|(k, _)| k.as_str()).collect();
    assert_eq!(keys, ["defect.ring", "defect.width", "operating.speed_rpm"]);
    let canon =
        |i: usize| -> Vec<String> { runs[i].params.iter().map(|(_, v)| v.canonical()).collect() };
    assert_eq!(canon(0), ["outer", "0.001", "6000.0"]);
    assert_eq!(canon(1), ["outer", "0.001", "7500.0"]);
    assert_eq!(canon(3), ["outer", "0.0015", "6000.0"]);
    assert_eq!(canon(17), ["inner", "0.002", "9000.0"]);
    // Ids: FNV-1a 64 of the canonical text (fixed reference values), all distinct.
    assert_eq!(sweep::fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
    assert_eq!(sweep::fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
    assert_eq!(
        runs[0].id,
        format!(
            "{:016x}",
            sweep::fnv1a64(b"defect.ring=outer;defect.width=0.001;operating.speed_rpm=6000.0;")
        )
    );
    let mut ids: Vec<&str> = runs.iter().map(|r| r.id.as_str()).collect();
    ids.sort();
    ids.dedup();
    assert_eq!(ids.len(), runs.len());
    // The scene of a run carries its values.
    let (scene, noise) = sw.scene_for(&runs[17]).unwrap();
    assert_eq!(scene.operating.speed_rpm(), 9000.0);
    let d = scene.defect.unwrap();
    assert_eq!(d.width, 2e-3);
    assert_eq!(d.ring, raceway::Site::Inner);
    assert_eq!(noise, 0.0);
}

#[test]
fn ring_and_level_codes_are_stored_as_names() {
    let sw = parse(
        r#"
base = "../scenes/default.toml"
[axes]
"defect.ring" = [0, 1, "inner"]
"fidelity" = [2]
"#,
    )
    .unwrap();
    let runs = sw.runs();
    let canon: Vec<String> = runs
        .iter()
        .map(|r| {
            format!(
                "{}/{}",
                r.params[0].1.canonical(),
                r.params[1].1.canonical()
            )
        })
        .collect();
    assert_eq!(canon, ["none/lumped", "outer/lumped", "inner/lumped"]);
    assert!(sw.scene_for(&runs[0]).unwrap().0.defect.is_none());
    // Code 1 and the name give the same run id.
    let by_name = parse(
        "base = \"../scenes/default.toml\"\n[axes]\n\"defect.ring\" = [\"outer\"]\n\"fidelity\" = [\"lumped\"]\n",
    )
    .unwrap();
    assert_eq!(by_name.runs()[0].id, runs[1].id);
    let e = parse("base = \"../scenes/default.toml\"\n[axes]\n\"defect.ring\" = [1, \"outer\"]\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("appears twice"), "{e}");
}

#[test]
fn seed_run_gives_each_run_its_own_deterministic_seed() {
    let sw = parse(
        r#"
base = "../scenes/default.toml"
[set]
"lumped.seed" = "run"
"lumped.slip_jitter" = 0.01
[axes]
"operating.fr" = [500.0, 1500.0]
"#,
    )
    .unwrap();
    let runs = sw.runs();
    let seed = |i: usize| sw.scene_for(&runs[i]).unwrap().0.lumped.seed;
    assert_ne!(seed(0), seed(1));
    assert_eq!(seed(0), seed(0));
    assert_eq!(sw.scene_for(&runs[1]).unwrap().0.lumped.slip_jitter, 0.01);
    let e = parse("base = \"../scenes/default.toml\"\n[set]\n\"lumped.seed\" = \"random\"\n")
        .unwrap_err()
        .to_string();
    assert!(e.contains("lumped.seed"), "{e}");
}

#[test]
fn sweep_file_errors_are_clear() {
    let err = |t: &str| parse(t).unwrap_err().to_string();
    let e = err("base = \"../scenes/default.toml\"\n[axes]\n\"defect.widht\" = [1e-3]\n");
    assert!(e.contains("unknown sweep key 'defect.widht'"), "{e}");
    assert!(e.contains("defect.width"), "{e}");
    let e = err("base = \"../scenes/default.toml\"\n[axes]\n\"fidelity\" = [\"medium\"]\n");
    assert!(e.contains("fidelity = medium"), "{e}");
    let e = err("base = \"../scenes/default.toml\"\n[axes]\n\"defect.ring\" = [\"left\"]\n");
    assert!(e.contains("defect.ring = left"), "{e}");
    let e = err("base = \"../scenes/default.toml\"\n[axes]\n\"defect.width\" = [\"big\"]\n");
    assert!(e.contains("expected a number"), "{e}");
    let e = err(
        "base = \"../scenes/default.toml\"\n[axes]\n\"operating.fa\" = { start = 1, stop = 2 }\n",
    );
    assert!(e.contains("exactly one of num and step"), "{e}");
    let e = err("base = \"../scenes/default.toml\"\n[axes]\n\"operating.fa\" = [1, 1.0]\n");
    assert!(e.contains("appears twice"), "{e}");
    let e = err("base = \"no-such-scene.toml\"\n");
    assert!(e.contains("base scene"), "{e}");
    let e = err("[axes]\n\"operating.fa\" = [1]\n");
    assert!(e.contains("no base scene"), "{e}");
    let e = err("base = \"../scenes/default.toml\"\n[keep]\nsignal = \"nope\"\n");
    assert!(e.contains("keep.signal = 'nope'"), "{e}");
    let e = err("base = \"../scenes/default.toml\"\n[keep]\nrsm = true\n");
    assert!(e.contains("rsm"), "{e}");
}

#[test]
fn jobs_2_and_jobs_1_give_identical_rows() {
    let sw = parse(SMALL).unwrap();
    let (d1, d2) = (tmp("jobs1"), tmp("jobs2"));
    let s1 = run(&sw, &d1, 1);
    let s2 = run(&sw, &d2, 2);
    assert_eq!((s1.ran, s1.failed), (8, 0));
    assert_eq!((s2.ran, s2.failed), (8, 0));
    let (h1, r1) = canonical_rows(&d1.join("results.csv")).unwrap();
    let (h2, r2) = canonical_rows(&d2.join("results.csv")).unwrap();
    assert_eq!(h1, h2);
    assert_eq!(r1.len(), 8);
    assert_eq!(r1, r2, "rows differ between --jobs 1 and --jobs 2");
    // Noise is seeded per run: it changes the signal metrics, not the contact forces.
    let col = |name: &str| h1.iter().position(|h| h == name).unwrap();
    let (rms, q, noise) = (col("rms"), col("max_contact_force"), col("noise.rms"));
    assert_eq!(r1[0][noise], "0.0");
    // Rows 0 and 2 differ only in noise.rms (axes in key order: width, noise, speed).
    assert_eq!(r1[2][noise], "20.0");
    assert_ne!(r1[0][rms], r1[2][rms]);
    assert_eq!(r1[0][q], r1[2][q]);
    for r in &r1 {
        assert_eq!(r[col("status")], "ok", "{r:?}");
        let bpfo: f64 = r[col("env_bpfo_1")].parse().unwrap();
        assert!(bpfo > 0.0, "{r:?}");
        // The typical per-pass impact lies between the healthy-ish load and the run maximum.
        let impact: f64 = r[col("impact_q_median")].parse().unwrap();
        let q_out: f64 = r[col("max_q_outer")].parse().unwrap();
        assert!(impact > 100.0 && impact <= q_out, "{impact} vs {q_out}");
    }
    let _ = std::fs::remove_dir_all(&d1);
    let _ = std::fs::remove_dir_all(&d2);
}

#[test]
fn resume_runs_only_the_missing_runs() {
    let sw = parse(SMALL).unwrap();
    let d = tmp("resume");
    let full = run(&sw, &d, 2);
    assert_eq!(full.ran, 8);
    let path = d.join("results.csv");
    let (_, reference) = canonical_rows(&path).unwrap();

    // Simulate a kill: keep the header and 3 complete rows, plus half of the 4th row.
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut cut = lines[..4].join("\n");
    cut.push('\n');
    cut.push_str(&lines[4][..lines[4].len() / 2]);
    std::fs::write(&path, cut).unwrap();

    let resumed = run(&sw, &d, 2);
    assert_eq!(resumed.selected, 8);
    assert_eq!(resumed.skipped, 3, "the 3 complete rows are kept");
    assert_eq!(
        resumed.ran, 5,
        "only the 5 missing runs (one cut short) run again"
    );
    let (_, after) = canonical_rows(&path).unwrap();
    assert_eq!(after, reference);

    // Nothing left: a third call runs nothing.
    let again = run(&sw, &d, 1);
    assert_eq!((again.skipped, again.ran), (8, 0));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn impossible_run_is_recorded_as_failed_and_the_others_finish() {
    let sw = parse(
        r#"
base = "../scenes/default.toml"
[set]
"output.duration" = 0.04
"output.skip" = 0.01
[axes]
"defect.width" = [1.0e-3, 20.0e-3, -1.0e-3]
[keep]
raw_signal = true
"#,
    )
    .unwrap();
    let d = tmp("failed");
    let s = run(&sw, &d, 2);
    assert_eq!((s.ran, s.failed), (3, 2));
    let (h, rows) = canonical_rows(&d.join("results.csv")).unwrap();
    let col = |name: &str| h.iter().position(|x| x == name).unwrap();
    assert_eq!(rows[0][col("status")], "ok");
    assert!(rows[0][col("error")].is_empty());
    let signal = d.join(&rows[0][col("signal_file")]);
    let text = std::fs::read_to_string(&signal).unwrap();
    assert!(text.starts_with("time,pedestal.a.z\n"), "{}", &text[..40]);
    assert!(text.lines().count() > 1000);
    for r in &rows[1..] {
        assert_eq!(r[col("status")], "failed", "{r:?}");
        assert!(r[col("error")].contains("defect.width"), "{r:?}");
        assert!(r[col("rms")].is_empty());
    }
    // Failed runs are recorded, so a re-run does not retry them.
    let again = run(&sw, &d, 2);
    assert_eq!((again.skipped, again.ran), (3, 0));
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn a_results_file_of_another_sweep_is_refused() {
    let d = tmp("other");
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("results.csv"), "run_index,run_id,x\n0,abc,1\n").unwrap();
    let sw = parse(SMALL).unwrap();
    let e = sweep::execute(&sw, &d, &ExecOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains("another study or model version")
            && e.to_string().contains("older raceway"),
        "{e}"
    );
    let e = sweep::execute(
        &sw,
        &tmp("only"),
        &ExecOptions {
            jobs: 1,
            only: Some(vec![8]),
            ..ExecOptions::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("outside the grid"), "{e}");
    let _ = std::fs::remove_dir_all(&d);
}

/// The paper's impact force at L4 (`impact_q_zone`): one pass per ball crossing of the outer
/// spall, counted against the kinematic pass rate, and the per-pass maximum inside the zone is
/// a multiple of the running load (docs/model.md#ref-quasi-static: Q_o = 417.6 N for Fa 3000 N at 10 000 rpm) but not
/// above the run's largest outer-race force. A level without ball positions records no pass.
#[test]
fn impact_in_the_spall_zone_counts_every_pass() {
    let sw = parse(
        r#"
base = "../scenes/default.toml"
[set]
"operating.speed_rpm" = 10000.0
"operating.fa" = 3000.0
"operating.fr" = 0.0
"defect.width" = 2.0e-3
"defect.depth" = 0.5e-3
"output.duration" = 0.008
"output.skip" = 0.002
"output.sample_rate" = 204800.0
[axes]
"fidelity" = ["lumped", "full"]
[keep]
harmonics = 1
"#,
    )
    .unwrap();
    let d = tmp("impact-zone");
    let s = run(&sw, &d, 2);
    assert_eq!((s.ran, s.failed), (2, 0));
    let (h, rows) = canonical_rows(&d.join("results.csv")).unwrap();
    let col = |name: &str| h.iter().position(|x| x == name).unwrap();
    let num = |r: &Vec<String>, c: &str| r[col(c)].parse::<f64>().unwrap();
    let full = rows.iter().find(|r| r[col("fidelity")] == "full").unwrap();
    let lumped = rows
        .iter()
        .find(|r| r[col("fidelity")] == "lumped")
        .unwrap();
    // Passes in 6 ms at the model's BPFO (±1 for the passes cut by the window).
    let expected = 0.006 * num(full, "bpfo_hz");
    let passes = num(full, "impact_passes");
    assert!(
        (passes - expected).abs() <= 1.0,
        "{passes} passes, expected {expected:.1}"
    );
    let impact = num(full, "impact_q_zone");
    assert!(
        impact > 1.5 * 417.6 && impact <= num(full, "max_q_outer"),
        "impact {impact} N"
    );
    assert_eq!(num(lumped, "impact_passes"), 0.0);
    assert!(num(lumped, "impact_q_zone").is_nan());
    let _ = std::fs::remove_dir_all(&d);
}

/// `defect.blend_length` sets the C9 (docs/model.md#c9) edge-stiffness blend of the run's bearing (0 = abrupt).
#[test]
fn blend_length_key_reaches_the_scene() {
    let sw = parse(
        r#"
base = "../scenes/default.toml"
[axes]
"defect.blend_length" = [0.0, 2.0e-4]
"#,
    )
    .unwrap();
    let runs = sw.runs();
    let blend = |i: usize| {
        sw.scene_for(&runs[i])
            .unwrap()
            .0
            .bearing
            .defect
            .blend_length
    };
    assert_eq!(blend(0), raceway::BlendLength::Metres(0.0));
    assert_eq!(blend(1), raceway::BlendLength::Metres(2.0e-4));
}

/// A row damaged in the middle of the table (a field changed on disk) fails its check: it is
/// dropped and its run runs again, and the table equals an uninterrupted run's.
#[test]
fn a_damaged_row_fails_its_check_and_runs_again() {
    let sw = parse(SMALL).unwrap();
    let d = tmp("damaged");
    run(&sw, &d, 2);
    let path = d.join("results.csv");
    let (_, reference) = canonical_rows(&path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    // change one digit of a metric of the third row
    let row = &mut lines[3];
    let at = row.rfind(|c: char| c.is_ascii_digit() && c != '9').unwrap();
    row.replace_range(at..=at, "9");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let resumed = run(&sw, &d, 1);
    assert_eq!((resumed.skipped, resumed.ran), (7, 1));
    assert_eq!(resumed.opened.dropped, 1);
    let (_, after) = canonical_rows(&path).unwrap();
    assert_eq!(after, reference);
    let _ = std::fs::remove_dir_all(&d);
}

/// Resuming into a folder after a fixed setting changed (here `output.duration`): refused,
/// naming what changed; with OnChange::NewTable the old table is kept as results.1.csv and a
/// new one is made (issue 21: before, the old rows were silently kept).
#[test]
fn a_changed_study_is_refused_with_what_changed_or_starts_a_new_table() {
    let sw = parse(SMALL).unwrap();
    let d = tmp("changed");
    run(&sw, &d, 2);
    let changed =
        parse(&SMALL.replace("\"output.duration\" = 0.05", "\"output.duration\" = 0.06")).unwrap();
    let e = sweep::execute(&changed, &d, &ExecOptions::default()).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("set.output.duration: 0.05 → 0.06") && msg.contains("--new-table"),
        "{msg}"
    );
    // the model version is part of the record (a table of another build is refused the same way)
    let study = std::fs::read_to_string(d.join("study.json")).unwrap();
    assert!(study.contains(raceway::MODEL_VERSION), "{study}");
    let fresh = sweep::execute(
        &changed,
        &d,
        &ExecOptions {
            on_change: OnChange::NewTable,
            ..ExecOptions::default()
        },
    )
    .unwrap();
    assert_eq!((fresh.skipped, fresh.ran), (0, 8));
    assert_eq!(fresh.opened.kept_as, Some(d.join("results.1.csv")));
    assert!(d.join("study.1.json").exists());
    // the old table is intact beside the new one
    let (_, old) = canonical_rows(&d.join("results.1.csv")).unwrap();
    assert_eq!(old.len(), 8);
    let _ = std::fs::remove_dir_all(&d);
}

/// A distributed sweep's tasks (one run each, in their own folders) merged into one table by
/// the same reader give the table of a single sweep; a task of another study is refused.
#[test]
fn merged_task_tables_equal_one_sweep_and_another_studys_rows_are_refused() {
    let sw = parse(SMALL).unwrap();
    let whole = tmp("merge-whole");
    run(&sw, &whole, 2);
    let (_, reference) = canonical_rows(&whole.join("results.csv")).unwrap();
    let d = tmp("merge");
    std::fs::create_dir_all(&d).unwrap();
    let mut table = ResultsFile::open(&d, &sw, OnChange::Refuse).unwrap();
    for i in 0..8 {
        let task = tmp(&format!("merge-task{i}"));
        sweep::execute(
            &sw,
            &task,
            &ExecOptions {
                jobs: 1,
                only: Some(vec![i]),
                ..ExecOptions::default()
            },
        )
        .unwrap();
        assert_eq!(table.merge(&sw, &task.join("results.csv")).unwrap(), 1);
        // merged twice: nothing new
        assert_eq!(table.merge(&sw, &task.join("results.csv")).unwrap(), 0);
        let _ = std::fs::remove_dir_all(&task);
    }
    drop(table);
    let (_, merged) = canonical_rows(&d.join("results.csv")).unwrap();
    assert_eq!(merged, reference);
    let other = parse(&SMALL.replace("\"output.skip\" = 0.01", "\"output.skip\" = 0.02")).unwrap();
    let od = tmp("merge-other");
    std::fs::create_dir_all(&od).unwrap();
    let mut t = ResultsFile::open(&od, &other, OnChange::Refuse).unwrap();
    let e = t.merge(&other, &whole.join("results.csv")).unwrap_err();
    assert!(e.to_string().contains("run_key differs"), "{e}");
    let _ = std::fs::remove_dir_all(&od);
    let _ = std::fs::remove_dir_all(&d);
    let _ = std::fs::remove_dir_all(&whole);
}

#[test]
fn a_ring_axis_mixes_race_and_ball_spalls_and_defect_ball_picks_the_ball() {
    let sw = parse(
        r#"
base = "../scenes/default.toml"
[set]
"defect.ball" = 5
[axes]
"defect.ring" = ["none", "outer", "inner", 3]
"#,
    )
    .unwrap();
    let runs = sw.runs();
    let rings: Vec<String> = runs.iter().map(|r| r.params[0].1.canonical()).collect();
    assert_eq!(rings, ["none", "outer", "inner", "ball"]);
    let site = |i: usize| sw.scene_for(&runs[i]).unwrap().0.defect.map(|d| d.ring);
    assert_eq!(site(0), None);
    assert_eq!(site(1), Some(raceway::Site::Outer));
    assert_eq!(site(2), Some(raceway::Site::Inner));
    assert_eq!(site(3), Some(raceway::Site::Ball(5)));
    // Without defect.ball, ball 1.
    let sw =
        parse("base = \"../scenes/default.toml\"\n[axes]\n\"defect.ring\" = [\"ball\"]\n").unwrap();
    let scene = sw.scene_for(&sw.runs()[0]).unwrap().0;
    assert_eq!(scene.defect.unwrap().ring, raceway::Site::Ball(1));
    // Not a ball number.
    let sw = parse(
        "base = \"../scenes/default.toml\"\n[set]\n\"defect.ball\" = 0\n[axes]\n\"defect.ring\" = [\"ball\"]\n",
    )
    .unwrap();
    let e = sw.scene_for(&sw.runs()[0]).unwrap_err();
    assert!(
        e.contains("defect.ball = 0") && e.contains("integer ≥ 1"),
        "{e}"
    );
}

#[test]
fn a_ring_axis_over_a_ball_spall_base_keeps_its_ball() {
    let sw = parse(
        "base = \"../scenes/ball-spall.toml\"\n[axes]\n\"defect.ring\" = [\"outer\", \"ball\"]\n",
    )
    .unwrap();
    let runs = sw.runs();
    let site = |i: usize| sw.scene_for(&runs[i]).unwrap().0.defect.map(|d| d.ring);
    assert_eq!(site(0), Some(raceway::Site::Outer));
    // The base's ball 1 stays: change it to see that it is kept, not reset.
    let text = std::fs::read_to_string(scenes_dir().join("../scenes/ball-spall.toml"))
        .unwrap()
        .replace("ball = 1\n", "ball = 7\n");
    let dir = tmp("keep-ball");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("base.toml"), text).unwrap();
    let sw = Sweep::from_toml_str(
        "base = \"base.toml\"\n[axes]\n\"defect.ring\" = [\"none\", 3]\n",
        "test",
        &dir,
    )
    .unwrap();
    let runs = sw.runs();
    assert!(sw.scene_for(&runs[0]).unwrap().0.defect.is_none());
    assert_eq!(
        sw.scene_for(&runs[1]).unwrap().0.defect.unwrap().ring,
        raceway::Site::Ball(7)
    );
}
