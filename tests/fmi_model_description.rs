//! The committed modelDescription/modelDescription.xml must be what the variable table
//! generates for the default bearing, and the generated XML must be self-consistent.

use raceway::config::BearingFile;
use raceway::fmi::{guid, model_description_xml, variables};

const COMMITTED: &str = include_str!("../modelDescription/modelDescription.xml");

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
        if e.var.causality == raceway::fmi::shell::Causality::Output {
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
    for attr in [
        "canHandleVariableCommunicationStepSize=\"true\"",
        "canGetAndSetFMUstate=\"true\"",
        "canSerializeFMUstate=\"true\"",
        "needsExecutionTool=\"false\"",
        "canBeInstantiatedOnlyOncePerProcess=\"false\"",
        "providesDirectionalDerivative=\"false\"",
        "modelIdentifier=\"BallBearing\"",
        "<BaseUnit s=\"-1\" rad=\"1\"/>",
        "<DisplayUnit name=\"rpm\" factor=\"9.549296585513721\"/>",
        "<DefaultExperiment startTime=\"0\" stopTime=\"0.1\" tolerance=\"0.000001\" stepSize=\"0.0001\"/>",
    ] {
        assert!(xml.contains(attr), "missing {attr}");
    }
}
