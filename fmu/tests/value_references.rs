//! Value references never move: every variable of `value_references.tsv` (the BallBearing as
//! released before the declarative table, default preset) is still in the table with the same
//! value reference, name, type, causality, variability and start value. New variables may be
//! added (with new value references); none may be renumbered, retyped or dropped (an Integer
//! that became an Enumeration keeps its type of access, Integer).

use ballbearing_fmu::variables::table;
use fmi2::Start;
use raceway::BearingFile;

const LOCK: &str = include_str!("value_references.tsv");

#[test]
fn released_variables_keep_their_value_references_and_attributes() {
    let t = table(&BearingFile::default_preset());
    let mut checked = 0;
    for line in LOCK.lines().filter(|l| !l.starts_with('#')) {
        let f: Vec<&str> = line.split('\t').collect();
        let [vr, name, ty, causality, variability, start] = f[..] else {
            panic!("malformed line: {line}");
        };
        let vr: u32 = vr.parse().unwrap();
        let e = t
            .iter()
            .find(|e| e.var.vr == vr)
            .unwrap_or_else(|| panic!("value reference {vr} ('{name}') is gone"));
        let v = &e.var;
        assert_eq!(v.name, name, "value reference {vr}");
        // An Integer may become an Enumeration (a mode switch with named items): it is still
        // read and written with fmi2GetInteger/fmi2SetInteger under the same value reference.
        assert_eq!(v.ty.access_type().name(), ty, "{name}");
        assert_eq!(v.causality.name(), causality, "{name}");
        assert_eq!(v.variability.name(), variability, "{name}");
        match (&v.start, start) {
            (Start::None, "-") => {}
            (Start::Real(x), s) => assert_eq!(*x, s.parse::<f64>().unwrap(), "{name}"),
            (Start::Integer(i), s) => assert_eq!(*i, s.parse::<i32>().unwrap(), "{name}"),
            (other, s) => panic!("{name}: start {other:?}, released {s}"),
        }
        checked += 1;
    }
    assert_eq!(checked, 119 + 2 * 142 + 2 + 15);
}
