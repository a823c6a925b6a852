//! Tests of the generic shell with a toy model (a damped oscillator), through the same generic
//! functions the C entry points call.

use fmi2::bindings::*;
use fmi2::codec::{ByteReader, ByteWriter};
use fmi2::functions as sh;
use fmi2::*;
use std::ffi::{CStr, CString};
use std::os::raw::{c_char, c_void};
use std::sync::Mutex;

/// x'' = −k x − c x' + u, integrated by RK4 with sub-steps ≤ 1 ms ending exactly at t_end.
#[derive(Clone)]
struct Toy {
    vars: Vec<Variable>,
    guid: String,
    k: f64,
    c: f64,
    fail_at: f64,
    panic_at: f64,
    flag: bool,
    label: String,
    u: f64,
    x: f64,
    v: f64,
    t: f64,
    steps: i32,
    ready: bool,
}

const GUID: &str = "{toy-oscillator-1}";

fn var(
    vr: u32,
    name: &str,
    ty: VarType,
    causality: Causality,
    variability: Variability,
    start: Start,
) -> Variable {
    Variable {
        vr,
        name: name.into(),
        ty,
        causality,
        variability,
        initial: None,
        description: String::new(),
        unit: None,
        declared_type: None,
        display_unit: None,
        start,
        min: None,
        max: None,
        derivative_of: None,
    }
}

impl Toy {
    fn fresh() -> Self {
        use Causality::*;
        use Variability::*;
        let mut vars = vec![
            var(1, "x", VarType::Real, Output, Continuous, Start::None),
            var(2, "v", VarType::Real, Output, Continuous, Start::None),
            var(3, "u", VarType::Real, Input, Continuous, Start::Real(0.0)),
            var(4, "k", VarType::Real, Parameter, Fixed, Start::Real(100.0)),
            var(5, "c", VarType::Real, Parameter, Tunable, Start::Real(1.0)),
            var(
                6,
                "fail_at",
                VarType::Real,
                Parameter,
                Fixed,
                Start::Real(1e9),
            ),
            var(
                7,
                "panic_at",
                VarType::Real,
                Parameter,
                Fixed,
                Start::Real(1e9),
            ),
            var(8, "steps", VarType::Integer, Output, Discrete, Start::None),
            var(
                9,
                "flag",
                VarType::Boolean,
                Parameter,
                Fixed,
                Start::Boolean(false),
            ),
            var(
                10,
                "label",
                VarType::String,
                Parameter,
                Fixed,
                Start::String("a".into()),
            ),
        ];
        vars[3].min = Some(0.0);
        vars[3].max = Some(1e6);
        Self {
            vars,
            guid: GUID.into(),
            k: 100.0,
            c: 1.0,
            fail_at: 1e9,
            panic_at: 1e9,
            flag: false,
            label: "a".into(),
            u: 0.0,
            x: 1.0,
            v: 0.0,
            t: 0.0,
            steps: 0,
            ready: false,
        }
    }

    fn rhs(&self, x: f64, v: f64) -> (f64, f64) {
        (v, -self.k * x - self.c * v + self.u)
    }
}

impl FmuModel for Toy {
    const MODEL_IDENTIFIER: &'static str = "Toy";

    fn instantiate(args: &InstantiateArgs, _log: &Logger) -> Result<Self, String> {
        if args.instance_name == "refuse" {
            return Err("refused by the model".into());
        }
        Ok(Self::fresh())
    }
    fn guid(&self) -> &str {
        &self.guid
    }
    fn variables(&self) -> &[Variable] {
        &self.vars
    }
    fn setup_experiment(
        &mut self,
        _tol: Option<f64>,
        start: f64,
        _stop: Option<f64>,
    ) -> Result<(), String> {
        self.t = start;
        Ok(())
    }
    fn exit_initialization(&mut self, _log: &Logger) -> Result<(), String> {
        if self.k == 0.0 {
            return Err("k: must be > 0".into());
        }
        self.ready = true;
        Ok(())
    }
    fn do_step(&mut self, t: f64, t_end: f64, log: &Logger) -> StepResult {
        assert_eq!(t, self.t);
        if t_end > self.panic_at {
            panic!("toy panic requested at {t_end}");
        }
        if t_end > self.fail_at {
            return StepResult::Discard {
                message: format!("step size underflow near {}", self.fail_at),
                last_good_time: t,
            };
        }
        let n = ((t_end - t) / 1e-3).ceil().max(1.0) as usize;
        let h = (t_end - t) / n as f64;
        for _ in 0..n {
            let (x, v) = (self.x, self.v);
            let k1 = self.rhs(x, v);
            let k2 = self.rhs(x + 0.5 * h * k1.0, v + 0.5 * h * k1.1);
            let k3 = self.rhs(x + 0.5 * h * k2.0, v + 0.5 * h * k2.1);
            let k4 = self.rhs(x + h * k3.0, v + h * k3.1);
            self.x += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            self.v += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            self.steps += 1;
        }
        self.t = t_end;
        log.log(Fmi2Status::Ok, LOG_SOLVER, &format!("{n} steps"));
        StepResult::Ok
    }
    fn reset(&mut self) -> Result<(), String> {
        *self = Self::fresh();
        Ok(())
    }
    fn get_real(&mut self, i: usize) -> Result<f64, String> {
        Ok(match self.vars[i].vr {
            1 => self.x,
            2 => self.v,
            3 => self.u,
            4 => self.k,
            5 => self.c,
            6 => self.fail_at,
            7 => self.panic_at,
            _ => unreachable!(),
        })
    }
    fn set_real(&mut self, i: usize, value: f64) -> Result<(), String> {
        match self.vars[i].vr {
            3 => self.u = value,
            4 => self.k = value,
            // A refusal only the model can make (no declared bounds on c).
            5 if value > 1e3 => return Err(format!("c = {value} is refused by the model")),
            5 => self.c = value,
            6 => self.fail_at = value,
            7 => self.panic_at = value,
            _ => unreachable!(),
        }
        Ok(())
    }
    fn get_integer(&mut self, _i: usize) -> Result<i32, String> {
        Ok(self.steps)
    }
    fn get_boolean(&mut self, _i: usize) -> Result<bool, String> {
        Ok(self.flag)
    }
    fn set_boolean(&mut self, _i: usize, v: bool) -> Result<(), String> {
        self.flag = v;
        Ok(())
    }
    fn get_string(&mut self, _i: usize) -> Result<String, String> {
        Ok(self.label.clone())
    }
    fn set_string(&mut self, _i: usize, v: &str) -> Result<(), String> {
        if v == "refused" {
            return Err("label 'refused' is refused by the model".into());
        }
        self.label = v.to_string();
        Ok(())
    }
    type Undo = Box<Toy>;
    fn begin_set(&self, _indices: &[usize]) -> Box<Toy> {
        Box::new(self.clone())
    }
    fn rollback_set(&mut self, undo: Box<Toy>) -> Result<(), String> {
        *self = *undo;
        Ok(())
    }
    fn save_state(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.u32(1)
            .f64(self.k)
            .f64(self.c)
            .f64(self.fail_at)
            .f64(self.panic_at)
            .bool(self.flag)
            .str(&self.label)
            .f64(self.u)
            .f64(self.x)
            .f64(self.v)
            .f64(self.t)
            .u32(self.steps as u32)
            .bool(self.ready);
        w.into_bytes()
    }
    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let mut r = ByteReader::new(bytes);
        if r.u32("version")? != 1 {
            return Err("toy state version".into());
        }
        let mut n = self.clone();
        n.k = r.f64("k")?;
        n.c = r.f64("c")?;
        n.fail_at = r.f64("fail_at")?;
        n.panic_at = r.f64("panic_at")?;
        n.flag = r.bool("flag")?;
        n.label = r.str("label")?.to_string();
        n.u = r.f64("u")?;
        n.x = r.f64("x")?;
        n.v = r.f64("v")?;
        n.t = r.f64("t")?;
        n.steps = r.u32("steps")? as i32;
        n.ready = r.bool("ready")?;
        r.finish("toy state")?;
        *self = n;
        Ok(())
    }
}

// --- test harness ------------------------------------------------------------------------------

type Log = Mutex<Vec<(i32, String, String)>>;

/// Non-variadic stand-in for the importer's logger: with "%s" the message is the 6th argument,
/// which the x86-64/aarch64 C ABIs pass exactly like a fixed argument.
unsafe extern "C" fn test_logger(
    env: Fmi2ComponentEnvironment,
    _name: Fmi2String,
    status: Fmi2Status,
    category: Fmi2String,
    fmt: Fmi2String,
    msg: *const c_char,
) {
    // SAFETY: env is the Box<Log> this harness registered, alive as long as the harness.
    let log = unsafe { &*(env as *const Log) };
    // SAFETY: the shell passes NUL-terminated strings valid during the call.
    let fmt = unsafe { CStr::from_ptr(fmt) }
        .to_string_lossy()
        .into_owned();
    assert_eq!(fmt, "%s");
    // SAFETY: as above.
    let cat = unsafe { CStr::from_ptr(category) }
        .to_string_lossy()
        .into_owned();
    // SAFETY: as above.
    let msg = unsafe { CStr::from_ptr(msg) }
        .to_string_lossy()
        .into_owned();
    log.lock().unwrap().push((status as i32, cat, msg));
}

struct Harness {
    log: Box<Log>,
    cb: Box<Fmi2CallbackFunctions>,
}

impl Harness {
    fn new() -> Self {
        let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
        // SAFETY: see test_logger.
        let logger: Fmi2CallbackLogger = unsafe { fixed_args_logger(test_logger) };
        let cb = Box::new(Fmi2CallbackFunctions {
            logger: Some(logger),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: &*log as *const Log as *mut c_void,
        });
        Self { log, cb }
    }

    fn inst_named(&self, name: &str, guid: &str, logging: bool) -> Fmi2Component {
        let n = CString::new(name).unwrap();
        let g = CString::new(guid).unwrap();
        // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
        // and strings passed outlive the call (FMI 2.0 pointer rules).
        unsafe {
            sh::instantiate::<Toy>(
                n.as_ptr(),
                FMI2_CO_SIMULATION,
                g.as_ptr(),
                c"file:///nonexistent/resources".as_ptr(),
                &*self.cb,
                0,
                logging as i32,
            )
        }
    }

    fn inst(&self) -> Fmi2Component {
        self.inst_named("toy", GUID, false)
    }

    fn messages(&self) -> Vec<String> {
        self.log
            .lock()
            .unwrap()
            .iter()
            .map(|m| m.2.clone())
            .collect()
    }

    fn last(&self) -> String {
        self.messages().last().cloned().unwrap_or_default()
    }
}

fn ready(h: &Harness) -> Fmi2Component {
    let c = h.inst();
    assert!(!c.is_null());
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        assert_eq!(
            sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 1, 10.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
    }
    c
}

fn get(c: Fmi2Component, vrs: &[u32]) -> Vec<f64> {
    let mut out = vec![0.0; vrs.len()];
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    let s = unsafe { sh::get_real::<Toy>(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
    assert_eq!(s, Fmi2Status::Ok);
    out
}

fn set(c: Fmi2Component, vr: u32, v: f64) -> Fmi2Status {
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe { sh::set_real::<Toy>(c, &vr, 1, &v) }
}

fn run(c: Fmi2Component, t0: f64, h: f64, n: usize) -> Vec<[f64; 2]> {
    let mut t = t0;
    let mut out = Vec::new();
    for _ in 0..n {
        // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
        // and strings passed outlive the call (FMI 2.0 pointer rules).
        assert_eq!(unsafe { sh::do_step::<Toy>(c, t, h, 0) }, Fmi2Status::Ok);
        t += h;
        let v = get(c, &[1, 2]);
        out.push([v[0], v[1]]);
    }
    out
}

fn free(c: Fmi2Component) {
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe { sh::free_instance::<Toy>(c) }
}

#[test]
fn happy_path_and_exact_time() {
    let h = Harness::new();
    let c = ready(&h);
    let r = run(c, 0.0, 0.01, 100);
    // no drift: the FMU's time is the master's t + h
    let mut t = 0.0;
    for _ in 0..100 {
        t += 0.01;
    }
    // SAFETY: c is a live instance of Toy from instantiate, and no call is running on it.
    let inst = unsafe { &*(c as *const Instance<Toy>) };
    assert_eq!(inst.time(), t);
    assert!(r.iter().all(|v| v[0].is_finite()));
    let x_exact = {
        let w = (100.0f64 - 0.25).sqrt();
        (-0.5 * 1.0f64).exp() * ((w * 1.0).cos() + 0.5 / w * (w * 1.0).sin())
    };
    assert!(
        (r[99][0] - x_exact).abs() < 1e-6,
        "{} vs {x_exact}",
        r[99][0]
    );
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        assert_eq!(sh::terminate::<Toy>(c), Fmi2Status::Ok);
    }
    free(c);
}

#[test]
fn illegal_call_sequences() {
    let h = Harness::new();
    let c = h.inst();
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 0.1, 0), Fmi2Status::Error);
        assert!(
            h.last().starts_with("fmi2DoStep: illegal call sequence"),
            "{}",
            h.last()
        );
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Error);
        assert!(h.last().contains("illegal call sequence"));
        let mut x = 0.0;
        assert_eq!(sh::get_real::<Toy>(c, &1, 1, &mut x), Fmi2Status::Error);
        assert_eq!(sh::terminate::<Toy>(c), Fmi2Status::Error);
        // the rejected calls had no effect
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(
            sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Error
        );
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Error);
        assert_eq!(sh::cancel_step::<Toy>(c), Fmi2Status::Error);
        assert_eq!(sh::terminate::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 0.1, 0), Fmi2Status::Error);
        assert_eq!(sh::reset::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 0.1, 0), Fmi2Status::Error);
    }
    free(c);
    // NULL component everywhere
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        let n = std::ptr::null_mut();
        assert_eq!(sh::do_step::<Toy>(n, 0.0, 0.1, 0), Fmi2Status::Error);
        assert_eq!(sh::reset::<Toy>(n), Fmi2Status::Error);
        sh::free_instance::<Toy>(n);
    }
}

#[test]
fn do_step_arguments() {
    let h = Harness::new();
    let c = ready(&h);
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 0.0, 0), Fmi2Status::Error);
        assert!(
            h.last().contains("communicationStepSize = 0"),
            "{}",
            h.last()
        );
        assert_eq!(sh::do_step::<Toy>(c, 0.0, -0.1, 0), Fmi2Status::Error);
        assert_eq!(sh::do_step::<Toy>(c, 0.0, f64::NAN, 0), Fmi2Status::Error);
        assert_eq!(sh::do_step::<Toy>(c, 0.5, 0.1, 0), Fmi2Status::Error);
        assert!(
            h.last().contains("does not match the FMU's time 0"),
            "{}",
            h.last()
        );
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 11.0, 0), Fmi2Status::Error);
        assert!(h.last().contains("past the stop time 10"), "{}", h.last());
        // still usable; a tiny rounding difference in t is accepted
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 0.1, 0), Fmi2Status::Ok);
        assert_eq!(sh::do_step::<Toy>(c, 0.1 + 1e-15, 0.1, 0), Fmi2Status::Ok);
        // exactly to the stop time
        let t = (&*(c as *const Instance<Toy>)).time();
        assert_eq!(sh::do_step::<Toy>(c, t, 10.0 - t, 0), Fmi2Status::Ok);
    }
    free(c);
}

#[test]
fn set_rules_and_value_checks() {
    let h = Harness::new();
    let c = h.inst();
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        // parameters and inputs before initialization
        assert_eq!(set(c, 4, 50.0), Fmi2Status::Ok);
        assert_eq!(set(c, 1, 1.0), Fmi2Status::Error);
        assert!(
            h.last()
                .contains("'x' (value reference 1) is a calculated output"),
            "{}",
            h.last()
        );
        assert_eq!(set(c, 99, 1.0), Fmi2Status::Error);
        assert!(h.last().contains("unknown value reference 99"));
        assert_eq!(set(c, 3, f64::NAN), Fmi2Status::Error);
        assert!(
            h.last().contains("'u' = NaN is not a finite number"),
            "{}",
            h.last()
        );
        assert_eq!(set(c, 4, -1.0), Fmi2Status::Error);
        assert!(
            h.last()
                .contains("'k' = -1 is outside its range [0, 1000000]"),
            "{}",
            h.last()
        );
        let one = 1;
        assert_eq!(sh::set_integer::<Toy>(c, &4, 1, &one), Fmi2Status::Error);
        assert!(
            h.last().contains("a Real variable, not a Integer"),
            "{}",
            h.last()
        );
        assert_eq!(
            sh::set_real::<Toy>(c, std::ptr::null(), 1, &1.0),
            Fmi2Status::Error
        );
        assert_eq!(
            sh::set_real::<Toy>(c, std::ptr::null(), 0, std::ptr::null()),
            Fmi2Status::Ok
        );
        assert_eq!(sh::set_boolean::<Toy>(c, &9, 1, &one), Fmi2Status::Ok);
        let s = c"hello".as_ptr();
        assert_eq!(sh::set_string::<Toy>(c, &10, 1, &s), Fmi2Status::Ok);
        assert_eq!(
            sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(set(c, 4, 100.0), Fmi2Status::Ok);
        // 'u' still holds its value from before the refused NaN: the model does not run on it
        // (and the call has no effect) until it is set again.
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Error);
        assert!(
            h.last()
                .contains("'u' still holds its value from before a refused set (fmi2SetReal refused 'u' = NaN)"),
            "{}",
            h.last()
        );
        assert_eq!(set(c, 3, 0.0), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        // after initialization: fixed parameters refused, tunable ones and inputs accepted
        assert_eq!(set(c, 4, 10.0), Fmi2Status::Error);
        assert!(
            h.last().contains("'k' is a fixed parameter"),
            "{}",
            h.last()
        );
        assert_eq!(set(c, 5, 2.0), Fmi2Status::Ok);
        assert_eq!(set(c, 3, 2.0), Fmi2Status::Ok);
        assert_eq!(get(c, &[3, 4, 5]), vec![2.0, 100.0, 2.0]);
        let mut b = 0;
        assert_eq!(sh::get_boolean::<Toy>(c, &9, 1, &mut b), Fmi2Status::Ok);
        assert_eq!(b, 1);
        let mut p: Fmi2String = std::ptr::null();
        assert_eq!(sh::get_string::<Toy>(c, &10, 1, &mut p), Fmi2Status::Ok);
        assert_eq!(CStr::from_ptr(p).to_str().unwrap(), "hello");
        let mut out = [0.0; 2];
        assert_eq!(
            sh::get_real::<Toy>(c, [1, 77].as_ptr(), 2, out.as_mut_ptr()),
            Fmi2Status::Error
        );
        assert_eq!(
            sh::get_real::<Toy>(c, [1].as_ptr(), 1, std::ptr::null_mut()),
            Fmi2Status::Error
        );
    }
    free(c);
}

#[test]
fn instantiate_checks() {
    let h = Harness::new();
    assert!(h.inst_named("toy", "{wrong}", false).is_null());
    assert!(
        h.last().contains("GUID {wrong} does not match this FMU"),
        "{}",
        h.last()
    );
    assert!(h.inst_named("", GUID, false).is_null());
    assert!(h.last().contains("instance name is empty"));
    assert!(h.inst_named("refuse", GUID, false).is_null());
    assert!(h.last().contains("refused by the model"));
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        let me = sh::instantiate::<Toy>(
            c"x".as_ptr(),
            FMI2_MODEL_EXCHANGE,
            c"{toy-oscillator-1}".as_ptr(),
            std::ptr::null(),
            &*h.cb,
            0,
            0,
        );
        assert!(me.is_null());
        assert!(h.last().contains("Co-Simulation"), "{}", h.last());
        let mut no_logger = *h.cb;
        no_logger.logger = None;
        let c = sh::instantiate::<Toy>(
            c"x".as_ptr(),
            FMI2_CO_SIMULATION,
            c"{toy-oscillator-1}".as_ptr(),
            std::ptr::null(),
            &no_logger,
            0,
            0,
        );
        assert!(c.is_null());
        let c = sh::instantiate::<Toy>(
            c"x".as_ptr(),
            FMI2_CO_SIMULATION,
            c"{toy-oscillator-1}".as_ptr(),
            std::ptr::null(),
            std::ptr::null(),
            0,
            0,
        );
        assert!(c.is_null());
    }
}

#[test]
fn logging_categories() {
    let h = Harness::new();
    let c = ready(&h);
    let before = h.messages().len();
    run(c, 0.0, 0.01, 1);
    assert_eq!(h.messages().len(), before, "logging is off");
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        let cats = [c"logSolver".as_ptr()];
        assert_eq!(
            sh::set_debug_logging::<Toy>(c, 1, 1, cats.as_ptr()),
            Fmi2Status::Ok
        );
        assert_eq!(sh::do_step::<Toy>(c, 0.01, 0.01, 0), Fmi2Status::Ok);
        assert_eq!(h.last(), "10 steps");
        let bad = [c"logNonsense".as_ptr()];
        assert_eq!(
            sh::set_debug_logging::<Toy>(c, 1, 1, bad.as_ptr()),
            Fmi2Status::Error
        );
        assert!(h.last().contains("unknown log category 'logNonsense'"));
        assert!(h.last().contains("logEvents, logSolver"), "{}", h.last());
        assert_eq!(
            sh::set_debug_logging::<Toy>(c, 1, 1, std::ptr::null()),
            Fmi2Status::Error
        );
        assert_eq!(
            sh::set_debug_logging::<Toy>(c, 0, 0, std::ptr::null()),
            Fmi2Status::Ok
        );
        let n = h.messages().len();
        assert_eq!(sh::do_step::<Toy>(c, 0.02, 0.01, 0), Fmi2Status::Ok);
        assert_eq!(h.messages().len(), n);
    }
    free(c);
}

#[test]
fn discard_then_status_and_reset() {
    let h = Harness::new();
    let c = h.inst();
    assert_eq!(set(c, 6, 0.25), Fmi2Status::Ok);
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        let mut t = 0.0;
        for _ in 0..2 {
            assert_eq!(sh::do_step::<Toy>(c, t, 0.1, 0), Fmi2Status::Ok);
            t += 0.1;
        }
        assert_eq!(sh::do_step::<Toy>(c, t, 0.1, 0), Fmi2Status::Discard);
        assert!(h.last().contains("step size underflow"), "{}", h.last());
        let mut term = 0;
        assert_eq!(
            sh::get_boolean_status::<Toy>(c, FMI2_TERMINATED, &mut term),
            Fmi2Status::Ok
        );
        assert_eq!(term, 1);
        let mut last = -1.0;
        assert_eq!(
            sh::get_real_status::<Toy>(c, FMI2_LAST_SUCCESSFUL_TIME, &mut last),
            Fmi2Status::Ok
        );
        assert_eq!(last, t);
        let mut st = Fmi2Status::Ok;
        assert_eq!(
            sh::get_status::<Toy>(c, FMI2_DO_STEP_STATUS, &mut st),
            Fmi2Status::Discard
        );
        assert!(get(c, &[1])[0].is_finite());
        assert_eq!(sh::do_step::<Toy>(c, t, 0.1, 0), Fmi2Status::Error);
        assert_eq!(sh::terminate::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::reset::<Toy>(c), Fmi2Status::Ok);
    }
    // after reset: exactly like a fresh instance
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
    }
    let a = run(c, 0.0, 0.05, 20);
    let h2 = Harness::new();
    let d = ready(&h2);
    let b = run(d, 0.0, 0.05, 20);
    assert_eq!(a, b);
    free(c);
    free(d);
}

#[test]
fn panic_becomes_fatal() {
    let h = Harness::new();
    let c = h.inst();
    assert_eq!(set(c, 7, 0.05), Fmi2Status::Ok);
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 0.1, 0), Fmi2Status::Fatal);
        assert!(h.last().contains("toy panic requested"), "{}", h.last());
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 0.1, 0), Fmi2Status::Error);
        assert_eq!(sh::reset::<Toy>(c), Fmi2Status::Error);
    }
    free(c);
}

#[test]
fn fmu_state_get_set_serialize() {
    let h = Harness::new();
    let c = ready(&h);
    run(c, 0.0, 0.01, 10);
    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
    // and strings passed outlive the call (FMI 2.0 pointer rules).
    unsafe {
        let mut s: Fmi2FmuState = std::ptr::null_mut();
        assert_eq!(sh::get_fmu_state::<Toy>(c, &mut s), Fmi2Status::Ok);
        let a = run(c, 0.1, 0.01, 10);
        assert_eq!(sh::set_fmu_state::<Toy>(c, s), Fmi2Status::Ok);
        let b = run(c, 0.1, 0.01, 10);
        assert_eq!(a, b);
        // serialize, deserialize into another instance, continue bit-identically
        let mut size = 0usize;
        assert_eq!(
            sh::serialized_fmu_state_size::<Toy>(c, s, &mut size),
            Fmi2Status::Ok
        );
        let mut buf = vec![0 as c_char; size];
        assert_eq!(
            sh::serialize_fmu_state::<Toy>(c, s, buf.as_mut_ptr(), size),
            Fmi2Status::Ok
        );
        assert_eq!(
            sh::serialize_fmu_state::<Toy>(c, s, buf.as_mut_ptr(), size - 1),
            Fmi2Status::Error
        );
        let h2 = Harness::new();
        let d = h2.inst();
        let mut s2: Fmi2FmuState = std::ptr::null_mut();
        assert_eq!(
            sh::deserialize_fmu_state::<Toy>(d, buf.as_ptr(), size, &mut s2),
            Fmi2Status::Ok
        );
        assert_eq!(sh::set_fmu_state::<Toy>(d, s2), Fmi2Status::Ok);
        let c2 = run(d, 0.1, 0.01, 10);
        assert_eq!(a, c2);
        // truncated, corrupted, foreign blobs
        let mut s3: Fmi2FmuState = std::ptr::null_mut();
        for cut in [0, 5, 12, size / 2, size - 1] {
            assert_eq!(
                sh::deserialize_fmu_state::<Toy>(d, buf.as_ptr(), cut, &mut s3),
                Fmi2Status::Error,
                "cut {cut}"
            );
        }
        let mut bad = buf.clone();
        bad[size / 2] ^= 1;
        assert_eq!(
            sh::deserialize_fmu_state::<Toy>(d, bad.as_ptr(), size, &mut s3),
            Fmi2Status::Error
        );
        assert!(h2.last().contains("checksum"), "{}", h2.last());
        let junk = [7 as c_char; 64];
        assert_eq!(
            sh::deserialize_fmu_state::<Toy>(d, junk.as_ptr(), 64, &mut s3),
            Fmi2Status::Error
        );
        assert!(h2.last().contains("bad magic"), "{}", h2.last());
        assert_eq!(
            sh::deserialize_fmu_state::<Toy>(d, std::ptr::null(), 10, &mut s3),
            Fmi2Status::Error
        );
        assert!(s3.is_null());
        // a state from a different GUID
        let mut other = buf.iter().map(|&b| b as u8).collect::<Vec<u8>>();
        let pos = other
            .windows(GUID.len())
            .position(|w| w == GUID.as_bytes())
            .unwrap();
        other[pos + 1] = b'X';
        let n = other.len();
        let sum = fmi2::codec::fnv1a64(&other[..n - 8]);
        other[n - 8..].copy_from_slice(&sum.to_le_bytes());
        assert_eq!(
            sh::deserialize_fmu_state::<Toy>(d, other.as_ptr() as *const c_char, n, &mut s3),
            Fmi2Status::Error
        );
        assert!(h2.last().contains("GUID"), "{}", h2.last());
        assert_eq!(
            sh::set_fmu_state::<Toy>(d, std::ptr::null_mut()),
            Fmi2Status::Error
        );
        assert_eq!(sh::free_fmu_state::<Toy>(c, &mut s), Fmi2Status::Ok);
        assert!(s.is_null());
        assert_eq!(sh::free_fmu_state::<Toy>(d, &mut s2), Fmi2Status::Ok);
        free(d);
    }
    free(c);
}

#[test]
fn instances_on_threads() {
    let serial: Vec<Vec<[f64; 2]>> = (0..4)
        .map(|i| {
            let h = Harness::new();
            let c = h.inst();
            set(c, 4, 50.0 + i as f64);
            // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
            // and strings passed outlive the call (FMI 2.0 pointer rules).
            unsafe {
                sh::enter_initialization_mode::<Toy>(c);
                sh::exit_initialization_mode::<Toy>(c);
            }
            let r = run(c, 0.0, 0.01, 50);
            free(c);
            r
        })
        .collect();
    // instantiate here, step on worker threads, free here
    struct SendPtr(Fmi2Component);
    // SAFETY: each thread uses its own instance; FMI only forbids concurrent calls on one.
    unsafe impl Send for SendPtr {}
    let h = Harness::new();
    let comps: Vec<SendPtr> = (0..4)
        .map(|i| {
            let c = h.inst();
            set(c, 4, 50.0 + i as f64);
            SendPtr(c)
        })
        .collect();
    let results: Vec<(SendPtr, Vec<[f64; 2]>)> = std::thread::scope(|s| {
        let hs: Vec<_> = comps
            .into_iter()
            .map(|p| {
                s.spawn(move || {
                    let p = p;
                    let c = p.0;
                    // SAFETY: test importer: the component comes from instantiate and is live, and the arrays
                    // and strings passed outlive the call (FMI 2.0 pointer rules).
                    unsafe {
                        sh::enter_initialization_mode::<Toy>(c);
                        sh::exit_initialization_mode::<Toy>(c);
                    }
                    let r = run(c, 0.0, 0.01, 50);
                    (SendPtr(c), r)
                })
            })
            .collect();
        hs.into_iter().map(|j| j.join().unwrap()).collect()
    });
    for (i, (p, r)) in results.into_iter().enumerate() {
        assert_eq!(r, serial[i]);
        free(p.0);
    }
}

/// A set call applies all its values or none: a value the model refuses takes back the values
/// of the same call applied before it (not only the shell's own checks).
#[test]
fn setters_apply_all_values_or_none() {
    let h = Harness::new();
    let c = h.inst();
    // SAFETY: c is a live instance; the arrays hold 2 elements each.
    let s = unsafe { sh::set_real::<Toy>(c, [4u32, 5].as_ptr(), 2, [50.0, 1e4].as_ptr()) };
    assert_eq!(s, Fmi2Status::Error);
    assert!(
        h.last().contains("c = 10000 is refused by the model"),
        "{}",
        h.last()
    );
    // SAFETY: as above.
    unsafe { assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok) };
    assert_eq!(
        get(c, &[4, 5]),
        [100.0, 1.0],
        "k was applied although c was refused"
    );
    // The shell's own checks (here the bounds of k) also leave earlier values unapplied.
    // SAFETY: as above.
    let s = unsafe { sh::set_real::<Toy>(c, [5u32, 4].as_ptr(), 2, [2.0, -1.0].as_ptr()) };
    assert_eq!(s, Fmi2Status::Error);
    assert_eq!(get(c, &[4, 5]), [100.0, 1.0]);
    // Strings: the first value is taken back when the second is refused.
    let (x, bad) = (c"x", c"refused");
    // SAFETY: as above; the strings are NUL-terminated and outlive the call.
    let s = unsafe {
        sh::set_string::<Toy>(
            c,
            [10u32, 10].as_ptr(),
            2,
            [x.as_ptr(), bad.as_ptr()].as_ptr(),
        )
    };
    assert_eq!(s, Fmi2Status::Error);
    let mut out: [Fmi2String; 1] = [std::ptr::null()];
    // SAFETY: as above; out has room for one pointer.
    unsafe {
        assert_eq!(
            sh::get_string::<Toy>(c, &10, 1, out.as_mut_ptr()),
            Fmi2Status::Ok
        )
    };
    // SAFETY: the shell returned a NUL-terminated string valid until its next fmi2GetString.
    assert_eq!(unsafe { CStr::from_ptr(out[0]) }.to_str().unwrap(), "a");
    // A call whose values are all accepted applies them all.
    // SAFETY: as above.
    let s = unsafe { sh::set_real::<Toy>(c, [4u32, 5].as_ptr(), 2, [50.0, 2.0].as_ptr()) };
    assert_eq!(s, Fmi2Status::Ok);
    assert_eq!(get(c, &[4, 5]), [50.0, 2.0]);
    free(c);
}
