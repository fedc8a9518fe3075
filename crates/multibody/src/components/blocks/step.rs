//! BlockComponents.Step: a step signal.

use super::{SourceBlock, OFFSET, OUTPUT, START_TIME, VARIABLES};
use crate::components::spec::{ComponentSpec, ParamSpec, ParamType};
use crate::components::{Component, ParamSet, SignalSource};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Step",
    doc: "Step signal: y = offset before start_time, offset + height from start_time on.",
    params: &[START_TIME, OFFSET, ParamSpec::required("height", ParamType::Real, "", "Magnitude of the step change")],
    connectors: &OUTPUT,
    variables: &VARIABLES,
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let signal =
        SignalSource::Step { height: p.real("height"), offset: p.real("offset"), start_time: p.real("start_time") };
    Ok(Box::new(SourceBlock { signal }))
}
