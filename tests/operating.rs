//! The operating point: one SI type from the scene file to the models (issue 18 item 5).

use raceway::{OperatingPoint, Scene};

#[test]
fn rpm_and_the_paper_loads_become_si_components() {
    let p = OperatingPoint::from_rpm(9900.0, 4000.0, 1000.0);
    // 9900 rpm = 165 rev/s = 330π rad/s.
    assert!((p.shaft_speed - 330.0 * std::f64::consts::PI).abs() < 1e-12);
    assert_eq!((p.fx, p.fy, p.fz), (4000.0, 0.0, -1000.0));
    assert!((p.speed_rpm() - 9900.0).abs() < 1e-9);
}

#[test]
fn a_scene_file_states_rpm_fa_fr_fy_and_the_scene_holds_si() {
    let text = "[operating]\nspeed_rpm = 6000.0\nfa = 3000.0\nfr = 500.0\nfy = 20.0\n";
    let s = Scene::from_toml_str(text, "test", None).unwrap();
    let want = OperatingPoint {
        fy: 20.0,
        ..OperatingPoint::from_rpm(6000.0, 3000.0, 500.0)
    };
    assert_eq!(s.operating, want);
    assert!((s.operating.shaft_speed - 200.0 * std::f64::consts::PI).abs() < 1e-12);
    // A negative speed is refused naming the file's key.
    let e = Scene::from_toml_str("[operating]\nspeed_rpm = -1.0\n", "test", None).unwrap_err();
    assert!(e.to_string().contains("operating.speed_rpm"), "{e}");
}

#[test]
fn check_names_the_fmu_input_that_is_wrong() {
    let ok = OperatingPoint::from_rpm(1000.0, 100.0, 10.0);
    assert!(ok.check().is_ok());
    let nan = OperatingPoint { fy: f64::NAN, ..ok };
    assert!(nan.check().unwrap_err().contains("load.Fy"));
    let back = OperatingPoint {
        shaft_speed: -1.0,
        ..ok
    };
    assert!(back.check().unwrap_err().contains("shaft.speed"));
    let inf = OperatingPoint {
        shaft_speed: f64::INFINITY,
        ..ok
    };
    assert!(inf.check().unwrap_err().contains("shaft.speed"));
}
