//! The BallBearing FMU's variable table: one row per variable with its value reference written
//! out, its metadata and its accessors, the one source of truth for the runtime
//! ([`crate::ballbearing`]), the model description ([`fmi2::xml`]) and the documentation
//! ([`crate::docs`]). A parameter is added with one row of [`ROWS`]; value references never
//! move (a new variable takes a new one).
//!
//! Value references: inputs 1–4, journal inputs 5–10, transmission-line inputs 11–15, ring
//! velocity outputs 16–18, parameters 100–129, solver counters 900–902, written out in
//! [`ROWS`]; the parameters of spalls 2–4, 130–144, in [`SPALL_ROWS`]; the real outputs are
//! 1000 + i, i being the position in [`raceway::output_table_with_cage`] (their number depends
//! on the bearing's ball count; the cage block comes last, so the others keep their
//! references).
//! Start values of inputs and parameters are the base scene's: the default scene on the FMU's
//! bearing, or the FMU's scene resource (`resources/scene.toml`).

use fmi2::table::Row;
use fmi2::{
    Causality, EnumerationItem, EnumerationType, Initial, Start, VarType, Variability, Variable,
};
use raceway::models::LEVELS;
use raceway::{
    output_table_with_cage, AxialMount, BearingFile, CageSpeed, CouplingMode, DefectMode,
    DefectSpec, Fidelity, Journal, MethodName, Mounting, OperatingPoint, Scene, Site, WorkStats,
};
use Causality::{Input as In, Output as Out, Parameter};
use VarType::{Enumeration, Integer, Real};

/// What a variable reads and writes.
#[derive(Debug, Clone, Copy)]
pub enum Access {
    /// A field of the operating inputs; `load`: a component of the external load (in coupling
    /// mode motion it only sets the quasi-static start, so the outputs do not depend on it
    /// directly).
    Input {
        /// Reads the input.
        get: fn(&OperatingPoint) -> f64,
        /// Writes the input (the value has passed the shell's checks).
        set: fn(&mut OperatingPoint, f64),
        /// Whether it is a load component.
        load: bool,
    },
    /// Journal input `k` of coupling mode motion: displacement x, y, z (k = 0..3), then
    /// velocity (k = 3..6).
    Journal(usize),
    /// Input `k` of the transmission-line (TLM) port, coupling mode tlm: the line's wave on
    /// the journal at the step's start (k = 0, 1: y, z) and end (k = 2, 3: y, z) and its
    /// impedance (k = 4).
    Line(usize),
    /// The inner ring's velocity along x, y, z (k = 0..3), a Real output.
    RingVelocity(usize),
    /// A structural parameter (Integers pass as exact `f64`).
    Param {
        /// Reads the parameter.
        get: fn(&Config) -> f64,
        /// Writes the parameter; `Err` for a value the model refuses.
        set: fn(&mut Config, f64) -> Result<(), String>,
    },
    /// A solver work counter (Integer output).
    Stat(fn(&WorkStats) -> u64),
    /// Position in the simulation's output vector (Real output; generated rows only).
    Output(usize),
    /// Model Exchange: continuous state `i` (`state[i + 1]`, a local Real; beyond the level's
    /// number of states a padding state, 0).
    State(usize),
    /// Model Exchange: the derivative of continuous state `i` (`der(state[i + 1])`; 0 for a
    /// padding state).
    Derivative(usize),
}

/// Value reference of `state[i + 1]` (Model Exchange); its derivative is `DERIVATIVE_VR + i`.
pub const STATE_VR: u32 = 2000;
/// Value reference of `der(state[i + 1])`.
pub const DERIVATIVE_VR: u32 = 3000;

/// One row of the table.
pub type VarRow = Row<Access>;

const IMAX: f64 = i32::MAX as f64;

/// A Real continuous input row.
#[allow(clippy::too_many_arguments)]
const fn input(
    vr: u32,
    name: &'static str,
    unit: &'static str,
    min: Option<f64>,
    description: &'static str,
    get: fn(&OperatingPoint) -> f64,
    set: fn(&mut OperatingPoint, f64),
    load: bool,
) -> VarRow {
    Row {
        vr,
        name,
        ty: Real,
        causality: In,
        variability: Variability::Continuous,
        initial: None,
        unit: Some(unit),
        declared_type: None,
        min,
        max: None,
        description,
        access: Access::Input { get, set, load },
    }
}

/// A journal input row (metres or metres per second).
const fn journal(vr: u32, name: &'static str, k: usize, description: &'static str) -> VarRow {
    Row {
        vr,
        name,
        ty: Real,
        causality: In,
        variability: Variability::Continuous,
        initial: None,
        unit: Some(if k < 3 { "m" } else { "m/s" }),
        declared_type: None,
        min: None,
        max: None,
        description,
        access: Access::Journal(k),
    }
}

/// A transmission-line input row (see [`Access::Line`]).
const fn line(
    vr: u32,
    name: &'static str,
    k: usize,
    unit: &'static str,
    description: &'static str,
) -> VarRow {
    Row {
        vr,
        name,
        ty: Real,
        causality: In,
        variability: Variability::Continuous,
        initial: None,
        unit: Some(unit),
        declared_type: None,
        min: if k == 4 { Some(0.0) } else { None },
        max: None,
        description,
        access: Access::Line(k),
    }
}

/// A ring-velocity output row (m/s).
const fn ring_velocity(vr: u32, name: &'static str, k: usize, description: &'static str) -> VarRow {
    Row {
        vr,
        name,
        ty: Real,
        causality: Out,
        variability: Variability::Continuous,
        initial: Some(Initial::Calculated),
        unit: Some("m/s"),
        declared_type: None,
        min: None,
        max: None,
        description,
        access: Access::RingVelocity(k),
    }
}

/// A fixed parameter row (`initial="exact"`).
#[allow(clippy::too_many_arguments)]
const fn param(
    vr: u32,
    name: &'static str,
    ty: VarType,
    unit: Option<&'static str>,
    (min, max): (Option<f64>, Option<f64>),
    description: &'static str,
    get: fn(&Config) -> f64,
    set: fn(&mut Config, f64) -> Result<(), String>,
) -> VarRow {
    Row {
        vr,
        name,
        ty,
        causality: Parameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Exact),
        unit,
        declared_type: None,
        min,
        max,
        description,
        access: Access::Param { get, set },
    }
}

/// A fixed parameter row that chooses among the items of the enumeration type `declared_type`
/// (one of [`enumerations`]); its `min` and `max` are the items' range (set by [`table`]).
const fn choice(
    vr: u32,
    name: &'static str,
    declared_type: &'static str,
    description: &'static str,
    get: fn(&Config) -> f64,
    set: fn(&mut Config, f64) -> Result<(), String>,
) -> VarRow {
    Row {
        vr,
        name,
        ty: Enumeration,
        causality: Parameter,
        variability: Variability::Fixed,
        initial: Some(Initial::Exact),
        unit: None,
        declared_type: Some(declared_type),
        min: None,
        max: None,
        description,
        access: Access::Param { get, set },
    }
}

/// A solver-counter row (Integer output).
const fn stat(
    vr: u32,
    name: &'static str,
    description: &'static str,
    get: fn(&WorkStats) -> u64,
) -> VarRow {
    Row {
        vr,
        name,
        ty: Integer,
        causality: Out,
        variability: Variability::Discrete,
        initial: Some(Initial::Calculated),
        unit: None,
        declared_type: None,
        min: None,
        max: None,
        description,
        access: Access::Stat(get),
    }
}

/// Every variable but the real outputs, in the model description's order (the outputs, 1000
/// + i, come between the parameters and the solver counters).
pub const ROWS: &[VarRow] = &[
    input(
        1,
        "shaft.speed",
        "rad/s",
        Some(0.0),
        "Shaft (inner-ring) speed about +x (>= 0)",
        |i| i.shaft_speed,
        |i, v| i.shaft_speed = v,
        false,
    ),
    input(
        2,
        "load.Fx",
        "N",
        None,
        "External force on the inner ring along x (axial load Fa, +x)",
        |i| i.fx,
        |i, v| i.fx = v,
        true,
    ),
    input(
        3,
        "load.Fy",
        "N",
        None,
        "External force on the inner ring along y",
        |i| i.fy,
        |i, v| i.fy = v,
        true,
    ),
    input(
        4,
        "load.Fz",
        "N",
        None,
        "External force on the inner ring along z (the paper's radial load: Fz = -Fr)",
        |i| i.fz,
        |i, v| i.fz = v,
        true,
    ),
    journal(
        5,
        "journal.x",
        0,
        "Journal (inner-ring centre) displacement along x in coupling mode motion, same frame and origin as ring.x; ignored in force mode",
    ),
    journal(
        6,
        "journal.y",
        1,
        "Journal (inner-ring centre) displacement along y in coupling mode motion, same frame and origin as ring.y; ignored in force mode",
    ),
    journal(
        7,
        "journal.z",
        2,
        "Journal (inner-ring centre) displacement along z in coupling mode motion, same frame and origin as ring.z; ignored in force mode",
    ),
    journal(
        8,
        "journal.v.x",
        3,
        "Journal (inner-ring centre) velocity along x in coupling mode motion: within a communication step the ring moves as x_k + v_k (t - t_k); ignored in force mode",
    ),
    journal(
        9,
        "journal.v.y",
        4,
        "Journal (inner-ring centre) velocity along y in coupling mode motion: within a communication step the ring moves as x_k + v_k (t - t_k); ignored in force mode",
    ),
    journal(
        10,
        "journal.v.z",
        5,
        "Journal (inner-ring centre) velocity along z in coupling mode motion: within a communication step the ring moves as x_k + v_k (t - t_k); ignored in force mode",
    ),
    line(
        11,
        "tlm.c0.y",
        0,
        "N",
        "Coupling mode tlm: the line's force on the journal along y at the start of the communication step (connect the JeffcottRotor's tlm.c0.y); ignored in the other modes",
    ),
    line(
        12,
        "tlm.c0.z",
        1,
        "N",
        "Coupling mode tlm: the line's force on the journal along z at the start of the communication step (connect the JeffcottRotor's tlm.c0.z); ignored in the other modes",
    ),
    line(
        13,
        "tlm.c1.y",
        2,
        "N",
        "Coupling mode tlm: the line's force on the journal along y at the end of the communication step; the inner ring feels F = c0 + (c1 - c0)(t - t_k)/H - Zc v over the step (connect the JeffcottRotor's tlm.c1.y); ignored in the other modes",
    ),
    line(
        14,
        "tlm.c1.z",
        3,
        "N",
        "Coupling mode tlm: the line's force on the journal along z at the end of the communication step (connect the JeffcottRotor's tlm.c1.z); its value at initialization is the line's force at rest, part of the start's equilibrium; ignored in the other modes",
    ),
    line(
        15,
        "tlm.Zc",
        4,
        "N.s/m",
        "Coupling mode tlm: the line's characteristic impedance (with the shaft damping it carries), acting as a damper on the journal's y and z velocity (connect the JeffcottRotor's tlm.Zc); ignored in the other modes",
    ),
    ring_velocity(
        16,
        "ring.v.x",
        0,
        "Inner-ring (journal) velocity along x on the lumped, reduced and full levels (in motion mode the journal.v.x input); 0 on the kinematic and quasi-static levels, whose ring is quasi-static",
    ),
    ring_velocity(
        17,
        "ring.v.y",
        1,
        "Inner-ring (journal) velocity along y (coupling mode tlm: connect it to the JeffcottRotor's tlm.v.y); see ring.v.x",
    ),
    ring_velocity(
        18,
        "ring.v.z",
        2,
        "Inner-ring (journal) velocity along z (coupling mode tlm: connect it to the JeffcottRotor's tlm.v.z); see ring.v.x",
    ),
    choice(
        100,
        "fidelity",
        "Fidelity",
        // Written from the level registry by `table` (fidelity_description).
        "",
        |c| c.scene.fidelity.code() as f64,
        |c, v| {
            let code = v as i32;
            c.scene.fidelity = Fidelity::from_code(code).ok_or_else(|| {
                format!("fidelity = {code}: valid codes are 0..{}", LEVELS.len() - 1)
            })?;
            Ok(())
        },
    ),
    // An Integer, not an Enumeration like the other switches: libcosim (libcosimpy 0.0.6)
    // ignores Enumeration variables ("FMI 2.0 Enumeration variable type not supported"), and
    // a rotor-bearing system run there (examples/systems) must set the coupling mode.
    param(
        101,
        "coupling",
        Integer,
        None,
        (Some(0.0), Some(2.0)),
        "Coupling mode: 0 force (load.F* in, the inner ring integrated inside), 1 motion (journal.* displacement and velocity in, bearing.F = the reaction on the journal out; load.F* only set the quasi-static start), 2 tlm (force mode plus a transmission line through the shaft to the JeffcottRotor: tlm.c0/c1/Zc in, ring.v.y/z out; the journal's mass is the inner ring's; stable at any communication step; lumped, reduced and full levels)",
        |c| if c.tlm { 2.0 } else { c.scene.coupling.code() as f64 },
        |c, v| {
            let code = v as i32;
            c.tlm = code == 2;
            c.scene.coupling = match code {
                2 => CouplingMode::Force,
                _ => CouplingMode::from_code(code).ok_or_else(|| {
                    format!("coupling = {code}: valid codes are 0 (force), 1 (motion) and 2 (tlm)")
                })?,
            };
            Ok(())
        },
    ),
    choice(
        102,
        "defect.ring",
        "DefectRing",
        "Spalled ring: 0 none (healthy), 1 outer race, 2 inner race, 3 a ball (defect.ball; not at the quasi-static level)",
        |c| c.spalls[0].ring as f64,
        |c, v| {
            c.spalls[0].ring = v as i32;
            Ok(())
        },
    ),
    param(
        103,
        "defect.width",
        Real,
        Some("m"),
        (Some(0.0), Some(0.1)),
        "Spall width along the track w_d (> 0, smaller than the ball diameter)",
        |c| c.spalls[0].width,
        |c, v| {
            c.spalls[0].width = v;
            Ok(())
        },
    ),
    param(
        104,
        "defect.depth",
        Real,
        Some("m"),
        (Some(0.0), Some(0.1)),
        "Spall depth h_d (> 0)",
        |c| c.spalls[0].depth,
        |c, v| {
            c.spalls[0].depth = v;
            Ok(())
        },
    ),
    param(
        105,
        "defect.theta0",
        Real,
        Some("rad"),
        (None, None),
        "Angular position of the spall centre (pi = load-zone centre of a load along -z; inner ring: at shaft angle 0)",
        |c| c.spalls[0].theta0,
        |c, v| {
            c.spalls[0].theta0 = v;
            Ok(())
        },
    ),
    choice(
        106,
        "defect.mode",
        "DefectMode",
        "Spall model: 0 finite-size ball resting on the edges (default), 1 paper-literal point contact",
        |c| match c.scene.bearing.defect.mode {
            DefectMode::Finite => 0.0,
            DefectMode::Point => 1.0,
        },
        |c, v| {
            c.scene.bearing.defect.mode = if v as i32 == 0 {
                DefectMode::Finite
            } else {
                DefectMode::Point
            };
            Ok(())
        },
    ),
    param(
        107,
        "pedestal.mass",
        Real,
        Some("kg"),
        (Some(0.0), None),
        "Pedestal mass including the outer ring (> 0)",
        |c| c.scene.bearing.pedestal.mass,
        |c, v| {
            c.scene.bearing.pedestal.mass = v;
            Ok(())
        },
    ),
    param(
        108,
        "pedestal.k_y",
        Real,
        Some("N/m"),
        (Some(0.0), None),
        "Pedestal support stiffness along y (> 0)",
        |c| c.scene.bearing.pedestal.k_y,
        |c, v| {
            c.scene.bearing.pedestal.k_y = v;
            Ok(())
        },
    ),
    param(
        109,
        "pedestal.k_z",
        Real,
        Some("N/m"),
        (Some(0.0), None),
        "Pedestal support stiffness along z (> 0)",
        |c| c.scene.bearing.pedestal.k_z,
        |c, v| {
            c.scene.bearing.pedestal.k_z = v;
            Ok(())
        },
    ),
    param(
        110,
        "pedestal.c_y",
        Real,
        Some("N.s/m"),
        (Some(0.0), None),
        "Pedestal support damping along y",
        |c| c.scene.bearing.pedestal.c_y,
        |c, v| {
            c.scene.bearing.pedestal.c_y = v;
            Ok(())
        },
    ),
    param(
        111,
        "pedestal.c_z",
        Real,
        Some("N.s/m"),
        (Some(0.0), None),
        "Pedestal support damping along z",
        |c| c.scene.bearing.pedestal.c_z,
        |c, v| {
            c.scene.bearing.pedestal.c_z = v;
            Ok(())
        },
    ),
    param(
        112,
        "inner_ring.mass",
        Real,
        Some("kg"),
        (Some(0.0), None),
        "Inner ring (and shaft share) mass (> 0)",
        |c| c.scene.bearing.inner_ring.mass,
        |c, v| {
            c.scene.bearing.inner_ring.mass = v;
            Ok(())
        },
    ),
    param(
        113,
        "contact.c_br",
        Real,
        Some("N.s/m"),
        (Some(0.0), None),
        "Ball-race normal contact damping",
        |c| c.scene.bearing.contact.c_br,
        |c, v| {
            c.scene.bearing.contact.c_br = v;
            Ok(())
        },
    ),
    param(
        114,
        "traction.kappa_0",
        Real,
        None,
        (Some(0.0), Some(1.0)),
        "Traction coefficient at zero slip",
        |c| c.scene.bearing.traction.kappa_0,
        |c, v| {
            c.scene.bearing.traction.kappa_0 = v;
            Ok(())
        },
    ),
    param(
        115,
        "traction.kappa_max",
        Real,
        None,
        (Some(0.0), Some(1.0)),
        "Maximum traction coefficient (>= kappa_0 and >= kappa_inf)",
        |c| c.scene.bearing.traction.kappa_max,
        |c, v| {
            c.scene.bearing.traction.kappa_max = v;
            Ok(())
        },
    ),
    param(
        116,
        "traction.u_max",
        Real,
        Some("m/s"),
        (Some(0.0), None),
        "Slip speed at the traction maximum (> 0)",
        |c| c.scene.bearing.traction.u_max,
        |c, v| {
            c.scene.bearing.traction.u_max = v;
            Ok(())
        },
    ),
    param(
        117,
        "traction.kappa_inf",
        Real,
        None,
        (Some(0.0), Some(1.0)),
        "Traction coefficient at large slip",
        |c| c.scene.bearing.traction.kappa_inf,
        |c, v| {
            c.scene.bearing.traction.kappa_inf = v;
            Ok(())
        },
    ),
    param(
        118,
        "lumped.slip_jitter",
        Real,
        None,
        (Some(0.0), Some(0.5)),
        "Random ball slip (lumped level): standard deviation as a fraction of the ball spacing, in [0, 0.5)",
        |c| c.scene.lumped.slip_jitter,
        |c, v| {
            c.scene.lumped.slip_jitter = v;
            Ok(())
        },
    ),
    param(
        119,
        "lumped.seed",
        Integer,
        None,
        (Some(0.0), Some(IMAX)),
        "Seed of the random ball slip",
        |c| c.scene.lumped.seed.min(i32::MAX as u64) as f64,
        |c, v| {
            c.scene.lumped.seed = (v as i32).max(0) as u64;
            Ok(())
        },
    ),
    choice(
        120,
        "solver.method",
        "IntegrationMethod",
        "Integration method: 0 RKF45, 1 DOPRI5, 2 DOP853",
        |c| c.scene.solver.method.code() as f64,
        |c, v| {
            let code = v as i32;
            c.scene.solver.method = MethodName::from_code(code)
                .ok_or_else(|| format!("solver.method = {code}: valid codes are 0, 1, 2"))?;
            Ok(())
        },
    ),
    param(
        121,
        "solver.rtol",
        Real,
        None,
        (Some(raceway::MIN_RTOL), Some(0.1)),
        "Relative tolerance of the integrator in (0, 0.1); fmi2SetupExperiment's tolerance, when defined, overrides it",
        |c| c.scene.solver.rtol,
        |c, v| {
            c.scene.solver.rtol = v;
            Ok(())
        },
    ),
    param(
        122,
        "solver.max_steps",
        Integer,
        None,
        (Some(1.0), Some(IMAX)),
        "Work budget per communication step: attempted integrator steps and, at the kinematic level, spall passes registered (one unit each); when exhausted the step returns fmi2Discard and the FMU stays at the step's start",
        |c| c.scene.solver.max_steps.min(i32::MAX as u64) as f64,
        |c, v| {
            c.scene.solver.max_steps = (v as i32).max(1) as u64;
            Ok(())
        },
    ),
    choice(
        123,
        "lumped.cage_speed",
        "CageSpeed",
        "Cage speed of the kinematic, quasi-static and lumped levels: 0 the traction's caged balance (default: the common orbital rate at which the traction's orbital torques on the balls cancel, each ball in its steady spin), 1 L1's outer-race control",
        |c| c.scene.lumped.cage_speed.code() as f64,
        |c, v| {
            let code = v as i32;
            c.scene.lumped.cage_speed = CageSpeed::from_code(code)
                .ok_or_else(|| format!("lumped.cage_speed = {code}: valid codes are 0, 1"))?;
            Ok(())
        },
    ),
    param(
        124,
        "solver.pi_beta",
        Real,
        None,
        (Some(0.0), Some(raceway::MAX_PI_BETA)),
        "Beta of the PI step-size controller in [0, 0.2]; 0 (default) the I-controller, the more accurate at equal work at rtol 1e-6 and tighter",
        |c| c.scene.solver.pi_beta,
        |c, v| {
            c.scene.solver.pi_beta = v;
            Ok(())
        },
    ),
    choice(
        125,
        "ring.axial",
        "AxialMounting",
        "Axial mounting of the inner ring (force coupling): 0 the axial load load.Fx acts on it (default); 1 located where the start's load.Fx alone puts it (a preload; centred with the balls just touching at load.Fx = 0); 2 located at ring.axial_offset. Located, the ring carries a pure radial load, bearing.F.x is the axial reaction of its location, and load.Fx cannot change after the start",
        |c| match (c.scene.mounting.axial, c.scene.mounting.axial_offset) {
            (AxialMount::Load, _) => 0.0,
            (AxialMount::Located, None) => 1.0,
            (AxialMount::Located, Some(_)) => 2.0,
        },
        |c, v| {
            c.scene.mounting = match v as i32 {
                0 => Mounting::default(),
                1 => Mounting {
                    axial: AxialMount::Located,
                    axial_offset: None,
                },
                2 => Mounting {
                    axial: AxialMount::Located,
                    axial_offset: Some(c.axial_offset),
                },
                code => return Err(format!("ring.axial = {code}: valid codes are 0, 1, 2")),
            };
            Ok(())
        },
    ),
    param(
        126,
        "ring.axial_offset",
        Real,
        Some("m"),
        (Some(-1e-3), Some(1e-3)),
        "Axial displacement of a located inner ring (ring.axial = 2) from the unloaded, centred position, along +x (the way load.Fx > 0 pushes it)",
        |c| c.axial_offset,
        |c, v| {
            c.axial_offset = v;
            if c.scene.mounting.axial_offset.is_some() {
                c.scene.mounting.axial_offset = Some(v);
            }
            Ok(())
        },
    ),
    param(
        127,
        "solver.warn_steps",
        Integer,
        None,
        (Some(0.0), Some(IMAX)),
        "Integrator steps (accepted and rejected) in one communication step above which fmi2DoStep returns fmi2Warning and says how many it took (a long communication step, or stiff dynamics such as a coupling running away); 0: never",
        |c| c.warn_steps.min(i32::MAX as u64) as f64,
        |c, v| {
            c.warn_steps = (v as i32).max(0) as u64;
            Ok(())
        },
    ),
    choice(
        128,
        "cage",
        "Cage",
        "The cage of the reduced and full levels: 1 a rigid cage with its pockets, guided by the balls or a ring land, its constants from the bearing's [cage] (default; cage.speed is then the cage's own rate and cage.y, cage.z, cage.pocket.P[j] its whirl and pocket forces); 0 the paper's cage-less balls, which touch each other where they drift together (the cage outputs stay 0). The other levels have no cage body either way",
        |c| f64::from(u8::from(c.scene.full.cage)),
        |c, v| {
            c.scene.full.cage = match v as i32 {
                0 => false,
                1 => true,
                code => return Err(format!("cage = {code}: valid codes are 0 (none), 1 (a cage)")),
            };
            Ok(())
        },
    ),
    param(
        129,
        "defect.ball",
        Integer,
        None,
        (Some(1.0), Some(IMAX)),
        "The spalled ball's number (from 1, at most the bearing's ball count) when defect.ring = 3 (ball)",
        |c| f64::from(c.spalls[0].ball),
        |c, v| {
            c.spalls[0].ball = v as i32;
            Ok(())
        },
    ),
    stat(900, "solver.steps", "Accepted integrator steps since the start", |s| s.steps),
    stat(901, "solver.rejected", "Rejected integrator steps since the start", |s| s.rejected),
    stat(902, "solver.rhs_evals", "Right-hand-side evaluations since the start", |s| s.rhs_evals),
];

/// The scene resource's name in messages (`resources/scene.toml`).
pub const SCENE_RESOURCE_NAME: &str = "resources/scene.toml";

/// Number of spalls that are parameters: `defect.*` (spall 1) and `defect2.*` … `defect4.*`.
pub const SPALL_SLOTS: usize = 4;

/// The rows of parameter spall `$k + 1` (`$k` = 1, 2, 3: spalls 2, 3, 4), value references
/// `$vr` … `$vr + 4`: ring, width, depth, theta0, ball, like `defect.*`.
macro_rules! spall_rows {
    ($(($k:literal, $vr:literal, $g:literal, $n:literal)),* $(,)?) => {
        /// The parameters of spalls 2 … [`SPALL_SLOTS`] (value references 130–144, after every
        /// older one), listed in the model description after the Model Exchange states so that
        /// the indices of the older variables (which `ModelStructure` uses) do not move.
        pub const SPALL_ROWS: &[VarRow] = &[$(
            choice(
                $vr,
                concat!($g, ".ring"),
                "DefectRing",
                concat!("Spall ", $n, ": its ring, 0 none (absent), 1 outer race, 2 inner race, 3 a ball (", $g, ".ball; not at the quasi-static level); the simulation's spalls are defect.* and ", "defect2.* … defect4.* whose ring is not 0, in that order, then the scene resource's spalls 5 and later"),
                |c| f64::from(c.spalls[$k].ring),
                |c, v| {
                    c.spalls[$k].ring = v as i32;
                    Ok(())
                },
            ),
            param(
                $vr + 1,
                concat!($g, ".width"),
                Real,
                Some("m"),
                (Some(0.0), Some(0.1)),
                concat!("Spall ", $n, ": width along the track w_d (> 0, smaller than the ball diameter)"),
                |c| c.spalls[$k].width,
                |c, v| {
                    c.spalls[$k].width = v;
                    Ok(())
                },
            ),
            param(
                $vr + 2,
                concat!($g, ".depth"),
                Real,
                Some("m"),
                (Some(0.0), Some(0.1)),
                concat!("Spall ", $n, ": depth h_d (> 0)"),
                |c| c.spalls[$k].depth,
                |c, v| {
                    c.spalls[$k].depth = v;
                    Ok(())
                },
            ),
            param(
                $vr + 3,
                concat!($g, ".theta0"),
                Real,
                Some("rad"),
                (None, None),
                concat!("Spall ", $n, ": angular position of its centre, as defect.theta0 (two spalls on one ring must not overlap)"),
                |c| c.spalls[$k].theta0,
                |c, v| {
                    c.spalls[$k].theta0 = v;
                    Ok(())
                },
            ),
            param(
                $vr + 4,
                concat!($g, ".ball"),
                Integer,
                None,
                (Some(1.0), Some(IMAX)),
                concat!("Spall ", $n, ": the spalled ball's number (from 1, at most the bearing's ball count) when ", $g, ".ring = 3 (ball)"),
                |c| f64::from(c.spalls[$k].ball),
                |c, v| {
                    c.spalls[$k].ball = v as i32;
                    Ok(())
                },
            ),
        )*];
    };
}

spall_rows!(
    (1, 130, "defect2", "2"),
    (2, 135, "defect3", "3"),
    (3, 140, "defect4", "4"),
);

/// Every row: [`ROWS`], then [`SPALL_ROWS`].
pub fn all_rows() -> impl Iterator<Item = &'static VarRow> {
    ROWS.iter().chain(SPALL_ROWS)
}

/// The parameter rows, in value-reference order (the order of the FMU state's parameters).
pub fn params() -> impl Iterator<Item = &'static VarRow> {
    all_rows().filter(|r| matches!(r.access, Access::Param { .. }))
}

/// The row of the variable called `name`.
pub fn row(name: &str) -> Option<&'static VarRow> {
    all_rows().find(|r| r.name == name)
}

/// Journal input `k` of `j` (see [`Access::Journal`]).
pub fn journal_get(j: &Journal, k: usize) -> f64 {
    if k < 3 {
        j.x[k]
    } else {
        j.v[k - 3]
    }
}

/// Sets journal input `k` of `j`.
pub fn journal_set(j: &mut Journal, k: usize, v: f64) {
    if k < 3 {
        j.x[k] = v
    } else {
        j.v[k - 3] = v
    }
}

/// A spall as the FMU's parameters describe it (kept even while its ring is 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DefectParams {
    /// 0 none, 1 outer, 2 inner, 3 a ball.
    pub ring: i32,
    /// The ball's number (from 1) with `ring` = 3.
    pub ball: i32,
    pub width: f64,
    pub depth: f64,
    pub theta0: f64,
}

impl DefectParams {
    /// Spall 1 of `scene` (its size and place those of the default scene's spall when the
    /// scene has none, with ring 0).
    pub fn from_scene(scene: &Scene) -> Self {
        Self::from_spec(scene.defect.as_ref())
    }

    /// The parameters of `spec`; `None`: ring 0, with the default scene's spall's size and
    /// place as the start values of the other fields.
    pub fn from_spec(spec: Option<&DefectSpec>) -> Self {
        // (the default scene is parsed only for an absent spall)
        let fallback = spec
            .is_none()
            .then(|| Scene::default_scene().defect)
            .flatten();
        let (width, depth, theta0) = spec
            .or(fallback.as_ref())
            .map_or((1e-3, 0.2e-3, std::f64::consts::PI), |d| {
                (d.width, d.depth, d.theta0)
            });
        let (ring, ball) = match spec.map(|d| d.ring) {
            None => (0, 1),
            Some(Site::Outer) => (1, 1),
            Some(Site::Inner) => (2, 1),
            Some(Site::Ball(k)) => (3, i32::try_from(k).unwrap_or(i32::MAX)),
        };
        Self {
            ring,
            ball,
            width,
            depth,
            theta0,
        }
    }

    /// The scene's spall (`None` with ring 0).
    pub fn spec(&self) -> Option<DefectSpec> {
        let ring = match self.ring {
            1 => Site::Outer,
            2 => Site::Inner,
            // A number below 1 stays as given for the scene's check to refuse (defect.ball).
            3 => Site::Ball(usize::try_from(self.ball).unwrap_or(0)),
            _ => return None,
        };
        Some(DefectSpec {
            ring,
            width: self.width,
            depth: self.depth,
            theta0: self.theta0,
        })
    }
}

/// The FMU name of parameter spall `slot` (0-based): `defect`, `defect2`, …
pub fn slot_name(slot: usize) -> String {
    if slot == 0 {
        "defect".into()
    } else {
        format!("defect{}", slot + 1)
    }
}

/// Everything the parameters edit: the scene (bearing, fidelity, solver, ...) and the spalls.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The base scene (the default scene on the FMU's bearing, or the scene resource). Its
    /// operating point is replaced by the inputs and its spalls by [`Config::spall_list`] when
    /// the simulation is built ([`Config::scene_with_spalls`]).
    pub scene: Scene,
    /// The parameter spalls: `defect.*`, `defect2.*` … `defect4.*`.
    pub spalls: [DefectParams; SPALL_SLOTS],
    /// The scene resource's own `mode` of its spalls 1 … 4, kept with the parameter spall of
    /// the same number (None: the shared `defect.mode`). Fixed.
    pub slot_modes: [Option<DefectMode>; SPALL_SLOTS],
    /// The scene resource's spalls 5 and later, with their modes: fixed, after the parameter
    /// spalls.
    pub fixed: Vec<(DefectSpec, Option<DefectMode>)>,
    /// `ring.axial_offset` as set (it enters the scene's mounting with `ring.axial` = 2).
    pub axial_offset: f64,
    /// `solver.warn_steps`: integrator steps per communication step above which a step warns
    /// (0: never).
    pub warn_steps: u64,
    /// Coupling mode tlm (`coupling` = 2): force mode plus the transmission line's port.
    pub tlm: bool,
}

/// Default of `solver.warn_steps`: a communication step of 0.1 ms at the full level takes
/// tens of integrator steps; 100 000 means the step is far too long for what the bearing does.
pub const DEFAULT_WARN_STEPS: u64 = 100_000;

impl Config {
    /// The default scene on `bearing` (the FMU without a scene resource).
    pub fn default_for(bearing: &BearingFile) -> Self {
        let mut scene = Scene::default_scene();
        scene.bearing = bearing.clone();
        Self::from_scene(&scene)
    }

    /// The configuration whose start values and fixed parts are `scene`'s: its spalls 1 … 4
    /// become the parameter spalls, the later ones stay fixed.
    pub fn from_scene(scene: &Scene) -> Self {
        let all: Vec<(&DefectSpec, Option<DefectMode>)> = scene.spalls().collect();
        let spalls = std::array::from_fn(|k| DefectParams::from_spec(all.get(k).map(|s| s.0)));
        let slot_modes = std::array::from_fn(|k| all.get(k).and_then(|s| s.1));
        let fixed = all
            .iter()
            .skip(SPALL_SLOTS)
            .map(|&(d, m)| (d.clone(), m))
            .collect();
        let axial_offset = scene.mounting.axial_offset.unwrap_or(0.0);
        Self {
            scene: scene.clone(),
            spalls,
            slot_modes,
            fixed,
            axial_offset,
            warn_steps: DEFAULT_WARN_STEPS,
            tlm: false,
        }
    }

    /// The simulation's spalls: the parameter spalls whose ring is not 0, in order, then the
    /// fixed ones; each with its mode and its FMU name (`defect2`, or for a fixed one
    /// `defect[k]` of the scene resource).
    pub fn spall_list(&self) -> Vec<(DefectSpec, Option<DefectMode>, String)> {
        let params = self
            .spalls
            .iter()
            .zip(self.slot_modes)
            .enumerate()
            .filter_map(|(k, (p, m))| p.spec().map(|d| (d, m, slot_name(k))));
        let fixed = self.fixed.iter().enumerate().map(|(j, (d, m))| {
            (
                d.clone(),
                *m,
                format!("{SCENE_RESOURCE_NAME}'s defect[{}]", SPALL_SLOTS + j),
            )
        });
        params.chain(fixed).collect()
    }

    /// The base scene with [`Config::spall_list`] as its spalls (operating point and tolerance
    /// as in the base scene).
    pub fn scene_with_spalls(&self) -> Scene {
        let list = self.spall_list();
        let mut s = self.scene.clone();
        let modes: Vec<Option<DefectMode>> = list.iter().map(|l| l.1).collect();
        s.set_defects(list.into_iter().map(|l| l.0).collect());
        if modes.iter().any(Option::is_some) {
            s.defect_modes = modes;
        }
        s
    }

    /// `message` (of the library, about the scene of [`Config::scene_with_spalls`]) with the
    /// spalls named as the FMU names them: the library's `defect[k]` (several spalls) or
    /// `defect.` (one) become the parameter group (`defect3.width`) or the fixed spall of the
    /// scene resource.
    pub fn name_spalls(&self, message: &str) -> String {
        let names: Vec<String> = self.spall_list().into_iter().map(|l| l.2).collect();
        let mut m = message.to_string();
        if names.len() == 1 {
            if names[0] != "defect" {
                for f in ["ring", "width", "depth", "theta0", "ball"] {
                    m = m.replace(&format!("defect.{f}"), &format!("{}.{f}", names[0]));
                }
            }
            return m;
        }
        // Placeholders first, so that a new name is never renamed again.
        for k in 0..names.len() {
            m = m
                .replace(&format!("defect[{k}]."), &format!("\u{1}{k}\u{2}"))
                .replace(&format!("defect[{k}]"), &format!("\u{1}{k}\u{3}"));
        }
        for (k, n) in names.iter().enumerate() {
            // A parameter spall is its group of parameters, a fixed one its scene entry.
            let bare = if n.starts_with("defect") {
                format!("{n}.*")
            } else {
                n.clone()
            };
            m = m
                .replace(&format!("\u{1}{k}\u{2}"), &format!("{n}."))
                .replace(&format!("\u{1}{k}\u{3}"), &bare);
        }
        m
    }

    /// The value of the parameter `name` (Integers as exact f64); `None` if there is none.
    pub fn get(&self, name: &str) -> Option<f64> {
        match row(name)?.access {
            Access::Param { get, .. } => Some(get(self)),
            _ => None,
        }
    }

    /// Sets the parameter `name` (as `fmi2Set*` does after the shell's type and range checks).
    pub fn set(&mut self, name: &str, v: f64) -> Result<(), String> {
        match row(name).map(|r| r.access) {
            Some(Access::Param { set, .. }) => set(self, v),
            _ => Err(format!("'{name}' is not a parameter")),
        }
    }
}

/// One variable of the FMU built for a bearing: its metadata and its access.
#[derive(Debug, Clone)]
pub struct Entry {
    /// The variable as the shell and the XML see it.
    pub var: Variable,
    /// What it reads and writes.
    pub role: Access,
}

/// The `SimpleType` name used for a unit.
pub fn quantity_of(unit: &str) -> Option<&'static str> {
    Some(match unit {
        "rad/s" => "AngularVelocity",
        "rad" => "Angle",
        "m" => "Length",
        "m/s" => "Velocity",
        "m/s2" => "Acceleration",
        "N" => "Force",
        "N.m" => "Torque",
        "kg" => "Mass",
        "N/m" => "TranslationalSpringConstant",
        "N.s/m" => "TranslationalDampingConstant",
        _ => return None,
    })
}

fn with_unit(mut v: Variable) -> Variable {
    if let Some(u) = v.unit.clone() {
        v.declared_type = quantity_of(&u).map(str::to_string);
        if u == "rad/s" {
            v.display_unit = Some("rpm".into());
        }
    }
    v
}

/// The `fidelity` parameter's description, from the level registry: "Fidelity level: 0
/// kinematic (L0), 1 quasi-static (L1), …".
fn fidelity_description() -> String {
    let levels: Vec<String> = LEVELS
        .iter()
        .map(|l| {
            let dep = if l.deprecated.is_some() {
                ", deprecated"
            } else {
                ""
            };
            format!("{} {} ({}{dep})", l.code, l.name.replace('_', "-"), l.label)
        })
        .collect();
    format!(
        "Fidelity level: {}; see the documentation for which levels this build provides",
        levels.join(", ")
    )
}

/// The enumeration types of the mode switches (the `declared_type` of the `choice` rows of
/// [`ROWS`]), their items named as in scene files where a scene names them: the value a
/// variable takes is the item's value, read and written with `fmi2GetInteger` and
/// `fmi2SetInteger`.
pub fn enumerations() -> Vec<EnumerationType> {
    let ty = |name: &str, description: &str, items: &[(i32, &str, &str)]| EnumerationType {
        name: name.into(),
        description: description.into(),
        items: items
            .iter()
            .map(|&(value, name, description)| EnumerationItem {
                name: name.into(),
                value,
                description: description.into(),
            })
            .collect(),
    };
    vec![
        EnumerationType {
            name: "Fidelity".into(),
            description: "Fidelity level of the bearing model (the ladder L0 … L4)".into(),
            items: LEVELS
                .iter()
                .map(|l| EnumerationItem {
                    name: l.name.into(),
                    value: l.code,
                    description: match l.deprecated {
                        Some(_) => format!("{}, deprecated: {}", l.label, l.summary),
                        None => format!("{}: {}", l.label, l.summary),
                    },
                })
                .collect(),
        },
        ty(
            "DefectRing",
            "The ring that carries the spall",
            &[
                (0, "none", "No spall (healthy bearing)"),
                (1, "outer", "Spall on the outer race"),
                (2, "inner", "Spall on the inner race"),
                (3, "ball", "Spall on a ball (defect.ball; not at the quasi-static level)"),
            ],
        ),
        ty(
            "DefectMode",
            "How a ball meets the spall",
            &[
                (0, "finite", "Finite-size ball resting on the spall's edges"),
                (1, "point", "Paper-literal point contact"),
            ],
        ),
        ty(
            "IntegrationMethod",
            "Explicit embedded Runge–Kutta pair with step-size control",
            &[
                (0, "rkf45", "Runge–Kutta–Fehlberg 4(5)"),
                (1, "dopri5", "Dormand–Prince 5(4)"),
                (2, "dop853", "Dormand–Prince 8(5,3)"),
            ],
        ),
        ty(
            "CageSpeed",
            "Cage speed of the levels with kinematic balls",
            &[
                (
                    0,
                    "traction",
                    "The traction's caged balance: the orbital rate at which the traction's orbital torques on the balls cancel",
                ),
                (1, "outer_race_control", "L1's outer-race control"),
            ],
        ),
        ty(
            "AxialMounting",
            "Axial mounting of the inner ring (force coupling)",
            &[
                (0, "load", "The axial load load.Fx acts on the ring"),
                (
                    1,
                    "located",
                    "Located where the start's load.Fx alone puts it (a preload)",
                ),
                (2, "located_offset", "Located at ring.axial_offset"),
            ],
        ),
        ty(
            "Cage",
            "The cage of the reduced and full levels",
            &[
                (0, "none", "The paper's cage-less balls"),
                (1, "rigid", "A rigid cage with its pockets, from the bearing's [cage]"),
            ],
        ),
    ]
}

/// The full table of the FMU built on `bearing` without a scene resource: [`table_for`] the
/// default scene on it.
pub fn table(bearing: &BearingFile) -> Vec<Entry> {
    table_for(&Config::default_for(bearing).scene)
}

/// The full table of the FMU whose base scene is `scene`: [`ROWS`] with the scene's start
/// values, the real outputs (1000 + i) before the solver counters, the Model Exchange states,
/// then [`SPALL_ROWS`].
pub fn table_for(scene: &Scene) -> Vec<Entry> {
    let cfg = Config::from_scene(scene);
    let bearing = &scene.bearing;
    let inputs = cfg.scene.operating;
    let journal = Journal::default();
    let enums = enumerations();
    let entry = |r: &VarRow| {
        let start = match (r.access, r.ty) {
            (Access::Input { get, .. }, _) => Start::Real(get(&inputs)),
            (Access::Journal(k), _) => Start::Real(journal_get(&journal, k)),
            (Access::Param { get, .. }, Integer | Enumeration) => Start::Integer(get(&cfg) as i32),
            (Access::Param { get, .. }, _) => Start::Real(get(&cfg)),
            (Access::Line(_), _) => Start::Real(0.0),
            (
                Access::Stat(_)
                | Access::Output(_)
                | Access::RingVelocity(_)
                | Access::State(_)
                | Access::Derivative(_),
                _,
            ) => Start::None,
        };
        let mut var = with_unit(r.variable(start));
        if r.name == "fidelity" {
            var.description = fidelity_description();
        }
        if let Some(t) = r.declared_type {
            let (lo, hi) = enums
                .iter()
                .find(|e| e.name == t)
                .and_then(EnumerationType::range)
                .expect("a choice row names an enumeration of `enumerations` with items");
            var.min = Some(lo.into());
            var.max = Some(hi.into());
        }
        Entry {
            var,
            role: r.access,
        }
    };
    let mut t: Vec<Entry> = ROWS
        .iter()
        .filter(|r| !matches!(r.access, Access::Stat(_)))
        .map(entry)
        .collect();
    let z = bearing.bearing.z as usize;
    for (i, o) in output_table_with_cage(z).into_iter().enumerate() {
        let var = Variable {
            vr: 1000 + i as u32,
            name: o.name.clone(),
            ty: Real,
            causality: Out,
            variability: Variability::Continuous,
            initial: Some(Initial::Calculated),
            description: o.description.clone(),
            unit: Some(o.unit.to_string()),
            declared_type: None,
            display_unit: None,
            start: Start::None,
            min: None,
            max: None,
            derivative_of: None,
        };
        t.push(Entry {
            var: with_unit(var),
            role: Access::Output(i),
        });
    }
    t.extend(
        ROWS.iter()
            .filter(|r| matches!(r.access, Access::Stat(_)))
            .map(entry),
    );
    // Model Exchange: the continuous states and their derivatives, as many as the level with
    // the most states has on this bearing (the others pad).
    let (nx, _) = raceway::model_exchange_capacity(z);
    for i in 0..nx {
        let state = Variable {
            vr: STATE_VR + i as u32,
            name: format!("state[{}]", i + 1),
            ty: Real,
            causality: Causality::Local,
            variability: Variability::Continuous,
            initial: Some(Initial::Calculated),
            description: format!(
                "Model Exchange: continuous state {} of the level's state vector (its meaning \
                 depends on the level, see the documentation); a level with fewer states pads \
                 with states that stay 0 (derivative 0)",
                i + 1
            ),
            unit: None,
            declared_type: None,
            display_unit: None,
            start: Start::None,
            min: None,
            max: None,
            derivative_of: None,
        };
        let der = Variable {
            vr: DERIVATIVE_VR + i as u32,
            name: format!("der(state[{}])", i + 1),
            description: format!(
                "Model Exchange: the derivative of state[{}] (0 for a padding state)",
                i + 1
            ),
            derivative_of: Some(STATE_VR + i as u32),
            ..state.clone()
        };
        t.push(Entry {
            var: state,
            role: Access::State(i),
        });
        t.push(Entry {
            var: der,
            role: Access::Derivative(i),
        });
    }
    t.extend(SPALL_ROWS.iter().map(entry));
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn table_is_consistent() {
        let b = BearingFile::default_preset();
        let t = table(&b);
        let vrs: HashSet<u32> = t.iter().map(|e| e.var.vr).collect();
        assert_eq!(vrs.len(), t.len(), "unique value references");
        let names: HashSet<&str> = t.iter().map(|e| e.var.name.as_str()).collect();
        assert_eq!(names.len(), t.len(), "unique names");
        let z = b.bearing.z as usize;
        let (nx, _) = raceway::model_exchange_capacity(z);
        assert_eq!(
            t.len(),
            ROWS.len() + SPALL_ROWS.len() + output_table_with_cage(z).len() + 2 * nx
        );
        assert_eq!(params().count(), 30 + 5 * (SPALL_SLOTS - 1));
        for e in &t {
            if let (Start::Real(x), Some(lo)) = (&e.var.start, e.var.min) {
                assert!(*x >= lo, "{}", e.var.name);
            }
            if let (Start::Real(x), Some(hi)) = (&e.var.start, e.var.max) {
                assert!(*x <= hi, "{}", e.var.name);
            }
        }
        let speed = &t[0].var;
        assert_eq!(speed.name, "shaft.speed");
        assert_eq!(
            speed.start,
            Start::Real(9900.0 * std::f64::consts::PI / 30.0)
        );
        let fz = t.iter().find(|e| e.var.name == "load.Fz").unwrap();
        assert_eq!(fz.var.start, Start::Real(-1000.0));
    }

    #[test]
    fn mode_switches_are_enumerations_with_the_library_codes() {
        let b = BearingFile::default_preset();
        let t = table(&b);
        let enums = enumerations();
        let choices: Vec<&Entry> = t.iter().filter(|e| e.var.ty == Enumeration).collect();
        assert_eq!(choices.len(), 7 + (SPALL_SLOTS - 1));
        let mut cfg = Config::default_for(&b);
        for e in choices {
            let v = &e.var;
            let ty = enums
                .iter()
                .find(|t| Some(&t.name) == v.declared_type.as_ref())
                .unwrap_or_else(|| panic!("{}: its type is defined", v.name));
            // Values 0, 1, …: the shell's range check is the check that a value is an item.
            let values: Vec<i32> = ty.items.iter().map(|i| i.value).collect();
            assert_eq!(
                values,
                (0..ty.items.len() as i32).collect::<Vec<_>>(),
                "{}",
                v.name
            );
            assert_eq!(v.min, Some(0.0), "{}", v.name);
            assert_eq!(v.max, Some((ty.items.len() - 1) as f64), "{}", v.name);
            let Start::Integer(start) = v.start else {
                panic!("{}: an Integer start", v.name)
            };
            assert!(ty.item(start).is_some(), "{}: start {start}", v.name);
            // Every item is a value the model takes and reads back.
            for item in &ty.items {
                cfg.set(&v.name, item.value.into()).unwrap();
                assert_eq!(cfg.get(&v.name), Some(item.value.into()), "{}", item.name);
            }
        }
        // The items are named as the library (and scene files) name the choices.
        let names = |t: &str| -> Vec<String> {
            let ty = enums.iter().find(|e| e.name == t).unwrap();
            ty.items.iter().map(|i| i.name.clone()).collect()
        };
        let levels: Vec<String> = LEVELS.iter().map(|l| l.name.to_string()).collect();
        assert_eq!(names("Fidelity"), levels);
        assert!(LEVELS.iter().enumerate().all(|(i, l)| l.code == i as i32));
        let methods: Vec<String> = (0..3)
            .map(|c| MethodName::from_code(c).unwrap().name().to_string())
            .collect();
        assert_eq!(names("IntegrationMethod"), methods);
        assert!(MethodName::from_code(3).is_none());
        assert_eq!(
            CageSpeed::from_code(1),
            Some(CageSpeed::OuterRaceControl),
            "{:?}",
            names("CageSpeed")
        );
        assert!(CageSpeed::from_code(2).is_none());
    }

    #[test]
    fn params_round_trip() {
        let b = BearingFile::default_preset();
        let mut cfg = Config::default_for(&b);
        for r in params() {
            let v = cfg.get(r.name).unwrap();
            cfg.set(r.name, v).unwrap();
            assert_eq!(cfg.get(r.name), Some(v), "{}", r.name);
        }
        assert_eq!(cfg, Config::default_for(&b));
    }
}
