//! The BallBearing model through the generic FMI shell (the code the C entry points run):
//! bearing from the resources, GUID check, parameters, initialization-mode outputs, states.

use raceway::config::BearingFile;
use raceway::fmi::ballbearing::BallBearing;
use raceway::fmi::bindings::*;
use raceway::fmi::shell as sh;
use std::ffi::{CStr, CString};
use std::os::raw::{c_char, c_void};
use std::sync::Mutex;

type Log = Mutex<Vec<String>>;

/// With the format "%s", the message is the sixth argument, passed like a fixed argument by
/// the x86-64 and aarch64 C ABIs.
unsafe extern "C" fn logger(
    env: Fmi2ComponentEnvironment,
    _name: Fmi2String,
    _status: Fmi2Status,
    _category: Fmi2String,
    _fmt: Fmi2String,
    msg: *const c_char,
) {
    let log = unsafe { &*(env as *const Log) };
    let m = unsafe { CStr::from_ptr(msg) }
        .to_string_lossy()
        .into_owned();
    log.lock().unwrap().push(m);
}

struct H {
    log: Box<Log>,
    cb: Fmi2CallbackFunctions,
}

impl H {
    fn new() -> Self {
        let log: Box<Log> = Box::default();
        let l: Fmi2CallbackLogger = unsafe { fixed_args_logger(logger) };
        let cb = Fmi2CallbackFunctions {
            logger: Some(l),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: &*log as *const Log as *mut c_void,
        };
        Self { log, cb }
    }
    fn inst(&self, guid: &str, resources: Option<&str>) -> Fmi2Component {
        let g = CString::new(guid).unwrap();
        let r = resources.map(|r| CString::new(r).unwrap());
        unsafe {
            sh::instantiate::<BallBearing>(
                c"bb".as_ptr(),
                FMI2_CO_SIMULATION,
                g.as_ptr(),
                r.as_ref().map_or(std::ptr::null(), |r| r.as_ptr()),
                &self.cb,
                0,
                0,
            )
        }
    }
    fn last(&self) -> String {
        self.log.lock().unwrap().last().cloned().unwrap_or_default()
    }
}

fn vr(b: &BearingFile, name: &str) -> u32 {
    raceway::fmi::variables::table(b)
        .into_iter()
        .find(|e| e.var.name == name)
        .unwrap_or_else(|| panic!("{name}"))
        .var
        .vr
}

fn resources_with(text: &str) -> (tempdir::Dir, String) {
    let d = tempdir::Dir::new();
    std::fs::write(d.path().join("bearing.toml"), text).unwrap();
    // percent-encode the space of the folder name, as Path.as_uri() does
    let uri = format!("file://{}", d.path().to_string_lossy().replace(' ', "%20"));
    (d, uri)
}

mod tempdir {
    use std::path::{Path, PathBuf};
    pub struct Dir(PathBuf);
    impl Dir {
        pub fn new() -> Self {
            use std::sync::atomic::{AtomicUsize, Ordering};
            static N: AtomicUsize = AtomicUsize::new(0);
            let p = std::env::temp_dir().join(format!(
                "raceway fmi test {} {}",
                std::process::id(),
                N.fetch_add(1, Ordering::SeqCst)
            ));
            std::fs::create_dir_all(&p).unwrap();
            Self(p)
        }
        pub fn path(&self) -> &Path {
            &self.0
        }
    }
    impl Drop for Dir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

#[test]
fn default_bearing_without_resources() {
    let h = H::new();
    let b = BearingFile::default_preset();
    let c = h.inst(&raceway::fmi::guid(&b), None);
    assert!(!c.is_null(), "{}", h.last());
    unsafe { sh::free_instance::<BallBearing>(c) };
    let c = h.inst(&raceway::fmi::guid(&b), Some("file:///no/such/folder"));
    assert!(!c.is_null(), "{}", h.last());
    unsafe { sh::free_instance::<BallBearing>(c) };
}

#[test]
fn bearing_from_resources_decides_the_guid() {
    let h = H::new();
    let text = raceway::config::PRESETS
        .iter()
        .find(|(n, _)| *n == "cwru-6205-de")
        .unwrap()
        .1;
    let cwru = BearingFile::load("cwru-6205-de").unwrap();
    let (_d, uri) = resources_with(text);
    let c = h.inst(&raceway::fmi::guid(&cwru), Some(&uri));
    assert!(!c.is_null(), "{}", h.last());
    unsafe { sh::free_instance::<BallBearing>(c) };
    let default_guid = raceway::fmi::guid(&BearingFile::default_preset());
    let c = h.inst(&default_guid, Some(&uri));
    assert!(c.is_null());
    assert!(h.last().contains("does not match this FMU"), "{}", h.last());
}

#[test]
fn invalid_bearing_resource_is_refused_naming_the_field() {
    let h = H::new();
    let text = raceway::config::PRESETS[0]
        .1
        .replace("f_inner = 0.515", "f_inner = 0.4");
    let (_d, uri) = resources_with(&text);
    let c = h.inst("{any}", Some(&uri));
    assert!(c.is_null());
    assert!(h.last().contains("bearing.f_inner"), "{}", h.last());
}

#[test]
fn initialization_mode_outputs_parameters_and_states() {
    let h = H::new();
    let b = BearingFile::default_preset();
    let c = h.inst(&raceway::fmi::guid(&b), None);
    assert!(!c.is_null());
    unsafe {
        assert_eq!(
            sh::setup_experiment::<BallBearing>(c, 1, 1e-7, 0.0, 1, 0.1),
            Fmi2Status::Ok
        );
        let seed = vr(&b, "lumped.seed");
        assert_eq!(
            sh::set_integer::<BallBearing>(c, &seed, 1, &7),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::enter_initialization_mode::<BallBearing>(c),
            Fmi2Status::Ok
        );
        // outputs in initialization mode: the quasi-static start, finite
        let fz = vr(&b, "bearing.F.z");
        let mut v = f64::NAN;
        assert_eq!(
            sh::get_real::<BallBearing>(c, &fz, 1, &mut v),
            Fmi2Status::Ok
        );
        assert!(v.is_finite());
        // a saved state of the instance before initialization restores
        let mut s: Fmi2FmuState = std::ptr::null_mut();
        assert_eq!(sh::get_fmu_state::<BallBearing>(c, &mut s), Fmi2Status::Ok);
        let mut got = 0;
        assert_eq!(
            sh::set_integer::<BallBearing>(c, &seed, 1, &9),
            Fmi2Status::Ok
        );
        assert_eq!(sh::set_fmu_state::<BallBearing>(c, s), Fmi2Status::Ok);
        assert_eq!(
            sh::get_integer::<BallBearing>(c, &seed, 1, &mut got),
            Fmi2Status::Ok
        );
        assert_eq!(got, 7);
        assert_eq!(sh::free_fmu_state::<BallBearing>(c, &mut s), Fmi2Status::Ok);
        assert_eq!(
            sh::exit_initialization_mode::<BallBearing>(c),
            Fmi2Status::Ok
        );
        // fixed parameters are frozen now
        assert_eq!(
            sh::set_integer::<BallBearing>(c, &seed, 1, &8),
            Fmi2Status::Error
        );
        sh::free_instance::<BallBearing>(c);
    }
}

#[test]
fn unavailable_fidelity_fails_exit_initialization_with_the_library_message() {
    let h = H::new();
    let b = BearingFile::default_preset();
    let fid = vr(&b, "fidelity");
    for code in 0..=4 {
        let c = h.inst(&raceway::fmi::guid(&b), None);
        unsafe {
            assert_eq!(
                sh::set_integer::<BallBearing>(c, &fid, 1, &code),
                Fmi2Status::Ok
            );
            assert_eq!(
                sh::enter_initialization_mode::<BallBearing>(c),
                Fmi2Status::Ok
            );
            let s = sh::exit_initialization_mode::<BallBearing>(c);
            if s != Fmi2Status::Ok {
                assert_eq!(s, Fmi2Status::Error);
                assert!(h.last().contains("unsupported"), "{code}: {}", h.last());
                // reset leads out of the error
                assert_eq!(sh::reset::<BallBearing>(c), Fmi2Status::Ok);
                assert_eq!(
                    sh::enter_initialization_mode::<BallBearing>(c),
                    Fmi2Status::Ok
                );
                assert_eq!(
                    sh::exit_initialization_mode::<BallBearing>(c),
                    Fmi2Status::Ok
                );
            }
            sh::free_instance::<BallBearing>(c);
        }
        let _ = code;
    }
    // out of range
    let c = h.inst(&raceway::fmi::guid(&b), None);
    unsafe {
        assert_eq!(
            sh::set_integer::<BallBearing>(c, &fid, 1, &5),
            Fmi2Status::Error
        );
        assert!(
            h.last()
                .contains("'fidelity' = 5 is outside its range [0, 4]"),
            "{}",
            h.last()
        );
        sh::free_instance::<BallBearing>(c);
    }
}

/// One stalled fmi2DoStep of the default scene and what the instance reports afterwards.
struct Stall {
    status: Fmi2Status,
    message: String,
    terminated: Fmi2Boolean,
    last_good: f64,
    rhs_evals: i32,
    steps: i32,
    rejected: i32,
    pedestal_z: f64,
    ring_z: f64,
    next: Fmi2Status,
    wall: f64,
}

/// Initializes the default scene (tolerance from fmi2SetupExperiment, solver.max_steps), takes
/// one 1 ms step, records the outcome, then checks that reset, a fresh initialization with the
/// defaults and a step work, and frees the instance.
fn stall(tolerance: f64, max_steps: i32) -> Stall {
    let h = H::new();
    let b = BearingFile::default_preset();
    let c = h.inst(&raceway::fmi::guid(&b), None);
    assert!(!c.is_null(), "{}", h.last());
    let (budget, rhs, steps, rejected) = (
        vr(&b, "solver.max_steps"),
        vr(&b, "solver.rhs_evals"),
        vr(&b, "solver.steps"),
        vr(&b, "solver.rejected"),
    );
    let (pz, rz) = (vr(&b, "pedestal.z"), vr(&b, "ring.z"));
    unsafe {
        assert_eq!(
            sh::setup_experiment::<BallBearing>(c, 1, tolerance, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::set_integer::<BallBearing>(c, &budget, 1, &max_steps),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::enter_initialization_mode::<BallBearing>(c),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::exit_initialization_mode::<BallBearing>(c),
            Fmi2Status::Ok
        );
        let start = std::time::Instant::now();
        let status = sh::do_step::<BallBearing>(c, 0.0, 1e-3, 1);
        let wall = start.elapsed().as_secs_f64();
        let message = h.last();
        let mut terminated = FMI2_FALSE;
        assert_eq!(
            sh::get_boolean_status::<BallBearing>(c, FMI2_TERMINATED, &mut terminated),
            Fmi2Status::Ok
        );
        let mut last_good = f64::NAN;
        assert_eq!(
            sh::get_real_status::<BallBearing>(c, FMI2_LAST_SUCCESSFUL_TIME, &mut last_good),
            Fmi2Status::Ok
        );
        let (mut rhs_evals, mut n_steps, mut n_rejected) = (-1, -1, -1);
        assert_eq!(
            sh::get_integer::<BallBearing>(c, &rejected, 1, &mut n_rejected),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::get_integer::<BallBearing>(c, &rhs, 1, &mut rhs_evals),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::get_integer::<BallBearing>(c, &steps, 1, &mut n_steps),
            Fmi2Status::Ok
        );
        let (mut pedestal_z, mut ring_z) = (f64::NAN, f64::NAN);
        assert_eq!(
            sh::get_real::<BallBearing>(c, &pz, 1, &mut pedestal_z),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::get_real::<BallBearing>(c, &rz, 1, &mut ring_z),
            Fmi2Status::Ok
        );
        let next = sh::do_step::<BallBearing>(c, last_good, 1e-3, 1);
        // The instance is still usable: reset, initialize with the defaults, step.
        assert_eq!(sh::reset::<BallBearing>(c), Fmi2Status::Ok, "{}", h.last());
        assert_eq!(
            sh::enter_initialization_mode::<BallBearing>(c),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::exit_initialization_mode::<BallBearing>(c),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::do_step::<BallBearing>(c, 0.0, 1e-3, 1),
            Fmi2Status::Ok,
            "{}",
            h.last()
        );
        sh::free_instance::<BallBearing>(c);
        Stall {
            status,
            message,
            terminated,
            last_good,
            rhs_evals,
            steps: n_steps,
            rejected: n_rejected,
            pedestal_z,
            ring_z,
            next,
            wall,
        }
    }
}

/// (accepted, rejected, RHS evaluations) of the work a failed step discarded, from its message
/// "… (work discarded with the advance: A steps accepted, R rejected, E right-hand-side
/// evaluations)".
fn discarded_work(message: &str) -> (u64, u64, u64) {
    let tail = message
        .split("work discarded with the advance: ")
        .nth(1)
        .unwrap_or_else(|| panic!("no discarded work in: {message}"));
    let n: Vec<u64> = tail
        .split(|c: char| !c.is_ascii_digit())
        .filter(|w| !w.is_empty())
        .take(3)
        .map(|w| w.parse().unwrap())
        .collect();
    (n[0], n[1], n[2])
}

/// T3 (FMU): a stall inside fmi2DoStep ends as fmi2Discard with a message, in bounded work, and
/// leaves a usable instance. Criteria, for a step budget of 3 (solver.max_steps) on the default
/// scene, whose first 1 ms step needs ~50 steps:
/// - fmi2DoStep returns fmi2Discard and the logger receives a message naming the cause ("step
///   budget") and the time;
/// - fmi2Terminated is true, fmi2LastSuccessfulTime is the step's start (0), further
///   fmi2DoStep calls are refused (fmi2Error), fmi2GetReal returns the outputs of that point
///   (the pedestal at its static deflection −Fr/k_z within 2 %);
/// - the work is bounded by counts, not by time: at most 3 attempted steps (accepted + rejected,
///   as the message reports the discarded work) in the whole communication step, spall stops
///   and contact events included, and at most 16 RHS evaluations per attempt (DOP853: 12
///   stages, 3 for the dense output, 1 restart) plus 2 for the initial step size; a wall-time
///   sanity bound of 20 s; the counters solver.steps, solver.rejected, solver.rhs_evals read
///   those of the last good point (0);
/// - fmi2Reset, a new initialization and a step then succeed, and the instance frees.
///
/// An unattainable tolerance (1e-18, below round-off) is refused by fmi2SetupExperiment with a
/// message naming it: measured before this check, DOP853 at 1e-18 did not fail but crawled at
/// 1e-9 s steps (7761 wall s per simulated s).
#[test]
fn t3_fmu_stall_ends_as_discard_with_a_message_in_bounded_work() {
    let b = BearingFile::default_preset();
    let zp = -1000.0 / b.pedestal.k_z; // default scene: Fr = 1000 N
    let s = stall(1e-6, 3);
    assert_eq!(s.status, Fmi2Status::Discard, "{}", s.message);
    assert!(
        s.message.contains("discarded") && s.message.contains("step budget"),
        "{}",
        s.message
    );
    assert_eq!(s.terminated, FMI2_TRUE);
    assert_eq!(s.last_good, 0.0);
    assert_eq!(s.next, Fmi2Status::Error);
    assert!(s.pedestal_z.is_finite() && s.ring_z.is_finite());
    assert!(
        (s.pedestal_z - zp).abs() < 0.02 * zp.abs(),
        "pedestal.z {} vs {zp}",
        s.pedestal_z
    );
    assert_eq!((s.steps, s.rejected, s.rhs_evals), (0, 0, 0));
    let (accepted, rejected, rhs_evals) = discarded_work(&s.message);
    let attempts = accepted + rejected;
    assert!((1..=3).contains(&attempts), "{attempts} attempted steps");
    assert!(
        rhs_evals <= 16 * attempts + 2,
        "{rhs_evals} RHS evaluations for {attempts} attempted steps"
    );
    assert!(s.wall < 20.0, "{} s", s.wall);
    eprintln!(
        "T3 FMU stall: last good t = {:.6e} s, {accepted} steps + {rejected} rejected, \
         {rhs_evals} RHS, {:.4} s wall: {}",
        s.last_good, s.wall, s.message
    );

    let h = H::new();
    let c = h.inst(&raceway::fmi::guid(&b), None);
    unsafe {
        assert_eq!(
            sh::setup_experiment::<BallBearing>(c, 1, 1e-18, 0.0, 0, 0.0),
            Fmi2Status::Error
        );
        assert!(h.last().contains("tolerance = 1e-18"), "{}", h.last());
        sh::free_instance::<BallBearing>(c);
    }
}
