//! Packs the BallBearing FMU for a bearing: the model description, documentation, resources and
//! the reference run (through the shipped shared library itself) around binaries made
//! elsewhere. Used by `fmu-build` (which builds the binaries) and by `raceway fmu` (which takes
//! them from an FMU made by fmu-build, so that any bearing gets an FMU without a Rust
//! toolchain: the binary reads its bearing from `resources/bearing.toml` and, for an FMU made
//! from a scene, its base scene from `resources/scene.toml`).

use ballbearing_fmu::ballbearing::BEARING_RESOURCE;
use ballbearing_fmu::base::{Base, SCENE_RESOURCE};
use fmi2::bindings::*;
use fmi2::Variable;
use raceway::{BearingFile, Scene, DEFAULT_PRESET, PRESETS};
use std::ffi::{CStr, CString};
use std::io::{Read, Write};
use std::os::raw::{c_char, c_int, c_void};
use std::path::Path;

// ---------------------------------------------------------------------------------------------
// Reference run through the shipped shared library itself (dlopen), so that an importer loading
// the FMU reproduces it bit for bit where the C maths library rounds as the build machine's
// (docs/platforms.md)
// ---------------------------------------------------------------------------------------------

#[link(name = "dl")]
extern "C" {
    fn dlopen(filename: *const c_char, flag: c_int) -> *mut c_void;
    fn dlsym(handle: *mut c_void, symbol: *const c_char) -> *mut c_void;
    fn dlerror() -> *const c_char;
}
const RTLD_NOW: c_int = 2;
const RTLD_LOCAL: c_int = 0;

type VrArr = *const Fmi2ValueReference;

/// The FMI functions the reference run needs, resolved from the shared library.
struct Api {
    instantiate: unsafe extern "C" fn(
        Fmi2String,
        Fmi2Type,
        Fmi2String,
        Fmi2String,
        *const Fmi2CallbackFunctions,
        Fmi2Boolean,
        Fmi2Boolean,
    ) -> Fmi2Component,
    free_instance: unsafe extern "C" fn(Fmi2Component),
    setup_experiment:
        unsafe extern "C" fn(Fmi2Component, Fmi2Boolean, f64, f64, Fmi2Boolean, f64) -> Fmi2Status,
    enter_init: unsafe extern "C" fn(Fmi2Component) -> Fmi2Status,
    exit_init: unsafe extern "C" fn(Fmi2Component) -> Fmi2Status,
    terminate: unsafe extern "C" fn(Fmi2Component) -> Fmi2Status,
    set_real: unsafe extern "C" fn(Fmi2Component, VrArr, usize, *const f64) -> Fmi2Status,
    get_real: unsafe extern "C" fn(Fmi2Component, VrArr, usize, *mut f64) -> Fmi2Status,
    get_integer: unsafe extern "C" fn(Fmi2Component, VrArr, usize, *mut Fmi2Integer) -> Fmi2Status,
    do_step: unsafe extern "C" fn(Fmi2Component, f64, f64, Fmi2Boolean) -> Fmi2Status,
}

impl Api {
    /// Loads `path` (kept loaded for the life of the process).
    #[allow(clippy::missing_transmute_annotations)] // the field types are the annotations
    fn load(path: &Path) -> Result<Self, String> {
        let cpath = CString::new(path.as_os_str().to_string_lossy().as_bytes())
            .map_err(|_| "path contains NUL".to_string())?;
        // SAFETY: plain dlopen/dlsym; each symbol is transmuted to its FMI 2.0 signature.
        unsafe {
            let h = dlopen(cpath.as_ptr(), RTLD_NOW | RTLD_LOCAL);
            if h.is_null() {
                let e = dlerror();
                let msg = if e.is_null() {
                    "unknown error".into()
                } else {
                    CStr::from_ptr(e).to_string_lossy().into_owned()
                };
                return Err(format!("dlopen {}: {msg}", path.display()));
            }
            let sym = |name: &str| -> Result<*mut c_void, String> {
                let c = CString::new(name).expect("no NUL");
                let p = dlsym(h, c.as_ptr());
                if p.is_null() {
                    Err(format!("{} does not export {name}", path.display()))
                } else {
                    Ok(p)
                }
            };
            macro_rules! f {
                ($name:literal) => {
                    std::mem::transmute::<*mut c_void, _>(sym($name)?)
                };
            }
            Ok(Api {
                instantiate: f!("fmi2Instantiate"),
                free_instance: f!("fmi2FreeInstance"),
                setup_experiment: f!("fmi2SetupExperiment"),
                enter_init: f!("fmi2EnterInitializationMode"),
                exit_init: f!("fmi2ExitInitializationMode"),
                terminate: f!("fmi2Terminate"),
                set_real: f!("fmi2SetReal"),
                get_real: f!("fmi2GetReal"),
                get_integer: f!("fmi2GetInteger"),
                do_step: f!("fmi2DoStep"),
            })
        }
    }
}

/// Checks that the shared library at `path` exports the whole FMI 2.0 function set (Model
/// Exchange and Co-Simulation: [`fmi2::exports::EXPORTED_FUNCTIONS`]); an importer of either
/// interface resolves every function at load time.
pub fn check_exports(path: &Path) -> Result<(), String> {
    let cpath = CString::new(path.as_os_str().to_string_lossy().as_bytes())
        .map_err(|_| "path contains NUL".to_string())?;
    // SAFETY: plain dlopen/dlsym of a library this program just built; nothing is called.
    unsafe {
        let h = dlopen(cpath.as_ptr(), RTLD_NOW | RTLD_LOCAL);
        if h.is_null() {
            return Err(format!("dlopen {} failed", path.display()));
        }
        let missing: Vec<&str> = fmi2::exports::EXPORTED_FUNCTIONS
            .iter()
            .copied()
            .filter(|name| {
                let c = CString::new(*name).expect("no NUL");
                dlsym(h, c.as_ptr()).is_null()
            })
            .collect();
        if missing.is_empty() {
            Ok(())
        } else {
            Err(format!(
                "{} does not export {} of the {} FMI 2.0 functions: {}",
                path.display(),
                missing.len(),
                fmi2::exports::EXPORTED_FUNCTIONS.len(),
                missing.join(", ")
            ))
        }
    }
}

/// Logger for the reference run. With the format "%s" the message is the sixth argument,
/// which the C ABIs of linux64 (x86-64, aarch64) pass like a fixed argument.
unsafe extern "C" fn print_logger(
    _env: Fmi2ComponentEnvironment,
    _name: Fmi2String,
    status: Fmi2Status,
    _category: Fmi2String,
    _fmt: Fmi2String,
    msg: *const c_char,
) {
    // SAFETY: the FMU passes the message as a NUL-terminated string valid during the call.
    let m = unsafe { CStr::from_ptr(msg) }.to_string_lossy();
    eprintln!("reference run: [{}] {m}", status.name());
}

/// The reference experiment: StartTime, StopTime, StepSize, RelTol.
const START: f64 = ballbearing_fmu::DEFAULT_START_TIME;
const STOP: f64 = ballbearing_fmu::DEFAULT_STOP_TIME;
const STEP: f64 = ballbearing_fmu::DEFAULT_STEP_SIZE;
const RELTOL: f64 = ballbearing_fmu::DEFAULT_TOLERANCE;

/// Rows of the input table: (time, shaft.speed, load.Fx, load.Fy, load.Fz). Piecewise constant
/// with a radial-load step at 30 ms and a speed step at 60 ms (duplicate time rows mark the
/// discontinuities, as in the FMI cross-check format).
fn input_rows(start: [f64; 4]) -> Vec<(f64, [f64; 4])> {
    let [w, fx, fy, fz] = start;
    let w2 = 10500.0 * std::f64::consts::PI / 30.0;
    let fz2 = fz * 1.5;
    vec![
        (0.0, [w, fx, fy, fz]),
        (0.03, [w, fx, fy, fz]),
        (0.03, [w, fx, fy, fz2]),
        (0.06, [w, fx, fy, fz2]),
        (0.06, [w2, fx, fy, fz2]),
        (STOP, [w2, fx, fy, fz2]),
    ]
}

/// `math.isclose` with its defaults (relative 1e-9).
fn isclose(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-9 * a.abs().max(b.abs())
}

/// The input at a communication point exactly as fmpy's `Input.interpolate` computes it
/// (continuous inputs, right-hand value at a duplicated time row when `after_event`), so that
/// `fmpy.simulate_fmu` with the shipped `_in.csv` reproduces `_ref.csv` bit for bit.
fn input_at(rows: &[(f64, [f64; 4])], time: f64, after_event: bool) -> [f64; 4] {
    let n = rows.len();
    if n < 2 {
        return rows[0].1;
    }
    let mut i0 = rows.partition_point(|(t, _)| *t < time);
    if i0 == 0 {
        return rows[0].1;
    }
    if i0 == n {
        return rows[n - 1].1;
    }
    if isclose(time, rows[i0].0) && i0 < n - 1 && isclose(rows[i0].0, rows[i0 + 1].0) {
        if after_event {
            while i0 < n - 1 && isclose(rows[i0].0, rows[i0 + 1].0) {
                i0 += 1;
            }
        }
        return rows[i0].1;
    }
    let (t0, v0) = rows[i0 - 1];
    let (t1, v1) = rows[i0];
    let w0 = (t1 - time) / (t1 - t0);
    let w1 = 1.0 - w0;
    std::array::from_fn(|k| w0 * v0[k] + w1 * v1[k])
}

/// fmpy's next input event after `time` (duplicated time rows), or +inf.
fn next_event(rows: &[(f64, [f64; 4])], time: f64) -> f64 {
    rows.windows(2)
        .filter(|w| w[0].0 == w[1].0)
        .map(|w| w[0].0)
        .find(|&t| t > time && !isclose(t, time))
        .unwrap_or(f64::INFINITY)
}

/// The reference run's results (documentation/BallBearing_ref.csv), or why there are none.
pub struct Reference {
    /// "time" and the output names.
    pub header: Vec<String>,
    /// One row per communication point.
    pub rows: Vec<Vec<String>>,
    /// Why the run was not made or stopped (then `rows` is empty).
    pub note: Option<String>,
}

/// Runs the reference experiment through the shared library at `lib` (dlopen).
fn reference_run(
    lib: &Path,
    p: &Package,
    vars: &[Variable],
    inputs: &[(f64, [f64; 4])],
) -> Reference {
    let outputs: Vec<&Variable> = vars
        .iter()
        .filter(|v| v.causality == fmi2::Causality::Output)
        .collect();
    let mut header = vec!["time".to_string()];
    header.extend(outputs.iter().map(|v| v.name.clone()));
    let mut rows = Vec::new();
    let api = match Api::load(lib) {
        Ok(a) => a,
        Err(e) => {
            return Reference {
                header,
                rows,
                note: Some(e),
            }
        }
    };
    let guid = CString::new(ballbearing_fmu::guid_for(p.base)).expect("no NUL");
    // Resources: a temporary folder with the bearing (and scene), like the unzipped FMU.
    let dir = std::env::temp_dir().join(format!("fmu-build-ref-{}", std::process::id()));
    if let Err(e) = write_resources(&dir, p.bearing_text, p.scene_text) {
        return Reference {
            header,
            rows,
            note: Some(format!("{}: {e}", dir.display())),
        };
    }
    let uri = CString::new(format!("file://{}", dir.display())).expect("no NUL");
    // SAFETY: see print_logger.
    let logger: Fmi2CallbackLogger = unsafe { fixed_args_logger(print_logger) };
    let cb = Fmi2CallbackFunctions {
        logger: Some(logger),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let input_vrs = [1u32, 2, 3, 4];
    let real_out: Vec<u32> = outputs
        .iter()
        .filter(|v| v.ty == fmi2::VarType::Real)
        .map(|v| v.vr)
        .collect();
    let int_out: Vec<u32> = outputs
        .iter()
        .filter(|v| v.ty == fmi2::VarType::Integer)
        .map(|v| v.vr)
        .collect();
    // SAFETY: the functions come from the loaded FMU library with their FMI 2.0 signatures; the
    // component comes from its fmi2Instantiate and the arrays and strings outlive each call.
    let note = unsafe {
        let c = (api.instantiate)(
            c"reference".as_ptr(),
            FMI2_CO_SIMULATION,
            guid.as_ptr(),
            uri.as_ptr(),
            &cb,
            0,
            0,
        );
        if c.is_null() {
            return Reference {
                header,
                rows,
                note: Some("the reference instance could not be created".into()),
            };
        }
        let sample = |c: Fmi2Component, t: f64| -> Result<Vec<String>, String> {
            let mut r = vec![0.0; real_out.len()];
            let mut i = vec![0; int_out.len()];
            if (api.get_real)(c, real_out.as_ptr(), r.len(), r.as_mut_ptr()) != Fmi2Status::Ok
                || (api.get_integer)(c, int_out.as_ptr(), i.len(), i.as_mut_ptr()) != Fmi2Status::Ok
            {
                return Err(format!("reading the outputs at t = {t} failed"));
            }
            let mut row = vec![format!("{t}")];
            let (mut ri, mut ii) = (r.iter(), i.iter());
            for v in &outputs {
                row.push(match v.ty {
                    fmi2::VarType::Integer => ii.next().expect("counted").to_string(),
                    _ => format!("{}", ri.next().expect("counted")),
                });
            }
            Ok(row)
        };
        let run = |rows: &mut Vec<Vec<String>>| -> Result<(), String> {
            let ok = |s: Fmi2Status, what: &str| {
                if s == Fmi2Status::Ok {
                    Ok(())
                } else {
                    Err(format!("{what} returned {}", s.name()))
                }
            };
            ok(
                (api.setup_experiment)(c, 1, RELTOL, START, 1, STOP),
                "fmi2SetupExperiment",
            )?;
            ok((api.enter_init)(c), "fmi2EnterInitializationMode")?;
            let u = input_at(inputs, START, false);
            ok(
                (api.set_real)(c, input_vrs.as_ptr(), 4, u.as_ptr()),
                "fmi2SetReal",
            )?;
            ok((api.exit_init)(c), "fmi2ExitInitializationMode")?;
            rows.push(sample(c, START)?);
            // fmpy's co-simulation loop (simulateCS): regular points start + (n+1)·interval,
            // input events in between, the last point clipped to the stop time.
            let mut time = START;
            let mut n_steps = 0u64;
            loop {
                if time > STOP || isclose(time, STOP) {
                    break;
                }
                let next_regular = START + (n_steps + 1) as f64 * STEP;
                let mut next = next_regular;
                let ev = next_event(inputs, time);
                if next > ev && !isclose(next, ev) {
                    next = ev;
                }
                if next > STOP && !isclose(next, STOP) {
                    next = STOP;
                }
                let u = input_at(inputs, time, true);
                ok(
                    (api.set_real)(c, input_vrs.as_ptr(), 4, u.as_ptr()),
                    "fmi2SetReal",
                )?;
                ok(
                    (api.do_step)(c, time, next - time, 1),
                    &format!("fmi2DoStep at t = {time}"),
                )?;
                time = next;
                rows.push(sample(c, time)?);
                if isclose(time, next_regular) {
                    n_steps += 1;
                }
            }
            ok((api.terminate)(c), "fmi2Terminate")?;
            Ok(())
        };
        let r = run(&mut rows);
        (api.free_instance)(c);
        r.err()
    };
    let _ = std::fs::remove_dir_all(&dir);
    if note.is_some() {
        rows.clear();
    }
    Reference { header, rows, note }
}

fn csv_line(cells: &[String]) -> String {
    cells.join(",") + "\n"
}

fn quoted(names: &[String]) -> String {
    names
        .iter()
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(",")
        + "\n"
}

/// A bearing argument: a preset name or a bearing TOML file; the bearing and the text shipped
/// as `resources/bearing.toml`.
pub fn bearing_arg(arg: &str) -> Result<(BearingFile, String), String> {
    match PRESETS.iter().find(|(n, _)| *n == arg) {
        Some((_, text)) => Ok((
            BearingFile::load(arg).map_err(|e| e.to_string())?,
            text.to_string(),
        )),
        None => {
            let text = std::fs::read_to_string(arg).map_err(|e| {
                format!(
                    "bearing '{arg}' is neither a preset ({}) nor a readable file: {e}",
                    PRESETS
                        .iter()
                        .map(|(n, _)| *n)
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })?;
            let b = BearingFile::from_toml_str(&text, arg).map_err(|e| e.to_string())?;
            Ok((b, text))
        }
    }
}

/// Writes `resources/bearing.toml` and, if any, `resources/scene.toml` into `dir` (created).
fn write_resources(
    dir: &Path,
    bearing_text: &str,
    scene_text: Option<&str>,
) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    std::fs::write(dir.join(BEARING_RESOURCE), bearing_text)?;
    if let Some(s) = scene_text {
        std::fs::write(dir.join(SCENE_RESOURCE), s)?;
    }
    Ok(())
}

/// The base of the FMU whose resources are `bearing_text` and `scene_text`, read as the FMU
/// reads them at fmi2Instantiate (from a temporary copy of the resources); `origin` names the
/// scene in messages.
pub fn base_of(bearing_text: &str, scene_text: Option<&str>, origin: &str) -> Result<Base, String> {
    let bearing = BearingFile::from_toml_str(bearing_text, BEARING_RESOURCE)
        .map_err(|e| format!("{origin}: bearing: {e}"))?;
    let Some(scene_text) = scene_text else {
        return Ok(Base::default_for(&bearing));
    };
    // One folder per call (threads of one process may read scenes at once).
    static CALLS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("raceway-fmu-scene-{}-{n}", std::process::id()));
    let r = write_resources(&dir, bearing_text, None)
        .map_err(|e| format!("{}: {e}", dir.display()))
        .and_then(|()| Base::from_scene_text(scene_text, origin, Some(&dir), &bearing));
    let _ = std::fs::remove_dir_all(&dir);
    r
}

/// What an FMU is made from, read from `raceway fmu`/`fmu-build` arguments.
pub struct Source {
    /// The FMU's base (bearing and scene).
    pub base: Base,
    /// `resources/bearing.toml`.
    pub bearing_text: String,
    /// `resources/scene.toml`, for an FMU made from a scene.
    pub scene_text: Option<String>,
}

/// A scene argument: the scene file at `path`, its bearing's file text, and the text shipped
/// as `resources/scene.toml`: the scene's own values with its `bearing` key set to
/// `"bearing.toml"` (the bearing resource beside it), so the FMU needs no other file. The
/// scene is checked first as `raceway simulate` reads it (errors name the file, line and
/// field), then as the FMU will read it.
pub fn scene_arg(path: &str) -> Result<Source, String> {
    Scene::load(Path::new(path)).map_err(|e| e.to_string())?;
    let text =
        std::fs::read_to_string(path).map_err(|e| format!("cannot read scene {path}: {e}"))?;
    let mut table: toml::Table =
        toml::from_str(&text).map_err(|e| format!("{path}: {}", e.to_string().trim_end()))?;
    let dir = Path::new(path).parent().unwrap_or(Path::new(""));
    let bearing_text = match table.get("bearing") {
        None => preset_text(DEFAULT_PRESET)?,
        Some(toml::Value::String(name)) => match PRESETS.iter().find(|(n, _)| n == name) {
            Some((_, t)) => t.to_string(),
            None => {
                let p = dir.join(name);
                std::fs::read_to_string(&p)
                    .map_err(|e| format!("{path}: bearing: cannot read {}: {e}", p.display()))?
            }
        },
        Some(toml::Value::Table(t)) => toml::to_string(t)
            .map_err(|e| format!("{path}: bearing: cannot write the inline bearing: {e}"))?,
        Some(_) => return Err(format!("{path}: bearing: a preset name, a path or a table")),
    };
    table.insert(
        "bearing".into(),
        toml::Value::String(BEARING_RESOURCE.into()),
    );
    let body = toml::to_string(&table).map_err(|e| format!("{path}: {e}"))?;
    let file_name = Path::new(path)
        .file_name()
        .map_or(path.into(), |n| n.to_string_lossy());
    let scene_text = format!(
        "# The base scene of this FMU: {file_name} as packed by raceway {}, its bearing the\n\
         # bearing resource beside it. Its values are the parameters' start values and the fixed\n\
         # configuration; editing it needs a new model description (repack the FMU).\n{body}",
        env!("CARGO_PKG_VERSION")
    );
    let base = base_of(&bearing_text, Some(&scene_text), path)?;
    Ok(Source {
        base,
        bearing_text,
        scene_text: Some(scene_text),
    })
}

/// The text of preset `name`.
fn preset_text(name: &str) -> Result<String, String> {
    PRESETS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, t)| t.to_string())
        .ok_or_else(|| format!("no preset '{name}'"))
}

/// The source of an FMU from `--bearing` and `--scene` (exclusive: a scene names its bearing;
/// neither: the default preset without a scene resource).
pub fn source_arg(bearing: Option<&str>, scene: Option<&str>) -> Result<Source, String> {
    match (bearing, scene) {
        (Some(_), Some(_)) => Err(
            "--bearing and --scene are exclusive: the scene names its bearing (its `bearing` \
             key); to use another bearing, write a scene that names it"
                .into(),
        ),
        (_, Some(s)) => scene_arg(s),
        (b, None) => {
            let (bearing, bearing_text) = bearing_arg(b.unwrap_or(DEFAULT_PRESET))?;
            Ok(Source {
                base: Base::default_for(&bearing),
                bearing_text,
                scene_text: None,
            })
        }
    }
}

/// What [`write_fmu`] packs.
pub struct Package<'a> {
    /// The base of the FMU: its bearing (`resources/bearing.toml`) and base scene.
    pub base: &'a Base,
    /// The text of the bearing's file.
    pub bearing_text: &'a str,
    /// The text of `resources/scene.toml` (an FMU made from a scene); `None`: the default scene.
    pub scene_text: Option<&'a str>,
    /// The shared libraries: (path in the archive, e.g. `binaries/linux64/BallBearing.so`,
    /// bytes).
    pub binaries: &'a [(String, Vec<u8>)],
    /// The linux64 library the reference run loads, or why there is no reference run.
    pub reference_lib: Result<&'a Path, String>,
}

/// What [`write_fmu`] wrote.
pub struct Written {
    /// The FMU's GUID.
    pub guid: String,
    /// The number of its scalar variables.
    pub variables: usize,
    /// Why `documentation/BallBearing_ref.csv` has only its header, if it has.
    pub reference_note: Option<String>,
}

/// Writes the FMU of `p` to `out` (through a temporary file renamed into place); `log` gets
/// the progress lines.
pub fn write_fmu(out: &Path, p: &Package, log: &dyn Fn(&str)) -> Result<Written, String> {
    let base = p.base;
    let xml = ballbearing_fmu::model_description_xml_for(base);
    let vars: Vec<Variable> = ballbearing_fmu::variables::table_for(&base.scene)
        .into_iter()
        .map(|e| e.var)
        .collect();
    log("probing the fidelity levels");
    let avail = ballbearing_fmu::docs::fidelity_availability(base);
    let html = ballbearing_fmu::docs::documentation_html_for(base, &avail);

    // Cross-check style reference.
    let mut start_inputs = [0.0; 4];
    for (x, vr) in start_inputs.iter_mut().zip([1u32, 2, 3, 4]) {
        *x = match vars.iter().find(|v| v.vr == vr).map(|v| &v.start) {
            Some(fmi2::Start::Real(x)) => *x,
            _ => return Err("input table changed: vr 1..4 must be the Real inputs".into()),
        };
    }
    let inputs = input_rows(start_inputs);
    let mut in_csv =
        quoted(&["time", "shaft.speed", "load.Fx", "load.Fy", "load.Fz"].map(String::from));
    for (t, v) in &inputs {
        in_csv += &csv_line(&[t, &v[0], &v[1], &v[2], &v[3]].map(|x| format!("{x}")));
    }
    let opt = format!("StartTime,{START}\nStopTime,{STOP}\nStepSize,{STEP}\nRelTol,{RELTOL}\n");
    let reference = match p.reference_lib {
        Ok(lib) => {
            log(&format!(
                "reference run ({START} .. {STOP} s, step {STEP} s)"
            ));
            reference_run(lib, p, &vars, &inputs)
        }
        Err(ref why) => Reference {
            header: Vec::new(),
            rows: Vec::new(),
            note: Some(why.clone()),
        },
    };
    let mut ref_csv = if reference.header.is_empty() {
        String::from("\"time\"\n")
    } else {
        quoted(&reference.header)
    };
    for r in &reference.rows {
        ref_csv += &csv_line(r);
    }
    if let Some(n) = &reference.note {
        log(&format!(
            "warning: no reference results ({n}); BallBearing_ref.csv has only its header \
             and documentation/REFERENCE_SKIPPED.txt says why"
        ));
    }

    // The archive.
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let tmp = out.with_extension("fmu.part");
    let file = std::fs::File::create(&tmp).map_err(|e| format!("{}: {e}", tmp.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let mut add = |name: &str, data: &[u8], mode: u32| -> Result<(), String> {
        zip.start_file(name, opts.unix_permissions(mode))
            .and_then(|_| zip.write_all(data).map_err(Into::into))
            .map_err(|e| format!("zip {name}: {e}"))
    };
    add("modelDescription.xml", xml.as_bytes(), 0o644)?;
    for (name, bytes) in p.binaries {
        add(name, bytes, 0o755)?;
    }
    add("documentation/index.html", html.as_bytes(), 0o644)?;
    add("documentation/BallBearing_in.csv", in_csv.as_bytes(), 0o644)?;
    add(
        "documentation/BallBearing_ref.csv",
        ref_csv.as_bytes(),
        0o644,
    )?;
    add("documentation/BallBearing_ref.opt", opt.as_bytes(), 0o644)?;
    if let Some(n) = &reference.note {
        let text = format!(
            "The reference run was not computed: {n}\nThe FMU itself is complete; rebuild it with fmu-build once the simulation runs.\n"
        );
        add(
            "documentation/REFERENCE_SKIPPED.txt",
            text.as_bytes(),
            0o644,
        )?;
    }
    add(
        &format!("resources/{BEARING_RESOURCE}"),
        p.bearing_text.as_bytes(),
        0o644,
    )?;
    if let Some(s) = p.scene_text {
        add(&format!("resources/{SCENE_RESOURCE}"), s.as_bytes(), 0o644)?;
    }
    add(
        "resources/default-scene.toml",
        raceway::DEFAULT_SCENE.as_bytes(),
        0o644,
    )?;
    for (name, text) in PRESETS {
        add(
            &format!("resources/presets/{name}.toml"),
            text.as_bytes(),
            0o644,
        )?;
    }
    zip.finish().map_err(|e| format!("zip: {e}"))?;
    std::fs::rename(&tmp, out).map_err(|e| format!("{}: {e}", out.display()))?;
    Ok(Written {
        guid: ballbearing_fmu::guid_for(base),
        variables: vars.len(),
        reference_note: reference.note,
    })
}

/// The binaries of a BallBearing FMU made by fmu-build, to be packed again for another bearing.
pub struct Template {
    /// (path in the archive, bytes) of every file under `binaries/`.
    pub binaries: Vec<(String, Vec<u8>)>,
}

impl Template {
    /// The linux64 library, if the template has one.
    pub fn linux64(&self) -> Option<&[u8]> {
        self.binaries
            .iter()
            .find(|(n, _)| n == "binaries/linux64/BallBearing.so")
            .map(|(_, b)| b.as_slice())
    }
}

/// Reads the binaries of the BallBearing FMU at `path`, after checking that they are this
/// program's: the template's model description must be the one this version writes for the
/// template's own bearing and scene (its `resources/bearing.toml` and `resources/scene.toml`),
/// so the variables it will be given match what the binaries serve.
pub fn read_template(path: &Path) -> Result<Template, String> {
    let what = path.display();
    let file = std::fs::File::open(path).map_err(|e| format!("template FMU {what}: {e}"))?;
    let mut zip =
        zip::ZipArchive::new(file).map_err(|e| format!("template FMU {what}: not a zip: {e}"))?;
    let mut text = |name: &str| -> Result<String, String> {
        let mut s = String::new();
        zip.by_name(name)
            .map_err(|e| format!("template FMU {what}: {name}: {e}"))?
            .read_to_string(&mut s)
            .map_err(|e| format!("template FMU {what}: {name}: {e}"))?;
        Ok(s)
    };
    let xml = text("modelDescription.xml")?;
    let bearing_text = text(&format!("resources/{BEARING_RESOURCE}"))?;
    let scene_text = text(&format!("resources/{SCENE_RESOURCE}")).ok();
    let origin = format!("{what}: resources/{SCENE_RESOURCE}");
    let base = base_of(&bearing_text, scene_text.as_deref(), &origin)?;
    if xml != ballbearing_fmu::model_description_xml_for(&base) {
        return Err(format!(
            "template FMU {what} was not made by this version of raceway ({}): its model \
             description differs from the one this version writes for its bearing; make the \
             template with the same version (`cargo run --release -p fmu-build`)",
            env!("CARGO_PKG_VERSION")
        ));
    }
    let mut binaries = Vec::new();
    for i in 0..zip.len() {
        let mut f = zip
            .by_index(i)
            .map_err(|e| format!("template FMU {what}: {e}"))?;
        let name = f
            .name()
            .map_err(|e| format!("template FMU {what}: {e}"))?
            .to_string();
        if f.is_file() && name.starts_with("binaries/") {
            let mut bytes = Vec::new();
            f.read_to_end(&mut bytes)
                .map_err(|e| format!("template FMU {what}: {name}: {e}"))?;
            binaries.push((name, bytes));
        }
    }
    if binaries.is_empty() {
        return Err(format!("template FMU {what} holds no binaries/"));
    }
    Ok(Template { binaries })
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/scenes");

    /// A temporary folder, removed on drop.
    struct Dir(std::path::PathBuf);
    impl Dir {
        fn new(tag: &str) -> Self {
            let p =
                std::env::temp_dir().join(format!("fmu-pack-test-{tag}-{}", std::process::id()));
            std::fs::create_dir_all(&p).unwrap();
            Self(p)
        }
    }
    impl Drop for Dir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// The packed scene is the scene as `raceway simulate` reads it, its bearing the resource.
    #[test]
    fn a_scene_packs_as_the_same_scene_on_its_bearing_resource() {
        let path = format!("{EXAMPLES}/two-spalls.toml");
        let s = source_arg(None, Some(&path)).unwrap();
        assert_eq!(s.base.scene, Scene::load(Path::new(&path)).unwrap());
        let text = s.scene_text.as_deref().unwrap();
        assert!(
            text.lines().any(|l| l == "bearing = \"bearing.toml\""),
            "{text}"
        );
        assert_eq!(s.bearing_text, PRESETS[0].1);
        assert!(s.base.scene_digest.is_some());
        // Without --scene: the default scene on the bearing, no scene resource.
        let plain = source_arg(Some("cwru-6205-de"), None).unwrap();
        assert!(plain.scene_text.is_none() && plain.base.scene_digest.is_none());
        assert_eq!(plain.base.bearing().name, "cwru-6205-de");
        let e = source_arg(Some("cwru-6205-de"), Some(&path)).err().unwrap();
        assert!(e.contains("exclusive"), "{e}");
    }

    /// A bearing named by a path relative to the scene, or written inline, is packed as
    /// bearing.toml and read back the same.
    #[test]
    fn a_scene_bearing_by_path_or_inline_becomes_the_bearing_resource() {
        let d = Dir::new("bearing");
        let cwru = PRESETS
            .iter()
            .find(|(n, _)| *n == "cwru-6205-de")
            .unwrap()
            .1;
        std::fs::create_dir_all(d.0.join("b")).unwrap();
        std::fs::write(d.0.join("b/mine.toml"), cwru).unwrap();
        let default = std::fs::read_to_string(format!("{EXAMPLES}/default.toml")).unwrap();
        let by_path = default.replace("bearing = \"niu2014-table1\"", "bearing = \"b/mine.toml\"");
        std::fs::write(d.0.join("by-path.toml"), &by_path).unwrap();
        let mut inline: toml::Table = toml::from_str(&default).unwrap();
        inline.insert(
            "bearing".into(),
            toml::Value::Table(toml::from_str(cwru).unwrap()),
        );
        std::fs::write(d.0.join("inline.toml"), toml::to_string(&inline).unwrap()).unwrap();
        let want = BearingFile::load("cwru-6205-de").unwrap();
        for f in ["by-path.toml", "inline.toml"] {
            let s = scene_arg(&d.0.join(f).to_string_lossy()).unwrap();
            assert_eq!(*s.base.bearing(), want, "{f}");
            assert_eq!(
                BearingFile::from_toml_str(&s.bearing_text, f).unwrap(),
                want,
                "{f}"
            );
        }
    }

    /// A scene the FMU cannot run is refused before anything is written, naming the field.
    #[test]
    fn an_impossible_scene_is_refused_naming_the_field() {
        let d = Dir::new("bad");
        let ball = std::fs::read_to_string(format!("{EXAMPLES}/ball-spall.toml")).unwrap();
        let p = d.0.join("ball-15.toml");
        std::fs::write(&p, ball.replace("ball = 1", "ball = 15")).unwrap();
        let e = scene_arg(&p.to_string_lossy()).err().unwrap();
        assert!(
            e.contains("defect.ball") && e.contains("ball-15.toml"),
            "{e}"
        );
    }
}
