//! The BallBearing model behind the generic shell: a [`Scene`] edited by the parameters until
//! `fmi2ExitInitializationMode`, then a [`Simulation`] stepped by `fmi2DoStep`.
//! No physics here: everything is delegated to [`Simulation`].

use crate::base::Base;
use crate::variables::{journal_get, journal_set, params, table_for, Access, Config, ROWS};
use fmi2::codec::{ByteReader, ByteWriter};
use fmi2::{
    EventUpdate, FmuModel, InstantiateArgs, Interface, Logger, StepEnd, StepResult, Variable,
    LOG_EVENTS, LOG_SOLVER,
};
use raceway::{
    out, BearingFile, CouplingMode, Journal, OperatingPoint, RingLoad, Scene, SimError, Simulation,
};
use std::path::Path;

/// Name of the bearing description inside the FMU's `resources/`.
pub const BEARING_RESOURCE: &str = "bearing.toml";

/// Version of the model part of the serialized FMU state.
// 3: the operating point in SI units (shaft speed in rad/s, force components).
// 4: the transmission-line inputs and the line's force at the start.
// 5: Model Exchange's mode flags (continuous-time mode, an event asked for by an input).
// 6: the parameters of spalls 2-4 (defect2.* … defect4.*).
const MODEL_STATE_VERSION: u32 = 6;

/// Reads `resources/bearing.toml`, or the default preset when there is none.
pub fn load_bearing(resource_dir: Option<&Path>) -> Result<(BearingFile, String), String> {
    if let Some(dir) = resource_dir {
        let p = dir.join(BEARING_RESOURCE);
        if p.is_file() {
            let text = std::fs::read_to_string(&p)
                .map_err(|e| format!("cannot read {}: {e}", p.display()))?;
            let b = BearingFile::from_toml_str(&text, &p.display().to_string())
                .map_err(|e| format!("invalid bearing file {}: {e}", p.display()))?;
            return Ok((b, p.display().to_string()));
        }
    }
    Ok((
        BearingFile::default_preset(),
        format!(
            "built-in preset '{}' (no {BEARING_RESOURCE} in the resources)",
            raceway::DEFAULT_PRESET
        ),
    ))
}

/// The live simulation and the exact scene it was built from.
struct Live {
    sim: Simulation,
    scene: Scene,
    /// Coupling mode tlm: the line's force on the journal (y, z) at the start, part of the
    /// scene's operating point (so the start is the equilibrium with it); the ring load of
    /// each step is the line's force less this.
    line_offset: [f64; 2],
}

/// What a multi-value `fmi2Set*` call may change, recorded before it (see
/// [`FmuModel::begin_set`]).
pub struct SetUndo {
    /// The configuration, if the call sets a parameter.
    cfg: Option<Config>,
    inputs: OperatingPoint,
    journal: Journal,
    journal_set: bool,
    loads_set_running: bool,
    journal_by_master: bool,
    line: [f64; 5],
    line_by_master: bool,
    me_input_event: bool,
    /// The live simulation's state, if the call sets two or more values that reach it (each
    /// input reaches it as it is set, as before this call-level undo existed).
    sim: Option<Vec<u8>>,
}

/// The BallBearing FMU model.
pub struct BallBearing {
    guid: String,
    vars: Vec<Variable>,
    roles: Vec<Access>,
    /// The configuration as instantiated (for fmi2Reset).
    initial: Config,
    cfg: Config,
    inputs: OperatingPoint,
    /// Journal inputs (coupling mode "motion") and whether the master has set any of them; if
    /// not, the journal starts at the static equilibrium of the L1 start, at rest.
    journal: Journal,
    journal_set: bool,
    /// The master has set a load input after initialization (ignored in coupling mode motion).
    loads_set_running: bool,
    /// The master has set a journal input (ignored in coupling mode force).
    journal_by_master: bool,
    /// Transmission-line inputs (coupling mode tlm): wave at the step's start (y, z), at its
    /// end (y, z), impedance; see [`Access::Line`].
    line: [f64; 5],
    /// The master has set a transmission-line input (ignored outside coupling mode tlm).
    line_by_master: bool,
    /// Which ignored inputs have been reported (loads in motion mode, journal in force and tlm
    /// mode, the line outside tlm mode): each once per instance, at warning level.
    ignored_reported: [bool; 3],
    /// Coupling mode motion: the largest communication step at which value exchange with a
    /// constant input over the step is stable on the bearing's own damping, 2c/k (from the
    /// reaction's stiffness k and damping c at the start), and whether a longer step has
    /// been reported.
    stable_step: Option<f64>,
    stable_step_reported: bool,
    start_time: f64,
    tolerance: Option<f64>,
    initialized: bool,
    live: Option<Live>,
    /// The last simulation built, as built, and its scene ([`BallBearing::new_simulation`]).
    fresh: Option<(Scene, Simulation)>,
    /// The outputs at the simulation's current time when `outputs_valid` (computed on demand,
    /// and by every successful step). A failed step leaves them (and the simulation) at its
    /// start, the last successful communication point.
    outputs: Vec<f64>,
    outputs_valid: bool,
    /// Where a step computes the outputs at its end before it accepts them.
    step_outputs: Vec<f64>,
    /// The interface of the instance (`fmuType`).
    interface: Interface,
    /// Model Exchange: the numbers of continuous states and event indicators the model
    /// description declares (the most of any level on this bearing; see
    /// [`raceway::model_exchange_capacity`]).
    me_nx: usize,
    me_ni: usize,
    /// Model Exchange: in continuous-time mode (inputs then act without changing the discrete
    /// mode), and whether an input set there needs an event (asked for at the next completed
    /// integrator step).
    me_continuous: bool,
    me_input_event: bool,
}

/// `inputs` plus the line's force at the start (y, z), as the model runs on them in coupling
/// mode tlm (zero offset otherwise).
fn with_line_offset(inputs: OperatingPoint, offset: [f64; 2]) -> OperatingPoint {
    OperatingPoint {
        fy: inputs.fy + offset[0],
        fz: inputs.fz + offset[1],
        ..inputs
    }
}

fn sim_err(e: SimError) -> String {
    e.to_string()
}

impl BallBearing {
    /// A model for `bearing` without a scene resource.
    pub fn new(bearing: &BearingFile) -> Self {
        Self::from_base(&Base::default_for(bearing))
    }

    /// A model made from `base` (what fmi2Instantiate builds after reading the resources).
    pub fn from_base(base: &Base) -> Self {
        let bearing = base.bearing();
        let entries = table_for(&base.scene);
        let guid = crate::description::guid_for(base);
        let cfg = Config::from_scene(&base.scene);
        let inputs = cfg.scene.operating;
        let n_out = entries
            .iter()
            .filter(|e| matches!(e.role, Access::Output(_)))
            .count();
        let (me_nx, me_ni) = raceway::model_exchange_capacity(bearing.bearing.z as usize);
        Self {
            guid,
            vars: entries.iter().map(|e| e.var.clone()).collect(),
            roles: entries.iter().map(|e| e.role).collect(),
            initial: cfg.clone(),
            cfg,
            inputs,
            journal: Journal::default(),
            journal_set: false,
            loads_set_running: false,
            journal_by_master: false,
            line: [0.0; 5],
            line_by_master: false,
            ignored_reported: [false; 3],
            stable_step: None,
            stable_step_reported: false,
            start_time: 0.0,
            tolerance: None,
            initialized: false,
            live: None,
            fresh: None,
            outputs: vec![0.0; n_out],
            outputs_valid: false,
            step_outputs: vec![0.0; n_out],
            interface: Interface::CoSimulation,
            me_nx,
            me_ni,
            me_continuous: false,
            me_input_event: false,
        }
    }

    /// Model Exchange: the live simulation (after initialization; before it, the provisional
    /// one that answers queries in initialization mode).
    fn me_live(&mut self) -> Result<&mut Live, String> {
        self.ensure_live()
    }

    /// Inputs the master has set that `coupling` ignores, each kind reported once per instance:
    /// the journal in force mode (the loads drive the inner ring), the loads after
    /// initialization in motion mode (they act only at the start's equilibrium).
    fn ignored_inputs(&mut self, coupling: CouplingMode) -> Vec<String> {
        let mut notes = Vec::new();
        let mode = if self.cfg.tlm {
            "tlm (coupling = 2"
        } else {
            "force (coupling = 0"
        };
        if coupling == CouplingMode::Force && self.journal_by_master && !self.ignored_reported[1] {
            self.ignored_reported[1] = true;
            notes.push(format!(
                "the journal.* inputs are set but ignored in coupling mode {mode}: the load.F* \
                 inputs act on the inner ring, which the bearing integrates); set coupling = 1 \
                 (motion) to drive the journal"
            ));
        }
        if !self.cfg.tlm && self.line_by_master && !self.ignored_reported[2] {
            self.ignored_reported[2] = true;
            notes.push(
                "the tlm.* inputs are set but ignored outside coupling mode tlm; set coupling = \
                 2 to couple through the transmission line"
                    .to_string(),
            );
        }
        if coupling == CouplingMode::Motion && self.loads_set_running && !self.ignored_reported[0] {
            self.ignored_reported[0] = true;
            notes.push(
                "the load.F* inputs are set after initialization but ignored in coupling mode \
                 motion (coupling = 1: the journal.* inputs move the inner ring; the loads act \
                 only at the start's equilibrium); set coupling = 0 (force) to apply loads"
                    .to_string(),
            );
        }
        notes
    }

    /// The scene the simulation is built from: parameters, spalls, tolerance override and the
    /// current inputs as the operating point (so the initial state is the equilibrium at the
    /// inputs). Validated, with errors naming the FMU variable.
    fn scene_to_build(&self) -> Result<Scene, String> {
        let mut s = self.cfg.scene_with_spalls();
        if let Some(t) = self.tolerance {
            if !(raceway::MIN_RTOL..0.1).contains(&t) {
                return Err(format!(
                    "the tolerance {t:e} of fmi2SetupExperiment is outside [{:e}, 0.1) (it overrides solver.rtol)",
                    raceway::MIN_RTOL
                ));
            }
            s.solver.rtol = t;
        }
        s.operating = self.model_inputs(self.start_line_offset());
        self.inputs
            .check()
            .map_err(|m| sim_err(SimError::Input(m)))?;
        s.bearing.validate().map_err(|e| e.to_string())?;
        s.validate()
            .map_err(|e| self.cfg.name_spalls(&e.to_string()))?;
        Ok(s)
    }

    /// The line's force on the journal (y, z) at rest, from the line inputs as they are now
    /// (coupling mode tlm; zero otherwise): the start's equilibrium carries it.
    fn start_line_offset(&self) -> [f64; 2] {
        if self.cfg.tlm {
            [self.line[2], self.line[3]]
        } else {
            [0.0; 2]
        }
    }

    /// The operating point the model runs on: the inputs plus, in coupling mode tlm, the
    /// line's force at the start (`offset`).
    fn model_inputs(&self, offset: [f64; 2]) -> OperatingPoint {
        with_line_offset(self.inputs, offset)
    }

    /// `Simulation::new(scene)`, copied from the one kept when it was last made for the same
    /// scene: restoring a state (fmi2SetFMUstate, often once per step for a master that
    /// retries steps) then costs a copy instead of building the model again (the lumped
    /// level's build solves the quasi-static operating point and the cage speed).
    fn new_simulation(&mut self, scene: &Scene) -> Result<Simulation, String> {
        if let Some((kept, sim)) = &self.fresh {
            if kept == scene {
                return Ok(sim.clone());
            }
        }
        let sim = Simulation::new(scene).map_err(|e| self.cfg.name_spalls(&sim_err(e)))?;
        self.fresh = Some((scene.clone(), sim.clone()));
        Ok(sim)
    }

    fn build(&mut self) -> Result<Live, String> {
        let scene = self.scene_to_build()?;
        let line_offset = self.start_line_offset();
        let mut sim = self.new_simulation(&scene)?;
        sim.set_inputs(self.model_inputs(line_offset))
            .map_err(sim_err)?;
        if scene.coupling == CouplingMode::Motion && self.journal_set {
            sim.set_journal(self.journal).map_err(sim_err)?;
        }
        if self.cfg.tlm {
            // Refused on a level without a dynamic ring: the journal's mass lives in the ring.
            sim.set_ring_load(None)
                .map_err(|e| format!("coupling = 2 (tlm): {}", sim_err(e)))?;
        }
        Ok(Live {
            sim,
            scene,
            line_offset,
        })
    }

    /// Coupling mode motion: the first communication step longer than the stable one of value
    /// exchange (see `stable_step`) is reported, once.
    fn step_size_warning(&mut self, h: f64) -> Vec<String> {
        match self.stable_step {
            Some(hs) if h > hs && !self.stable_step_reported => {
                self.stable_step_reported = true;
                vec![format!(
                    "the communication step {h:e} s is longer than {hs:e} s, the largest at which \
                     value exchange (the force held over the step, as fmpy and libcosim do) is \
                     stable on the bearing's own damping (2c/k, see the log at initialization): \
                     unless the partner damps the journal or applies the interface Jacobian, \
                     the coupling will run away; shorten the step or couple through the \
                     transmission line (coupling = 2 with the JeffcottRotor), which is stable at \
                     any step"
                )]
            }
            _ => Vec::new(),
        }
    }

    /// What fmi2ExitInitializationMode says about the coupling in use: in motion mode the
    /// largest stable step of value exchange (it also sets `stable_step`), in tlm mode the
    /// line. `None` in force mode.
    fn coupling_note(&mut self) -> Option<String> {
        let live = self.live.as_mut()?;
        if self.cfg.tlm {
            return Some(format!(
                "coupling tlm: the transmission line's force acts on the inner ring (impedance \
                 tlm.Zc = {} N s/m now, the line's force at rest ({}, {}) N in the start's \
                 equilibrium); the line is passive, so the coupling is stable at any \
                 communication step; its accuracy is set by the line's delay, which the \
                 JeffcottRotor checks and logs",
                self.line[4], live.line_offset[0], live.line_offset[1]
            ));
        }
        if live.scene.coupling != CouplingMode::Motion {
            return None;
        }
        let jac = match live.sim.reaction_jacobian() {
            Ok(j) => j,
            Err(e) => return Some(format!("coupling motion: no stable-step estimate ({e})")),
        };
        let mut h_min = f64::INFINITY;
        let mut parts = Vec::new();
        for (lim, axis) in jac.exchange_limits().into_iter().zip(["x", "y", "z"]) {
            if let Some(l) = lim {
                h_min = h_min.min(l.step);
                parts.push(format!(
                    "{axis}: k = {:.4e} N/m, c = {:.4} N s/m, 2c/k = {:.3e} s",
                    l.k, l.c, l.step
                ));
            }
        }
        if !h_min.is_finite() {
            return Some(
                "coupling motion: the bearing has no stiffness against the journal at the start"
                    .into(),
            );
        }
        self.stable_step = Some(h_min);
        Some(format!(
            "coupling motion: value exchange with the force held over the communication step is \
             stable for H < 2c/k = {h_min:.3e} s on the bearing's own damping, whatever the \
             journal's mass ({}); the partner's damping on the journal adds to c; the \
             transmission-line coupling (coupling = 2 with the JeffcottRotor) is stable at any step",
            parts.join("; ")
        ))
    }

    /// The line's force law over the step from `t` to `t_end` (simulation time), less the
    /// start's part that the operating point carries.
    fn line_law(&self, t: f64, t_end: f64, offset: [f64; 2]) -> Result<RingLoad, String> {
        let [c0y, c0z, c1y, c1z, zc] = self.line;
        RingLoad::linear(
            t,
            t_end - t,
            [0.0, c0y - offset[0], c0z - offset[1]],
            [0.0, c1y - offset[0], c1z - offset[1]],
            [0.0, zc, zc],
        )
    }

    /// The journal the model uses: the one set, or (motion mode, none set) the start's.
    fn journal_now(&self) -> Journal {
        match &self.live {
            Some(l) if !self.journal_set && l.scene.coupling == CouplingMode::Motion => {
                l.sim.journal()
            }
            _ => self.journal,
        }
    }

    fn ensure_live(&mut self) -> Result<&mut Live, String> {
        if self.live.is_none() {
            self.live = Some(self.build()?);
            self.outputs_valid = false;
        }
        Ok(self.live.as_mut().expect("just built"))
    }

    fn refresh_outputs(&mut self) -> Result<(), String> {
        if !self.outputs_valid {
            let mut out = std::mem::take(&mut self.outputs);
            let r = self
                .ensure_live()
                .and_then(|l| l.sim.try_outputs(&mut out).map_err(sim_err));
            self.outputs = out;
            r?;
            self.outputs_valid = true;
        }
        Ok(())
    }

    /// Before initialization a change of a parameter or input invalidates the provisional
    /// simulation (built only to answer output queries in initialization mode).
    fn invalidate(&mut self) {
        if !self.initialized {
            self.live = None;
        }
        self.outputs_valid = false;
    }
}

impl FmuModel for BallBearing {
    const MODEL_IDENTIFIER: &'static str = "BallBearing";

    fn instantiate(args: &InstantiateArgs, log: &Logger) -> Result<Self, String> {
        let (bearing, origin) = load_bearing(args.resource_dir.as_deref())?;
        let base = crate::base::load_scene(args.resource_dir.as_deref(), &bearing)?;
        if log.enabled(LOG_EVENTS) {
            let scene = match &base.scene_digest {
                Some(_) => format!(
                    "base scene '{}' ({} spalls) from resources/{}",
                    base.scene.name,
                    base.scene.n_defects(),
                    crate::base::SCENE_RESOURCE
                ),
                None => "the default scene (no scene resource)".into(),
            };
            log.log(
                fmi2::bindings::Fmi2Status::Ok,
                LOG_EVENTS,
                &format!(
                    "bearing '{}' ({} balls) from {origin}; {scene}",
                    bearing.name, bearing.bearing.z
                ),
            );
        }
        let mut m = Self::from_base(&base);
        m.interface = args.interface;
        Ok(m)
    }

    fn guid(&self) -> &str {
        &self.guid
    }

    fn variables(&self) -> &[Variable] {
        &self.vars
    }

    fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start_time: f64,
        _stop_time: Option<f64>,
    ) -> Result<(), String> {
        if let Some(t) = tolerance {
            if !(raceway::MIN_RTOL..0.1).contains(&t) {
                return Err(format!(
                    "tolerance = {t:e}: the integrator's relative tolerance must lie in [{:e}, 0.1): {}",
                    raceway::MIN_RTOL,
                    raceway::RTOL_FLOOR_WHY
                ));
            }
        }
        self.tolerance = tolerance;
        self.start_time = start_time;
        self.invalidate();
        Ok(())
    }

    fn exit_initialization(&mut self, log: &Logger) -> Result<(), String> {
        if self.interface == Interface::ModelExchange && self.cfg.tlm {
            return Err(
                "Model Exchange: coupling = 2 (tlm) is refused: the transmission line exchanges \
                 waves over communication steps, a co-simulation device; in Model Exchange \
                 couple by force (coupling = 0) and let the importer integrate the bearing and \
                 its partner together"
                    .into(),
            );
        }
        // Always rebuild: the provisional simulation may predate the last parameter change.
        let mut live = self.build()?;
        if self.interface == Interface::ModelExchange {
            live.sim
                .begin_model_exchange()
                .map_err(|e| format!("Model Exchange: {}", sim_err(e)))?;
        }
        let mut warnings = live.sim.take_warnings();
        warnings.extend(self.ignored_inputs(live.scene.coupling));
        for w in warnings {
            log.log(
                fmi2::bindings::Fmi2Status::Warning,
                fmi2::LOG_STATUS_WARNING,
                &format!("fmi2ExitInitializationMode: {w}"),
            );
        }
        if log.enabled(LOG_EVENTS) {
            log.log(
                fmi2::bindings::Fmi2Status::Ok,
                LOG_EVENTS,
                &format!(
                    "initialized: fidelity {} ({}), method {}, rtol {:e}, defect {:?}, cage speed \
                     of the kinematic-ball levels {}, inner ring axially {:?}{}",
                    live.scene.fidelity.code(),
                    live.scene.fidelity.name(),
                    live.scene.solver.method.name(),
                    live.scene.solver.rtol,
                    live.scene.defect,
                    match live.scene.lumped.cage_speed {
                        raceway::CageSpeed::Traction => "the traction's caged balance",
                        raceway::CageSpeed::OuterRaceControl => "L1's outer-race control",
                    },
                    live.scene.mounting,
                    if live.scene.more_defects.is_empty() {
                        String::new()
                    } else {
                        format!(", further spalls {:?}", live.scene.more_defects)
                    }
                ),
            );
        }
        self.live = Some(live);
        self.journal = self.journal_now();
        self.journal_set = true;
        self.initialized = true;
        self.outputs_valid = false;
        self.stable_step = None;
        self.stable_step_reported = false;
        self.me_continuous = false;
        self.me_input_event = false;
        // (communication steps exist in Co-Simulation only)
        let note = match self.interface {
            Interface::CoSimulation => self.coupling_note(),
            Interface::ModelExchange => None,
        };
        if let Some(note) = note {
            if log.enabled(LOG_EVENTS) {
                log.log(fmi2::bindings::Fmi2Status::Ok, LOG_EVENTS, &note);
            }
        }
        Ok(())
    }

    /// Advances the simulation to `t_end` and computes the outputs there; the step counts only
    /// if both succeed and every output is finite. Otherwise the simulation is put back to `t`
    /// (a failed advance does that itself) and the outputs stay those of `t`: the master reads
    /// the last successful communication point, never a failed attempt.
    fn do_step(&mut self, t: f64, t_end: f64, log: &Logger) -> StepResult {
        let start = self.start_time;
        // The simulation is where the communication point says (it advanced to exactly this
        // time at the last step): not so only after a state whose parts disagree was set.
        if let Some(live) = &self.live {
            let (here, want) = (live.sim.time(), t - start);
            let off = (here - want).abs();
            if off.is_nan() || off > 1e-9 * want.abs().max(1.0) {
                return StepResult::Error(format!(
                    "the FMU state is inconsistent: the simulation is at {here} s from the \
                     start time {start} s, the communication point {t} s is {want} s from it"
                ));
            }
        }
        let law = match &self.live {
            Some(live) if self.cfg.tlm => {
                match self.line_law(t - start, t_end - start, live.line_offset) {
                    Ok(l) => Some(l),
                    Err(e) => return StepResult::Error(format!("coupling mode tlm: {e}")),
                }
            }
            _ => None,
        };
        let mut warnings = self.step_size_warning(t_end - t);
        let Some(live) = self.live.as_mut() else {
            return StepResult::Error("no simulation (internal error)".into());
        };
        if law.is_some() {
            if let Err(e) = live.sim.set_ring_load(law) {
                return StepResult::Error(e.to_string());
            }
        }
        let before = live.sim.stats();
        match live.sim.advance(t_end - start) {
            Ok(()) => {}
            Err(SimError::Solver { t: tg, message }) => {
                return StepResult::Discard {
                    message: format!("the advance stopped at t = {}: {message}", start + tg),
                    last_good_time: t,
                }
            }
            Err(e) => return StepResult::Error(e.to_string()),
        }
        // Integrator work of this step (for the solver log and the warn_steps check).
        let after = live.sim.stats();
        if log.enabled(LOG_SOLVER) {
            log.log(
                fmi2::bindings::Fmi2Status::Ok,
                LOG_SOLVER,
                &format!(
                    "t = {t} → {t_end}: {} steps, {} rejected, {} rhs evaluations",
                    after.steps - before.steps,
                    after.rejected - before.rejected,
                    after.rhs_evals - before.rhs_evals
                ),
            );
        }
        let failure = match live.sim.try_outputs(&mut self.step_outputs) {
            Err(e) => Some(StepResult::Error(format!(
                "the outputs at t = {t_end} cannot be computed: {e}"
            ))),
            Ok(()) => self
                .step_outputs
                .iter()
                .position(|v| !v.is_finite())
                .map(|i| {
                    let name = self
                        .roles
                        .iter()
                        .zip(&self.vars)
                        .find(|(r, _)| matches!(r, Access::Output(o) if *o == i))
                        .map_or("?", |(_, v)| v.name.as_str());
                    StepResult::Discard {
                        message: format!(
                            "output '{name}' became {} at t = {t_end}",
                            self.step_outputs[i]
                        ),
                        last_good_time: t,
                    }
                }),
        };
        if let Some(f) = failure {
            return match (live.sim.undo_advance(), f) {
                (Ok(()), f) => f,
                (Err(e), StepResult::Discard { message, .. } | StepResult::Error(message)) => {
                    StepResult::Error(format!("{message}; then {e}"))
                }
                (Err(e), StepResult::Ok | StepResult::Warning(_)) => {
                    StepResult::Error(e.to_string())
                }
            };
        }
        std::mem::swap(&mut self.outputs, &mut self.step_outputs);
        self.outputs_valid = true;
        // Plausibility warnings of this step and of the inputs set before it, and inputs that
        // the coupling mode ignores.
        let coupling = live.scene.coupling;
        warnings.extend(live.sim.take_warnings());
        let attempted = (after.steps + after.rejected) - (before.steps + before.rejected);
        if self.cfg.warn_steps > 0 && attempted > self.cfg.warn_steps {
            warnings.push(format!(
                "the step from t = {t} to {t_end} took {attempted} integrator steps ({} rejected), \
                 more than solver.warn_steps = {}: either the communication step is long for \
                 this level, or the dynamics became stiff, as when a coupling runs away or the \
                 inputs jump; check the coupling and the communication step",
                after.rejected - before.rejected,
                self.cfg.warn_steps
            ));
        }
        warnings.extend(self.ignored_inputs(coupling));
        if warnings.is_empty() {
            StepResult::Ok
        } else {
            StepResult::Warning(warnings)
        }
    }

    fn reset(&mut self) -> Result<(), String> {
        self.cfg = self.initial.clone();
        self.inputs = self.cfg.scene.operating;
        self.journal = Journal::default();
        self.journal_set = false;
        self.loads_set_running = false;
        self.journal_by_master = false;
        self.line = [0.0; 5];
        self.line_by_master = false;
        self.ignored_reported = [false; 3];
        self.stable_step = None;
        self.stable_step_reported = false;
        self.start_time = 0.0;
        self.tolerance = None;
        self.initialized = false;
        self.live = None;
        self.outputs_valid = false;
        self.me_continuous = false;
        self.me_input_event = false;
        Ok(())
    }

    fn get_real(&mut self, index: usize) -> Result<f64, String> {
        match self.roles[index] {
            Access::Input { get, .. } => Ok(get(&self.inputs)),
            Access::Journal(k) => {
                // Motion mode, none set yet: the start's equilibrium (builds the provisional
                // simulation in initialization mode, like an output query).
                if !self.journal_set
                    && self.cfg.scene.coupling == CouplingMode::Motion
                    && self.live.is_none()
                {
                    self.ensure_live()?;
                }
                Ok(journal_get(&self.journal_now(), k))
            }
            Access::Line(k) => Ok(self.line[k]),
            Access::RingVelocity(k) => {
                let live = self.ensure_live()?;
                Ok(live.sim.ring_velocity().map_or(0.0, |v| v[k]))
            }
            Access::Param { get, .. } => Ok(get(&self.cfg)),
            Access::Output(i) => {
                self.refresh_outputs()?;
                Ok(self.outputs[i])
            }
            Access::State(i) => {
                let live = self.ensure_live()?;
                Ok(live.sim.state().get(i).copied().unwrap_or(0.0))
            }
            Access::Derivative(i) => {
                let live = self.ensure_live()?;
                let mut d = vec![0.0; live.sim.state_dim()];
                live.sim.derivatives(&mut d);
                Ok(d.get(i).copied().unwrap_or(0.0))
            }
            Access::Stat(_) => Err("not a Real".into()),
        }
    }

    fn set_real(&mut self, index: usize, value: f64) -> Result<(), String> {
        match self.roles[index] {
            Access::Input { set, load, .. } => {
                let mut next = self.inputs;
                set(&mut next, value);
                if let Some(live) = self.live.as_mut().filter(|_| self.initialized) {
                    let model = with_line_offset(next, live.line_offset);
                    match (self.interface, self.me_continuous) {
                        (Interface::CoSimulation, _) => {
                            live.sim.set_inputs(model).map_err(sim_err)?
                        }
                        // Model Exchange, continuous-time mode: the inputs act at once, the
                        // discrete mode waits for an event (asked for when needed).
                        (Interface::ModelExchange, true) => {
                            self.me_input_event |=
                                live.sim.set_inputs_continuous(model).map_err(sim_err)?
                        }
                        (Interface::ModelExchange, false) => {
                            live.sim.set_inputs_at_event(model).map_err(sim_err)?
                        }
                    }
                } else {
                    next.check().map_err(|m| sim_err(SimError::Input(m)))?;
                }
                self.inputs = next;
                self.loads_set_running |= self.initialized && load;
                self.invalidate();
                Ok(())
            }
            Access::Journal(k) => {
                let mut next = self.journal_now();
                journal_set(&mut next, k, value);
                match self.live.as_mut().filter(|_| self.initialized) {
                    // Model Exchange: the journal acts on the derivatives at once; a contact
                    // it switches is an event the indicators show.
                    Some(live) if live.scene.coupling == CouplingMode::Motion => {
                        match self.interface {
                            Interface::ModelExchange => live.sim.set_journal_continuous(next),
                            Interface::CoSimulation => live.sim.set_journal(next),
                        }
                        .map_err(sim_err)?;
                    }
                    _ => next.check().map_err(sim_err)?,
                }
                self.journal = next;
                self.journal_set = true;
                self.journal_by_master = true;
                self.invalidate();
                Ok(())
            }
            Access::Line(k) => {
                // (the shell has refused non-finite values and a negative tlm.Zc, below its min)
                self.line[k] = value;
                self.line_by_master = true;
                self.invalidate();
                Ok(())
            }
            Access::Param { set, .. } => {
                set(&mut self.cfg, value)?;
                self.invalidate();
                Ok(())
            }
            _ => Err(format!("'{}' cannot be set", self.vars[index].name)),
        }
    }

    /// ∂(bearing.F.*, ring.*)/∂(journal.*, load.F*) in coupling mode motion: bearing.F from the
    /// level's reaction Jacobian, ring.* = journal displacement (identity), loads act only at
    /// the start (zero). Other pairs are refused with a message (their direct dependence is not
    /// linearized).
    fn directional_derivative(
        &mut self,
        unknowns: &[usize],
        knowns: &[usize],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> Result<(), String> {
        let roles = self.roles.clone();
        let names: Vec<String> = self.vars.iter().map(|v| v.name.clone()).collect();
        let live = self.ensure_live()?;
        if live.scene.coupling != CouplingMode::Motion {
            return Err(
                "directional derivatives are provided in coupling mode motion (coupling = 1): \
                 ∂bearing.F.*/∂journal.*; in force mode the outputs depend on the loads only \
                 through the state"
                    .into(),
            );
        }
        let jac = live.sim.reaction_jacobian().map_err(sim_err)?;
        for (u, &iu) in unknowns.iter().enumerate() {
            let mut acc = 0.0;
            for (&ik, &dk) in knowns.iter().zip(dv_known) {
                let row = match roles[iu] {
                    Access::Output(o) if (out::BEARING_F_X..=out::BEARING_F_Z).contains(&o) => {
                        Some((o - out::BEARING_F_X, false))
                    }
                    Access::Output(o) if (out::RING_X..=out::RING_Z).contains(&o) => {
                        Some((o - out::RING_X, true))
                    }
                    _ => None,
                };
                let d = match (row, roles[ik]) {
                    (_, Access::Input { load: true, .. }) => 0.0,
                    (Some((r, false)), Access::Journal(k)) if k < 3 => jac.dfdx[r][k],
                    (Some((r, false)), Access::Journal(k)) => jac.dfdv[r][k - 3],
                    (Some((r, true)), Access::Journal(k)) => {
                        if k == r {
                            1.0
                        } else {
                            0.0
                        }
                    }
                    _ => {
                        return Err(format!(
                            "∂{}/∂{} is not provided: directional derivatives cover bearing.F.* and ring.* with respect to journal.* and load.F*",
                            names[iu], names[ik]
                        ))
                    }
                };
                acc += d * dk;
            }
            dv_unknown[u] = acc;
        }
        Ok(())
    }

    fn get_integer(&mut self, index: usize) -> Result<i32, String> {
        match self.roles[index] {
            Access::Param { get, .. } => Ok(get(&self.cfg) as i32),
            Access::Stat(get) => {
                let st = self.ensure_live()?.sim.stats();
                let v = get(&st);
                Ok(v.min(i32::MAX as u64) as i32)
            }
            _ => Err(format!("'{}' is not an Integer", self.vars[index].name)),
        }
    }

    fn set_integer(&mut self, index: usize, value: i32) -> Result<(), String> {
        match self.roles[index] {
            Access::Param { set, .. } => {
                set(&mut self.cfg, value as f64)?;
                self.invalidate();
                Ok(())
            }
            _ => Err(format!("'{}' cannot be set", self.vars[index].name)),
        }
    }

    type Undo = SetUndo;

    fn begin_set(&self, indices: &[usize]) -> SetUndo {
        let sets_param = indices
            .iter()
            .any(|&i| matches!(self.roles[i], Access::Param { .. }));
        let reaching_sim = indices
            .iter()
            .filter(|&&i| matches!(self.roles[i], Access::Input { .. } | Access::Journal(_)))
            .count();
        let sim = match &self.live {
            Some(live) if self.initialized && reaching_sim >= 2 => Some(live.sim.save_state()),
            _ => None,
        };
        SetUndo {
            cfg: sets_param.then(|| self.cfg.clone()),
            inputs: self.inputs,
            journal: self.journal,
            journal_set: self.journal_set,
            loads_set_running: self.loads_set_running,
            journal_by_master: self.journal_by_master,
            line: self.line,
            line_by_master: self.line_by_master,
            me_input_event: self.me_input_event,
            sim,
        }
    }

    fn rollback_set(&mut self, undo: SetUndo) -> Result<(), String> {
        if let Some(cfg) = undo.cfg {
            self.cfg = cfg;
        }
        self.inputs = undo.inputs;
        self.journal = undo.journal;
        self.journal_set = undo.journal_set;
        self.loads_set_running = undo.loads_set_running;
        self.journal_by_master = undo.journal_by_master;
        self.line = undo.line;
        self.line_by_master = undo.line_by_master;
        self.me_input_event = undo.me_input_event;
        self.invalidate();
        if let (Some(bytes), Some(live)) = (undo.sim, self.live.as_mut()) {
            live.sim.restore_state(&bytes).map_err(sim_err)?;
        }
        Ok(())
    }

    fn save_state(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.u32(MODEL_STATE_VERSION).u32(params().count() as u32);
        for r in params() {
            if let Access::Param { get, .. } = r.access {
                w.f64(get(&self.cfg));
            }
        }
        for r in ROWS {
            if let Access::Input { get, .. } = r.access {
                w.f64(get(&self.inputs));
            }
        }
        for k in 0..6 {
            w.f64(journal_get(&self.journal, k));
        }
        for v in self.line {
            w.f64(v);
        }
        w.bool(self.journal_set);
        w.f64(self.start_time)
            .opt_f64(self.tolerance)
            .bool(self.initialized)
            .bool(self.me_continuous)
            .bool(self.me_input_event);
        match (&self.live, self.initialized) {
            (Some(live), true) => {
                let op = &live.scene.operating;
                w.bool(true)
                    .f64(op.shaft_speed)
                    .f64(op.fx)
                    .f64(op.fy)
                    .f64(op.fz)
                    .f64(live.scene.solver.rtol)
                    .f64(live.line_offset[0])
                    .f64(live.line_offset[1])
                    .bytes(&live.sim.save_state());
            }
            _ => {
                w.bool(false);
            }
        }
        w.into_bytes()
    }

    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let mut r = ByteReader::new(bytes);
        let v = r.u32("model state version")?;
        if v != MODEL_STATE_VERSION {
            return Err(format!(
                "BallBearing state version {v} is not supported (expected {MODEL_STATE_VERSION})"
            ));
        }
        let n = r.u32("parameter count")? as usize;
        if n != params().count() {
            return Err(format!(
                "the state has {n} parameters, this FMU {}",
                params().count()
            ));
        }
        let mut cfg = self.initial.clone();
        for row in params() {
            let x = r.f64(row.name)?;
            if let Access::Param { set, .. } = row.access {
                set(&mut cfg, x).map_err(|e| format!("corrupt state: {e}"))?;
            }
        }
        let mut inputs = self.inputs;
        for row in ROWS {
            if let Access::Input { set, .. } = row.access {
                set(&mut inputs, r.f64("input")?);
            }
        }
        let mut journal = Journal::default();
        for row in ROWS {
            if let Access::Journal(k) = row.access {
                journal_set(&mut journal, k, r.f64(row.name)?);
            }
        }
        let mut line = [0.0; 5];
        for row in ROWS {
            if let Access::Line(k) = row.access {
                line[k] = r.f64(row.name)?;
            }
        }
        let journal_set = r.bool("journal flag")?;
        let start_time = r.f64("start time")?;
        let tolerance = r.opt_f64("tolerance")?;
        let initialized = r.bool("initialized flag")?;
        let me_continuous = r.bool("continuous-time mode flag")?;
        let me_input_event = r.bool("input event flag")?;
        let live = if r.bool("simulation flag")? {
            let operating = OperatingPoint {
                shaft_speed: r.f64("operating shaft speed")?,
                fx: r.f64("operating fx")?,
                fy: r.f64("operating fy")?,
                fz: r.f64("operating fz")?,
            };
            let rtol = r.f64("rtol")?;
            let line_offset = [
                r.f64("line force y at the start")?,
                r.f64("line force z at the start")?,
            ];
            let sim_bytes = r.bytes("simulation state")?;
            r.finish("the BallBearing state")?;
            let mut scene = cfg.scene_with_spalls();
            scene.operating = operating;
            scene.solver.rtol = rtol;
            let mut sim = self.new_simulation(&scene)?;
            sim.restore_state(sim_bytes).map_err(sim_err)?;
            Some(Live {
                sim,
                scene,
                line_offset,
            })
        } else {
            r.finish("the BallBearing state")?;
            None
        };
        self.cfg = cfg;
        self.inputs = inputs;
        self.journal = journal;
        self.line = line;
        self.journal_set = journal_set;
        self.start_time = start_time;
        self.tolerance = tolerance;
        self.initialized = initialized;
        self.me_continuous = me_continuous;
        self.me_input_event = me_input_event;
        self.live = live;
        self.outputs_valid = false;
        Ok(())
    }

    const MODEL_EXCHANGE: bool = true;

    fn number_of_continuous_states(&self) -> usize {
        self.me_nx
    }

    fn number_of_event_indicators(&self) -> usize {
        self.me_ni
    }

    fn set_time(&mut self, t: f64) -> Result<(), String> {
        let start = self.start_time;
        self.me_live()?.sim.set_time(t - start).map_err(sim_err)?;
        self.outputs_valid = false;
        Ok(())
    }

    /// The level's states are the first [`raceway::Simulation::state_dim`]; the padding ones
    /// are ignored (their derivative is 0: they keep the 0 they start with).
    fn set_continuous_states(&mut self, x: &[f64]) -> Result<(), String> {
        let live = self.me_live()?;
        let (t, n) = (live.sim.time(), live.sim.state_dim());
        live.sim.set_state(t, &x[..n]).map_err(sim_err)?;
        self.outputs_valid = false;
        Ok(())
    }

    fn get_continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        let live = self.me_live()?;
        let y = live.sim.state();
        x[..y.len()].copy_from_slice(y);
        x[y.len()..].fill(0.0);
        Ok(())
    }

    fn get_derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        let live = self.me_live()?;
        let n = live.sim.state_dim();
        live.sim.derivatives(&mut dx[..n]);
        dx[n..].fill(0.0);
        Ok(())
    }

    /// The level's event functions, then constant 1.0 for the padding indicators.
    fn get_event_indicators(&mut self, g: &mut [f64]) -> Result<(), String> {
        let live = self.me_live()?;
        let n = live.sim.n_event_functions();
        live.sim.event_functions(&mut g[..n]);
        g[n..].fill(1.0);
        Ok(())
    }

    fn get_nominals(&mut self, nominal: &mut [f64]) -> Result<(), String> {
        let live = self.me_live()?;
        let n = live.sim.state_dim();
        live.sim.nominals(&mut nominal[..n]);
        nominal[n..].fill(1.0);
        Ok(())
    }

    fn enter_event_mode(&mut self) -> Result<(), String> {
        self.me_continuous = false;
        Ok(())
    }

    /// The event update: the indicators that changed sign since the last reference fire, the
    /// discrete mode is re-derived, and the next time event (a ball reaching a spall edge, a
    /// jitter revolution, a pulse kink) is predicted from the state and inputs now.
    fn new_discrete_states(&mut self, log: &Logger) -> Result<EventUpdate, String> {
        let start = self.start_time;
        let live = self.me_live()?;
        let fired = live.sim.event_update().map_err(sim_err)?;
        let t = live.sim.time();
        let next = live.sim.next_time_event().map(|tn| tn + start);
        let coupling = live.scene.coupling;
        let mut warnings = live.sim.take_warnings();
        if log.enabled(LOG_EVENTS) {
            log.log(
                fmi2::bindings::Fmi2Status::Ok,
                LOG_EVENTS,
                &format!(
                    "event update at t = {}: indicators fired {fired:?}; next time event {next:?}",
                    t + start
                ),
            );
        }
        warnings.extend(self.ignored_inputs(coupling));
        self.me_input_event = false;
        self.outputs_valid = false;
        Ok(EventUpdate {
            next_event_time: next,
            warnings,
            ..EventUpdate::default()
        })
    }

    fn enter_continuous_time_mode(&mut self) -> Result<(), String> {
        self.me_continuous = true;
        Ok(())
    }

    /// Asks for an event when an indicator changed sign over the step (the importer may not
    /// locate roots itself) or an input set in continuous-time mode needs a discrete change.
    fn completed_integrator_step(
        &mut self,
        _inputs_changed: bool,
        _log: &Logger,
    ) -> Result<StepEnd, String> {
        let live = self.me_live()?;
        let crossed = live.sim.step_completed();
        let warnings = live.sim.take_warnings();
        Ok(StepEnd {
            enter_event_mode: crossed || self.me_input_event,
            terminate_simulation: false,
            warnings,
        })
    }
}
