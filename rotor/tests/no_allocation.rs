//! The rotor's right-hand sides and stepping (both coupling modes) do not allocate (engineering rule), checked with
//! raceway's counting allocator.

#[path = "../../tests/common/alloc_counter.rs"]
mod alloc_counter;

use raceway_rotor::jeffcott::{Coupling, InterfaceForce, Rotor, RotorParams, TlmRotor};

#[test]
fn advancing_the_rotor_does_not_allocate() {
    let p = RotorParams {
        speed_rate: 500.0,
        speed_final: 1200.0,
        ..RotorParams::default()
    };
    let mut r = Rotor::new(&p, 0.0, 1e-8).unwrap();
    let mut iface = InterfaceForce {
        f: [-4000.0, 0.0, 1098.0],
        ..Default::default()
    };
    iface.k[1][1] = -1e8;
    iface.k[2][2] = -1e8;
    iface.c[2][2] = -100.0;
    r.set_interface(iface);
    r.advance(1e-3).unwrap(); // warm-up
    let (n, res) = alloc_counter::allocations_during(|| {
        let mut out = 0.0;
        for k in 2..20 {
            r.set_interface(iface);
            r.advance(k as f64 * 1e-3)?;
            out += r.outputs().journal_x[2];
        }
        Ok::<f64, raceway_rotor::jeffcott::RotorError>(out)
    });
    assert!(res.unwrap().is_finite());
    assert_eq!(n, 0, "{n} allocations while stepping");
}

#[test]
fn stepping_the_disk_on_the_line_does_not_allocate() {
    let p = RotorParams {
        coupling: Coupling::Tlm,
        speed_rate: 500.0,
        speed_final: 1200.0,
        ..RotorParams::default()
    };
    let t = p.tlm_delay;
    let mut r = TlmRotor::new(&p, 0.0, 1e-8).unwrap();
    r.step([1e-4, -2e-4], t).unwrap(); // warm-up
    let (n, res) = alloc_counter::allocations_during(|| {
        let mut out = 0.0;
        for k in 2..200 {
            let v = [1e-4 * (k as f64).sin(), -2e-4];
            r.step(v, k as f64 * t)?;
            let o = r.outputs(v);
            out += o.tlm_c1[1] + o.journal_x[2];
        }
        Ok::<f64, raceway_rotor::jeffcott::RotorError>(out)
    });
    assert!(res.unwrap().is_finite());
    assert_eq!(n, 0, "{n} allocations while stepping");
}
