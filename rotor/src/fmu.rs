//! The FMI 2.0 Co-Simulation model `JeffcottRotor`: a thin [`FmuModel`] around
//! [`crate::jeffcott::Rotor`], with its variable table (one source of truth for the shell, the
//! model description and the documentation).

use crate::jeffcott::{InterfaceForce, Rotor, RotorParams};
use fmi2::bindings::Fmi2Status;
use fmi2::codec::{ByteReader, ByteWriter};
use fmi2::table::Row;
use fmi2::xml;
use fmi2::{
    Causality, FmuModel, Initial, InstantiateArgs, Logger, Start, StepResult, VarType, Variability,
    Variable, LOG_EVENTS, LOG_SOLVER,
};
use raceway_solver::IntegratorState;

pub const MODEL_IDENTIFIER: &str = "JeffcottRotor";
pub const DEFAULT_START_TIME: f64 = 0.0;
pub const DEFAULT_STOP_TIME: f64 = 0.1;
pub const DEFAULT_TOLERANCE: f64 = 1e-8;
pub const DEFAULT_STEP_SIZE: f64 = 1e-4;
const MODEL_STATE_VERSION: u32 = 1;

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
    Out(O),
}

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
}

impl O {
    pub const ALL: [O; 17] = [
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
    ];

    fn info(self) -> (String, &'static str, String) {
        const XYZ: [&str; 3] = ["x", "y", "z"];
        const YZ: [&str; 2] = ["y", "z"];
        match self {
            O::X(i) => (format!("journal.{}", XYZ[i]), "m", format!("Journal (inner-ring centre) displacement along {} in the bearing's frame (connect to the BallBearing's journal.{} in motion mode)", XYZ[i], XYZ[i])),
            O::V(i) => (format!("journal.v.{}", XYZ[i]), "m/s", format!("Journal velocity along {}", XYZ[i])),
            O::A(i) => (format!("journal.a.{}", XYZ[i]), "m/s2", format!("Journal acceleration along {}", XYZ[i])),
            O::Disk(i) => (format!("disk.{}", YZ[i]), "m", format!("Disk displacement along {}", YZ[i])),
            O::DiskV(i) => (format!("disk.v.{}", YZ[i]), "m/s", format!("Disk velocity along {}", YZ[i])),
            O::Speed => ("shaft.speed".into(), "rad/s", "Shaft speed (connect to the BallBearing's shaft.speed)".into()),
            O::Angle => ("shaft.angle".into(), "rad", "Shaft angle, wrapped to [0, 2 pi)".into()),
            O::Unbalance(i) => (format!("unbalance.F.{}", YZ[i]), "N", format!("Unbalance force along {}", YZ[i])),
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
    t
}

pub fn model_info() -> xml::ModelInfo {
    xml::ModelInfo {
        model_name: MODEL_IDENTIFIER.into(),
        model_identifier: MODEL_IDENTIFIER.into(),
        description: "Jeffcott rotor (journal and disk on a flexible shaft) with unbalance, gravity, a speed ramp and one bearing station; couples to the BallBearing FMU in motion mode".into(),
        author: "raceway developers".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        license: env!("CARGO_PKG_LICENSE").into(),
        generation_tool: format!("raceway-rotor {}", env!("CARGO_PKG_VERSION")),
        start_time: DEFAULT_START_TIME,
        stop_time: DEFAULT_STOP_TIME,
        tolerance: DEFAULT_TOLERANCE,
        step_size: DEFAULT_STEP_SIZE,
        provides_directional_derivative: false,
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

/// The FMU model.
pub struct JeffcottRotor {
    guid: String,
    vars: Vec<Variable>,
    roles: Vec<Role>,
    params: RotorParams,
    iface: InterfaceForce,
    start_time: f64,
    tolerance: Option<f64>,
    live: Option<Rotor>,
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
            start_time: 0.0,
            tolerance: None,
            live: None,
        }
    }

    fn build(&self) -> Result<Rotor, String> {
        let mut r = Rotor::new(
            &self.params,
            self.start_time,
            self.tolerance.unwrap_or(DEFAULT_TOLERANCE),
        )
        .map_err(|e| e.to_string())?;
        r.set_interface(self.iface);
        Ok(r)
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

impl FmuModel for JeffcottRotor {
    const MODEL_IDENTIFIER: &'static str = MODEL_IDENTIFIER;

    fn instantiate(_args: &InstantiateArgs, _log: &Logger) -> Result<Self, String> {
        Ok(Self::new())
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
        let r = self.build()?;
        if log.enabled(LOG_EVENTS) {
            let p = &self.params;
            log.log(
                Fmi2Status::Ok,
                LOG_EVENTS,
                &format!(
                    "initialized: journal {} kg, disk {} kg, shaft {} N/m, unbalance {} kg.m, speed {} -> {} rad/s",
                    p.journal_mass, p.disk_mass, p.shaft_k, p.unbalance, p.speed_initial, p.speed_final
                ),
            );
        }
        self.live = Some(r);
        Ok(())
    }
    fn do_step(&mut self, t: f64, t_end: f64, log: &Logger) -> StepResult {
        let Some(r) = self.live.as_mut() else {
            return StepResult::Error("no rotor (internal error)".into());
        };
        let before = r.stats();
        if let Err(e) = r.advance(t_end) {
            return StepResult::Discard {
                message: e.to_string(),
                last_good_time: e.t,
            };
        }
        if log.enabled(LOG_SOLVER) {
            let s = r.stats();
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
        let o = r.outputs();
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
        StepResult::Ok
    }
    fn reset(&mut self) -> Result<(), String> {
        *self = Self::new();
        Ok(())
    }
    fn get_real(&mut self, index: usize) -> Result<f64, String> {
        let role = self.roles[index];
        if let Some(v) = iface_get(&self.iface, role) {
            return Ok(v);
        }
        match role {
            Role::Param(k) => Ok((PARAMS[k].access.get)(&self.params)),
            Role::Out(o) => {
                if self.live.is_none() {
                    self.live = Some(self.build()?);
                }
                let r = self.live.as_mut().expect("just built");
                Ok(o.get(&r.outputs()))
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
            Role::Out(_) => Err(format!("'{}' cannot be set", self.vars[index].name)),
            _ => {
                iface_set(&mut self.iface, role, value);
                if let Some(r) = self.live.as_mut() {
                    r.set_interface(self.iface);
                }
                Ok(())
            }
        }
    }
    /// The parameters and the interface inputs before a multi-value set call.
    type Undo = (RotorParams, InterfaceForce);

    fn begin_set(&self, _indices: &[usize]) -> Self::Undo {
        (self.params.clone(), self.iface)
    }

    fn rollback_set(&mut self, (params, iface): Self::Undo) -> Result<(), String> {
        if params != self.params {
            self.params = params;
            self.live = None;
        }
        self.iface = iface;
        if let Some(r) = self.live.as_mut() {
            r.set_interface(iface);
        }
        Ok(())
    }

    fn save_state(&self) -> Vec<u8> {
        let mut w = ByteWriter::new();
        w.u32(MODEL_STATE_VERSION).u32(PARAMS.len() as u32);
        for p in PARAMS {
            w.f64((p.access.get)(&self.params));
        }
        write_iface(&mut w, &self.iface);
        w.f64(self.start_time).opt_f64(self.tolerance);
        match &self.live {
            Some(r) => {
                let (s, iface, tk, xk) = r.snapshot();
                w.bool(true);
                write_iface(&mut w, &iface);
                w.f64(tk);
                for x in xk {
                    w.f64(x);
                }
                w.bytes(&serde_json::to_vec(&s).expect("an integrator state serializes"));
            }
            None => {
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
        let iface = read_iface(&mut r)?;
        let start_time = r.f64("start time")?;
        let tolerance = r.opt_f64("tolerance")?;
        let live = if r.bool("rotor flag")? {
            let step_iface = read_iface(&mut r)?;
            let tk = r.f64("step start")?;
            let mut xk = [0.0; 6];
            for x in &mut xk {
                *x = r.f64("step start state")?;
            }
            let js = r.bytes("integrator state")?;
            r.finish("the JeffcottRotor state")?;
            let s: IntegratorState =
                serde_json::from_slice(js).map_err(|e| format!("corrupt integrator state: {e}"))?;
            let mut rotor = Rotor::new(&params, start_time, tolerance.unwrap_or(DEFAULT_TOLERANCE))
                .map_err(|e| format!("corrupt state: {e}"))?;
            rotor.restore(&s, step_iface, tk, xk)?;
            Some(rotor)
        } else {
            r.finish("the JeffcottRotor state")?;
            None
        };
        self.params = params;
        self.iface = iface;
        self.start_time = start_time;
        self.tolerance = tolerance;
        self.live = live;
        Ok(())
    }
}

/// `documentation/index.html` of the rotor FMU: the model, the coupling convention and the
/// variable table.
pub fn documentation_html() -> String {
    let mut h = String::new();
    h.push_str("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>JeffcottRotor</title></head><body>\n");
    h.push_str("<h1>JeffcottRotor</h1>\n<p>A Jeffcott rotor with one bearing station, an FMI 2.0 Co-Simulation FMU built with raceway's generic FMI shell. It is the shaft side of a rotor&ndash;bearing co-simulation with the <code>BallBearing</code> FMU in motion mode (<code>coupling = 1</code>).</p>\n");
    h.push_str("<h2>Model</h2>\n<p>Frame of the bearing: x axial, y and z radial, the shaft turns about +x. A journal of mass m<sub>j</sub> (the inner-ring centre) and a disk of mass m<sub>d</sub> on a massless shaft of lateral stiffness k<sub>s</sub> and damping c<sub>s</sub>; axially the disk rides with the journal. disk.mass = 0 makes a rigid rotor of mass journal.mass carrying the unbalance.</p>\n<pre>\n(m_j + m_d) x''_j = F_x + L_x - c_j x'_j\nm_j y''_j = F_y + L_y - c_j y'_j + k_s (y_d - y_j) + c_s (y'_d - y'_j)\nm_j z''_j = F_z + L_z - c_j z'_j + k_s (z_d - z_j) + c_s (z'_d - z'_j) - m_j g\nm_d y''_d = -k_s (y_d - y_j) - c_s (y'_d - y'_j) + U_y\nm_d z''_d = -k_s (z_d - z_j) - c_s (z'_d - z'_j) - m_d g + U_z\nU = m_u e (W^2 cos phi + W' sin phi, W^2 sin phi - W' cos phi),  phi' = W\n</pre>\n<p>F: force of the bearing on the shaft (input), L: constant load (parameters load.F*), g: gravity along -z, W: shaft speed, ramping from speed.initial to speed.final at speed.rate (closed form, so a run-up needs no input). The state is integrated by DOPRI5 (relative tolerance from fmi2SetupExperiment, default 1e-8).</p>\n");
    h.push_str("<h2>Coupling inputs</h2>\n<p>Inside a communication step [t<sub>k</sub>, t<sub>k</sub>+H] the bearing force is</p>\n<pre>F(t) = bearing.F + bearing.dF (t - t_k) + bearing.dF_dx (x_j(t) - x_j(t_k)) + bearing.dF_dv (x'_j(t) - x'_j(t_k))</pre>\n<ul><li>Constant-input (Jacobi) coupling: set bearing.F only.</li><li>Linear extrapolation: bearing.dF = (F<sub>k</sub> - F<sub>k-1</sub>)/H.</li><li>Interface Jacobian: bearing.dF_dx and bearing.dF_dv from the BallBearing's fmi2GetDirectionalDerivative of bearing.F.* with respect to journal.* and journal.v.*; the rotor then integrates the linearised bearing reaction inside its step (stable at master steps far beyond the explicit limit &omega;H &lt; 4&zeta;).</li></ul>\n<p>Outputs journal.x/y/z and journal.v.x/y/z connect to the BallBearing's journal inputs, shaft.speed to its shaft.speed.</p>\n");
    h.push_str("<h2>Behaviour</h2>\n<ul><li>Any number of instances; no global state; FMU state get/set/serialize supported.</li><li>Invalid parameters (non-finite, negative masses, a disk without shaft stiffness) are rejected at fmi2ExitInitializationMode with a message naming the parameter.</li><li>No directional derivatives, no input derivatives (the coupling inputs above serve instead).</li></ul>\n");
    h.push_str("<h2>Variables</h2>\n<table border=\"1\"><tr><th>name</th><th>vr</th><th>causality</th><th>unit</th><th>start</th><th>description</th></tr>\n");
    for (v, _) in table() {
        let start = match v.start {
            Start::Real(x) => format!("{x}"),
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
