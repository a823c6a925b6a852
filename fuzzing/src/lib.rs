//! Fuzz harnesses of raceway: each takes arbitrary bytes and returns `Err` with a description
//! when it finds a violation of the property it checks (a panic is a finding too).
//!
//! - [`fmi_calls`]: a random sequence of FMI 2.0 Co-Simulation calls with random arguments
//!   (NaN and infinite values, unknown value references, NULL arrays with a non-zero length,
//!   repeated `fmi2FreeFMUstate`, Integer parameters such as the fidelity level and the spalls'
//!   rings and balls set around their valid values) through the BallBearing's C entry points:
//!   every call returns
//!   a status the standard allows in the state the instance is in (a call the state does not
//!   allow returns fmi2Error), none takes longer than [`HANG_S`], and no `fmi2DoStep` that
//!   returns fmi2OK or fmi2Warning leaves a non-finite output. After an fmi2Error the sequence
//!   goes on as a compliant master would: `fmi2Reset`, `fmi2SetFMUstate` or `fmi2FreeInstance`.
//! - [`input_files`]: a bearing, scene or sweep file of the repository, mutated (values
//!   replaced by random ones, lines dropped, duplicated or added, bytes flipped, the text cut):
//!   it is read, or refused with an error; an error after a value replacement in a file that is
//!   still valid TOML names the replaced key.
//! - [`state_blob`]: a valid serialized FMU state, mutated (bytes flipped or inserted, cut, or
//!   mutated with its checksum recomputed, so that the model's own reader sees it): it is
//!   rejected with a message or, if accepted, a following step ends with finite outputs or an
//!   error.
//!
//! Two drivers: libFuzzer through cargo-fuzz (`fuzzing/fuzz`, nightly; `scripts/fuzz_long.sh`)
//! and [`drive`], a seeded random driver on the stable toolchain for the short runs of the test
//! command (`fuzzing/tests/fuzz.rs`).

use ballbearing_fmu::ballbearing::BallBearing;
use cpu_time::ThreadTime;
use fmi2::bindings::*;
use fmi2::capture::LogCapture;
use fmi2::functions as sh;
use std::ffi::CString;
use std::path::Path;

/// A call that keeps its thread busy longer than this (CPU seconds: a long run shares the
/// machine, and wall time then counts the waits) is reported as a hang. libFuzzer's own
/// `-timeout` (wall) catches a call that blocks.
pub const HANG_S: f64 = 30.0;

/// The step budget (`solver.max_steps`, units of work per communication step) the harnesses give
/// their instances. A parameter set that makes the integration crawl (a contact damping of 1e9
/// N s/m made steps of 3e-10 s before `contact.c_br` was bounded) ends as fmi2Discard when the
/// budget is spent; at the FMU's default,
/// 2 000 000, that takes about 10 s here and 40 CPU s in libFuzzer's instrumented build, beyond
/// [`HANG_S`]. At this budget it takes about 0.5 s (2 s instrumented), so that a call that
/// [`HANG_S`] catches is one the budget does not bound.
pub const FUZZ_MAX_STEPS: i32 = 100_000;

/// The fuzz input as a source of choices (zeros once exhausted).
pub struct Bytes<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Bytes<'a> {
    /// Choices from `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Self { data, pos: 0 }
    }
    /// Whether every byte has been used.
    pub fn done(&self) -> bool {
        self.pos >= self.data.len()
    }
    /// The next byte (0 when exhausted).
    pub fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }
    /// A number below `n` (n ≥ 1).
    pub fn below(&mut self, n: usize) -> usize {
        let v = (usize::from(self.u8()) << 8) | usize::from(self.u8());
        v % n.max(1)
    }
    /// A value for a Real argument: special values, magnitudes across the range, or `typical`
    /// scaled.
    pub fn real(&mut self, typical: f64) -> f64 {
        match self.u8() % 12 {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => f64::NEG_INFINITY,
            3 => 0.0,
            4 => -typical,
            5 => typical * 1e6,
            6 => f64::MAX,
            7 => f64::MIN_POSITIVE,
            8 => -1.0,
            _ => typical * (1.0 + (f64::from(self.u8()) - 128.0) / 256.0),
        }
    }
}

type M = BallBearing;

/// The FMI 2.0 Co-Simulation call states (standard, section 4.2.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    Instantiated,
    Init,
    StepComplete,
    StepFailed,
    Terminated,
    Error,
}

/// Whether the standard allows `call` in `s` (Co-Simulation, the calls fuzzed here).
fn allowed(call: &str, s: State) -> bool {
    use State::*;
    match call {
        "fmi2SetupExperiment" | "fmi2EnterInitializationMode" => s == Instantiated,
        "fmi2ExitInitializationMode" => s == Init,
        "fmi2DoStep" => s == StepComplete,
        "fmi2Terminate" => matches!(s, StepComplete | StepFailed),
        "fmi2Reset" => true,
        "fmi2SetReal" | "fmi2SetInteger" => matches!(s, Instantiated | Init | StepComplete),
        "fmi2GetReal" => matches!(s, Init | StepComplete | StepFailed | Terminated | Error),
        "fmi2GetFMUstate" | "fmi2SetFMUstate" | "fmi2FreeFMUstate" => {
            matches!(
                s,
                Instantiated | Init | StepComplete | StepFailed | Terminated | Error
            )
        }
        "fmi2GetRealStatus" => matches!(s, StepComplete | StepFailed),
        _ => false,
    }
}

fn finding(what: String) -> Result<(), String> {
    Err(what)
}

thread_local! {
    /// The default bearing's GUID, Real value references and Real output value references:
    /// made once (the GUID hashes the whole model description).
    static SESSION_TABLE: (CString, Vec<u32>, Vec<u32>, u32, Vec<u32>) = {
        let b = raceway::BearingFile::default_preset();
        let table = ballbearing_fmu::variables::table(&b);
        let real = |e: &&ballbearing_fmu::variables::Entry| e.var.ty == fmi2::VarType::Real;
        let reals = table.iter().filter(real).map(|e| e.var.vr).collect();
        let outputs = table
            .iter()
            .filter(real)
            .filter(|e| e.var.causality == fmi2::Causality::Output)
            .map(|e| e.var.vr)
            .collect();
        // The Integer and Enumeration parameters but the step budget (fidelity, spall rings and
        // balls, seeds, ...).
        let ints = table
            .iter()
            .filter(|e| {
                matches!(e.var.ty, fmi2::VarType::Integer | fmi2::VarType::Enumeration)
                    && e.var.causality == fmi2::Causality::Parameter
                    && e.var.name != "solver.max_steps"
            })
            .map(|e| e.var.vr)
            .collect();
        let guid = CString::new(ballbearing_fmu::guid(&b)).expect("no NUL");
        let budget = table
            .iter()
            .find(|e| e.var.name == "solver.max_steps")
            .expect("solver.max_steps")
            .var
            .vr;
        (guid, reals, outputs, budget, ints)
    };
}

/// One instance of the BallBearing with the call state a compliant master tracks.
struct Session {
    log: LogCapture,
    c: Fmi2Component,
    state: State,
    t: f64,
    reals: Vec<u32>,
    outputs: Vec<u32>,
    /// Value reference of solver.max_steps.
    budget: u32,
    /// Integer and Enumeration parameters (solver.max_steps apart).
    ints: Vec<u32>,
    /// A saved FMU state and the call state it was saved in.
    saved: Option<(Fmi2FmuState, State)>,
}

impl Session {
    fn new() -> Result<Self, String> {
        let (guid, reals, outputs, budget, ints) = SESSION_TABLE.with(Clone::clone);
        let log = LogCapture::new();
        // SAFETY: the strings and callbacks outlive the call.
        let c = unsafe {
            sh::instantiate::<M>(
                c"fuzz".as_ptr(),
                FMI2_CO_SIMULATION,
                guid.as_ptr(),
                std::ptr::null(),
                log.callbacks(),
                0,
                0,
            )
        };
        if c.is_null() {
            return Err(format!("fmi2Instantiate returned NULL: {}", log.last()));
        }
        let s = Self {
            log,
            c,
            state: State::Instantiated,
            t: 0.0,
            reals,
            outputs,
            budget,
            ints,
            saved: None,
        };
        s.set_budget()?;
        Ok(s)
    }

    /// Gives the instance the harnesses' step budget ([`FUZZ_MAX_STEPS`]); after
    /// instantiation and after every fmi2Reset (which restores the start values).
    fn set_budget(&self) -> Result<(), String> {
        // SAFETY: live instance; one value.
        let st = unsafe { sh::set_integer::<M>(self.c, &self.budget, 1, &FUZZ_MAX_STEPS) };
        if st == Fmi2Status::Ok {
            Ok(())
        } else {
            Err(format!(
                "setting solver.max_steps failed: {}",
                self.log.last()
            ))
        }
    }

    /// Checks a call's status against the standard and moves the tracked state.
    fn check(&mut self, call: &str, st: Fmi2Status, cpu: f64, ok_to: State) -> Result<(), String> {
        if cpu > HANG_S {
            return finding(format!(
                "{call} took {cpu:.1} CPU s in state {:?}",
                self.state
            ));
        }
        if matches!(st, Fmi2Status::Fatal | Fmi2Status::Pending) {
            return finding(format!(
                "{call} returned {st:?} in state {:?}: {}",
                self.state,
                self.log.last()
            ));
        }
        if !allowed(call, self.state) {
            if st != Fmi2Status::Error {
                return finding(format!(
                    "{call} is not allowed in state {:?} but returned {st:?}",
                    self.state
                ));
            }
            return Ok(()); // refused; the master now recovers
        }
        match st {
            Fmi2Status::Ok | Fmi2Status::Warning => self.state = ok_to,
            Fmi2Status::Discard if call == "fmi2DoStep" => self.state = State::StepFailed,
            Fmi2Status::Discard => {
                return finding(format!("{call} returned fmi2Discard"));
            }
            Fmi2Status::Error => {
                if self.log.last().trim().is_empty() {
                    return finding(format!("{call} returned fmi2Error without a message"));
                }
                self.state = State::Error;
            }
            _ => {}
        }
        Ok(())
    }

    fn finite_outputs(&mut self) -> Result<(), String> {
        let mut v = vec![0.0; self.outputs.len()];
        // SAFETY: live instance, arrays of the given length.
        let st = unsafe {
            sh::get_real::<M>(
                self.c,
                self.outputs.as_ptr(),
                self.outputs.len(),
                v.as_mut_ptr(),
            )
        };
        if matches!(st, Fmi2Status::Ok | Fmi2Status::Warning) {
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return finding(format!(
                    "after a successful fmi2DoStep output vr {} is {}",
                    self.outputs[i], v[i]
                ));
            }
        }
        Ok(())
    }

    /// One call chosen by the input (after an error only the recovery calls).
    fn step(&mut self, b: &mut Bytes) -> Result<(), String> {
        let recovering = self.state == State::Error;
        let pick = if recovering {
            [6, 7, 9][b.below(3)]
        } else {
            b.below(12)
        };
        let t0 = ThreadTime::now();
        // SAFETY: (all calls below) `self.c` is a live instance; every array passed holds the
        // length passed with it, or is NULL where the fuzz case asks for a NULL array.
        unsafe {
            match pick {
                0 => {
                    let stop = b.real(1.0);
                    let st = sh::setup_experiment::<M>(
                        self.c,
                        b.u8() as i32 & 1,
                        b.real(1e-6),
                        0.0,
                        b.u8() as i32 & 1,
                        stop,
                    );
                    self.check(
                        "fmi2SetupExperiment",
                        st,
                        t0.elapsed().as_secs_f64(),
                        State::Instantiated,
                    )
                }
                1 => {
                    let st = sh::enter_initialization_mode::<M>(self.c);
                    self.check(
                        "fmi2EnterInitializationMode",
                        st,
                        t0.elapsed().as_secs_f64(),
                        State::Init,
                    )
                }
                2 => {
                    let st = sh::exit_initialization_mode::<M>(self.c);
                    self.t = 0.0;
                    self.check(
                        "fmi2ExitInitializationMode",
                        st,
                        t0.elapsed().as_secs_f64(),
                        State::StepComplete,
                    )
                }
                3 | 4 => {
                    let h =
                        [1e-6, 1e-5, 1e-4, 1e-3, 0.0, -1e-4, f64::NAN, f64::INFINITY][b.below(8)];
                    let t = match b.u8() % 6 {
                        0 => self.t + 1e-7,
                        1 => f64::NAN,
                        _ => self.t,
                    };
                    let st = sh::do_step::<M>(self.c, t, h, 1);
                    let was = self.state;
                    self.check(
                        "fmi2DoStep",
                        st,
                        t0.elapsed().as_secs_f64(),
                        State::StepComplete,
                    )?;
                    if allowed("fmi2DoStep", was)
                        && matches!(st, Fmi2Status::Ok | Fmi2Status::Warning)
                    {
                        self.t = t + h;
                        self.finite_outputs()?;
                    }
                    Ok(())
                }
                5 if b.u8() < 48 => {
                    // An Integer parameter (the fidelity level, a spall's ring or ball, ...):
                    // values around the valid ones, and far out.
                    let vr = self.ints[b.below(self.ints.len())];
                    let v = [-1, 0, 1, 2, 3, 4, 5, 14, 15, i32::MAX][b.below(10)];
                    let st = sh::set_integer::<M>(self.c, &vr, 1, &v);
                    let to = self.state;
                    self.check("fmi2SetInteger", st, t0.elapsed().as_secs_f64(), to)
                }
                5 => {
                    let vr = if b.u8() < 240 {
                        self.reals[b.below(self.reals.len())]
                    } else {
                        b.below(1 << 16) as u32
                    };
                    let v = b.real(1000.0);
                    let st = if b.u8() < 16 {
                        sh::set_real::<M>(self.c, std::ptr::null(), 1, std::ptr::null())
                    } else {
                        sh::set_real::<M>(self.c, &vr, 1, &v)
                    };
                    let to = self.state;
                    self.check("fmi2SetReal", st, t0.elapsed().as_secs_f64(), to)
                }
                6 => {
                    let st = sh::reset::<M>(self.c);
                    self.check(
                        "fmi2Reset",
                        st,
                        t0.elapsed().as_secs_f64(),
                        State::Instantiated,
                    )?;
                    if st == Fmi2Status::Ok {
                        self.set_budget()?;
                    }
                    Ok(())
                }
                7 => {
                    // a restored state brings back the call state it was saved in
                    let before = self.state;
                    if let Some((s, at)) = self.saved {
                        let st = sh::set_fmu_state::<M>(self.c, s);
                        self.check("fmi2SetFMUstate", st, t0.elapsed().as_secs_f64(), at)
                    } else {
                        let mut s = std::ptr::null_mut();
                        let st = sh::get_fmu_state::<M>(self.c, &mut s);
                        self.check("fmi2GetFMUstate", st, t0.elapsed().as_secs_f64(), before)?;
                        if st == Fmi2Status::Ok {
                            self.saved = Some((s, before));
                        }
                        Ok(())
                    }
                }
                8 => {
                    // freed twice: the handle is NULL after the first free
                    let mut s = self.saved.take().map_or(std::ptr::null_mut(), |(s, _)| s);
                    let st = sh::free_fmu_state::<M>(self.c, &mut s);
                    let to = self.state;
                    self.check("fmi2FreeFMUstate", st, t0.elapsed().as_secs_f64(), to)?;
                    let st = sh::free_fmu_state::<M>(self.c, &mut s);
                    self.check("fmi2FreeFMUstate", st, t0.elapsed().as_secs_f64(), to)
                }
                9 => Err(String::new()), // fmi2FreeInstance: the caller ends the sequence
                10 => {
                    let st = sh::terminate::<M>(self.c);
                    self.check(
                        "fmi2Terminate",
                        st,
                        t0.elapsed().as_secs_f64(),
                        State::Terminated,
                    )
                }
                _ => {
                    let n = b.below(4);
                    let vr: Vec<u32> = (0..n)
                        .map(|_| self.outputs[b.below(self.outputs.len())])
                        .collect();
                    let mut v = vec![0.0; n];
                    let st = if b.u8() < 16 && n > 0 {
                        sh::get_real::<M>(self.c, std::ptr::null(), n, std::ptr::null_mut())
                    } else {
                        sh::get_real::<M>(self.c, vr.as_ptr(), n, v.as_mut_ptr())
                    };
                    let to = self.state;
                    self.check("fmi2GetReal", st, t0.elapsed().as_secs_f64(), to)
                }
            }
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        // SAFETY: live instance; the saved state belongs to it; freed once.
        unsafe {
            if let Some((mut s, _)) = self.saved.take() {
                sh::free_fmu_state::<M>(self.c, &mut s);
            }
            sh::free_instance::<M>(self.c);
        }
    }
}

/// Harness (a): a sequence of at most 64 FMI calls chosen by `data` on one BallBearing
/// instance (lumped level), ended by `fmi2FreeInstance`.
pub fn fmi_calls(data: &[u8]) -> Result<(), String> {
    let mut b = Bytes::new(data);
    let mut s = Session::new()?;
    for _ in 0..64 {
        if b.done() {
            break;
        }
        match s.step(&mut b) {
            Ok(()) => {}
            Err(e) if e.is_empty() => break, // fmi2FreeInstance
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// The files [`input_files`] mutates: (kind, name, text).
const CORPUS: &[(&str, &str, &str)] = &[
    (
        "bearing",
        "niu2014-table1",
        include_str!("../../presets/niu2014-table1.toml"),
    ),
    (
        "bearing",
        "cwru-6205-de",
        include_str!("../../presets/cwru-6205-de.toml"),
    ),
    (
        "bearing",
        "ims-za2115",
        include_str!("../../presets/ims-za2115.toml"),
    ),
    (
        "scene",
        "default",
        include_str!("../../examples/scenes/default.toml"),
    ),
    (
        "scene",
        "sec3.5-outer-full",
        include_str!("../../examples/scenes/sec3.5-outer-full.toml"),
    ),
    (
        "sweep",
        "small",
        include_str!("../../examples/sweeps/small.toml"),
    ),
    (
        "sweep",
        "sec3.4-position",
        include_str!("../../examples/sweeps/sec3.4-position.toml"),
    ),
];

/// The key of a `key = value` line (None for tables, comments, blank lines).
fn key_of(line: &str) -> Option<&str> {
    let t = line.trim();
    if t.starts_with('#') || t.starts_with('[') {
        return None;
    }
    let (k, _) = t.split_once('=')?;
    let k = k.trim().trim_matches('"');
    (!k.is_empty()).then_some(k)
}

fn random_value(b: &mut Bytes) -> String {
    match b.u8() % 12 {
        0 => "nan".into(),
        1 => "inf".into(),
        2 => "-inf".into(),
        3 => "-1.0".into(),
        4 => "0".into(),
        5 => "1e308".into(),
        6 => "\"b\"".into(),
        7 => "true".into(),
        8 => "[1.0, \"x\"]".into(),
        9 => "{ a = 1 }".into(),
        10 => format!("{}", i64::from(b.u8()) * 1_000_000_007),
        _ => format!("{:e}", f64::from(b.u8()) * 1e-4),
    }
}

/// Harness (b): a repository file mutated by `data`, read as its kind.
pub fn input_files(data: &[u8]) -> Result<(), String> {
    let mut b = Bytes::new(data);
    let (kind, name, text) = CORPUS[b.below(CORPUS.len())];
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let mut replaced: Vec<String> = Vec::new();
    let mut other = false; // a mutation other than value replacements
    let n = 1 + b.below(4);
    for _ in 0..n {
        let i = b.below(lines.len().max(1));
        match b.u8() % 8 {
            0..=3 => {
                if let Some(k) = lines.get(i).and_then(|l| key_of(l)).map(String::from) {
                    let indent = lines[i].len() - lines[i].trim_start().len();
                    let key = lines[i]
                        .trim_start()
                        .split_once('=')
                        .map(|(k, _)| k.trim().to_string())
                        .unwrap_or_default();
                    lines[i] = format!("{}{key} = {}", " ".repeat(indent), random_value(&mut b));
                    replaced.push(k);
                }
            }
            4 => {
                if i < lines.len() {
                    lines.remove(i);
                    other = true;
                }
            }
            5 => {
                if let Some(l) = lines.get(i).cloned() {
                    lines.insert(i, l);
                    other = true;
                }
            }
            6 => {
                lines.insert(
                    i.min(lines.len()),
                    format!("fuzz_{} = {}", b.u8(), random_value(&mut b)),
                );
                other = true;
            }
            _ => {
                if let Some(l) = lines.get_mut(i) {
                    let mut bytes = l.clone().into_bytes();
                    if !bytes.is_empty() {
                        let j = b.below(bytes.len());
                        bytes[j] = b.u8();
                        *l = String::from_utf8_lossy(&bytes).into_owned();
                        other = true;
                    }
                }
            }
        }
    }
    let text = lines.join("\n") + "\n";
    let sweeps = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/sweeps");
    let read = std::panic::catch_unwind(|| -> Result<(), String> {
        match kind {
            "bearing" => raceway::BearingFile::from_toml_str(&text, "fuzz")
                .map_err(|e| e.to_string())
                .and_then(|f| {
                    raceway::Bearing::new(&f)
                        .map(|_| ())
                        .map_err(|e| e.to_string())
                }),
            "scene" => raceway::Scene::from_toml_str(&text, "fuzz", None)
                .map(|_| ())
                .map_err(|e| e.to_string()),
            _ => raceway::sweep::Sweep::from_toml_str(&text, "fuzz", &sweeps)
                .map(|_| ())
                .map_err(|e| e.to_string()),
        }
    });
    let result = match read {
        Ok(r) => r,
        Err(_) => return finding(format!("reading the {kind} file {name} panicked:\n{text}")),
    };
    if let Err(e) = result {
        if e.trim().is_empty() {
            return finding(format!("{kind} {name}: an empty error"));
        }
        let toml_ok = text.parse::<toml::Table>().is_ok();
        let named = replaced
            .iter()
            .any(|k| e.contains(k.rsplit('.').next().unwrap_or(k)));
        if !replaced.is_empty() && !other && toml_ok && !named {
            return finding(format!(
                "{kind} {name}: after replacing {replaced:?} the error names none of them: {e}\n{text}"
            ));
        }
    }
    Ok(())
}

thread_local! {
    static BLOB_SESSION: std::cell::RefCell<Option<(Session, Vec<u8>)>> = const { std::cell::RefCell::new(None) };
}

/// A lumped instance stepped to 2 ms and its serialized state.
fn blob_session() -> Result<(Session, Vec<u8>), String> {
    let s = Session::new()?;
    // SAFETY: live instance; out-pointers valid.
    unsafe {
        sh::setup_experiment::<M>(s.c, 0, 0.0, 0.0, 0, 0.0);
        sh::enter_initialization_mode::<M>(s.c);
        sh::exit_initialization_mode::<M>(s.c);
        for k in 0..20 {
            sh::do_step::<M>(s.c, k as f64 * 1e-4, 1e-4, 1);
        }
        let mut st: Fmi2FmuState = std::ptr::null_mut();
        sh::get_fmu_state::<M>(s.c, &mut st);
        let mut n = 0usize;
        sh::serialized_fmu_state_size::<M>(s.c, st, &mut n);
        let mut bytes = vec![0u8; n];
        sh::serialize_fmu_state::<M>(s.c, st, bytes.as_mut_ptr().cast(), n);
        sh::free_fmu_state::<M>(s.c, &mut st);
        Ok((s, bytes))
    }
}

/// Harness (c): the serialized state of a running instance, mutated by `data`, deserialized
/// and restored.
pub fn state_blob(data: &[u8]) -> Result<(), String> {
    BLOB_SESSION.with(|cell| {
        let mut slot = cell.borrow_mut();
        if slot.is_none() {
            *slot = Some(blob_session()?);
        }
        let (s, valid) = slot.as_mut().expect("just made");
        let mut b = Bytes::new(data);
        let mut blob = valid.clone();
        let mode = b.u8() % 4;
        let edits = 1 + b.below(8);
        for _ in 0..edits {
            match b.u8() % 4 {
                0 if !blob.is_empty() => {
                    let i = b.below(blob.len());
                    blob[i] = b.u8();
                }
                1 => {
                    let i = b.below(blob.len() + 1);
                    blob.insert(i, b.u8());
                }
                2 => {
                    let i = b.below(blob.len() + 1);
                    blob.truncate(i);
                }
                _ => {
                    let i = b.below(blob.len().max(1));
                    if i < blob.len() {
                        blob.remove(i);
                    }
                }
            }
        }
        if mode == 0 {
            // random bytes instead
            blob = (0..b.below(512)).map(|_| b.u8()).collect();
        } else if mode >= 2 && blob.len() > 8 {
            // the checksum made right again: the model's reader sees the mutation
            let n = blob.len() - 8;
            let sum = fmi2::codec::fnv1a64(&blob[..n]);
            blob[n..].copy_from_slice(&sum.to_le_bytes());
        }
        let changed = blob != *valid;
        let mut st: Fmi2FmuState = std::ptr::null_mut();
        let t0 = ThreadTime::now();
        // SAFETY: live instance; `blob` holds `blob.len()` bytes; out-pointer valid.
        let des = unsafe {
            sh::deserialize_fmu_state::<M>(s.c, blob.as_ptr().cast(), blob.len(), &mut st)
        };
        let mut result = Ok(());
        match des {
            Fmi2Status::Ok => {
                // SAFETY: live instance and state.
                let set = unsafe { sh::set_fmu_state::<M>(s.c, st) };
                if set == Fmi2Status::Ok {
                    // SAFETY: live instance.
                    let stp = unsafe { sh::do_step::<M>(s.c, 2e-3, 1e-5, 1) };
                    if matches!(stp, Fmi2Status::Ok | Fmi2Status::Warning) {
                        s.state = State::StepComplete;
                        result = s.finite_outputs();
                    }
                } else if s.log.last().trim().is_empty() {
                    result = finding("fmi2SetFMUstate refused a state without a message".into());
                }
                // SAFETY: live instance and state, freed once.
                unsafe { sh::free_fmu_state::<M>(s.c, &mut st) };
            }
            Fmi2Status::Error => {
                if !changed {
                    result = finding("the valid state was refused".into());
                } else if s.log.last().trim().is_empty() {
                    result = finding("a refused state without a message".into());
                }
            }
            other => result = finding(format!("fmi2DeSerializeFMUstate returned {other:?}")),
        }
        if t0.elapsed().as_secs_f64() > HANG_S {
            result = finding("a state took longer than the hang limit".into());
        }
        // back to the valid state for the next case
        let mut good: Fmi2FmuState = std::ptr::null_mut();
        // SAFETY: live instance; `valid` holds its bytes; the handle is freed once.
        unsafe {
            sh::reset::<M>(s.c);
            if sh::deserialize_fmu_state::<M>(s.c, valid.as_ptr().cast(), valid.len(), &mut good)
                == Fmi2Status::Ok
            {
                sh::set_fmu_state::<M>(s.c, good);
                sh::free_fmu_state::<M>(s.c, &mut good);
            }
        }
        result
    })
}

/// The seeded random driver: `cases` inputs of up to `max_len` random bytes (SplitMix64 from
/// `seed`) through `target`; the first finding with its case number and input in hex.
pub fn drive(
    target: fn(&[u8]) -> Result<(), String>,
    seed: u64,
    cases: u64,
    max_len: usize,
) -> Result<u64, String> {
    let mut x = seed;
    let mut next = || {
        x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    };
    for case in 0..cases {
        let len = (next() as usize) % (max_len + 1);
        let data: Vec<u8> = (0..len).map(|_| next() as u8).collect();
        let r =
            std::panic::catch_unwind(|| target(&data)).unwrap_or_else(|_| Err("panicked".into()));
        if let Err(e) = r {
            let hex: String = data.iter().map(|b| format!("{b:02x}")).collect();
            return Err(format!("case {case} (seed {seed}): {e}\ninput: {hex}"));
        }
    }
    Ok(cases)
}
