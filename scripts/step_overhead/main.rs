//! Wall time of 1 s of the default scene in 1e-4 s communication steps, through the library
//! (advance + read every output) and through the FMU shell in-process (fmi2DoStep + fmi2GetReal
//! of every Real output). Prints one line per repeat: mode level seconds.
//!
//! Builds against both layouts of the repository: before the workspace split (the FMI shell in
//! `raceway::fmi`) and after it (feature `split`: the `fmi2` and `ballbearing-fmu` crates), as
//! scripts/step_overhead.sh chooses.
use api::*;
use std::ffi::CString;
use std::os::raw::{c_char, c_void};
use std::time::Instant;

#[cfg(not(feature = "split"))]
mod api {
    pub use raceway::config::BearingFile;
    pub use raceway::fmi::ballbearing::BallBearing;
    pub use raceway::fmi::bindings::*;
    pub use raceway::fmi::shell as sh;
    pub use raceway::scene::{Fidelity, Scene};
    pub use raceway::simulation::Simulation;
    use raceway::fmi::shell::{Causality, VarType};

    pub fn guid(b: &BearingFile) -> String {
        raceway::fmi::guid(b)
    }

    /// (value reference, name, is a Real output) of every variable.
    pub fn vars(b: &BearingFile) -> Vec<(u32, String, bool)> {
        raceway::fmi::variables::table(b)
            .into_iter()
            .map(|e| {
                let out = e.var.causality == Causality::Output && e.var.ty == VarType::Real;
                (e.var.vr, e.var.name, out)
            })
            .collect()
    }
}

#[cfg(feature = "split")]
mod api {
    pub use ballbearing_fmu::ballbearing::BallBearing;
    pub use fmi2::bindings::*;
    pub use fmi2::functions as sh;
    use fmi2::{Causality, VarType};
    pub use raceway::{BearingFile, Fidelity, Scene, Simulation};

    pub fn guid(b: &BearingFile) -> String {
        ballbearing_fmu::guid(b)
    }

    /// (value reference, name, is a Real output) of every variable.
    pub fn vars(b: &BearingFile) -> Vec<(u32, String, bool)> {
        ballbearing_fmu::variables::table(b)
            .into_iter()
            .map(|e| {
                let out = e.var.causality == Causality::Output && e.var.ty == VarType::Real;
                (e.var.vr, e.var.name, out)
            })
            .collect()
    }
}

unsafe extern "C" fn quiet(
    _env: Fmi2ComponentEnvironment,
    _name: Fmi2String,
    _status: Fmi2Status,
    _category: Fmi2String,
    _fmt: Fmi2String,
    _msg: *const c_char,
) {
}

const H: f64 = 1e-4;
const N: usize = 10_000;

fn library(level: Fidelity) -> f64 {
    let mut s = Scene::default_scene();
    s.fidelity = level;
    let mut sim = Simulation::new(&s).unwrap();
    let mut o = vec![0.0; sim.output_table().len()];
    let t0 = Instant::now();
    for k in 1..=N {
        sim.advance(k as f64 * H).unwrap();
        sim.outputs(&mut o);
    }
    let w = t0.elapsed().as_secs_f64();
    std::hint::black_box(&o);
    w
}

fn fmu(level: Fidelity) -> f64 {
    let b = BearingFile::default_preset();
    let guid = CString::new(guid(&b)).unwrap();
    let vars = vars(&b);
    let outs: Vec<u32> = vars.iter().filter(|v| v.2).map(|v| v.0).collect();
    let fid = vars.iter().find(|v| v.1 == "fidelity").unwrap().0;
    let cb = Fmi2CallbackFunctions {
        logger: Some(unsafe { fixed_args_logger(quiet) }),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut::<c_void>(),
    };
    let mut v = vec![0.0; outs.len()];
    unsafe {
        let c = sh::instantiate::<BallBearing>(
            c"bench".as_ptr(),
            FMI2_CO_SIMULATION,
            guid.as_ptr(),
            std::ptr::null(),
            &cb,
            0,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(
            sh::set_integer::<BallBearing>(c, &fid, 1, &level.code()),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::setup_experiment::<BallBearing>(c, 0, 0.0, 0.0, 0, 0.0),
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
        let t0 = Instant::now();
        let mut t = 0.0;
        for _ in 0..N {
            assert_eq!(sh::do_step::<BallBearing>(c, t, H, 1), Fmi2Status::Ok);
            t += H;
            assert_eq!(
                sh::get_real::<BallBearing>(c, outs.as_ptr(), outs.len(), v.as_mut_ptr()),
                Fmi2Status::Ok
            );
        }
        let w = t0.elapsed().as_secs_f64();
        sh::free_instance::<BallBearing>(c);
        w
    }
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let level = Fidelity::from_name(&a[1]).unwrap();
    let reps: usize = a[2].parse().unwrap();
    for _ in 0..reps {
        println!("library {} {:.6}", level.name(), library(level));
        println!("fmu {} {:.6}", level.name(), fmu(level));
    }
}
