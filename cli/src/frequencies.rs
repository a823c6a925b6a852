//! `raceway frequencies`: kinematic fault frequencies (L0) of a bearing at one shaft speed.

use raceway::fault_frequencies::fault_frequencies;
use raceway::{Bearing, DEFAULT_PRESET};
use std::fmt::Write as _;

/// Arguments of `raceway frequencies`.
#[derive(clap::Args)]
pub struct Args {
    /// Bearing: a preset (niu2014-table1, cwru-6205-de, cwru-6203-fe, ims-za2115) or a TOML file
    #[arg(long, default_value = DEFAULT_PRESET)]
    pub bearing: String,
    /// Shaft (inner-ring) speed [rpm]; the outer ring is fixed
    #[arg(long, allow_negative_numbers = true)]
    pub speed_rpm: f64,
    /// Contact angle [deg] (default: the bearing's free contact angle α0)
    #[arg(long, allow_negative_numbers = true)]
    pub contact_angle_deg: Option<f64>,
    /// Print JSON (keys shaft, ftf, bpfo, bpfi, bsf, two_bsf; Hz) instead of a table
    #[arg(long)]
    pub json: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<(), String> {
    let mut out = String::new();
    if !args.speed_rpm.is_finite() {
        return Err(format!(
            "--speed-rpm {}: not a finite number",
            args.speed_rpm
        ));
    }
    let b = Bearing::load(&args.bearing).map_err(|e| e.to_string())?;
    let alpha_deg = match args.contact_angle_deg {
        Some(a) if !a.is_finite() || !(-90.0..90.0).contains(&a) => {
            return Err(format!(
                "--contact-angle-deg {a}: must be a finite angle in (−90°, 90°)"
            ))
        }
        Some(a) => a,
        None => b.alpha0.to_degrees(),
    };
    let fs = args.speed_rpm / 60.0;
    let f = fault_frequencies(&b, fs, alpha_deg.to_radians());
    if args.json {
        let text = serde_json::to_string_pretty(&f).map_err(|e| e.to_string())?;
        let _ = writeln!(out, "{text}");
        emit(&out);
        return Ok(());
    }
    let name = if b.file.name.is_empty() {
        args.bearing.as_str()
    } else {
        b.file.name.as_str()
    };
    let _ = writeln!(
        out,
        "Bearing {name}: z = {}, D = {:.3} mm, dm = {:.3} mm, contact angle {alpha_deg:.2}°",
        b.z,
        b.d * 1e3,
        b.dm * 1e3
    );
    let _ = writeln!(
        out,
        "Shaft {} rpm (fs = {:.3} Hz), outer ring fixed, pure rolling",
        args.speed_rpm, fs
    );
    let _ = writeln!(out);
    let ratio = |x: f64| if fs != 0.0 { x / fs } else { 0.0 };
    let rows = [
        ("FTF", f.ftf, "cage"),
        ("BPFO", f.bpfo, "outer-race defect"),
        ("BPFI", f.bpfi, "inner-race defect"),
        ("BSF", f.bsf, "ball spin"),
        ("2BSF", f.two_bsf, "ball defect"),
    ];
    let _ = writeln!(out, "  {:<5} {:>12}   {:>9}", "", "Hz", "× fs");
    for (label, v, what) in rows {
        let _ = writeln!(out, "  {label:<5} {v:>12.3}   {:>9.5}   {what}", ratio(v));
    }
    emit(&out);
    Ok(())
}

/// Writes the output in one go; a closed pipe (e.g. `| head`) is not an error.
fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}
