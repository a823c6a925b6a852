//! Long-run check of the cage and of the cage-less balls at the full level (docs/research/cage.md;
//! a check, not a test): one scene run with the cage and without it (ball-to-ball contact), the
//! two simulations advanced in turns over the same stretches, so that their CPU times are
//! measured side by side under the same load of the host.
//!
//! `cargo run --release -p raceway-studies --bin cage_longrun -- SCENE [DURATION] [SAMPLE]
//! [cage.KEY=VALUE …]`
//!
//! SCENE is `partial` (the Table-1 bearing at Fa 1000 N, Fr 4000 N, 9900 rpm, healthy: a
//! partial load zone) or a scene file (run at the full level); DURATION defaults to 2 s, SAMPLE
//! (the interval at which the states are read, from the dense output) to 20 µs; `cage.KEY=VALUE`
//! (pocket_friction, pocket_damping, pocket_clearance) changes the bearing's `[cage]` for a
//! sensitivity run. Prints a
//! Markdown report: per run the
//! smallest centre distance of each pair of neighbouring balls less D (from the states), the
//! cage speed against the kinematic ones (pure rolling at α0, L1's outer-race control, the
//! traction's caged balance), per quarter of the run the cage speed, the cage's whirl, the pocket
//! forces, the smallest ball gap and the mechanical energy (FullModel::energy on the states), and
//! the cost.

use raceway::fault_frequencies::fault_frequencies;
use raceway::load_distribution;
use raceway::models::internals::ball_ball_stiffness;
use raceway::models::internals::layout::{Layout, BR, BTH, BX, CW, CY, PY};
use raceway::models::{traction_cage_speed, FullModel};
use raceway::{out, Bearing, BearingFile, Fidelity, OperatingPoint, Scene, Simulation};
use std::f64::consts::{PI, TAU};

fn cpu() -> f64 {
    cpu_time::ThreadTime::try_now().map_or(f64::NAN, |t| t.as_duration().as_secs_f64())
}

/// What one run records per window (a stretch of the run).
#[derive(Clone, Default)]
struct Window {
    n: usize,
    cage: f64,
    cage_min: f64,
    cage_max: f64,
    whirl_max: f64,
    whirl_sum: f64,
    pocket_max: f64,
    gap_min: f64,
    energy_min: f64,
    energy_max: f64,
    energy_sum: f64,
    orbit_spread: f64,
}

impl Window {
    fn new() -> Self {
        Self {
            cage_min: f64::INFINITY,
            cage_max: f64::NEG_INFINITY,
            gap_min: f64::INFINITY,
            energy_min: f64::INFINITY,
            energy_max: f64::NEG_INFINITY,
            ..Self::default()
        }
    }
}

struct Run {
    label: &'static str,
    sim: Simulation,
    energy: FullModel,
    lay: Layout,
    cpu: f64,
    pair_min: Vec<f64>,
    touching: usize,
    samples: usize,
    windows: Vec<Window>,
}

impl Run {
    fn new(label: &'static str, scene: &Scene) -> Self {
        let sim = Simulation::new(scene).unwrap();
        let b = Bearing::new(&scene.bearing).unwrap();
        let energy = FullModel::new(scene, &b, &scene.operating).unwrap();
        let lay = Layout::full(b.z).with_cage(scene.full.cage);
        assert_eq!(sim.state_dim(), lay.dim());
        Self {
            label,
            sim,
            energy,
            lay,
            cpu: 0.0,
            pair_min: vec![f64::INFINITY; b.z],
            touching: 0,
            samples: 0,
            windows: Vec::new(),
        }
    }

    /// Advances to `t_end` reading the states every `dt` (from the dense output: no extra
    /// steps), into window `w`; the CPU time of the advance less that of the reading.
    fn advance(&mut self, t_end: f64, dt: f64, w: usize, b: &Bearing) {
        while self.windows.len() <= w {
            self.windows.push(Window::new());
        }
        let z = b.z;
        let Run {
            sim,
            energy,
            lay,
            pair_min,
            touching,
            samples,
            windows,
            cpu: spent,
            ..
        } = self;
        let lay = *lay;
        let win = &mut windows[w];
        let mut reading = 0.0;
        let start = cpu();
        let mut read = |_t: f64, y: &[f64], o: &[f64]| {
            let c0 = cpu();
            let pos = |j: usize| {
                let bj = lay.ball(j);
                let theta = y[lay.psi()] + TAU * j as f64 / z as f64 + y[bj + BTH];
                let r = 0.5 * b.dm + y[bj + BR];
                [y[bj + BX], -r * theta.sin(), r * theta.cos()]
            };
            let mut gap_min = f64::INFINITY;
            for (j, m) in pair_min.iter_mut().enumerate() {
                let (a, c) = (pos(j), pos((j + 1) % z));
                let g = ((c[0] - a[0]).powi(2) + (c[1] - a[1]).powi(2) + (c[2] - a[2]).powi(2))
                    .sqrt()
                    - b.d;
                *m = m.min(g);
                gap_min = gap_min.min(g);
            }
            if gap_min < 0.0 {
                *touching += 1;
            }
            *samples += 1;
            let e = energy.energy(y);
            let cage = o[out::CAGE_SPEED];
            win.n += 1;
            win.cage += cage;
            win.cage_min = win.cage_min.min(cage);
            win.cage_max = win.cage_max.max(cage);
            if lay.cage {
                let c = lay.cage_block();
                let p = lay.pedestal();
                // The whirl about the outer ring's centre (which moves with the pedestal).
                let r = (y[c + CY] - y[p + PY]).hypot(y[c + CY + 1] - y[p + PY + 1]);
                win.whirl_max = win.whirl_max.max(r);
                win.whirl_sum += r;
                for j in 0..z {
                    win.pocket_max = win.pocket_max.max(o[out::pocket_force(z, j)].abs());
                }
                debug_assert_eq!(y[c + CW], cage);
            }
            let (lo, hi) = (0..z)
                .map(|j| o[out::orbit_speed(z, j)])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), w| {
                    (lo.min(w), hi.max(w))
                });
            win.orbit_spread = win.orbit_spread.max(hi - lo);
            win.gap_min = win.gap_min.min(gap_min);
            win.energy_min = win.energy_min.min(e);
            win.energy_max = win.energy_max.max(e);
            win.energy_sum += e;
            reading += cpu() - c0;
        };
        sim.advance_sampled_with_state(t_end, dt, &mut read)
            .unwrap();
        *spent += cpu() - start - reading;
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let which = args.next().unwrap_or_else(|| "partial".into());
    let duration: f64 = args.next().map_or(2.0, |v| v.parse().unwrap());
    let dt: f64 = args.next().map_or(20e-6, |v| v.parse().unwrap());
    let overrides: Vec<String> = args.collect();
    let mut scene = if which == "partial" {
        let mut s = Scene::healthy(
            BearingFile::load("niu2014-table1").unwrap(),
            OperatingPoint::from_rpm(9900.0, 1000.0, 4000.0),
        );
        s.name = "partial load zone (Table 1, Fa 1000 N, Fr 4000 N, 9900 rpm)".into();
        s
    } else {
        Scene::load(std::path::Path::new(&which)).unwrap()
    };
    scene.fidelity = Fidelity::Full;
    // `cage.pocket_friction=0` and the like: the bearing's [cage] changed for a sensitivity run.
    for kv in &overrides {
        let (key, value) = kv.split_once('=').expect("KEY=VALUE");
        let v: f64 = value.parse().unwrap();
        let c = &mut scene.bearing.cage;
        match key {
            "cage.pocket_friction" => c.pocket_friction = Some(v),
            "cage.pocket_damping" => c.pocket_damping = Some(v),
            "cage.pocket_clearance" => c.pocket_clearance = Some(v),
            other => panic!("{other}: not a key this study overrides"),
        }
        scene.name = format!("{}, {kv}", scene.name);
    }
    let b = Bearing::new(&scene.bearing).unwrap();
    let inputs = scene.operating;
    let (mut caged, mut free) = (scene.clone(), scene.clone());
    caged.full.cage = true;
    free.full.cage = false;
    let mut runs = [Run::new("cage", &caged), Run::new("no cage", &free)];

    // The kinematic cage speeds: pure rolling at α0 (fault_frequencies), L1's outer-race control
    // (load_distribution::solve, QuasiStatic::cage_speed), the traction's caged balance
    // (models::traction_cage_speed).
    let fs = inputs.shaft_speed / TAU;
    let rolling = fault_frequencies(&b, fs, b.alpha0).ftf * TAU;
    let l1 = load_distribution::solve(&b, &inputs).unwrap();
    let orc = l1.cage_speed;
    let balance = traction_cage_speed(&b, &inputs, Some(&l1), None).unwrap();
    let loaded = l1.balls.iter().filter(|e| e.q_inner > 0.0).count();

    // Windows of a quarter of the run (or 0.25 s); the two runs advance in turns of 50 ms.
    let n_windows = 8usize;
    let chunk = 0.05_f64.min(duration / n_windows as f64);
    let mut t = 0.0;
    while t < duration - 1e-12 {
        let t_next = (t + chunk).min(duration);
        let w = ((t / duration) * n_windows as f64).floor() as usize;
        for r in runs.iter_mut() {
            r.advance(t_next, dt, w.min(n_windows - 1), &b);
        }
        t = t_next;
        eprintln!(
            "t = {t:.3} s: cpu {:.1} s (cage), {:.1} s (no cage)",
            runs[0].cpu, runs[1].cpu
        );
    }

    let hz = |w: f64| w / TAU;
    println!(
        "## {} — full level, {duration} s, states read every {:.0} µs\n",
        scene.name,
        dt * 1e6
    );
    println!(
        "Kinematic cage speeds: pure rolling at α0 {:.4} Hz, L1's outer-race control {:.4} Hz \
         ({loaded} of {} balls loaded), the traction's caged balance {:.4} Hz. Even spacing of \
         the balls leaves {:.4} mm between neighbours.\n",
        hz(rolling),
        hz(orc),
        b.z,
        hz(balance),
        (b.dm * (PI / b.z as f64).sin() - b.d) * 1e3
    );
    println!("| run | CPU s | CPU s per simulated s | steps | rejected | RHS evaluations | smallest ball gap [mm] | samples with balls touching | mean cage speed, second half [Hz] | slip vs pure rolling | slip vs outer-race control | slip vs caged balance |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &runs {
        let st = r.sim.stats();
        let half = &r.windows[n_windows / 2..];
        let (s, n) = half
            .iter()
            .fold((0.0, 0), |(s, n), w| (s + w.cage, n + w.n));
        let mean = s / n as f64;
        let gap = r.pair_min.iter().cloned().fold(f64::INFINITY, f64::min);
        println!(
            "| {} | {:.1} | {:.2} | {} | {} | {} | {:.4} | {} of {} | {:.4} | {:+.3} % | {:+.3} % | {:+.3} % |",
            r.label,
            r.cpu,
            r.cpu / duration,
            st.steps,
            st.rejected,
            st.rhs_evals,
            gap * 1e3,
            r.touching,
            r.samples,
            hz(mean),
            100.0 * (1.0 - mean / rolling),
            100.0 * (1.0 - mean / orc),
            100.0 * (1.0 - mean / balance),
        );
    }
    println!(
        "\nCost of the cage: {:.3} × the CPU time without it (side by side, same stretches).\n",
        runs[0].cpu / runs[1].cpu
    );
    for r in &runs {
        println!("### {}\n", r.label);
        println!(
            "Smallest gap per pair of neighbours (j, j+1) [mm]: {}\n",
            r.pair_min
                .iter()
                .map(|g| format!("{:.4}", g * 1e3))
                .collect::<Vec<_>>()
                .join(", ")
        );
        println!("| window [s] | cage speed mean [Hz] | min … max [Hz] | largest orbit-speed spread [rad/s] | whirl mean / max [µm] | largest pocket force [N] | smallest ball gap [mm] | energy mean [J] | energy min … max [J] |");
        println!("|---|---|---|---|---|---|---|---|---|");
        for (k, w) in r.windows.iter().enumerate() {
            let (t0, t1) = (
                duration * k as f64 / n_windows as f64,
                duration * (k + 1) as f64 / n_windows as f64,
            );
            let whirl = if r.lay.cage {
                format!(
                    "{:.1} / {:.1}",
                    w.whirl_sum / w.n as f64 * 1e6,
                    w.whirl_max * 1e6
                )
            } else {
                "—".into()
            };
            let pocket = if r.lay.cage {
                format!("{:.1}", w.pocket_max)
            } else {
                "—".into()
            };
            println!(
                "| {t0:.3}–{t1:.3} | {:.4} | {:.3} … {:.3} | {:.2} | {whirl} | {pocket} | {:.4} | {:.6} | {:.6} … {:.6} |",
                hz(w.cage / w.n as f64),
                hz(w.cage_min),
                hz(w.cage_max),
                w.orbit_spread,
                w.gap_min * 1e3,
                w.energy_sum / w.n as f64,
                w.energy_min,
                w.energy_max,
            );
        }
        println!();
    }
    // What the windows say, computed: overlap, and drift from the second window (after the
    // start's transient) to the last.
    let k_bb = ball_ball_stiffness(b.d, b.e_prime);
    println!("### Checks\n");
    for r in &runs {
        let gap = r.pair_min.iter().cloned().fold(f64::INFINITY, f64::min);
        let (first, last) = (&r.windows[1], &r.windows[n_windows - 1]);
        let mean = |w: &Window, v: f64| v / w.n as f64;
        let overlap = if gap > 0.0 {
            format!(
                "the balls never touch (smallest gap {:.4} mm of {:.4} mm at even spacing)",
                gap * 1e3,
                (b.dm * (PI / b.z as f64).sin() - b.d) * 1e3
            )
        } else {
            format!(
                "neighbours touch in {} of {} samples; the deepest approach is {:.2} µm, the \
                 elastic overlap of the Hertz contact of two balls at {:.1} N (K = {:.3e} N/m^1.5), \
                 not an interpenetration",
                r.touching,
                r.samples,
                -gap * 1e6,
                k_bb * (-gap).powf(1.5),
                k_bb
            )
        };
        let whirl = if r.lay.cage {
            format!(
                "; whirl mean {:.1} → {:.1} µm, largest pocket force {:.1} → {:.1} N",
                mean(first, first.whirl_sum) * 1e6,
                mean(last, last.whirl_sum) * 1e6,
                first.pocket_max,
                last.pocket_max
            )
        } else {
            String::new()
        };
        println!(
            "- {}: {overlap}. From the second window to the last: cage speed {:.4} → {:.4} Hz, \
             energy mean {:.6} → {:.6} J ({:+.2e} of it), orbit-speed spread {:.2} → {:.2} \
             rad/s{whirl}.",
            r.label,
            hz(mean(first, first.cage)),
            hz(mean(last, last.cage)),
            mean(first, first.energy_sum),
            mean(last, last.energy_sum),
            mean(last, last.energy_sum) / mean(first, first.energy_sum) - 1.0,
            first.orbit_spread,
            last.orbit_spread,
        );
    }
    println!();
}
