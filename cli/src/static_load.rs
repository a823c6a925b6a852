//! `raceway static`: quasi-static (L1) load distribution, ring displacements, stiffness and
//! outer-race-control frequencies.

use raceway::load_distribution::{is_loaded, solve};
use raceway::{
    peak_contact, Bearing, OperatingPoint, StaticRating, DEFAULT_PRESET, MAX_CONTACT_PRESSURE,
};
use serde_json::json;
use std::f64::consts::TAU;
use std::fmt::Write as _;

/// Arguments of `raceway static`.
#[derive(clap::Args)]
pub struct Args {
    /// Bearing: a preset (niu2014-table1, cwru-6205-de, cwru-6203-fe, ims-za2115) or a TOML file
    #[arg(long, default_value = DEFAULT_PRESET)]
    pub bearing: String,
    /// Axial load on the inner ring along +x [N]
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub fa: f64,
    /// Radial load on the inner ring along −z [N]
    #[arg(long, allow_negative_numbers = true)]
    pub fr: f64,
    /// Shaft speed [rpm] (centrifugal and gyroscopic effects; 0 = static)
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub speed_rpm: f64,
    /// Hold the inner ring axially at this displacement [m] (an axially located ring: --fa is
    /// not applied, the axial reaction is printed); lets an angular-contact bearing carry a
    /// pure radial load
    #[arg(long, allow_negative_numbers = true)]
    pub axial_offset: Option<f64>,
    /// Print JSON (SI units: m, N, rad, rad/s, N/m; frequencies in Hz) instead of tables
    #[arg(long)]
    pub json: bool,
}

/// Runs the subcommand.
pub fn run(args: Args) -> Result<(), String> {
    let mut out = String::new();
    for (name, v) in [
        ("--fa", args.fa),
        ("--fr", args.fr),
        ("--speed-rpm", args.speed_rpm),
        ("--axial-offset", args.axial_offset.unwrap_or(0.0)),
    ] {
        if !v.is_finite() {
            return Err(format!("{name} {v}: not a finite number"));
        }
    }
    let b = Bearing::load(&args.bearing).map_err(|e| e.to_string())?;
    let case = OperatingPoint::from_rpm(args.speed_rpm, args.fa, args.fr);
    // The same input rules as the simulation and the FMU.
    case.check().map_err(|m| format!("invalid input: {m}"))?;
    if args.axial_offset.is_some() && args.fa != 0.0 {
        return Err(
            "--fa acts on a ring free to move axially; with --axial-offset the ring is located \
             and its axial reaction is computed: give one or the other"
                .into(),
        );
    }
    let q = match args.axial_offset {
        None => solve(&b, &case),
        Some(d) => raceway::load_distribution::solve_located(&b, &case, d),
    }
    .map_err(|e| e.to_string())?;
    // Plausibility (the simulation and the FMU apply the same limits): a contact beyond what the
    // model's elastic Hertz contact describes is an error; loads beyond the static load rating
    // a warning.
    let rating = StaticRating::of(&b);
    let qi: Vec<f64> = q.balls.iter().map(|e| e.q_inner).collect();
    let qo: Vec<f64> = q.balls.iter().map(|e| e.q_outer).collect();
    let (p_max, j_max, race_max, q_max) = peak_contact(&b, &qi, &qo);
    if p_max > MAX_CONTACT_PRESSURE {
        return Err(format!(
            "ball j = {}'s {} contact would carry {q_max:.0} N at a peak Hertz pressure of {:.2} GPa, \
             beyond the {:.1} GPa the model accepts (hardened steel deforms grossly): the load is \
             beyond what the bearing carries",
            j_max,
            race_max.name(),
            p_max * 1e-9,
            MAX_CONTACT_PRESSURE * 1e-9
        ));
    }
    let located_fa = args.axial_offset.map_or(args.fa, |_| q.ring_force()[0]);
    let p0 = rating.equivalent_load(located_fa, args.fr.abs());
    let mut warnings = Vec::new();
    if p0 > rating.c0 {
        warnings.push(format!(
            "the static equivalent load P0 = {p0:.0} N exceeds the basic static load rating C0 = \
             {:.0} N (ISO 76; static safety factor {:.2}): the races deform permanently",
            rating.c0,
            rating.c0 / p0
        ));
    }
    for w in &warnings {
        eprintln!("raceway: warning: {w}");
    }
    let freq = q.frequencies(&b);
    // The cage speed under the traction (the default of the kinematic levels); None at rest.
    // Where the traction has no equilibrium the reason is printed instead.
    let traction = (case.shaft_speed > 0.0)
        .then(|| raceway::models::traction_cage_speed(&b, &case, Some(&q), None));
    let traction_cage = traction.as_ref().and_then(|r| r.as_ref().ok().copied());
    let traction_error = traction
        .as_ref()
        .and_then(|r| r.as_ref().err().map(|e| e.to_string()));
    let name = if b.file.name.is_empty() {
        args.bearing.clone()
    } else {
        b.file.name.clone()
    };

    if args.json {
        let balls: Vec<_> = q
            .balls
            .iter()
            .map(|e| {
                json!({
                    "theta": e.theta,
                    "q_inner": e.q_inner,
                    "q_outer": e.q_outer,
                    "alpha_inner": e.alpha_inner,
                    "alpha_outer": e.alpha_outer,
                    "delta_inner": e.delta_inner,
                    "delta_outer": e.delta_outer,
                    "cage_speed": e.cage_speed,
                    "spin_speed": e.spin_speed,
                    "beta": e.beta,
                    "x": e.x,
                    "centrifugal": e.centrifugal,
                    "gyro_force": e.gyro_force,
                })
            })
            .collect();
        let doc = json!({
            "bearing": name,
            "speed_rpm": args.speed_rpm,
            "fa": args.fa,
            "fr": args.fr,
            "delta_axial": q.delta_axial,
            "axially_located": args.axial_offset.is_some(),
            "axial_reaction": args.axial_offset.map(|_| q.ring_force()[0]),
            "delta_radial": q.delta_radial(),
            "delta_y": q.delta_y,
            "delta_z": q.delta_z,
            "stiffness": q.stiffness,
            "cage_speed": q.cage_speed,
            "traction_cage_speed": traction_cage,
            "traction_cage_error": traction_error,
            "spin_speed": q.spin_speed,
            "frequencies": freq,
            "iterations": q.iterations,
            "residual": q.residual,
            "static_load_rating": rating.c0,
            "static_equivalent_load": p0,
            "peak_contact_pressure": p_max,
            "warnings": warnings,
            "balls": balls,
        });
        let text = serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?;
        let _ = writeln!(out, "{text}");
        emit(&out);
        return Ok(());
    }

    let _ = writeln!(
        out,
        "Bearing {name}: z = {}, α0 = {:.2}°; Fa = {} N (+x), Fr = {} N (−z), shaft {} rpm",
        b.z,
        b.alpha0.to_degrees(),
        args.fa,
        args.fr,
        args.speed_rpm
    );
    let _ = writeln!(
        out,
        "Solved in {} Newton iterations, force residual {:.1e} N",
        q.iterations, q.residual
    );
    let _ = writeln!(
        out,
        "Static load rating C0 = {:.0} N (ISO 76), P0 = {p0:.0} N (safety factor {:.2}); peak \
         Hertz pressure {:.2} GPa (ball j = {}, {} race)",
        rating.c0,
        rating.c0 / p0.max(1e-300),
        p_max * 1e-9,
        j_max,
        race_max.name()
    );
    let _ = writeln!(out);
    let _ = writeln!(out, "Inner-ring displacement relative to the outer ring:");
    let _ = writeln!(
        out,
        "  δa = {:9.4} µm   δr = {:9.4} µm   (δy = {:.4} µm, δz = {:.4} µm)",
        um(q.delta_axial),
        um(q.delta_radial()),
        um(q.delta_y),
        um(q.delta_z)
    );
    if args.axial_offset.is_some() {
        let _ = writeln!(
            out,
            "Axially located: the location pushes the ring with {:.3} N along +x against the \
             balls' axial thrust",
            q.ring_force()[0]
        );
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "Balls (θ from +z toward −y; load zone of Fr at θ = 180°):"
    );
    let _ = writeln!(
        out,
        "  {:>3} {:>7} {:>9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8}",
        "j", "θ [°]", "Q_i [N]", "Q_o [N]", "α_i [°]", "α_o [°]", "F_c [N]", "F_g [N]", "FTF [Hz]"
    );
    for (j, e) in q.balls.iter().enumerate() {
        let _ = writeln!(
            out,
            "  {:>3} {:>7.2} {:>9.2} {:>9.2} {:>8.3} {:>8.3} {:>8.3} {:>8.3} {:>8.3}{}",
            j,
            e.theta.to_degrees(),
            e.q_inner,
            e.q_outer,
            e.alpha_inner.to_degrees(),
            e.alpha_outer.to_degrees(),
            e.centrifugal,
            e.gyro_force,
            e.cage_speed / TAU,
            if is_loaded(e.q_inner) {
                ""
            } else {
                "  (unloaded)"
            }
        );
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "Stiffness ∂F/∂δ [N/m] (rows F_x, F_y, F_z; columns δx, δy, δz):"
    );
    for row in &q.stiffness {
        let _ = writeln!(
            out,
            "  {:>12.4e} {:>12.4e} {:>12.4e}",
            row[0], row[1], row[2]
        );
    }
    let _ = writeln!(out);
    if args.speed_rpm == 0.0 {
        let _ = writeln!(out, "Shaft at rest: no cage speed.");
    } else {
        let _ = writeln!(
            out,
            "Outer-race control, mean over loaded balls: cage {:.3} rad/s, spin {:.1} rad/s",
            q.cage_speed, q.spin_speed
        );
        let _ = writeln!(
            out,
            "  FTF {:.3} Hz   BPFO {:.2} Hz   BPFI {:.2} Hz   BSF {:.2} Hz   2BSF {:.2} Hz",
            freq.ftf, freq.bpfo, freq.bpfi, freq.bsf, freq.two_bsf
        );
        if let Some(e) = &traction_error {
            let _ = writeln!(out, "Cage speed under the traction: none ({e})");
        }
        if let Some(w) = traction_cage {
            let (ftf, z, fs) = (w / std::f64::consts::TAU, b.z as f64, args.speed_rpm / 60.0);
            let _ = writeln!(
                out,
                "Cage speed under the traction (a caged bearing's balls in their steady spin; \
                 the levels' default cage speed): cage {w:.3} rad/s"
            );
            let _ = writeln!(
                out,
                "  FTF {ftf:.3} Hz   BPFO {:.2} Hz   BPFI {:.2} Hz",
                z * ftf,
                z * (fs - ftf)
            );
        }
    }
    emit(&out);
    Ok(())
}

/// Metres to micrometres, with values below the printed precision shown as 0 (not −0).
fn um(x: f64) -> f64 {
    let v = x * 1e6;
    if v.abs() < 5e-5 {
        0.0
    } else {
        v
    }
}

/// Writes the output in one go; a closed pipe (e.g. `| head`) is not an error.
fn emit(text: &str) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_all(text.as_bytes());
}
