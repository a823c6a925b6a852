//! The committed rotor/modelDescription/modelDescription.xml must be what the rotor's variable
//! table generates, and the table must be consistent.

use raceway_rotor::fmu::{guid, model_description_xml, table};
use std::collections::HashSet;

const COMMITTED: &str = include_str!("../modelDescription/modelDescription.xml");

#[test]
fn committed_model_description_is_current() {
    let fresh = model_description_xml();
    if fresh != COMMITTED && std::env::var_os("RACEWAY_WRITE_MODEL_DESCRIPTION").is_some() {
        // the rotor's alone (fmu-build's --write-model-description writes the bearing's, too)
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/modelDescription/modelDescription.xml"
        );
        std::fs::write(path, &fresh).unwrap();
        eprintln!("wrote {path}; run the test again");
        return;
    }
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
            "rotor/modelDescription/modelDescription.xml is stale ({line}).\n\
             Regenerate it with:  cargo run -p fmu-build -- --write-model-description\n\
             or the rotor's alone: RACEWAY_WRITE_MODEL_DESCRIPTION=1 cargo test -p raceway-rotor \
             --test model_description"
        );
    }
    assert!(COMMITTED.contains(&format!("guid=\"{}\"", guid())));
    assert!(COMMITTED.contains("modelIdentifier=\"JeffcottRotor\""));
}

#[test]
fn names_and_value_references_are_unique_and_coupling_variables_exist() {
    let t = table();
    let vrs: HashSet<u32> = t.iter().map(|(v, _)| v.vr).collect();
    let names: HashSet<&str> = t.iter().map(|(v, _)| v.name.as_str()).collect();
    assert_eq!(vrs.len(), t.len());
    assert_eq!(names.len(), t.len());
    for n in [
        "bearing.F.x",
        "bearing.F.z",
        "bearing.dF_dx.yz",
        "bearing.dF_dv.zz",
        "journal.x",
        "journal.v.z",
        "shaft.speed",
        "disk.z",
        "coupling",
        "tlm.delay",
        "tlm.v.y",
        "tlm.v.z",
        "tlm.c0.y",
        "tlm.c0.z",
        "tlm.c1.y",
        "tlm.c1.z",
        "tlm.Zc",
    ] {
        assert!(names.contains(n), "missing {n}");
        assert!(
            COMMITTED.contains(&format!("name=\"{n}\"")),
            "{n} not in the XML"
        );
    }
}
