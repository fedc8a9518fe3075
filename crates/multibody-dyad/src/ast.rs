//! The syntax tree of a `.dyad` file: the subset that composes models.
//! Every node keeps its source span for diagnostics.

use crate::source::Span;

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
}

#[derive(Clone, Debug, PartialEq)]
pub enum Item {
    Component(ComponentDef),
    Analysis(AnalysisDef),
    /// `type Stiffness = Real(units = "N/m")`: a new name for a type.
    TypeAlias(TypeAlias),
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
}

impl Declaration {
    pub fn name(&self) -> &Ident {
        match self {
            Declaration::Component(c) => &c.name,
            Declaration::Parameter(p) => &p.name,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct ComponentDecl {
    pub doc: Option<String>,
    pub name: Ident,
    pub kind: Path,
    pub modifiers: Vec<Modifier>,
    /// The whole declaration.
    pub span: Span,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Parameter,
    Structural,
    /// Cannot be changed by a modifier.
    Final,
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
    /// `connect(a.b, c.d, ...)`.
    Connect { ends: Vec<Path>, span: Span },
    /// `initial x.y = expr`: a start value.
    Initial { target: Path, value: Expr, span: Span },
    /// `x.y = expr`: an equation (today: a signal input's formula of time).
    Equation { lhs: Path, rhs: Expr, span: Span },
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
    /// Parsed so that the message can point at it, but not evaluated yet
    /// (`if ... then ... else`, comparisons, `and`/`or`, ranges).
    Unsupported(&'static str),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnaryOp {
    Neg,
    Plus,
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
        }
    }
}
