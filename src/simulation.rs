//! The stepping object shared by the CLI and the FMU: scene → state → advance(to t) → outputs.
//!
//! A [`Simulation`] owns one dynamic [`Model`] (chosen by the scene's
//! fidelity) and one [`Integrator`]. Inputs (shaft speed, loads) may
//! change between advances; each change is a discontinuity for the integrator. Failures of an
//! advance are returned as values (naming the time the integrator stopped at) and leave the
//! simulation exactly where the advance started.

use crate::config::ConfigError;
use crate::geometry::Bearing;
use crate::limits::{peak_contact, StaticRating, MAX_CONTACT_PRESSURE, RATING_PRESSURE};
use crate::models::motion::QsMotion;
use crate::models::{Model, ReactionJacobian};
// The models' interface types, at the paths they had when they lived here.
pub use crate::models::{out, output_table, output_table_for, OutputInfo, SimError};
use crate::operating::{OperatingPoint, RingLoad};
use crate::scene::{CouplingMode, MethodName, Scene};
use raceway_solver::{
    grid_points, AdvanceOutcome, Checkpoint, EventAction, EventSystem, Integrator, IntegratorState,
    Method, Options, StepView, System,
};

/// The journal's (inner-ring centre's) motion in coupling mode "motion": displacement `x` \[m\]
/// and velocity `v` [m/s] along x, y, z at the time it was set, in the frame and from the origin
/// of the `ring.x/y/z` outputs: the inertial frame, x along the shaft axis (the axial load
/// direction), z up (the radial load acts along −z); origin = the inner-ring centre when the
/// bearing is unloaded and centred, with the pedestal (outer ring) at rest on unloaded supports.
/// Until the next change the ring moves as x(t) = x + v (t − t_set).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Journal {
    /// Journal displacement along x, y, z at the time it was set \[m\].
    pub x: [f64; 3],
    /// Journal velocity along x, y, z \[m/s\].
    pub v: [f64; 3],
}

impl Journal {
    /// Rejects non-finite values, naming the FMU input.
    pub fn check(&self) -> Result<(), SimError> {
        for (k, axis) in ["x", "y", "z"].into_iter().enumerate() {
            if !self.x[k].is_finite() {
                return Err(SimError::Input(format!(
                    "journal.{axis} = {} is not a finite number",
                    self.x[k]
                )));
            }
            if !self.v[k].is_finite() {
                return Err(SimError::Input(format!(
                    "journal.v.{axis} = {} is not a finite number",
                    self.v[k]
                )));
            }
        }
        Ok(())
    }

    /// Displacement at `dt` after it was set.
    pub fn at(&self, dt: f64) -> [f64; 3] {
        [
            self.x[0] + self.v[0] * dt,
            self.x[1] + self.v[1] * dt,
            self.x[2] + self.v[2] * dt,
        ]
    }
}

/// Work counters of the integrator since the start (or the last reset).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WorkStats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
}

/// Output sampling of an advance: the interval and the callback receiving (time, outputs).
/// A sample callback that also sees the model (time, outputs, model).
pub type ModelSampler<'a> = dyn FnMut(f64, &[f64], &dyn Model) + 'a;

/// A sample callback that also sees the model's state there (time, state, outputs).
pub type StateSampler<'a> = dyn FnMut(f64, &[f64], &[f64]) + 'a;

/// What the samples of an advance are handed to: (time, state, outputs, model).
type SampleSink<'a> = dyn FnMut(f64, &[f64], &[f64], &dyn Model) + 'a;

type Sampler<'a> = (f64, &'a mut SampleSink<'a>);

/// One simulation run.
#[derive(Clone)]
pub struct Simulation {
    scene: Scene,
    bearing: Bearing,
    model: Box<dyn Model>,
    integrator: Integrator,
    inputs: OperatingPoint,
    /// Scratch for interpolated states between stops (CLI sampling).
    samples: Vec<f64>,
    sample_times: Vec<f64>,
    /// One interpolated state and one output vector (no allocation per advance).
    y_scratch: Vec<f64>,
    out_scratch: Vec<f64>,
    /// Length of the output vector the samplers see: the whole table, or
    /// [`out::BEARING_OUTPUTS`] without the per-ball block ([`Simulation::set_ball_outputs`]).
    sampled_outputs: usize,
    /// Motion coupling: the journal, when it was set, and the loads of the start (the loads
    /// the model keeps: `load.F*` act only at initialization in this mode).
    journal: Journal,
    journal_t: f64,
    start_loads: [f64; 3],
    /// Motion coupling, levels with ring states: the shaft speed of the last L1 operating-point
    /// update ([`Model::update_operating_point`], made at the start of a step).
    l1_speed: f64,
    /// Motion coupling at levels without ring states (L0, L1).
    qs_motion: Option<QsMotion>,
    /// Where the current (or last) advance started: put back when it fails
    /// ([`Simulation::undo_advance`]); buffers reused from advance to advance.
    start: Start,
    /// The plausibility limits of the loads and contacts, and the warnings not yet taken.
    limits: Limits,
    /// Model Exchange: what the event functions were at the last completed step or event
    /// update, and which have changed sign since (see [`Simulation::step_completed`]).
    me: MeMemory,
}

/// Model Exchange's memory of the event functions: their values at the last reference point
/// (the last completed integrator step or event update) and the indices that changed sign since
/// the last event update. Not needed by [`Simulation::advance`] (which locates events itself).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
struct MeMemory {
    g_ref: Vec<f64>,
    fired: Vec<bool>,
}

/// Model Exchange: how far ahead (in seconds, times 1 + |t|) of an event the simulation looks
/// for the side an event function goes to ([`Simulation::event_update`]). The importer's event
/// state carries its integration error, so a located root may sit on the old side by more than
/// the location tolerance (a contact function at 1e-12 with a rate of 0.1/s: 1e-11 s before its
/// root); a nanosecond covers that and stays a thousand times below the bearing's time scales
/// (a contact lasts microseconds), so a function that would cross within it switches a
/// nanosecond early at worst.
pub const EVENT_HAIR: f64 = 1e-9;

/// The most continuous states and event functions any level has on a bearing with `z` balls:
/// what a Model Exchange FMU, whose numbers are fixed in its model description whatever the
/// level, declares (a level with fewer pads). The full level has the most of both: 9 states per
/// ball, 16 more for the rings, pedestal and angles; 5 event functions per ball with a spall.
pub fn model_exchange_capacity(z: usize) -> (usize, usize) {
    let full = crate::models::internals::layout::Layout::full(z)
        .with_cage(true)
        .dim();
    (full.max(14), (5 * z).max(z))
}

/// The plausibility limits ([`crate::limits`]) a simulation applies: a load beyond the static
/// load rating or a contact beyond its pressure is a warning (given once each); a contact
/// beyond [`MAX_CONTACT_PRESSURE`] is an error naming what caused it.
#[derive(Clone)]
struct Limits {
    rating: StaticRating,
    warned_rating: bool,
    warned_pressure: bool,
    warnings: Vec<String>,
}

impl Limits {
    /// Checks the loads of `inputs` against the static load rating: beyond it a warning
    /// (once); beyond (MAX_CONTACT_PRESSURE / RATING_PRESSURE)³ C0, the static equivalent load
    /// at which ISO 76's load distribution puts the most loaded contact at the pressure limit
    /// (Hertz pressure grows as the cube root of the load), an error naming the loads. A
    /// located ring's axial reaction is not known here: only its radial load counts.
    fn loads(&mut self, inputs: &OperatingPoint, located: bool) -> Result<(), SimError> {
        let fa = if located { 0.0 } else { inputs.fx };
        let p0 = self.rating.equivalent_load(fa, inputs.fy.hypot(inputs.fz));
        let limit = (MAX_CONTACT_PRESSURE / RATING_PRESSURE).powi(3) * self.rating.c0;
        if p0 > limit {
            return Err(SimError::Input(format!(
                "the loads ({}, {}, {}) N are beyond what the bearing carries: their static \
                 equivalent load P0 = {p0:.0} N is {:.1} times its basic static load rating C0 = \
                 {:.0} N (ISO 76), where the most loaded contact would pass the {:.1} GPa the \
                 model accepts ({limit:.0} N)",
                inputs.fx,
                inputs.fy,
                inputs.fz,
                p0 / self.rating.c0,
                self.rating.c0,
                MAX_CONTACT_PRESSURE * 1e-9
            )));
        }
        if p0 > self.rating.c0 && !self.warned_rating {
            self.warned_rating = true;
            self.warnings.push(format!(
                "the static equivalent load P0 = {p0:.0} N of the loads ({}, {}, {}) N exceeds the \
                 bearing's basic static load rating C0 = {:.0} N (ISO 76, static safety factor \
                 {:.2}): the raceways deform permanently",
                inputs.fx,
                inputs.fy,
                inputs.fz,
                self.rating.c0,
                self.rating.c0 / p0
            ));
        }
        Ok(())
    }

    /// Checks the contact forces `q_inner`, `q_outer` (per ball) at time `t`: beyond
    /// [`MAX_CONTACT_PRESSURE`] an error naming `cause()`, beyond [`RATING_PRESSURE`] a warning
    /// (once). Non-finite forces are left to the callers' checks of the outputs.
    fn contacts(
        &mut self,
        b: &Bearing,
        q_inner: &[f64],
        q_outer: &[f64],
        t: f64,
        cause: impl Fn() -> String,
    ) -> Result<(), SimError> {
        let (p, j, race, q) = peak_contact(b, q_inner, q_outer);
        if p > MAX_CONTACT_PRESSURE {
            return Err(SimError::Input(format!(
                "{} puts ball {}'s {} contact at {q:.0} N, a peak Hertz pressure of {:.2} GPa at \
                 t = {t:.9} s, beyond the {:.1} GPa the model accepts: hardened bearing steel \
                 deforms grossly there and the elastic contact no longer holds (the static load \
                 rating C0 = {:.0} N corresponds to {:.1} GPa)",
                cause(),
                j + 1,
                race.name(),
                p * 1e-9,
                MAX_CONTACT_PRESSURE * 1e-9,
                self.rating.c0,
                RATING_PRESSURE * 1e-9
            )));
        }
        if p > RATING_PRESSURE && !self.warned_pressure {
            self.warned_pressure = true;
            self.warnings.push(format!(
                "{} puts ball {}'s {} contact at {q:.0} N, a peak Hertz pressure of {:.2} GPa at \
                 t = {t:.9} s, beyond the {:.1} GPa of the static load rating (ISO 76): the raceways \
                 deform permanently",
                cause(),
                j + 1,
                race.name(),
                p * 1e-9,
                RATING_PRESSURE * 1e-9
            ));
        }
        Ok(())
    }
}

/// The simulation at the start of an advance: what an advance can change.
#[derive(Default, Clone)]
struct Start {
    integrator: Checkpoint,
    model: Vec<f64>,
    l1_speed: f64,
    /// True from a successful advance until anything else changes the simulation.
    undoable: bool,
}

/// Lets the integrator drive a model (the integrator knows nothing about bearings): the event
/// protocol of [`Simulation`] (an event stops the advance after `event_fired`; the caller then
/// calls `update_mode` and `Integrator::discontinuity`). Public for drivers that step a model
/// themselves (the diagnostic examples).
pub struct ModelSystem<'a>(pub &'a mut dyn Model);

impl System for ModelSystem<'_> {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        self.0.rhs(t, y, dydt)
    }
    fn begin_step(&mut self) {
        self.0.begin_step()
    }
}

impl EventSystem for ModelSystem<'_> {
    fn n_events(&self) -> usize {
        self.0.n_events()
    }
    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]) {
        self.0.events(t, y, g)
    }
    fn event(&mut self, i: usize, t: f64, y: &[f64], g: &mut [f64]) -> f64 {
        self.0.event(i, t, y, g)
    }
    /// The advance stops at the event; the simulation then switches the mode exactly as at a
    /// known-time stop (after the outputs of the samples before the event are taken).
    fn handle_event(&mut self, index: usize, _t: f64, _y: &mut [f64]) -> EventAction {
        self.0.event_fired(index);
        EventAction::Stop
    }
    fn suspect(&mut self, t_old: f64, t_new: f64) -> Option<f64> {
        self.0.suspect(t_old, t_new)
    }
    fn mode_sign(&self, index: usize) -> Option<f64> {
        self.0.mode_sign(index)
    }
}

/// The versioned, pointer-free snapshot of a simulation.
#[derive(serde::Serialize, serde::Deserialize)]
struct Snapshot {
    format: String,
    version: u32,
    fidelity: String,
    dim: usize,
    inputs: OperatingPoint,
    model: Vec<f64>,
    integrator: IntegratorState,
    #[serde(default)]
    journal: Option<(Journal, f64)>,
    #[serde(default)]
    l1_speed: Option<f64>,
    #[serde(default)]
    model_exchange: Option<MeMemory>,
}

/// Motion coupling (levels with ring states): the L1 operating point behind the cage speed is
/// moved when the shaft speed has changed by more than this fraction since the last move (the
/// same threshold as the lumped level's own re-solve in force mode).
pub const L1_SPEED_STEP: f64 = 0.02;

const SNAPSHOT_FORMAT: &str = "raceway-simulation";
const SNAPSHOT_VERSION: u32 = 1;

fn method_of(m: MethodName) -> Method {
    match m {
        MethodName::Rkf45 => Method::Rkf45,
        MethodName::Dopri5 => Method::Dopri5,
        MethodName::Dop853 => Method::Dop853,
    }
}

impl Simulation {
    /// Builds the model of the scene's fidelity and its initial state (from L1, docs/model.md#initial-state).
    pub fn new(scene: &Scene) -> Result<Self, SimError> {
        scene.validate()?;
        let bearing = Bearing::new(&scene.bearing)?;
        // The loads against the static load rating first (a load the bearing cannot carry is
        // refused before any model is built on it).
        let mut limits = Limits {
            rating: StaticRating::of(&bearing),
            warned_rating: false,
            warned_pressure: false,
            warnings: Vec::new(),
        };
        let inputs = scene.operating;
        inputs.check().map_err(SimError::Input)?;
        if scene.coupling == CouplingMode::Force {
            let located = scene.mounting.axial == crate::scene::AxialMount::Located;
            limits.loads(&inputs, located)?;
        }
        let mut model = crate::models::build(scene, &bearing, &inputs)?;
        let n = model.dim();
        let mut y0 = vec![0.0; n];
        model.initial_state(&mut y0);
        model.update_mode(0.0, &y0);
        let integrator = Integrator::new(Self::options(scene, model.as_ref()), 0.0, &y0)
            .map_err(|e| SimError::Config(ConfigError::new("solver", e.to_string())))?;
        let n_out = output_table_for(bearing.z, model.has_cage()).len();
        let n_events = model.n_events();
        let mut sim = Self {
            scene: scene.clone(),
            bearing,
            model,
            integrator,
            inputs,
            samples: Vec::new(),
            sample_times: Vec::new(),
            y_scratch: vec![0.0; n],
            out_scratch: vec![0.0; n_out],
            sampled_outputs: n_out,
            journal: Journal::default(),
            journal_t: 0.0,
            start_loads: [inputs.fx, inputs.fy, inputs.fz],
            l1_speed: inputs.shaft_speed,
            qs_motion: None,
            start: Start {
                integrator: Checkpoint::with_capacity(n, n_events),
                ..Start::default()
            },
            limits,
            me: MeMemory::default(),
        };
        if let Some(w) = crate::models::deprecation_warning(scene.fidelity) {
            sim.limits.warnings.push(w);
        }
        if let Some(note) = sim.model.start_note() {
            sim.limits.warnings.push(note);
        }
        if scene.coupling == CouplingMode::Force {
            sim.check_contacts(|| {
                format!("the start's {}", crate::models::operating_point(&inputs))
            })?;
        }
        if scene.coupling == CouplingMode::Motion {
            // The journal starts where the loads of the scene put the ring (the L1 start,
            // docs/model.md#initial-state), at rest.
            let mut o = vec![0.0; n_out];
            sim.model.outputs(0.0, &y0, &mut o);
            let x = [o[out::RING_X], o[out::RING_Y], o[out::RING_Z]];
            match sim.model.ring_states() {
                Some(_) => sim.model.set_prescribed_ring(true),
                None => sim.qs_motion = Some(QsMotion::new(&sim.bearing)),
            }
            sim.set_journal(Journal { x, v: [0.0; 3] })?;
        }
        Ok(sim)
    }

    /// The plausibility of the contacts at the current state ([`crate::limits`]): an error
    /// naming `cause()` beyond [`MAX_CONTACT_PRESSURE`], a warning (once) beyond the rating.
    fn check_contacts(&mut self, cause: impl Fn() -> String) -> Result<(), SimError> {
        let t = self.integrator.t();
        let z = self.bearing.z;
        self.model
            .outputs(t, self.integrator.y(), &mut self.out_scratch);
        let (qi, qo) = self.out_scratch[out::CONTACT_START..out::CONTACT_START + 2 * z].split_at(z);
        self.limits.contacts(&self.bearing, qi, qo, t, cause)
    }

    /// The warnings since the last call (a deprecated level, [`crate::models::Level::deprecated`];
    /// loads beyond the static load rating, contacts beyond its pressure: each given once per
    /// simulation; a start other than the level's usual one, [`Model::start_note`]), for the
    /// caller to show: the FMU logs them with status
    /// fmi2Warning, the CLI prints them.
    pub fn take_warnings(&mut self) -> Vec<String> {
        std::mem::take(&mut self.limits.warnings)
    }

    /// The coupling mode of the scene.
    pub fn coupling(&self) -> CouplingMode {
        self.scene.coupling
    }

    /// The journal motion in force (last set, or the start's equilibrium at rest).
    pub fn journal(&self) -> Journal {
        self.journal
    }

    /// Prescribes the journal's (inner-ring centre's) motion from now on: the ring moves as
    /// x(t) = j.x + j.v (t − now) until the next call (coupling mode "motion" only).
    pub fn set_journal(&mut self, j: Journal) -> Result<(), SimError> {
        if self.scene.coupling != CouplingMode::Motion {
            return Err(SimError::Unsupported(
                "the journal motion is an input in coupling mode 'motion' only (this simulation couples by force)".into(),
            ));
        }
        j.check()?;
        self.start.undoable = false;
        let t = self.integrator.t();
        let cause = || {
            format!(
                "the journal at ({:e}, {:e}, {:e}) m",
                j.x[0], j.x[1], j.x[2]
            )
        };
        if let Some(rs) = self.model.ring_states() {
            let n = self.state_with_journal(rs, &j);
            // The contacts the prescribed ring would press, before it is taken.
            let z = self.bearing.z;
            self.model
                .outputs(t, &self.y_scratch[..n], &mut self.out_scratch);
            let (qi, qo) =
                self.out_scratch[out::CONTACT_START..out::CONTACT_START + 2 * z].split_at(z);
            self.limits.contacts(&self.bearing, qi, qo, t, cause)?;
            self.integrator.set_state(t, &self.y_scratch[..n]);
        } else if let Some(qs) = self.qs_motion.as_mut() {
            // L0/L1: the model runs at the load the displaced ring needs.
            let r = qs.solve(self.inputs.shaft_speed, j.x)?;
            let qi: Vec<f64> = r.solution.balls.iter().map(|b| b.q_inner).collect();
            let qo: Vec<f64> = r.solution.balls.iter().map(|b| b.q_outer).collect();
            self.limits.contacts(&self.bearing, &qi, &qo, t, cause)?;
            let load = r.load;
            let eff = OperatingPoint {
                fx: load[0],
                fy: load[1],
                fz: load[2],
                ..self.inputs
            };
            self.model.set_inputs(&eff, t, self.integrator.y())?;
            qs.applied_load = load;
        }
        self.journal = j;
        self.journal_t = t;
        self.model.update_mode(t, self.integrator.y());
        self.integrator.discontinuity();
        Ok(())
    }

    /// Linearization of the bearing's reaction on the journal (`bearing.F`) with respect to
    /// the journal's displacement and velocity at the current state (coupling mode "motion").
    /// Analytic where the level provides it, else central differences of the level's outputs.
    pub fn reaction_jacobian(&mut self) -> Result<ReactionJacobian, SimError> {
        if self.scene.coupling != CouplingMode::Motion {
            return Err(SimError::Unsupported(
                "the reaction Jacobian ∂bearing.F/∂journal exists in coupling mode 'motion' only"
                    .into(),
            ));
        }
        let t = self.integrator.t();
        if let Some(qs) = self.qs_motion.as_mut() {
            let x = self.journal.at(t - self.journal_t);
            return Ok(qs.solve(self.inputs.shaft_speed, x)?.jacobian);
        }
        let Some(rs) = self.model.ring_states() else {
            return Err(SimError::Unsupported("no ring states".into()));
        };
        if let Some(j) = self.model.reaction_jacobian(t, self.integrator.y()) {
            return Ok(j);
        }
        // Central differences of the model's own bearing.F.
        let n = self.model.dim();
        let mut y = self.integrator.y().to_vec();
        let mut o = vec![0.0; self.out_scratch.len()];
        let mut jac = ReactionJacobian::default();
        for (idx, h, is_pos) in rs
            .pos
            .iter()
            .map(|&i| (i, 1e-10, true))
            .chain(rs.vel.iter().map(|&i| (i, 1e-5, false)))
            .collect::<Vec<_>>()
        {
            let col = if is_pos {
                rs.pos.iter().position(|&p| p == idx)
            } else {
                rs.vel.iter().position(|&p| p == idx)
            }
            .expect("index of the ring");
            let save = y[idx];
            y[idx] = save + h;
            self.model.outputs(t, &y[..n], &mut o);
            let fp = [
                o[out::BEARING_F_X],
                o[out::BEARING_F_Y],
                o[out::BEARING_F_Z],
            ];
            y[idx] = save - h;
            self.model.outputs(t, &y[..n], &mut o);
            let fm = [
                o[out::BEARING_F_X],
                o[out::BEARING_F_Y],
                o[out::BEARING_F_Z],
            ];
            y[idx] = save;
            for i in 0..3 {
                let d = (fp[i] - fm[i]) / (2.0 * h);
                if is_pos {
                    jac.dfdx[i][col] = d;
                } else {
                    jac.dfdv[i][col] = d;
                }
            }
        }
        // Leave the model's caches at the current state.
        self.model.outputs(t, &y[..n], &mut o);
        Ok(jac)
    }

    /// Absolute tolerances: rtol × each state's nominal value (docs/model.md#tolerances).
    fn atol(model: &dyn Model, rtol: f64) -> Vec<f64> {
        let mut nominal = vec![0.0; model.dim()];
        model.nominal(&mut nominal);
        nominal.iter().map(|v| v * rtol).collect()
    }

    fn options(scene: &Scene, model: &dyn Model) -> Options {
        let rtol = scene.solver.rtol;
        let mut o = Options::new(
            method_of(scene.solver.method),
            rtol,
            Self::atol(model, rtol),
        );
        o.max_steps = scene.solver.max_steps;
        o.pi_beta = scene.solver.pi_beta;
        // The models' events are contacts and spall boundaries. 50 steps in a row ending in one,
        // within 10 ns, is chatter (as a contact damping far beyond critical, before contact.c_br
        // was bounded, opened and closed a contact every step or two), not physics: the fastest
        // contact vibration of a preset's ball lasts microseconds, and the envelope's busiest
        // runs (balls rattling in a spall under light load) take more than 1e-4 s for such a run.
        o.chatter_events = 50;
        o.chatter_span = 1e-8;
        o
    }

    /// The scene the simulation was built from.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The derived bearing geometry.
    pub fn bearing(&self) -> &Bearing {
        &self.bearing
    }

    /// Current time \[s\].
    pub fn time(&self) -> f64 {
        self.integrator.t()
    }

    /// The current inputs: shaft speed and loads in SI units.
    pub fn inputs(&self) -> OperatingPoint {
        self.inputs
    }

    /// Coupling mode "force", levels with a dynamic inner ring (lumped, reduced, full): a
    /// force law on the ring added to the inputs' load from now on (`None`: none), e.g. a
    /// partner model's transmission line over the next communication step. It is not part of
    /// a checkpoint: set it before every advance that should feel it.
    pub fn set_ring_load(&mut self, law: Option<RingLoad>) -> Result<(), SimError> {
        if self.scene.coupling != CouplingMode::Force {
            return Err(SimError::Unsupported(
                "a ring load law acts in coupling mode 'force' only (in motion mode the journal's motion is the input)".into(),
            ));
        }
        if !self.model.set_ring_load(law) {
            return Err(SimError::Unsupported(format!(
                "the {} level has no dynamic inner ring to carry a ring load law: use the lumped, reduced or full level",
                self.scene.fidelity.name()
            )));
        }
        self.integrator.discontinuity();
        Ok(())
    }

    /// The inner ring's velocity \[m/s\] along x, y, z at the current state, on the levels
    /// where the ring is a dynamic body (`None` on the kinematic and quasi-static levels).
    pub fn ring_velocity(&self) -> Option<[f64; 3]> {
        let rs = self.model.ring_states()?;
        let y = self.integrator.y();
        Some(rs.vel.map(|i| y[i]))
    }

    /// Sets the inputs from now on (piecewise constant until the next change). Unchanged
    /// inputs are free; a change is a discontinuity for the integrator.
    ///
    /// In coupling mode "motion" the loads act only at the start: later loads are kept (and
    /// reported by [`Simulation::inputs`]) but the model runs on the start's loads (L2, L4) or
    /// on the load the displaced ring needs (L0, L1). With an axially located inner ring
    /// ([`crate::scene::Mounting`]) the axial load cannot change (an error names it).
    pub fn set_inputs(&mut self, inputs: OperatingPoint) -> Result<(), SimError> {
        inputs.check().map_err(SimError::Input)?;
        if inputs == self.inputs {
            return Ok(());
        }
        if self.scene.mounting.axial == crate::scene::AxialMount::Located
            && inputs.fx != self.inputs.fx
        {
            return Err(SimError::Input(format!(
                "load.Fx = {} N cannot act on an axially located inner ring (it sets the ring's \
                 axial place only at the start, {} N there; bearing.F.x is the axial reaction \
                 of the location)",
                inputs.fx, self.inputs.fx
            )));
        }
        self.start.undoable = false;
        if self.scene.coupling == CouplingMode::Force {
            let located = self.scene.mounting.axial == crate::scene::AxialMount::Located;
            self.limits.loads(&inputs, located)?;
        }
        let t = self.integrator.t();
        let (eff, applied) = self.effective_inputs(&inputs, t)?;
        self.model.set_inputs(&eff, t, self.integrator.y())?;
        if let (Some(qs), Some(load)) = (self.qs_motion.as_mut(), applied) {
            qs.applied_load = load;
        }
        self.inputs = inputs;
        self.model.update_mode(t, self.integrator.y());
        self.integrator.discontinuity();
        Ok(())
    }

    /// The inputs the model runs on: the given ones in force mode; in motion mode with the
    /// start's loads (L2, L4: the prescribed ring ignores loads; the L1 cage-speed update on a
    /// speed change is [`Simulation::update_l1_point`]), or the load the displaced ring needs in
    /// quasi-static equilibrium (L0, L1), returned as well (the caller records it as the load
    /// the model runs on once the model has taken the inputs).
    fn effective_inputs(
        &mut self,
        inputs: &OperatingPoint,
        t: f64,
    ) -> Result<(OperatingPoint, Option<[f64; 3]>), SimError> {
        let mut eff = *inputs;
        let mut applied = None;
        if self.scene.coupling == CouplingMode::Motion {
            let load = match self.qs_motion.as_mut() {
                Some(qs) => {
                    let x = self.journal.at(t - self.journal_t);
                    let load = qs.solve(inputs.shaft_speed, x)?.load;
                    applied = Some(load);
                    load
                }
                None => self.start_loads,
            };
            eff.fx = load[0];
            eff.fy = load[1];
            eff.fz = load[2];
        }
        Ok((eff, applied))
    }

    /// Motion coupling, levels with ring states (L2, L4): when the shaft speed has moved by more
    /// than [`L1_SPEED_STEP`] since the last update, moves the level's L1 operating point (its
    /// cage speed) to the current speed at the start's loads. Called at the start of every
    /// advance, so it sees the inputs of the communication point whatever the order they were
    /// set in, and a speed ramp re-solves L1 once per [`L1_SPEED_STEP`] of speed, not once per
    /// step. It depends on the inputs alone (the speed at the communication points and the
    /// start's loads), not on the journal's state at that moment, so two masters that hand the
    /// same inputs at the same communication points get the same cage speed.
    fn update_l1_point(&mut self) -> Result<(), SimError> {
        if self.scene.coupling != CouplingMode::Motion || self.qs_motion.is_some() {
            return Ok(());
        }
        let speed = self.inputs.shaft_speed;
        if (speed - self.l1_speed).abs() <= L1_SPEED_STEP * self.l1_speed.abs().max(1.0) {
            return Ok(());
        }
        let t = self.integrator.t();
        let [fx, fy, fz] = self.start_loads;
        let point = OperatingPoint {
            fx,
            fy,
            fz,
            ..self.inputs
        };
        self.model.update_operating_point(&point)?;
        self.l1_speed = speed;
        self.model.update_mode(t, self.integrator.y());
        self.integrator.discontinuity();
        Ok(())
    }

    /// Changes the relative tolerance (absolute tolerances follow: rtol × nominal).
    pub fn set_rtol(&mut self, rtol: f64) -> Result<(), SimError> {
        if !(crate::scene::MIN_RTOL..0.1).contains(&rtol) {
            return Err(SimError::Config(ConfigError::new(
                "solver.rtol",
                format!(
                    "{rtol} must lie in [{:e}, 0.1): {}",
                    crate::scene::MIN_RTOL,
                    crate::scene::RTOL_FLOOR_WHY
                ),
            )));
        }
        // Keep the integrator (its step size, FSAL stage and work counters); change the tolerances.
        let atol = Self::atol(self.model.as_ref(), rtol);
        let bad = |e: raceway_solver::SolverError| {
            SimError::Config(ConfigError::new("solver.rtol", e.to_string()))
        };
        self.integrator.set_rtol(rtol).map_err(bad)?;
        self.integrator.set_atol(&atol).map_err(bad)?;
        self.scene.solver.rtol = rtol;
        Ok(())
    }

    /// Changes the integrator's step-size controller (safety, factor limits, PI β, restart after
    /// discontinuities; see [`crate::solver::Integrator::set_step_control`]). For studies of
    /// the controller (`studies/controller_study.rs`); scenes use the defaults.
    pub fn set_step_control(&mut self, c: &Options) -> Result<(), SimError> {
        self.integrator
            .set_step_control(c)
            .map_err(|e| SimError::Config(ConfigError::new("solver", e.to_string())))
    }

    /// Advances to exactly `t_end`, landing on every known discontinuity of the model on the way.
    /// On failure the simulation is back where the advance started (state, modes, operating
    /// point, work counters), and the error says where the integrator stopped and what the
    /// discarded attempt cost ([`SimError::Solver`]).
    pub fn advance(&mut self, t_end: f64) -> Result<(), SimError> {
        self.advance_impl(t_end, None)
    }

    /// Puts the simulation back where the last advance started, for a caller that rejects the
    /// advance's result (the FMU when an output it reads at the end is not finite). Possible only
    /// right after a successful advance: any other change since (inputs, journal, a restored
    /// state) makes it an error.
    pub fn undo_advance(&mut self) -> Result<(), SimError> {
        if !self.start.undoable {
            return Err(SimError::State(
                "no advance to undo: the simulation changed since the last one".into(),
            ));
        }
        self.rollback()
    }

    /// Takes the checkpoint an advance starts from (no allocation once the buffers have their
    /// size).
    fn checkpoint(&mut self) {
        self.integrator.checkpoint(&mut self.start.integrator);
        self.model.checkpoint(&mut self.start.model);
        self.start.l1_speed = self.l1_speed;
        self.start.undoable = false;
    }

    /// Puts back the checkpoint of the last advance.
    fn rollback(&mut self) -> Result<(), SimError> {
        self.start.undoable = false;
        self.integrator.rollback(&self.start.integrator);
        self.l1_speed = self.start.l1_speed;
        let t = self.integrator.t();
        self.model
            .rollback(&self.start.model, t, self.integrator.y())
            .map_err(|e| {
                SimError::State(format!("the model could not be put back at t = {t} s: {e}"))
            })
    }

    /// Whether the samplers ([`Simulation::advance_sampled`] and
    /// [`Simulation::advance_sampled_with_model`]) get the per-ball outputs (contact forces,
    /// orbital speeds, separation flags; on by default). Off, they get the first
    /// [`out::BEARING_OUTPUTS`] outputs only (pedestal, ring, bearing force, friction torque,
    /// cage speed), and the models skip the per-ball work at every sample: for callers that
    /// want a signal such as `pedestal.a.z` (spectra, sweeps). The states, and so every output,
    /// are the same either way.
    pub fn set_ball_outputs(&mut self, on: bool) {
        self.sampled_outputs = if on {
            self.out_scratch.len()
        } else {
            out::BEARING_OUTPUTS.min(self.out_scratch.len())
        };
    }

    /// True when the samplers get the per-ball outputs ([`Simulation::set_ball_outputs`]).
    pub fn ball_outputs(&self) -> bool {
        self.sampled_outputs == self.out_scratch.len()
    }

    /// Advances to `t_end` and calls `sample(t, outputs)` at every multiple of `dt` in
    /// (current time, t_end], from the integrator's dense output (no extra steps). `outputs`
    /// is the whole output vector, or its bearing-level part ([`Simulation::set_ball_outputs`]).
    pub fn advance_sampled(
        &mut self,
        t_end: f64,
        dt: f64,
        sample: &mut dyn FnMut(f64, &[f64]),
    ) -> Result<(), SimError> {
        self.advance_impl(t_end, Some((dt, &mut |t, _, o, _| sample(t, o))))
    }

    /// [`Simulation::advance_sampled`] whose callback also sees the model in the sample's
    /// discrete mode, e.g. to ask which balls are inside the spall zone
    /// ([`Model::in_spall_zone`]).
    pub fn advance_sampled_with_model(
        &mut self,
        t_end: f64,
        dt: f64,
        sample: &mut ModelSampler<'_>,
    ) -> Result<(), SimError> {
        self.advance_impl(t_end, Some((dt, &mut |t, _, o, m| sample(t, o, m))))
    }

    /// [`Simulation::advance_sampled`] whose callback also gets the model's state at the
    /// sample, interpolated from the dense output like the outputs (no extra steps): for
    /// studies that measure what no output gives (e.g. the distances between the balls).
    pub fn advance_sampled_with_state(
        &mut self,
        t_end: f64,
        dt: f64,
        sample: &mut StateSampler<'_>,
    ) -> Result<(), SimError> {
        self.advance_impl(t_end, Some((dt, &mut |t, y, o, _| sample(t, y, o))))
    }

    /// Checks the target, takes the checkpoint, advances, and on any failure puts the
    /// checkpoint back. (Samples already handed to the sampler stay delivered: they are points
    /// of the trajectory the integrator accepted before it stopped.)
    fn advance_impl(&mut self, t_end: f64, sampling: Option<Sampler<'_>>) -> Result<(), SimError> {
        if !t_end.is_finite() {
            return Err(SimError::Input(format!("end time {t_end} is not finite")));
        }
        let t0 = self.integrator.t();
        if t_end < t0 {
            return Err(SimError::Input(format!(
                "cannot advance backwards from t = {t0} s to {t_end} s"
            )));
        }
        self.checkpoint();
        let checked = self
            .advance_from_checkpoint(t_end, sampling)
            .and_then(|()| {
                // Contacts that follow the inputs were checked when those were set.
                if self.model.contacts_follow_inputs() {
                    return Ok(());
                }
                let (inputs, journal) = (self.inputs, self.journal.at(t_end - self.journal_t));
                let motion = self.scene.coupling == CouplingMode::Motion;
                self.check_contacts(|| {
                    if motion {
                        format!(
                            "the journal at ({:e}, {:e}, {:e}) m",
                            journal[0], journal[1], journal[2]
                        )
                    } else {
                        crate::models::operating_point(&inputs)
                    }
                })
            });
        match checked {
            Ok(()) => {
                self.start.undoable = true;
                Ok(())
            }
            Err(mut e) => {
                if let SimError::Solver { message, .. } = &mut e {
                    // The counters go back with the rest: say what the failed attempt cost.
                    let (now, then) = (self.integrator.stats(), self.start.integrator.stats());
                    message.push_str(&format!(
                        " (work discarded with the advance: {} steps accepted, {} rejected, {} \
                         right-hand-side evaluations)",
                        now.steps - then.steps,
                        now.rejected - then.rejected,
                        now.rhs_evals - then.rhs_evals
                    ));
                }
                match self.rollback() {
                    Ok(()) => Err(e),
                    Err(r) => Err(SimError::State(format!("{e}; then {r}"))),
                }
            }
        }
    }

    fn advance_from_checkpoint(
        &mut self,
        t_end: f64,
        mut sampling: Option<Sampler<'_>>,
    ) -> Result<(), SimError> {
        self.update_l1_point()?;
        // The sampler below reads the dense output only at multiples of dt: the integrator
        // builds it only for the steps that contain one (or need it for an event).
        self.integrator
            .set_sample_grid(sampling.as_ref().map(|(dt, _)| *dt));
        let n = self.model.dim();
        // The budget (solver.max_steps) holds for the whole advance (one communication step),
        // not for each integrator call between two stops or events, and covers every unit of
        // work whose count the inputs decide: attempted integrator steps, the model's catch-up
        // ([`Model::catch_up`]), and one unit for an integrator call that took no step.
        let budget = self.scene.solver.max_steps;
        let attempts = |s: raceway_solver::Stats| s.steps + s.rejected;
        let used0 = attempts(self.integrator.stats());
        let mut other = 0u64;
        let exhausted = |sim: &mut Self, other: u64| {
            let s = sim.integrator.stats();
            let tried = attempts(s) - used0;
            sim.failure(format!(
                "step budget exhausted: {budget} units of work (solver.max_steps) used in this \
                 advance ({tried} integrator steps attempted{}), the last accepted step {:.3e} s",
                if other > 0 {
                    format!(", {other} other units")
                } else {
                    String::new()
                },
                s.h_last
            ))
        };
        let caught_up = |t: f64, e: String| SimError::Solver {
            t,
            message: format!(
                "{e} (solver.max_steps = {budget} units of work per communication step: \
                 integrator steps and spall passes)"
            ),
        };
        while self.integrator.t() < t_end {
            let t = self.integrator.t();
            let before = attempts(self.integrator.stats());
            let used = before - used0 + other;
            if used >= budget {
                return Err(exhausted(self, other));
            }
            self.integrator.set_max_steps(budget - used);
            let stop = self.model.next_stop(t, self.integrator.y(), t_end);
            let target = stop.unwrap_or(t_end);
            self.samples.clear();
            self.sample_times.clear();
            let result = {
                let with_events = self.model.n_events() > 0;
                let mut sys = ModelSystem(self.model.as_mut());
                match sampling.as_mut() {
                    None if with_events => self
                        .integrator
                        .advance_with_events(&mut sys, target, None)
                        .map(|o| matches!(o, AdvanceOutcome::Stopped { .. })),
                    None => self
                        .integrator
                        .advance(&mut sys, target, None)
                        .map(|_| false),
                    Some((dt, _)) => {
                        let dt = *dt;
                        let samples = &mut self.samples;
                        let times = &mut self.sample_times;
                        let buf = &mut self.y_scratch;
                        let mut obs = |v: &StepView| {
                            for ts in grid_points(dt, v.t_start(), v.t_end()) {
                                v.interpolate(ts.min(v.t_end()), buf);
                                // Element by element: `extend_from_slice` becomes a memmove
                                // call per sample, 7 % of the kinematic level's time.
                                for &x in buf.iter() {
                                    samples.push(x);
                                }
                                times.push(ts);
                            }
                        };
                        if with_events {
                            self.integrator
                                .advance_with_events(&mut sys, target, Some(&mut obs))
                                .map(|o| matches!(o, AdvanceOutcome::Stopped { .. }))
                        } else {
                            self.integrator
                                .advance(&mut sys, target, Some(&mut obs))
                                .map(|_| false)
                        }
                    }
                }
            };
            if attempts(self.integrator.stats()) == before {
                other += 1;
            }
            // Outputs of the samples of this interval use its (frozen) discrete mode.
            if let Some((_, cb)) = sampling.as_mut() {
                for (i, &ts) in self.sample_times.iter().enumerate() {
                    let y = &self.samples[i * n..(i + 1) * n];
                    let used = attempts(self.integrator.stats()) - used0 + other;
                    other += self
                        .model
                        .catch_up(ts, y, budget.saturating_sub(used))
                        .map_err(|e| caught_up(ts, e))?;
                    let o = &mut self.out_scratch[..self.sampled_outputs];
                    self.model.outputs(ts, y, o);
                    if let Some(qs) = self.qs_motion.as_mut() {
                        let x = self.journal.at(ts - self.journal_t);
                        qs_motion_outputs(qs, &self.bearing, self.inputs.shaft_speed, x, o)?;
                    }
                    cb(ts, y, o, self.model.as_ref());
                }
            }
            let event = match result {
                Ok(event) => event,
                Err(raceway_solver::SolverError::StepBudget { .. }) => {
                    return Err(exhausted(self, other))
                }
                Err(e) => {
                    let model = self.model.as_ref();
                    let message = e.describe_with_events(
                        &|i| format!("{} (state {i})", model.state_name(i)),
                        &|i| model.event_name(i),
                    );
                    return Err(self.failure(message));
                }
            };
            if stop.is_some() || event {
                let t = self.integrator.t();
                self.model.update_mode(t, self.integrator.y());
                self.integrator.discontinuity();
            }
        }
        // Leave the model caught up at the end, so that reading the outputs costs no more. A
        // sampled advance leaves the work after its last sample to the next sample, where it
        // would have been done (done here, at an end between samples, it would round the pass
        // times differently from a run cut into other advances), and only checks that it fits
        // in what the budget leaves, so that no later call is unbounded either.
        let used = attempts(self.integrator.stats()) - used0 + other;
        let left = budget.saturating_sub(used);
        let y = self.integrator.y();
        match sampling {
            None => self.model.catch_up(t_end, y, left).map(|_| ()),
            Some(_) => self.model.check_catch_up(t_end, y, left),
        }
        .map_err(|e| caught_up(t_end, e))?;
        Ok(())
    }

    /// The error of an advance that stopped at the integrator's current state, for `cause`, with
    /// what the model can tell about that state ([`Model::diagnose`]).
    fn failure(&mut self, cause: String) -> SimError {
        let t = self.integrator.t();
        let message = match self.model.diagnose(t, self.integrator.y()) {
            Some(facts) => format!("{cause}; there {facts}"),
            None => cause,
        };
        SimError::Solver { t, message }
    }

    /// The output table of this simulation (with the cage block when its model has a cage).
    pub fn output_table(&self) -> Vec<OutputInfo> {
        output_table_for(self.bearing.z, self.model.has_cage())
    }

    /// Fills `out` (length `output_table().len()`) with the outputs at the current time.
    ///
    /// In coupling mode "motion" at L0/L1 the ring, pedestal and bearing force come from the
    /// displacement-controlled quasi-static reaction at the journal's current displacement; if
    /// that cannot be solved (e.g. the journal pushed past the balls) the outputs keep the
    /// model's values and the error is returned.
    pub fn outputs(&mut self, out: &mut [f64]) {
        let _ = self.try_outputs(out);
    }

    /// [`Simulation::outputs`] reporting a failed quasi-static reaction (motion mode, L0/L1).
    pub fn try_outputs(&mut self, out: &mut [f64]) -> Result<(), SimError> {
        let t = self.integrator.t();
        self.model.outputs(t, self.integrator.y(), out);
        if let Some(qs) = self.qs_motion.as_mut() {
            let x = self.journal.at(t - self.journal_t);
            qs_motion_outputs(qs, &self.bearing, self.inputs.shaft_speed, x, out)?;
        }
        Ok(())
    }

    /// The cage speed the model uses [rad/s].
    pub fn cage_speed(&self) -> f64 {
        self.model.cage_speed()
    }

    /// Integrator work since the start.
    pub fn stats(&self) -> WorkStats {
        let s = self.integrator.stats();
        WorkStats {
            steps: s.steps,
            rejected: s.rejected,
            rhs_evals: s.rhs_evals,
        }
    }

    /// The integrator's full work counters (events handled, steps flagged by the stiffness
    /// detection, step-size range) since the start.
    pub fn solver_stats(&self) -> raceway_solver::Stats {
        self.integrator.stats()
    }

    /// A pointer-free snapshot from which [`Simulation::restore_state`] continues bit-identically.
    pub fn save_state(&self) -> Vec<u8> {
        let snap = Snapshot {
            format: SNAPSHOT_FORMAT.into(),
            version: SNAPSHOT_VERSION,
            fidelity: self.scene.fidelity.name().into(),
            dim: self.model.dim(),
            inputs: self.inputs,
            model: self.model.discrete_state(),
            integrator: self.integrator.snapshot(),
            journal: Some((self.journal, self.journal_t)),
            l1_speed: Some(self.l1_speed),
            model_exchange: (self.me != MeMemory::default()).then(|| self.me.clone()),
        };
        serde_json::to_vec(&snap).expect("a snapshot serializes")
    }

    /// Restores a snapshot taken from a simulation of the same scene.
    pub fn restore_state(&mut self, bytes: &[u8]) -> Result<(), SimError> {
        let snap: Snapshot = serde_json::from_slice(bytes)
            .map_err(|e| SimError::State(format!("not a raceway simulation snapshot: {e}")))?;
        if snap.format != SNAPSHOT_FORMAT || snap.version != SNAPSHOT_VERSION {
            return Err(SimError::State(format!(
                "snapshot format {} v{} is not {SNAPSHOT_FORMAT} v{SNAPSHOT_VERSION}",
                snap.format, snap.version
            )));
        }
        if snap.fidelity != self.scene.fidelity.name() || snap.dim != self.model.dim() {
            return Err(SimError::State(format!(
                "snapshot of a '{}' model with {} states does not fit this '{}' model with {}",
                snap.fidelity,
                snap.dim,
                self.scene.fidelity.name(),
                self.model.dim()
            )));
        }
        snap.inputs.check().map_err(SimError::Input)?;
        self.start.undoable = false;
        self.integrator
            .restore(&snap.integrator)
            .map_err(|e| SimError::State(e.to_string()))?;
        self.inputs = snap.inputs;
        let t = self.integrator.t();
        if let Some((j, tj)) = snap.journal {
            j.check()?;
            self.journal = j;
            self.journal_t = tj;
        }
        if let Some(s) = snap.l1_speed {
            self.l1_speed = s;
        }
        let me = snap.model_exchange.unwrap_or_default();
        let ne = self.model.n_events();
        if !(me.g_ref.is_empty() || me.g_ref.len() == ne)
            || !(me.fired.is_empty() || me.fired.len() == ne)
        {
            return Err(SimError::State(format!(
                "the snapshot's event memory has {} values for {ne} event functions",
                me.g_ref.len()
            )));
        }
        self.me = me;
        // The discrete state first (the L1 operating point, the spall passes registered so
        // far), so that the inputs find the model where it was: no L1 re-solve, and no catch-up
        // from t = 0 (unbounded for a late snapshot) at the kinematic level.
        self.model
            .set_discrete_state(&snap.model)
            .map_err(SimError::State)?;
        let (eff, applied) = self.effective_inputs(&snap.inputs, t)?;
        self.model.set_inputs(&eff, t, self.integrator.y())?;
        if let (Some(qs), Some(load)) = (self.qs_motion.as_mut(), applied) {
            qs.applied_load = load;
        }
        self.model.update_mode(t, self.integrator.y());
        Ok(())
    }
}

/// Model Exchange: the importer integrates the continuous states ([`Simulation::state`],
/// [`Simulation::derivatives`]) and locates the events ([`Simulation::event_functions`],
/// [`Simulation::next_time_event`]); the simulation keeps the time, the state and the frozen
/// discrete mode, which changes only at [`Simulation::event_update`]. The integrator of
/// [`Simulation::advance`] only holds the time and the state here (so that
/// [`Simulation::save_state`] and the outputs work unchanged); do not mix the two ways of
/// running one simulation.
impl Simulation {
    /// Whether the importer can integrate this simulation (Model Exchange): not the kinematic
    /// level (its signal is impulse trains registered lazily, spall pass by spall pass, on the
    /// way to each output: no continuous dynamics of its own); in coupling mode motion only the
    /// levels whose ring is a dynamic body (there the journal inputs take the ring's states:
    /// [`Simulation::set_journal_continuous`]).
    pub fn model_exchange_check(&self) -> Result<(), SimError> {
        if self.scene.fidelity == crate::scene::Fidelity::Kinematic {
            return Err(SimError::Unsupported(
                "the kinematic level (L0) has no continuous dynamics of its own for an importer \
                 to integrate: its pedestal signal is impulse responses registered pass by pass \
                 on the way to each output; use it in Co-Simulation, or the quasi-static, \
                 lumped, reduced or full level in Model Exchange"
                    .into(),
            ));
        }
        // The FMU declares a fixed number of states and indicators per bearing.
        let (nx, ni) = model_exchange_capacity(self.bearing.z);
        let (n, m) = (self.state_dim(), self.n_event_functions());
        if n > nx || m > ni {
            return Err(SimError::Unsupported(format!(
                "this scene has {n} continuous states and {m} event indicators at the {} level, \
                 more than the {nx} and {ni} a Model Exchange FMU of this bearing declares (its \
                 full level with the cage and one spall): each further raceway spall adds {} \
                 indicators, each spall on a ball 3 states and {} indicators at the reduced and \
                 full levels, ball waviness 3 states per ball there; use Co-Simulation for this \
                 scene, or Model Exchange with one raceway spall",
                self.scene.fidelity.name(),
                3 * self.bearing.z,
                6 * self.bearing.z
            )));
        }
        if self.scene.coupling == CouplingMode::Motion && self.model.ring_states().is_none() {
            return Err(SimError::Unsupported(
                "coupling mode motion in Model Exchange needs a level whose inner ring is a \
                 dynamic body (lumped, reduced or full: the journal inputs take the ring's \
                 states); at the quasi-static level the reaction is an algebraic solve per \
                 journal position: use it in Co-Simulation, or couple by force"
                    .into(),
            ));
        }
        Ok(())
    }

    /// Model Exchange in coupling mode motion: the ring's six states hold the journal inputs
    /// (written here and by [`Simulation::set_state`], whatever the importer writes there;
    /// their derivatives are 0). The discrete mode stays frozen until the next
    /// [`Simulation::event_update`]; a journal that switches a contact is an event the
    /// indicators show. No allocation.
    pub fn set_journal_continuous(&mut self, j: Journal) -> Result<(), SimError> {
        if self.scene.coupling != CouplingMode::Motion {
            return Err(SimError::Unsupported(
                "the journal motion is an input in coupling mode 'motion' only (this simulation couples by force)".into(),
            ));
        }
        j.check()?;
        self.start.undoable = false;
        self.journal = j;
        self.journal_t = self.integrator.t();
        self.journal_into_ring();
        Ok(())
    }

    /// Model Exchange, motion mode on a level with ring states: writes the journal inputs into
    /// the ring's position and velocity states (a no-op otherwise).
    fn journal_into_ring(&mut self) {
        if self.scene.coupling != CouplingMode::Motion {
            return;
        }
        let Some(rs) = self.model.ring_states() else {
            return;
        };
        let t = self.integrator.t();
        let j = self.journal;
        let n = self.state_with_journal(rs, &j);
        self.integrator.set_state(t, &self.y_scratch[..n]);
    }

    /// The current state with the ring's position and velocity states replaced by the
    /// journal's, in `y_scratch`; returns its length.
    fn state_with_journal(&mut self, rs: crate::models::RingStates, j: &Journal) -> usize {
        let n = self.model.dim();
        self.y_scratch[..n].copy_from_slice(self.integrator.y());
        for k in 0..3 {
            self.y_scratch[rs.pos[k]] = j.x[k];
            self.y_scratch[rs.vel[k]] = j.v[k];
        }
        n
    }

    /// Number of continuous states of the level (the importer's vector may be longer: see
    /// [`model_exchange_capacity`]).
    pub fn state_dim(&self) -> usize {
        self.model.dim()
    }

    /// Number of event functions of the level.
    pub fn n_event_functions(&self) -> usize {
        self.model.n_events()
    }

    /// The continuous state at [`Simulation::time`].
    pub fn state(&self) -> &[f64] {
        self.integrator.y()
    }

    /// Sets the time and the continuous state (`y` of length [`Simulation::state_dim`], finite)
    /// at which the next evaluations are made. The discrete mode stays as it is.
    /// In coupling mode motion the ring's states keep the journal inputs.
    pub fn set_state(&mut self, t: f64, y: &[f64]) -> Result<(), SimError> {
        self.start.undoable = false;
        self.integrator
            .try_set_state(t, y)
            .map_err(|e| SimError::Input(format!("continuous states: {e}")))?;
        self.journal_t = t;
        self.journal_into_ring();
        Ok(())
    }

    /// Sets the time of the next evaluations (the state is kept).
    pub fn set_time(&mut self, t: f64) -> Result<(), SimError> {
        if !t.is_finite() {
            return Err(SimError::Input(format!("time {t} is not finite")));
        }
        self.start.undoable = false;
        let n = self.model.dim();
        self.y_scratch[..n].copy_from_slice(self.integrator.y());
        self.integrator.set_state(t, &self.y_scratch[..n]);
        Ok(())
    }

    /// The derivatives of the state at the current time, state and inputs in the frozen mode
    /// (`dydt` of length [`Simulation::state_dim`]). No allocation.
    /// In coupling mode motion the ring's states are the journal inputs: their derivatives are 0.
    pub fn derivatives(&mut self, dydt: &mut [f64]) {
        let t = self.integrator.t();
        self.model.rhs(t, self.integrator.y(), dydt);
        if self.scene.coupling == CouplingMode::Motion {
            if let Some(rs) = self.model.ring_states() {
                for k in 0..3 {
                    dydt[rs.pos[k]] = 0.0;
                    dydt[rs.vel[k]] = 0.0;
                }
            }
        }
    }

    /// The event functions at the current time and state (`g` of length
    /// [`Simulation::n_event_functions`]): a sign change is an event.
    pub fn event_functions(&mut self, g: &mut [f64]) {
        let t = self.integrator.t();
        self.model.events(t, self.integrator.y(), g);
    }

    /// Nominal magnitudes of the states (the absolute tolerance is rtol × nominal).
    pub fn nominals(&self, out: &mut [f64]) {
        self.model.nominal(out);
    }

    /// The next known discontinuity strictly after the current time (a time event), from the
    /// current state and inputs.
    pub fn next_time_event(&self) -> Option<f64> {
        self.model
            .next_stop(self.integrator.t(), self.integrator.y(), f64::INFINITY)
    }

    /// The event functions a hair ahead of the current point along the motion (`t + δ`, `y +
    /// δ y'` in the frozen mode, δ = [`EVENT_HAIR`] (1 + |t|)): at a located root the importer's
    /// state sits near 0 on either side (its location tolerance and integration error), and the
    /// sign a hair ahead is the side the trajectory goes to.
    fn events_ahead(&mut self, g: &mut [f64]) {
        let n = self.model.dim();
        let t = self.integrator.t();
        let dt = EVENT_HAIR * (1.0 + t.abs());
        let mut f = vec![0.0; n];
        self.model.rhs(t, self.integrator.y(), &mut f);
        let y: Vec<f64> = self
            .integrator
            .y()
            .iter()
            .zip(&f)
            .map(|(y, f)| y + dt * f)
            .collect();
        self.model.events(t + dt, &y, g);
    }

    /// Takes the event functions a hair ahead of the current state (after the mode was
    /// re-derived) as the reference of the next sign changes.
    fn me_reference(&mut self) {
        let ne = self.model.n_events();
        let mut g = std::mem::take(&mut self.me.g_ref);
        g.resize(ne, 0.0);
        self.events_ahead(&mut g);
        self.me.g_ref = g;
        self.me.fired.clear();
        self.me.fired.resize(ne, false);
    }

    /// Notes the sign changes of the event functions (at the current state, or `ahead`) since
    /// the reference, and takes those values as the new reference; true if any changed.
    fn me_note_crossings(&mut self, ahead: bool) -> bool {
        let ne = self.model.n_events();
        if self.me.g_ref.len() != ne {
            self.me_reference();
            return false;
        }
        let mut g = vec![0.0; ne];
        if ahead {
            self.events_ahead(&mut g);
        } else {
            self.event_functions(&mut g);
        }
        let mut any = false;
        for ((r, &now), fired) in self.me.g_ref.iter_mut().zip(&g).zip(&mut self.me.fired) {
            if (*r > 0.0) != (now > 0.0) {
                *fired = true;
                any = true;
            }
            *r = now;
        }
        any
    }

    /// The importer accepted a step at the current time and state: the event functions that
    /// changed sign since the last step are noted as fired (the importer may not have located
    /// the root itself); true if any did, i.e. an event is due.
    pub fn step_completed(&mut self) -> bool {
        self.me_note_crossings(false)
    }

    /// The event update at the current time and state (a located state event, a time event,
    /// or inputs that changed the discrete state): the event functions that changed sign since
    /// the last reference, at the state or a hair ahead of it (a root located on the old side
    /// by round-off still fires: the importer does not say which function it located), are
    /// reported fired ([`Model::event_fired`]), the discrete mode is re-derived
    /// ([`Model::update_mode`]), and the contacts are checked against the pressure limits.
    /// Returns the indices that fired.
    pub fn event_update(&mut self) -> Result<Vec<usize>, SimError> {
        self.me_note_crossings(true);
        let fired: Vec<usize> = (0..self.me.fired.len())
            .filter(|&i| self.me.fired[i])
            .collect();
        for &i in &fired {
            self.model.event_fired(i);
        }
        // Motion mode: the cage speed follows a shaft speed that has moved far enough.
        self.update_l1_point()?;
        let t = self.integrator.t();
        self.model.update_mode(t, self.integrator.y());
        self.integrator.discontinuity();
        self.me_reference();
        self.start.undoable = false;
        let inputs = self.inputs;
        self.check_contacts(|| crate::models::operating_point(&inputs))?;
        Ok(fired)
    }

    /// Model Exchange in continuous-time mode: the new inputs act on the derivatives from now
    /// on, but the discrete mode stays frozen until the next [`Simulation::event_update`].
    /// Returns true when the change needs an event: the level re-solved its quasi-static
    /// operating point (a discrete change of its cage speed) or the shaft speed changed (the
    /// time events were predicted at the old speed). Loads that move within the level's
    /// re-solve threshold need none. The same checks as [`Simulation::set_inputs`] (in motion
    /// mode the loads act only at the start, as there); on an error nothing changes.
    pub fn set_inputs_continuous(&mut self, inputs: OperatingPoint) -> Result<bool, SimError> {
        inputs.check().map_err(SimError::Input)?;
        if inputs == self.inputs {
            return Ok(false);
        }
        let located = self.scene.mounting.axial == crate::scene::AxialMount::Located;
        if located && inputs.fx != self.inputs.fx {
            return Err(SimError::Input(format!(
                "load.Fx = {} N cannot act on an axially located inner ring (it sets the ring's \
                 axial place only at the start, {} N there)",
                inputs.fx, self.inputs.fx
            )));
        }
        if self.scene.coupling == CouplingMode::Force {
            self.limits.loads(&inputs, located)?;
        }
        self.start.undoable = false;
        let before = self.model.discrete_state();
        let t = self.integrator.t();
        let (eff, _) = self.effective_inputs(&inputs, t)?;
        self.model.set_inputs(&eff, t, self.integrator.y())?;
        let speed_changed = inputs.shaft_speed != self.inputs.shaft_speed;
        self.inputs = inputs;
        Ok(speed_changed || self.model.discrete_state() != before)
    }

    /// Model Exchange in event mode (or at initialization): [`Simulation::set_inputs`], then the
    /// event functions at the new mode become the reference of the next sign changes.
    pub fn set_inputs_at_event(&mut self, inputs: OperatingPoint) -> Result<(), SimError> {
        self.set_inputs(inputs)?;
        self.me_reference();
        Ok(())
    }

    /// Model Exchange: the start of the importer's integration (after initialization): the
    /// event functions at the initial state become the reference of the first sign changes.
    pub fn begin_model_exchange(&mut self) -> Result<(), SimError> {
        self.model_exchange_check()?;
        self.me_reference();
        Ok(())
    }
}

/// Overrides ring, pedestal and bearing-force outputs with the displacement-controlled
/// quasi-static reaction at journal displacement `x` (L0/L1 in coupling mode "motion").
fn qs_motion_outputs(
    qs: &mut QsMotion,
    bearing: &Bearing,
    speed: f64,
    x: [f64; 3],
    o: &mut [f64],
) -> Result<(), SimError> {
    let applied = qs.applied_load;
    let r = qs.solve(speed, x)?;
    let p = &bearing.file.pedestal;
    // The level placed the pedestal at (the load it runs on)/k_p: move it to this solution's.
    o[out::PEDESTAL_Y] += r.pedestal[0] - applied[1] / p.k_y;
    o[out::PEDESTAL_Z] += r.pedestal[1] - applied[2] / p.k_z;
    o[out::RING_X] = x[0];
    o[out::RING_Y] = x[1];
    o[out::RING_Z] = x[2];
    o[out::BEARING_F_X] = -r.load[0];
    o[out::BEARING_F_Y] = -r.load[1];
    o[out::BEARING_F_Z] = -r.load[2];
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn snapshot_numbers_round_trip_exactly_through_json() {
        // Snapshots (save_state, fmi2SerializeFMUstate) are JSON: every f64 must come back with
        // the same bits, or a restored run drifts from the original in the last digits.
        // serde_json's default parser is off by an ulp for some values; the crate is built
        // with its `float_roundtrip` feature. 200 000 pseudo-random finite doubles of all
        // magnitudes, plus values from the model's range.
        let mut s = 0x2545_F491_4F6C_DD1D_u64;
        let mut values = vec![70.42241863912_f64, 0.42680253412, 1.0 / 3.0, 2.0e-5 / 7.0];
        while values.len() < 200_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let v = f64::from_bits(s);
            if v.is_finite() {
                values.push(v);
            }
        }
        let text = serde_json::to_string(&values).unwrap();
        let back: Vec<f64> = serde_json::from_str(&text).unwrap();
        let bad = values
            .iter()
            .zip(&back)
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(
            bad,
            0,
            "{bad} of {} values changed in the round trip",
            values.len()
        );
    }

    #[test]
    fn every_simulation_integrates_with_the_zeno_guard_on() {
        // The guard is off in the solver by default; the simulation turns it on for every level
        // (docs/research/step-control.md): 50 events in a row, each within 3 steps, within 10 ns.
        for level in ["kinematic", "lumped", "reduced", "full"] {
            let text = crate::DEFAULT_SCENE
                .replace("fidelity = \"lumped\"", &format!("fidelity = \"{level}\""));
            assert!(text.contains(&format!("fidelity = \"{level}\"")));
            let scene = crate::Scene::from_toml_str(&text, "test", None).unwrap();
            let sim = super::Simulation::new(&scene).unwrap();
            let o = super::Simulation::options(&scene, sim.model.as_ref());
            assert_eq!(o.chatter_events, 50, "{level}");
            assert_eq!(o.chatter_steps, 3, "{level}");
            assert_eq!(o.chatter_span, 1e-8, "{level}");
        }
    }

    #[test]
    fn the_lumped_models_events_are_named_by_ball_from_one() {
        let sim = super::Simulation::new(&crate::Scene::default_scene()).unwrap();
        assert_eq!(sim.model.event_name(0), "the contact of ball 1");
        assert_eq!(sim.model.event_name(13), "the contact of ball 14");
    }

    #[test]
    fn a_spall_on_a_ball_at_the_ball_levels_has_named_direction_states_and_events() {
        // An outer-race spall and a spall on ball 3: at the full level (14 balls, cage) the
        // states are the 148 of docs/model.md#state and 3 for the spall's direction; the events
        // 2·14 contacts, then 3·14 per spall slot: the raceway spall's, then the ball spall's
        // at its outer and at its inner contact.
        let text = r#"
name = "mixed"
bearing = "niu2014-table1"
fidelity = "full"
[operating]
speed_rpm = 9900.0
fa = 4000.0
fr = 1000.0
[[defect]]
ring = "outer"
width = 1.0e-3
depth = 0.2e-3
theta0 = 3.1416
[[defect]]
ring = "ball"
ball = 3
width = 1.0e-3
depth = 0.2e-3
"#;
        let sc = crate::Scene::from_toml_str(text, "mixed", None).unwrap();
        let sim = super::Simulation::new(&sc).unwrap();
        let m = &sim.model;
        assert_eq!(m.dim(), 148 + 3);
        assert_eq!(
            m.state_name(148),
            "direction of spall 1 on ball 3 (x component)"
        );
        assert_eq!(
            m.state_name(150),
            "direction of spall 1 on ball 3 (z component)"
        );
        assert_eq!(m.n_events(), 28 + 3 * 42);
        assert_eq!(m.event_name(28), "ball 1 at the edge of spall 1");
        assert_eq!(
            m.event_name(28 + 42 + 2 * 2),
            "the edge of ball spall 1 (on ball 3) at its outer contact"
        );
        assert_eq!(
            m.event_name(28 + 84 + 2 * 2 + 1),
            "the centre of ball spall 1 (on ball 3) at its inner contact"
        );
        assert_eq!(
            m.event_name(28 + 84 + 28 + 2),
            "the blend of ball spall 1 (on ball 3) at its inner contact"
        );
        // The direction starts as a unit vector.
        let y = sim.state();
        let u = &y[148..151];
        assert!(
            (u.iter().map(|v| v * v).sum::<f64>() - 1.0).abs() < 1e-12,
            "{u:?}"
        );
        // Ball waviness adds a reference direction per ball after the spall's, at the reduced
        // level too (its 110 + 6 states with the cage, docs/model.md#l3).
        let mut sc = sc;
        sc.waviness = Some(crate::WavinessSpec {
            ball: vec![crate::Harmonic(2.0, 1e-7, 0.0)],
            ..Default::default()
        });
        for (fidelity, base) in [
            (crate::Fidelity::Full, 148 + 3),
            (crate::Fidelity::Reduced, 116 + 3),
        ] {
            sc.fidelity = fidelity;
            let sim = super::Simulation::new(&sc).unwrap();
            let m = &sim.model;
            assert_eq!(m.dim(), base + 3 * 14);
            assert_eq!(
                m.state_name(base + 3),
                "reference direction on ball 2 (x component)"
            );
            assert_eq!(
                m.state_name(base - 1),
                "direction of spall 1 on ball 3 (z component)"
            );
            for j in 0..14 {
                let u = &sim.state()[base + 3 * j..base + 3 * j + 3];
                assert!((u.iter().map(|v| v * v).sum::<f64>() - 1.0).abs() < 1e-12);
            }
        }
    }
}
