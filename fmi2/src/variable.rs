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
    /// `Enumeration`: an Integer whose values are the items of an [`EnumerationType`], which
    /// the variable names in [`Variable::declared_type`]. It is read and written through
    /// `fmi2GetInteger` and `fmi2SetInteger` (Integer and Enumeration share the Integer value
    /// references), its start value is a [`Start::Integer`], and the shell enforces its
    /// `min`/`max` as for an Integer.
    Enumeration,
}

impl VarType {
    /// The XML element name.
    pub fn name(self) -> &'static str {
        match self {
            VarType::Real => "Real",
            VarType::Integer => "Integer",
            VarType::Boolean => "Boolean",
            VarType::String => "String",
            VarType::Enumeration => "Enumeration",
        }
    }

    /// The type of the `fmi2Get*`/`fmi2Set*` functions that access a variable of this type:
    /// [`VarType::Integer`] for an Enumeration, the type itself otherwise.
    pub fn access_type(self) -> VarType {
        match self {
            VarType::Enumeration => VarType::Integer,
            t => t,
        }
    }
}

/// One item of an [`EnumerationType`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EnumerationItem {
    /// The item's name (what an importer shows instead of the value).
    pub name: String,
    /// The item's value, as `fmi2GetInteger`/`fmi2SetInteger` pass it.
    pub value: i32,
    /// What the item means.
    pub description: String,
}

/// An FMI 2.0 enumeration type (`<SimpleType name><Enumeration><Item …/></Enumeration>`), named
/// by the [`Variable::declared_type`] of its variables of type [`VarType::Enumeration`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct EnumerationType {
    /// The `SimpleType` name.
    pub name: String,
    /// The `SimpleType` description (empty: omitted).
    pub description: String,
    /// The items, in the order the XML lists them (FMI 2.0: distinct names and values).
    pub items: Vec<EnumerationItem>,
}

impl EnumerationType {
    /// The smallest and largest item value; `None` without items.
    pub fn range(&self) -> Option<(i32, i32)> {
        let lo = self.items.iter().map(|i| i.value).min()?;
        let hi = self.items.iter().map(|i| i.value).max()?;
        Some((lo, hi))
    }

    /// The item of value `value`, if any.
    pub fn item(&self, value: i32) -> Option<&EnumerationItem> {
        self.items.iter().find(|i| i.value == value)
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
    /// An Integer (or Enumeration) start value.
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
    /// The `SimpleType` name, if any: for a Real, a type the XML writer derives from the unit
    /// (`quantity` = the name); for an Enumeration (required), an [`EnumerationType`] of the
    /// model description ([`crate::xml::ModelInfo::enumerations`]).
    pub declared_type: Option<String>,
    /// Display unit (Real only).
    pub display_unit: Option<String>,
    /// Start value.
    pub start: Start,
    /// Inclusive bounds (Real, Integer and Enumeration); the shell enforces them on every set.
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
