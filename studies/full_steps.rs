//! Work counters of the full model on the bench's default scene (S1 healthy / S2 outer spall):
//! steps, rejected steps, RHS evaluations and CPU seconds per simulated second, sampled like
//! `raceway bench` (51.2 kHz, 10 ms chunks). Usage:
//! `cargo run --release -p raceway-studies --bin full_steps -- [S1|S2] [dop853|dopri5|rkf45] [rtol] [duration] [lock]`
//! (`lock` holds the inner-ring tilt, as `examples/scenes/sec3.5-outer-full.toml` does).
//! An optional 7th argument names a file for the sampled pedestal.a.z (one value a line).
//! Prints one CSV line: scene,method,rtol,duration,lock,steps,rejected,rhs,cpu_s,cpu_per_sim_s,us_per_rhs,rms_az,
//! cage (mean sampled cage speed after 5 ms [Hz]), strips.
//! `FS_STRIPS=equal:10` / `gauss:6` overrides the strip rule and count (`contact.strip_rule`,
//! `contact.n_strips`).

use raceway::{out, Fidelity, MethodName, Scene, Simulation};

fn cpu_seconds() -> f64 {
    // utime + stime of this process from /proc (clock ticks of 10 ms).
    let s = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let rest = s.rsplit(')').next().unwrap_or("");
    let f: Vec<&str> = rest.split_whitespace().collect();
    let tick = |i: usize| f.get(i).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    (tick(11) + tick(12)) / 100.0
}

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let scene = a.get(1).map_or("S2", |s| s.as_str()).to_string();
    let method = match a.get(2).map_or("dop853", |s| s.as_str()) {
        "dopri5" => MethodName::Dopri5,
        "rkf45" => MethodName::Rkf45,
        _ => MethodName::Dop853,
    };
    let rtol: f64 = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(1e-6);
    let duration: f64 = a.get(4).and_then(|s| s.parse().ok()).unwrap_or(0.02);
    let lock = a.get(5).is_some_and(|s| s == "lock");
    // Optional: file for the sampled pedestal.a.z (one value per line).
    let dump = a.get(6).cloned();
    let mut sig = Vec::new();
    // FS_NOSAMPLE=1: advance in 10 ms chunks without sampling (as an FMU master without
    // outputs between communication points; no dense output unless events need it).
    let nosample = std::env::var_os("FS_NOSAMPLE").is_some();
    let mut s = Scene::default_scene();
    if let Ok(v) = std::env::var("FS_STRIPS") {
        let (rule, n) = v.split_once(':').expect("FS_STRIPS=rule:n");
        s.bearing.contact.strip_rule = match rule {
            "gauss" => raceway::StripRule::Gauss,
            _ => raceway::StripRule::Equal,
        };
        s.bearing.contact.n_strips = n.parse().expect("n_strips");
    }
    let strips = format!(
        "{:?}:{}",
        s.bearing.contact.strip_rule, s.bearing.contact.n_strips
    );
    let (mut cage, mut n_cage) = (0.0, 0usize);
    s.fidelity = Fidelity::Full;
    if scene == "S1" {
        s.defect = None;
    }
    s.full.lock_tilt = lock;
    s.solver.method = method;
    s.solver.rtol = rtol;
    s.solver.max_steps = 5_000_000;
    let c0 = cpu_seconds();
    let w0 = std::time::Instant::now();
    let mut sim = Simulation::new(&s).expect("scene");
    let mut t = 0.0;
    let (mut sum2, mut n) = (0.0, 0usize);
    while t < duration - 1e-12 {
        let t_next = (t + 0.01).min(duration);
        if nosample {
            sim.advance(t_next).expect("advance");
        } else {
            sim.advance_sampled(t_next, 1.0 / 51_200.0, &mut |ts, o| {
                if ts > 5e-3 {
                    cage += o[out::CAGE_SPEED] / std::f64::consts::TAU;
                    n_cage += 1;
                }
                sum2 += o[out::PEDESTAL_A_Z].powi(2);
                sig.push(o[out::PEDESTAL_A_Z]);
                n += 1;
            })
            .expect("advance");
        }
        t = t_next;
    }
    let cpu = cpu_seconds() - c0;
    let wall = w0.elapsed().as_secs_f64();
    let st = sim.stats();
    if let Some(path) = dump {
        let text: Vec<String> = sig.iter().map(|v| format!("{v:.17e}")).collect();
        std::fs::write(path, text.join("\n")).expect("write signal");
    }
    println!(
        "{scene},{method:?},{rtol:e},{duration},{lock},{},{},{},{cpu:.2},{:.1},{:.2},{:.6e},{:.5},{strips},wall={wall:.2}",
        st.steps,
        st.rejected,
        st.rhs_evals,
        cpu / duration,
        1e6 * cpu / st.rhs_evals as f64,
        (sum2 / n.max(1) as f64).sqrt(),
        cage / n_cage.max(1) as f64
    );
}
