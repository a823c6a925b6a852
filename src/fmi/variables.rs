//! The BallBearing FMU's variable table: the one source of truth for the runtime
//! ([`super::ballbearing`]), the model description ([`super::xml`]) and the documentation
//! ([`super::docs`]).
//!
//! Value references: inputs 1–4, journal inputs 5–10 (`journal.x/y/z`, `journal.v.x/y/z`),
//! parameters 100 + k (in [`Param::ALL`] order), solver counters 900–902, real outputs 1000 + i
//! (i = position in [`crate::simulation::output_table`]).

use super::shell::{Causality, Initial, Start, VarType, Variability, Variable};
use crate::config::{BearingFile, DefectMode};
use crate::defect::DefectSpec;
use crate::geometry::Race;
use crate::operating::OperatingPoint;
use crate::scene::{AxialMount, CageSpeed, CouplingMode, Fidelity, MethodName, Mounting, Scene};
use crate::simulation::{output_table, Journal};

/// The continuous inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    ShaftSpeed,
    Fx,
    Fy,
    Fz,
}

impl Input {
    pub const ALL: [Input; 4] = [Input::ShaftSpeed, Input::Fx, Input::Fy, Input::Fz];

    pub fn get(self, i: &OperatingPoint) -> f64 {
        match self {
            Input::ShaftSpeed => i.shaft_speed,
            Input::Fx => i.fx,
            Input::Fy => i.fy,
            Input::Fz => i.fz,
        }
    }

    pub fn set(self, i: &mut OperatingPoint, v: f64) {
        match self {
            Input::ShaftSpeed => i.shaft_speed = v,
            Input::Fx => i.fx = v,
            Input::Fy => i.fy = v,
            Input::Fz => i.fz = v,
        }
    }
}

/// The journal inputs of coupling mode "motion": displacement x, y, z then velocity x, y, z.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct JournalInput(pub usize);

impl JournalInput {
    pub const ALL: [JournalInput; 6] = [
        JournalInput(0),
        JournalInput(1),
        JournalInput(2),
        JournalInput(3),
        JournalInput(4),
        JournalInput(5),
    ];

    pub fn get(self, j: &Journal) -> f64 {
        if self.0 < 3 {
            j.x[self.0]
        } else {
            j.v[self.0 - 3]
        }
    }

    pub fn set(self, j: &mut Journal, v: f64) {
        if self.0 < 3 {
            j.x[self.0] = v
        } else {
            j.v[self.0 - 3] = v
        }
    }

    pub fn name(self) -> &'static str {
        [
            "journal.x",
            "journal.y",
            "journal.z",
            "journal.v.x",
            "journal.v.y",
            "journal.v.z",
        ][self.0]
    }
}

/// The structural parameters (all `variability="fixed"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Param {
    Fidelity,
    Coupling,
    DefectRing,
    DefectWidth,
    DefectDepth,
    DefectTheta0,
    DefectMode,
    PedestalMass,
    PedestalKy,
    PedestalKz,
    PedestalCy,
    PedestalCz,
    InnerRingMass,
    ContactCbr,
    TractionKappa0,
    TractionKappaMax,
    TractionUMax,
    TractionKappaInf,
    LumpedSlipJitter,
    LumpedSeed,
    SolverMethod,
    SolverRtol,
    SolverMaxSteps,
    /// Appended last so that the earlier value references stay as they were.
    LumpedCageSpeed,
    SolverPiBeta,
    RingAxial,
    RingAxialOffset,
}

/// The solver's work counters (Integer outputs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stat {
    Steps,
    Rejected,
    RhsEvals,
}

/// What a variable of the table is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    Input(Input),
    Journal(JournalInput),
    Param(Param),
    /// Position in the simulation's output vector.
    Output(usize),
    Stat(Stat),
}

/// The defect as the FMU's parameters describe it (kept even while `defect.ring = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DefectParams {
    /// 0 none, 1 outer, 2 inner.
    pub ring: i32,
    pub width: f64,
    pub depth: f64,
    pub theta0: f64,
}

impl DefectParams {
    pub fn from_scene(scene: &Scene) -> Self {
        let d = scene
            .defect
            .clone()
            .or_else(|| Scene::default_scene().defect);
        let (width, depth, theta0) = d
            .as_ref()
            .map_or((1e-3, 0.2e-3, std::f64::consts::PI), |d| {
                (d.width, d.depth, d.theta0)
            });
        let ring = match scene.defect.as_ref().map(|d| d.ring) {
            None => 0,
            Some(Race::Outer) => 1,
            Some(Race::Inner) => 2,
        };
        Self {
            ring,
            width,
            depth,
            theta0,
        }
    }

    /// The scene's defect.
    pub fn spec(&self) -> Option<DefectSpec> {
        let ring = match self.ring {
            1 => Race::Outer,
            2 => Race::Inner,
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

/// Everything the parameters edit: the scene (bearing, fidelity, solver, ...) and the defect.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    pub scene: Scene,
    pub defect: DefectParams,
    /// `ring.axial_offset` as set (it enters the scene's mounting with `ring.axial` = 2).
    pub axial_offset: f64,
}

impl Config {
    /// The default scene on `bearing`.
    pub fn default_for(bearing: &BearingFile) -> Self {
        let mut scene = Scene::default_scene();
        scene.bearing = bearing.clone();
        let defect = DefectParams::from_scene(&scene);
        let axial_offset = scene.mounting.axial_offset.unwrap_or(0.0);
        Self {
            scene,
            defect,
            axial_offset,
        }
    }

    /// The value of a parameter (Integers as exact f64).
    pub fn get(&self, p: Param) -> f64 {
        let s = &self.scene;
        let b = &s.bearing;
        match p {
            Param::Fidelity => s.fidelity.code() as f64,
            Param::Coupling => s.coupling.code() as f64,
            Param::DefectRing => self.defect.ring as f64,
            Param::DefectWidth => self.defect.width,
            Param::DefectDepth => self.defect.depth,
            Param::DefectTheta0 => self.defect.theta0,
            Param::DefectMode => match b.defect.mode {
                DefectMode::Finite => 0.0,
                DefectMode::Point => 1.0,
            },
            Param::PedestalMass => b.pedestal.mass,
            Param::PedestalKy => b.pedestal.k_y,
            Param::PedestalKz => b.pedestal.k_z,
            Param::PedestalCy => b.pedestal.c_y,
            Param::PedestalCz => b.pedestal.c_z,
            Param::InnerRingMass => b.inner_ring.mass,
            Param::ContactCbr => b.contact.c_br,
            Param::TractionKappa0 => b.traction.kappa_0,
            Param::TractionKappaMax => b.traction.kappa_max,
            Param::TractionUMax => b.traction.u_max,
            Param::TractionKappaInf => b.traction.kappa_inf,
            Param::LumpedSlipJitter => s.lumped.slip_jitter,
            Param::LumpedSeed => s.lumped.seed.min(i32::MAX as u64) as f64,
            Param::SolverMethod => s.solver.method.code() as f64,
            Param::SolverRtol => s.solver.rtol,
            Param::SolverMaxSteps => s.solver.max_steps.min(i32::MAX as u64) as f64,
            Param::LumpedCageSpeed => s.lumped.cage_speed.code() as f64,
            Param::SolverPiBeta => s.solver.pi_beta,
            Param::RingAxial => match (s.mounting.axial, s.mounting.axial_offset) {
                (AxialMount::Load, _) => 0.0,
                (AxialMount::Located, None) => 1.0,
                (AxialMount::Located, Some(_)) => 2.0,
            },
            Param::RingAxialOffset => self.axial_offset,
        }
    }

    /// Sets a parameter; `v` has passed the table's type and range checks.
    pub fn set(&mut self, p: Param, v: f64) -> Result<(), String> {
        let s = &mut self.scene;
        let code = v as i32;
        match p {
            Param::Fidelity => {
                s.fidelity = Fidelity::from_code(code)
                    .ok_or_else(|| format!("fidelity = {code}: valid codes are 0..4"))?
            }
            Param::Coupling => {
                s.coupling = CouplingMode::from_code(code).ok_or_else(|| {
                    format!("coupling = {code}: valid codes are 0 (force) and 1 (motion)")
                })?
            }
            Param::DefectRing => self.defect.ring = code,
            Param::DefectWidth => self.defect.width = v,
            Param::DefectDepth => self.defect.depth = v,
            Param::DefectTheta0 => self.defect.theta0 = v,
            Param::DefectMode => {
                s.bearing.defect.mode = if code == 0 {
                    DefectMode::Finite
                } else {
                    DefectMode::Point
                }
            }
            Param::PedestalMass => s.bearing.pedestal.mass = v,
            Param::PedestalKy => s.bearing.pedestal.k_y = v,
            Param::PedestalKz => s.bearing.pedestal.k_z = v,
            Param::PedestalCy => s.bearing.pedestal.c_y = v,
            Param::PedestalCz => s.bearing.pedestal.c_z = v,
            Param::InnerRingMass => s.bearing.inner_ring.mass = v,
            Param::ContactCbr => s.bearing.contact.c_br = v,
            Param::TractionKappa0 => s.bearing.traction.kappa_0 = v,
            Param::TractionKappaMax => s.bearing.traction.kappa_max = v,
            Param::TractionUMax => s.bearing.traction.u_max = v,
            Param::TractionKappaInf => s.bearing.traction.kappa_inf = v,
            Param::LumpedSlipJitter => s.lumped.slip_jitter = v,
            Param::LumpedSeed => s.lumped.seed = code.max(0) as u64,
            Param::SolverMethod => {
                s.solver.method = MethodName::from_code(code)
                    .ok_or_else(|| format!("solver.method = {code}: valid codes are 0, 1, 2"))?
            }
            Param::SolverRtol => s.solver.rtol = v,
            Param::SolverMaxSteps => s.solver.max_steps = code.max(1) as u64,
            Param::LumpedCageSpeed => {
                s.lumped.cage_speed = CageSpeed::from_code(code)
                    .ok_or_else(|| format!("lumped.cage_speed = {code}: valid codes are 0, 1"))?
            }
            Param::SolverPiBeta => s.solver.pi_beta = v,
            Param::RingAxial => {
                s.mounting = match code {
                    0 => Mounting::default(),
                    1 => Mounting {
                        axial: AxialMount::Located,
                        axial_offset: None,
                    },
                    2 => Mounting {
                        axial: AxialMount::Located,
                        axial_offset: Some(self.axial_offset),
                    },
                    _ => return Err(format!("ring.axial = {code}: valid codes are 0, 1, 2")),
                }
            }
            Param::RingAxialOffset => {
                self.axial_offset = v;
                if s.mounting.axial_offset.is_some() {
                    s.mounting.axial_offset = Some(v);
                }
            }
        }
        Ok(())
    }
}

impl Param {
    pub const ALL: [Param; 27] = [
        Param::Fidelity,
        Param::Coupling,
        Param::DefectRing,
        Param::DefectWidth,
        Param::DefectDepth,
        Param::DefectTheta0,
        Param::DefectMode,
        Param::PedestalMass,
        Param::PedestalKy,
        Param::PedestalKz,
        Param::PedestalCy,
        Param::PedestalCz,
        Param::InnerRingMass,
        Param::ContactCbr,
        Param::TractionKappa0,
        Param::TractionKappaMax,
        Param::TractionUMax,
        Param::TractionKappaInf,
        Param::LumpedSlipJitter,
        Param::LumpedSeed,
        Param::SolverMethod,
        Param::SolverRtol,
        Param::SolverMaxSteps,
        Param::LumpedCageSpeed,
        Param::SolverPiBeta,
        Param::RingAxial,
        Param::RingAxialOffset,
    ];

    /// (name, type, unit, min, max, description)
    pub fn info(
        self,
    ) -> (
        &'static str,
        VarType,
        Option<&'static str>,
        Option<f64>,
        Option<f64>,
        &'static str,
    ) {
        use VarType::{Integer as I, Real as R};
        let imax = i32::MAX as f64;
        match self {
            Param::Fidelity => ("fidelity", I, None, Some(0.0), Some(4.0),
                "Fidelity level: 0 kinematic (L0), 1 quasi-static (L1), 2 lumped (L2), 3 reduced (L3), 4 full (L4); see the documentation for which levels this build provides"),
            Param::Coupling => ("coupling", I, None, Some(0.0), Some(1.0),
                "Coupling mode: 0 force (load.F* in, the inner ring integrated inside), 1 motion (journal.* displacement and velocity in, bearing.F = the reaction on the journal out; load.F* only set the quasi-static start)"),
            Param::DefectRing => ("defect.ring", I, None, Some(0.0), Some(2.0),
                "Spalled ring: 0 none (healthy), 1 outer race, 2 inner race"),
            Param::DefectWidth => ("defect.width", R, Some("m"), Some(0.0), Some(0.1),
                "Spall width along the track w_d (> 0, smaller than the ball diameter)"),
            Param::DefectDepth => ("defect.depth", R, Some("m"), Some(0.0), Some(0.1),
                "Spall depth h_d (> 0)"),
            Param::DefectTheta0 => ("defect.theta0", R, Some("rad"), None, None,
                "Angular position of the spall centre (pi = load-zone centre of a load along -z; inner ring: at shaft angle 0)"),
            Param::DefectMode => ("defect.mode", I, None, Some(0.0), Some(1.0),
                "Spall model: 0 finite-size ball resting on the edges (default), 1 paper-literal point contact"),
            Param::PedestalMass => ("pedestal.mass", R, Some("kg"), Some(0.0), None,
                "Pedestal mass including the outer ring (> 0)"),
            Param::PedestalKy => ("pedestal.k_y", R, Some("N/m"), Some(0.0), None,
                "Pedestal support stiffness along y (> 0)"),
            Param::PedestalKz => ("pedestal.k_z", R, Some("N/m"), Some(0.0), None,
                "Pedestal support stiffness along z (> 0)"),
            Param::PedestalCy => ("pedestal.c_y", R, Some("N.s/m"), Some(0.0), None,
                "Pedestal support damping along y"),
            Param::PedestalCz => ("pedestal.c_z", R, Some("N.s/m"), Some(0.0), None,
                "Pedestal support damping along z"),
            Param::InnerRingMass => ("inner_ring.mass", R, Some("kg"), Some(0.0), None,
                "Inner ring (and shaft share) mass (> 0)"),
            Param::ContactCbr => ("contact.c_br", R, Some("N.s/m"), Some(0.0), None,
                "Ball-race normal contact damping"),
            Param::TractionKappa0 => ("traction.kappa_0", R, None, Some(0.0), Some(1.0),
                "Traction coefficient at zero slip"),
            Param::TractionKappaMax => ("traction.kappa_max", R, None, Some(0.0), Some(1.0),
                "Maximum traction coefficient (>= kappa_0 and >= kappa_inf)"),
            Param::TractionUMax => ("traction.u_max", R, Some("m/s"), Some(0.0), None,
                "Slip speed at the traction maximum (> 0)"),
            Param::TractionKappaInf => ("traction.kappa_inf", R, None, Some(0.0), Some(1.0),
                "Traction coefficient at large slip"),
            Param::LumpedSlipJitter => ("lumped.slip_jitter", R, None, Some(0.0), Some(0.5),
                "Random ball slip (lumped level): standard deviation as a fraction of the ball spacing, in [0, 0.5)"),
            Param::LumpedSeed => ("lumped.seed", I, None, Some(0.0), Some(imax),
                "Seed of the random ball slip"),
            Param::SolverMethod => ("solver.method", I, None, Some(0.0), Some(2.0),
                "Integration method: 0 RKF45, 1 DOPRI5, 2 DOP853"),
            Param::SolverRtol => ("solver.rtol", R, None, Some(crate::scene::MIN_RTOL), Some(0.1),
                "Relative tolerance of the integrator in (0, 0.1); fmi2SetupExperiment's tolerance, when defined, overrides it"),
            Param::SolverMaxSteps => ("solver.max_steps", I, None, Some(1.0), Some(imax),
                "Work budget per communication step: attempted integrator steps and, at the kinematic level, spall passes registered (one unit each); when exhausted the step returns fmi2Discard and the FMU stays at the step's start"),
            Param::LumpedCageSpeed => ("lumped.cage_speed", I, None, Some(0.0), Some(1.0),
                "Cage speed of the kinematic, quasi-static and lumped levels: 0 the traction's caged balance (default: the common orbital rate at which the traction's orbital torques on the balls cancel, each ball in its steady spin), 1 L1's outer-race control"),
            Param::SolverPiBeta => ("solver.pi_beta", R, None, Some(0.0), Some(crate::scene::MAX_PI_BETA),
                "Beta of the PI step-size controller in [0, 0.2]; 0 (default) the I-controller; 0.08 keeps the reduced and full levels on track at loose tolerances (rtol >= 1e-4) for about 25 % more work"),
            Param::RingAxial => ("ring.axial", I, None, Some(0.0), Some(2.0),
                "Axial mounting of the inner ring (force coupling): 0 the axial load load.Fx acts on it (default); 1 located where the start's load.Fx alone puts it (a preload; centred with the balls just touching at load.Fx = 0); 2 located at ring.axial_offset. Located, the ring carries a pure radial load, bearing.F.x is the axial reaction of its location, and load.Fx cannot change after the start"),
            Param::RingAxialOffset => ("ring.axial_offset", R, Some("m"), Some(-1e-3), Some(1e-3),
                "Axial displacement of a located inner ring (ring.axial = 2) from the unloaded, centred position, along +x (the way load.Fx > 0 pushes it)"),
        }
    }

    pub fn name(self) -> &'static str {
        self.info().0
    }
}

impl Stat {
    pub const ALL: [Stat; 3] = [Stat::Steps, Stat::Rejected, Stat::RhsEvals];
}

/// One row of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    pub var: Variable,
    pub role: Role,
}

fn base(vr: u32, name: &str, ty: VarType, c: Causality, v: Variability, desc: &str) -> Variable {
    Variable {
        vr,
        name: name.to_string(),
        ty,
        causality: c,
        variability: v,
        initial: None,
        description: desc.to_string(),
        unit: None,
        declared_type: None,
        display_unit: None,
        start: Start::None,
        min: None,
        max: None,
    }
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

fn with_unit(mut v: Variable, unit: Option<&str>) -> Variable {
    if let Some(u) = unit {
        v.unit = Some(u.to_string());
        v.declared_type = quantity_of(u).map(str::to_string);
        if u == "rad/s" {
            v.display_unit = Some("rpm".into());
        }
    }
    v
}

/// The full table for an FMU built on `bearing`.
pub fn table(bearing: &BearingFile) -> Vec<Entry> {
    let cfg = Config::default_for(bearing);
    let inputs = cfg.scene.operating;
    let mut t = Vec::new();
    let input_info = [
        (
            Input::ShaftSpeed,
            "shaft.speed",
            "rad/s",
            "Shaft (inner-ring) speed about +x (>= 0)",
        ),
        (
            Input::Fx,
            "load.Fx",
            "N",
            "External force on the inner ring along x (axial load Fa, +x)",
        ),
        (
            Input::Fy,
            "load.Fy",
            "N",
            "External force on the inner ring along y",
        ),
        (
            Input::Fz,
            "load.Fz",
            "N",
            "External force on the inner ring along z (the paper's radial load: Fz = -Fr)",
        ),
    ];
    for (k, (inp, name, unit, desc)) in input_info.into_iter().enumerate() {
        let mut v = with_unit(
            base(
                1 + k as u32,
                name,
                VarType::Real,
                Causality::Input,
                Variability::Continuous,
                desc,
            ),
            Some(unit),
        );
        v.start = Start::Real(inp.get(&inputs));
        if inp == Input::ShaftSpeed {
            v.min = Some(0.0);
        }
        t.push(Entry {
            var: v,
            role: Role::Input(inp),
        });
    }
    for j in JournalInput::ALL {
        let (unit, desc) = if j.0 < 3 {
            ("m", "Journal (inner-ring centre) displacement along {axis} in coupling mode motion, same frame and origin as ring.{axis}; ignored in force mode")
        } else {
            ("m/s", "Journal (inner-ring centre) velocity along {axis} in coupling mode motion: within a communication step the ring moves as x_k + v_k (t - t_k); ignored in force mode")
        };
        let axis = ["x", "y", "z"][j.0 % 3];
        let mut v = with_unit(
            base(
                5 + j.0 as u32,
                j.name(),
                VarType::Real,
                Causality::Input,
                Variability::Continuous,
                &desc.replace("{axis}", axis),
            ),
            Some(unit),
        );
        v.start = Start::Real(0.0);
        t.push(Entry {
            var: v,
            role: Role::Journal(j),
        });
    }
    for (k, p) in Param::ALL.into_iter().enumerate() {
        let (name, ty, unit, min, max, desc) = p.info();
        let mut v = with_unit(
            base(
                100 + k as u32,
                name,
                ty,
                Causality::Parameter,
                Variability::Fixed,
                desc,
            ),
            unit,
        );
        v.initial = Some(Initial::Exact);
        let value = cfg.get(p);
        v.start = match ty {
            VarType::Integer => Start::Integer(value as i32),
            _ => Start::Real(value),
        };
        v.min = min;
        v.max = max;
        t.push(Entry {
            var: v,
            role: Role::Param(p),
        });
    }
    let z = bearing.bearing.z as usize;
    for (i, o) in output_table(z).into_iter().enumerate() {
        let mut v = with_unit(
            base(
                1000 + i as u32,
                &o.name,
                VarType::Real,
                Causality::Output,
                Variability::Continuous,
                &o.description,
            ),
            Some(o.unit),
        );
        v.initial = Some(Initial::Calculated);
        t.push(Entry {
            var: v,
            role: Role::Output(i),
        });
    }
    let stats = [
        (
            Stat::Steps,
            "solver.steps",
            "Accepted integrator steps since the start",
        ),
        (
            Stat::Rejected,
            "solver.rejected",
            "Rejected integrator steps since the start",
        ),
        (
            Stat::RhsEvals,
            "solver.rhs_evals",
            "Right-hand-side evaluations since the start",
        ),
    ];
    for (k, (s, name, desc)) in stats.into_iter().enumerate() {
        let mut v = base(
            900 + k as u32,
            name,
            VarType::Integer,
            Causality::Output,
            Variability::Discrete,
            desc,
        );
        v.initial = Some(Initial::Calculated);
        t.push(Entry {
            var: v,
            role: Role::Stat(s),
        });
    }
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
        assert_eq!(
            t.len(),
            4 + 6 + Param::ALL.len() + output_table(z).len() + 3
        );
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
    fn params_round_trip() {
        let b = BearingFile::default_preset();
        let mut cfg = Config::default_for(&b);
        for p in Param::ALL {
            let v = cfg.get(p);
            cfg.set(p, v).unwrap();
            assert_eq!(cfg.get(p), v, "{}", p.name());
        }
        assert_eq!(cfg, Config::default_for(&b));
    }
}
