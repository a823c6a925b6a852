//! Coupling mode tlm of the JeffcottRotor FMU through the generic FMI shell (the code the C
//! entry points run): the new variables, the start values of the line, the step-size check,
//! the warnings, order independence of a Jacobi master, and the FMU state.

use fmi2::bindings::*;
use fmi2::capture::LogCapture;
use fmi2::functions as sh;
use raceway_rotor::fmu::{guid, table, JeffcottRotor};
use std::ffi::CString;

type M = JeffcottRotor;
/// One rotor instance with logging on, and what it logged.
struct Rotor {
    log: LogCapture,
    c: Fmi2Component,
}

fn vr(name: &str) -> u32 {
    table()
        .into_iter()
        .find(|(v, _)| v.name == name)
        .unwrap_or_else(|| panic!("no variable {name}"))
        .0
        .vr
}

impl Rotor {
    fn new() -> Self {
        let log = LogCapture::new();
        let g = CString::new(guid()).unwrap();
        // SAFETY: test importer: the strings and callbacks outlive the instance (FMI 2.0
        // pointer rules).
        let c = unsafe {
            sh::instantiate::<M>(
                c"rotor".as_ptr(),
                FMI2_CO_SIMULATION,
                g.as_ptr(),
                std::ptr::null(),
                log.callbacks(),
                0,
                1,
            )
        };
        assert!(!c.is_null());
        // SAFETY: as above; the instance is live.
        let status = unsafe { sh::setup_experiment::<M>(c, 1, 1e-8, 0.0, 0, 0.0) };
        assert_eq!(status, Fmi2Status::Ok);
        Rotor { log, c }
    }

    /// A rotor in coupling mode tlm with the given Real parameters, initialized.
    fn tlm(params: &[(&str, f64)]) -> Self {
        let r = Rotor::new();
        assert_eq!(r.set_int("coupling", 1), Fmi2Status::Ok);
        for (n, v) in params {
            assert_eq!(r.set(n, *v), Fmi2Status::Ok, "{n}");
        }
        assert_eq!(r.init(), Fmi2Status::Ok, "{:?}", r.messages());
        r
    }

    fn init(&self) -> Fmi2Status {
        // SAFETY: test importer: the instance is live.
        unsafe {
            assert_eq!(sh::enter_initialization_mode::<M>(self.c), Fmi2Status::Ok);
            sh::exit_initialization_mode::<M>(self.c)
        }
    }

    fn set(&self, name: &str, v: f64) -> Fmi2Status {
        let r = vr(name);
        // SAFETY: test importer: one value reference and one value, the instance is live.
        unsafe { sh::set_real::<M>(self.c, &r, 1, &v) }
    }

    fn set_int(&self, name: &str, v: i32) -> Fmi2Status {
        let r = vr(name);
        // SAFETY: as in `set`.
        unsafe { sh::set_integer::<M>(self.c, &r, 1, &v) }
    }

    fn get(&self, name: &str) -> f64 {
        let r = vr(name);
        let mut v = f64::NAN;
        // SAFETY: as in `set`.
        let s = unsafe { sh::get_real::<M>(self.c, &r, 1, &mut v) };
        assert_eq!(
            s,
            Fmi2Status::Ok,
            "get {name}: {:?}",
            self.messages().last()
        );
        v
    }

    fn step(&self, t: f64, h: f64) -> Fmi2Status {
        // SAFETY: test importer: the instance is live.
        unsafe { sh::do_step::<M>(self.c, t, h, 1) }
    }

    /// The tlm.* outputs.
    fn waves(&self) -> [f64; 5] {
        ["tlm.c0.y", "tlm.c0.z", "tlm.c1.y", "tlm.c1.z", "tlm.Zc"].map(|n| self.get(n))
    }

    fn messages(&self) -> Vec<(Fmi2Status, String, String)> {
        self.log.lock().unwrap().clone()
    }

    fn warnings(&self) -> Vec<String> {
        self.messages()
            .into_iter()
            .filter(|(s, _, _)| *s == Fmi2Status::Warning)
            .map(|(_, _, m)| m)
            .collect()
    }

    fn save(&self) -> Vec<u8> {
        let mut s: Fmi2FmuState = std::ptr::null_mut();
        let mut n = 0usize;
        // SAFETY: test importer: the instance is live, the state pointer and the buffer are
        // valid for the sizes passed.
        unsafe {
            assert_eq!(sh::get_fmu_state::<M>(self.c, &mut s), Fmi2Status::Ok);
            assert_eq!(
                sh::serialized_fmu_state_size::<M>(self.c, s, &mut n),
                Fmi2Status::Ok
            );
            let mut bytes = vec![0 as Fmi2Byte; n];
            assert_eq!(
                sh::serialize_fmu_state::<M>(self.c, s, bytes.as_mut_ptr(), n),
                Fmi2Status::Ok
            );
            assert_eq!(sh::free_fmu_state::<M>(self.c, &mut s), Fmi2Status::Ok);
            bytes.iter().map(|b| *b as u8).collect()
        }
    }

    fn restore(&self, bytes: &[u8]) -> Fmi2Status {
        let b: Vec<Fmi2Byte> = bytes.iter().map(|x| *x as Fmi2Byte).collect();
        let mut s: Fmi2FmuState = std::ptr::null_mut();
        // SAFETY: test importer: the instance is live, the buffer is valid for its length.
        unsafe {
            let st = sh::deserialize_fmu_state::<M>(self.c, b.as_ptr(), b.len(), &mut s);
            if st != Fmi2Status::Ok {
                return st;
            }
            let st = sh::set_fmu_state::<M>(self.c, s);
            assert_eq!(sh::free_fmu_state::<M>(self.c, &mut s), Fmi2Status::Ok);
            st
        }
    }
}

impl Drop for Rotor {
    fn drop(&mut self) {
        // SAFETY: test importer: the instance is live and freed once.
        unsafe { sh::free_instance::<M>(self.c) };
    }
}

/// A quiet rotor for the line: no loads or journal damping (they would only warn).
const QUIET: [(&str, f64); 4] = [
    ("load.Fx", 0.0),
    ("load.Fz", 0.0),
    ("journal.c", 0.0),
    ("unbalance", 0.0),
];

#[test]
fn the_new_variables_have_their_value_references_and_causalities() {
    use fmi2::{Causality, VarType};
    let t = table();
    let find = |n: &str| t.iter().find(|(v, _)| v.name == n).unwrap().0.clone();
    for (n, r, c) in [
        ("tlm.v.y", 30, Causality::Input),
        ("tlm.v.z", 31, Causality::Input),
        ("coupling", 116, Causality::Parameter),
        ("tlm.delay", 117, Causality::Parameter),
        ("tlm.c0.y", 1017, Causality::Output),
        ("tlm.c0.z", 1018, Causality::Output),
        ("tlm.c1.y", 1019, Causality::Output),
        ("tlm.c1.z", 1020, Causality::Output),
        ("tlm.Zc", 1021, Causality::Output),
    ] {
        let v = find(n);
        assert_eq!((v.vr, v.causality), (r, c), "{n}");
    }
    // coupling stays an Integer (libcosim ignores Enumerations); disk.axial is an Enumeration
    // (read and written as an Integer) with named items.
    let c = find("coupling");
    assert_eq!(c.ty, VarType::Integer);
    assert_eq!((c.min, c.max), (Some(0.0), Some(1.0)));
    assert_eq!(c.start, fmi2::Start::Integer(0));
    let a = find("disk.axial");
    assert_eq!(a.ty.access_type(), VarType::Integer);
    assert_eq!(a.ty, VarType::Enumeration);
    assert_eq!(a.declared_type.as_deref(), Some("DiskAxial"));
    let enums = raceway_rotor::fmu::enumerations();
    let items = |t: &str| -> Vec<(i32, String)> {
        let e = enums.iter().find(|e| e.name == t).unwrap();
        e.items.iter().map(|i| (i.value, i.name.clone())).collect()
    };
    assert_eq!(
        items("DiskAxial"),
        [(0, "lateral".into()), (1, "with_journal".into())]
    );
    assert_eq!(find("tlm.delay").start, fmi2::Start::Real(1e-4));
    // the released variables kept their value references and their places
    assert_eq!((t[0].0.name.as_str(), t[0].0.vr), ("bearing.F.x", 1));
    assert_eq!((t[40].0.name.as_str(), t[40].0.vr), ("journal.x", 1000));
    assert_eq!((t[56].0.name.as_str(), t[56].0.vr), ("unbalance.F.z", 1016));
    // the tlm.* outputs have no dependencies, the others depend on the inputs
    let xml = raceway_rotor::fmu::model_description_xml();
    for n in ["tlm.c0.y", "tlm.c0.z", "tlm.c1.y", "tlm.c1.z", "tlm.Zc"] {
        let i = t.iter().position(|(v, _)| v.name == n).unwrap() + 1;
        let entry = format!("<Unknown index=\"{i}\" dependencies=\"\" dependenciesKind=\"\"/>");
        assert!(xml.contains(&entry), "{n}: {entry}");
    }
    let i = t.iter().position(|(v, _)| v.name == "journal.v.y").unwrap() + 1;
    let tv = t.iter().position(|(v, _)| v.name == "tlm.v.y").unwrap() + 1;
    let line = xml
        .lines()
        .find(|l| l.contains(&format!("<Unknown index=\"{i}\" dependencies=")))
        .unwrap();
    assert!(line.contains(&format!(" {tv} ")), "{line}");
}

#[test]
fn force_mode_is_the_default_and_its_tlm_outputs_are_zero() {
    let r = Rotor::new();
    assert_eq!(r.init(), Fmi2Status::Ok);
    assert_eq!(r.waves(), [0.0; 5]);
    let mut c = -1;
    let v = vr("coupling");
    // SAFETY: test importer: one value reference and one value, the instance is live.
    let status = unsafe { sh::get_integer::<M>(r.c, &v, 1, &mut c) };
    assert_eq!(status, Fmi2Status::Ok);
    assert_eq!(c, 0);
    // tlm.v set in force mode: one warning at the next step, then quiet
    assert_eq!(r.set("tlm.v.y", 1e-3), Fmi2Status::Ok);
    assert_eq!(r.step(0.0, 1e-4), Fmi2Status::Warning);
    assert!(r
        .warnings()
        .iter()
        .any(|w| w.contains("tlm.v.y") && w.contains("ignored in coupling mode force")));
    assert_eq!(r.set("tlm.v.y", 2e-3), Fmi2Status::Ok);
    assert_eq!(r.step(1e-4, 1e-4), Fmi2Status::Ok);
}

#[test]
fn at_the_start_the_journal_carries_the_disk_weight_and_the_line_is_logged() {
    let mut ps = QUIET.to_vec();
    ps.push(("tlm.delay", 1e-4));
    let r = Rotor::tlm(&ps);
    let (md, g, k, c) = (8.0, 9.81, 2.0e6, 160.0);
    assert_eq!(r.waves(), [0.0, -md * g, 0.0, -md * g, k * 1e-4 + c]);
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());
    let info: Vec<_> = r
        .messages()
        .into_iter()
        .filter(|(s, cat, m)| {
            *s == Fmi2Status::Ok && cat == "logEvents" && m.contains("transmission line")
        })
        .collect();
    assert_eq!(info.len(), 1, "{info:?}");
    let m = &info[0].2;
    for part in [
        "Zc = shaft.k*T = 200 N.s/m",
        "tlm.Zc = Zc + shaft.c = 360 N.s/m",
        "T = tlm.delay = 0.0001 s",
        "= 0.25 % of disk.mass = 8 kg",
        "T_acc = sqrt(0.01 disk.mass/shaft.k) = 0.0002 s",
        "passive: stable at any delay",
    ] {
        assert!(m.contains(part), "'{part}' not in: {m}");
    }
    // in initialization mode too
    let r = Rotor::new();
    assert_eq!(r.set_int("coupling", 1), Fmi2Status::Ok);
    // SAFETY: test importer: the instance is live.
    unsafe { assert_eq!(sh::enter_initialization_mode::<M>(r.c), Fmi2Status::Ok) };
    assert_eq!(r.get("tlm.c1.z"), -md * g);
}

#[test]
fn a_coarse_delay_and_bearing_side_parameters_warn_once_at_initialization() {
    let r = Rotor::tlm(&[("tlm.delay", 1e-3), ("journal.c", 50.0)]);
    let w = r.warnings();
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(w[0].contains("tlm.delay = 0.001 s exceeds the largest accurate delay"));
    assert!(w[0].contains("accuracy, not stability"));
    assert!(w[1].starts_with("journal.c = 50 N.s/m, load.Fx = 4000 N, load.Fz = -1000 N do not act in coupling mode tlm"), "{}", w[1]);
    assert!(!w[1].contains("load.Fy"));
}

#[test]
fn the_largest_accurate_delay_itself_does_not_warn() {
    // T_acc = sqrt(0.01 * 8 kg / 2e6 N/m) = 2e-4 s exactly in binary, the bound included
    let mut ps = QUIET.to_vec();
    ps.push(("tlm.delay", 2e-4));
    let r = Rotor::tlm(&ps);
    assert!(r.warnings().is_empty(), "{:?}", r.warnings());
}

#[test]
fn tlm_mode_without_disk_or_shaft_is_refused_naming_the_parameter() {
    for (name, msg) in [
        ("disk.mass", "disk.mass = 0 kg"),
        ("shaft.k", "shaft.k = 0 N/m"),
    ] {
        let r = Rotor::new();
        assert_eq!(r.set_int("coupling", 1), Fmi2Status::Ok);
        assert_eq!(r.set(name, 0.0), Fmi2Status::Ok);
        assert_eq!(r.init(), Fmi2Status::Error);
        let m = r.messages().last().unwrap().2.clone();
        assert!(m.contains(msg) && m.contains("coupling = 1 (tlm)"), "{m}");
    }
    let r = Rotor::new();
    assert_eq!(r.set_int("coupling", 1), Fmi2Status::Ok);
    assert_eq!(r.set("tlm.delay", 0.0), Fmi2Status::Ok);
    assert_eq!(r.init(), Fmi2Status::Error);
    assert!(r
        .messages()
        .last()
        .unwrap()
        .2
        .contains("tlm.delay = 0 s must be > 0"));
    // the shell refuses values outside the declared range
    let r = Rotor::new();
    assert_eq!(r.set_int("coupling", 2), Fmi2Status::Error);
}

#[test]
fn a_step_other_than_the_delay_is_refused_and_changes_nothing() {
    let r = Rotor::tlm(&QUIET);
    assert_eq!(r.set("tlm.v.z", 1e-3), Fmi2Status::Ok);
    assert_eq!(r.step(0.0, 1e-4), Fmi2Status::Ok);
    let state = r.save();
    let before = (r.waves(), r.get("disk.z"), r.get("journal.z"));
    assert_eq!(r.step(1e-4, 5e-5), Fmi2Status::Error);
    let m = r.messages().last().unwrap().2.clone();
    assert!(
        m.contains(
            "communication step 5e-5 s differs from the TLM line's delay tlm.delay = 1e-4 s: \
             set tlm.delay to the master's communication step"
        ),
        "{m}"
    );
    assert_eq!((r.waves(), r.get("disk.z"), r.get("journal.z")), before);
    // out of the Error state by the saved state, and on with the right step (within 1e-9)
    assert_eq!(r.restore(&state), Fmi2Status::Ok);
    assert_eq!(r.step(1e-4, 1e-4 * (1.0 + 5e-10)), Fmi2Status::Ok);
    assert_eq!(r.step(r.time(), 1e-4 * (1.0 + 2e-9)), Fmi2Status::Error);
}

impl Rotor {
    fn time(&self) -> f64 {
        let mut t = f64::NAN;
        // SAFETY: test importer: the instance is live.
        let s = unsafe { sh::get_real_status::<M>(self.c, FMI2_LAST_SUCCESSFUL_TIME, &mut t) };
        assert_eq!(s, Fmi2Status::Ok);
        t
    }
}

#[test]
fn force_inputs_set_in_tlm_mode_warn_once_after_initialization() {
    let r = Rotor::new();
    assert_eq!(r.set_int("coupling", 1), Fmi2Status::Ok);
    for (n, v) in QUIET {
        assert_eq!(r.set(n, v), Fmi2Status::Ok);
    }
    // before initialization: silent (a master sets every input's start value)
    assert_eq!(r.set("bearing.F.z", 100.0), Fmi2Status::Ok);
    assert_eq!(r.init(), Fmi2Status::Ok);
    assert_eq!(r.step(0.0, 1e-4), Fmi2Status::Ok);
    assert_eq!(r.set("bearing.dF_dv.zz", -3.0), Fmi2Status::Ok);
    assert_eq!(r.step(1e-4, 1e-4), Fmi2Status::Warning);
    let w = r.warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("ignored in coupling mode tlm"), "{}", w[0]);
    assert_eq!(r.set("bearing.F.y", 5.0), Fmi2Status::Ok);
    assert_eq!(r.step(2e-4, 1e-4), Fmi2Status::Ok);
    assert_eq!(r.warnings().len(), 1);
    // and they do not act: the disk stays at rest in its equilibrium
    assert_eq!(r.get("disk.v.z"), 0.0);
    assert_eq!(r.waves()[..4], [0.0, -8.0 * 9.81, 0.0, -8.0 * 9.81]);
}

/// A Jacobi master's exchange at one communication point, with a journal velocity that
/// depends on the rotor's outputs (a stand-in for the bearing); `set_first` chooses the order.
fn exchange(r: &Rotor, k: usize, set_first: bool) -> [f64; 5] {
    let vj = [
        1e-3 * (k as f64 * 0.37).sin(),
        2e-3 * (k as f64 * 0.21).cos(),
    ];
    let waves = if set_first {
        assert_eq!(r.set("tlm.v.y", vj[0]), Fmi2Status::Ok);
        assert_eq!(r.set("tlm.v.z", vj[1]), Fmi2Status::Ok);
        r.waves()
    } else {
        let w = r.waves();
        assert_eq!(r.set("tlm.v.y", vj[0]), Fmi2Status::Ok);
        assert_eq!(r.set("tlm.v.z", vj[1]), Fmi2Status::Ok);
        w
    };
    assert_eq!(r.step(k as f64 * 1e-4, 1e-4), Fmi2Status::Ok);
    waves
}

#[test]
fn the_outputs_do_not_depend_on_the_order_of_setting_and_reading() {
    let a = Rotor::tlm(&QUIET);
    let b = Rotor::tlm(&QUIET);
    for k in 0..40 {
        assert_eq!(exchange(&a, k, true), exchange(&b, k, false), "point {k}");
    }
    assert_eq!(a.get("disk.z"), b.get("disk.z"));
    // the journal outputs do follow the input at once (direct feedthrough)
    assert_eq!(a.set("tlm.v.y", 0.5), Fmi2Status::Ok);
    assert_eq!(a.get("journal.v.y"), 0.5);
}

#[test]
fn a_restored_state_continues_bit_exactly() {
    let ps = [
        ("unbalance", 2e-4),
        ("speed.rate", 2000.0),
        ("speed.final", 1500.0),
    ];
    let a = Rotor::tlm(&ps);
    for k in 0..25 {
        exchange(&a, k, true);
    }
    let saved = a.save();
    let mut run = Vec::new();
    for k in 25..60 {
        run.push((exchange(&a, k, true), a.get("disk.y"), a.get("journal.z")));
    }
    // in another instance (in another mode until the state arrives) and in the same one
    let b = Rotor::new();
    assert_eq!(b.restore(&saved), Fmi2Status::Ok);
    assert_eq!(a.restore(&saved), Fmi2Status::Ok);
    for (i, k) in (25..60).enumerate() {
        for r in [&a, &b] {
            let got = (exchange(r, k, true), r.get("disk.y"), r.get("journal.z"));
            assert_eq!(got, run[i], "point {k}");
        }
    }
    // the model's part of a state of the previous version is refused with a message
    use fmi2::FmuModel;
    let mut m = JeffcottRotor::new();
    let mut part = m.save_state();
    assert_eq!(part[..4], 3u32.to_le_bytes());
    part[..4].copy_from_slice(&1u32.to_le_bytes());
    let e = m.restore_state(&part).unwrap_err();
    assert!(
        e.contains("state version 1 is not supported (expected 3)"),
        "{e}"
    );
}
