//! Convergence of the strip quadrature of the traction (docs/model.md#strips, #c7) on contact states of a
//! running L4 simulation (not part of CI).
//!
//! Runs the default scene at L4 (S2: outer spall; `S1` drops it) with DOP853 at rtol 1e-6,
//! skips `skip` seconds, then samples the state from the dense output at `fs` for `span`
//! seconds. At every sample, for every loaded contact (16 balls × 2 races), it takes the slip
//! field (`FullModel::ball_slip_fields`) and integrates the strip sums (traction force in the
//! contact plane and the three moment sums, [`strip_sums`]) with equal strips and with the
//! Gauss rule for the line-load weight 1 − s², N = 2…16 (and, for comparison, composite
//! 2-/3-point Gauss–Legendre `cgl2`/`cgl3` and Richardson-extrapolated equal strips `rich3`),
//! against a reference: composite 3-point
//! Gauss–Legendre on `panels` equal panels of the full integrand (1 − s²)·κ(|u|)·u/|u|.
//!
//! Errors are normalised by the largest traction the contact can carry:
//! - `eF = |ΔF| / (κm Q)`: traction force (both in-plane components);
//! - `eMs = |Δ Σξ f2| / (κm Q a)`: spin moment (about the normal);
//! - `eMr = |Δ(Σζ f1, Σζ f2)| / (κm Q R)`: rolling/tilting moments.
//!
//! `cargo run --release -p raceway-studies --bin strip_study -- [S1|S2] [skip=0.02] [span=0.005] [fs=2e5]
//! [panels=1000] [csv=FILE]` prints one table row per (rule, N): median, 99th percentile and
//! maximum of each error over all sampled loaded contacts, and the same maxima over the
//! contacts inside the spall.

use raceway::contact::TractionCurve;
use raceway::models::internals::{strip_sums, SlipField, Strips};
use raceway::models::FullModel;
use raceway::models::Model;
use raceway::solver::{EventAction, EventSystem, Integrator, Method, Options, StepView, System};
use raceway::{Fidelity, Scene};

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

/// Reference strip sums: composite 3-point Gauss–Legendre on `panels` panels of (−1, 1) with
/// the weight (3/4)(1 − s²) in the integrand.
fn reference(curve: &TractionCurve, sf: &SlipField, panels: usize) -> [f64; 5] {
    let g = (0.6f64).sqrt();
    let nodes = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
    let h = 2.0 / panels as f64;
    let mut r = [0.0; 5];
    for p in 0..panels {
        let mid = -1.0 + (p as f64 + 0.5) * h;
        for &(x, wx) in &nodes {
            let s = mid + 0.5 * h * x;
            let w = 0.5 * h * wx * 0.75 * (1.0 - s * s);
            let (zeta, u1, u2) = sf.at(s);
            let k = curve.kappa_over_u((u1 * u1 + u2 * u2).sqrt());
            let gq = -sf.q * w * k;
            let xi = sf.a * s;
            r[0] += gq * u1;
            r[1] += gq * u2;
            r[2] += xi * gq * u2;
            r[3] += zeta * gq * u1;
            r[4] += zeta * gq * u2;
        }
    }
    r
}

/// Composite Gauss–Legendre: `panels` equal panels of `p` points (p = 2, 3), weight
/// (3/4)(1 − s²) multiplied in (exact for the total load since p ≥ 2).
fn composite(panels: usize, p: usize) -> Strips {
    let g: &[(f64, f64)] = match p {
        2 => &[
            (-0.577_350_269_189_625_8, 1.0),
            (0.577_350_269_189_625_8, 1.0),
        ],
        _ => &[
            (-0.774_596_669_241_483_4, 5.0 / 9.0),
            (0.0, 8.0 / 9.0),
            (0.774_596_669_241_483_4, 5.0 / 9.0),
        ],
    };
    let mut st = Strips::new(1);
    st.n = panels * p;
    let h = 2.0 / panels as f64;
    for k in 0..panels {
        let mid = -1.0 + (k as f64 + 0.5) * h;
        for (i, &(x, wx)) in g.iter().enumerate() {
            let s = mid + 0.5 * h * x;
            st.s[k * p + i] = s;
            st.w[k * p + i] = 0.5 * h * wx * 0.75 * (1.0 - s * s);
        }
    }
    // Exact symmetry (the strip sums mirror ζ).
    for k in 0..st.n / 2 {
        let m = st.n - 1 - k;
        let (s, w) = (0.5 * (st.s[k] - st.s[m]), 0.5 * (st.w[k] + st.w[m]));
        st.s[k] = s;
        st.s[m] = -s;
        st.w[k] = w;
        st.w[m] = w;
    }
    st
}

/// Richardson extrapolation of equal strips from n/3 to n (nested midpoints; error ∝ h² for a
/// smooth integrand): (9 I_n − I_{n/3})/8 on the n nodes of the finer rule.
fn richardson3(n: usize) -> Strips {
    let (fine, coarse) = (Strips::new(n), Strips::new(n / 3));
    let mut st = fine;
    for k in 0..n {
        st.w[k] *= 9.0 / 8.0;
    }
    for j in 0..n / 3 {
        // Coarse strip j's centre is the centre of fine strip 3j + 1.
        st.w[3 * j + 1] -= coarse.w[j] / 8.0;
    }
    st
}

struct Sample {
    sf: SlipField,
    spall: bool,
    reference: [f64; 5],
}

fn pct(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let mut scene = Scene::default_scene();
    scene.fidelity = Fidelity::Full;
    let (mut skip, mut span, mut fs, mut panels) = (0.02, 0.005, 2e5, 1000usize);
    let mut csv: Option<String> = None;
    for a in &args[1..] {
        if a == "S1" {
            scene.defect = None;
            continue;
        }
        if a == "S2" {
            continue;
        }
        let (k, v) = a.split_once('=').expect("key=value");
        let x = || v.parse::<f64>().expect("number");
        match k {
            "skip" => skip = x(),
            "span" => span = x(),
            "fs" => fs = x(),
            "panels" => panels = x() as usize,
            "csv" => csv = Some(v.to_string()),
            _ => panic!("unknown key {k}"),
        }
    }
    let bearing = raceway::Bearing::new(&scene.bearing).expect("bearing");
    let inputs = scene.operating;
    let mut m = FullModel::new(&scene, &bearing, &inputs).expect("model");
    let curve = m.traction().expect("traction on").0;
    let ball_radius = 0.5 * bearing.d;
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
    integ
        .advance_with_events(&mut Driver(&mut m), skip, None)
        .expect("skip");
    let mut states: Vec<(f64, Vec<f64>)> = Vec::new();
    {
        let mut buf = vec![0.0; n];
        let mut obs = |v: &StepView| {
            let mut k = (v.t_start() * fs).floor() as i64 + 1;
            while k as f64 / fs <= v.t_end() {
                if k as f64 / fs > skip {
                    v.interpolate(k as f64 / fs, &mut buf);
                    states.push((k as f64 / fs, buf.clone()));
                }
                k += 1;
            }
        };
        integ
            .advance_with_events(&mut Driver(&mut m), skip + span, Some(&mut obs))
            .expect("advance");
    }
    let mut samples = Vec::new();
    let mut open = 0usize;
    for (t, y) in &states {
        m.update_mode(*t, y);
        for j in 0..bearing.z {
            let (ci, co) = m.ball_contacts(y, j);
            let (si, so) = m.ball_slip_fields(y, j);
            for (c, s) in [(ci, si), (co, so)] {
                match s {
                    Some(sf) if sf.q > 0.0 => samples.push(Sample {
                        sf,
                        spall: c.in_defect,
                        reference: reference(&curve, &sf, panels),
                    }),
                    _ => open += 1,
                }
            }
        }
    }
    let n_spall = samples.iter().filter(|s| s.spall).count();
    // Reference check: the reference against one with half the panels.
    let mut ref_err: f64 = 0.0;
    for s in samples.iter().step_by(37) {
        let r2 = reference(&curve, &s.sf, panels / 2);
        let df = ((s.reference[0] - r2[0]).powi(2) + (s.reference[1] - r2[1]).powi(2)).sqrt();
        ref_err = ref_err.max(df / (curve.kappa_max * s.sf.q));
    }
    // Slip statistics of the sample (what the integrand looks like).
    let mut spin_ratio: Vec<f64> = samples
        .iter()
        .map(|s| {
            let (_, u1, u2) = s.sf.at(0.0);
            (s.sf.s * s.sf.a).abs() / (u1 * u1 + u2 * u2).sqrt().max(1e-12)
        })
        .collect();
    let mut spin_speed: Vec<f64> = samples.iter().map(|s| (s.sf.s * s.sf.a).abs()).collect();
    let mut q: Vec<f64> = samples.iter().map(|s| s.sf.q).collect();
    println!(
        "# {} states t = {skip}..{} s at {fs} Hz, {} loaded contacts ({} in the spall), {} open; \
         reference: {panels} panels × 3-pt Gauss–Legendre, max eF against {} panels {:.1e}",
        states.len(),
        skip + span,
        samples.len(),
        n_spall,
        open,
        panels / 2,
        ref_err
    );
    println!(
        "# Q [N] median {:.0} 99% {:.0} max {:.0}; spin slip |s|·a [m/s] median {:.3} max {:.3}; \
         |s|·a / |u(0)| median {:.2} 99% {:.1}",
        pct(&mut q.clone(), 0.5),
        pct(&mut q.clone(), 0.99),
        pct(&mut q, 1.0),
        pct(&mut spin_speed.clone(), 0.5),
        pct(&mut spin_speed, 1.0),
        pct(&mut spin_ratio.clone(), 0.5),
        pct(&mut spin_ratio, 0.99),
    );
    println!(
        "rule,N,eF_med,eF_99,eF_max,eMs_med,eMs_99,eMs_max,eMr_med,eMr_99,eMr_max,spall_eF_max,spall_eMs_max"
    );
    let mut rows = Vec::new();
    for rule in ["equal", "gauss", "cgl2", "cgl3", "rich3"] {
        for nn in 2..=16 {
            let strips = match rule {
                "equal" => Strips::new(nn),
                "gauss" => Strips::gauss(nn),
                "cgl2" if nn % 2 == 0 => composite(nn / 2, 2),
                "cgl3" if nn % 3 == 0 => composite(nn / 3, 3),
                "rich3" if nn % 3 == 0 => richardson3(nn),
                _ => continue,
            };
            let (mut ef, mut ems, mut emr) = (Vec::new(), Vec::new(), Vec::new());
            let (mut sf_max, mut sms_max) = (0.0f64, 0.0f64);
            for s in &samples {
                let r = strip_sums(&curve, &strips, &s.sf);
                let d: Vec<f64> = (0..5).map(|i| r[i] - s.reference[i]).collect();
                let scale = curve.kappa_max * s.sf.q;
                let e_f = d[0].hypot(d[1]) / scale;
                let e_ms = d[2].abs() / (scale * s.sf.a);
                let e_mr = d[3].hypot(d[4]) / (scale * ball_radius);
                if s.spall {
                    sf_max = sf_max.max(e_f);
                    sms_max = sms_max.max(e_ms);
                }
                ef.push(e_f);
                ems.push(e_ms);
                emr.push(e_mr);
            }
            let row = format!(
                "{rule},{nn},{:.2e},{:.2e},{:.2e},{:.2e},{:.2e},{:.2e},{:.2e},{:.2e},{:.2e},{:.2e},{:.2e}",
                pct(&mut ef, 0.5),
                pct(&mut ef, 0.99),
                pct(&mut ef, 1.0),
                pct(&mut ems, 0.5),
                pct(&mut ems, 0.99),
                pct(&mut ems, 1.0),
                pct(&mut emr, 0.5),
                pct(&mut emr, 0.99),
                pct(&mut emr, 1.0),
                sf_max,
                sms_max
            );
            println!("{row}");
            rows.push(row);
        }
    }
    if let Some(path) = csv {
        std::fs::write(path, rows.join("\n")).expect("write csv");
    }
}
