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
