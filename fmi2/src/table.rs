//! Declarative variable tables: one [`Row`] per variable with its value reference written out,
//! its metadata and what the model reads and writes for it (`A`, the model's accessor type), so
//! that a variable is added in one place and value references never move.

use crate::variable::{Causality, Initial, Start, VarType, Variability, Variable};

/// One row of a model's variable table.
#[derive(Debug, Clone, Copy)]
pub struct Row<A> {
    /// Value reference (written out, never derived from the row's position).
    pub vr: u32,
    /// Variable name.
    pub name: &'static str,
    /// FMI base type.
    pub ty: VarType,
    /// FMI causality.
    pub causality: Causality,
    /// FMI variability.
    pub variability: Variability,
    /// `initial` attribute (`None`: omitted).
    pub initial: Option<Initial>,
    /// Unit (Real only).
    pub unit: Option<&'static str>,
    /// The `SimpleType` an Enumeration names (its [`crate::EnumerationType`]'s name); `None`
    /// for the other types (a Real's type follows from its unit).
    pub declared_type: Option<&'static str>,
    /// Inclusive lower bound, enforced by the shell on every set.
    pub min: Option<f64>,
    /// Inclusive upper bound, enforced by the shell on every set.
    pub max: Option<f64>,
    /// Description.
    pub description: &'static str,
    /// What the model reads and writes for the variable (getter and setter).
    pub access: A,
}

impl<A> Row<A> {
    /// The [`Variable`] of this row with the given start value (the model computes it, e.g.
    /// from its default configuration).
    pub fn variable(&self, start: Start) -> Variable {
        Variable {
            vr: self.vr,
            name: self.name.to_string(),
            ty: self.ty,
            causality: self.causality,
            variability: self.variability,
            initial: self.initial,
            description: self.description.to_string(),
            unit: self.unit.map(str::to_string),
            declared_type: self.declared_type.map(str::to_string),
            display_unit: None,
            start,
            min: self.min,
            max: self.max,
            derivative_of: None,
        }
    }
}

/// Checks that value references and names are unique; `Err` names the first duplicate.
pub fn check_unique(vars: &[Variable]) -> Result<(), String> {
    let mut vrs = std::collections::HashSet::new();
    let mut names = std::collections::HashSet::new();
    for v in vars {
        if !vrs.insert(v.vr) {
            return Err(format!("duplicate value reference {}", v.vr));
        }
        if !names.insert(v.name.as_str()) {
            return Err(format!("duplicate variable name '{}'", v.name));
        }
    }
    Ok(())
}
