//! Diagnostics of the spall impact at L4 (not part of CI): per ball pass over the spall, the
//! running load before entry, the largest force on the spalled race while the ball is inside
//! the zone (the paper's "impact force", the trailing-edge hit) and after it left (the rattle),
//! sampled from the dense output at a high rate.
//!
//! `cargo run --release -p raceway-studies --bin impact_probe -- SCENE [key=value ...]`
//! keys: duration, skip, fs (sample rate), theta0, width, depth, rpm, fa, fr, mode (finite|point),
//! blend (m), edge_radius (m), tilt (free|held), traction (on|off), cbr, cp (pedestal damping), summary (1: one line of medians only).

use raceway::models::Model;
use raceway::models::{FullModel, FullOptions};
use raceway::solver::{EventAction, EventSystem, Integrator, Method, Options, StepView, System};
use raceway::{out, Bearing, Race, Scene};

struct Driver<'a>(&'a mut FullModel);

impl System for Driver<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        self.0.rhs(t, y, dydt)
    }
}

impl EventSystem for Driver<'_> {
    fn n_events(&self) -> usize {
        self.0.n_events()
    }
    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        self.0.events(t, y, g)
    }
    fn handle_event(&mut self, index: usize, t: f64, y: &mut [f64]) -> EventAction {
        self.0.event_fired(index);
        self.0.update_mode(t, y);
        EventAction::Continue
    }
}

#[derive(Default, Clone)]
struct Pass {
    ball: usize,
    t_in: f64,
    t_out: f64,
    q_before: f64,
    q_other_before: f64,
    q_zone: f64,
    t_zone: f64,
    q_zone_other: f64,
    q_after: f64,
    q_after_other: f64,
    a_max: f64,
    e_in: f64,
    e_out: f64,
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let Some(path) = args.get(1) else {
        eprintln!("usage: impact_probe SCENE [key=value ...]");
        std::process::exit(2);
    };
    let mut scene = Scene::load(std::path::Path::new(path)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let (mut duration, mut skip, mut fs) = (0.01, 0.002, 1.0e6);
    let mut opts = FullOptions {
        lock_tilt: scene.full.lock_tilt,
        traction: scene.full.traction,
        ..FullOptions::default()
    };
    let mut summary = false;
    let mut trace: Option<(usize, f64, f64)> = None;
    for kv in &args[2..] {
        let (k, v) = kv.split_once('=').expect("key=value");
        let x = || v.parse::<f64>().expect("number");
        match k {
            "duration" => duration = x(),
            "skip" => skip = x(),
            "fs" => fs = x(),
            "theta0" => scene.defect.as_mut().expect("spall").theta0 = x(),
            "width" => scene.defect.as_mut().expect("spall").width = x(),
            "depth" => scene.defect.as_mut().expect("spall").depth = x(),
            "rpm" => scene.operating.shaft_speed = raceway::rpm_to_rad_s(x()),
            "fa" => scene.operating.fx = x(),
            "fr" => scene.operating.fz = -(x()),
            "cbr" => scene.bearing.contact.c_br = x(),
            "mode" => {
                scene.bearing.defect.mode = match v {
                    "point" => raceway::DefectMode::Point,
                    _ => raceway::DefectMode::Finite,
                }
            }
            "blend" => scene.bearing.defect.blend_length = raceway::BlendLength::Metres(x()),
            "edge_radius" => scene.bearing.defect.edge_radius = x(),
            "cp" => {
                scene.bearing.pedestal.c_y = x();
                scene.bearing.pedestal.c_z = x();
            }
            "tilt" => opts.lock_tilt = v == "held",
            "traction" => opts.traction = v == "on",
            "trace" => {
                // trace=ball:t0:t1 (ms)
                let p: Vec<&str> = v.split(':').collect();
                trace = Some((
                    p[0].parse().expect("ball"),
                    p[1].parse::<f64>().expect("t0") * 1e-3,
                    p[2].parse::<f64>().expect("t1") * 1e-3,
                ));
            }
            "summary" => summary = v == "1",
            _ => panic!("unknown key {k}"),
        }
    }
    let bearing = Bearing::new(&scene.bearing).expect("bearing");
    let inputs = scene.operating;
    let mut m = FullModel::with_options(&scene, &bearing, &inputs, opts).expect("model");
    let z = bearing.z;
    let inner_spall = m.defect().is_some_and(|d| d.ring() == Race::Inner);
    let (qs, qo) = if inner_spall { (0, z) } else { (z, 0) };
    let n = m.dim();
    let mut y0 = vec![0.0; n];
    m.initial_state(&mut y0);
    m.update_mode(0.0, &y0);
    let mut nominal = vec![0.0; n];
    m.nominal(&mut nominal);
    let rtol = scene.solver.rtol;
    let atol = nominal.iter().map(|v| v * rtol).collect();
    let mut integ =
        Integrator::new(Options::new(Method::Dop853, rtol, atol), 0.0, &y0).expect("integrator");
    let mut o = vec![0.0; raceway::output_table(z).len()];
    let mut was_in = vec![false; z];
    let mut open: Vec<Option<Pass>> = vec![None; z];
    let mut done: Vec<Pass> = Vec::new();
    let mut after: Vec<Option<Pass>> = vec![None; z];
    let mut last_q = vec![(0.0, 0.0); z];
    let chunk = 5e-4;
    let mut t = 0.0;
    let wall = std::time::Instant::now();
    while t < duration - 1e-12 {
        let t1 = (t + chunk).min(duration);
        let mut states: Vec<(f64, Vec<f64>)> = Vec::new();
        let mut buf = vec![0.0; n];
        let mut obs = |v: &StepView| {
            let mut k = (v.t_start() * fs).floor() as i64 + 1;
            while k as f64 / fs <= v.t_end() {
                v.interpolate(k as f64 / fs, &mut buf);
                states.push((k as f64 / fs, buf.clone()));
                k += 1;
            }
        };
        if let Err(e) = integ.advance_with_events(&mut Driver(&mut m), t1, Some(&mut obs)) {
            eprintln!("run failed at {}: {e}", integ.t());
            break;
        }
        for (ts, y) in &states {
            m.update_mode(*ts, y);
            m.outputs(*ts, y, &mut o);
            let acc = o[out::PEDESTAL_A_Z].abs();
            if let Some((j, t0, t1)) = trace {
                if *ts >= t0 && *ts <= t1 {
                    let (ci, co) = m.ball_contacts(y, j);
                    let d = m.defect().expect("spall");
                    let tbd = m.ball_theta_bd(y, j);
                    let b = m.layout().ball(j);
                    println!(
                        "T {:.7} y_b {:8.4} mm r {:8.3} um vr {:7.3} in {} | o: d {:8.3} um K {:.3e} Q {:7.1} | i: d {:8.3} Q {:7.1} | E {:.4} mJ",
                        ts * 1e3,
                        d.along_track(tbd) * 1e3,
                        y[b + 1] * 1e6,
                        y[b + 4],
                        u8::from(co.in_defect || ci.in_defect),
                        co.delta * 1e6,
                        co.k,
                        co.q,
                        ci.delta * 1e6,
                        ci.q,
                        m.energy(y) * 1e3
                    );
                }
            }
            for j in 0..z {
                let q = o[out::CONTACT_START + qs + j];
                let q_other = o[out::CONTACT_START + qo + j];
                let inz = m.in_defect_zone(j);
                if inz && !was_in[j] {
                    if let Some(p) = after[j].take() {
                        done.push(p);
                    }
                    open[j] = Some(Pass {
                        ball: j,
                        t_in: *ts,
                        e_in: m.energy(y),
                        q_before: last_q[j].0,
                        q_other_before: last_q[j].1,
                        ..Pass::default()
                    });
                }
                if !inz && was_in[j] {
                    if let Some(mut p) = open[j].take() {
                        p.t_out = *ts;
                        p.e_out = m.energy(y);
                        after[j] = Some(p);
                    }
                }
                if let Some(p) = open[j].as_mut() {
                    if q > p.q_zone {
                        p.q_zone = q;
                        p.t_zone = *ts;
                    }
                    p.q_zone_other = p.q_zone_other.max(q_other);
                    p.a_max = p.a_max.max(acc);
                }
                if let Some(p) = after[j].as_mut() {
                    if *ts - p.t_out < 1e-3 {
                        p.q_after = p.q_after.max(q);
                        p.q_after_other = p.q_after_other.max(q_other);
                        p.a_max = p.a_max.max(acc);
                    } else {
                        done.push(after[j].take().unwrap());
                    }
                }
                was_in[j] = inz;
                if !inz {
                    // running load: a little before entry (20 µs lag via the smoothing below)
                    last_q[j] = (q, q_other);
                }
            }
        }
        t = integ.t();
        if t < t1 - 1e-12 {
            break;
        }
    }
    done.extend(after.into_iter().flatten());
    done.retain(|p| p.t_in >= skip);
    done.sort_by(|a, b| a.t_in.total_cmp(&b.t_in));
    let sr = if inner_spall { "inner" } else { "outer" };
    if !summary {
        println!(
            "# {} passes, spalled race {sr}; wall {:.1} s for {:.4} s",
            done.len(),
            wall.elapsed().as_secs_f64(),
            t
        );
        println!("ball   t_in[ms] dwell[us] Q_before Qoth_bef | Q_zone t_hit-t_in[us] Qoth_zone | Q_after Qoth_after | |a|max | E_out-E_in [mJ]");
        for p in &done {
            println!(
                "{:3} {:9.4} {:8.1} {:8.0} {:8.0} | {:7.0} {:8.1} {:8.0} | {:7.0} {:8.0} | {:8.0} | {:.4}",
                p.ball,
                p.t_in * 1e3,
                (p.t_out - p.t_in) * 1e6,
                p.q_before,
                p.q_other_before,
                p.q_zone,
                (p.t_zone - p.t_in) * 1e6,
                p.q_zone_other,
                p.q_after,
                p.q_after_other,
                p.a_max,
                (p.e_out - p.e_in) * 1e3
            );
        }
    }
    let col = |f: &dyn Fn(&Pass) -> f64| median(&mut done.iter().map(f).collect::<Vec<_>>());
    println!(
        "median over {} passes: Q_before {:.0}  Q_zone(impact) {:.0}  Qother_zone {:.0}  Q_after {:.0}  Qother_after {:.0}  |a|max {:.0}",
        done.len(),
        col(&|p| p.q_before),
        col(&|p| p.q_zone),
        col(&|p| p.q_zone_other),
        col(&|p| p.q_after),
        col(&|p| p.q_after_other),
        col(&|p| p.a_max)
    );
}
