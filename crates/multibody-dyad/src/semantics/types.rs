//! Types of parameters declared in model files: `Real`, `Integer`,
//! `Boolean`, `String`, the library's enumerations, unit types such as
//! `Length` (numbers), arrays `Length[3]`, and aliases `type X = ...`.

use crate::reports::diagnostics::Diagnostic;
use crate::semantics::eval::Val;
use crate::syntax::ast::{Dim, Modifier, TypeAlias, TypeRef};
use multibody::components::{registry, ParamType};
use std::collections::HashMap;

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BaseType {
    /// `Real` and the unit types (`Length`, `Angle`, ...).
    Real,
    Integer,
    Boolean,
    String,
    /// An enumeration of the library, with its variants.
    Enum(&'static str, &'static [&'static str]),
}

impl BaseType {
    fn describe(&self) -> String {
        match self {
            BaseType::Real => "a number".into(),
            BaseType::Integer => "a whole number".into(),
            BaseType::Boolean => "`true` or `false`".into(),
            BaseType::String => "a string".into(),
            BaseType::Enum(ty, variants) => {
                format!("one of {}", variants.iter().map(|v| format!("{ty}.{v}()")).collect::<Vec<_>>().join(", "))
            }
        }
    }
}

/// A declared type, aliases followed.
pub struct ResolvedType<'a> {
    pub base: BaseType,
    /// The name the aliases end at: `Real`, `Length`, `Integer`, ...
    pub name: &'a str,
    pub dims: &'a [Dim],
    /// `min`, `max`, `units`, ... of the declaration and of its aliases.
    pub attributes: Vec<&'a Modifier>,
}

/// The enumerations the library's parameters use, e.g. `OrientationState`.
pub fn library_enum(name: &str) -> Option<(&'static str, &'static [&'static str])> {
    registry().iter().flat_map(|s| s.params.iter()).find_map(|p| match p.ty {
        ParamType::Enum(ty, variants) if ty == name => Some((ty, variants)),
        _ => None,
    })
}

/// Follows aliases to the base type.
pub fn resolve<'a>(ty: &'a TypeRef, aliases: &HashMap<&str, &'a TypeAlias>) -> Result<ResolvedType<'a>, Diagnostic> {
    let mut current = ty;
    let mut dims: &'a [Dim] = &ty.dims;
    let mut attributes: Vec<&'a Modifier> = ty.attributes.iter().collect();
    for _ in 0..32 {
        let name = current.name.text();
        let Some(alias) = aliases.get(name.as_str()) else {
            let last = current.name.last().name.as_str();
            let base = match last {
                "Integer" => BaseType::Integer,
                "Boolean" => BaseType::Boolean,
                "String" => BaseType::String,
                _ => match library_enum(last) {
                    Some((ty, variants)) => BaseType::Enum(ty, variants),
                    None => BaseType::Real,
                },
            };
            return Ok(ResolvedType { base, name: last, dims, attributes });
        };
        current = &alias.base;
        if dims.is_empty() {
            dims = &current.dims;
        }
        attributes.extend(current.attributes.iter());
    }
    Err(Diagnostic::error(format!("the type `{}` is an alias of itself", ty.name.text()))
        .primary(ty.name.span, "aliases go round in a circle")
        .help("make one of the `type` definitions name a base type such as `Real`"))
}

/// The units of Dyad's standard types (`type Length = Real(units = "m")`
/// in Dyad's `Dyad` library), with the lower bound those that state one
/// give (`type Mass = Real(units = "kg", min = 0)`). The files use these
/// names without defining them; other names are plain numbers.
const STANDARD_TYPES: &[(&str, &str, Option<f64>)] = &[
    ("Acceleration", "m/s2", None),
    ("Angle", "rad", None),
    ("AngularAcceleration", "rad/s2", None),
    ("AngularFrequency", "rad/s", None),
    ("AngularVelocity", "rad/s", None),
    ("Breadth", "m", Some(0.0)),
    ("Capacitance", "F", Some(0.0)),
    ("Conductance", "S", None),
    ("Current", "A", None),
    ("Density", "kg/m3", Some(0.0)),
    ("Diameter", "m", Some(0.0)),
    ("Distance", "m", Some(0.0)),
    ("Duration", "s", None),
    ("ElectricCharge", "C", None),
    ("ElectricCurrent", "A", None),
    ("ElectricPotential", "V", None),
    ("ElectricalForceConstant", "N/A", None),
    ("ElectricalTorqueConstant", "N.m/A", None),
    ("Energy", "J", None),
    ("Force", "N", None),
    ("Frequency", "Hz", None),
    ("HeatCapacity", "J/K", None),
    ("HeatFlowRate", "W", None),
    ("Inductance", "H", None),
    ("Inertia", "kg.m2", None),
    ("Length", "m", None),
    ("Mass", "kg", Some(0.0)),
    ("MomentOfForce", "N.m", None),
    ("MomentOfInertia", "kg.m2", None),
    ("Position", "m", None),
    ("Power", "W", None),
    ("Radius", "m", Some(0.0)),
    ("Resistance", "Ohm", None),
    ("RotationalDampingConstant", "N.m.s/rad", None),
    ("RotationalSpringConstant", "N.m/rad", None),
    ("Temperature", "K", Some(0.0)),
    ("TemperatureDifference", "K", None),
    ("ThermalConductance", "W/K", None),
    ("ThermalResistance", "K/W", None),
    ("ThermodynamicTemperature", "K", Some(0.0)),
    ("Time", "s", None),
    ("Torque", "N.m", None),
    ("TranslationalDampingConstant", "N.s/m", None),
    ("TranslationalSpringConstant", "N/m", None),
    ("Velocity", "m/s", None),
    ("Voltage", "V", None),
];

/// The unit of a standard type such as `Length`, and its lower bound if
/// it states one (see [`STANDARD_TYPES`]).
pub fn standard_unit(name: &str) -> Option<(&'static str, Option<f64>)> {
    STANDARD_TYPES.iter().find(|(n, _, _)| *n == name).map(|(_, unit, min)| (*unit, *min))
}

/// Checks a value against a base type (no dimensions); enumeration values
/// come back as `Type.Variant`.
pub fn check_scalar(base: BaseType, value: &Val) -> Result<Val, String> {
    let wrong = || format!("it takes {}, but this is {}", base.describe(), value.describe());
    match (base, value) {
        (BaseType::Real, Val::Number(_)) | (BaseType::Boolean, Val::Bool(_)) | (BaseType::String, Val::Str(_)) => {
            Ok(value.clone())
        }
        (BaseType::Integer, Val::Number(x)) if x.fract() == 0.0 => Ok(value.clone()),
        (BaseType::Enum(ty, variants), Val::Enum(v)) => {
            let (prefix, variant) = v.rsplit_once('.').unwrap_or(("", v));
            if (prefix.is_empty() || prefix == ty) && variants.contains(&variant) {
                Ok(Val::Enum(format!("{ty}.{variant}")))
            } else {
                Err(wrong())
            }
        }
        _ => Err(wrong()),
    }
}
