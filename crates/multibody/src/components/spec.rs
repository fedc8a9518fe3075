//! The declarative description of a component kind: its parameters,
//! connectors and variables. The same tables drive validation, the
//! `describe` command and the output names.

use super::shapes::LocalShape;
use super::{Component, ParamSet};
use crate::Error;

/// A component kind.
pub struct ComponentSpec {
    /// The name users write, e.g. `"Body"`.
    pub kind: &'static str,
    pub doc: &'static str,
    pub params: &'static [ParamSpec],
    pub connectors: &'static [ConnectorSpec],
    /// Every variable the kind can have; some exist only with some
    /// parameter values (see each `doc`).
    pub variables: &'static [VarSpec],
    /// Builds the component from validated parameters.
    pub build: fn(&ParamSet) -> Result<Box<dyn Component>, Error>,
    /// The shapes it draws in animations (none when `render = false`).
    pub shapes: fn(&ParamSet) -> Vec<LocalShape>,
}

impl ComponentSpec {
    pub fn param(&self, name: &str) -> Option<&ParamSpec> {
        self.params.iter().find(|p| p.name == name)
    }

    /// The public connector `name` and its number.
    pub fn connector(&self, name: &str) -> Option<(usize, &ConnectorSpec)> {
        self.connectors.iter().enumerate().find(|(_, c)| c.name == name && !c.internal)
    }

    /// The connectors models connect to.
    pub fn public_connectors(&self) -> impl Iterator<Item = &ConnectorSpec> {
        self.connectors.iter().filter(|c| !c.internal)
    }

    /// Whether it is a planar component (PlanarMechanics; its first
    /// connector is a Frame2D): it lives in the planar World's plane, whose
    /// pose places its grounds, and reads its frames in its coordinates.
    pub fn is_planar(&self) -> bool {
        self.connectors.first().is_some_and(|k| k.ty == ConnectorType::Frame2D)
    }
}

impl std::fmt::Debug for ComponentSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "ComponentSpec({})", self.kind)
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamType {
    Real,
    /// A vector of this many numbers (a colour is a vector of 4).
    Vector(usize),
    Bool,
    Integer,
    /// A vector of this many integers, e.g. an Euler sequence.
    IntVector(usize),
    /// An enumeration type and its variants.
    Enum(&'static str, &'static [&'static str]),
    /// Rows of this many numbers each, any number of rows (a table).
    Matrix(usize),
    /// Exactly this many rows of this many numbers each, e.g. a 4x4
    /// homogeneous transform.
    FixedMatrix(usize, usize),
    /// A string in double quotes, e.g. the path of a mesh file.
    Text,
}

impl ParamType {
    pub fn describe(&self) -> String {
        match self {
            ParamType::Real => "a number".into(),
            ParamType::Vector(0) => "an array of numbers, one per axis".into(),
            ParamType::Vector(n) => format!("an array of {n} numbers"),
            ParamType::Bool => "true or false".into(),
            ParamType::Integer => "an integer".into(),
            ParamType::IntVector(n) => format!("an array of {n} integers"),
            ParamType::Matrix(n) => format!("rows of {n} numbers, e.g. [[0, 1], [2, 3]]"),
            ParamType::FixedMatrix(r, c) => format!("a {r}x{c} array of numbers, given as {r} rows of {c}"),
            ParamType::Text => "a string, e.g. \"meshes/part.stl\"".into(),
            ParamType::Enum(ty, variants) => {
                format!("one of {}", variants.iter().map(|v| format!("{ty}.{v}")).collect::<Vec<_>>().join(", "))
            }
        }
    }
}

/// A parameter's default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Default {
    Number(f64),
    Vector(&'static [f64]),
    Bool(bool),
    Enum(&'static str),
    /// A matrix, as rows.
    Matrix(&'static [&'static [f64]]),
    /// A string.
    Text(&'static str),
    /// A World parameter times a factor, e.g. `world.default_body_diameter / 2`.
    World(&'static str, f64),
    /// Computed by the component from its other parameters; the text says how.
    Derived(&'static str),
    /// No default: the model must set it.
    Required,
}

impl std::fmt::Display for Default {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Default::Number(x) => write!(f, "{x}"),
            Default::Vector(v) => write!(f, "{}", crate::Value::Array(v.to_vec())),
            Default::Bool(b) => write!(f, "{b}"),
            Default::Enum(v) => write!(f, "{v}"),
            Default::Matrix(rows) => write!(f, "{}", crate::Value::Matrix(rows.iter().map(|r| r.to_vec()).collect())),
            Default::Text(text) => write!(f, "{text:?}"),
            Default::World(p, s) if *s == 1.0 => write!(f, "world.{p}"),
            Default::World(p, s) if *s < 1.0 => write!(f, "world.{p} / {}", 1.0 / s),
            Default::World(p, s) => write!(f, "world.{p} * {s}"),
            Default::Derived(text) => write!(f, "{text}"),
            Default::Required => write!(f, "(required)"),
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub struct ParamSpec {
    pub name: &'static str,
    pub ty: ParamType,
    pub default: Default,
    pub unit: &'static str,
    pub doc: &'static str,
}

impl ParamSpec {
    pub const fn real(name: &'static str, default: f64, unit: &'static str, doc: &'static str) -> Self {
        Self { name, ty: ParamType::Real, default: Default::Number(default), unit, doc }
    }
    pub const fn vector(name: &'static str, default: &'static [f64], unit: &'static str, doc: &'static str) -> Self {
        Self { name, ty: ParamType::Vector(default.len()), default: Default::Vector(default), unit, doc }
    }
    pub const fn boolean(name: &'static str, default: bool, doc: &'static str) -> Self {
        Self { name, ty: ParamType::Bool, default: Default::Bool(default), unit: "", doc }
    }
    pub const fn text(name: &'static str, default: &'static str, doc: &'static str) -> Self {
        Self { name, ty: ParamType::Text, default: Default::Text(default), unit: "", doc }
    }
    /// A matrix of as many rows and columns as its default has.
    pub const fn matrix(
        name: &'static str,
        default: &'static [&'static [f64]],
        unit: &'static str,
        doc: &'static str,
    ) -> Self {
        Self {
            name,
            ty: ParamType::FixedMatrix(default.len(), default[0].len()),
            default: Default::Matrix(default),
            unit,
            doc,
        }
    }
    pub const fn integer(name: &'static str, default: f64, doc: &'static str) -> Self {
        Self { name, ty: ParamType::Integer, default: Default::Number(default), unit: "", doc }
    }
    pub const fn world(
        name: &'static str,
        ty: ParamType,
        param: &'static str,
        factor: f64,
        unit: &'static str,
        doc: &'static str,
    ) -> Self {
        Self { name, ty, default: Default::World(param, factor), unit, doc }
    }
    pub const fn required(name: &'static str, ty: ParamType, unit: &'static str, doc: &'static str) -> Self {
        Self { name, ty, default: Default::Required, unit, doc }
    }
    pub const fn derived(
        name: &'static str,
        ty: ParamType,
        how: &'static str,
        unit: &'static str,
        doc: &'static str,
    ) -> Self {
        Self { name, ty, default: Default::Derived(how), unit, doc }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConnectorType {
    /// A 3-D frame (Frame3D).
    Frame,
    /// A planar frame (Frame2D): a frame that stays in the world's x-y
    /// plane, turned about z. Inside, it is a frame like any other; it
    /// connects only to planar frames, and reads as `x`, `y`, `phi`, `fx`,
    /// `fy`, `tau` (world coordinates).
    Frame2D,
    /// A 1-D rotational flange (Dyad's Spline).
    Spline,
    /// A 1-D translational flange.
    Flange,
    /// A real signal input.
    RealInput,
    /// A real signal output.
    RealOutput,
}

impl ConnectorType {
    pub fn name(&self) -> &'static str {
        match self {
            ConnectorType::Frame => "Frame3D",
            ConnectorType::Frame2D => "Frame2D",
            ConnectorType::Spline => "Spline",
            ConnectorType::Flange => "Flange",
            ConnectorType::RealInput => "RealInput",
            ConnectorType::RealOutput => "RealOutput",
        }
    }

    /// Whether connectors of the two types may be connected.
    pub fn connects_to(&self, other: &ConnectorType) -> bool {
        self == other || (self.is_signal() && other.is_signal())
    }

    /// Whether it is a frame (3-D or planar): a node of the mechanism.
    pub fn is_frame(&self) -> bool {
        matches!(self, ConnectorType::Frame | ConnectorType::Frame2D)
    }

    pub fn is_signal(&self) -> bool {
        matches!(self, ConnectorType::RealInput | ConnectorType::RealOutput)
    }
}

#[derive(Clone, Copy, Debug)]
pub struct ConnectorSpec {
    pub name: &'static str,
    pub ty: ConnectorType,
    pub doc: &'static str,
    /// A connector inside the component (between its inner joints, say),
    /// which models cannot connect to and `describe` does not show.
    pub internal: bool,
}

impl ConnectorSpec {
    pub const fn frame(name: &'static str, doc: &'static str) -> Self {
        Self { name, ty: ConnectorType::Frame, doc, internal: false }
    }
    pub const fn frame_2d(name: &'static str, doc: &'static str) -> Self {
        Self { name, ty: ConnectorType::Frame2D, doc, internal: false }
    }
    pub const fn flange(name: &'static str, ty: ConnectorType, doc: &'static str) -> Self {
        Self { name, ty, doc, internal: false }
    }
    pub const fn input(name: &'static str, doc: &'static str) -> Self {
        Self { name, ty: ConnectorType::RealInput, doc, internal: false }
    }
    pub const fn output(name: &'static str, doc: &'static str) -> Self {
        Self { name, ty: ConnectorType::RealOutput, doc, internal: false }
    }
    /// An internal connector; they come after the public ones.
    pub const fn internal(name: &'static str, ty: ConnectorType) -> Self {
        Self { name, ty, doc: "", internal: true }
    }
}

/// The shape of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Scalar,
    Vector(usize),
    Matrix(usize, usize),
}

impl Shape {
    pub fn len(&self) -> usize {
        match self {
            Shape::Scalar => 1,
            Shape::Vector(n) => *n,
            Shape::Matrix(r, c) => r * c,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The 1-based suffixes of the scalar signals, e.g. `[1]`, `[2,3]`.
    pub fn suffixes(&self) -> Vec<String> {
        match *self {
            Shape::Scalar => vec![String::new()],
            Shape::Vector(n) => (1..=n).map(|i| format!("[{i}]")).collect(),
            Shape::Matrix(r, c) => (1..=r).flat_map(|i| (1..=c).map(move |j| format!("[{i},{j}]"))).collect(),
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub struct VarSpec {
    pub name: &'static str,
    pub shape: Shape,
    pub unit: &'static str,
    pub doc: &'static str,
}

impl VarSpec {
    pub const fn scalar(name: &'static str, unit: &'static str, doc: &'static str) -> Self {
        Self { name, shape: Shape::Scalar, unit, doc }
    }
    pub const fn vector(name: &'static str, n: usize, unit: &'static str, doc: &'static str) -> Self {
        Self { name, shape: Shape::Vector(n), unit, doc }
    }
}

/// `a` followed by `b`: tables built from shared parts.
pub const fn concat<T: Copy, const N: usize>(a: &[T], b: &[T]) -> [T; N] {
    assert!(a.len() + b.len() == N, "concat: N must be the sum of the lengths");
    let mut out = [if a.is_empty() { b[0] } else { a[0] }; N];
    let mut i = 0;
    while i < N {
        out[i] = if i < a.len() { a[i] } else { b[i - a.len()] };
        i += 1;
    }
    out
}
