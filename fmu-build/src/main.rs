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
//! `CARGO_TARGET_DIR`), check its exports, and hand it to `fmu-pack`, which generates
//! modelDescription.xml and documentation/index.html from the variable table for the chosen
//! bearing, runs the cross-check reference (inputs, outputs, options) through the built shared
//! library (dlopen), and zips it all.

use clap::Parser;
use raceway::{BearingFile, DEFAULT_PRESET};
use std::ffi::CString;
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

// dlopen, to check the exports of the built libraries.
#[link(name = "dl")]
extern "C" {
    fn dlopen(filename: *const c_char, flag: c_int) -> *mut c_void;
    fn dlsym(handle: *mut c_void, symbol: *const c_char) -> *mut c_void;
}
const RTLD_NOW: c_int = 2;
const RTLD_LOCAL: c_int = 0;

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

    let (bearing, bearing_text) = fmu_pack::bearing_arg(&args.bearing).unwrap_or_else(|e| fail(e));
    let lib = args.lib.clone().unwrap_or_else(build_cdylib);
    let staged = stage_library(&lib, "BallBearing.so");
    check_exports(&staged).unwrap_or_else(|e| fail(e));
    let so = std::fs::read(&staged).unwrap_or_else(|e| fail(format!("{}: {e}", staged.display())));
    let binaries = [("binaries/linux64/BallBearing.so".to_string(), so)];
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| target_dir().join("fmu").join("BallBearing.fmu"));
    let package = fmu_pack::Package {
        bearing: &bearing,
        bearing_text: &bearing_text,
        binaries: &binaries,
        reference_lib: if args.no_reference {
            Err("skipped with --no-reference".into())
        } else {
            Ok(&staged)
        },
    };
    let w = fmu_pack::write_fmu(&out, &package, &|m| eprintln!("fmu-build: {m}"))
        .unwrap_or_else(|e| fail(e));
    println!(
        "fmu-build: wrote {} (bearing '{}', {} balls, GUID {}, {} variables{})",
        out.display(),
        bearing.name,
        bearing.bearing.z,
        w.guid,
        w.variables,
        if w.reference_note.is_some() {
            ", no reference results"
        } else {
            ""
        }
    );
}
