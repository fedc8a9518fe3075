//! The syntax tree of a `.dyad` file. Every node keeps its source span
//! for diagnostics.

use crate::syntax::source::Span;

#[derive(Clone, Debug, PartialEq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

/// A dotted name: `MultibodyComponents.Body`, `joint.frame_a`.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    pub parts: Vec<Ident>,
    pub span: Span,
}

impl Path {
    pub fn text(&self) -> String {
        self.parts.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(".")
    }

    pub fn last(&self) -> &Ident {
        self.parts.last().expect("a path has at least one part")
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct File {
    pub items: Vec<Item>,
    /// The library package the file is inside (`PlanarMechanics` for a file
    /// in a folder of that name): its short names refer to that package's
    /// components first, as Dyad's folders make them.
    pub package: Option<String>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    Component(ComponentDef),
    Analysis(Box<AnalysisDef>),
    /// `type Stiffness = Real(units = "N/m")`: a new name for a type.
    TypeAlias(TypeAlias),
    /// `connector Pin potential v::Voltage flow i::Current end`.
    Connector(ConnectorDef),
}

/// A connector type: what two connected components share. Its potentials
/// are equal across a connection and its flows sum to zero there; a
/// signal connector (`connector RealInput = input Real`) is the signal
/// itself.
#[derive(Clone, Debug, PartialEq)]
pub struct ConnectorDef {
    pub name: Ident,
    pub doc: Option<String>,
    /// From `connector` to the name.
    pub header: Span,
    pub fields: Vec<ConnectorField>,
    /// Parameters (of rendering, say): accepted, and not part of a connection.
    pub parameters: Vec<ParameterDecl>,
    /// `= input Real`: a signal connector, with its causality and type.
    pub signal: Option<(Causality, TypeRef)>,
    /// The metadata's `"Multibody": {"engine": "Frame3D"}`: the engine's
    /// connector the standard library maps this one onto, where it was written.
    pub engine: Option<(String, Span)>,
}

/// What a field of a connector is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldKind {
    Potential,
    Flow,
    Input,
    Output,
}

impl FieldKind {
    pub fn keyword(&self) -> &'static str {
        match self {
            FieldKind::Potential => "potential",
            FieldKind::Flow => "flow",
            FieldKind::Input => "input",
            FieldKind::Output => "output",
        }
    }
}

/// `potential v::Voltage`, `flow f::Force[3]`.
#[derive(Clone, Debug, PartialEq)]
pub struct ConnectorField {
    pub doc: Option<String>,
    pub kind: FieldKind,
    pub name: Ident,
    pub ty: TypeRef,
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ComponentKind {
    Component,
    Example,
    Test,
    /// A base for other components; not instantiable.
    Partial,
}

impl ComponentKind {
    pub fn keyword(&self) -> &'static str {
        match self {
            ComponentKind::Component => "component",
            ComponentKind::Example => "example component",
            ComponentKind::Test => "test component",
            ComponentKind::Partial => "partial component",
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct ComponentDef {
    pub kind: ComponentKind,
    pub name: Ident,
    pub doc: Option<String>,
    /// From the first keyword to the name.
    pub header: Span,
    pub declarations: Vec<Declaration>,
    pub relations: Vec<Relation>,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Declaration {
    /// `name = Kind(modifiers)`: a sub-component or a connector.
    Component(ComponentDecl),
    Parameter(ParameterDecl),
    /// `variable x::Real`, `input u::Real`, `output y::Real`.
    Variable(VariableDecl),
    /// `extends Base(modifiers)`.
    Extends(ExtendsDecl),
}

impl Declaration {
    /// The declared name (`extends` has its base's).
    pub fn name(&self) -> &Ident {
        match self {
            Declaration::Component(c) => &c.name,
            Declaration::Parameter(p) => &p.name,
            Declaration::Variable(v) => &v.name,
            Declaration::Extends(e) => e.base.last(),
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct ComponentDecl {
    pub doc: Option<String>,
    pub name: Ident,
    pub kind: Path,
    pub modifiers: Vec<Modifier>,
    /// `name = Kind() if condition`: present only when it holds.
    pub condition: Option<Expr>,
    /// `name = [Kind(...) for i in range]`: an array of components.
    pub array: Option<(Ident, Expr)>,
    /// The whole declaration.
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Parameter,
    Structural,
    /// Cannot be changed by a modifier (`final parameter`, `constant`).
    Final,
}

/// Whether a variable is a signal connector of its component.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Internal,
    Input,
    Output,
}

#[derive(Clone, Debug, PartialEq)]
pub struct VariableDecl {
    pub doc: Option<String>,
    pub causality: Causality,
    pub name: Ident,
    pub ty: TypeRef,
    /// `= expr`: an equation that holds throughout.
    pub binding: Option<Expr>,
    /// `= initial expr` (or `= expr initial start`): the start value.
    pub initial: Option<Expr>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ExtendsDecl {
    pub base: Path,
    pub modifiers: Vec<Modifier>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub struct ParameterDecl {
    pub doc: Option<String>,
    pub variability: Variability,
    pub name: Ident,
    pub ty: TypeRef,
    pub default: Option<Expr>,
    pub span: Span,
}

/// `Real`, `Length[3]`, `Real[:, :]`, `Dyad.Angle(min = 0)`.
#[derive(Clone, Debug, PartialEq)]
pub struct TypeRef {
    pub name: Path,
    pub attributes: Vec<Modifier>,
    pub dims: Vec<Dim>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Dim {
    Size(Expr),
    /// `:`: any size.
    Any(Span),
}

/// `m = 1`, `phi(initial = 0.3)`, `final k = 2`.
#[derive(Clone, Debug, PartialEq)]
pub struct Modifier {
    pub is_final: bool,
    pub name: Ident,
    pub value: Option<Expr>,
    /// `name(...)`: modifiers of a variable's attributes or of a sub-component.
    pub nested: Option<Vec<Modifier>>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum Relation {
    /// `connect(a.b, c[i].d, ...)`: each end a reference (names, indices).
    Connect { ends: Vec<Expr>, span: Span },
    /// `initial lhs = rhs`: an equation at the start (a start value when
    /// `lhs` is a variable and `rhs` a constant).
    Initial { lhs: Expr, rhs: Expr, span: Span },
    /// `guess x = value`: a start value the start may change.
    Guess { lhs: Expr, rhs: Expr, span: Span },
    /// `lhs = rhs`.
    Equation { lhs: Expr, rhs: Expr, span: Span },
    /// `if c1 ... elseif c2 ... else ... end`.
    If { branches: Vec<(Expr, Vec<Relation>)>, otherwise: Option<Vec<Relation>>, span: Span },
    /// `for i in range ... end`.
    For { var: Ident, range: Expr, body: Vec<Relation>, span: Span },
    /// `switch subject case A ... end ... end`.
    Switch { subject: Expr, cases: Vec<(Path, Vec<Relation>)>, default: Option<Vec<Relation>>, span: Span },
    /// `assert(condition, "message")`.
    Assert { condition: Expr, message: String, span: Span },
    /// `when c1 ... elsewhen c2 ... end`: what happens at the events where
    /// a condition becomes true.
    When { branches: Vec<(Expr, Vec<Relation>)>, span: Span },
    /// `reinit(x, value)`: a state jumps (inside `when`).
    Reinit { state: Expr, value: Expr, span: Span },
}

#[derive(Clone, Debug, PartialEq)]
pub struct AnalysisDef {
    pub name: Ident,
    pub doc: Option<String>,
    pub header: Span,
    /// `extends TransientAnalysis(...)`.
    pub base: Path,
    pub base_modifiers: Vec<Modifier>,
    pub base_span: Span,
    pub parameters: Vec<ParameterDecl>,
    /// `model = Kind(...)`.
    pub model: Option<ComponentDecl>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct TypeAlias {
    pub name: Ident,
    pub base: TypeRef,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    pub kind: ExprKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ExprKind {
    Number(f64),
    Bool(bool),
    Str(String),
    /// A name: a parameter, `pi`, `missing`, or an enumeration value.
    Name(Path),
    Call {
        callee: Path,
        args: Vec<Expr>,
    },
    Array(Vec<Expr>),
    Index {
        base: Box<Expr>,
        indices: Vec<Expr>,
    },
    Unary {
        op: UnaryOp,
        operand: Box<Expr>,
    },
    Binary {
        op: BinaryOp,
        lhs: Box<Expr>,
        rhs: Box<Expr>,
    },
    /// `first op1 e1 op2 e2 ...`: three or more operands of one precedence
    /// level, evaluated from the left. A flat list, so that a long sum
    /// nests no deeper than a short one.
    Chain {
        first: Box<Expr>,
        rest: Vec<(BinaryOp, Expr)>,
    },
    /// `base.name` after an index: `links[2].frame_a`.
    Field {
        base: Box<Expr>,
        name: Ident,
    },
    /// `c ? a : b`, `if c then a else b`, `ifelse(c, a, b)`.
    If {
        condition: Box<Expr>,
        then: Box<Expr>,
        otherwise: Box<Expr>,
    },
    /// `start:stop` or `start:step:stop`.
    Range {
        start: Box<Expr>,
        step: Option<Box<Expr>>,
        stop: Box<Expr>,
    },
    /// Parsed so that the message can point at it, but not evaluated yet
    /// (`if ... then ... else`, comparisons, `and`/`or`, ranges).
    Unsupported(&'static str),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnaryOp {
    Neg,
    Plus,
    Not,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinaryOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    ElemAdd,
    ElemSub,
    ElemMul,
    ElemDiv,
    ElemPow,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
}

impl BinaryOp {
    pub fn symbol(&self) -> &'static str {
        match self {
            BinaryOp::Add => "+",
            BinaryOp::Sub => "-",
            BinaryOp::Mul => "*",
            BinaryOp::Div => "/",
            BinaryOp::Pow => "^",
            BinaryOp::ElemAdd => ".+",
            BinaryOp::ElemSub => ".-",
            BinaryOp::ElemMul => ".*",
            BinaryOp::ElemDiv => "./",
            BinaryOp::ElemPow => ".^",
            BinaryOp::Lt => "<",
            BinaryOp::Le => "<=",
            BinaryOp::Gt => ">",
            BinaryOp::Ge => ">=",
            BinaryOp::Eq => "==",
            BinaryOp::Ne => "!=",
            BinaryOp::And => "and",
            BinaryOp::Or => "or",
        }
    }
}

impl Expr {
    /// The expression as a dotted name, if it is one.
    pub fn as_path(&self) -> Option<&Path> {
        match &self.kind {
            ExprKind::Name(p) => Some(p),
            _ => None,
        }
    }
}
