//! Where the start of a scene's levels spends its wall time (diagnostic, not part of CI): L1,
//! the full model's build, its steady-rotation solve (the free orbits first, the caged balance
//! when some ball has no free steady rotation), the kinematic levels' traction cage speed, and
//! each level's `Simulation::new` and a short run.
//!
//! `cargo run --release -p raceway-studies --bin start_cost -- RPM FA FR K [located]` on the Table-1 bearing
//! (pedestal stiffness K in N/m; `located`: the ring held axially, `[mounting] axial`).
use raceway::models::internals::{steady_rotation, Orbit};
use raceway::models::{self, Model};
use raceway::models::{FullModel, FullOptions};
use raceway::{
    AxialMount, Bearing, BearingFile, Fidelity, Mounting, OperatingPoint, Scene, Simulation,
};
use std::time::Instant;

fn scene(op: OperatingPoint, k: f64, located: bool, level: Fidelity) -> Scene {
    let mut file = BearingFile::load("niu2014-table1").expect("preset");
    file.pedestal.k_y = k;
    file.pedestal.k_z = k;
    let mut s = Scene::healthy(file, op);
    s.fidelity = level;
    if located {
        s.mounting = Mounting {
            axial: AxialMount::Located,
            axial_offset: None,
        };
    }
    s
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let num = |i: usize| -> f64 {
        args.get(i)
            .and_then(|a| a.parse().ok())
            .unwrap_or_else(|| panic!("usage: start_cost RPM FA FR K [located]"))
    };
    let op = OperatingPoint::from_rpm(num(0), num(1), num(2));
    let k = num(3);
    let located = args.get(4).is_some_and(|a| a == "located");
    let sc = scene(op, k, located, Fidelity::Full);
    let b = Bearing::new(&sc.bearing).expect("bearing");
    let inputs = sc.operating;
    println!(
        "{} rpm, Fa {} N, Fr {} N, pedestal {k:e} N/m{}",
        op.speed_rpm(),
        op.fx,
        -op.fz,
        if located { ", ring located" } else { "" }
    );
    let held = models::held_axial(&sc, &b, &inputs).expect("held");
    let t = Instant::now();
    let qs = models::solve_l1_held(&b, &inputs, held, "L1").expect("L1");
    println!("L1: {:.2} ms ({} iterations)", ms(t), qs.iterations);
    let t = Instant::now();
    let no_traction = FullOptions {
        traction: false,
        lock_tilt: false,
        ..FullOptions::default()
    };
    FullModel::with_options(&sc, &b, &inputs, no_traction).expect("full model");
    println!(
        "full model without traction (no steady-rotation solve): {:.2} ms",
        ms(t)
    );
    let t = Instant::now();
    let built = FullModel::new(&sc, &b, &inputs);
    let total = ms(t);
    let mut m = match built {
        Ok(m) => {
            println!("full model: {total:.1} ms; {:?}", m.settle_report());
            m
        }
        Err(e) => {
            println!("full model: {total:.1} ms; {e}");
            return;
        }
    };
    // The build's two solves again from L1's start, each timed.
    m.restart_from_l1(&b, Some(&qs)).expect("start");
    let mut y0 = vec![0.0; m.dim()];
    m.initial_state(&mut y0);
    for orbit in [Orbit::Free, Orbit::Caged] {
        let mut y = y0.clone();
        m.update_mode(0.0, &y);
        let t = Instant::now();
        let r = steady_rotation(&mut m, &mut y, orbit, None);
        let took = ms(t);
        match r {
            Ok(r) => println!(
                "  {orbit:?}: {took:.1} ms, {} evaluations, {} RHS, {} unsettled",
                r.evaluations, r.rhs_evals, r.unsettled
            ),
            Err(e) => println!("  {orbit:?}: {took:.1} ms, {e}"),
        }
    }
    let t = Instant::now();
    let w = models::traction_cage_speed(&b, &inputs, Some(&qs), None);
    println!(
        "kinematic levels' traction cage speed: {:.1} ms ({:?})",
        ms(t),
        w.map(|w| w / inputs.shaft_speed)
    );
    for level in [
        Fidelity::Kinematic,
        Fidelity::QuasiStatic,
        Fidelity::Lumped,
        Fidelity::Reduced,
        Fidelity::Full,
    ] {
        let t = Instant::now();
        let Ok(mut sim) = Simulation::new(&scene(op, k, located, level)) else {
            println!("{level:?}: Simulation::new failed after {:.1} ms", ms(t));
            continue;
        };
        let build = ms(t);
        let duration = if matches!(level, Fidelity::Reduced | Fidelity::Full) {
            0.004
        } else {
            0.02
        };
        let t = Instant::now();
        let run = sim.advance(duration);
        println!(
            "{level:?}: Simulation::new {build:.1} ms, {} ms simulated in {:.1} ms ({} RHS){}",
            duration * 1e3,
            ms(t),
            sim.stats().rhs_evals,
            run.err().map(|e| format!(": {e}")).unwrap_or_default()
        );
    }
}
