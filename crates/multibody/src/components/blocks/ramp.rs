//! BlockComponents.Ramp: a ramp signal.

use super::{SourceBlock, OFFSET, OUTPUT, START_TIME, VARIABLES};
use crate::components::spec::{ComponentSpec, ParamSpec, ParamType};
use crate::components::{Component, ParamSet, SignalSource};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Ramp",
    doc: "Ramp signal: offset until start_time, then rising linearly by height over duration, then constant.",
    params: &[
        START_TIME,
        OFFSET,
        ParamSpec::required("duration", ParamType::Real, "s", "Duration of the ramp transition"),
        ParamSpec::required("height", ParamType::Real, "", "Total height (amplitude) of the ramp"),
    ],
    connectors: &OUTPUT,
    variables: &VARIABLES,
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let duration = p.non_negative("duration", false)?;
    let signal = SignalSource::Ramp {
        height: p.real("height"),
        duration,
        offset: p.real("offset"),
        start_time: p.real("start_time"),
    };
    Ok(Box::new(SourceBlock { signal }))
}
