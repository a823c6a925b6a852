//! Tests of the generic shell with a toy model (a damped oscillator), through the same generic
//! functions the C entry points call.

use fmi2::bindings::*;
use fmi2::codec::{ByteReader, ByteWriter};
use fmi2::functions as sh;
use fmi2::*;
use std::ffi::{CStr, CString};
use std::os::raw::{c_char, c_void};
use std::sync::Mutex;

/// x'' = −k x − c x' + u, integrated by RK4 with sub-steps ≤ 1 ms ending exactly at t_end
/// (Co-Simulation), or by the importer (Model Exchange when `ME`: states x, v; one event
/// indicator, x; `steps` counts the event updates).
#[derive(Clone)]
struct ToyModel<const ME: bool> {
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

/// The toy with Model Exchange.
type Toy = ToyModel<true>;
/// The toy without it (Co-Simulation only).
type CsToy = ToyModel<false>;

impl<const ME: bool> ToyModel<ME> {
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

impl<const ME: bool> FmuModel for ToyModel<ME> {
    const MODEL_IDENTIFIER: &'static str = "Toy";
    const MODEL_EXCHANGE: bool = ME;

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
    type Undo = Box<Self>;
    fn begin_set(&self, _indices: &[usize]) -> Box<Self> {
        Box::new(self.clone())
    }
    fn rollback_set(&mut self, undo: Box<Self>) -> Result<(), String> {
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

    fn number_of_continuous_states(&self) -> usize {
        2
    }
    fn number_of_event_indicators(&self) -> usize {
        1
    }
    fn set_time(&mut self, t: f64) -> Result<(), String> {
        self.t = t;
        Ok(())
    }
    fn set_continuous_states(&mut self, x: &[f64]) -> Result<(), String> {
        if x[0] > 1e6 {
            return Err(format!("x = {} is refused by the model", x[0]));
        }
        self.x = x[0];
        self.v = x[1];
        Ok(())
    }
    fn get_continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        x.copy_from_slice(&[self.x, self.v]);
        Ok(())
    }
    fn get_derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        if self.t > self.panic_at {
            panic!("toy panic requested at {}", self.t);
        }
        let (a, b) = self.rhs(self.x, self.v);
        // A derivative the model cannot compute: NaN past fail_at.
        dx.copy_from_slice(&[a, if self.t > self.fail_at { f64::NAN } else { b }]);
        Ok(())
    }
    fn get_event_indicators(&mut self, g: &mut [f64]) -> Result<(), String> {
        g[0] = self.x;
        Ok(())
    }
    fn get_nominals(&mut self, n: &mut [f64]) -> Result<(), String> {
        n.copy_from_slice(&[1.0, 10.0]);
        Ok(())
    }
    fn new_discrete_states(&mut self, log: &Logger) -> Result<EventUpdate, String> {
        if self.t > self.fail_at {
            return Err(format!("event update failed at t = {}", self.t));
        }
        self.steps += 1;
        log.log(Fmi2Status::Ok, LOG_EVENTS, &format!("event {}", self.steps));
        Ok(EventUpdate {
            // one extra iteration at the first event, a time event every second
            new_discrete_states_needed: self.steps == 1,
            next_event_time: Some(self.t.floor() + 1.0),
            warnings: if self.u != 0.0 {
                vec![format!("u = {}", self.u)]
            } else {
                vec![]
            },
            ..EventUpdate::default()
        })
    }
    fn completed_integrator_step(
        &mut self,
        inputs_changed: bool,
        _log: &Logger,
    ) -> Result<StepEnd, String> {
        Ok(StepEnd {
            enter_event_mode: inputs_changed,
            terminate_simulation: self.t > 100.0,
            warnings: vec![],
        })
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
        let me = sh::instantiate::<CsToy>(
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

// --- Model Exchange ------------------------------------------------------------------------

impl Harness {
    fn inst_me(&self) -> Fmi2Component {
        // SAFETY: test importer: the strings and the callbacks outlive the call.
        unsafe {
            sh::instantiate::<Toy>(
                c"toy-me".as_ptr(),
                FMI2_MODEL_EXCHANGE,
                c"{toy-oscillator-1}".as_ptr(),
                std::ptr::null(),
                &*self.cb,
                0,
                0,
            )
        }
    }
}

fn state_of(c: Fmi2Component) -> CallState {
    // SAFETY: c is a live instance of Toy from instantiate, and no call is running on it.
    unsafe { &*(c as *const Instance<Toy>) }.call_state()
}

/// An ME instance in event mode right after fmi2ExitInitializationMode.
fn me_ready(h: &Harness) -> Fmi2Component {
    let c = h.inst_me();
    assert!(!c.is_null(), "{}", h.last());
    // SAFETY: test importer: the component comes from instantiate and is live.
    unsafe {
        assert_eq!(
            sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
    }
    assert_eq!(state_of(c), CallState::EventMode);
    c
}

fn new_discrete_states(c: Fmi2Component) -> (Fmi2Status, Fmi2EventInfo) {
    let mut info = Fmi2EventInfo::default();
    // SAFETY: test importer: live component, info outlives the call.
    let s = unsafe { sh::new_discrete_states::<Toy>(c, &mut info) };
    (s, info)
}

fn me_states(c: Fmi2Component) -> [f64; 2] {
    let mut x = [0.0; 2];
    // SAFETY: test importer: live component, x holds 2 values.
    let s = unsafe { sh::get_continuous_states::<Toy>(c, x.as_mut_ptr(), 2) };
    assert_eq!(s, Fmi2Status::Ok);
    x
}

fn indicator(c: Fmi2Component) -> f64 {
    let mut g = [0.0];
    // SAFETY: test importer: live component, g holds 1 value.
    let s = unsafe { sh::get_event_indicators::<Toy>(c, g.as_mut_ptr(), 1) };
    assert_eq!(s, Fmi2Status::Ok);
    g[0]
}

/// One RK4 step of the importer from (t, x) over h through the FMU's derivatives.
fn rk4(c: Fmi2Component, t: f64, x: [f64; 2], h: f64) -> [f64; 2] {
    let f = |t: f64, x: [f64; 2]| {
        let mut d = [0.0; 2];
        // SAFETY: test importer: live component, the arrays hold 2 values.
        unsafe {
            assert_eq!(sh::set_time::<Toy>(c, t), Fmi2Status::Ok);
            assert_eq!(
                sh::set_continuous_states::<Toy>(c, x.as_ptr(), 2),
                Fmi2Status::Ok
            );
            assert_eq!(
                sh::get_derivatives::<Toy>(c, d.as_mut_ptr(), 2),
                Fmi2Status::Ok
            );
        }
        d
    };
    let add = |x: [f64; 2], k: [f64; 2], s: f64| [x[0] + s * k[0], x[1] + s * k[1]];
    let k1 = f(t, x);
    let k2 = f(t + h / 2.0, add(x, k1, h / 2.0));
    let k3 = f(t + h / 2.0, add(x, k2, h / 2.0));
    let k4 = f(t + h, add(x, k3, h));
    [
        x[0] + h / 6.0 * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]),
        x[1] + h / 6.0 * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]),
    ]
}

fn set_states(c: Fmi2Component, t: f64, x: [f64; 2]) {
    // SAFETY: test importer: live component, x holds 2 values.
    unsafe {
        assert_eq!(sh::set_time::<Toy>(c, t), Fmi2Status::Ok);
        assert_eq!(
            sh::set_continuous_states::<Toy>(c, x.as_ptr(), 2),
            Fmi2Status::Ok
        );
    }
}

fn completed(c: Fmi2Component) -> (Fmi2Status, bool, bool) {
    let (mut e, mut t) = (7, 7);
    // SAFETY: test importer: live component, e and t outlive the call.
    let s = unsafe { sh::completed_integrator_step::<Toy>(c, 1, &mut e, &mut t) };
    (s, e != 0, t != 0)
}

#[test]
fn model_exchange_importer_loop_locates_the_state_event_and_follows_the_oscillator() {
    let h = Harness::new();
    let c = me_ready(&h);
    // The initial event iteration: the model asks for a second round once.
    let (s, info) = new_discrete_states(c);
    assert_eq!((s, info.new_discrete_states_needed), (Fmi2Status::Ok, 1));
    let (s, info) = new_discrete_states(c);
    assert_eq!((s, info.new_discrete_states_needed), (Fmi2Status::Ok, 0));
    assert_eq!(info.next_event_time_defined, 1);
    assert_eq!(info.next_event_time, 1.0);
    assert_eq!(info.terminate_simulation, 0);
    // SAFETY: test importer: live component.
    let status = unsafe { sh::enter_continuous_time_mode::<Toy>(c) };
    assert_eq!(status, Fmi2Status::Ok);
    assert_eq!(state_of(c), CallState::ContinuousTimeMode);
    // Integrate to the first zero of x (t = asin-free: x = e^(-t/2)(cos wt + sin wt/(2w))),
    // locating it by bisection on the indicator.
    let (mut t, mut x, hstep) = (0.0, me_states(c), 1e-3);
    assert_eq!(x, [1.0, 0.0]);
    let mut event_at = None;
    while t < 0.5 {
        let g0 = indicator(c);
        let xn = rk4(c, t, x, hstep);
        set_states(c, t + hstep, xn);
        if (indicator(c) > 0.0) != (g0 > 0.0) {
            let (mut a, mut b) = (0.0, hstep);
            while b - a > 1e-13 {
                let m = 0.5 * (a + b);
                let xm = rk4(c, t, x, m);
                set_states(c, t + m, xm);
                if (indicator(c) > 0.0) == (g0 > 0.0) {
                    a = m
                } else {
                    b = m
                }
            }
            let xb = rk4(c, t, x, b);
            set_states(c, t + b, xb);
            event_at = Some(t + b);
            break;
        }
        t += hstep;
        x = xn;
        assert_eq!(completed(c), (Fmi2Status::Ok, false, false));
    }
    let te = event_at.expect("x crosses zero before t = 0.5");
    let w = (100.0f64 - 0.25).sqrt();
    // x = 0 where tan(w t) = -2 w
    let exact = (std::f64::consts::PI - (2.0 * w).atan()) / w;
    assert!((te - exact).abs() < 1e-9, "{te} vs {exact}");
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(completed(c).0, Fmi2Status::Ok);
        assert_eq!(sh::enter_event_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(state_of(c), CallState::EventMode);
        // fmi2SetTime is allowed in event mode, fmi2SetContinuousStates is not
        assert_eq!(sh::set_time::<Toy>(c, te), Fmi2Status::Ok);
        let x = [0.5, 0.5];
        assert_eq!(
            sh::set_continuous_states::<Toy>(c, x.as_ptr(), 2),
            Fmi2Status::Error
        );
        assert!(h.last().contains("illegal call sequence"), "{}", h.last());
    }
    let (s, info) = new_discrete_states(c);
    assert_eq!((s, info.new_discrete_states_needed), (Fmi2Status::Ok, 0));
    assert_eq!(get_steps(c), 3, "three event updates");
    assert!(h.messages().iter().all(|m| !m.contains("Error")));
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(sh::terminate::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(state_of(c), CallState::Terminated);
        // in Terminated the values can still be read
        let mut d = [0.0; 2];
        assert_eq!(
            sh::get_derivatives::<Toy>(c, d.as_mut_ptr(), 2),
            Fmi2Status::Ok
        );
        assert_eq!(sh::reset::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(state_of(c), CallState::Instantiated);
    }
    free(c);
}

fn get_steps(c: Fmi2Component) -> i32 {
    let mut v = 0;
    // SAFETY: test importer: live component.
    let status = unsafe { sh::get_integer::<Toy>(c, &8, 1, &mut v) };
    assert_eq!(status, Fmi2Status::Ok);
    v
}

/// Calls every Model Exchange function on `c`; the statuses in a fixed order.
fn every_me_call(c: Fmi2Component) -> Vec<Fmi2Status> {
    let mut x = [0.0; 2];
    let mut g = [0.0; 1];
    let mut info = Fmi2EventInfo::default();
    let (mut e, mut t) = (0, 0);
    // SAFETY: test importer: live component, the arrays hold their lengths.
    unsafe {
        vec![
            sh::set_time::<Toy>(c, 0.25),
            sh::set_continuous_states::<Toy>(c, [0.5, 0.5].as_ptr(), 2),
            sh::get_continuous_states::<Toy>(c, x.as_mut_ptr(), 2),
            sh::get_derivatives::<Toy>(c, x.as_mut_ptr(), 2),
            sh::get_event_indicators::<Toy>(c, g.as_mut_ptr(), 1),
            sh::get_nominals_of_continuous_states::<Toy>(c, x.as_mut_ptr(), 2),
            sh::new_discrete_states::<Toy>(c, &mut info),
            sh::completed_integrator_step::<Toy>(c, 0, &mut e, &mut t),
            sh::enter_continuous_time_mode::<Toy>(c),
            sh::enter_event_mode::<Toy>(c),
        ]
    }
}

#[test]
fn model_exchange_call_sequences_are_checked_and_refused_calls_have_no_effect() {
    use Fmi2Status::{Error as E, Ok as O};
    let h = Harness::new();
    let c = h.inst_me();
    let steps0 = 0;
    // Instantiated: only the nominals.
    assert_eq!(every_me_call(c), vec![E, E, E, E, E, O, E, E, E, E]);
    assert_eq!(state_of(c), CallState::Instantiated);
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(
            sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        // fmi2DoStep is a Co-Simulation function
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::do_step::<Toy>(c, 0.0, 0.1, 0), Fmi2Status::Error);
        assert!(h.last().contains("illegal call sequence"), "{}", h.last());
        let mut st = Fmi2Status::Ok;
        assert_eq!(sh::get_status::<Toy>(c, 0, &mut st), Fmi2Status::Error);
        assert_eq!(sh::reset::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(
            sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
    }
    // Initialization mode: states and indicators can be read, nothing else.
    assert_eq!(every_me_call(c), vec![E, E, O, E, O, E, E, E, E, E]);
    assert_eq!(state_of(c), CallState::InitializationMode);
    assert_eq!(me_states(c), [1.0, 0.0]);
    // SAFETY: test importer: live component.
    unsafe { assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok) };
    // Event mode: set_time, the getters, new_discrete_states, enter_continuous_time_mode.
    // (every_me_call ends in event mode again: its enter_continuous_time_mode then
    // enter_event_mode both succeed.)
    assert_eq!(every_me_call(c), vec![O, E, O, O, O, O, O, E, O, O]);
    assert_eq!(me_states(c), [1.0, 0.0], "the refused set had no effect");
    assert_eq!(get_steps(c), steps0 + 1);
    // SAFETY: test importer: live component.
    unsafe { assert_eq!(sh::enter_continuous_time_mode::<Toy>(c), Fmi2Status::Ok) };
    // Continuous-time mode: all but new_discrete_states (enter_event_mode last leaves it).
    assert_eq!(every_me_call(c), vec![O, O, O, O, O, O, E, O, E, O]);
    assert_eq!(
        get_steps(c),
        steps0 + 1,
        "no event update in continuous time"
    );
    assert_eq!(me_states(c), [0.5, 0.5]);
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(sh::terminate::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::terminate::<Toy>(c), Fmi2Status::Error);
    }
    // Terminated: the getters only (not the nominals' setters, no mode changes).
    assert_eq!(every_me_call(c), vec![E, E, O, O, O, O, E, E, E, E]);
    assert_eq!(state_of(c), CallState::Terminated);
    free(c);

    // A Co-Simulation instance refuses the Model Exchange functions, even where its state
    // would allow them (the nominals in Instantiated).
    let c = h.inst();
    assert_eq!(every_me_call(c), vec![E; 10]);
    assert!(
        h.last().contains(
            "is a Model Exchange function, and this instance was instantiated for Co-Simulation"
        ) || h
            .messages()
            .iter()
            .any(|m| m.contains("is a Model Exchange function")),
        "{:?}",
        h.messages()
    );
    free(c);
}

#[test]
fn model_exchange_arguments_are_checked() {
    let h = Harness::new();
    let c = me_ready(&h);
    // SAFETY: test importer: live component; the NULL pointers are the point of the test.
    unsafe {
        let mut x = [0.0; 3];
        assert_eq!(
            sh::get_continuous_states::<Toy>(c, x.as_mut_ptr(), 3),
            Fmi2Status::Error
        );
        assert!(h.last().contains("nx = 3"), "{}", h.last());
        assert_eq!(
            sh::get_event_indicators::<Toy>(c, x.as_mut_ptr(), 2),
            Fmi2Status::Error
        );
        assert!(h.last().contains("ni = 2"), "{}", h.last());
        assert_eq!(
            sh::get_derivatives::<Toy>(c, std::ptr::null_mut(), 2),
            Fmi2Status::Error
        );
        assert!(h.last().contains("NULL"), "{}", h.last());
        assert_eq!(
            sh::new_discrete_states::<Toy>(c, std::ptr::null_mut()),
            Fmi2Status::Error
        );
        assert_eq!(sh::set_time::<Toy>(c, f64::NAN), Fmi2Status::Error);
        assert_eq!(sh::set_time::<Toy>(c, -1.0), Fmi2Status::Error);
        assert!(h.last().contains("before the start time"), "{}", h.last());
        assert_eq!(sh::enter_continuous_time_mode::<Toy>(c), Fmi2Status::Ok);
        let (mut e, mut t) = (0, 0);
        assert_eq!(
            sh::completed_integrator_step::<Toy>(c, 0, std::ptr::null_mut(), &mut t),
            Fmi2Status::Error
        );
        assert_eq!(
            sh::completed_integrator_step::<Toy>(c, 0, &mut e, std::ptr::null_mut()),
            Fmi2Status::Error
        );
        for bad in [[f64::NAN, 0.0], [0.0, f64::INFINITY]] {
            assert_eq!(
                sh::set_continuous_states::<Toy>(c, bad.as_ptr(), 2),
                Fmi2Status::Error
            );
            assert!(h.last().contains("is not finite"), "{}", h.last());
        }
        assert_eq!(
            sh::set_continuous_states::<Toy>(c, [0.5].as_ptr(), 1),
            Fmi2Status::Error
        );
        assert_eq!(
            sh::set_continuous_states::<Toy>(c, std::ptr::null(), 2),
            Fmi2Status::Error
        );
        // a state the model refuses
        assert_eq!(
            sh::set_continuous_states::<Toy>(c, [2e6, 0.0].as_ptr(), 2),
            Fmi2Status::Error
        );
        assert!(h.last().contains("refused by the model"), "{}", h.last());
        assert_eq!(
            me_states(c),
            [1.0, 0.0],
            "no refused call changed the states"
        );
        assert_eq!(state_of(c), CallState::ContinuousTimeMode);
        // the NULL component
        let n = std::ptr::null_mut();
        assert_eq!(sh::set_time::<Toy>(n, 0.0), Fmi2Status::Error);
        assert_eq!(sh::enter_event_mode::<Toy>(n), Fmi2Status::Error);
    }
    free(c);
}

#[test]
fn model_exchange_setters_in_continuous_time_and_event_mode() {
    let h = Harness::new();
    let c = me_ready(&h);
    // Event mode: inputs and tunable parameters, not fixed ones.
    assert_eq!(set(c, 3, 2.0), Fmi2Status::Ok);
    assert_eq!(set(c, 5, 2.0), Fmi2Status::Ok);
    assert_eq!(set(c, 4, 50.0), Fmi2Status::Error);
    assert!(h.last().contains("fixed parameter"), "{}", h.last());
    // a warning from the model's event update is passed on
    let (s, _) = new_discrete_states(c);
    assert_eq!(s, Fmi2Status::Warning);
    assert!(h.last().contains("u = 2"), "{}", h.last());
    // SAFETY: test importer: live component, the values outlive the calls.
    unsafe {
        assert_eq!(sh::enter_continuous_time_mode::<Toy>(c), Fmi2Status::Ok);
        // continuous time: continuous inputs only, and only fmi2SetReal
        assert_eq!(completed(c), (Fmi2Status::Ok, false, false));
        assert_eq!(set(c, 3, 3.0), Fmi2Status::Ok);
        assert_eq!(set(c, 5, 3.0), Fmi2Status::Error);
        assert!(h.last().contains("only continuous inputs"), "{}", h.last());
        assert_eq!(get(c, &[3, 5]), vec![3.0, 2.0]);
        assert_eq!(
            sh::set_boolean::<Toy>(c, &9, 1, &1),
            Fmi2Status::Error,
            "fmi2SetBoolean is not allowed in continuous-time mode"
        );
        // the input change reaches the model at the completed step (once)
        assert_eq!(completed(c), (Fmi2Status::Ok, true, false));
        assert_eq!(completed(c), (Fmi2Status::Ok, false, false));
        // and the model may ask to stop
        assert_eq!(sh::set_time::<Toy>(c, 101.0), Fmi2Status::Ok);
        assert_eq!(completed(c), (Fmi2Status::Ok, false, true));
    }
    free(c);
}

#[test]
fn model_exchange_failures_error_and_fatal() {
    let h = Harness::new();
    // A non-finite derivative is an error with no effect.
    let c = me_ready(&h);
    assert_eq!(set(c, 6, 0.5), Fmi2Status::Error, "fail_at is fixed");
    // SAFETY: test importer: live component, the arrays hold their lengths.
    unsafe {
        assert_eq!(sh::reset::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(set(c, 6, 0.5), Fmi2Status::Ok);
        assert_eq!(set(c, 7, 0.75), Fmi2Status::Ok);
        assert_eq!(
            sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::set_time::<Toy>(c, 0.6), Fmi2Status::Ok);
        let mut d = [7.0; 2];
        assert_eq!(
            sh::get_derivatives::<Toy>(c, d.as_mut_ptr(), 2),
            Fmi2Status::Error
        );
        assert!(h.last().contains("element 1 is NaN"), "{}", h.last());
        assert_eq!(d, [7.0; 2], "the importer's array is untouched");
        assert_eq!(state_of(c), CallState::EventMode);
        // a failed event update: Error state, from which reset leads out
        let mut info = Fmi2EventInfo::default();
        assert_eq!(
            sh::new_discrete_states::<Toy>(c, &mut info),
            Fmi2Status::Error
        );
        assert!(h.last().contains("event update failed"), "{}", h.last());
        assert_eq!(state_of(c), CallState::Error);
        assert_eq!(sh::enter_continuous_time_mode::<Toy>(c), Fmi2Status::Error);
        assert_eq!(
            sh::get_derivatives::<Toy>(c, d.as_mut_ptr(), 2),
            Fmi2Status::Error,
            "still NaN at t = 0.6"
        );
        assert_eq!(sh::reset::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(set(c, 7, 0.75), Fmi2Status::Ok);
        assert_eq!(
            sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
        // a panic in the model becomes fmi2Fatal
        assert_eq!(sh::set_time::<Toy>(c, 0.8), Fmi2Status::Ok);
        assert_eq!(
            sh::get_derivatives::<Toy>(c, d.as_mut_ptr(), 2),
            Fmi2Status::Fatal
        );
        assert_eq!(state_of(c), CallState::Fatal);
        assert_eq!(sh::set_time::<Toy>(c, 0.1), Fmi2Status::Error);
    }
    free(c);
}

#[test]
fn model_exchange_fmu_state_round_trip_and_interface_check() {
    let h = Harness::new();
    let c = me_ready(&h);
    let _ = new_discrete_states(c);
    let _ = new_discrete_states(c);
    // SAFETY: test importer: live components, the states are ours.
    unsafe {
        assert_eq!(sh::enter_continuous_time_mode::<Toy>(c), Fmi2Status::Ok);
        set_states(c, 0.3, [0.25, -1.0]);
        let mut s: Fmi2FmuState = std::ptr::null_mut();
        assert_eq!(sh::get_fmu_state::<Toy>(c, &mut s), Fmi2Status::Ok);
        set_states(c, 0.4, [0.5, 2.0]);
        assert_eq!(sh::enter_event_mode::<Toy>(c), Fmi2Status::Ok);
        assert_eq!(sh::set_fmu_state::<Toy>(c, s), Fmi2Status::Ok);
        assert_eq!(state_of(c), CallState::ContinuousTimeMode);
        assert_eq!(me_states(c), [0.25, -1.0]);
        // SAFETY: as above.
        let inst = &*(c as *const Instance<Toy>);
        assert_eq!(inst.time(), 0.3);
        assert_eq!(inst.interface(), Interface::ModelExchange);
        // serialized, into a Co-Simulation instance: refused (its call state is an ME one)
        let mut size = 0;
        assert_eq!(
            sh::serialized_fmu_state_size::<Toy>(c, s, &mut size),
            Fmi2Status::Ok
        );
        let mut bytes = vec![0 as c_char; size];
        assert_eq!(
            sh::serialize_fmu_state::<Toy>(c, s, bytes.as_mut_ptr(), size),
            Fmi2Status::Ok
        );
        let cs = ready(&h);
        let mut s2: Fmi2FmuState = std::ptr::null_mut();
        assert_eq!(
            sh::deserialize_fmu_state::<Toy>(cs, bytes.as_ptr(), size, &mut s2),
            Fmi2Status::Error
        );
        assert!(
            h.last().contains("saved by a Model Exchange instance"),
            "{}",
            h.last()
        );
        assert_eq!(sh::free_fmu_state::<Toy>(c, &mut s), Fmi2Status::Ok);
        free(cs);
    }
    free(c);
}

/// The serialized FMU state of `c` (a fresh handle each time).
fn serialized(c: Fmi2Component) -> Vec<c_char> {
    // SAFETY: test importer: live component; the state handle is ours and freed here.
    unsafe {
        let mut s: Fmi2FmuState = std::ptr::null_mut();
        assert_eq!(sh::get_fmu_state::<Toy>(c, &mut s), Fmi2Status::Ok);
        let mut size = 0;
        assert_eq!(
            sh::serialized_fmu_state_size::<Toy>(c, s, &mut size),
            Fmi2Status::Ok
        );
        let mut bytes = vec![0 as c_char; size];
        assert_eq!(
            sh::serialize_fmu_state::<Toy>(c, s, bytes.as_mut_ptr(), size),
            Fmi2Status::Ok
        );
        assert_eq!(sh::free_fmu_state::<Toy>(c, &mut s), Fmi2Status::Ok);
        bytes
    }
}

/// Restores serialized `bytes` into `c`; the status.
fn restore(c: Fmi2Component, bytes: &[c_char]) -> Fmi2Status {
    // SAFETY: test importer: live component; the state handle is ours and freed here.
    unsafe {
        let mut s: Fmi2FmuState = std::ptr::null_mut();
        let r = sh::deserialize_fmu_state::<Toy>(c, bytes.as_ptr(), bytes.len(), &mut s);
        if r != Fmi2Status::Ok {
            return r;
        }
        let r = sh::set_fmu_state::<Toy>(c, s);
        assert_eq!(sh::free_fmu_state::<Toy>(c, &mut s), Fmi2Status::Ok);
        r
    }
}

#[test]
fn every_call_state_survives_serialization_within_its_interface_only() {
    let h = Harness::new();
    // (instance kind, the states it passes through), serialized in each and restored into a
    // fresh instance of the same kind and of the other
    let me = h.inst_me();
    let cs = h.inst();
    let mut me_states = Vec::new();
    let mut cs_states = Vec::new();
    // SAFETY: test importer: live components.
    unsafe {
        for (c, out) in [(me, &mut me_states), (cs, &mut cs_states)] {
            out.push((state_of(c), serialized(c)));
            assert_eq!(
                sh::setup_experiment::<Toy>(c, 0, 0.0, 0.0, 0, 0.0),
                Fmi2Status::Ok
            );
            assert_eq!(sh::enter_initialization_mode::<Toy>(c), Fmi2Status::Ok);
            out.push((state_of(c), serialized(c)));
            assert_eq!(sh::exit_initialization_mode::<Toy>(c), Fmi2Status::Ok);
            out.push((state_of(c), serialized(c)));
        }
        assert_eq!(sh::enter_continuous_time_mode::<Toy>(me), Fmi2Status::Ok);
        me_states.push((state_of(me), serialized(me)));
        assert_eq!(sh::terminate::<Toy>(me), Fmi2Status::Ok);
        me_states.push((state_of(me), serialized(me)));
        // a Co-Simulation step that fails: StepFailed; then Terminated
        assert_eq!(set(cs, 5, 2e3), Fmi2Status::Error); // refused by the model: no effect
        assert_eq!(sh::reset::<Toy>(cs), Fmi2Status::Ok);
        assert_eq!(set(cs, 6, 0.05), Fmi2Status::Ok);
        assert_eq!(
            sh::setup_experiment::<Toy>(cs, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(cs), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(cs), Fmi2Status::Ok);
        assert_eq!(sh::do_step::<Toy>(cs, 0.0, 0.1, 0), Fmi2Status::Discard);
        // the outputs of the last good point can be read after a discard
        assert_eq!(get(cs, &[1, 2]), vec![1.0, 0.0]);
        cs_states.push((state_of(cs), serialized(cs)));
        assert_eq!(sh::terminate::<Toy>(cs), Fmi2Status::Ok);
        cs_states.push((state_of(cs), serialized(cs)));
    }
    // a failed event update: the Error state (shared by both interfaces)
    let failed = h.inst_me();
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(set(failed, 6, 0.0), Fmi2Status::Ok);
        assert_eq!(
            sh::setup_experiment::<Toy>(failed, 0, 0.0, 0.0, 0, 0.0),
            Fmi2Status::Ok
        );
        assert_eq!(sh::enter_initialization_mode::<Toy>(failed), Fmi2Status::Ok);
        assert_eq!(sh::exit_initialization_mode::<Toy>(failed), Fmi2Status::Ok);
        assert_eq!(sh::set_time::<Toy>(failed, 0.5), Fmi2Status::Ok);
        let mut info = Fmi2EventInfo::default();
        assert_eq!(
            sh::new_discrete_states::<Toy>(failed, &mut info),
            Fmi2Status::Error
        );
    }
    me_states.push((state_of(failed), serialized(failed)));
    free(failed);
    let names = |v: &[(CallState, Vec<c_char>)]| v.iter().map(|s| s.0).collect::<Vec<_>>();
    use CallState::*;
    assert_eq!(
        names(&me_states),
        [
            Instantiated,
            InitializationMode,
            EventMode,
            ContinuousTimeMode,
            Terminated,
            Error
        ]
    );
    assert_eq!(
        names(&cs_states),
        [
            Instantiated,
            InitializationMode,
            StepComplete,
            StepFailed,
            Terminated
        ]
    );
    for (state, bytes) in &me_states {
        let fresh = h.inst_me();
        assert_eq!(restore(fresh, bytes), Fmi2Status::Ok, "{state:?}");
        assert_eq!(state_of(fresh), *state);
        free(fresh);
        let other = h.inst();
        let shared = matches!(
            state,
            Instantiated | InitializationMode | Terminated | Error
        );
        let want = if shared {
            Fmi2Status::Ok
        } else {
            Fmi2Status::Error
        };
        assert_eq!(restore(other, bytes), want, "ME {state:?} into CS");
        free(other);
    }
    for (state, bytes) in &cs_states {
        let fresh = h.inst();
        assert_eq!(restore(fresh, bytes), Fmi2Status::Ok, "{state:?}");
        assert_eq!(state_of(fresh), *state);
        free(fresh);
        let other = h.inst_me();
        let shared = matches!(state, Instantiated | InitializationMode | Terminated);
        let want = if shared {
            Fmi2Status::Ok
        } else {
            Fmi2Status::Error
        };
        assert_eq!(restore(other, bytes), want, "CS {state:?} into ME");
        if !shared {
            assert!(
                h.last().contains("saved by a Co-Simulation instance"),
                "{}",
                h.last()
            );
        }
        free(other);
    }
    free(me);
    free(cs);
}

#[test]
fn refusals_name_the_states_that_allow_the_call_and_event_mode_takes_the_other_setters() {
    let h = Harness::new();
    let c = h.inst_me();
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(sh::set_time::<Toy>(c, 0.0), Fmi2Status::Error);
        assert!(
            h.last().ends_with(
                "the instance is in state Instantiated; allowed in: EventMode, ContinuousTimeMode"
            ),
            "{}",
            h.last()
        );
        let mut info = Fmi2EventInfo::default();
        assert_eq!(
            sh::new_discrete_states::<Toy>(c, &mut info),
            Fmi2Status::Error
        );
        assert!(h.last().ends_with("allowed in: EventMode"), "{}", h.last());
        let mut x = [0.0; 2];
        assert_eq!(
            sh::get_derivatives::<Toy>(c, x.as_mut_ptr(), 2),
            Fmi2Status::Error
        );
        assert!(
            h.last()
                .ends_with("allowed in: EventMode, ContinuousTimeMode, Terminated, Error"),
            "{}",
            h.last()
        );
    }
    free(c);
    let c = me_ready(&h);
    // SAFETY: test importer: live component.
    unsafe {
        // event mode lets fmi2SetBoolean/Integer/String through the call-state check: the
        // refusal is the variable's (a fixed parameter), not the sequence
        assert_eq!(sh::set_boolean::<Toy>(c, &9, 1, &1), Fmi2Status::Error);
        assert!(h.last().contains("fixed parameter"), "{}", h.last());
        assert_eq!(
            sh::set_string::<Toy>(c, &10, 1, &c"b".as_ptr()),
            Fmi2Status::Error
        );
        assert!(h.last().contains("fixed parameter"), "{}", h.last());
    }
    free(c);
    // and so does StepComplete in Co-Simulation
    let c = ready(&h);
    // SAFETY: test importer: live component.
    unsafe {
        assert_eq!(sh::set_boolean::<Toy>(c, &9, 1, &1), Fmi2Status::Error);
        assert!(h.last().contains("fixed parameter"), "{}", h.last());
    }
    free(c);
}
