//! The interface between a model and the integrator.

/// A first-order ODE system `y' = f(t, y)`.
pub trait System {
    /// Number of state components.
    fn dim(&self) -> usize;
    /// Right-hand side; must not allocate. `y` and `dydt` have length [`System::dim`].
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]);
    /// Called before the stages of every step attempt (default: nothing).
    fn begin_step(&mut self) {}
}

/// A system with event functions and a discrete mode that changes only at events.
pub trait EventSystem: System {
    /// Number of event functions.
    fn n_events(&self) -> usize;
    /// Event functions `g_i(t, y)`; a sign change of `g_i` inside an accepted step is an event.
    /// The system's discrete mode must stay frozen inside a step (only
    /// [`EventSystem::handle_event`] may change it).
    fn events(&mut self, t: f64, y: &[f64], g: &mut [f64]);
    /// Event function `i` alone at `(t, y)`: the value [`EventSystem::events`] would put in
    /// `g[i]`, bit for bit. `g` (length [`EventSystem::n_events`]) is scratch the system may
    /// write anywhere. The root finder calls it for the one function it locates; the default
    /// evaluates them all. Must not allocate.
    fn event(&mut self, i: usize, t: f64, y: &[f64], g: &mut [f64]) -> f64 {
        self.events(t, y, g);
        g[i]
    }
    /// Called at the located event time with the (dense-output) state there; the system may switch
    /// its discrete mode and modify `y`. The integrator then restarts from `(t, y)` (FSAL
    /// invalidated).
    fn handle_event(&mut self, index: usize, t: f64, y: &mut [f64]) -> EventAction;
    /// After an accepted step from `t_old` to `t_new`: a time inside it at which the system
    /// suspects an event function of having changed sign and back (two roots in one step, which
    /// the sign test at the step end cannot see), e.g. because a stage found its frozen mode
    /// invalid there; `None` (the default) if nothing is suspect. The integrator then also
    /// tests the signs at that time on the dense output and locates a root before it.
    /// Must not allocate.
    fn suspect(&mut self, _t_old: f64, _t_new: f64) -> Option<f64> {
        None
    }
    /// For a function whose event only switches the system's mode (the state is not moved):
    /// the sign it has in the current mode (±1). After it fires, the integrator restarts with
    /// that sign as its reference, so a return to the other side, however soon, is an event
    /// (a function that touches 0 and comes back switches the mode back). `None` (the default,
    /// e.g. for a bounce that moves the state): the function counts as 0 at the restart and its
    /// reference sign comes from a probe just inside the next step, so leaving zero is not an
    /// event. Must not allocate.
    fn mode_sign(&self, _index: usize) -> Option<f64> {
        None
    }
}

/// What the integrator does after an event was handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventAction {
    /// Keep integrating towards the requested end time.
    Continue,
    /// Return early from [`crate::Integrator::advance_with_events`] at the event time.
    Stop,
}
