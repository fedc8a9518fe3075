//! The model: components, their parameter values and start values, and the
//! connections between their connectors. Plain data; `Model::assemble`
//! (in `assembly`) validates it and compiles it into a `Mechanism`.
//!
//! ```
//! use multibody::Model;
//! let mut model = Model::new("pendulum");
//! model.add("world", "World");
//! model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).initial("phi", 0.3);
//! model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
//! model.connect(["world.frame_b", "rev.frame_a"]);
//! model.connect(["rev.frame_b", "body.frame_a"]);
//! let mechanism = model.assemble().unwrap();
//! assert_eq!(mechanism.degrees_of_freedom(), 1);
//! ```

use crate::math::expr::Expr;
use std::fmt;

/// A parameter or start value.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Number(f64),
    Bool(bool),
    /// A vector of numbers, e.g. `r_cm = [0.5, 0, 0]`.
    Array(Vec<f64>),
    /// A rectangular array of numbers, given as rows.
    Matrix(Vec<Vec<f64>>),
    /// A variant of an enumeration, e.g. `Quaternion` of `OrientationState`.
    Enum(String),
    /// A string, e.g. the path of a mesh file.
    Str(String),
}

impl Value {
    /// A short description of the kind of value, for messages.
    pub fn describe(&self) -> String {
        match self {
            Value::Number(_) => "a number".into(),
            Value::Bool(_) => "a boolean".into(),
            Value::Array(v) => format!("an array of {} numbers", v.len()),
            Value::Matrix(rows) => format!("a {}x{} array", rows.len(), rows.first().map_or(0, |r| r.len())),
            Value::Enum(name) => format!("the enumeration value {name}"),
            Value::Str(_) => "a string".into(),
        }
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // Very large and very small numbers in exponent form (`1e300`, not
        // three hundred digits).
        fn number(f: &mut fmt::Formatter<'_>, x: f64) -> fmt::Result {
            if x != 0.0 && !(1e-5..1e15).contains(&x.abs()) {
                write!(f, "{x:e}")
            } else {
                write!(f, "{x}")
            }
        }
        fn list(f: &mut fmt::Formatter<'_>, v: &[f64]) -> fmt::Result {
            write!(f, "[")?;
            for (i, x) in v.iter().enumerate() {
                if i > 0 {
                    write!(f, ", ")?;
                }
                number(f, *x)?;
            }
            write!(f, "]")
        }
        match self {
            Value::Number(x) => number(f, *x),
            Value::Bool(b) => write!(f, "{b}"),
            Value::Array(v) => list(f, v),
            Value::Matrix(rows) => {
                write!(f, "[")?;
                for (i, r) in rows.iter().enumerate() {
                    if i > 0 {
                        write!(f, ", ")?;
                    }
                    list(f, r)?;
                }
                write!(f, "]")
            }
            Value::Enum(name) => write!(f, "{name}"),
            Value::Str(text) => write!(f, "{text:?}"),
        }
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Number(x)
    }
}
impl From<i32> for Value {
    fn from(x: i32) -> Self {
        Value::Number(x as f64)
    }
}
impl From<bool> for Value {
    fn from(b: bool) -> Self {
        Value::Bool(b)
    }
}
impl From<&str> for Value {
    fn from(text: &str) -> Self {
        Value::Str(text.into())
    }
}
impl From<String> for Value {
    fn from(text: String) -> Self {
        Value::Str(text)
    }
}
impl<const N: usize> From<[f64; N]> for Value {
    fn from(v: [f64; N]) -> Self {
        Value::Array(v.to_vec())
    }
}
impl<const N: usize> From<[i32; N]> for Value {
    fn from(v: [i32; N]) -> Self {
        Value::Array(v.iter().map(|&x| x as f64).collect())
    }
}
impl From<Vec<f64>> for Value {
    fn from(v: Vec<f64>) -> Self {
        Value::Array(v)
    }
}
impl From<&[f64]> for Value {
    fn from(v: &[f64]) -> Self {
        Value::Array(v.to_vec())
    }
}
impl From<crate::math::Vec3> for Value {
    fn from(v: crate::math::Vec3) -> Self {
        Value::Array(v.iter().copied().collect())
    }
}

/// How a rigid body's orientation is carried when it owns it (the library's
/// `OrientationState`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OrientationState {
    /// The orientation comes from what the component is connected to.
    None,
    /// Euler angles `phi` and their rates `phid` are states.
    Euler,
    /// A non-unit quaternion `Q_hat` and the angular velocity `w_a` are states.
    Quaternion,
}

impl OrientationState {
    pub const VARIANTS: &'static [&'static str] = &["None", "Euler", "Quaternion"];
}

impl From<OrientationState> for Value {
    fn from(o: OrientationState) -> Self {
        Value::Enum(format!("{o:?}"))
    }
}

/// One component of a model: its name, its kind (a name from the
/// registry, see [`crate::components::registry`]), the parameters it sets
/// and the start values of its variables.
#[derive(Clone, Debug, PartialEq)]
pub struct ComponentInstance {
    pub name: String,
    pub kind: String,
    pub params: Vec<(String, Value)>,
    /// Start values that must hold (`phi(initial = 0.3)`).
    pub initial: Vec<(String, Value)>,
    /// Start values that are only guesses for a solver (`s(guess = -0.2)`).
    pub guess: Vec<(String, Value)>,
    /// The road a wheel rolls on, `y = surface(x, z)` (a model's
    /// `wheel.surface = ...`); only components with a `surface` parameter
    /// take one.
    pub surface: Option<crate::math::expr::Expr>,
}

impl ComponentInstance {
    /// Sets a parameter, replacing an earlier value of the same name.
    pub fn set(&mut self, param: &str, value: impl Into<Value>) -> &mut Self {
        upsert(&mut self.params, param, value.into());
        self
    }

    /// Sets the start value of a variable (a state of the component).
    pub fn initial(&mut self, variable: &str, value: impl Into<Value>) -> &mut Self {
        upsert(&mut self.initial, variable, value.into());
        self
    }

    /// Gives a guess for a variable, used where start values are solved for.
    pub fn guess(&mut self, variable: &str, value: impl Into<Value>) -> &mut Self {
        upsert(&mut self.guess, variable, value.into());
        self
    }

    /// Sets the road surface `y = surface(x, z)` of a wheel: an expression
    /// in the variables `Expr::Var("x")` and `Expr::Var("z")` (the world's).
    pub fn surface(&mut self, surface: crate::math::expr::Expr) -> &mut Self {
        self.surface = Some(surface);
        self
    }

    pub fn param(&self, name: &str) -> Option<&Value> {
        self.params.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
}

fn upsert(list: &mut Vec<(String, Value)>, name: &str, value: Value) {
    match list.iter_mut().find(|(n, _)| n == name) {
        Some(entry) => entry.1 = value,
        None => list.push((name.to_string(), value)),
    }
}

/// A connection joining two or more connectors, each written
/// `component.connector`.
#[derive(Clone, Debug, PartialEq)]
pub struct Connection {
    pub ends: Vec<String>,
}

/// One equation `lhs = rhs` of the model's own (user-written) equations.
#[derive(Clone, Debug, PartialEq)]
pub struct Equation {
    pub lhs: Expr,
    pub rhs: Expr,
    /// What the equation is, for messages: the front end's words for it
    /// (where it was written, say), or empty.
    pub origin: String,
}

impl Equation {
    pub fn new(lhs: Expr, rhs: Expr) -> Self {
        Self { lhs, rhs, origin: String::new() }
    }
}

/// A variable of the model's equations: an unknown the equations decide,
/// or a state when its derivative appears (`der(x)`).
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub name: String,
    /// Its start value, if given; `fixed` says whether it must hold (an
    /// `initial` value) or is a guess the start may change.
    pub start: Option<f64>,
    pub fixed: bool,
    pub unit: String,
    /// Where it was declared, for messages.
    pub origin: String,
}

impl Variable {
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), start: None, fixed: false, unit: String::new(), origin: String::new() }
    }
}

/// A `when` clause: its branches (`when c1 ... elsewhen c2 ...`), each a
/// condition and what happens at the event where it becomes true (the
/// first branch whose condition became true, only).
#[derive(Clone, Debug, PartialEq)]
pub struct When {
    pub branches: Vec<(Expr, Vec<WhenAction>)>,
    /// Where it was written, for messages.
    pub origin: String,
}

/// What a `when` does when it fires.
#[derive(Clone, Debug, PartialEq)]
pub enum WhenAction {
    /// `x = value`: the variable `x` becomes discrete (it holds between
    /// events) and takes `value`.
    Assign { variable: String, value: Expr, origin: String },
    /// `reinit(state, value)`: the state (of the equations, `h`, or of the
    /// mechanics, `rev.w`) jumps to `value`.
    Reinit { state: String, value: Expr, origin: String },
}

/// The flows a component of the model's equations gives a connector that
/// the mechanics moves: the names of the variables that hold them. The
/// flows act on that component, so the connector's node receives their
/// opposite (Modelica's sign convention).
#[derive(Clone, Debug, PartialEq)]
pub enum Flow {
    /// At the frame of library connector `connector` (`body.frame_a`):
    /// force and torque, resolved in that frame.
    Frame { connector: String, force: [String; 3], torque: [String; 3] },
    /// At the planar library connector `connector` (`body.frame_a`): force
    /// `[fx, fy]` and torque `tau`, in world coordinates.
    Frame2D { connector: String, force: [String; 2], torque: String },
    /// At the 1-D library connector `connector` (`rev.axis`): torque or force.
    Flange { connector: String, value: String },
}

/// The model's own equations: variables, equations, initial equations and
/// the flows they put on the mechanics. Names in the equations are these
/// variables or quantities of the library components (see
/// [`crate::Model::equation`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Equations {
    pub variables: Vec<Variable>,
    pub equations: Vec<Equation>,
    /// Equations that hold at the start only.
    pub initial: Vec<Equation>,
    pub flows: Vec<Flow>,
    /// `when` clauses, in the order written.
    pub whens: Vec<When>,
}

impl Equations {
    pub fn is_empty(&self) -> bool {
        self.variables.is_empty()
            && self.equations.is_empty()
            && self.initial.is_empty()
            && self.flows.is_empty()
            && self.whens.is_empty()
    }
}

/// A model: components, the connections between them, and equations.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Model {
    pub name: String,
    pub components: Vec<ComponentInstance>,
    pub connections: Vec<Connection>,
    pub equations: Equations,
    /// The model's outputs: names of its signals (result columns) that a
    /// host reads while it runs (a Dyad model's top-level `RealOutput`s).
    pub outputs: Vec<String>,
}

impl Model {
    pub fn new(name: impl Into<String>) -> Self {
        Self { name: name.into(), ..Self::default() }
    }

    /// Adds a component of `kind` (e.g. `"Body"`) named `name`, and returns it
    /// for setting parameters. Names and kinds are checked by
    /// [`Model::assemble`], which suggests the closest valid name.
    pub fn add(&mut self, name: impl Into<String>, kind: impl Into<String>) -> &mut ComponentInstance {
        self.components.push(ComponentInstance {
            name: name.into(),
            kind: kind.into(),
            params: Vec::new(),
            initial: Vec::new(),
            guess: Vec::new(),
            surface: None,
        });
        self.components.last_mut().expect("just pushed")
    }

    /// The component named `name`, to change it after it was added.
    pub fn component_mut(&mut self, name: &str) -> Option<&mut ComponentInstance> {
        self.components.iter_mut().find(|c| c.name == name)
    }

    pub fn component(&self, name: &str) -> Option<&ComponentInstance> {
        self.components.iter().find(|c| c.name == name)
    }

    /// Gives the signal input `input` (`component.connector`) the formula
    /// of time `formula` (what `input = formula` says in a model file).
    pub fn set_input(&mut self, input: impl Into<String>, formula: Expr) -> &mut Self {
        self.equation(Expr::Var(input.into()), formula)
    }

    /// Adds the equation `lhs = rhs`. Its names are variables declared with
    /// [`Model::variable`] or quantities of library components: a signal
    /// connector (`sensor.phi`, `torque.tau`), a frame connector's `r_0[i]`
    /// and `R[i,j]`, a 1-D connector's `phi` or `s`, or a state
    /// (`rev.phi`, `rev.w`); `der` of these gives their rates.
    pub fn equation(&mut self, lhs: Expr, rhs: Expr) -> &mut Self {
        self.equations.equations.push(Equation::new(lhs, rhs));
        self
    }

    /// Declares a variable of the equations, and returns it to set its
    /// start value.
    pub fn variable(&mut self, name: impl Into<String>) -> &mut Variable {
        self.equations.variables.push(Variable::new(name));
        self.equations.variables.last_mut().expect("just pushed")
    }

    /// Connects connectors, each written `component.connector`.
    pub fn connect<S: Into<String>>(&mut self, ends: impl IntoIterator<Item = S>) -> &mut Self {
        self.connections.push(Connection { ends: ends.into_iter().map(Into::into).collect() });
        self
    }
}
