//! Wall time of 1 s of the default scene in 1e-4 s communication steps, through the library
//! (advance + read every output) and through the FMU shell in-process (fmi2DoStep + fmi2GetReal
//! of every Real output). Prints one line per repeat: mode level seconds.
use raceway::config::BearingFile;
use raceway::fmi::ballbearing::BallBearing;
use raceway::fmi::bindings::*;
use raceway::fmi::shell as sh;
use raceway::scene::{Fidelity, Scene};
use raceway::simulation::Simulation;
use std::ffi::CString;
use std::os::raw::{c_char, c_void};
use std::time::Instant;

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
    let guid = CString::new(raceway::fmi::guid(&b)).unwrap();
    let outs: Vec<u32> = raceway::fmi::variables::table(&b)
        .into_iter()
        .filter(|e| e.var.causality == sh::Causality::Output && e.var.ty == sh::VarType::Real)
        .map(|e| e.var.vr)
        .collect();
    let fid = raceway::fmi::variables::table(&b)
        .into_iter()
        .find(|e| e.var.name == "fidelity")
        .unwrap()
        .var
        .vr;
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
