//! Variable metadata: what the shell checks `fmi2Get*`/`fmi2Set*` calls against and what the
//! XML generator writes.

/// FMI base type of a variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VarType {
    /// `Real`.
    Real,
    /// `Integer`.
    Integer,
    /// `Boolean`.
    Boolean,
    /// `String`.
    String,
}

impl VarType {
    /// The XML element name.
    pub fn name(self) -> &'static str {
        match self {
            VarType::Real => "Real",
            VarType::Integer => "Integer",
            VarType::Boolean => "Boolean",
            VarType::String => "String",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
/// FMI causality of a variable.
pub enum Causality {
    /// `parameter`.
    Parameter,
    /// `calculatedParameter`.
    CalculatedParameter,
    /// `input`.
    Input,
    /// `output`.
    Output,
    /// `local`.
    Local,
    /// `independent`.
    Independent,
}

impl Causality {
    /// The XML attribute value.
    pub fn name(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
            Causality::Independent => "independent",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
/// FMI variability of a variable.
pub enum Variability {
    /// `constant`.
    Constant,
    /// `fixed`.
    Fixed,
    /// `tunable`.
    Tunable,
    /// `discrete`.
    Discrete,
    /// `continuous`.
    Continuous,
}

impl Variability {
    /// The XML attribute value.
    pub fn name(self) -> &'static str {
        match self {
            Variability::Constant => "constant",
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
/// FMI `initial` attribute of a variable.
pub enum Initial {
    /// `exact`.
    Exact,
    /// `approx`.
    Approx,
    /// `calculated`.
    Calculated,
}

impl Initial {
    /// The XML attribute value.
    pub fn name(self) -> &'static str {
        match self {
            Initial::Exact => "exact",
            Initial::Approx => "approx",
            Initial::Calculated => "calculated",
        }
    }
}

/// Start value of a variable (its type must match the variable's).
#[derive(Debug, Clone, PartialEq)]
pub enum Start {
    /// No start value.
    None,
    /// A Real start value.
    Real(f64),
    /// An Integer start value.
    Integer(i32),
    /// A Boolean start value.
    Boolean(bool),
    /// A String start value.
    String(String),
}

/// One model variable: what the shell checks calls against, and what the XML generator writes.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// Value reference.
    pub vr: u32,
    /// Variable name.
    pub name: String,
    /// FMI base type.
    pub ty: VarType,
    /// Causality.
    pub causality: Causality,
    /// Variability.
    pub variability: Variability,
    /// `None`: the attribute is omitted (FMI default for the causality/variability).
    pub initial: Option<Initial>,
    /// Description.
    pub description: String,
    /// Real only: unit name (must be defined in the model's unit definitions).
    pub unit: Option<String>,
    /// Real only: the `SimpleType` name, if any.
    pub declared_type: Option<String>,
    /// Display unit (Real only).
    pub display_unit: Option<String>,
    /// Start value.
    pub start: Start,
    /// Inclusive bounds (Real and Integer); the shell enforces them on every set.
    pub min: Option<f64>,
    /// Inclusive upper bound (see `min`).
    pub max: Option<f64>,
    /// Model Exchange: the value reference of the continuous state this variable is the
    /// derivative of (the XML's `derivative` attribute, written as that state's index).
    pub derivative_of: Option<u32>,
}

impl Variable {
    /// Whether `fmi2Set*` may write the variable at all (ignoring the call state).
    pub fn is_settable(&self) -> bool {
        self.variability != Variability::Constant
            && matches!(self.causality, Causality::Parameter | Causality::Input)
    }
}
