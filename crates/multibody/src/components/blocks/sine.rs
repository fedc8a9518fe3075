//! BlockComponents.Sine: a sine signal.

use super::{SourceBlock, OFFSET, OUTPUT, START_TIME, VARIABLES};
use crate::components::spec::{ComponentSpec, ParamSpec, ParamType};
use crate::components::{Component, ParamSet, SignalSource};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.Sine",
    doc: "Sine signal: y = offset + amplitude sin(2 pi frequency (t - start_time) + phase) from start_time on, \
          offset before.",
    params: &[
        START_TIME,
        OFFSET,
        ParamSpec::required("amplitude", ParamType::Real, "", "Peak value of the sine wave"),
        ParamSpec::required("frequency", ParamType::Real, "Hz", "Number of cycles per time unit"),
        ParamSpec::real("phase", 0.0, "rad", "Angular displacement of the sine wave at start time"),
    ],
    connectors: &OUTPUT,
    variables: &VARIABLES,
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let signal = SignalSource::Sine {
        amplitude: p.real("amplitude"),
        frequency: p.real("frequency"),
        phase: p.real("phase"),
        offset: p.real("offset"),
        start_time: p.real("start_time"),
    };
    Ok(Box::new(SourceBlock { signal }))
}
