//! Issue 23 in the FMU: a base scene packed as `resources/scene.toml` (its values the start
//! values, its later spalls, waviness and roughness fixed), and spalls 2–4 as the parameters
//! `defect2.*` … `defect4.*`. Each run is compared bit for bit with the library's
//! [`Simulation`] on the equivalent scene.

use ballbearing_fmu::ballbearing::BallBearing;
use ballbearing_fmu::base::Base;
use ballbearing_fmu::variables::table_for;
use fmi2::bindings::*;
use fmi2::capture::LogCapture;
use fmi2::functions as sh;
use raceway::{BearingFile, Scene, Simulation};
use std::ffi::CString;
use std::path::{Path, PathBuf};

const REPO: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/..");

/// Communication step [s] and number of steps of the compared runs (5 ms: every ball passes
/// each outer-race spall at least once, the ball-pass period being about 1 ms).
const STEP: f64 = 1e-4;
const STEPS: usize = 50;

/// A temporary resources folder, removed on drop.
struct Resources(PathBuf);

impl Resources {
    /// `bearing.toml` (the default preset's text) and, if given, `scene.toml`.
    fn new(scene: Option<&str>) -> Self {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static N: AtomicUsize = AtomicUsize::new(0);
        let p = std::env::temp_dir().join(format!(
            "raceway scene resource {} {}",
            std::process::id(),
            N.fetch_add(1, Ordering::SeqCst)
        ));
        std::fs::create_dir_all(&p).unwrap();
        std::fs::write(p.join("bearing.toml"), raceway::PRESETS[0].1).unwrap();
        if let Some(s) = scene {
            std::fs::write(p.join("scene.toml"), s).unwrap();
        }
        Self(p)
    }
    fn uri(&self) -> String {
        format!("file://{}", self.0.to_string_lossy().replace(' ', "%20"))
    }
    /// The base the FMU makes of these resources.
    fn base(&self) -> Base {
        ballbearing_fmu::base::load_scene(Some(&self.0), &BearingFile::default_preset()).unwrap()
    }
}

impl Drop for Resources {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A scene file of examples/scenes as the packer ships it: its bearing the resource beside it.
fn example_as_resource(name: &str) -> String {
    let text = std::fs::read_to_string(Path::new(REPO).join("examples/scenes").join(name)).unwrap();
    assert!(text.contains("bearing = \"niu2014-table1\""));
    text.replace("bearing = \"niu2014-table1\"", "bearing = \"bearing.toml\"")
}

/// The default scene as a resource with five outer spalls at 0.5, 1.7, 2.9, 4.1, 5.3 rad.
fn five_outer_spalls() -> String {
    let mut text = example_as_resource("default.toml");
    let at = text.find("[defect]").unwrap();
    let end = text[at..].find("[solver]").unwrap() + at;
    let spalls: String = [0.5, 1.7, 2.9, 4.1, 5.3]
        .iter()
        .map(|t| {
            format!(
                "[[defect]]\nring = \"outer\"\nwidth = 1.0e-3\ndepth = 0.2e-3\ntheta0 = {t}\n\n"
            )
        })
        .collect();
    text.replace_range(at..end, &spalls);
    text
}

fn example(name: &str) -> Scene {
    Scene::load(&Path::new(REPO).join("examples/scenes").join(name)).unwrap()
}

/// Instantiates (Co-Simulation) with `guid` and the resources at `uri`.
fn inst(log: &LogCapture, guid: &str, uri: Option<&str>) -> Fmi2Component {
    let g = CString::new(guid).unwrap();
    let r = uri.map(|r| CString::new(r).unwrap());
    // SAFETY: test importer: the strings outlive the call; the callbacks are the capture's.
    unsafe {
        sh::instantiate::<BallBearing>(
            c"bb".as_ptr(),
            FMI2_CO_SIMULATION,
            g.as_ptr(),
            r.as_ref().map_or(std::ptr::null(), |r| r.as_ptr()),
            log.callbacks(),
            0,
            0,
        )
    }
}

fn vr_of(base: &Base, name: &str) -> u32 {
    table_for(&base.scene)
        .into_iter()
        .find(|e| e.var.name == name)
        .unwrap_or_else(|| panic!("{name}"))
        .var
        .vr
}

/// The Real output value references of the FMU made from `base`, in table order.
fn real_outputs(base: &Base) -> Vec<u32> {
    table_for(&base.scene)
        .into_iter()
        .filter(|e| e.var.causality == fmi2::Causality::Output && e.var.ty == fmi2::VarType::Real)
        .filter(|e| matches!(e.role, ballbearing_fmu::variables::Access::Output(_)))
        .map(|e| e.var.vr)
        .collect()
}

/// Instantiates the FMU of `res` (or of the default bearing without resources), sets the
/// parameters, initializes (no tolerance: solver.rtol) and returns the instance, or the status
/// of fmi2ExitInitializationMode and the last message when it fails.
fn initialized(
    log: &LogCapture,
    res: Option<&Resources>,
    ints: &[(&str, i32)],
    reals: &[(&str, f64)],
) -> Result<(Fmi2Component, Base), (Fmi2Status, String)> {
    let base = res.map_or_else(
        || Base::default_for(&BearingFile::default_preset()),
        Resources::base,
    );
    let uri = res.map(Resources::uri);
    let c = inst(log, &ballbearing_fmu::guid_for(&base), uri.as_deref());
    assert!(!c.is_null(), "{}", log.last());
    // SAFETY: c is a live instance; single values.
    unsafe {
        assert_eq!(
            sh::setup_experiment::<BallBearing>(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        for (name, v) in ints {
            let s = sh::set_integer::<BallBearing>(c, &vr_of(&base, name), 1, v);
            assert_eq!(s, Fmi2Status::Ok, "{name}: {}", log.last());
        }
        for (name, v) in reals {
            let s = sh::set_real::<BallBearing>(c, &vr_of(&base, name), 1, v);
            assert_eq!(s, Fmi2Status::Ok, "{name}: {}", log.last());
        }
        assert_eq!(
            sh::enter_initialization_mode::<BallBearing>(c),
            Fmi2Status::Ok
        );
        let s = sh::exit_initialization_mode::<BallBearing>(c);
        if s != Fmi2Status::Ok {
            let m = log.last();
            sh::free_instance::<BallBearing>(c);
            return Err((s, m));
        }
    }
    Ok((c, base))
}

/// Every Real output (as bits) at each of [`STEPS`] communication points, the instance freed.
fn fmu_run(c: Fmi2Component, base: &Base) -> Vec<Vec<u64>> {
    let vrs = real_outputs(base);
    let mut rows = Vec::new();
    // SAFETY: c is a live instance, freed once at the end.
    unsafe {
        for k in 0..STEPS {
            assert_eq!(
                sh::do_step::<BallBearing>(c, k as f64 * STEP, STEP, 1),
                Fmi2Status::Ok
            );
            let mut v = vec![f64::NAN; vrs.len()];
            assert_eq!(
                sh::get_real::<BallBearing>(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()),
                Fmi2Status::Ok
            );
            rows.push(v.iter().map(|x| x.to_bits()).collect());
        }
        sh::free_instance::<BallBearing>(c);
    }
    rows
}

/// Asserts that two runs are bit-equal, naming the first difference (step, output index).
fn assert_same(fmu: &[Vec<u64>], lib: &[Vec<u64>]) {
    assert_eq!(fmu.len(), lib.len());
    for (k, (a, b)) in fmu.iter().zip(lib).enumerate() {
        assert_eq!(a.len(), b.len(), "step {k}: output counts");
        if let Some(i) = a.iter().zip(b).position(|(x, y)| x != y) {
            panic!(
                "step {k}, output {i}: FMU {} library {}",
                f64::from_bits(a[i]),
                f64::from_bits(b[i])
            );
        }
    }
}

/// The same run through the library: `scene` advanced to each communication point.
fn library_run(scene: &Scene) -> Vec<Vec<u64>> {
    let mut sim = Simulation::new(scene).unwrap();
    sim.set_inputs(scene.operating).unwrap();
    let n = raceway::output_table_with_cage(scene.bearing.bearing.z as usize).len();
    let mut rows = Vec::new();
    for k in 0..STEPS {
        // t + h as fmi2DoStep(t, h) computes it
        sim.advance(k as f64 * STEP + STEP).unwrap();
        // (zeros, as the FMU starts its outputs: the level writes only its own)
        let mut out = vec![0.0; n];
        sim.try_outputs(&mut out).unwrap();
        rows.push(out.iter().map(|x| x.to_bits()).collect());
    }
    rows
}

/// An FMU made from examples/scenes/two-spalls.toml starts from its values (both spalls as
/// defect.* and defect2.*) and runs as the library runs the scene; the second spall matters
/// (the run differs from the first spall alone).
#[test]
fn a_two_spall_scene_resource_runs_as_the_library() {
    let res = Resources::new(Some(&example_as_resource("two-spalls.toml")));
    let log = LogCapture::new();
    let (c, base) = initialized(&log, Some(&res), &[], &[]).unwrap_or_else(|e| panic!("{e:?}"));
    let start = |name: &str| {
        let mut v = f64::NAN;
        // SAFETY: c is a live instance; one value.
        let s = unsafe { sh::get_real::<BallBearing>(c, &vr_of(&base, name), 1, &mut v) };
        assert_eq!(s, Fmi2Status::Ok);
        v
    };
    assert_eq!(start("defect.theta0"), 2.3562);
    assert_eq!(start("defect2.theta0"), 3.9270);
    let mut ring = 0;
    // SAFETY: c is a live instance; one value.
    unsafe { sh::get_integer::<BallBearing>(c, &vr_of(&base, "defect2.ring"), 1, &mut ring) };
    assert_eq!(ring, 1);
    let scene = example("two-spalls.toml");
    let fmu = fmu_run(c, &base);
    assert_same(&fmu, &library_run(&scene));
    let mut first_only = scene.clone();
    first_only.more_defects.clear();
    assert_ne!(
        fmu,
        library_run(&first_only),
        "the second spall changes the run"
    );
}

/// On the default FMU (no scene resource), defect2.* set to the two-spalls scene's second
/// spall (and defect.theta0 to its first) run exactly as the library runs that scene.
#[test]
fn defect2_parameters_equal_the_two_spall_scene() {
    let log = LogCapture::new();
    let (c, base) = initialized(
        &log,
        None,
        &[("defect2.ring", 1)],
        &[
            ("defect.theta0", 2.3562),
            ("defect2.width", 1.0e-3),
            ("defect2.depth", 0.2e-3),
            ("defect2.theta0", 3.9270),
        ],
    )
    .unwrap_or_else(|e| panic!("{e:?}"));
    assert_same(
        &fmu_run(c, &base),
        &library_run(&example("two-spalls.toml")),
    );
}

/// A scene resource with five spalls: spalls 1–4 are the parameters, spall 5 is fixed and
/// appended; switching a parameter spall off (defect2.ring = 0) leaves the others, the fixed
/// one included, as the library's scene without it.
#[test]
fn spalls_beyond_four_are_fixed_and_follow_the_parameter_spalls() {
    let res = Resources::new(Some(&five_outer_spalls()));
    let base = res.base();
    assert_eq!(base.scene.n_defects(), 5);
    let starts: Vec<String> = table_for(&base.scene)
        .into_iter()
        .filter(|e| e.var.name.ends_with(".theta0"))
        .map(|e| format!("{}={:?}", e.var.name, e.var.start))
        .collect();
    assert_eq!(
        starts,
        [
            "defect.theta0=Real(0.5)",
            "defect2.theta0=Real(1.7)",
            "defect3.theta0=Real(2.9)",
            "defect4.theta0=Real(4.1)"
        ]
    );
    let log = LogCapture::new();
    let (c, base) = initialized(&log, Some(&res), &[], &[]).unwrap_or_else(|e| panic!("{e:?}"));
    assert_same(&fmu_run(c, &base), &library_run(&base.scene));
    let (c, base) = initialized(&log, Some(&res), &[("defect2.ring", 0)], &[])
        .unwrap_or_else(|e| panic!("{e:?}"));
    let mut without_2 = base.scene.clone();
    let mut all: Vec<_> = without_2.defects().cloned().collect();
    all.remove(1);
    without_2.set_defects(all);
    assert_same(&fmu_run(c, &base), &library_run(&without_2));
}

/// A malformed or impossible scene resource makes fmi2Instantiate fail with a message naming
/// the file and the field (or the spalls).
#[test]
fn a_bad_scene_resource_fails_instantiate_naming_the_file_and_the_field() {
    let two = example_as_resource("two-spalls.toml");
    let ball = example_as_resource("ball-spall.toml");
    for (text, words) in [
        (
            two.replace("rtol = 1e-6", "rtol = 0.5"),
            vec!["solver.rtol"],
        ),
        (
            two.replacen(
                "depth = 0.2e-3\ntheta0 = 3.9270",
                "depth = -1.0\ntheta0 = 3.9270",
                1,
            ),
            vec!["defect[1].depth"],
        ),
        (
            two.replace("theta0 = 3.9270", "theta0 = 2.3570"),
            vec!["defect[0]", "defect[1]", "overlap"],
        ),
        (ball.replace("ball = 1", "ball = 15"), vec!["ball", "14"]),
        (
            ball.replace("fidelity = \"lumped\"", "fidelity = \"quasi_static\""),
            vec![
                "spall on a ball",
                "levels that do: kinematic, lumped, reduced, full",
            ],
        ),
        (
            two.replace("bearing = \"bearing.toml\"", "bearing = \"cwru-6205-de\""),
            vec!["bearing", "cwru-6205-de"],
        ),
        (two.replace("[solver]", "[solver"), vec!["line"]),
        (
            two.replace("[solver]", "[lumped]\nseed = 3000000000\n\n[solver]"),
            vec!["lumped.seed"],
        ),
    ] {
        let res = Resources::new(Some(&text));
        let log = LogCapture::new();
        let c = inst(&log, "{any}", Some(&res.uri()));
        assert!(c.is_null());
        let m = log.last();
        eprintln!("{m}");
        assert!(m.contains("scene.toml"), "{m}");
        assert!(words.iter().all(|w| m.contains(w)), "{words:?}: {m}");
    }
}

/// The GUID follows the scene resource: another scene, a change of a fixed part only
/// (waviness), even of a comment, gives another GUID; the FMU refuses the GUID of its bearing
/// alone; without a scene resource the GUID is the bearing's as before.
#[test]
fn the_guid_follows_the_scene_resource() {
    let b = BearingFile::default_preset();
    let plain = ballbearing_fmu::guid(&b);
    assert_eq!(
        ballbearing_fmu::guid_for(&Resources::new(None).base()),
        plain
    );
    let two = example_as_resource("two-spalls.toml");
    let wavy = example_as_resource("waviness-roughness.toml");
    let guids: Vec<String> = [
        two.clone(),
        two.replace("theta0 = 3.9270", "theta0 = 3.9300"),
        two.clone() + "# a comment\n",
        wavy.clone(),
        wavy.replace("[[13, 0.1e-6, 1.0]]", "[[13, 0.1e-6, 1.5]]"),
    ]
    .iter()
    .map(|t| ballbearing_fmu::guid_for(&Resources::new(Some(t)).base()))
    .collect();
    for (i, g) in guids.iter().enumerate() {
        assert_ne!(*g, plain);
        assert!(guids[i + 1..].iter().all(|o| o != g), "{i}: {guids:?}");
    }
    // The model description says where the start values come from.
    let xml = ballbearing_fmu::model_description_xml_for(&Resources::new(Some(&two)).base());
    assert!(xml.contains("base scene &apos;two-spalls&apos; from resources/scene.toml (SHA-256 "));
    // An FMU whose XML (GUID) is the bearing's while its resources carry a scene refuses.
    let res = Resources::new(Some(&two));
    let log = LogCapture::new();
    let c = inst(&log, &plain, Some(&res.uri()));
    assert!(c.is_null());
    assert!(
        log.last().contains("does not match this FMU"),
        "{}",
        log.last()
    );
    let c = inst(&log, &guids[0], Some(&res.uri()));
    assert!(!c.is_null(), "{}", log.last());
    // SAFETY: c is a live instance, freed once.
    unsafe { sh::free_instance::<BallBearing>(c) };
}

/// Parameter spalls the model cannot simulate are refused at fmi2ExitInitializationMode with
/// fmi2Error and a message naming the parameters, never a panic.
#[test]
fn impossible_parameter_spalls_are_refused_naming_the_parameter() {
    let pi = std::f64::consts::PI;
    for (ints, reals, words) in [
        (
            vec![("defect2.ring", 1)],
            vec![("defect2.theta0", pi + 1e-3)],
            vec!["defect.*", "defect2.*", "overlap"],
        ),
        (
            vec![("defect3.ring", 2), ("defect4.ring", 2)],
            vec![("defect3.theta0", 1.0), ("defect4.theta0", 1.0)],
            vec!["defect3.*", "defect4.*", "overlap"],
        ),
        (
            vec![("defect3.ring", 3), ("defect3.ball", 15)],
            vec![],
            vec!["defect3.ball", "14"],
        ),
        (
            vec![("fidelity", 1), ("defect2.ring", 3)],
            vec![],
            vec!["defect2.*", "spall on a ball"],
        ),
        (
            vec![("defect2.ring", 2)],
            vec![("defect2.width", 0.0)],
            vec!["defect2.width"],
        ),
        // One spall in all, the third: named by its own parameters.
        (
            vec![("defect.ring", 0), ("defect3.ring", 1)],
            vec![("defect3.depth", 0.0)],
            vec!["defect3.depth"],
        ),
    ] {
        let log = LogCapture::new();
        let r = initialized(&log, None, &ints, &reals);
        let Err((s, m)) = r else {
            panic!("{ints:?} {reals:?} accepted")
        };
        assert_eq!(s, Fmi2Status::Error, "{m}");
        eprintln!("{m}");
        assert!(words.iter().all(|w| m.contains(w)), "{words:?}: {m}");
    }
}

/// Every Real output (as bits) at communication points `k0 + 1` … `k0 + n` (steps of [`STEP`]).
fn steps(c: Fmi2Component, base: &Base, k0: usize, n: usize) -> Vec<Vec<u64>> {
    let vrs = real_outputs(base);
    let mut rows = Vec::new();
    // SAFETY: c is a live instance; the arrays outlive each call.
    unsafe {
        for k in k0..k0 + n {
            assert_eq!(
                sh::do_step::<BallBearing>(c, k as f64 * STEP, STEP, 1),
                Fmi2Status::Ok
            );
            let mut v = vec![f64::NAN; vrs.len()];
            assert_eq!(
                sh::get_real::<BallBearing>(c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()),
                Fmi2Status::Ok
            );
            rows.push(v.iter().map(|x| x.to_bits()).collect());
        }
    }
    rows
}

/// The serialized FMU state of a scene FMU carries the spall parameters (defect3.theta0 moved)
/// and restores into a fresh instance of the same FMU, whose fixed spall 5 comes from its own
/// scene resource: the continuation is bit-equal.
#[test]
fn the_fmu_state_carries_the_spall_parameters_of_a_scene_fmu() {
    let res = Resources::new(Some(&five_outer_spalls()));
    let log = LogCapture::new();
    let (c, base) = initialized(&log, Some(&res), &[], &[("defect3.theta0", 3.1)])
        .unwrap_or_else(|e| panic!("{e:?}"));
    steps(c, &base, 0, 10);
    let mut st: Fmi2FmuState = std::ptr::null_mut();
    let mut size = 0usize;
    // SAFETY: c is a live instance; the state pointer and size are written by the calls.
    let bytes = unsafe {
        assert_eq!(sh::get_fmu_state::<BallBearing>(c, &mut st), Fmi2Status::Ok);
        assert_eq!(
            sh::serialized_fmu_state_size::<BallBearing>(c, st, &mut size),
            Fmi2Status::Ok
        );
        let mut bytes: Vec<Fmi2Byte> = vec![0; size];
        assert_eq!(
            sh::serialize_fmu_state::<BallBearing>(c, st, bytes.as_mut_ptr(), size),
            Fmi2Status::Ok
        );
        bytes
    };
    let first = steps(c, &base, 10, 10);
    let (fresh, _) = initialized(&log, Some(&res), &[], &[]).unwrap_or_else(|e| panic!("{e:?}"));
    let mut st2: Fmi2FmuState = std::ptr::null_mut();
    // SAFETY: fresh is a live instance; bytes holds `size` bytes of a serialized state.
    unsafe {
        assert_eq!(
            sh::deserialize_fmu_state::<BallBearing>(fresh, bytes.as_ptr(), size, &mut st2),
            Fmi2Status::Ok
        );
        assert_eq!(sh::set_fmu_state::<BallBearing>(fresh, st2), Fmi2Status::Ok);
    }
    let mut theta = 0.0;
    // SAFETY: fresh is a live instance; one value.
    unsafe { sh::get_real::<BallBearing>(fresh, &vr_of(&base, "defect3.theta0"), 1, &mut theta) };
    assert_eq!(theta, 3.1);
    assert_eq!(steps(fresh, &base, 10, 10), first);
    // SAFETY: live instances, each freed once.
    unsafe {
        sh::free_instance::<BallBearing>(c);
        sh::free_instance::<BallBearing>(fresh);
    }
}
