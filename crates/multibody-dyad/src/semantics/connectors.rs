//! Connector types as their declarations make them (`connector Pin
//! potential v::Voltage flow i::Current end`): the fields with their sizes
//! and whether each is a flow, and, for the mechanical and signal
//! connectors of the standard library, the engine connector they map onto.
//! Nothing here knows a domain: a heat port and a frame differ only in
//! their fields and in that mapping.

use crate::reports::diagnostics::Diagnostic;
use crate::syntax::ast::{Causality, ConnectorDef, Dim, ExprKind, FieldKind};
use crate::syntax::source::Span;
use multibody::components::ConnectorType;
use std::sync::Arc;

/// One field of a connector: `flow f::Force[3]` is `("f", [3], true)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Field {
    pub name: String,
    pub dims: Vec<usize>,
    pub flow: bool,
}

/// A connector type, ready for connections and equations.
#[derive(Debug, PartialEq)]
pub struct ConnectorShape {
    pub name: String,
    pub fields: Vec<Field>,
    /// A signal connector: the signal itself, an input or an output, and
    /// the name of its value's type (`Real`, `Boolean`, `Integer`).
    pub signal: Option<(Causality, String)>,
    /// The engine connector the declaration maps this one onto.
    pub engine: Option<ConnectorType>,
    pub declaration: Span,
}

/// A shared connector type.
pub type Connector = Arc<ConnectorShape>;

/// The engine's connectors that a declaration may name, by their names.
pub const ENGINE: [ConnectorType; 6] = [
    ConnectorType::Frame,
    ConnectorType::Frame2D,
    ConnectorType::Spline,
    ConnectorType::Flange,
    ConnectorType::RealInput,
    ConnectorType::RealOutput,
];

impl ConnectorShape {
    /// The shape of a declaration; sizes of fields must be whole numbers.
    pub fn of(def: &ConnectorDef) -> Result<Self, Diagnostic> {
        let engine = match &def.engine {
            None => None,
            Some((name, span)) => Some(ENGINE.iter().copied().find(|t| t.name() == name).ok_or_else(|| {
                Diagnostic::error(format!("the engine has no connector `{name}`"))
                    .primary(*span, "in this metadata")
                    .note(format!(
                        "the engine's connectors are: {}",
                        ENGINE.iter().map(|t| t.name()).collect::<Vec<_>>().join(", ")
                    ))
            })?),
        };
        let mut fields = Vec::with_capacity(def.fields.len());
        for f in &def.fields {
            if let Some(other) = fields.iter().find(|g: &&Field| g.name == f.name.name) {
                return Err(Diagnostic::error(format!(
                    "the connector `{}` has two fields `{}`",
                    def.name.name, other.name
                ))
                .primary(f.name.span, "declared again")
                .help("rename one of them"));
            }
            if matches!(f.kind, FieldKind::Input | FieldKind::Output) {
                return Err(Diagnostic::error("signal fields inside a connector are not supported yet")
                    .primary(f.span, "not supported yet")
                    .help("declare a signal connector of its own: `connector MyInput = input Real`"));
            }
            let mut dims = Vec::with_capacity(f.ty.dims.len());
            for d in &f.ty.dims {
                match d {
                    Dim::Size(e) => match e.kind {
                        ExprKind::Number(x) if x >= 1.0 && x.fract() == 0.0 && x <= 64.0 => dims.push(x as usize),
                        _ => {
                            return Err(Diagnostic::error(
                                "the size of a connector's field is a whole number from 1 to 64",
                            )
                            .primary(e.span, "not a size")
                            .help("write the size as a number: `flow f::Force[3]`"))
                        }
                    },
                    Dim::Any(span) => {
                        return Err(Diagnostic::error("a connector's field has a fixed size")
                            .primary(*span, "any size")
                            .help("write the size as a number: `flow f::Force[3]`"))
                    }
                }
            }
            fields.push(Field { name: f.name.name.clone(), dims, flow: f.kind == FieldKind::Flow });
        }
        if let (Some(ty), Some((_, span))) = (engine, &def.engine) {
            // The engine's connector has these quantities; a declaration
            // mapped onto it must have them, or what it reads would be wrong.
            let expected = engine_fields(ty);
            let matches = expected.len() == fields.len()
                && expected.iter().zip(&fields).all(|((n, d, f), g)| g.name == *n && g.dims == *d && g.flow == *f);
            if !matches {
                let list = expected
                    .iter()
                    .map(|(n, d, f)| format!("{} {n}{d:?}", if *f { "flow" } else { "potential" }))
                    .collect::<Vec<_>>()
                    .join(", ");
                return Err(Diagnostic::error(format!(
                    "`{}` is mapped onto the engine's {} but its fields differ",
                    def.name.name,
                    ty.name()
                ))
                .primary(*span, "mapped here")
                .secondary(def.header, "this connector")
                .note(format!(
                    "the engine's {} has: {}",
                    ty.name(),
                    if list.is_empty() { "one signal".into() } else { list }
                ))
                .help("declare the same fields in that order, or leave the engine out of the metadata"));
            }
        }
        let signal = def.signal.as_ref().map(|(c, ty)| (*c, ty.name.last().name.clone()));
        if signal.is_none() && !fields.is_empty() && fields.iter().all(|f| f.flow) {
            return Err(Diagnostic::error(format!("the connector `{}` has flows but no potential", def.name.name))
                .primary(def.header, "only flows")
                .help("declare what connected components share: `potential v::Voltage`"));
        }
        Ok(Self { name: def.name.name.clone(), fields, signal, engine, declaration: def.header })
    }

    pub fn is_signal(&self) -> bool {
        self.signal.is_some()
    }

    /// A frame (3-D or planar): a node of the mechanism.
    pub fn is_frame(&self) -> bool {
        self.engine.is_some_and(|t| t.is_frame())
    }

    pub fn is_input(&self) -> bool {
        matches!(self.signal, Some((Causality::Input, _)))
    }

    pub fn is_output(&self) -> bool {
        matches!(self.signal, Some((Causality::Output, _)))
    }

    /// Whether connectors of the two types may be connected: the same
    /// type, or signals of the same value type.
    pub fn connects_to(&self, other: &ConnectorShape) -> bool {
        match (&self.signal, &other.signal) {
            (Some((_, a)), Some((_, b))) => a == b || (is_number(a) && is_number(b)),
            (None, None) => self.name == other.name,
            _ => false,
        }
    }

    /// Whether a connector of this type may meet the engine's connector `ty`.
    pub fn meets_engine(&self, ty: ConnectorType) -> bool {
        match &self.signal {
            Some((_, value)) => ty.is_signal() && is_number(value),
            None => self.engine == Some(ty),
        }
    }

    pub fn field(&self, name: &str) -> Option<&Field> {
        self.fields.iter().find(|f| f.name == name)
    }
}

/// The quantities of each engine connector: name, sizes, whether a flow
/// (none for a signal, which is its value).
fn engine_fields(ty: ConnectorType) -> &'static [(&'static str, &'static [usize], bool)] {
    match ty {
        ConnectorType::Frame => &[("r_0", &[3], false), ("R", &[3, 3], false), ("f", &[3], true), ("tau", &[3], true)],
        ConnectorType::Frame2D => &[
            ("x", &[], false),
            ("y", &[], false),
            ("phi", &[], false),
            ("fx", &[], true),
            ("fy", &[], true),
            ("tau", &[], true),
        ],
        ConnectorType::Spline => &[("phi", &[], false), ("tau", &[], true)],
        ConnectorType::Flange => &[("s", &[], false), ("f", &[], true)],
        ConnectorType::RealInput | ConnectorType::RealOutput => &[],
    }
}

/// Value types the engine's signals carry as numbers.
fn is_number(ty: &str) -> bool {
    matches!(ty, "Real" | "Integer" | "Boolean")
}
