//! BlockComponents.Constant: a constant signal.

use super::{SourceBlock, OUTPUT, VARIABLES};
use crate::components::spec::{ComponentSpec, ParamSpec, ParamType};
use crate::components::{Component, ParamSet, SignalSource};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Constant",
    doc: "Constant signal: y = k.",
    params: &[ParamSpec::required("k", ParamType::Real, "", "The constant value to output")],
    connectors: &OUTPUT,
    variables: &VARIABLES,
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(SourceBlock { signal: SignalSource::Constant { k: p.real("k") } }))
}
