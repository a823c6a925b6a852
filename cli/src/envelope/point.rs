//! One operating point run through the library (in a worker process, see `envelope.rs`): what it
//! measures, for the classification to judge.

use super::grid::{self, PointSpec};
use raceway::fault_frequencies::{inner_race_control_cage_ratio, outer_race_control};
use raceway::load_distribution::{self, BallEquilibrium};
use raceway::{
    out, AxialMount, Bearing, BearingFile, DefectSpec, Fidelity, Mounting, OperatingPoint, Race,
    Scene, Simulation,
};
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Output sample rate of the checks \[Hz\] (the scenes' default).
const SAMPLE_RATE: f64 = 51_200.0;

/// The L1 reference at the point: the race-control range of the loaded balls.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct L1Ref {
    /// Smallest and largest race-control cage ratio ω_c/Ω over the loaded balls (inner-race
    /// control and outer-race control at each ball's loaded angles): point contacts.
    pub rc_lo: f64,
    pub rc_hi: f64,
    /// The same with each ball's rolling points anywhere across its contact ellipses
    /// ([`ellipse_range`]): the range the cage ratio is checked against.
    pub ell_lo: f64,
    pub ell_hi: f64,
    /// Largest relative change of a ball's range with 9 samples per angle instead of 3.
    pub ell_check: f64,
    /// L1's own cage ratio (outer-race control, load-weighted mean over the loaded balls).
    pub orc_ratio: f64,
    /// A located ring: where it is held \[m\] and the axial force the location supplies \[N\]
    /// (L1's `ring_force()[0]`: bearing.F.x is its negative at the static levels).
    pub held: Option<f64>,
    pub reaction: f64,
    /// Number of loaded balls.
    pub loaded: usize,
}

/// Extremes of the outputs over a set of samples.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct Extremes {
    pub samples: usize,
    /// First non-finite output: (output index, time).
    pub nonfinite: Option<(usize, f64)>,
    /// Largest |bearing.F + applied load| \[N\].
    pub max_f_dev: f64,
    /// Largest |bearing.F| \[N\].
    pub max_f: f64,
    /// Largest inner-ring displacement relative to the outer ring (pedestal) \[m\].
    pub max_ring: f64,
    /// Largest pedestal displacement \[m\].
    pub max_ped: f64,
    /// Largest inner and outer contact forces \[N\].
    pub max_qi: f64,
    pub max_qo: f64,
    /// Sum and count of cage.speed over the samples in the run's second half.
    pub cage_sum: f64,
    pub cage_n: usize,
    /// Smallest and largest cage.speed over all samples \[rad/s\].
    pub cage_min: f64,
    pub cage_max: f64,
    /// Smallest and largest ring.x \[m\] and bearing.F.x \[N\] (for a located ring).
    pub ring_x: [f64; 2],
    pub fx: [f64; 2],
}

impl Default for Extremes {
    fn default() -> Self {
        Self {
            samples: 0,
            nonfinite: None,
            max_f_dev: 0.0,
            max_f: 0.0,
            max_ring: 0.0,
            max_ped: 0.0,
            max_qi: 0.0,
            max_qo: 0.0,
            cage_sum: 0.0,
            cage_n: 0,
            cage_min: f64::INFINITY,
            cage_max: f64::NEG_INFINITY,
            ring_x: [f64::INFINITY, f64::NEG_INFINITY],
            fx: [f64::INFINITY, f64::NEG_INFINITY],
        }
    }
}

/// Widens `[lo, hi]` to hold `v`, a NaN included (it sticks).
fn widen(r: &mut [f64; 2], v: f64) {
    if v.is_nan() || r[0].is_nan() {
        *r = [f64::NAN; 2];
    } else {
        *r = [r[0].min(v), r[1].max(v)];
    }
}

/// `a.max(b)` that keeps a NaN (f64::max drops it).
fn max_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

impl Extremes {
    fn add(&mut self, t: f64, o: &[f64], z: usize, applied: [f64; 3], half: f64) {
        self.samples += 1;
        if self.nonfinite.is_none() {
            if let Some(i) = o.iter().position(|v| !v.is_finite()) {
                self.nonfinite = Some((i, t));
            }
        }
        let f = [
            o[out::BEARING_F_X],
            o[out::BEARING_F_Y],
            o[out::BEARING_F_Z],
        ];
        let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        self.max_f = max_nan(self.max_f, norm(f));
        self.max_f_dev = max_nan(
            self.max_f_dev,
            norm([f[0] + applied[0], f[1] + applied[1], f[2] + applied[2]]),
        );
        let ring = [
            o[out::RING_X],
            o[out::RING_Y] - o[out::PEDESTAL_Y],
            o[out::RING_Z] - o[out::PEDESTAL_Z],
        ];
        self.max_ring = max_nan(self.max_ring, norm(ring));
        widen(&mut self.ring_x, o[out::RING_X]);
        widen(&mut self.fx, f[0]);
        self.max_ped = max_nan(self.max_ped, o[out::PEDESTAL_Y].hypot(o[out::PEDESTAL_Z]));
        if out::has_ball_block(o, z) {
            let q = &o[out::CONTACT_START..out::CONTACT_START + 2 * z];
            for &v in &q[..z] {
                self.max_qi = max_nan(self.max_qi, v);
            }
            for &v in &q[z..] {
                self.max_qo = max_nan(self.max_qo, v);
            }
        }
        let w = o[out::CAGE_SPEED];
        self.cage_min = if w.is_nan() { w } else { self.cage_min.min(w) };
        self.cage_max = max_nan(self.cage_max, w);
        if t >= half {
            self.cage_sum += w;
            self.cage_n += 1;
        }
    }

    fn merge(&mut self, o: &Extremes) {
        self.samples += o.samples;
        if self.nonfinite.is_none() {
            self.nonfinite = o.nonfinite;
        }
        self.max_f_dev = max_nan(self.max_f_dev, o.max_f_dev);
        self.max_f = max_nan(self.max_f, o.max_f);
        self.max_ring = max_nan(self.max_ring, o.max_ring);
        self.max_ped = max_nan(self.max_ped, o.max_ped);
        self.max_qi = max_nan(self.max_qi, o.max_qi);
        self.max_qo = max_nan(self.max_qo, o.max_qo);
        self.cage_sum += o.cage_sum;
        self.cage_n += o.cage_n;
        self.cage_min = if o.cage_min.is_nan() {
            o.cage_min
        } else {
            self.cage_min.min(o.cage_min)
        };
        self.cage_max = max_nan(self.cage_max, o.cage_max);
        for (r, v) in [(&mut self.ring_x, o.ring_x), (&mut self.fx, o.fx)] {
            if v[0] <= v[1] || v[0].is_nan() {
                widen(r, v[0]);
                widen(r, v[1]);
            }
        }
    }
}

/// What a worker reports for one point.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Measured {
    /// The `SimError` (or setup error) that stopped the run, as the user sees it.
    pub error: Option<String>,
    /// Where it stopped: "setup", "build" (Simulation::new) or "advance".
    pub stage: String,
    /// Simulated time reached \[s\].
    pub t_reached: f64,
    /// Wall time of Simulation::new \[s\].
    pub build_wall: f64,
    /// The outputs at t = 0 and of every communication step that returned Ok (what an FMU
    /// master would have received with fmi2OK).
    pub ok: Extremes,
    /// Mean cage.speed over the second half of the delivered samples \[rad/s\] (NaN if none).
    pub cage_speed: f64,
    /// Simulation::cage_speed() at the end \[rad/s\].
    pub cage_model: f64,
    /// bearing.F at the start and at the end \[N\].
    pub f_start: [f64; 3],
    pub f_end: [f64; 3],
    /// Peak Hertz pressure of the largest contact forces \[Pa\].
    pub max_pressure: f64,
    /// Integrator steps (accepted + rejected) and RHS evaluations.
    pub steps: u64,
    pub rhs: u64,
    /// The L1 reference, or why it failed.
    pub l1: Option<L1Ref>,
    pub l1_error: Option<String>,
}

/// The scene of a point: the bearing with its pedestal, healthy or with the default outer-race
/// spall scaled to the ball, at the point's fidelity.
pub fn scene_of(p: &PointSpec) -> Result<Scene, String> {
    let mut file = BearingFile::load(&p.bearing).map_err(|e| e.to_string())?;
    if let Some(k) = p.k_pedestal {
        file.pedestal.k_y = k;
        file.pedestal.k_z = k;
    }
    let level = Fidelity::from_name(&p.level).ok_or_else(|| format!("level {}", p.level))?;
    let d = file.bearing.ball_diameter;
    let mut scene = Scene::healthy(file, OperatingPoint::from_rpm(p.speed_rpm, p.fa, p.fr));
    scene.name = "envelope".into();
    scene.fidelity = level;
    if p.located {
        scene.mounting = Mounting {
            axial: AxialMount::Located,
            axial_offset: None,
        };
    }
    if p.spall {
        scene.defect = Some(DefectSpec {
            ring: Race::Outer.into(),
            width: grid::SPALL_WIDTH_OVER_D * d,
            depth: grid::SPALL_DEPTH_OVER_D * d,
            theta0: std::f64::consts::PI,
        });
    }
    scene.output.duration = p.duration;
    Ok(scene)
}

/// Outer- and inner-race-control cage ratios ω_c/Ω of a ball rolling at contact angles
/// `alpha_i`, `alpha_o` \[rad\]: (smaller, larger).
fn race_control(b: &Bearing, alpha_i: f64, alpha_o: f64) -> (f64, f64) {
    let orc = outer_race_control(b, alpha_i, alpha_o).cage_ratio;
    let irc = inner_race_control_cage_ratio(b, alpha_i, alpha_o);
    (orc.min(irc), orc.max(irc))
}

/// Race-control cage ratios of a loaded ball whose rolling points lie anywhere across its
/// finite contacts: (smallest, largest). A contact ellipse's semi-major axis a lies across the
/// track in the plane of the contact angle, so a rolling point s from its centre rolls at the
/// contact angle shifted by s/R (R the ball radius); each angle goes over
/// [α − a/R, α + a/R], sampled at `n` ≥ 2 evenly spaced points (ends included), with both race
/// controls. The grid takes 3 (ends and middle) and checks them against 9 ([`L1Ref::ell_check`]).
pub fn ellipse_range(b: &Bearing, e: &BallEquilibrium, n: usize) -> (f64, f64) {
    let r = 0.5 * b.d;
    let shift_i = b.hertz(Race::Inner).semi_axes(e.q_inner).0 / r;
    let shift_o = b.hertz(Race::Outer).semi_axes(e.q_outer).0 / r;
    let at = |k: usize| 2.0 * k as f64 / (n - 1) as f64 - 1.0;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for ki in 0..n {
        for ko in 0..n {
            let (l, h) = race_control(
                b,
                e.alpha_inner + at(ki) * shift_i,
                e.alpha_outer + at(ko) * shift_o,
            );
            lo = lo.min(l);
            hi = hi.max(h);
        }
    }
    (lo, hi)
}

/// L1 at the point (of the scene's mounting) and the race-control cage ratios of its loaded
/// balls.
fn l1_reference(b: &Bearing, scene: &Scene, p: &PointSpec) -> Result<L1Ref, String> {
    let case = OperatingPoint::from_rpm(p.speed_rpm, p.fa, p.fr);
    let held =
        raceway::models::held_axial(scene, b, &scene.operating).map_err(|e| e.to_string())?;
    let q = match held {
        None => load_distribution::solve(b, &case),
        Some(d) => load_distribution::solve_located(b, &case, d),
    }
    .map_err(|e| e.to_string())?;
    let (mut lo, mut hi, mut n) = (f64::INFINITY, f64::NEG_INFINITY, 0);
    let (mut ell_lo, mut ell_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let mut ell_check: f64 = 0.0;
    for e in q.loaded_balls() {
        let (l, h) = race_control(b, e.alpha_inner, e.alpha_outer);
        lo = lo.min(l);
        hi = hi.max(h);
        let (l, h) = ellipse_range(b, e, 3);
        ell_lo = ell_lo.min(l);
        ell_hi = ell_hi.max(h);
        let (fl, fh) = ellipse_range(b, e, 9);
        ell_check = ell_check
            .max(((l - fl) / fl).abs())
            .max(((h - fh) / fh).abs());
        n += 1;
    }
    // The location's reaction; at the lumped level L1's at rest, since that level has no
    // centrifugal ball forces (they change the reaction: 204 N at rest, 1796 N at 14286 rpm
    // under Fr 293 N on the Table-1 bearing held at 0).
    let reaction = match held {
        None => p.fa,
        Some(d) if scene.fidelity == Fidelity::Lumped => {
            let rest = OperatingPoint {
                shaft_speed: 0.0,
                ..case
            };
            load_distribution::solve_located(b, &rest, d)
                .map_err(|e| e.to_string())?
                .ring_force()[0]
        }
        Some(_) => q.ring_force()[0],
    };
    Ok(L1Ref {
        rc_lo: lo,
        rc_hi: hi,
        ell_lo,
        ell_hi,
        ell_check,
        orc_ratio: if case.shaft_speed > 0.0 {
            q.cage_speed / case.shaft_speed
        } else {
            f64::NAN
        },
        loaded: n,
        held,
        reaction,
    })
}

/// Runs one point: builds the simulation, advances it in communication steps to the point's
/// duration, and records the extremes of the outputs that each successful step delivered.
pub fn run(p: &PointSpec) -> Measured {
    let mut m = Measured {
        cage_speed: f64::NAN,
        cage_model: f64::NAN,
        f_start: [f64::NAN; 3],
        f_end: [f64::NAN; 3],
        max_pressure: f64::NAN,
        stage: "setup".into(),
        ..Measured::default()
    };
    let scene = match scene_of(p) {
        Ok(s) => s,
        Err(e) => {
            m.error = Some(e);
            return m;
        }
    };
    let bearing = match Bearing::new(&scene.bearing) {
        Ok(b) => b,
        Err(e) => {
            m.error = Some(e.to_string());
            return m;
        }
    };
    match l1_reference(&bearing, &scene, p) {
        Ok(r) => m.l1 = Some(r),
        Err(e) => m.l1_error = Some(e),
    }
    let z = bearing.z;
    // The axial force on the ring: Fa, or a located ring's reaction from L1.
    let fa = m.l1.as_ref().map_or(p.fa, |l| l.reaction);
    let applied = [fa, 0.0, -p.fr];
    let half = 0.5 * p.duration;
    m.stage = "build".into();
    let started = Instant::now();
    let mut sim = match Simulation::new(&scene) {
        Ok(s) => s,
        Err(e) => {
            m.build_wall = started.elapsed().as_secs_f64();
            m.error = Some(e.to_string());
            return m;
        }
    };
    m.build_wall = started.elapsed().as_secs_f64();
    let n_out = sim.output_table().len();
    let mut o = vec![0.0; n_out];
    // The outputs at t = 0, readable before the first step (the FMU's initialization mode).
    let mut ok = Extremes::default();
    let _ = sim.try_outputs(&mut o);
    ok.add(0.0, &o, z, applied, half);
    m.f_start = [
        o[out::BEARING_F_X],
        o[out::BEARING_F_Y],
        o[out::BEARING_F_Z],
    ];
    m.stage = "advance".into();
    let dt = grid::comm_step(scene.fidelity);
    let steps = (p.duration / dt).round().max(1.0) as usize;
    for k in 1..=steps {
        let t_next = if k == steps {
            p.duration
        } else {
            k as f64 * dt
        };
        let mut step = Extremes::default();
        let r = sim.advance_sampled(t_next, 1.0 / SAMPLE_RATE, &mut |t, o| {
            step.add(t, o, z, applied, half)
        });
        match r {
            Ok(()) => ok.merge(&step),
            Err(e) => {
                m.error = Some(e.to_string());
                break;
            }
        }
    }
    if m.error.is_none() {
        m.stage = "done".into();
    }
    let _ = sim.try_outputs(&mut o);
    m.t_reached = sim.time();
    m.cage_model = sim.cage_speed();
    m.f_end = [
        o[out::BEARING_F_X],
        o[out::BEARING_F_Y],
        o[out::BEARING_F_Z],
    ];
    m.cage_speed = if ok.cage_n > 0 {
        ok.cage_sum / ok.cage_n as f64
    } else {
        f64::NAN
    };
    m.max_pressure = max_nan(
        bearing.hertz_inner.peak_pressure(ok.max_qi),
        bearing.hertz_outer.peak_pressure(ok.max_qo),
    );
    let s = sim.stats();
    m.steps = s.steps + s.rejected;
    m.rhs = s.rhs_evals;
    m.ok = ok;
    m
}
