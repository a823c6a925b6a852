//! Several spalls in one scene (`[[defect]]`, docs/scenes.md#several-spalls,
//! docs/model.md#several-spalls): every ball meets every spall. Two outer-race spalls 90° apart
//! on the Table-1 bearing at the default operating point (9900 rpm, Fa 4000 N, Fr 1000 N) give
//! each ball a force drop at both, a cage quarter-turn apart, and the pedestal two impacts per
//! ball-pass period, offset by frac(z/4) of it; one spall in `[[defect]]` form is the `[defect]`
//! scene bit for bit; an outer and an inner spall give both BPFO and BPFI lines; overlapping
//! spalls and bad entries are refused by name.

use raceway::signal::{self, Window};
use raceway::{out, Bearing, Fidelity, Scene, Simulation};
use std::f64::consts::{PI, TAU};

/// The default scene's text with its `[defect]` table replaced by `spalls`.
fn scene_with(spalls: &str) -> Scene {
    let text = raceway::DEFAULT_SCENE;
    let start = text.find("[defect]").unwrap();
    let end = text.find("[solver]").unwrap();
    let t = format!("{}{spalls}\n{}", &text[..start], &text[end..]);
    Scene::from_toml_str(&t, "test", None).unwrap_or_else(|e| panic!("{e}\n{t}"))
}

/// The default scene's spall centre θ_d0 = 3.1416 rad as its file writes it (not π).
#[allow(clippy::approx_constant)]
const DEFAULT_THETA0: f64 = 3.1416;

/// `[[defect]]` entries of 1.0 × 0.2 mm spalls, one per (ring, θ_d0).
fn spalls(entries: &[(&str, f64)]) -> String {
    entries
        .iter()
        .map(|(ring, theta0)| {
            format!(
                "[[defect]]\nring = \"{ring}\"\nwidth = 1.0e-3\ndepth = 0.2e-3\ntheta0 = {theta0:?}\n"
            )
        })
        .collect::<Vec<_>>()
        .join("\n")
}

const TWO_OUTER: &str = r#"
[[defect]]
ring = "outer"
width = 1.0e-3
depth = 0.2e-3
theta0 = 2.356194490192345

[[defect]]
ring = "outer"
width = 1.0e-3
depth = 0.2e-3
theta0 = 3.9269908169872414
"#;

/// Per-ball outer forces and the pedestal acceleration sampled every `dt` up to `t_end`, the
/// per-ball orbital speeds, and the model's cage speed [rad/s].
struct Run {
    t: Vec<f64>,
    qo: Vec<Vec<f64>>,
    orbit: Vec<Vec<f64>>,
    acc: Vec<f64>,
    cage: f64,
}

fn run(scene: &Scene, t_end: f64, dt: f64) -> Run {
    let z = 14;
    let mut sim = Simulation::new(scene).expect("builds");
    let cage = sim.cage_speed();
    let mut r = Run {
        t: Vec::new(),
        qo: vec![Vec::new(); z],
        orbit: vec![Vec::new(); z],
        acc: Vec::new(),
        cage,
    };
    sim.advance_sampled(t_end, dt, &mut |ts, o| {
        r.t.push(ts);
        r.acc.push(o[out::PEDESTAL_A_Z]);
        for j in 0..z {
            r.qo[j].push(o[out::CONTACT_START + z + j]);
            r.orbit[j].push(o[out::orbit_speed(z, j)]);
        }
    })
    .expect("runs");
    r
}

/// The passes of ball j over a spall: (first, last) sample index of each run of samples whose
/// outer force is below `frac` of the ball's median force, runs closer than `merge` samples
/// joined (a ball that bounces inside the spall is one pass).
fn passes(q: &[f64], frac: f64, merge: usize) -> Vec<(usize, usize)> {
    let mut sorted = q.to_vec();
    sorted.sort_by(f64::total_cmp);
    let thr = frac * sorted[sorted.len() / 2];
    let mut out: Vec<(usize, usize)> = Vec::new();
    for (k, &v) in q.iter().enumerate() {
        if v < thr {
            match out.last_mut() {
                Some(p) if k - p.1 <= merge => p.1 = k,
                _ => out.push((k, k)),
            }
        }
    }
    out
}

/// Textbook FTF at the nominal contact angle for the scene's speed [Hz] (pure rolling).
fn textbook_ftf(scene: &Scene) -> f64 {
    let b = Bearing::new(&scene.bearing).unwrap();
    let fs = scene.operating.shaft_speed / TAU;
    raceway::fault_frequencies::fault_frequencies(&b, fs, b.alpha0).ftf
}

#[test]
fn lumped_two_outer_spalls_each_ball_drops_at_both_a_quarter_turn_apart() {
    let sc = scene_with(TWO_OUTER);
    assert_eq!(sc.n_defects(), 2);
    let dt = 2e-6;
    let r = run(&sc, 0.03, dt);
    let w = r.cage;
    // The model's cage speed is the kinematic one (within 1.5 % of pure rolling at α0).
    let ftf = w / TAU;
    let ftf0 = textbook_ftf(&sc);
    assert!((ftf / ftf0 - 1.0).abs() < 0.015, "FTF {ftf} vs {ftf0}");
    // Kinematic gaps between a ball's consecutive spall centres: π/2 from the spall at 3π/4 to
    // the one at 5π/4, 3π/2 back.
    let (short, long) = (0.5 * PI / w, 1.5 * PI / w);
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    for (j, q) in r.qo.iter().enumerate() {
        // Below 10 % of the running force: the spall (the ball over it unloads fully; the
        // radial load alone takes a ball at the top of the ring only down to ≈ 50 %).
        let p = passes(q, 0.1, 5);
        // The pass centre: the middle of that interval (the
        // profile is symmetric, the lumped balls move at the cage speed); the first 2 ms (the
        // start's settling) left out.
        let mid: Vec<f64> = p
            .iter()
            .filter(|&&(a, b)| r.t[a] > 2e-3 && b + 1 < q.len())
            .map(|&(a, b)| 0.5 * (r.t[a] + r.t[b]))
            .collect();
        for pair in mid.windows(2) {
            let gap = pair[1] - pair[0];
            let expect = if (gap - short).abs() < (gap - long).abs() {
                short
            } else {
                long
            };
            let err = gap - expect;
            eprintln!(
                "ball {j}: pass gap {:.3} µs, kinematic {:.3} µs, error {:.2} µs",
                gap * 1e6,
                expect * 1e6,
                err * 1e6
            );
            assert!(err.abs() < 3.0 * dt, "ball {j}: gap {gap} vs {expect}");
            worst = worst.max(err.abs());
            checked += 1;
        }
        // Between consecutive passes of one ball the gaps alternate: short, long, short, ...
        for g in mid.windows(3) {
            let (a, b) = (g[1] - g[0], g[2] - g[1]);
            assert!(
                (a < 0.5 * (short + long)) != (b < 0.5 * (short + long)),
                "ball {j}: gaps {a} and {b} do not alternate"
            );
        }
    }
    eprintln!("{checked} pass gaps, worst error {:.2} µs", worst * 1e6);
    // 28 ms is 1.96 cage revolutions: every ball passes a spall at least three times.
    assert!(checked >= 14 * 2, "{checked} gaps");

    // The pedestal: the envelope of its acceleration (along z, on which both spalls, 45° either
    // side of the load-zone centre, project alike) folded on the ball-pass period 1/BPFO jumps
    // twice per period, offset by frac(z · 90°/360°) = frac(14/4) = 0.5 of it (the second
    // spall's train is (90°/360°)/FTF later).
    let bpfo = 14.0 * ftf;
    let (j1, j2, jumps) = folded_jumps(&r, bpfo, dt);
    let sep = circ(j1, j2, BINS) as f64 / BINS as f64;
    let expect = (14.0 * 0.25_f64).fract();
    eprintln!(
        "pedestal impacts at phases {:.2} and {:.2} of 1/BPFO, {sep:.2} apart (kinematic \
         {expect:.2}, (90°/360°)/FTF = {:.1} µs = {:.2} periods); jumps {:.3e} and {:.3e}",
        j1 as f64 / BINS as f64,
        j2 as f64 / BINS as f64,
        0.25 / ftf * 1e6,
        0.25 / ftf * bpfo,
        jumps[j1],
        jumps[j2]
    );
    assert!((sep - expect).abs() <= 0.03, "separation {sep}");
    assert!(
        jumps[j2] > 0.5 * jumps[j1],
        "second impact {} vs {}",
        jumps[j2],
        jumps[j1]
    );

    // The same fold of the one-spall scene jumps once per period.
    let one = run(&Scene::default_scene(), 0.03, dt);
    let (k1, k2, jumps1) = folded_jumps(&one, bpfo, dt);
    eprintln!(
        "one spall: largest jump {:.3e}, the next away from it {:.3e}",
        jumps1[k1], jumps1[k2]
    );
    assert!(jumps1[k2] < 0.3 * jumps1[k1]);
}

const BINS: usize = 100;

/// The envelope of the pedestal acceleration (after 5 ms) folded on the period 1/`f` in
/// [`BINS`] bins, its rise over 3 bins per bin (impacts start a ring-down: the envelope jumps),
/// and the two largest rises at least a fifth of a period apart.
fn folded_jumps(r: &Run, f: f64, dt: f64) -> (usize, usize, Vec<f64>) {
    let env = signal::envelope(&r.acc, 1.0 / dt, Some((2000.0, 50000.0))).unwrap();
    let mut fold = vec![0.0; BINS];
    let mut count = vec![0usize; BINS];
    for (&t, &a) in r.t.iter().zip(&env) {
        if t > 0.005 {
            let b = (((t * f).fract() * BINS as f64) as usize).min(BINS - 1);
            fold[b] += a;
            count[b] += 1;
        }
    }
    for (v, &n) in fold.iter_mut().zip(&count) {
        *v /= n.max(1) as f64;
    }
    let jumps: Vec<f64> = (0..BINS)
        .map(|i| fold[(i + 1) % BINS] - fold[(i + BINS - 2) % BINS])
        .collect();
    let first = (0..BINS)
        .max_by(|&a, &b| jumps[a].total_cmp(&jumps[b]))
        .unwrap();
    let second = (0..BINS)
        .filter(|&i| circ(i, first, BINS) > BINS / 5)
        .max_by(|&a, &b| jumps[a].total_cmp(&jumps[b]))
        .unwrap();
    (first, second, jumps)
}

/// Circular distance of bins a and b of n.
fn circ(a: usize, b: usize, n: usize) -> usize {
    let d = a.abs_diff(b);
    d.min(n - d)
}

#[test]
fn reduced_two_outer_spalls_a_ball_meets_both_a_quarter_turn_apart() {
    let mut sc = scene_with(TWO_OUTER);
    sc.fidelity = Fidelity::Reduced;
    let dt = 2e-6;
    let r = run(&sc, 0.009, dt);
    let mut checked = 0;
    for (j, q) in r.qo.iter().enumerate() {
        // Entry: the outer contact opens (the ball sinks into the spall, then flies and hits
        // the trailing edge; its rattle is one pass).
        let p = passes(q, 0.05, (150e-6 / dt) as usize);
        let entries: Vec<usize> = p
            .iter()
            .filter(|&&(a, _)| a > 0 && r.t[a] > 0.3e-3)
            .map(|&(a, _)| a)
            .collect();
        for pair in entries.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let gap = r.t[b] - r.t[a];
            // The ball's own mean orbital speed over the gap (the cage-less balls drift).
            let w = r.orbit[j][a..b].iter().sum::<f64>() / (b - a) as f64;
            let expect = 0.5 * PI / w;
            eprintln!(
                "ball {j}: entries {:.1} µs apart, kinematic (π/2)/ω̄ = {:.1} µs (ω̄ {w:.2} rad/s, \
                 cage {:.2}), error {:.2} µs",
                gap * 1e6,
                expect * 1e6,
                r.cage,
                (gap - expect) * 1e6
            );
            // Within 20 µs, a fifth of the ≈ 100 µs a pass lasts: the ball meets the second
            // spall where it lies. (The entry, where the outer force falls below 5 %, sits a
            // few µs deeper into one spall than the other: measured −6.7 … −8.7 µs.)
            assert!((gap - expect).abs() < 20e-6, "ball {j}: {gap} vs {expect}");
            checked += 1;
        }
    }
    assert!(checked >= 1, "no ball met both spalls in 9 ms");
}

#[test]
fn one_spall_in_array_form_is_the_table_form_bit_for_bit() {
    let table = Scene::default_scene();
    let array = scene_with(&spalls(&[("outer", DEFAULT_THETA0)]));
    assert_eq!(table, array);
    for level in [Fidelity::Lumped, Fidelity::Reduced] {
        let (mut a, mut b) = (table.clone(), array.clone());
        a.fidelity = level;
        b.fidelity = level;
        let t_end = if level == Fidelity::Lumped {
            0.02
        } else {
            1e-3
        };
        let (ra, rb) = (run(&a, t_end, 5e-6), run(&b, t_end, 5e-6));
        assert!(ra.t.len() > 100);
        let bits = |r: &Run| -> Vec<u64> {
            r.acc
                .iter()
                .chain(r.qo.iter().flatten())
                .map(|v| v.to_bits())
                .collect()
        };
        assert_eq!(bits(&ra), bits(&rb), "{level:?}");
    }
}

#[test]
fn outer_and_inner_spall_give_both_bpfo_and_bpfi() {
    let sc = scene_with(&spalls(&[("outer", DEFAULT_THETA0), ("inner", 0.0)]));
    let mut sim = Simulation::new(&sc).unwrap();
    let ftf = sim.cage_speed() / TAU;
    let fs_shaft = sc.operating.shaft_speed / TAU;
    let (bpfo, bpfi) = (14.0 * ftf, 14.0 * (fs_shaft - ftf));
    let fs = 51200.0;
    let mut a = Vec::new();
    sim.set_ball_outputs(false);
    sim.advance_sampled(0.32, 1.0 / fs, &mut |t, o| {
        if t >= 0.02 {
            a.push(o[out::PEDESTAL_A_Z]);
        }
    })
    .unwrap();
    let env = signal::envelope_spectrum(&a, fs, Some((2000.0, 12000.0)), Window::Hann).unwrap();
    for (name, f) in [("BPFO", bpfo), ("BPFI", bpfi)] {
        let p = signal::peak_near(&env, f, 0.03 * f).unwrap_or_else(|| panic!("no {name}"));
        eprintln!(
            "{name}: envelope peak {:.2} Hz vs kinematic {f:.2} Hz ({:+.3} %)",
            p.freq,
            100.0 * p.rel_error(f)
        );
        assert!(p.rel_error(f).abs() < 0.005, "{name} {} vs {f}", p.freq);
        assert!(p.is_significant(3.0), "{name} peak not significant");
    }
    // Each alone has only its own line: the outer spall's scene has no BPFI line.
    let outer_only = Scene::default_scene();
    let mut sim = Simulation::new(&outer_only).unwrap();
    sim.set_ball_outputs(false);
    let mut a1 = Vec::new();
    sim.advance_sampled(0.32, 1.0 / fs, &mut |t, o| {
        if t >= 0.02 {
            a1.push(o[out::PEDESTAL_A_Z]);
        }
    })
    .unwrap();
    let env1 = signal::envelope_spectrum(&a1, fs, Some((2000.0, 12000.0)), Window::Hann).unwrap();
    assert!(signal::peak_near(&env1, bpfi, 2.0).is_none_or(|p| !p.is_significant(3.0)));
}

#[test]
fn overlapping_spalls_are_refused_naming_both() {
    // θ_e ≈ 0.02 rad for a 1 mm spall: centres 0.01 rad apart overlap.
    let sc = scene_with(&spalls(&[("outer", 1.0), ("inner", 1.0), ("outer", 1.01)]));
    for level in [Fidelity::Lumped, Fidelity::Reduced, Fidelity::Full] {
        let mut s = sc.clone();
        s.fidelity = level;
        let e = Simulation::new(&s).err().expect("refused").to_string();
        assert!(
            e.contains("defect[0]") && e.contains("defect[2]") && e.contains("overlap"),
            "{level:?}: {e}"
        );
        assert!(!e.contains("defect[1]"), "{e}");
    }
    // On different races the same azimuth is fine, and so are outer spalls further apart.
    let mut ok = sc.clone();
    ok.more_defects[1].theta0 = 1.2;
    Simulation::new(&ok).expect("no overlap");
    // The kinematic level refuses several spalls with a reason.
    ok.fidelity = Fidelity::Kinematic;
    let e = Simulation::new(&ok).err().expect("refused").to_string();
    assert!(e.contains("kinematic") && e.contains("3"), "{e}");
}

#[test]
fn entry_errors_name_defect_k() {
    let bad = |entry: &str| {
        let text = raceway::DEFAULT_SCENE.replace(
            "[defect]",
            &format!(
                "[[defect]]\nring = \"inner\"\nwidth = 1e-3\ndepth = 1e-4\n\n[[defect]]\n{entry}\n\n[[defect]]"
            ),
        );
        Scene::from_toml_str(&text, "test", None)
            .err()
            .unwrap_or_else(|| panic!("accepted:\n{text}"))
    };
    let e = bad("ring = \"outer\"\nwidth = -1e-3\ndepth = 1e-4");
    assert_eq!(e.field, "defect[1].width", "{e}");
    let e = bad("ring = \"outer\"\nwidth = 1e-3\ndepth = 1e-4\ntheta0 = inf");
    assert_eq!(e.field, "defect[1].theta0", "{e}");
    let e = bad("ring = \"outer\"\nwidht = 1e-3\ndepth = 1e-4").to_string();
    assert!(e.contains("defect[1]") && e.contains("widht"), "{e}");
    let e = bad("ring = \"outer\"\ndepth = 1e-4").to_string();
    assert!(e.contains("defect[1]") && e.contains("width"), "{e}");
    // With one spall the names stay what they were.
    let text = raceway::DEFAULT_SCENE.replace("width = 1.0e-3", "width = -1.0e-3");
    let e = Scene::from_toml_str(&text, "test", None).unwrap_err();
    assert_eq!(e.field, "defect.width");
    // A width at or above the ball diameter is named per entry by the model too.
    let mut sc = scene_with(TWO_OUTER);
    sc.more_defects[0].width = 20e-3;
    let e = Simulation::new(&sc).err().unwrap().to_string();
    assert!(e.contains("defect[1].width"), "{e}");
}

#[test]
fn a_sweep_key_addresses_one_spall_of_several() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/sweeps");
    let sw = raceway::sweep::Sweep::from_toml_str(
        r#"
base = "../scenes/two-spalls.toml"
[axes]
"defect[1].width" = [0.5e-3, 1.5e-3]
"defect[0].theta0" = [3.0]
"#,
        "test",
        &dir,
    )
    .unwrap();
    let runs = sw.runs();
    assert_eq!(runs.len(), 2);
    let (s, _) = sw.scene_for(&runs[1]).unwrap();
    let base = Scene::load(&dir.join("../scenes/two-spalls.toml")).unwrap();
    let d = s.defects().collect::<Vec<_>>();
    assert_eq!(d.len(), 2);
    assert_eq!(
        (d[0].width, d[0].theta0),
        (base.defects().next().unwrap().width, 3.0)
    );
    assert_eq!(
        (d[1].width, d[1].theta0),
        (1.5e-3, base.more_defects[0].theta0)
    );
    // A spall the base does not have is a run error naming the key.
    let sw = raceway::sweep::Sweep::from_toml_str(
        "base = \"../scenes/two-spalls.toml\"\n[axes]\n\"defect[2].width\" = [1e-3]\n",
        "test",
        &dir,
    )
    .unwrap();
    let e = sw.scene_for(&sw.runs()[0]).unwrap_err();
    assert!(
        e.contains("defect[2].width") && e.contains("2 spall"),
        "{e}"
    );
}

#[test]
fn each_spall_of_several_may_have_its_own_mode() {
    // defect[1] in the paper-literal point mode, defect[0] in the bearing's (finite ball): the
    // largest drop is the finite ball's geometric limit R − √(R² − w_d²/4) for the first (its
    // floor, 0.2 mm deep, is out of reach) and the depth h_d for the second.
    let sc = scene_with(&format!("{TWO_OUTER}mode = \"point\"\n"));
    assert_eq!(sc.defect_modes, [None, Some(raceway::DefectMode::Point)]);
    let b = Bearing::new(&sc.bearing).unwrap();
    let r = 0.5 * b.d;
    let g_finite = r - (r * r - 0.25e-6).sqrt();
    let m = raceway::models::ReducedModel::new(&sc, &b, &sc.operating).unwrap();
    let d = m.defects();
    assert_eq!(d.len(), 2);
    assert_eq!(d[0].mode(), raceway::DefectMode::Finite);
    assert_eq!(d[1].mode(), raceway::DefectMode::Point);
    assert!(
        (d[0].max_drop() / g_finite - 1.0).abs() < 1e-9,
        "{}",
        d[0].max_drop()
    );
    assert!(
        (d[1].max_drop() / 0.2e-3 - 1.0).abs() < 1e-12,
        "{}",
        d[1].max_drop()
    );
    // The lumped level too: in point mode the ball drops by the depth d(y_b) under the nominal
    // contact, h_d(1 − (2y_b/w_d)²), steep from the edges on; the finite ball only sinks
    // R − √(R² − x²) once its centre is x past the leading corner (x²/2R: 1 µm at x = 0.09 mm).
    // So the unloaded part of a pass over defect[1] is several times longer than over
    // defect[0] (measured 55 vs 10 µs); with both finite they are equal.
    let unloaded = |scene: &Scene| {
        let mut s = scene.clone();
        s.fidelity = Fidelity::Lumped;
        let r = run(&s, 0.02, 1e-6);
        let mut d: Vec<f64> =
            r.qo.iter()
                .flat_map(|q| passes(q, 0.01, 3))
                .filter(|&(a, b)| r.t[a] > 2e-3 && b + 1 < r.t.len())
                .map(|(a, b)| r.t[b] - r.t[a])
                .collect();
        d.sort_by(f64::total_cmp);
        (d[0], d[d.len() - 1])
    };
    let (short, long) = unloaded(&sc);
    let (f0, f1) = unloaded(&scene_with(TWO_OUTER));
    eprintln!(
        "unloaded pass: finite {:.1} µs, point {:.1} µs (both finite: {:.1} … {:.1} µs)",
        short * 1e6,
        long * 1e6,
        f0 * 1e6,
        f1 * 1e6
    );
    assert!(long > 2.5 * short && f1 < 1.25 * f0);
    // A mode that is neither is named.
    let text = raceway::DEFAULT_SCENE.replace(
        "[defect]",
        "[[defect]]\nring = \"inner\"\nwidth = 1e-3\ndepth = 1e-4\nmode = \"exact\"\n\n[[defect]]",
    );
    let e = Scene::from_toml_str(&text, "test", None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("defect[0]") && e.contains("exact"), "{e}");
}
