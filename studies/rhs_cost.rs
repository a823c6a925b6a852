//! The bare cost of one right-hand-side evaluation: the model's RHS alone, called in a loop at
//! the quasi-static start state (modes set as the simulation sets them at t = 0), the fastest
//! of 100 timed batches of about 5 ms (the host is shared). Compares revisions' RHS code, e.g.
//! after copying this file into an older checkout's `studies/`:
//!
//! `cargo run --release -p raceway-studies --bin rhs_cost -- [scene.toml] [level ...]`
//!
//! (default scene: the shipped default; default levels: lumped, reduced, full). Prints one line
//! per level: the level, the state count and the fastest batch's µs per call.

use raceway::{models, Fidelity, Scene, Simulation};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (scene_path, levels): (Option<&String>, Vec<&String>) = match args.first() {
        Some(a) if a.ends_with(".toml") => (Some(a), args[1..].iter().collect()),
        _ => (None, args.iter().collect()),
    };
    let base = match scene_path {
        Some(p) => Scene::load(std::path::Path::new(p)).expect("scene"),
        None => Scene::default_scene(),
    };
    let levels: Vec<Fidelity> = if levels.is_empty() {
        vec![Fidelity::Lumped, Fidelity::Reduced, Fidelity::Full]
    } else {
        levels
            .iter()
            .map(|l| Fidelity::from_name(l).expect("a level name"))
            .collect()
    };
    for level in levels {
        let mut scene = base.clone();
        scene.fidelity = level;
        let sim = Simulation::new(&scene).expect("scene");
        let bearing = sim.bearing().clone();
        let mut model = models::build(&scene, &bearing, &scene.operating).expect("model");
        let n = model.dim();
        let mut y = vec![0.0; n];
        model.initial_state(&mut y);
        model.update_mode(0.0, &y);
        let mut dydt = vec![0.0; n];
        // About 5 ms per batch from a first estimate.
        let start = Instant::now();
        for i in 0..200 {
            model.rhs(i as f64 * 1e-9, &y, &mut dydt);
        }
        let calls = ((0.005 / (start.elapsed().as_secs_f64() / 200.0)) as usize).max(10);
        let mut best = f64::INFINITY;
        for _ in 0..100 {
            let start = Instant::now();
            for i in 0..calls {
                model.rhs(i as f64 * 1e-9, &y, &mut dydt);
                std::hint::black_box(&dydt);
            }
            best = best.min(start.elapsed().as_secs_f64() / calls as f64);
        }
        println!("{} {n} states: {:.4} µs per RHS", level.name(), best * 1e6);
    }
}
