//! The committed modelDescription/modelDescription.xml must be what the variable table
//! generates for the default bearing, and the generated XML must be self-consistent.

use ballbearing_fmu::{guid, model_description_xml, variables};
use raceway::BearingFile;

const COMMITTED: &str = include_str!("../../modelDescription/modelDescription.xml");

#[test]
fn committed_model_description_is_current() {
    let fresh = model_description_xml(&BearingFile::default_preset());
    if fresh != COMMITTED {
        let line = fresh
            .lines()
            .zip(COMMITTED.lines())
            .position(|(a, b)| a != b)
            .map_or_else(
                || "the lengths differ".to_string(),
                |i| format!("first difference at line {}", i + 1),
            );
        panic!(
            "modelDescription/modelDescription.xml is stale ({line}).\n\
             Regenerate it with:  cargo run -p fmu-build -- --write-model-description"
        );
    }
}

#[test]
fn guid_covers_the_content_and_is_deterministic() {
    let b = BearingFile::default_preset();
    let g = guid(&b);
    assert!(COMMITTED.contains(&format!("guid=\"{g}\"")));
    assert_eq!(g, guid(&BearingFile::default_preset()));
    // another bearing (different ball count) gives another description and GUID
    let other = BearingFile::load("cwru-6205-de").unwrap();
    assert_ne!(other.bearing.z, b.bearing.z);
    assert_ne!(guid(&other), g);
    // a parameter start value is part of the GUID too
    let mut stiffer = b.clone();
    stiffer.pedestal.k_z *= 2.0;
    assert_ne!(guid(&stiffer), g);
}

#[test]
fn every_variable_is_in_the_xml_once_and_outputs_are_listed() {
    let b = BearingFile::default_preset();
    let xml = model_description_xml(&b);
    let table = variables::table(&b);
    for (i, e) in table.iter().enumerate() {
        let decl = format!("name=\"{}\" valueReference=\"{}\"", e.var.name, e.var.vr);
        assert_eq!(xml.matches(&decl).count(), 1, "{}", e.var.name);
        if e.var.causality == fmi2::Causality::Output {
            assert!(
                xml.contains(&format!("<Unknown index=\"{}\" dependencies=", i + 1)),
                "{} in Outputs",
                e.var.name
            );
            assert!(
                xml.contains(&format!("<Unknown index=\"{}\"/>", i + 1)),
                "{} in InitialUnknowns",
                e.var.name
            );
        }
    }
    // The reaction depends directly on the journal motion (coupling mode motion): the
    // dependencies of bearing.F.* list every journal input (what directional derivatives need).
    let index = |name: &str| 1 + table.iter().position(|e| e.var.name == name).unwrap();
    for f in ["bearing.F.x", "bearing.F.y", "bearing.F.z"] {
        let start = xml
            .find(&format!("<Unknown index=\"{}\" dependencies=\"", index(f)))
            .unwrap();
        let line = &xml[start..start + xml[start..].find("/>").unwrap()];
        let deps: Vec<usize> = line
            .split("dependencies=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap()
            .split_whitespace()
            .map(|d| d.parse().unwrap())
            .collect();
        for j in [
            "journal.x",
            "journal.y",
            "journal.z",
            "journal.v.x",
            "journal.v.y",
            "journal.v.z",
        ] {
            assert!(deps.contains(&index(j)), "{f} depends on {j}: {line}");
        }
    }
    for attr in [
        "canHandleVariableCommunicationStepSize=\"true\"",
        "canGetAndSetFMUstate=\"true\"",
        "canSerializeFMUstate=\"true\"",
        "needsExecutionTool=\"false\"",
        "canBeInstantiatedOnlyOncePerProcess=\"false\"",
        "providesDirectionalDerivative=\"true\"",
        "modelIdentifier=\"BallBearing\"",
        "<BaseUnit s=\"-1\" rad=\"1\"/>",
        "<DisplayUnit name=\"rpm\" factor=\"9.549296585513721\"/>",
        "<DefaultExperiment startTime=\"0\" stopTime=\"0.1\" tolerance=\"0.000001\" stepSize=\"0.0001\"/>",
    ] {
        assert!(xml.contains(attr), "missing {attr}");
    }
}
