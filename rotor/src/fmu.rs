//! The FMI 2.0 Co-Simulation and Model Exchange model `JeffcottRotor`: a thin [`FmuModel`] around
//! [`crate::jeffcott::Rotor`] (coupling mode force) and [`crate::jeffcott::TlmRotor`]
//! (coupling mode tlm), with its variable table (one source of truth for the shell, the model
//! description and the documentation).
//!
//! Value references (written out in the table; a released one never moves):
//!
//! | range | variables |
//! |---|---|
//! | 1–3 | inputs `bearing.F.x/y/z` (coupling mode force) |
//! | 4–6 | inputs `bearing.dF.x/y/z` (force) |
//! | 10–18 | inputs `bearing.dF_dx.ij` (force) |
//! | 20–28 | inputs `bearing.dF_dv.ij` (force) |
//! | 30–31 | inputs `tlm.v.y`, `tlm.v.z` (coupling mode tlm) |
//! | 100–115 | the Real parameters of [`PARAMS`] |
//! | 116 | Integer parameter `coupling` (0 force, 1 tlm) |
//! | 117 | parameter `tlm.delay` ([`TLM_DELAY`]) |
//! | 118 | Enumeration parameter `disk.axial` (1 with_journal: the disk rides axially with the journal, 0 lateral: not) |
//! | 1000–1016 | outputs `journal.*`, `disk.*`, `shaft.*`, `unbalance.F.*` |
//! | 1017–1021 | outputs `tlm.c0.y`, `tlm.c0.z`, `tlm.c1.y`, `tlm.c1.z`, `tlm.Zc` (tlm) |
//!
//! # Coupling mode tlm
//!
//! With `coupling = 1` the rotor is cut from the bearing at the compliant shaft, which becomes
//! a transmission line of delay `tlm.delay` (the master's communication step `T`) simulated
//! inside this FMU (equations: [`crate::jeffcott`], [`crate::tlm`]). The journal's mass is the
//! BallBearing's (its `coupling = 2`, tlm). Connections, both ways at every communication
//! point of a Jacobi (or Gauss–Seidel) master:
//!
//! - rotor `tlm.c0.y`, `tlm.c0.z`, `tlm.c1.y`, `tlm.c1.z`, `tlm.Zc` → the BallBearing's inputs
//!   of the same names; over its step `[t_k, t_k + T]` the bearing applies
//!   `F = c0 + (c1 − c0)(t − t_k)/T − Zc v_j` to its journal;
//! - BallBearing `ring.v.y`, `ring.v.z` → rotor `tlm.v.y`, `tlm.v.z`.
//!
//! The `tlm.*` outputs depend on the rotor's own state and history only (the model
//! description declares them without dependencies), so the result does not depend on the
//! order in which the master sets and reads. A `fmi2DoStep` whose step differs from
//! `tlm.delay` (relative 1e-9) is refused: `fmi2Error` with the model unchanged (the shell
//! then holds the instance in its Error state, which `fmi2SetFMUstate` or `fmi2Reset` leave).
//! The force-mode inputs are ignored in this mode (set after initialization: one warning), and
//! so are the parameters `journal.mass`, `journal.c` and `load.*` (nonzero `journal.c` or
//! loads: one warning at initialization).

use crate::jeffcott::{
    Coupling, InterfaceForce, Rotor, RotorParams, SeenJournal, TlmRotor, TlmSnapshot,
};
use crate::tlm::{accurate_delay, LineHistory, AXES};
use fmi2::bindings::Fmi2Status;
use fmi2::codec::{ByteReader, ByteWriter};
use fmi2::table::Row;
use fmi2::xml;
use fmi2::{
    Causality, EnumerationItem, EnumerationType, EventUpdate, FmuModel, Initial, InstantiateArgs,
    Interface, Logger, Start, StepEnd, StepResult, VarType, Variability, Variable, LOG_EVENTS,
    LOG_SOLVER, LOG_STATUS_WARNING,
};
use raceway_solver::IntegratorState;

pub const MODEL_IDENTIFIER: &str = "JeffcottRotor";
pub const DEFAULT_START_TIME: f64 = 0.0;
pub const DEFAULT_STOP_TIME: f64 = 0.1;
pub const DEFAULT_TOLERANCE: f64 = 1e-8;
pub const DEFAULT_STEP_SIZE: f64 = 1e-4;
/// Version of the FMU state's model part (2: coupling mode tlm, the line's history; 3: disk.axial).
const MODEL_STATE_VERSION: u32 = 3;
/// Relative tolerance of the check that the communication step equals `tlm.delay`.
const DELAY_RTOL: f64 = 1e-9;

/// What a variable stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// Bearing force \[N\], component 0..3.
    F(usize),
    /// Bearing force rate [N/s].
    DF(usize),
    /// ∂F_i/∂x_j.
    K(usize, usize),
    /// ∂F_i/∂v_j.
    C(usize, usize),
    /// Index in [`PARAMS`].
    Param(usize),
    /// The Integer parameter `coupling`.
    Coupling,
    /// The parameter `tlm.delay` ([`TLM_DELAY`]).
    Delay,
    /// The Enumeration parameter `disk.axial`.
    DiskAxial,
    /// Journal velocity received in coupling mode tlm, axis 0 = y, 1 = z.
    TlmV(usize),
    Out(O),
    /// Model Exchange: continuous state `i` of coupling mode force (`state[i + 1]`).
    State(usize),
    /// Model Exchange: its derivative (`der(state[i + 1])`).
    Derivative(usize),
}

/// Value reference of `state[i + 1]` (Model Exchange); its derivative is `DERIVATIVE_VR + i`.
pub const STATE_VR: u32 = 2000;
/// Value reference of `der(state[i + 1])`.
pub const DERIVATIVE_VR: u32 = 3000;
/// What the rotor's continuous states are (coupling mode force), in order.
pub const STATE_NAMES: [&str; crate::jeffcott::DIM] = [
    "journal displacement x",
    "journal displacement y",
    "journal displacement z",
    "journal velocity x",
    "journal velocity y",
    "journal velocity z",
    "disk displacement y",
    "disk displacement z",
    "disk velocity y",
    "disk velocity z",
];

/// What a parameter row reads and writes in [`RotorParams`].
#[derive(Debug, Clone, Copy)]
pub struct ParamAccess {
    /// Reads the parameter.
    pub get: fn(&RotorParams) -> f64,
    /// Writes the parameter (the value has passed the shell's checks).
    pub set: fn(&mut RotorParams, f64),
}

/// A fixed Real parameter row (`initial="exact"`).
const fn param(
    vr: u32,
    name: &'static str,
    unit: &'static str,
    min: Option<f64>,
    description: &'static str,
    get: fn(&RotorParams) -> f64,
    set: fn(&mut RotorParams, f64),
) -> Row<ParamAccess> {
    Row {
        vr,
        name,
        ty: VarType::Real,
        causality: Causality::Parameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Exact),
        unit: Some(unit),
        declared_type: None,
        min,
        max: None,
        description,
        access: ParamAccess { get, set },
    }
}

/// The parameters, one row each with its value reference written out (their order is also
/// the FMU state's).
pub const PARAMS: &[Row<ParamAccess>] = &[
    param(
        100,
        "journal.mass",
        "kg",
        Some(0.0),
        "Journal (bearing-station) mass, > 0; with disk.mass = 0 the whole rigid rotor",
        |p| p.journal_mass,
        |p, v| p.journal_mass = v,
    ),
    param(
        101,
        "disk.mass",
        "kg",
        Some(0.0),
        "Disk mass on the flexible shaft (0: rigid rotor, the unbalance then sits on the journal)",
        |p| p.disk_mass,
        |p, v| p.disk_mass = v,
    ),
    param(
        102,
        "shaft.k",
        "N/m",
        Some(0.0),
        "Lateral shaft stiffness between journal and disk",
        |p| p.shaft_k,
        |p, v| p.shaft_k = v,
    ),
    param(
        103,
        "shaft.c",
        "N.s/m",
        Some(0.0),
        "Lateral shaft damping between journal and disk",
        |p| p.shaft_c,
        |p, v| p.shaft_c = v,
    ),
    param(
        104,
        "journal.c",
        "N.s/m",
        Some(0.0),
        "Damping of the journal to ground (x, y, z), e.g. a squeeze-film damper",
        |p| p.journal_c,
        |p, v| p.journal_c = v,
    ),
    param(
        105,
        "unbalance",
        "kg.m",
        Some(0.0),
        "Unbalance m_u*e on the disk (on the journal if rigid)",
        |p| p.unbalance,
        |p, v| p.unbalance = v,
    ),
    param(
        106,
        "gravity",
        "m/s2",
        None,
        "Gravitational acceleration, acting along -z",
        |p| p.gravity,
        |p, v| p.gravity = v,
    ),
    param(
        107,
        "load.Fx",
        "N",
        None,
        "Constant external force on the journal along x (the default scene's Fa = 4000 N along +x and Fr = 1000 N along -z)",
        |p| p.load[0],
        |p, v| p.load[0] = v,
    ),
    param(
        108,
        "load.Fy",
        "N",
        None,
        "Constant external force on the journal along y (the default scene's Fa = 4000 N along +x and Fr = 1000 N along -z)",
        |p| p.load[1],
        |p, v| p.load[1] = v,
    ),
    param(
        109,
        "load.Fz",
        "N",
        None,
        "Constant external force on the journal along z (the default scene's Fa = 4000 N along +x and Fr = 1000 N along -z)",
        |p| p.load[2],
        |p, v| p.load[2] = v,
    ),
    param(
        110,
        "journal.x0",
        "m",
        None,
        "Initial journal displacement along x (e.g. the bearing's static displacement); the disk starts at its static sag",
        |p| p.journal0[0],
        |p, v| p.journal0[0] = v,
    ),
    param(
        111,
        "journal.y0",
        "m",
        None,
        "Initial journal displacement along y (e.g. the bearing's static displacement); the disk starts at its static sag",
        |p| p.journal0[1],
        |p, v| p.journal0[1] = v,
    ),
    param(
        112,
        "journal.z0",
        "m",
        None,
        "Initial journal displacement along z (e.g. the bearing's static displacement); the disk starts at its static sag",
        |p| p.journal0[2],
        |p, v| p.journal0[2] = v,
    ),
    param(
        113,
        "speed.initial",
        "rad/s",
        Some(0.0),
        "Shaft speed at the start time",
        |p| p.speed_initial,
        |p, v| p.speed_initial = v,
    ),
    param(
        114,
        "speed.final",
        "rad/s",
        Some(0.0),
        "Shaft speed at the end of the ramp",
        |p| p.speed_final,
        |p, v| p.speed_final = v,
    ),
    param(
        115,
        "speed.rate",
        "rad/s2",
        Some(0.0),
        "Magnitude of the speed ramp from speed.initial to speed.final (0: constant speed.initial)",
        |p| p.speed_rate,
        |p, v| p.speed_rate = v,
    ),
];

/// The parameter `tlm.delay` (kept out of [`PARAMS`], whose order the released variable table
/// and the FMU state's first part follow).
pub const TLM_DELAY: Row<ParamAccess> = param(
    117,
    "tlm.delay",
    "s",
    Some(0.0),
    "Coupling mode tlm: delay T of the transmission line standing for the shaft, > 0; must equal the master's communication step (a fmi2DoStep of another size is refused). Line impedance Zc = shaft.k*T; its parasitic mass shaft.k*T^2 is the coupling's error (accurate while <= 1 % of disk.mass, T <= sqrt(0.01 disk.mass/shaft.k)); stable at any T",
    |p| p.tlm_delay,
    |p, v| p.tlm_delay = v,
);

/// Value reference of the Integer parameter `coupling`.
pub const VR_COUPLING: u32 = 116;
/// Value reference of the Enumeration parameter `disk.axial` (type `DiskAxial`).
pub const VR_DISK_AXIAL: u32 = 118;

/// The enumeration type of the parameter `disk.axial` (read and written with
/// `fmi2GetInteger`/`fmi2SetInteger`, their values the items').
pub fn enumerations() -> Vec<EnumerationType> {
    let item = |value: i32, name: &str, description: &str| EnumerationItem {
        name: name.into(),
        value,
        description: description.into(),
    };
    vec![EnumerationType {
        name: "DiskAxial".into(),
        description: "Whether the disk moves axially (coupling mode force)".into(),
        items: vec![
            item(
                0,
                "lateral",
                "The disk moves only laterally (axial inertia journal.mass)",
            ),
            item(
                1,
                "with_journal",
                "The disk rides axially with the journal (axial inertia journal.mass + disk.mass)",
            ),
        ],
    }]
}
/// Value references of the inputs `tlm.v.y`, `tlm.v.z`.
pub const VR_TLM_V: [u32; AXES] = [30, 31];

/// Outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum O {
    X(usize),
    V(usize),
    A(usize),
    Disk(usize),
    DiskV(usize),
    Speed,
    Angle,
    Unbalance(usize),
    /// `tlm.c0.y/z`.
    TlmC0(usize),
    /// `tlm.c1.y/z`.
    TlmC1(usize),
    /// `tlm.Zc`.
    TlmZc,
}

impl O {
    /// Every output, in value-reference order (1000 + position).
    pub const ALL: [O; 22] = [
        O::X(0),
        O::X(1),
        O::X(2),
        O::V(0),
        O::V(1),
        O::V(2),
        O::A(0),
        O::A(1),
        O::A(2),
        O::Disk(0),
        O::Disk(1),
        O::DiskV(0),
        O::DiskV(1),
        O::Speed,
        O::Angle,
        O::Unbalance(0),
        O::Unbalance(1),
        O::TlmC0(0),
        O::TlmC0(1),
        O::TlmC1(0),
        O::TlmC1(1),
        O::TlmZc,
    ];

    /// Whether the output may depend directly on the inputs (the `tlm.*` outputs depend on
    /// the rotor's own state and history only).
    pub fn feedthrough(self) -> bool {
        !matches!(self, O::TlmC0(_) | O::TlmC1(_) | O::TlmZc)
    }

    fn info(self) -> (String, &'static str, String) {
        const XYZ: [&str; 3] = ["x", "y", "z"];
        const YZ: [&str; 2] = ["y", "z"];
        match self {
            O::X(i) => (format!("journal.{}", XYZ[i]), "m", format!("Journal (inner-ring centre) displacement along {} in the bearing's frame (connect to the BallBearing's journal.{} in motion mode); in coupling mode tlm the journal as seen through the line: {}", XYZ[i], XYZ[i], if i == 0 { "journal.x0 (the axial direction is the bearing's)" } else { "integrated from tlm.v by the trapezoidal rule from journal.y0/z0" })),
            O::V(i) => (format!("journal.v.{}", XYZ[i]), "m/s", format!("Journal velocity along {}{}", XYZ[i], if i == 0 { " (0 in coupling mode tlm)" } else { " (in coupling mode tlm the received tlm.v)" })),
            O::A(i) => (format!("journal.a.{}", XYZ[i]), "m/s2", format!("Journal acceleration along {}{}", XYZ[i], if i == 0 { " (0 in coupling mode tlm)" } else { " (in coupling mode tlm the slope of the received tlm.v since the last sample used)" })),
            O::Disk(i) => (format!("disk.{}", YZ[i]), "m", format!("Disk displacement along {}", YZ[i])),
            O::DiskV(i) => (format!("disk.v.{}", YZ[i]), "m/s", format!("Disk velocity along {}", YZ[i])),
            O::Speed => ("shaft.speed".into(), "rad/s", "Shaft speed (connect to the BallBearing's shaft.speed)".into()),
            O::Angle => ("shaft.angle".into(), "rad", "Shaft angle, wrapped to [0, 2 pi)".into()),
            O::Unbalance(i) => (format!("unbalance.F.{}", YZ[i]), "N", format!("Unbalance force along {}", YZ[i])),
            O::TlmC0(i) => (format!("tlm.c0.{}", YZ[i]), "N", format!("Coupling mode tlm: the line's force on the journal along {} at the start of the bearing's next communication step, before its impedance term (c0 = w(t_k - T), w = o_d + shaft.c*v_d); connect to the BallBearing's tlm.c0.{} (its coupling = 2, tlm). The rotor's own state only (no direct feedthrough); 0 in coupling mode force", YZ[i], YZ[i])),
            O::TlmC1(i) => (format!("tlm.c1.{}", YZ[i]), "N", format!("Coupling mode tlm: the same at the end of the bearing's next step (c1 = w(t_k)); over its step [t_k, t_k + T] the bearing applies F = c0 + (c1 - c0)(t - t_k)/T - tlm.Zc*v_j to its journal; connect to the BallBearing's tlm.c1.{}. The rotor's own state only (no direct feedthrough); 0 in coupling mode force", YZ[i])),
            O::TlmZc => ("tlm.Zc".into(), "N.s/m", "Coupling mode tlm: impedance of the line at the journal, shaft.k*tlm.delay + shaft.c; connect to the BallBearing's tlm.Zc. A parameter of the rotor only (no direct feedthrough); 0 in coupling mode force".into()),
        }
    }

    fn get(self, o: &crate::jeffcott::RotorOutputs) -> f64 {
        match self {
            O::X(i) => o.journal_x[i],
            O::V(i) => o.journal_v[i],
            O::A(i) => o.journal_a[i],
            O::Disk(i) => o.disk[i],
            O::DiskV(i) => o.disk_v[i],
            O::Speed => o.speed,
            O::Angle => o.angle,
            O::Unbalance(i) => o.unbalance[i],
            O::TlmC0(i) => o.tlm_c0[i],
            O::TlmC1(i) => o.tlm_c1[i],
            O::TlmZc => o.tlm_zc,
        }
    }
}

fn var(vr: u32, name: &str, ty: VarType, c: Causality, v: Variability, desc: &str) -> Variable {
    Variable {
        vr,
        name: name.into(),
        ty,
        causality: c,
        variability: v,
        initial: None,
        description: desc.into(),
        unit: None,
        declared_type: None,
        display_unit: None,
        start: Start::None,
        min: None,
        max: None,
        derivative_of: None,
    }
}

/// The variable table: (variable, role).
#[allow(clippy::needless_range_loop)] // i, j are both indices and names here
pub fn table() -> Vec<(Variable, Role)> {
    use Causality::*;
    use Variability::*;
    const XYZ: [&str; 3] = ["x", "y", "z"];
    let mut t = Vec::new();
    for i in 0..3 {
        let mut v = var(
            1 + i as u32,
            &format!("bearing.F.{}", XYZ[i]),
            VarType::Real,
            Input,
            Continuous,
            &format!("Force of the bearing on the shaft along {} at the step start (the BallBearing's bearing.F.{} in motion mode)", XYZ[i], XYZ[i]),
        );
        v.unit = Some("N".into());
        v.start = Start::Real(0.0);
        t.push((v, Role::F(i)));
    }
    for i in 0..3 {
        let mut v = var(
            4 + i as u32,
            &format!("bearing.dF.{}", XYZ[i]),
            VarType::Real,
            Input,
            Continuous,
            &format!(
                "Rate of bearing.F.{} over the step (linear input extrapolation; 0: held constant)",
                XYZ[i]
            ),
        );
        v.unit = Some("N/s".into());
        v.start = Start::Real(0.0);
        t.push((v, Role::DF(i)));
    }
    for i in 0..3 {
        for j in 0..3 {
            let mut v = var(
                10 + (3 * i + j) as u32,
                &format!("bearing.dF_dx.{}{}", XYZ[i], XYZ[j]),
                VarType::Real,
                Input,
                Continuous,
                &format!("Interface Jacobian dF_{}/dx_{} of the bearing (0: none); inside the step F += dF/dx (x(t) - x(t_k))", XYZ[i], XYZ[j]),
            );
            v.unit = Some("N/m".into());
            v.start = Start::Real(0.0);
            t.push((v, Role::K(i, j)));
        }
    }
    for i in 0..3 {
        for j in 0..3 {
            let mut v = var(
                20 + (3 * i + j) as u32,
                &format!("bearing.dF_dv.{}{}", XYZ[i], XYZ[j]),
                VarType::Real,
                Input,
                Continuous,
                &format!("Interface Jacobian dF_{}/dv_{} of the bearing (0: none); inside the step F += dF/dv (v(t) - v(t_k))", XYZ[i], XYZ[j]),
            );
            v.unit = Some("N.s/m".into());
            v.start = Start::Real(0.0);
            t.push((v, Role::C(i, j)));
        }
    }
    let d = RotorParams::default();
    for (k, p) in PARAMS.iter().enumerate() {
        t.push((p.variable(Start::Real((p.access.get)(&d))), Role::Param(k)));
    }
    for (k, o) in O::ALL.into_iter().enumerate() {
        let (name, unit, desc) = o.info();
        let mut v = var(
            1000 + k as u32,
            &name,
            VarType::Real,
            Output,
            Continuous,
            &desc,
        );
        v.unit = Some(unit.into());
        v.initial = Some(Initial::Calculated);
        t.push((v, Role::Out(o)));
    }
    // Coupling mode tlm (after every released variable, so their indices stay).
    let mut v = var(
        VR_COUPLING,
        "coupling",
        // An Integer, not an Enumeration: libcosim ignores Enumeration variables, and a
        // rotor-bearing system run there (examples/systems) must set the coupling mode.
        VarType::Integer,
        Parameter,
        Fixed,
        "Coupling to the BallBearing. 0 = force: the rotor owns the journal and takes the bearing force (inputs bearing.*; outputs journal.* to the BallBearing's journal inputs, its coupling = 1, motion). 1 = tlm: transmission line at the shaft, stable at any communication step; the journal's mass is the BallBearing's (its coupling = 2, tlm): connect tlm.c0.y/z, tlm.c1.y/z and tlm.Zc to the BallBearing's inputs of the same names and its ring.v.y/z to tlm.v.y/z, and step with tlm.delay; needs disk.mass > 0 and shaft.k > 0, and journal.mass, journal.c and load.* do not act",
    );
    v.initial = Some(Initial::Exact);
    v.start = Start::Integer(Coupling::default().code());
    v.min = Some(0.0);
    v.max = Some(1.0);
    t.push((v, Role::Coupling));
    t.push((TLM_DELAY.variable(Start::Real(d.tlm_delay)), Role::Delay));
    let mut v = var(
        VR_DISK_AXIAL,
        "disk.axial",
        VarType::Enumeration,
        Parameter,
        Fixed,
        "Coupling mode force: 1 (default) the disk rides axially with the journal (axial inertia journal.mass + disk.mass); 0 it moves only laterally (axial inertia journal.mass, as in coupling mode tlm, where the axial direction is the BallBearing's ring)",
    );
    v.initial = Some(Initial::Exact);
    v.declared_type = Some("DiskAxial".into());
    v.start = Start::Integer(i32::from(d.disk_axial));
    v.min = Some(0.0);
    v.max = Some(1.0);
    t.push((v, Role::DiskAxial));
    for (i, vr) in VR_TLM_V.into_iter().enumerate() {
        let yz = ["y", "z"][i];
        let mut v = var(
            vr,
            &format!("tlm.v.{yz}"),
            VarType::Real,
            Input,
            Continuous,
            &format!("Coupling mode tlm: journal velocity along {yz} at the communication point, from the BallBearing's ring.v.{yz} (its coupling = 2, tlm); ignored in coupling mode force"),
        );
        v.unit = Some("m/s".into());
        v.start = Start::Real(0.0);
        t.push((v, Role::TlmV(i)));
    }
    for (i, what) in STATE_NAMES.iter().enumerate() {
        let mut v = var(
            STATE_VR + i as u32,
            &format!("state[{}]", i + 1),
            VarType::Real,
            Local,
            Continuous,
            &format!("Model Exchange: continuous state {} of coupling mode force, the {what} (0 in coupling mode tlm)", i + 1),
        );
        v.initial = Some(Initial::Calculated);
        let mut d = var(
            DERIVATIVE_VR + i as u32,
            &format!("der(state[{}])", i + 1),
            VarType::Real,
            Local,
            Continuous,
            &format!("Model Exchange: the derivative of state[{}]", i + 1),
        );
        d.initial = Some(Initial::Calculated);
        d.derivative_of = Some(STATE_VR + i as u32);
        t.push((v, Role::State(i)));
        t.push((d, Role::Derivative(i)));
    }
    t
}

pub fn model_info() -> xml::ModelInfo {
    xml::ModelInfo {
        model_name: MODEL_IDENTIFIER.into(),
        model_identifier: MODEL_IDENTIFIER.into(),
        description: "Jeffcott rotor (journal and disk on a flexible shaft) with unbalance, gravity, a speed ramp and one bearing station; couples to the BallBearing FMU in motion mode (coupling = 0, force) or through a transmission line at the shaft (coupling = 1, tlm)".into(),
        author: "raceway developers".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        license: env!("CARGO_PKG_LICENSE").into(),
        generation_tool: format!("raceway-rotor {}", env!("CARGO_PKG_VERSION")),
        start_time: DEFAULT_START_TIME,
        stop_time: DEFAULT_STOP_TIME,
        tolerance: DEFAULT_TOLERANCE,
        step_size: DEFAULT_STEP_SIZE,
        provides_directional_derivative: false,
        model_exchange: Some(0),
        // The tlm.* outputs depend on the rotor's own state and history only (the line's
        // samples), not on the inputs of the same communication point.
        independent_outputs: table()
            .into_iter()
            .filter(|(_, r)| matches!(r, Role::Out(o) if !o.feedthrough()))
            .map(|(v, _)| v.vr)
            .collect(),
        enumerations: enumerations(),
    }
}

fn description_and_guid() -> (String, String) {
    let vars: Vec<Variable> = table().into_iter().map(|(v, _)| v).collect();
    xml::model_description(&model_info(), &vars)
}

/// The `modelDescription.xml` of the rotor FMU.
pub fn model_description_xml() -> String {
    description_and_guid().0
}

/// The GUID of the rotor FMU (a hash of its model description).
pub fn guid() -> String {
    description_and_guid().1
}

/// The running model of either coupling mode.
#[derive(Debug, Clone)]
enum Live {
    Force(Box<Rotor>),
    Tlm(Box<TlmRotor>),
}

impl Live {
    fn outputs(&mut self, tlm_v: [f64; AXES]) -> crate::jeffcott::RotorOutputs {
        match self {
            Live::Force(r) => r.outputs(),
            Live::Tlm(r) => r.outputs(tlm_v),
        }
    }

    fn stats(&self) -> (u64, u64, u64) {
        match self {
            Live::Force(r) => r.stats(),
            Live::Tlm(r) => r.stats(),
        }
    }
}

/// Inputs the master set after initialization that the coupling mode ignores (each kind
/// reported once per instance, at warning level).
const IGNORED_FORCE_INPUTS: usize = 0;
const IGNORED_TLM_INPUTS: usize = 1;

/// What [`JeffcottRotor::begin_set`] records: parameters, inputs and the ignored-input flags.
#[derive(Debug, Clone)]
pub struct SetUndo {
    params: RotorParams,
    iface: InterfaceForce,
    tlm_v: [f64; AXES],
    ignored_set: [bool; 2],
}

/// The FMU model.
pub struct JeffcottRotor {
    guid: String,
    vars: Vec<Variable>,
    roles: Vec<Role>,
    params: RotorParams,
    iface: InterfaceForce,
    /// The inputs `tlm.v.y`, `tlm.v.z`.
    tlm_v: [f64; AXES],
    start_time: f64,
    tolerance: Option<f64>,
    live: Option<Live>,
    /// `fmi2ExitInitializationMode` has run (since the last reset).
    initialized: bool,
    /// Ignored inputs set after initialization: the force-mode inputs in mode tlm, `tlm.v` in
    /// mode force.
    ignored_set: [bool; 2],
    /// Which of them have been reported.
    ignored_reported: [bool; 2],
    /// The interface of the instance (`fmuType`).
    interface: Interface,
}

impl JeffcottRotor {
    pub fn new() -> Self {
        let (vars, roles): (Vec<_>, Vec<_>) = table().into_iter().unzip();
        JeffcottRotor {
            guid: guid(),
            vars,
            roles,
            params: RotorParams::default(),
            iface: InterfaceForce::default(),
            tlm_v: [0.0; AXES],
            start_time: 0.0,
            tolerance: None,
            live: None,
            initialized: false,
            ignored_set: [false; 2],
            ignored_reported: [false; 2],
            interface: Interface::CoSimulation,
        }
    }

    /// Model Exchange: the rotor of coupling mode force (built provisionally before
    /// initialization, to answer queries in initialization mode).
    fn me_rotor(&mut self) -> Result<&mut Rotor, String> {
        if self.live.is_none() {
            self.live = Some(self.build()?);
        }
        match self.live.as_mut() {
            Some(Live::Force(r)) => Ok(r),
            _ => Err("Model Exchange needs coupling = 0 (force)".into()),
        }
    }

    fn build(&self) -> Result<Live, String> {
        let rtol = self.tolerance.unwrap_or(DEFAULT_TOLERANCE);
        match self.params.coupling {
            Coupling::Force => {
                let mut r =
                    Rotor::new(&self.params, self.start_time, rtol).map_err(|e| e.to_string())?;
                r.set_interface(self.iface);
                Ok(Live::Force(Box::new(r)))
            }
            Coupling::Tlm => TlmRotor::new(&self.params, self.start_time, rtol)
                .map(|r| Live::Tlm(Box::new(r)))
                .map_err(|e| e.to_string()),
        }
    }

    /// Ignored inputs set since initialization that have not been reported yet (each kind
    /// once per instance).
    fn ignored_inputs(&mut self) -> Vec<String> {
        let mut notes = Vec::new();
        let k = IGNORED_FORCE_INPUTS;
        if self.ignored_set[k] && !self.ignored_reported[k] {
            self.ignored_reported[k] = true;
            notes.push(
                "the force-mode inputs bearing.F*, bearing.dF*, bearing.dF_dx*, bearing.dF_dv* \
                 are set but ignored in coupling mode tlm (coupling = 1: the line's tlm.* \
                 outputs and the tlm.v inputs couple the rotor to the BallBearing)"
                    .to_string(),
            );
        }
        let k = IGNORED_TLM_INPUTS;
        if self.ignored_set[k] && !self.ignored_reported[k] {
            self.ignored_reported[k] = true;
            notes.push(
                "the inputs tlm.v.y, tlm.v.z are set but ignored in coupling mode force \
                 (coupling = 0: the bearing.F* inputs act on the journal); set coupling = 1 \
                 (tlm) for the transmission-line coupling"
                    .to_string(),
            );
        }
        notes
    }

    /// The initialization log of coupling mode tlm: the line (events category), and warnings
    /// for an inaccurate delay and for parameters that do not act in this mode.
    fn log_tlm_line(&self, log: &Logger) {
        let p = &self.params;
        let t = p.tlm_delay;
        let zc = p.shaft_k * t;
        let mp = zc * t;
        let t_acc = accurate_delay(p.shaft_k, p.disk_mass);
        log.log(
            Fmi2Status::Ok,
            LOG_EVENTS,
            &format!(
                "coupling = 1 (tlm): the shaft is a transmission line of characteristic \
                 impedance Zc = shaft.k*T = {zc} N.s/m (tlm.Zc = Zc + shaft.c = {} N.s/m) and \
                 delay T = tlm.delay = {t} s; parasitic mass Zc*T = shaft.k*T^2 = {mp} kg = {} % \
                 of disk.mass = {} kg; largest accurate delay T_acc = sqrt(0.01 disk.mass/shaft.k) \
                 = {t_acc} s (parasitic mass <= 1 % of the disk); stability: passive: stable at \
                 any delay",
                zc + p.shaft_c,
                100.0 * mp / p.disk_mass,
                p.disk_mass
            ),
        );
        if t > t_acc {
            log.log(
                Fmi2Status::Warning,
                LOG_STATUS_WARNING,
                &format!(
                    "tlm.delay = {t} s exceeds the largest accurate delay T_acc = \
                     sqrt(0.01 disk.mass/shaft.k) = {t_acc} s: the line's parasitic mass \
                     shaft.k*T^2 = {mp} kg is {} % of disk.mass = {} kg and lowers the disk's \
                     frequencies accordingly (accuracy, not stability: the coupling stays \
                     stable); a smaller communication step and tlm.delay reduce it \
                     quadratically",
                    100.0 * mp / p.disk_mass,
                    p.disk_mass
                ),
            );
        }
        let idle: Vec<String> = [
            ("journal.c", p.journal_c, "N.s/m"),
            ("load.Fx", p.load[0], "N"),
            ("load.Fy", p.load[1], "N"),
            ("load.Fz", p.load[2], "N"),
        ]
        .into_iter()
        .filter(|(_, v, _)| *v != 0.0)
        .map(|(n, v, u)| format!("{n} = {v} {u}"))
        .collect();
        if !idle.is_empty() {
            log.log(
                Fmi2Status::Warning,
                LOG_STATUS_WARNING,
                &format!(
                    "{} do not act in coupling mode tlm (coupling = 1): the journal, its damping \
                     and its loads belong to the BallBearing side (its inner-ring mass and its \
                     load inputs); set them on the bearing and to 0 here",
                    idle.join(", ")
                ),
            );
        }
    }
}

impl Default for JeffcottRotor {
    fn default() -> Self {
        Self::new()
    }
}

fn iface_get(f: &InterfaceForce, r: Role) -> Option<f64> {
    Some(match r {
        Role::F(i) => f.f[i],
        Role::DF(i) => f.df[i],
        Role::K(i, j) => f.k[i][j],
        Role::C(i, j) => f.c[i][j],
        _ => return None,
    })
}

fn iface_set(f: &mut InterfaceForce, r: Role, v: f64) {
    match r {
        Role::F(i) => f.f[i] = v,
        Role::DF(i) => f.df[i] = v,
        Role::K(i, j) => f.k[i][j] = v,
        Role::C(i, j) => f.c[i][j] = v,
        _ => {}
    }
}

fn write_iface(w: &mut ByteWriter, f: &InterfaceForce) {
    for i in 0..3 {
        w.f64(f.f[i]).f64(f.df[i]);
        for j in 0..3 {
            w.f64(f.k[i][j]).f64(f.c[i][j]);
        }
    }
}

fn read_iface(r: &mut ByteReader) -> Result<InterfaceForce, String> {
    let mut f = InterfaceForce::default();
    for i in 0..3 {
        f.f[i] = r.f64("bearing.F")?;
        f.df[i] = r.f64("bearing.dF")?;
        for j in 0..3 {
            f.k[i][j] = r.f64("bearing.dF_dx")?;
            f.c[i][j] = r.f64("bearing.dF_dv")?;
        }
    }
    Ok(f)
}

fn write_axes(w: &mut ByteWriter, v: &[f64; AXES]) {
    for x in v {
        w.f64(*x);
    }
}

fn read_axes(r: &mut ByteReader, what: &str) -> Result<[f64; AXES], String> {
    let mut v = [0.0; AXES];
    for x in &mut v {
        *x = r.f64(what)?;
    }
    Ok(v)
}

fn write_line(w: &mut ByteWriter, h: &LineHistory) {
    for v in [&h.oj_prev, &h.vj_prev, &h.od_prev, &h.od, &h.w_prev, &h.w] {
        write_axes(w, v);
    }
}

fn read_line(r: &mut ByteReader) -> Result<LineHistory, String> {
    Ok(LineHistory {
        oj_prev: read_axes(r, "line o_j")?,
        vj_prev: read_axes(r, "line v_j")?,
        od_prev: read_axes(r, "line o_d")?,
        od: read_axes(r, "line o_d")?,
        w_prev: read_axes(r, "line w")?,
        w: read_axes(r, "line w")?,
    })
}

/// Tags of the live model in the FMU state.
const LIVE_NONE: u8 = 0;
const LIVE_FORCE: u8 = 1;
const LIVE_TLM: u8 = 2;

/// A short decimal of a step size for messages (12 significant digits: 5e-5, not
/// 4.9999999999999996e-5).
fn short(x: f64) -> String {
    let r: f64 = format!("{x:.11e}").parse().unwrap_or(x);
    format!("{r:e}")
}

impl FmuModel for JeffcottRotor {
    const MODEL_IDENTIFIER: &'static str = MODEL_IDENTIFIER;

    fn instantiate(args: &InstantiateArgs, _log: &Logger) -> Result<Self, String> {
        let mut m = Self::new();
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
            if !(t > 0.0 && t < 0.1) {
                return Err(format!(
                    "tolerance = {t}: the integrator's relative tolerance must lie in (0, 0.1)"
                ));
            }
        }
        self.tolerance = tolerance;
        self.start_time = start_time;
        self.live = None;
        Ok(())
    }
    fn exit_initialization(&mut self, log: &Logger) -> Result<(), String> {
        if self.interface == Interface::ModelExchange && self.params.coupling == Coupling::Tlm {
            return Err(
                "Model Exchange: coupling = 1 (tlm) is refused: the transmission line exchanges \
                 waves over communication steps of tlm.delay, a co-simulation device; use \
                 coupling = 0 (force) in Model Exchange"
                    .into(),
            );
        }
        let r = self.build()?;
        if log.enabled(LOG_EVENTS) {
            let p = &self.params;
            log.log(
                Fmi2Status::Ok,
                LOG_EVENTS,
                &format!(
                    "initialized: journal {} kg, disk {} kg, shaft {} N/m, unbalance {} kg.m, speed {} -> {} rad/s, coupling = {} ({})",
                    p.journal_mass, p.disk_mass, p.shaft_k, p.unbalance, p.speed_initial, p.speed_final,
                    p.coupling.code(), p.coupling.name()
                ),
            );
        }
        if self.params.coupling == Coupling::Tlm {
            self.log_tlm_line(log);
        }
        self.live = Some(r);
        self.initialized = true;
        Ok(())
    }
    fn do_step(&mut self, t: f64, t_end: f64, log: &Logger) -> StepResult {
        let tlm_v = self.tlm_v;
        let Some(live) = self.live.as_mut() else {
            return StepResult::Error("no rotor (internal error)".into());
        };
        let before = live.stats();
        let advanced = match live {
            Live::Force(r) => r.advance(t_end),
            Live::Tlm(r) => {
                let (h, d) = (t_end - t, r.line().delay());
                if (h - d).abs() > DELAY_RTOL * d {
                    return StepResult::Error(format!(
                        "communication step {} s differs from the TLM line's delay tlm.delay = \
                         {} s: set tlm.delay to the master's communication step",
                        short(h),
                        short(d)
                    ));
                }
                r.step(tlm_v, t_end)
            }
        };
        if let Err(e) = advanced {
            return StepResult::Discard {
                message: e.to_string(),
                last_good_time: e.t,
            };
        }
        if log.enabled(LOG_SOLVER) {
            let s = live.stats();
            log.log(
                Fmi2Status::Ok,
                LOG_SOLVER,
                &format!(
                    "t = {t} → {t_end}: {} steps, {} rejected, {} rhs evaluations",
                    s.0 - before.0,
                    s.1 - before.1,
                    s.2 - before.2
                ),
            );
        }
        let o = live.outputs(tlm_v);
        let bad = O::ALL.into_iter().find(|k| !k.get(&o).is_finite());
        if let Some(k) = bad {
            return StepResult::Discard {
                message: format!(
                    "output '{}' became {} at t = {t_end}",
                    k.info().0,
                    k.get(&o)
                ),
                last_good_time: t,
            };
        }
        let notes = self.ignored_inputs();
        if notes.is_empty() {
            StepResult::Ok
        } else {
            StepResult::Warning(notes)
        }
    }
    fn reset(&mut self) -> Result<(), String> {
        let interface = self.interface;
        *self = Self::new();
        self.interface = interface;
        Ok(())
    }
    fn get_real(&mut self, index: usize) -> Result<f64, String> {
        let role = self.roles[index];
        if let Some(v) = iface_get(&self.iface, role) {
            return Ok(v);
        }
        match role {
            Role::Param(k) => Ok((PARAMS[k].access.get)(&self.params)),
            Role::Delay => Ok((TLM_DELAY.access.get)(&self.params)),
            Role::TlmV(i) => Ok(self.tlm_v[i]),
            Role::State(i) | Role::Derivative(i) => {
                if self.live.is_none() {
                    self.live = Some(self.build()?);
                }
                match self.live.as_mut() {
                    Some(Live::Force(r)) if matches!(role, Role::State(_)) => Ok(r.state()[i]),
                    Some(Live::Force(r)) => {
                        let mut d = [0.0; crate::jeffcott::DIM];
                        r.derivatives(&mut d);
                        Ok(d[i])
                    }
                    _ => Ok(0.0),
                }
            }
            Role::Out(o) => {
                if self.live.is_none() {
                    self.live = Some(self.build()?);
                }
                let r = self.live.as_mut().expect("just built");
                Ok(o.get(&r.outputs(self.tlm_v)))
            }
            _ => Err(format!("'{}' is not readable", self.vars[index].name)),
        }
    }
    fn set_real(&mut self, index: usize, value: f64) -> Result<(), String> {
        let role = self.roles[index];
        match role {
            Role::Param(k) => {
                let mut next = self.params.clone();
                (PARAMS[k].access.set)(&mut next, value);
                self.params = next;
                self.live = None;
                Ok(())
            }
            Role::Delay => {
                (TLM_DELAY.access.set)(&mut self.params, value);
                self.live = None;
                Ok(())
            }
            Role::TlmV(i) => {
                self.tlm_v[i] = value;
                if self.initialized && self.params.coupling == Coupling::Force {
                    self.ignored_set[IGNORED_TLM_INPUTS] = true;
                }
                Ok(())
            }
            Role::Out(_) | Role::Coupling | Role::State(_) | Role::Derivative(_) => {
                Err(format!("'{}' cannot be set", self.vars[index].name))
            }
            _ => {
                iface_set(&mut self.iface, role, value);
                match self.live.as_mut() {
                    Some(Live::Force(r)) => r.set_interface(self.iface),
                    Some(Live::Tlm(_)) | None => {}
                }
                if self.initialized && self.params.coupling == Coupling::Tlm {
                    self.ignored_set[IGNORED_FORCE_INPUTS] = true;
                }
                Ok(())
            }
        }
    }
    fn get_integer(&mut self, index: usize) -> Result<i32, String> {
        match self.roles[index] {
            Role::Coupling => Ok(self.params.coupling.code()),
            Role::DiskAxial => Ok(i32::from(self.params.disk_axial)),
            _ => Err(format!("'{}' is not an Integer", self.vars[index].name)),
        }
    }
    fn set_integer(&mut self, index: usize, value: i32) -> Result<(), String> {
        match self.roles[index] {
            Role::Coupling => {
                self.params.coupling = Coupling::from_code(value)
                    .ok_or_else(|| format!("coupling = {value}: must be 0 (force) or 1 (tlm)"))?;
                self.live = None;
                Ok(())
            }
            Role::DiskAxial => {
                self.params.disk_axial = match value {
                    0 => false,
                    1 => true,
                    _ => return Err(format!("disk.axial = {value}: must be 0 or 1")),
                };
                self.live = None;
                Ok(())
            }
            _ => Err(format!("'{}' is not an Integer", self.vars[index].name)),
        }
    }
    /// The parameters, the inputs and the ignored-input flags before a multi-value set call.
    type Undo = SetUndo;

    fn begin_set(&self, _indices: &[usize]) -> Self::Undo {
        SetUndo {
            params: self.params.clone(),
            iface: self.iface,
            tlm_v: self.tlm_v,
            ignored_set: self.ignored_set,
        }
    }

    fn rollback_set(&mut self, undo: Self::Undo) -> Result<(), String> {
        if undo.params != self.params {
            self.params = undo.params;
            self.live = None;
        }
        self.iface = undo.iface;
        self.tlm_v = undo.tlm_v;
        self.ignored_set = undo.ignored_set;
        if let Some(Live::Force(r)) = self.live.as_mut() {
            r.set_interface(undo.iface);
        }
        Ok(())
    }

    fn save_state(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.u32(MODEL_STATE_VERSION).u32(PARAMS.len() as u32);
        for p in PARAMS {
            w.f64((p.access.get)(&self.params));
        }
        w.u32(self.params.coupling.code() as u32)
            .f64(self.params.tlm_delay)
            .bool(self.params.disk_axial);
        write_iface(&mut w, &self.iface);
        write_axes(&mut w, &self.tlm_v);
        w.f64(self.start_time).opt_f64(self.tolerance);
        w.bool(self.initialized);
        for k in 0..2 {
            w.bool(self.ignored_set[k]).bool(self.ignored_reported[k]);
        }
        match &self.live {
            Some(Live::Force(r)) => {
                let (s, iface, tk, xk) = r.snapshot();
                w.u8(LIVE_FORCE);
                write_iface(&mut w, &iface);
                w.f64(tk);
                for x in xk {
                    w.f64(x);
                }
                w.bytes(&serde_json::to_vec(&s).expect("an integrator state serializes"));
            }
            Some(Live::Tlm(r)) => {
                let s = r.snapshot();
                w.u8(LIVE_TLM);
                write_line(&mut w, &s.line);
                w.f64(s.journal.t);
                write_axes(&mut w, &s.journal.x);
                write_axes(&mut w, &s.journal.v);
                w.bytes(
                    &serde_json::to_vec(&s.integrator).expect("an integrator state serializes"),
                );
            }
            None => {
                w.u8(LIVE_NONE);
            }
        }
        w.into_bytes()
    }
    fn restore_state(&mut self, bytes: &[u8]) -> Result<(), String> {
        let mut r = ByteReader::new(bytes);
        let v = r.u32("model state version")?;
        if v != MODEL_STATE_VERSION {
            return Err(format!(
                "JeffcottRotor state version {v} is not supported (expected {MODEL_STATE_VERSION})"
            ));
        }
        let n = r.u32("parameter count")? as usize;
        if n != PARAMS.len() {
            return Err(format!(
                "the state has {n} parameters, this FMU {}",
                PARAMS.len()
            ));
        }
        let mut params = RotorParams::default();
        for p in PARAMS {
            (p.access.set)(&mut params, r.f64("parameter")?);
        }
        let code = r.u32("coupling")?;
        params.coupling = i32::try_from(code)
            .ok()
            .and_then(Coupling::from_code)
            .ok_or_else(|| format!("corrupt state: coupling = {code}"))?;
        params.tlm_delay = r.f64("tlm.delay")?;
        params.disk_axial = r.bool("disk.axial")?;
        let iface = read_iface(&mut r)?;
        let tlm_v = read_axes(&mut r, "tlm.v")?;
        let start_time = r.f64("start time")?;
        let tolerance = r.opt_f64("tolerance")?;
        let initialized = r.bool("initialized flag")?;
        let mut ignored_set = [false; 2];
        let mut ignored_reported = [false; 2];
        for k in 0..2 {
            ignored_set[k] = r.bool("ignored-input flag")?;
            ignored_reported[k] = r.bool("ignored-input flag")?;
        }
        let rtol = tolerance.unwrap_or(DEFAULT_TOLERANCE);
        let tag = r.u8("rotor tag")?;
        let integrator = |js: &[u8]| -> Result<IntegratorState, String> {
            serde_json::from_slice(js).map_err(|e| format!("corrupt integrator state: {e}"))
        };
        let live = match (tag, params.coupling) {
            (LIVE_NONE, _) => {
                r.finish("the JeffcottRotor state")?;
                None
            }
            (LIVE_FORCE, Coupling::Force) => {
                let step_iface = read_iface(&mut r)?;
                let tk = r.f64("step start")?;
                let mut xk = [0.0; 6];
                for x in &mut xk {
                    *x = r.f64("step start state")?;
                }
                let s = integrator(r.bytes("integrator state")?)?;
                r.finish("the JeffcottRotor state")?;
                let mut rotor = Rotor::new(&params, start_time, rtol)
                    .map_err(|e| format!("corrupt state: {e}"))?;
                rotor.restore(&s, step_iface, tk, xk)?;
                Some(Live::Force(Box::new(rotor)))
            }
            (LIVE_TLM, Coupling::Tlm) => {
                let line = read_line(&mut r)?;
                let journal = SeenJournal {
                    t: r.f64("journal sample time")?,
                    x: read_axes(&mut r, "journal displacement")?,
                    v: read_axes(&mut r, "journal velocity")?,
                };
                let integrator = integrator(r.bytes("integrator state")?)?;
                r.finish("the JeffcottRotor state")?;
                let mut rotor = TlmRotor::new(&params, start_time, rtol)
                    .map_err(|e| format!("corrupt state: {e}"))?;
                rotor.restore(&TlmSnapshot {
                    integrator,
                    line,
                    journal,
                })?;
                Some(Live::Tlm(Box::new(rotor)))
            }
            (tag, c) => {
                return Err(format!(
                    "corrupt state: rotor tag {tag} with coupling mode {}",
                    c.name()
                ))
            }
        };
        self.params = params;
        self.iface = iface;
        self.tlm_v = tlm_v;
        self.start_time = start_time;
        self.tolerance = tolerance;
        self.live = live;
        self.initialized = initialized;
        self.ignored_set = ignored_set;
        self.ignored_reported = ignored_reported;
        Ok(())
    }

    const MODEL_EXCHANGE: bool = true;

    fn number_of_continuous_states(&self) -> usize {
        crate::jeffcott::DIM
    }

    fn set_time(&mut self, t: f64) -> Result<(), String> {
        let r = self.me_rotor()?;
        let mut y = [0.0; crate::jeffcott::DIM];
        y.copy_from_slice(r.state());
        r.set_state(t, &y)
    }

    fn set_continuous_states(&mut self, x: &[f64]) -> Result<(), String> {
        let r = self.me_rotor()?;
        let t = r.t();
        r.set_state(t, x)
    }

    fn get_continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        x.copy_from_slice(self.me_rotor()?.state());
        Ok(())
    }

    fn get_derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        self.me_rotor()?.derivatives(dx);
        Ok(())
    }

    fn get_event_indicators(&mut self, _g: &mut [f64]) -> Result<(), String> {
        Ok(())
    }

    fn get_nominals(&mut self, nominal: &mut [f64]) -> Result<(), String> {
        Rotor::nominals(nominal);
        Ok(())
    }

    /// Nothing discrete changes; the next time event is the end of the speed ramp.
    fn new_discrete_states(&mut self, _log: &Logger) -> Result<EventUpdate, String> {
        let next = self.me_rotor()?.next_time_event();
        Ok(EventUpdate {
            next_event_time: next,
            warnings: self.ignored_inputs(),
            ..EventUpdate::default()
        })
    }

    fn completed_integrator_step(
        &mut self,
        _inputs_changed: bool,
        _log: &Logger,
    ) -> Result<StepEnd, String> {
        Ok(StepEnd::default())
    }
}

/// `documentation/index.html` of the rotor FMU: the model, the coupling convention and the
/// variable table.
pub fn documentation_html() -> String {
    let mut h = String::new();
    h.push_str("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>JeffcottRotor</title></head><body>\n");
    h.push_str("<h1>JeffcottRotor</h1>\n<p>A Jeffcott rotor with one bearing station, an FMI 2.0 Co-Simulation and Model Exchange FMU built with raceway's generic FMI shell. It is the shaft side of a rotor&ndash;bearing co-simulation with the <code>BallBearing</code> FMU, either in the bearing's motion mode (its <code>coupling = 1</code>; this FMU's <code>coupling = 0</code>, force) or through a transmission line at the shaft (the bearing's <code>coupling = 2</code>; this FMU's <code>coupling = 1</code>, tlm).</p>\n");
    h.push_str("<h2>Model</h2>\n<p>Frame of the bearing: x axial, y and z radial, the shaft turns about +x. A journal of mass m<sub>j</sub> (the inner-ring centre) and a disk of mass m<sub>d</sub> on a massless shaft of lateral stiffness k<sub>s</sub> and damping c<sub>s</sub>; axially the disk rides with the journal. disk.mass = 0 makes a rigid rotor of mass journal.mass carrying the unbalance.</p>\n<pre>\n(m_j + m_d) x''_j = F_x + L_x - c_j x'_j\nm_j y''_j = F_y + L_y - c_j y'_j + k_s (y_d - y_j) + c_s (y'_d - y'_j)\nm_j z''_j = F_z + L_z - c_j z'_j + k_s (z_d - z_j) + c_s (z'_d - z'_j) - m_j g\nm_d y''_d = -k_s (y_d - y_j) - c_s (y'_d - y'_j) + U_y\nm_d z''_d = -k_s (z_d - z_j) - c_s (z'_d - z'_j) - m_d g + U_z\nU = m_u e (W^2 cos phi + W' sin phi, W^2 sin phi - W' cos phi),  phi' = W\n</pre>\n<p>F: force of the bearing on the shaft (input), L: constant load (parameters load.F*), g: gravity along -z, W: shaft speed, ramping from speed.initial to speed.final at speed.rate (closed form, so a run-up needs no input). The state is integrated by DOPRI5 (relative tolerance from fmi2SetupExperiment, default 1e-8).</p>\n");
    h.push_str("<h2>Coupling inputs (coupling = 0, force)</h2>\n<p>Inside a communication step [t<sub>k</sub>, t<sub>k</sub>+H] the bearing force is</p>\n<pre>F(t) = bearing.F + bearing.dF (t - t_k) + bearing.dF_dx (x_j(t) - x_j(t_k)) + bearing.dF_dv (x'_j(t) - x'_j(t_k))</pre>\n<ul><li>Constant-input (Jacobi) coupling: set bearing.F only.</li><li>Linear extrapolation: bearing.dF = (F<sub>k</sub> - F<sub>k-1</sub>)/H.</li><li>Interface Jacobian: bearing.dF_dx and bearing.dF_dv from the BallBearing's fmi2GetDirectionalDerivative of bearing.F.* with respect to journal.* and journal.v.*; the rotor then integrates the linearised bearing reaction inside its step (stable at master steps far beyond the explicit limit &omega;H &lt; 4&zeta;).</li></ul>\n<p>Outputs journal.x/y/z and journal.v.x/y/z connect to the BallBearing's journal inputs, shaft.speed to its shaft.speed.</p>\n");
    h.push_str("<h2>Coupling mode tlm (coupling = 1)</h2>\n<p>Value exchange at the stiff bearing contact (above) is unstable at any useful communication step. With <code>coupling = 1</code> the rotor is cut at the compliant shaft instead: the journal's mass moves into the BallBearing FMU (its <code>coupling = 2</code>, tlm), the rotor keeps the disk (lateral y, z), and the shaft (k<sub>s</sub>, c<sub>s</sub>) becomes a transmission line of delay T = <code>tlm.delay</code> (the master's communication step) and characteristic impedance Z<sub>c</sub> = k<sub>s</sub> T, simulated inside this FMU. Per axis (y, z):</p>\n<pre>\nm_d y''_d = F_line(t) + U_y            m_d z''_d = F_line(t) - m_d g + U_z\nF_line(t) = g_d(t) - (Zc + c_s) v_d + c_s v_j(t - T)\ng_d(t) = o_j(t - T),  o_j = 2 Zc v_j - g_j,  g_j(t) = o_d(t - T),  o_d = 2 Zc v_d - g_d\nforce of the line on the journal: F(t) = c0 + (c1 - c0)(t - t_k)/T - (Zc + c_s) v_j(t)\n  over [t_k, t_k + T], with c0 = w(t_k - T), c1 = w(t_k), w = o_d + c_s v_d\n</pre>\n<p>g<sub>d</sub> and v<sub>j</sub>(t - T) are linear inside a step between their samples. At the start the disk rests in its static equilibrium and the line carries its weight (c0 = c1 = -m<sub>d</sub> g along z). The line is passive: the coupling is stable at any delay; its error is the line's parasitic mass k<sub>s</sub> T<sup>2</sup> (accurate while at most 1 % of the disk: T &le; sqrt(0.01 m<sub>d</sub>/k<sub>s</sub>), logged at initialization with a warning beyond), second order in T, plus that of the damper acting one delay apart, a mass-like c<sub>s</sub> T (first order in T, small for light shaft damping).</p>\n<p>Connections at every communication point (Jacobi or Gauss&ndash;Seidel):</p>\n<ul><li>rotor <code>tlm.c0.y</code>, <code>tlm.c0.z</code>, <code>tlm.c1.y</code>, <code>tlm.c1.z</code>, <code>tlm.Zc</code> &rarr; BallBearing inputs of the same names;</li><li>BallBearing <code>ring.v.y</code>, <code>ring.v.z</code> &rarr; rotor <code>tlm.v.y</code>, <code>tlm.v.z</code>;</li><li><code>shaft.speed</code> &rarr; BallBearing <code>shaft.speed</code> as in force mode.</li></ul>\n<p>The <code>tlm.*</code> outputs depend on the rotor's own state and history only (declared without dependencies in the model description), so the result does not depend on the order in which the master sets and reads. The communication step must equal <code>tlm.delay</code>: a fmi2DoStep of another size returns fmi2Error and changes nothing in the model (the shell's Error state: fmi2SetFMUstate or fmi2Reset lead out). Requires disk.mass &gt; 0 and shaft.k &gt; 0. The force-mode inputs are ignored (set after initialization: one warning); journal.mass, journal.c and load.* do not act (nonzero journal.c or loads: one warning at initialization), and axially nothing moves (the axial direction is the bearing's). The journal outputs show the journal as seen through the line: journal.y/z integrated from tlm.v by the trapezoidal rule from journal.y0/z0, journal.v the received tlm.v, journal.x = journal.x0.</p>\n");
    h.push_str("<h2>Behaviour</h2>\n<ul><li>Any number of instances; no global state; FMU state get/set/serialize supported (including the TLM line's history).</li><li>Invalid parameters (non-finite, negative masses, a disk without shaft stiffness) are rejected at fmi2ExitInitializationMode with a message naming the parameter.</li><li>No directional derivatives, no input derivatives (the coupling inputs above serve instead).</li></ul>\n");
    h.push_str("<h2>Model Exchange</h2>\n<p>The same binary and model description serve <code>fmuType = fmi2ModelExchange</code> in coupling mode force (<code>coupling = 0</code>): the importer integrates the rotor's 10 states (<code>state[1]</code> &hellip; <code>state[10]</code>, vr 2000 + i: journal x, y, z, its velocities, disk y, z and their velocities; <code>der(state[i])</code>, vr 3000 + i) with its own solver. There are no event indicators; the end of the speed ramp is a time event (nextEventTime). The bearing force is the law above anchored at the time and state at which <code>bearing.*</code> was last set (set them at every evaluation, with the rates and Jacobians 0, for a force that follows the importer). Coupling mode tlm is refused at fmi2ExitInitializationMode: the transmission line exchanges waves over communication steps of <code>tlm.delay</code>, a co-simulation device.</p>\n");
    h.push_str("<h2>Variables</h2>\n<table border=\"1\"><tr><th>name</th><th>vr</th><th>causality</th><th>unit</th><th>start</th><th>description</th></tr>\n");
    let enums = enumerations();
    for (v, _) in table() {
        let item = |x: i32| {
            let t = v.declared_type.as_ref()?;
            enums.iter().find(|e| &e.name == t)?.item(x)
        };
        let start = match v.start {
            Start::Real(x) => format!("{x}"),
            Start::Integer(x) => match item(x) {
                Some(i) => format!("{x} ({})", xml::esc(&i.name)),
                None => format!("{x}"),
            },
            _ => String::new(),
        };
        h.push_str(&format!(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
            xml::esc(&v.name),
            v.vr,
            v.causality.name(),
            xml::esc(v.unit.as_deref().unwrap_or("")),
            start,
            xml::esc(&v.description)
        ));
    }
    h.push_str("</table>\n</body></html>\n");
    h
}
