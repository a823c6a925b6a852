//! The interface between a dynamic model and the [`Simulation`](crate::simulation::Simulation)
//! that drives it: the [`Model`] trait (whose continuous inputs are an [`OperatingPoint`]), the
//! errors a model reports ([`SimError`]), and what motion coupling needs of a level
//! ([`RingStates`], [`ReactionJacobian`]). The output vector's layout is [`super::out`].

use crate::config::ConfigError;
use crate::operating::{OperatingPoint, RingLoad};
use std::fmt;

/// What went wrong.
#[derive(Debug, Clone, PartialEq)]
pub enum SimError {
    /// A scene or bearing value is invalid.
    Config(ConfigError),
    /// An input is invalid (named in the message).
    Input(String),
    /// An advance could not reach its end: it stopped at `t` (the last step the integrator
    /// accepted, or the time whose outputs the model could not catch up to within the step
    /// budget), for the reason in `message`. The simulation is back where the advance started
    /// ([`Simulation::time`](crate::simulation::Simulation::time)), as if it had not been asked.
    Solver {
        /// Where the advance stopped \[s\].
        t: f64,
        /// Why.
        message: String,
    },
    /// The requested feature is not available at this fidelity level.
    Unsupported(String),
    /// A saved state could not be restored.
    State(String),
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Config(e) => write!(f, "{e}"),
            SimError::Input(m) => write!(f, "invalid input: {m}"),
            SimError::Solver { t, message } => {
                write!(f, "integration failed at t = {t} s: {message}")
            }
            SimError::Unsupported(m) => write!(f, "unsupported: {m}"),
            SimError::State(m) => write!(f, "cannot restore state: {m}"),
        }
    }
}

impl std::error::Error for SimError {}

impl From<ConfigError> for SimError {
    fn from(e: ConfigError) -> Self {
        SimError::Config(e)
    }
}

/// Where a level keeps the inner ring's translation in its state vector (coupling mode
/// "motion", see [`crate::simulation::Journal`]): `pos[k]`, `vel[k]` are the indices of the
/// ring's displacement and velocity along x, y, z, in the frame and from the origin of the
/// `ring.x/y/z` outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RingStates {
    /// State indices of the ring's displacement along x, y, z \[m\].
    pub pos: [usize; 3],
    /// State indices of the ring's velocity along x, y, z \[m/s\].
    pub vel: [usize; 3],
}

/// Linearization of the bearing's reaction on the journal (`bearing.F`, the force of the
/// bearing on the shaft) about the current state: `dfdx[i][k] = ∂F_i/∂x_k`, `dfdv[i][k] =
/// ∂F_i/∂v_k` with x, v the journal (inner-ring centre) displacement and velocity [N/m, N s/m].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ReactionJacobian {
    /// `dfdx[i][k] = ∂F_i/∂x_k`, the stiffness of the reaction \[N/m\].
    pub dfdx: [[f64; 3]; 3],
    /// `dfdv[i][k] = ∂F_i/∂v_k`, the damping of the reaction [N s/m].
    pub dfdv: [[f64; 3]; 3],
}

/// One axis of [`ReactionJacobian::exchange_limits`]: the reaction's stiffness and damping
/// along it and the largest stable step of value exchange on them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExchangeLimit {
    /// Stiffness −∂F_k/∂x_k \[N/m\] (> 0).
    pub k: f64,
    /// Damping −∂F_k/∂v_k [N s/m].
    pub c: f64,
    /// `2c/k` \[s\] (0 when c ≤ 0: no damping, no stable step).
    pub step: f64,
}

impl ReactionJacobian {
    /// Per axis (x, y, z), where the reaction is stiff (k > 0): the largest communication step at
    /// which a partner that holds the force over the step (value exchange) is stable on this
    /// damping alone. A journal of any mass M on stiffness k and damping c has ω = √(k/M) and
    /// ζ = c/(2Mω), and the constant-input coupling is stable for ωH < 4ζ, that is H < 2c/k
    /// (docs/model.md#coupling-stability): independent of the mass.
    pub fn exchange_limits(&self) -> [Option<ExchangeLimit>; 3] {
        std::array::from_fn(|i| {
            let (k, c) = (-self.dfdx[i][i], -self.dfdv[i][i]);
            (k > 0.0).then(|| ExchangeLimit {
                k,
                c,
                step: 2.0 * c.max(0.0) / k,
            })
        })
    }
}

/// A boxed copy of a model, so that a [`Simulation`](crate::simulation::Simulation) can be
/// cloned (the FMU keeps a freshly built one to restore states from without building anew).
/// Implemented for every [`Model`] that is [`Clone`].
pub trait CloneModel {
    /// A copy of this model in a new box.
    fn clone_model(&self) -> Box<dyn Model>;
}

impl<T: Model + Clone + 'static> CloneModel for T {
    fn clone_model(&self) -> Box<dyn Model> {
        Box::new(self.clone())
    }
}

impl Clone for Box<dyn Model> {
    fn clone(&self) -> Self {
        self.clone_model()
    }
}

/// One dynamic model of the ladder.
///
/// Motion coupling (the journal's motion prescribed, issue 6). A level with a dynamic
/// inner ring needs only two things: [`Model::ring_states`] (where its ring translation lives in
/// the state) and to honour [`Model::set_prescribed_ring`] in its right-hand side (ring
/// translational accelerations zero, so that the states follow x_k + v_k (t − t_k) exactly; the
/// [`Simulation`](crate::simulation::Simulation) writes x_k, v_k into the state at every
/// communication point). `bearing.F` must then be the sum of the contact forces on the inner
/// ring. [`Model::reaction_jacobian`] is optional (the simulation falls back to central
/// differences of the model's own outputs). Levels without ring states (L0, L1) get the
/// quasi-static displacement-controlled reaction (`models/motion.rs`) through the simulation.
pub trait Model: Send + CloneModel {
    /// Number of first-order states.
    fn dim(&self) -> usize;

    /// Nominal magnitude of each state: the absolute tolerance is `rtol × nominal`.
    fn nominal(&self, out: &mut [f64]);

    /// What state `i` is, for failure messages: e.g. "ball 3 orbital rate θ̇" or "pedestal
    /// velocity along z" (balls counted from 1, as in the outputs). Default: its index.
    fn state_name(&self, i: usize) -> String {
        format!("state component {i}")
    }

    /// Facts the model can tell about the state (t, y) at which an advance failed, for the
    /// message: e.g. that contact is lost at every ball. `None`: nothing to add. Called only on
    /// a failure (it may allocate and disturb caches: the simulation rolls back afterwards).
    fn diagnose(&mut self, _t: f64, _y: &[f64]) -> Option<String> {
        None
    }

    /// The initial state at t = 0 (from L1 equilibrium, docs/model.md#initial-state).
    fn initial_state(&self, y: &mut [f64]);

    /// New inputs, constant from time `t` on (state `y` at that time). On an error (no
    /// equilibrium at the new inputs, named in the message) the model is unchanged.
    fn set_inputs(&mut self, inputs: &OperatingPoint, t: f64, y: &[f64]) -> Result<(), SimError>;

    /// Right-hand side; must not allocate.
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]);

    /// The first known discontinuity strictly after `t` and not after `t_max`, if any.
    fn next_stop(&self, t: f64, y: &[f64], t_max: f64) -> Option<f64>;

    /// Re-derives the frozen discrete mode for the interval that starts at `t` (called after
    /// every stop and every located event, and after inputs change).
    fn update_mode(&mut self, t: f64, y: &[f64]);

    /// Number of state-event functions (e.g. a free ball reaching a spall edge); 0 = none.
    /// Events are located on the dense output; the discrete mode stays frozen inside a step.
    fn n_events(&self) -> usize {
        0
    }

    /// What event function `i` watches, for failure messages: e.g. "the outer contact of ball
    /// 3" (balls counted from 1). Default: its index.
    fn event_name(&self, i: usize) -> String {
        format!("event function {i}")
    }

    /// Event functions g_i(t, y): a sign change inside a step is an event, after which
    /// [`Model::update_mode`] is called at the located time.
    fn events(&mut self, _t: f64, _y: &[f64], _g: &mut [f64]) {}

    /// Event function `i` alone: what [`Model::events`] puts in `g[i]`, bit for bit (`g` is
    /// scratch of length [`Model::n_events`]). The root finder calls it for the function it
    /// locates; the default evaluates them all.
    fn event(&mut self, i: usize, t: f64, y: &[f64], g: &mut [f64]) -> f64 {
        self.events(t, y, g);
        g[i]
    }

    /// Called before the stages of every integrator step attempt (see
    /// [`crate::solver::System::begin_step`]).
    fn begin_step(&mut self) {}

    /// A time inside the step just accepted where an event function may have changed sign and
    /// back (see [`crate::solver::EventSystem::suspect`]); default none.
    fn suspect(&mut self, _t_old: f64, _t_new: f64) -> Option<f64> {
        None
    }

    /// The sign event `index` has in the current mode, for an event that only switches a mode
    /// (see [`crate::solver::EventSystem::mode_sign`]); default none.
    fn mode_sign(&self, _index: usize) -> Option<f64> {
        None
    }

    /// Event `index` fired at the located time (called before [`Model::update_mode`]). At the
    /// located state the function sits within the location tolerance of 0, on either side by
    /// round-off, so a model whose mode follows the sign of g can use this to switch reliably.
    fn event_fired(&mut self, _index: usize) {}

    /// Does now the work that the outputs at (t, y) would do lazily (the kinematic level
    /// registers the spall passes reached by then), at most `budget` units (one unit a spall
    /// pass): returns the units used. Needing more is an error naming the cause and the numbers,
    /// with nothing done. The simulation calls it before every output it takes in an advance,
    /// and at the advance's end, charging it to the advance's step budget (`solver.max_steps`),
    /// so that no call does unbounded work. Default: nothing to do.
    fn catch_up(&mut self, _t: f64, _y: &[f64], _budget: u64) -> Result<u64, String> {
        Ok(0)
    }

    /// [`Model::catch_up`]'s check alone (to within one unit): the work fits in `budget`, or the
    /// same error; nothing is done. Default: nothing to do.
    fn check_catch_up(&mut self, _t: f64, _y: &[f64], _budget: u64) -> Result<(), String> {
        Ok(())
    }

    /// Fills the output vector (layout of [`super::out::output_table`]). `out` is either
    /// the whole vector or its first [`super::out::BEARING_OUTPUTS`] entries (the
    /// bearing-level outputs, without the per-ball block): then the per-ball quantities are
    /// not computed ([`crate::simulation::Simulation::set_ball_outputs`]).
    fn outputs(&mut self, t: f64, y: &[f64], out: &mut [f64]);

    /// Model quantities that are not states but must survive a save/restore.
    fn discrete_state(&self) -> Vec<f64> {
        Vec::new()
    }

    /// Restores what [`Model::discrete_state`] returned.
    fn set_discrete_state(&mut self, _s: &[f64]) -> Result<(), String> {
        Ok(())
    }

    /// Writes into `buf` (cleared first) everything an advance can change in the model besides
    /// the state vector (operating point, frozen modes, what the outputs remember), so that
    /// [`Model::rollback`] puts the model back bit for bit: a failed communication step leaves
    /// no trace. The simulation calls it at the start of every advance, so it must not allocate
    /// once `buf` has its size. The default stores [`Model::discrete_state`] (which allocates,
    /// and whose restore re-derives the modes); the levels of the ladder override both.
    fn checkpoint(&self, buf: &mut Vec<f64>) {
        buf.clear();
        buf.extend_from_slice(&self.discrete_state());
    }

    /// Puts back what [`Model::checkpoint`] wrote on this model, at time `t` and state `y` (the
    /// integrator's, rolled back too). The default restores the discrete state and re-derives
    /// the modes. An error means the model could not be put back (the simulation reports it).
    fn rollback(&mut self, buf: &[f64], t: f64, y: &[f64]) -> Result<(), String> {
        self.set_discrete_state(buf)?;
        self.update_mode(t, y);
        Ok(())
    }

    /// The cage speed the model uses [rad/s] (for fault-frequency bookkeeping).
    fn cage_speed(&self) -> f64;

    /// True when the model has a cage as a body (the reduced and full levels with one,
    /// docs/model.md#cage): its outputs then include the cage block
    /// ([`super::out::output_table_with_cage`]).
    fn has_cage(&self) -> bool {
        false
    }

    /// A note on the start when it is not the one the level normally takes (the full and
    /// reduced levels' balls at the caged rate where some ball has no steady rotation of its
    /// own); the simulation passes it on with its warnings.
    fn start_note(&self) -> Option<String> {
        None
    }

    /// True when the contact forces change only with the inputs (the kinematic and
    /// quasi-static levels: L1's load distribution, less a spall's dip): the simulation then
    /// checks them at the start and when the inputs change, not after every advance.
    fn contacts_follow_inputs(&self) -> bool {
        false
    }

    /// The inner ring's translation states, if the ring is a dynamic body of this level.
    fn ring_states(&self) -> Option<RingStates> {
        None
    }

    /// Motion coupling on/off: when on, the right-hand side must set the ring's translational
    /// accelerations to zero (the ring velocity is then constant over a communication step).
    fn set_prescribed_ring(&mut self, _on: bool) {}

    /// Force coupling: a force law on the inner ring added to the inputs' constant load from
    /// now on (`None`: none). Returns false on a level without a dynamic ring (which cannot
    /// take one); a level with [`Model::ring_states`] must apply it in its right-hand side.
    fn set_ring_load(&mut self, _law: Option<RingLoad>) -> bool {
        false
    }

    /// Motion coupling: the simulation moves the level's quasi-static (L1) operating point
    /// (speed and the load the ring carries) from which the level takes its cage speed. Called
    /// at the start of a communication step when the speed has moved by more than
    /// `L1_SPEED_STEP` (2 % of the speed) since the last call; levels without an L1 cage speed
    /// ignore it. (In force mode the level follows its own inputs.) On an error the level
    /// keeps its operating point.
    fn update_operating_point(&mut self, _inputs: &OperatingPoint) -> Result<(), SimError> {
        Ok(())
    }

    /// Analytic linearization of `bearing.F` with respect to the ring's displacement and
    /// velocity at state `y` (everything else held: pedestal, balls, cage). `None` = not
    /// implemented (the simulation uses central differences of [`Model::outputs`]).
    fn reaction_jacobian(&mut self, _t: f64, _y: &[f64]) -> Option<ReactionJacobian> {
        None
    }

    /// True when ball j is inside the zone of the spall (|θ_bd| < θ_e) in the current discrete
    /// mode; false for levels without per-ball positions. Used to measure the paper's impact
    /// force (the largest contact force while the ball crosses the spall).
    fn in_spall_zone(&self, _j: usize) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2c/k per stiff axis; an axis without stiffness has no limit, one without damping a zero
    /// step (value exchange is never stable on it).
    #[test]
    fn exchange_limits_are_2c_over_k() {
        let mut j = ReactionJacobian::default();
        j.dfdx[0][0] = -2.0e8;
        j.dfdv[0][0] = -100.0;
        j.dfdx[1][1] = -4.0e8;
        j.dfdv[1][1] = 5.0;
        let l = j.exchange_limits();
        let x = l[0].unwrap();
        assert_eq!((x.k, x.c, x.step), (2.0e8, 100.0, 1e-6));
        let y = l[1].unwrap();
        assert_eq!((y.c, y.step), (-5.0, 0.0));
        assert!(l[2].is_none());
    }
}
