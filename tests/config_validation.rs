//! Invalid bearing files: each case is the niu2014-table1 preset text with one change, and the
//! error must name the offending field (`section.key`) both in `field` and in its Display.

use raceway::{BearingFile, PRESETS};

fn preset() -> &'static str {
    PRESETS
        .iter()
        .find(|(n, _)| *n == "niu2014-table1")
        .map(|(_, t)| *t)
        .expect("preset shipped")
}

/// Replaces the first line whose key is `key` inside `[section]` (a line starting with
/// `key =` or `key=`) by `new_line`; panics if the key is not found, so a changed preset
/// cannot silently turn a case into a no-op.
fn replace_line(text: &str, section: &str, key: &str, new_line: Option<&str>) -> String {
    let mut out = Vec::new();
    let mut current = String::new();
    let mut done = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with('[') {
            current = t
                .trim_start_matches('[')
                .split(']')
                .next()
                .unwrap()
                .trim()
                .to_string();
        }
        let k = t.split('=').next().unwrap_or("").trim();
        if !done && current == section && k == key && t.contains('=') {
            if let Some(n) = new_line {
                out.push(n.to_string());
            }
            done = true;
        } else {
            out.push(line.to_string());
        }
    }
    assert!(done, "[{section}] {key} not found in the preset");
    out.join("\n") + "\n"
}

fn set(section: &str, key: &str, value: &str) -> String {
    replace_line(preset(), section, key, Some(&format!("{key} = {value}")))
}

fn remove(section: &str, key: &str) -> String {
    replace_line(preset(), section, key, None)
}

/// Adds a line right after the `[section]` header.
fn insert_after_header(section: &str, line: &str) -> String {
    let header = format!("[{section}]");
    let mut out = Vec::new();
    let mut done = false;
    for l in preset().lines() {
        out.push(l.to_string());
        if !done && l.trim_start().starts_with(&header) {
            out.push(line.to_string());
            done = true;
        }
    }
    assert!(done, "no [{section}] in the preset");
    out.join("\n") + "\n"
}

#[test]
fn the_unchanged_preset_is_valid() {
    let b = BearingFile::from_toml_str(preset(), "niu2014-table1").unwrap();
    assert_eq!(b.bearing.z, 14);
    // And the editing helpers leave it valid when the value is unchanged.
    BearingFile::from_toml_str(&set("bearing", "f_inner", "0.515"), "same").unwrap();
}

/// Parses every case; returns a line per case that was accepted or named the wrong field.
fn misnamed(cases: &[(&str, String, &str)]) -> Vec<String> {
    let mut failures = Vec::new();
    for (name, text, field) in cases {
        match BearingFile::from_toml_str(text, name) {
            Ok(_) => failures.push(format!("{name}: accepted")),
            Err(e) => {
                let shown = e.to_string();
                if e.field != *field || !shown.contains(field) {
                    failures.push(format!(
                        "{name}: expected field `{field}`, got field `{}`, message `{shown}`",
                        e.field
                    ));
                }
            }
        }
    }
    failures
}

#[test]
fn invalid_files_name_the_field() {
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "f_inner = 0.5",
            set("bearing", "f_inner", "0.5"),
            "bearing.f_inner",
        ),
        (
            "f_outer = 0.45",
            set("bearing", "f_outer", "0.45"),
            "bearing.f_outer",
        ),
        (
            "f_outer = 1.5",
            set("bearing", "f_outer", "1.5"),
            "bearing.f_outer",
        ),
        (
            "ball_diameter = pitch_diameter",
            set("bearing", "ball_diameter", "70.0e-3"),
            "bearing.ball_diameter",
        ),
        (
            "ball_diameter > pitch_diameter",
            set("bearing", "ball_diameter", "80.0e-3"),
            "bearing.ball_diameter",
        ),
        (
            "ball_diameter = 0",
            set("bearing", "ball_diameter", "0.0"),
            "bearing.ball_diameter",
        ),
        (
            "negative inner_ring.mass",
            set("inner_ring", "mass", "-0.29"),
            "inner_ring.mass",
        ),
        (
            "negative pedestal.k_z",
            set("pedestal", "k_z", "-15e6"),
            "pedestal.k_z",
        ),
        (
            "unknown key in [bearing]",
            insert_after_header("bearing", "width = 20e-3"),
            "bearing.width",
        ),
        (
            "nan youngs_modulus",
            set("material", "youngs_modulus", "nan"),
            "material.youngs_modulus",
        ),
        (
            "inf density",
            set("material", "density", "inf"),
            "material.density",
        ),
        (
            "poisson 0.6",
            set("material", "poisson", "0.6"),
            "material.poisson",
        ),
        ("z = 2", set("bearing", "z", "2"), "bearing.z"),
        (
            "z = 40 (balls overlap)",
            set("bearing", "z", "40"),
            "bearing.z",
        ),
        (
            "string where a number belongs",
            set("bearing", "pitch_diameter", "\"70 mm\""),
            "bearing.pitch_diameter",
        ),
        (
            "kappa_max below kappa_inf",
            set("traction", "kappa_max", "0.04"),
            "traction.kappa_max",
        ),
        (
            "contact angle 90°",
            set("bearing", "contact_angle_free_deg", "90.0"),
            "bearing.contact_angle_free_deg",
        ),
        (
            "negative clearance",
            set("bearing", "clearance", "-1e-6"),
            "bearing.clearance",
        ),
        (
            "n_strips = 0",
            set("contact", "n_strips", "0"),
            "contact.n_strips",
        ),
        (
            "unknown hertz_method",
            set("contact", "hertz_method", "\"magic\""),
            "contact.hertz_method",
        ),
        (
            "negative edge radius",
            set("defect", "edge_radius", "-0.1e-3"),
            "defect.edge_radius",
        ),
        (
            "negative c_br",
            set("contact", "c_br", "-20.0"),
            "contact.c_br",
        ),
    ];
    assert!(cases.len() >= 12);
    let failures = misnamed(&cases);
    assert!(
        failures.is_empty(),
        "{} of {} cases misnamed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

/// Field naming where the toml error's position is awkward: a `[section]` header followed by a
/// comment (`[traction]   # C8`), a missing key (toml reports it at the table header itself) and
/// an unknown section (reported at its own header).
#[test]
fn invalid_files_with_commented_headers_or_missing_keys_name_the_field() {
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "unknown section",
            format!("{}\n[seals]\nmass = 0.1\n", preset()),
            "seals",
        ),
        (
            "missing required key",
            remove("traction", "kappa_max"),
            "traction.kappa_max",
        ),
        (
            "unknown key in [pedestal]",
            insert_after_header("pedestal", "k_x = 1e6"),
            "pedestal.k_x",
        ),
        (
            "string in [traction]",
            set("traction", "u_max", "\"fast\""),
            "traction.u_max",
        ),
        ("missing bearing.z", remove("bearing", "z"), "bearing.z"),
        (
            "missing material.poisson",
            remove("material", "poisson"),
            "material.poisson",
        ),
        (
            "bool in [material]",
            set("material", "density", "true"),
            "material.density",
        ),
    ];
    let failures = misnamed(&cases);
    assert!(
        failures.is_empty(),
        "{} of {} cases misnamed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}
