//! Packs the BallBearing cdylib (`ballbearing-fmu`) into `target/fmu/BallBearing.fmu` and the rotor cdylib into
//! `target/fmu/JeffcottRotor.fmu`.
//!
//! ```text
//! cargo run --release -p fmu-build -- [--bearing <preset|file.toml> | --scene <scene.toml>] [--out target/fmu/BallBearing.fmu]
//! cargo run -p fmu-build -- --write-model-description     # refresh modelDescription/modelDescription.xml
//!                                                         # and rotor/modelDescription/modelDescription.xml
//! cargo run --release -p fmu-build -- --only rotor         # only target/fmu/JeffcottRotor.fmu
//! cargo run --release -p fmu-build -- --host-only          # quick: linux64 for this machine, no win64
//! ```
//!
//! Steps: build the release cdylib for each platform the FMU ships, honouring `CARGO_TARGET_DIR`:
//! linux64 against glibc 2.17 (`cargo zigbuild --release --target x86_64-unknown-linux-gnu.2.17`)
//! and win64 (`cargo build --release --target x86_64-pc-windows-gnu`, MinGW-w64, linked
//! statically by `.cargo/config.toml`), with the tools scripts/setup-cross.sh installs (`--host-only`:
//! linux64 for this machine's glibc only, no win64); check their exports (and the DLL's imports),
//! and hand them to `fmu-pack`, which generates modelDescription.xml and documentation/index.html
//! from the variable table for the chosen bearing, runs the cross-check reference (inputs,
//! outputs, options) through the linux64 library itself (dlopen), and zips it all.

use clap::Parser;
use raceway::BearingFile;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(Parser, Debug)]
#[command(about = "Build the BallBearing FMI 2.0 Co-Simulation FMU")]
struct Args {
    /// Bearing of the FMU: a preset name or a bearing TOML file [default: niu2014-table1].
    /// Exclusive with --scene.
    #[arg(long, conflicts_with = "scene")]
    bearing: Option<String>,
    /// Base scene of the FMU (a scene TOML file, packed as resources/scene.toml): its bearing is
    /// the FMU's, its values the parameters' start values, its later spalls, waviness and
    /// roughness fixed.
    #[arg(long)]
    scene: Option<String>,
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
    /// Quick developer build: the libraries for this machine only (binaries/linux64 needing this
    /// machine's glibc, no binaries/win64), without the cross-compilation tools of
    /// scripts/setup-cross.sh. Not for distribution.
    #[arg(long)]
    host_only: bool,
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

/// Cargo target of the linux64 binaries: cargo-zigbuild's glibc-versioned triple, linking
/// against glibc 2.17's symbol versions so that the library loads on glibc 2.17 and later
/// (RHEL 7, Debian 9, Ubuntu 18.04 and newer) rather than only on the build machine's glibc.
const LINUX64_TARGET: &str = "x86_64-unknown-linux-gnu.2.17";
/// Cargo's output folder for [`LINUX64_TARGET`] (the triple without the glibc version).
const LINUX64_TARGET_DIR: &str = "x86_64-unknown-linux-gnu";
/// Cargo target of the win64 binaries, linked by MinGW-w64 statically (`.cargo/config.toml`).
const WIN64_TARGET: &str = "x86_64-pc-windows-gnu";
/// The MinGW-w64 C compiler (the win64 linker) and its `strip`.
const MINGW_GCC: &str = "x86_64-w64-mingw32-gcc";
const MINGW_STRIP: &str = "x86_64-w64-mingw32-strip";

/// The shared libraries of one FMU, one per platform it ships.
struct Libraries {
    /// `binaries/linux64`: built against glibc 2.17 (cargo-zigbuild), or for this machine
    /// (`--host-only`, `--lib`).
    linux64: PathBuf,
    /// `binaries/win64`; none with `--host-only` or `--lib`.
    win64: Option<PathBuf>,
}

/// Runs `cargo args...`, or `program args...` for a cargo subcommand's own executable
/// (`cargo-zigbuild zigbuild ...` is `cargo zigbuild ...`).
fn run_cargo(program: Option<&Path>, args: &[&str], envs: &[(String, String)], what: &str) {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let program = program.map_or(cargo, |p| p.as_os_str().to_owned());
    eprintln!("fmu-build: cargo {}", args.join(" "));
    let status = Command::new(program)
        .args(args)
        .envs(envs.iter().map(|(k, v)| (k, v)))
        .current_dir(workspace_root())
        .status()
        .unwrap_or_else(|e| fail(format!("cannot run cargo: {e}")));
    if !status.success() {
        fail(format!("cargo build of {what} failed"));
    }
}

/// Whether `program args...` runs and exits with success.
fn runs(program: impl AsRef<std::ffi::OsStr>, args: &[&str]) -> bool {
    Command::new(program)
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Checks that the cross-compilation tools are installed (else fails naming
/// scripts/setup-cross.sh). Returns cargo-zigbuild's executable (None: `cargo zigbuild` finds it
/// on the PATH) and the environment it needs to find zig.
fn cross_tools() -> (Option<PathBuf>, Vec<(String, String)>) {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut missing = Vec::new();
    let mut envs = Vec::new();
    // cargo-zigbuild: the PyPI package's executable in the project's .venv
    // (scripts/setup-cross.sh), else a `cargo-zigbuild` on the PATH (cargo install).
    let venv_zigbuild = workspace_root()
        .join(".venv")
        .join("bin")
        .join("cargo-zigbuild");
    let zigbuild = if runs(&venv_zigbuild, &["--version"]) {
        Some(venv_zigbuild)
    } else {
        if !runs(&cargo, &["zigbuild", "--help"]) {
            missing.push("cargo-zigbuild (PyPI package cargo-zigbuild in .venv)".to_string());
        }
        None
    };
    // zig: the PyPI package ziglang in the project's .venv (scripts/setup-cross.sh), unless
    // CARGO_ZIGBUILD_PYTHON_PATH names another Python or a `zig` is on the PATH.
    let venv_python = workspace_root().join(".venv").join("bin").join("python");
    if std::env::var_os("CARGO_ZIGBUILD_PYTHON_PATH").is_none()
        && runs(&venv_python, &["-m", "ziglang", "version"])
    {
        envs.push((
            "CARGO_ZIGBUILD_PYTHON_PATH".to_string(),
            venv_python.display().to_string(),
        ));
    } else if !runs("zig", &["version"])
        && !std::env::var_os("CARGO_ZIGBUILD_PYTHON_PATH")
            .is_some_and(|py| runs(py, &["-m", "ziglang", "version"]))
    {
        missing.push(format!(
            "zig (PyPI package ziglang in {})",
            venv_python
                .parent()
                .and_then(Path::parent)
                .unwrap_or(Path::new(".venv"))
                .display()
        ));
    }
    let rustc = std::env::var_os("RUSTC").unwrap_or_else(|| "rustc".into());
    let win_std = Command::new(&rustc)
        .args(["--print", "target-libdir", "--target", WIN64_TARGET])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| PathBuf::from(String::from_utf8_lossy(&o.stdout).trim()))
        .and_then(|dir| std::fs::read_dir(dir).ok())
        .is_some_and(|mut d| {
            d.any(|e| e.is_ok_and(|e| e.file_name().to_string_lossy().starts_with("libstd-")))
        });
    if !win_std {
        missing.push(format!(
            "the Rust target {WIN64_TARGET} (rustup target add)"
        ));
    }
    if !runs(MINGW_GCC, &["--version"]) {
        missing.push(format!("{MINGW_GCC} (Debian package gcc-mingw-w64-x86-64)"));
    }
    if !missing.is_empty() {
        fail(format!(
            "the FMU's linux64 (glibc 2.17) and win64 binaries need cross-compilation tools that are \
             missing: {}. Install them with scripts/setup-cross.sh (or build for this machine only \
             with --host-only: binaries/linux64 needing this machine's glibc, no binaries/win64)",
            missing.join(", ")
        ));
    }
    (zigbuild, envs)
}

/// Builds the cdylib of `package` (library file stem `stem`): linux64 against glibc 2.17 with
/// cargo-zigbuild and win64 with MinGW-w64, or for this machine only with `host_only`.
fn build_cdylib(package: &str, stem: &str, host_only: bool) -> Libraries {
    let expect = |lib: PathBuf| {
        if !lib.is_file() {
            fail(format!("{} was not produced", lib.display()));
        }
        lib
    };
    let so = format!("lib{stem}.so");
    if host_only {
        // With `-p fmu-build` in the same invocation Cargo resolves the features of the shared
        // dependencies as for `cargo run -p fmu-build`, so nothing is rebuilt with other features.
        run_cargo(
            None,
            &["build", "--release", "-p", package, "-p", "fmu-build"],
            &[],
            package,
        );
        eprintln!(
            "fmu-build: warning: --host-only: {package}'s FMU gets binaries/linux64 built for this \
             machine's glibc and no binaries/win64; not for distribution"
        );
        return Libraries {
            linux64: expect(target_dir().join("release").join(so)),
            win64: None,
        };
    }
    let (zigbuild, envs) = cross_tools();
    run_cargo(
        zigbuild.as_deref(),
        &[
            "zigbuild",
            "--release",
            "-p",
            package,
            "--target",
            LINUX64_TARGET,
        ],
        &envs,
        package,
    );
    run_cargo(
        None,
        &[
            "build",
            "--release",
            "-p",
            package,
            "--target",
            WIN64_TARGET,
        ],
        &[],
        package,
    );
    Libraries {
        linux64: expect(
            target_dir()
                .join(LINUX64_TARGET_DIR)
                .join("release")
                .join(so),
        ),
        win64: Some(expect(
            target_dir()
                .join(WIN64_TARGET)
                .join("release")
                .join(format!("{stem}.dll")),
        )),
    }
}

/// The exported names and the imported DLLs of a PE32+ (win64) image, read from its export and
/// import directories.
fn pe_exports_imports(data: &[u8]) -> Option<(Vec<String>, Vec<String>)> {
    let u16_at = |o: usize| Some(u16::from_le_bytes(data.get(o..o + 2)?.try_into().ok()?));
    let u32_at = |o: usize| Some(u32::from_le_bytes(data.get(o..o + 4)?.try_into().ok()?));
    let pe = u32_at(0x3c)? as usize;
    if data.get(pe..pe + 4)? != b"PE\0\0" {
        return None;
    }
    let coff = pe + 4;
    let n_sections = u16_at(coff + 2)? as usize;
    let optional = coff + 20;
    if u16_at(optional)? != 0x20b {
        return None; // not PE32+
    }
    let sections = optional + u16_at(coff + 16)? as usize;
    // File offset of a relative virtual address.
    let offset = |rva: u32| -> Option<usize> {
        (0..n_sections).find_map(|i| {
            let h = sections + 40 * i;
            let (size, va, raw) = (
                u32_at(h + 8)?.max(u32_at(h + 16)?),
                u32_at(h + 12)?,
                u32_at(h + 20)?,
            );
            (va..va.checked_add(size)?)
                .contains(&rva)
                .then(|| (rva - va + raw) as usize)
        })
    };
    let c_string = |rva: u32| -> Option<String> {
        let o = offset(rva)?;
        let len = data.get(o..)?.iter().position(|&b| b == 0)?;
        String::from_utf8(data[o..o + len].to_vec()).ok()
    };
    // Data directories 0 (exports) and 1 (imports): (RVA, size) pairs from offset 112 of PE32+.
    let directory = |i: usize| u32_at(optional + 112 + 8 * i);
    let mut exports = Vec::new();
    let export_rva = directory(0)?;
    if export_rva != 0 {
        let e = offset(export_rva)?;
        let names = offset(u32_at(e + 32)?)?;
        for i in 0..u32_at(e + 24)? as usize {
            exports.push(c_string(u32_at(names + 4 * i)?)?);
        }
    }
    let mut imports = Vec::new();
    let import_rva = directory(1)?;
    if import_rva != 0 {
        let d = offset(import_rva)?;
        for i in 0.. {
            let name_rva = u32_at(d + 20 * i + 12)?;
            if name_rva == 0 {
                break;
            }
            imports.push(c_string(name_rva)?);
        }
    }
    Some((exports, imports))
}

/// Whether a DLL a win64 library imports is part of Windows itself (not a MinGW runtime DLL
/// such as libgcc_s_seh-1.dll, libwinpthread-1.dll or libstdc++-6.dll, which an importer's
/// machine does not have).
fn windows_system_dll(name: &str) -> bool {
    const SYSTEM: [&str; 10] = [
        "kernel32.dll",
        "ntdll.dll",
        "bcrypt.dll",
        "bcryptprimitives.dll",
        "advapi32.dll",
        "userenv.dll",
        "ws2_32.dll",
        "msvcrt.dll",
        "ucrtbase.dll",
        "synchronization.dll",
    ];
    let n = name.to_ascii_lowercase();
    SYSTEM.contains(&n.as_str()) || (n.starts_with("api-ms-win-") && n.ends_with(".dll"))
}

/// Checks a win64 library: it exports exactly the FMI 2.0 function set
/// ([`fmi2::exports::EXPORTED_FUNCTIONS`]) among its `fmi2*` names and imports only Windows
/// system DLLs. Returns the imported DLLs.
fn check_win64(path: &Path) -> Result<Vec<String>, String> {
    let data = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let (exports, imports) = pe_exports_imports(&data)
        .ok_or_else(|| format!("{} is not a readable PE32+ (win64) image", path.display()))?;
    let mut fmi: Vec<&str> = exports
        .iter()
        .map(String::as_str)
        .filter(|n| n.starts_with("fmi2"))
        .collect();
    fmi.sort_unstable();
    let mut expected = fmi2::exports::EXPORTED_FUNCTIONS.to_vec();
    expected.sort_unstable();
    if fmi != expected {
        let missing: Vec<&str> = expected
            .iter()
            .copied()
            .filter(|n| !fmi.contains(n))
            .collect();
        let extra: Vec<&str> = fmi
            .iter()
            .copied()
            .filter(|n| !expected.contains(n))
            .collect();
        return Err(format!(
            "{} exports {} fmi2 functions instead of the {} of FMI 2.0: missing [{}], extra [{}]",
            path.display(),
            fmi.len(),
            expected.len(),
            missing.join(", "),
            extra.join(", ")
        ));
    }
    let foreign: Vec<&str> = imports
        .iter()
        .map(String::as_str)
        .filter(|n| !windows_system_dll(n))
        .collect();
    if !foreign.is_empty() {
        return Err(format!(
            "{} imports DLLs that are not part of Windows: {} (the win64 link must be static: \
             .cargo/config.toml's [target.{WIN64_TARGET}] rustflags, which a RUSTFLAGS \
             environment variable replaces)",
            path.display(),
            foreign.join(", ")
        ));
    }
    Ok(imports)
}

// ---------------------------------------------------------------------------------------------

/// Copies the library to `<target>/fmu/stage/<name>`, without debug info when
/// `strip` is available (the release profile keeps line tables for backtraces); a `.dll` with
/// MinGW-w64's `strip`.
fn stage_library(lib: &Path, name: &str) -> PathBuf {
    let dir = target_dir().join("fmu").join("stage");
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| fail(format!("{}: {e}", dir.display())));
    let out = dir.join(name);
    let _ = std::fs::remove_file(&out);
    let strip = if name.ends_with(".dll") {
        MINGW_STRIP
    } else {
        "strip"
    };
    let stripped = Command::new(strip)
        .arg("--strip-debug")
        .arg("-o")
        .arg(&out)
        .arg(lib)
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    if !stripped {
        eprintln!(
            "fmu-build: note: `{strip}` unavailable or failed; shipping {name} with its debug info"
        );
        std::fs::copy(lib, &out).unwrap_or_else(|e| fail(format!("{}: {e}", out.display())));
    }
    out
}

/// Stages the FMU's libraries as `<model>.so` and `<model>.dll` and checks their exports (and the
/// DLL's imports). Returns the staged linux64 library (for the reference run) and the bytes of
/// both.
fn stage_libraries(libs: &Libraries, model: &str) -> (PathBuf, Vec<u8>, Option<Vec<u8>>) {
    let read =
        |p: &Path| std::fs::read(p).unwrap_or_else(|e| fail(format!("{}: {e}", p.display())));
    let staged = stage_library(&libs.linux64, &format!("{model}.so"));
    fmu_pack::check_exports(&staged).unwrap_or_else(|e| fail(e));
    let so = read(&staged);
    let dll = libs.win64.as_ref().map(|lib| {
        let staged = stage_library(lib, &format!("{model}.dll"));
        let imports = check_win64(&staged).unwrap_or_else(|e| fail(e));
        eprintln!(
            "fmu-build: {model}.dll exports the {} FMI 2.0 functions and imports only {}",
            fmi2::exports::EXPORTED_FUNCTIONS.len(),
            imports.join(", ")
        );
        read(&staged)
    });
    (staged, so, dll)
}

/// Builds `<target>/fmu/JeffcottRotor.fmu`: the rotor cdylib, its model description and
/// documentation.
fn build_rotor_fmu(host_only: bool) {
    let libs = build_cdylib("raceway-rotor", "raceway_rotor", host_only);
    let (_, so, dll) = stage_libraries(&libs, "JeffcottRotor");
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
    if let Some(dll) = &dll {
        add("binaries/win64/JeffcottRotor.dll", dll, 0o755);
    }
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
        build_rotor_fmu(args.host_only);
        if args.only == "rotor" {
            return;
        }
    }

    let source = fmu_pack::source_arg(args.bearing.as_deref(), args.scene.as_deref())
        .unwrap_or_else(|e| fail(e));
    let bearing = source.base.bearing();
    let libs = match &args.lib {
        Some(lib) => {
            eprintln!(
                "fmu-build: warning: --lib: binaries/linux64 is {}, no binaries/win64",
                lib.display()
            );
            Libraries {
                linux64: lib.clone(),
                win64: None,
            }
        }
        None => build_cdylib("ballbearing-fmu", "ballbearing_fmu", args.host_only),
    };
    let (staged, so, dll) = stage_libraries(&libs, "BallBearing");
    let mut binaries = vec![("binaries/linux64/BallBearing.so".to_string(), so)];
    if let Some(dll) = dll {
        binaries.push(("binaries/win64/BallBearing.dll".to_string(), dll));
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| target_dir().join("fmu").join("BallBearing.fmu"));
    let package = fmu_pack::Package {
        base: &source.base,
        bearing_text: &source.bearing_text,
        scene_text: source.scene_text.as_deref(),
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
