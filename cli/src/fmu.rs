//! `raceway fmu`: the BallBearing FMU for any bearing or scene, without a Rust toolchain. The
//! FMU's binary reads its bearing from `resources/bearing.toml` at instantiation, and with
//! `--scene` its base scene from `resources/scene.toml`; this command writes the model
//! description for them (its per-ball outputs sized from the number of balls, its start values
//! the scene's), the documentation, the resources and the reference run around the binaries of
//! a template FMU made by fmu-build of the same version (`cargo run --release -p fmu-build`, or
//! the `BallBearing.fmu` shipped beside the program).

use std::path::{Path, PathBuf};

/// Arguments of `raceway fmu`.
#[derive(clap::Args)]
pub struct Args {
    /// Bearing: a preset (niu2014-table1, cwru-6205-de, cwru-6203-fe, ims-za2115) or a TOML file
    /// [default: niu2014-table1]. Exclusive with --scene
    #[arg(long, conflicts_with = "scene")]
    pub bearing: Option<String>,
    /// Base scene (a scene TOML file): its bearing becomes the FMU's, its values the start values
    /// of the parameters and inputs, its spalls 1-4 defect.* … defect4.*, its later spalls,
    /// waviness and roughness fixed (packed as resources/scene.toml)
    #[arg(long)]
    pub scene: Option<String>,
    /// The FMU to write
    #[arg(long)]
    pub out: PathBuf,
    /// The FMU whose binaries are packed (made by fmu-build of this version) [default: the first
    /// of BallBearing.fmu beside this program, ../fmu/BallBearing.fmu from it (cargo's target
    /// folder), and $RACEWAY_FMU]
    #[arg(long)]
    pub template: Option<PathBuf>,
    /// Skip the reference run (documentation/BallBearing_ref.csv then has only its header)
    #[arg(long)]
    pub no_reference: bool,
}

/// Where the template is looked for when `--template` is not given.
fn template_candidates() -> Vec<PathBuf> {
    let mut c = Vec::new();
    if let Some(dir) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent().map(Path::to_path_buf))
    {
        c.push(dir.join("BallBearing.fmu"));
        c.push(dir.join("..").join("fmu").join("BallBearing.fmu"));
    }
    if let Some(p) = std::env::var_os("RACEWAY_FMU") {
        c.push(PathBuf::from(p));
    }
    c
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<(), String> {
    let source = fmu_pack::source_arg(args.bearing.as_deref(), args.scene.as_deref())?;
    let bearing = source.base.bearing();
    let template = match args.template {
        Some(t) => t,
        None => {
            let c = template_candidates();
            c.iter().find(|p| p.is_file()).cloned().ok_or_else(|| {
                format!(
                    "no template FMU with the binaries: looked for {}; make one with \
                     `cargo run --release -p fmu-build` (or scripts/demo.sh) or pass --template",
                    c.iter()
                        .map(|p| p.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            })?
        }
    };
    let t = fmu_pack::read_template(&template)?;
    // The reference run loads the template's linux64 library, where this program can load it.
    let dir = std::env::temp_dir().join(format!("raceway-fmu-{}", std::process::id()));
    let lib = dir.join("BallBearing.so");
    let reference_lib = if args.no_reference {
        Err("skipped with --no-reference".to_string())
    } else if !cfg!(all(target_os = "linux", target_arch = "x86_64")) {
        Err("the reference run loads the linux64 binary: made on linux64 only".to_string())
    } else {
        match t.linux64() {
            None => Err(format!("{} has no linux64 binary", template.display())),
            Some(so) => std::fs::create_dir_all(&dir)
                .and_then(|()| std::fs::write(&lib, so))
                .map(|()| lib.as_path())
                .map_err(|e| format!("{}: {e}", lib.display())),
        }
    };
    let package = fmu_pack::Package {
        base: &source.base,
        bearing_text: &source.bearing_text,
        scene_text: source.scene_text.as_deref(),
        binaries: &t.binaries,
        reference_lib,
    };
    let w = fmu_pack::write_fmu(&args.out, &package, &|m| eprintln!("raceway fmu: {m}"));
    let _ = std::fs::remove_dir_all(&dir);
    let w = w?;
    println!(
        "wrote {} (bearing '{}', {} balls{}, GUID {}, {} variables, binaries: {}{})",
        args.out.display(),
        bearing.name,
        bearing.bearing.z,
        match &source.scene_text {
            Some(_) => {
                let n = source.base.scene.n_defects();
                format!(
                    ", base scene '{}' with {n} spall{}",
                    source.base.scene.name,
                    if n == 1 { "" } else { "s" }
                )
            }
            None => String::new(),
        },
        w.guid,
        w.variables,
        t.binaries
            .iter()
            .map(|(n, _)| n.trim_start_matches("binaries/"))
            .collect::<Vec<_>>()
            .join(", "),
        if w.reference_note.is_some() {
            "; no reference results"
        } else {
            ""
        }
    );
    Ok(())
}
