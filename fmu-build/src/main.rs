//! Packs the BallBearing cdylib (`ballbearing-fmu`) into `target/fmu/BallBearing.fmu` and the rotor cdylib into
//! `target/fmu/JeffcottRotor.fmu`.
//!
//! ```text
//! cargo run --release -p fmu-build -- [--bearing <preset|file.toml>] [--out target/fmu/BallBearing.fmu]
//! cargo run -p fmu-build -- --write-model-description     # refresh modelDescription/modelDescription.xml
//!                                                         # and rotor/modelDescription/modelDescription.xml
//! cargo run --release -p fmu-build -- --only rotor         # only target/fmu/JeffcottRotor.fmu
//! ```
//!
//! Steps: build the release cdylib (`cargo build --release -p ballbearing-fmu -p fmu-build`, honouring
//! `CARGO_TARGET_DIR`), generate modelDescription.xml and documentation/index.html from the
//! variable table for the chosen bearing, run the cross-check reference (inputs, outputs,
//! options) in-process through the same FMI shell the shared library exports, and zip it all.

use ballbearing_fmu::ballbearing::BEARING_RESOURCE;
use clap::Parser;
use fmi2::bindings::*;
use fmi2::Variable;
use raceway::{BearingFile, DEFAULT_PRESET, PRESETS};
use std::ffi::{CStr, CString};
use std::io::Write;
use std::os::raw::{c_char, c_int, c_void};
use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Parser, Debug)]
#[command(about = "Build the BallBearing FMI 2.0 Co-Simulation FMU")]
struct Args {
    /// Bearing of the FMU: a preset name or a bearing TOML file.
    #[arg(long, default_value = DEFAULT_PRESET)]
    bearing: String,
    /// Output file [default: TARGET_DIR/fmu/BallBearing.fmu, TARGET_DIR being cargo's target folder].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Only (re)write modelDescription/modelDescription.xml (default preset) and exit.
    #[arg(long)]
    write_model_description: bool,
    /// Use this shared library instead of building one.
    #[arg(long)]
    lib: Option<PathBuf>,
    /// Skip the reference run (documentation/BallBearing_ref.csv gets only its header).
    #[arg(long)]
    no_reference: bool,
    /// Which FMUs to build: `all`, `bearing` (BallBearing.fmu) or `rotor` (JeffcottRotor.fmu).
    #[arg(long, default_value = "all", value_parser = ["all", "bearing", "rotor"])]
    only: String,
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("fmu-build lives in the workspace")
        .to_path_buf()
}

fn target_dir() -> PathBuf {
    match std::env::var_os("CARGO_TARGET_DIR") {
        Some(d) if !d.is_empty() => {
            let p = PathBuf::from(d);
            if p.is_absolute() {
                p
            } else {
                workspace_root().join(p)
            }
        }
        _ => workspace_root().join("target"),
    }
}

fn fail(msg: impl AsRef<str>) -> ! {
    eprintln!("fmu-build: error: {}", msg.as_ref());
    std::process::exit(1);
}

fn build_cdylib() -> PathBuf {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    // With `-p fmu-build` in the same invocation Cargo resolves the features of the shared
    // dependencies as for `cargo run -p fmu-build`, so nothing is rebuilt with other features.
    eprintln!("fmu-build: cargo build --release -p ballbearing-fmu -p fmu-build");
    let status = Command::new(cargo)
        .args([
            "build",
            "--release",
            "-p",
            "ballbearing-fmu",
            "-p",
            "fmu-build",
        ])
        .current_dir(workspace_root())
        .status()
        .unwrap_or_else(|e| fail(format!("cannot run cargo: {e}")));
    if !status.success() {
        fail("cargo build of the BallBearing cdylib failed");
    }
    let lib = target_dir().join("release").join("libballbearing_fmu.so");
    if !lib.is_file() {
        fail(format!("{} was not produced", lib.display()));
    }
    lib
}

// ---------------------------------------------------------------------------------------------
// Reference run through the shipped shared library itself (dlopen), so that any importer
// loading the FMU reproduces it bit for bit
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
fn check_exports(path: &Path) -> Result<(), String> {
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
    eprintln!("fmu-build: reference run: [{}] {m}", status.name());
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

struct Reference {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
    note: Option<String>,
}

fn reference_run(
    lib: &Path,
    bearing: &BearingFile,
    bearing_text: &str,
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
    let guid = CString::new(ballbearing_fmu::guid(bearing)).expect("no NUL");
    // Resources: a temporary folder with the bearing, like the unzipped FMU.
    let dir = std::env::temp_dir().join(format!("fmu-build-ref-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| fail(format!("{}: {e}", dir.display())));
    std::fs::write(dir.join(BEARING_RESOURCE), bearing_text)
        .unwrap_or_else(|e| fail(format!("{e}")));
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
            fail("the reference instance could not be created");
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

// ---------------------------------------------------------------------------------------------

/// Copies the library to `<target>/fmu/stage/<name>`, without debug info when
/// `strip` is available (the release profile keeps line tables for backtraces).
fn stage_library(lib: &Path, name: &str) -> PathBuf {
    let dir = target_dir().join("fmu").join("stage");
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| fail(format!("{}: {e}", dir.display())));
    let out = dir.join(name);
    let _ = std::fs::remove_file(&out);
    let stripped = Command::new("strip")
        .arg("--strip-debug")
        .arg("-o")
        .arg(&out)
        .arg(lib)
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    if !stripped {
        eprintln!("fmu-build: note: `strip` unavailable or failed; shipping the library with its debug info");
        std::fs::copy(lib, &out).unwrap_or_else(|e| fail(format!("{}: {e}", out.display())));
    }
    out
}

/// Builds `<target>/fmu/JeffcottRotor.fmu`: the rotor cdylib, its model description and
/// documentation.
fn build_rotor_fmu() {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    eprintln!("fmu-build: cargo build --release -p raceway-rotor -p fmu-build");
    let status = Command::new(cargo)
        .args([
            "build",
            "--release",
            "-p",
            "raceway-rotor",
            "-p",
            "fmu-build",
        ])
        .current_dir(workspace_root())
        .status()
        .unwrap_or_else(|e| fail(format!("cannot run cargo: {e}")));
    if !status.success() {
        fail("cargo build of the rotor cdylib failed");
    }
    let lib = target_dir().join("release").join("libraceway_rotor.so");
    if !lib.is_file() {
        fail(format!("{} was not produced", lib.display()));
    }
    let staged = stage_library(&lib, "JeffcottRotor.so");
    check_exports(&staged).unwrap_or_else(|e| fail(e));
    let so = std::fs::read(&staged).unwrap_or_else(|e| fail(format!("{}: {e}", staged.display())));
    let out = target_dir().join("fmu").join("JeffcottRotor.fmu");
    let tmp = out.with_extension("fmu.part");
    let file =
        std::fs::File::create(&tmp).unwrap_or_else(|e| fail(format!("{}: {e}", tmp.display())));
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let mut add = |name: &str, data: &[u8], mode: u32| {
        zip.start_file(name, opts.unix_permissions(mode))
            .and_then(|_| zip.write_all(data).map_err(Into::into))
            .unwrap_or_else(|e| fail(format!("zip {name}: {e}")));
    };
    add(
        "modelDescription.xml",
        raceway_rotor::fmu::model_description_xml().as_bytes(),
        0o644,
    );
    add("binaries/linux64/JeffcottRotor.so", &so, 0o755);
    add(
        "documentation/index.html",
        raceway_rotor::fmu::documentation_html().as_bytes(),
        0o644,
    );
    zip.finish().unwrap_or_else(|e| fail(format!("zip: {e}")));
    std::fs::rename(&tmp, &out).unwrap_or_else(|e| fail(format!("{}: {e}", out.display())));
    println!(
        "fmu-build: wrote {} (GUID {})",
        out.display(),
        raceway_rotor::fmu::guid()
    );
}

fn main() {
    let args = Args::parse();

    if args.write_model_description {
        let rotor_path = workspace_root()
            .join("rotor")
            .join("modelDescription")
            .join("modelDescription.xml");
        std::fs::create_dir_all(rotor_path.parent().expect("has a parent"))
            .unwrap_or_else(|e| fail(format!("{e}")));
        std::fs::write(&rotor_path, raceway_rotor::fmu::model_description_xml())
            .unwrap_or_else(|e| fail(format!("{}: {e}", rotor_path.display())));
        eprintln!("fmu-build: wrote {}", rotor_path.display());
        let b = BearingFile::default_preset();
        let path = workspace_root()
            .join("modelDescription")
            .join("modelDescription.xml");
        std::fs::create_dir_all(path.parent().expect("has a parent"))
            .unwrap_or_else(|e| fail(format!("{e}")));
        std::fs::write(&path, ballbearing_fmu::model_description_xml(&b))
            .unwrap_or_else(|e| fail(format!("{}: {e}", path.display())));
        eprintln!("fmu-build: wrote {}", path.display());
        return;
    }

    if args.only != "bearing" {
        build_rotor_fmu();
        if args.only == "rotor" {
            return;
        }
    }

    // The bearing and its file text (shipped as resources/bearing.toml).
    let (bearing, bearing_text) = match PRESETS.iter().find(|(n, _)| *n == args.bearing) {
        Some((_, text)) => (
            BearingFile::load(&args.bearing).unwrap_or_else(|e| fail(e.to_string())),
            text.to_string(),
        ),
        None => {
            let text = std::fs::read_to_string(&args.bearing)
                .unwrap_or_else(|e| fail(format!("bearing '{}': {e}", args.bearing)));
            let b = BearingFile::from_toml_str(&text, &args.bearing)
                .unwrap_or_else(|e| fail(e.to_string()));
            (b, text)
        }
    };

    let lib = args.lib.clone().unwrap_or_else(build_cdylib);
    let staged = stage_library(&lib, "BallBearing.so");
    check_exports(&staged).unwrap_or_else(|e| fail(e));
    let so = std::fs::read(&staged).unwrap_or_else(|e| fail(format!("{}: {e}", staged.display())));

    let xml = ballbearing_fmu::model_description_xml(&bearing);
    let vars: Vec<Variable> = ballbearing_fmu::variables::table(&bearing)
        .into_iter()
        .map(|e| e.var)
        .collect();
    eprintln!("fmu-build: probing the fidelity levels");
    let avail = ballbearing_fmu::docs::fidelity_availability(&bearing);
    let html = ballbearing_fmu::docs::documentation_html(&bearing, &avail);

    // Cross-check style reference.
    let start_inputs =
        [1u32, 2, 3, 4].map(
            |vr| match vars.iter().find(|v| v.vr == vr).map(|v| &v.start) {
                Some(fmi2::Start::Real(x)) => *x,
                _ => fail("input table changed: vr 1..4 must be the Real inputs"),
            },
        );
    let inputs = input_rows(start_inputs);
    let mut in_csv =
        quoted(&["time", "shaft.speed", "load.Fx", "load.Fy", "load.Fz"].map(String::from));
    for (t, v) in &inputs {
        in_csv += &csv_line(&[t, &v[0], &v[1], &v[2], &v[3]].map(|x| format!("{x}")));
    }
    let opt = format!("StartTime,{START}\nStopTime,{STOP}\nStepSize,{STEP}\nRelTol,{RELTOL}\n");
    let reference = if args.no_reference {
        Reference {
            header: Vec::new(),
            rows: Vec::new(),
            note: Some("skipped with --no-reference".into()),
        }
    } else {
        eprintln!("fmu-build: reference run ({START} .. {STOP} s, step {STEP} s)");
        reference_run(&staged, &bearing, &bearing_text, &vars, &inputs)
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
        eprintln!(
            "fmu-build: warning: no reference results ({n}); BallBearing_ref.csv has only its header \
             and documentation/REFERENCE_SKIPPED.txt says why"
        );
    }

    // The archive.
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| target_dir().join("fmu").join("BallBearing.fmu"));
    if let Some(dir) = out.parent() {
        std::fs::create_dir_all(dir).unwrap_or_else(|e| fail(format!("{}: {e}", dir.display())));
    }
    let tmp = out.with_extension("fmu.part");
    let file =
        std::fs::File::create(&tmp).unwrap_or_else(|e| fail(format!("{}: {e}", tmp.display())));
    let mut zip = zip::ZipWriter::new(file);
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .unix_permissions(0o644);
    let mut add = |name: &str, data: &[u8], mode: u32| {
        zip.start_file(name, opts.unix_permissions(mode))
            .and_then(|_| zip.write_all(data).map_err(Into::into))
            .unwrap_or_else(|e| fail(format!("zip {name}: {e}")));
    };
    add("modelDescription.xml", xml.as_bytes(), 0o644);
    add("binaries/linux64/BallBearing.so", &so, 0o755);
    add("documentation/index.html", html.as_bytes(), 0o644);
    add("documentation/BallBearing_in.csv", in_csv.as_bytes(), 0o644);
    add(
        "documentation/BallBearing_ref.csv",
        ref_csv.as_bytes(),
        0o644,
    );
    add("documentation/BallBearing_ref.opt", opt.as_bytes(), 0o644);
    if let Some(n) = &reference.note {
        let text = format!(
            "The reference run was not computed: {n}\nThe FMU itself is complete; rebuild it with fmu-build once the simulation runs.\n"
        );
        add(
            "documentation/REFERENCE_SKIPPED.txt",
            text.as_bytes(),
            0o644,
        );
    }
    add(
        &format!("resources/{BEARING_RESOURCE}"),
        bearing_text.as_bytes(),
        0o644,
    );
    add(
        "resources/default-scene.toml",
        raceway::DEFAULT_SCENE.as_bytes(),
        0o644,
    );
    for (name, text) in PRESETS {
        add(
            &format!("resources/presets/{name}.toml"),
            text.as_bytes(),
            0o644,
        );
    }
    zip.finish().unwrap_or_else(|e| fail(format!("zip: {e}")));
    std::fs::rename(&tmp, &out).unwrap_or_else(|e| fail(format!("{}: {e}", out.display())));
    println!(
        "fmu-build: wrote {} (bearing '{}', {} balls, GUID {}, {} variables{})",
        out.display(),
        bearing.name,
        bearing.bearing.z,
        ballbearing_fmu::guid(&bearing),
        vars.len(),
        if reference.note.is_some() {
            ", no reference results"
        } else {
            ""
        }
    );
}
