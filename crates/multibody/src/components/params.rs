//! Parameter values of one component, checked against its kind's table and
//! completed with defaults.

use super::spec::{ComponentSpec, Default, ParamType};
use super::world::WorldSettings;
use crate::error::closest;
use crate::math::Vec3;
use crate::{ComponentInstance, Error, Value};

/// The validated parameters of one component: every parameter of its kind
/// has a value of the right type and size, except `Derived` defaults that
/// were not given (the component computes those).
#[derive(Debug)]
pub struct ParamSet<'a> {
    pub component: &'a str,
    pub spec: &'static ComponentSpec,
    values: Vec<Option<Value>>,
    given: Vec<bool>,
    pub world: &'a WorldSettings,
    /// The road the model gives the component (`wheel.surface = ...`).
    pub surface: Option<&'a crate::math::expr::Expr>,
}

impl<'a> ParamSet<'a> {
    /// Checks `instance`'s parameters against `spec` and fills in defaults.
    pub fn resolve(
        instance: &'a ComponentInstance,
        spec: &'static ComponentSpec,
        world: &'a WorldSettings,
    ) -> Result<Self, Error> {
        let mut values: Vec<Option<Value>> = vec![None; spec.params.len()];
        let mut given = vec![false; spec.params.len()];
        for (name, value) in &instance.params {
            let Some(index) = spec.params.iter().position(|p| p.name == name) else {
                return Err(Error::UnknownParameter {
                    component: instance.name.clone(),
                    kind: spec.kind.into(),
                    param: name.clone(),
                    suggestions: closest(name, spec.params.iter().map(|p| p.name)),
                    valid: spec.params.iter().map(|p| p.name.to_string()).collect(),
                    planar_has_it: planar_has(spec, name),
                });
            };
            values[index] = Some(check_value(&instance.name, name, spec.params[index].ty, value)?);
            given[index] = true;
        }
        for (index, p) in spec.params.iter().enumerate() {
            if values[index].is_none() {
                values[index] = match p.default {
                    Default::Number(x) => Some(Value::Number(x)),
                    Default::Vector(v) => Some(Value::Array(v.to_vec())),
                    Default::Bool(b) => Some(Value::Bool(b)),
                    Default::Enum(e) => Some(Value::Enum(e.to_string())),
                    Default::Matrix(rows) => Some(Value::Matrix(rows.iter().map(|r| r.to_vec()).collect())),
                    Default::Text(text) => Some(Value::Str(text.to_string())),
                    Default::World(name, factor) => Some(world.scaled(name, factor)),
                    Default::Derived(_) => None,
                    Default::Required => {
                        return Err(Error::MissingParameter {
                            component: instance.name.clone(),
                            kind: spec.kind.into(),
                            param: p.name.into(),
                            doc: p.doc.into(),
                        })
                    }
                };
            }
        }
        if instance.surface.is_some() && spec.param("surface").is_none() {
            return Err(Error::InvalidValue {
                component: instance.name.clone(),
                name: "surface".into(),
                value: "a road".into(),
                reason: format!(
                    "a {} rolls on no road surface; the wheels that may lean (RollingWheel, \
                     RollingWheelJoint, SlippingWheel, SlipWheelJoint, PacejkaSlippingWheel, PacejkaWheelJoint) \
                     take one",
                    spec.kind
                ),
            });
        }
        Ok(Self { component: &instance.name, spec, values, given, world, surface: instance.surface.as_ref() })
    }

    fn value(&self, name: &str) -> Option<&Value> {
        let index = self
            .spec
            .params
            .iter()
            .position(|p| p.name == name)
            .unwrap_or_else(|| panic!("{} has no parameter {name}", self.spec.kind));
        self.values[index].as_ref()
    }

    /// The value as given or defaulted (`None`: a derived default not given).
    pub(crate) fn raw(&self, name: &str) -> Option<&Value> {
        self.value(name)
    }

    /// Whether the model set this parameter (rather than the default).
    pub fn is_given(&self, name: &str) -> bool {
        self.spec.params.iter().position(|p| p.name == name).is_some_and(|i| self.given[i])
    }

    pub fn real(&self, name: &str) -> f64 {
        self.real_opt(name).unwrap_or(0.0)
    }

    /// A real parameter, or `None` for a derived default that was not given.
    pub fn real_opt(&self, name: &str) -> Option<f64> {
        match self.value(name) {
            Some(Value::Number(x)) => Some(*x),
            _ => None,
        }
    }

    pub fn vector(&self, name: &str) -> Vec<f64> {
        self.vector_opt(name).unwrap_or_default()
    }

    pub fn vector_opt(&self, name: &str) -> Option<Vec<f64>> {
        match self.value(name) {
            Some(Value::Array(v)) => Some(v.clone()),
            _ => None,
        }
    }

    pub fn vec3(&self, name: &str) -> Vec3 {
        self.vec3_opt(name).unwrap_or_else(Vec3::zeros)
    }

    pub fn vec3_opt(&self, name: &str) -> Option<Vec3> {
        self.vector_opt(name).map(|v| Vec3::new(v[0], v[1], v[2]))
    }

    pub fn color(&self, name: &str) -> [f64; 4] {
        let v = self.vector(name);
        [v[0], v[1], v[2], v[3]]
    }

    /// The rows of a table parameter.
    pub fn matrix(&self, name: &str) -> Vec<Vec<f64>> {
        match self.value(name) {
            Some(Value::Matrix(rows)) => rows.clone(),
            _ => Vec::new(),
        }
    }

    /// A string parameter (`""` if it has none).
    pub fn text(&self, name: &str) -> &str {
        match self.value(name) {
            Some(Value::Str(text)) => text,
            _ => "",
        }
    }

    pub fn boolean(&self, name: &str) -> bool {
        matches!(self.value(name), Some(Value::Bool(true)))
    }

    pub fn integer(&self, name: &str) -> i64 {
        self.real(name) as i64
    }

    /// An Euler sequence, checked: axes 1, 2 or 3, neighbours different.
    pub fn sequence(&self, name: &str) -> Result<[usize; 3], Error> {
        let v = self.vector(name);
        let seq = [v[0] as usize, v[1] as usize, v[2] as usize];
        if crate::math::is_valid_sequence(seq) {
            Ok(seq)
        } else {
            Err(self.invalid(
                name,
                "an Euler sequence has axes 1, 2 or 3, and neighbouring axes differ, e.g. [1, 2, 3] or [3, 1, 3]",
            ))
        }
    }

    pub fn variant(&self, name: &str) -> &str {
        match self.value(name) {
            Some(Value::Enum(v)) => v,
            _ => "",
        }
    }

    /// A unit vector from a direction parameter, which must not be zero.
    pub fn direction(&self, name: &str) -> Result<Vec3, Error> {
        let v = self.vec3(name);
        let n = v.norm();
        if n < 1e-10 {
            return Err(self.invalid(name, "a direction must not be the zero vector"));
        }
        Ok(v / n)
    }

    /// A parameter that must be positive (or zero when `allow_zero`).
    pub fn non_negative(&self, name: &str, allow_zero: bool) -> Result<f64, Error> {
        let x = self.real(name);
        if x > 0.0 || (allow_zero && x == 0.0) {
            Ok(x)
        } else {
            let what = if allow_zero { "it must not be negative" } else { "it must be positive" };
            Err(self.invalid(name, what))
        }
    }

    /// An error about this component's parameter `name`.
    pub fn invalid(&self, name: &str, reason: impl Into<String>) -> Error {
        Error::InvalidValue {
            component: self.component.into(),
            name: name.into(),
            value: self.value(name).map_or_else(|| "(default)".into(), |v| v.to_string()),
            reason: reason.into(),
        }
    }
}

/// Checks one value against a parameter (or variable) type, and normalises
/// it (enum values lose a `Type.` prefix).
pub fn check_value(component: &str, name: &str, ty: ParamType, value: &Value) -> Result<Value, Error> {
    let wrong = || Error::WrongType {
        component: component.into(),
        name: name.into(),
        expected: ty.describe(),
        got: value.describe(),
    };
    let wrong_size = |expected: usize, got: usize| Error::WrongSize {
        component: component.into(),
        name: name.into(),
        expected,
        got,
    };
    match (ty, value) {
        (ParamType::Real, Value::Number(x)) => finite(component, name, value, &[*x]).map(|_| value.clone()),
        // `Vector(0)`: one number per axis, as many as there are.
        (ParamType::Vector(0), Value::Array(v)) if !v.is_empty() => {
            finite(component, name, value, v).map(|_| value.clone())
        }
        (ParamType::Vector(0), Value::Number(x)) => {
            finite(component, name, value, &[*x]).map(|_| Value::Array(vec![*x]))
        }
        (ParamType::Vector(n), Value::Array(v)) => {
            if v.len() != n {
                return Err(wrong_size(n, v.len()));
            }
            finite(component, name, value, v).map(|_| value.clone())
        }
        (ParamType::Vector(n), Value::Number(_)) if n > 1 => Err(wrong_size(n, 1)),
        (ParamType::Bool, Value::Bool(_)) => Ok(value.clone()),
        (ParamType::Integer, Value::Number(x)) if x.fract() == 0.0 => Ok(value.clone()),
        (ParamType::IntVector(n), Value::Array(v)) => {
            if v.len() != n {
                return Err(wrong_size(n, v.len()));
            }
            if v.iter().any(|x| x.fract() != 0.0) {
                return Err(wrong());
            }
            Ok(value.clone())
        }
        (ParamType::Matrix(n), Value::Matrix(rows)) => {
            if let Some(bad) = rows.iter().find(|r| r.len() != n) {
                return Err(wrong_size(n, bad.len()));
            }
            finite(component, name, value, &rows.concat()).map(|_| value.clone())
        }
        (ParamType::FixedMatrix(r, c), Value::Matrix(rows)) => {
            if let Some(bad) = rows.iter().find(|row| row.len() != c) {
                return Err(wrong_size(c, bad.len()));
            }
            if rows.len() != r {
                return Err(Error::InvalidValue {
                    component: component.into(),
                    name: name.into(),
                    value: value.to_string(),
                    reason: format!("it needs {r} rows of {c} numbers, not {} rows", rows.len()),
                });
            }
            finite(component, name, value, &rows.concat()).map(|_| value.clone())
        }
        (ParamType::Text, Value::Str(_)) => Ok(value.clone()),
        (ParamType::Enum(ty_name, variants), Value::Enum(v)) => {
            let bare = v.strip_prefix(ty_name).and_then(|s| s.strip_prefix('.')).unwrap_or(v);
            let bare = bare.strip_suffix("()").unwrap_or(bare);
            if variants.contains(&bare) {
                Ok(Value::Enum(bare.to_string()))
            } else {
                Err(Error::InvalidValue {
                    component: component.into(),
                    name: name.into(),
                    value: v.clone(),
                    reason: format!("it must be {}", ty.describe()),
                })
            }
        }
        _ => Err(wrong()),
    }
}

fn finite(component: &str, name: &str, value: &Value, xs: &[f64]) -> Result<(), Error> {
    if xs.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(Error::InvalidValue {
            component: component.into(),
            name: name.into(),
            value: value.to_string(),
            reason: "values must be finite numbers".into(),
        })
    }
}

/// Whether the planar kind of the same name as the 3-D kind `spec` has
/// `param` (which the 3-D kind lacks).
fn planar_has(spec: &ComponentSpec, param: &str) -> bool {
    super::lookup(&format!("PlanarMechanics.{}", spec.kind)).is_some_and(|p| p.param(param).is_some())
}
