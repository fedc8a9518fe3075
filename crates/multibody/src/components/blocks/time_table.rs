//! BlockComponents.TimeTable: a signal interpolated in a table of time and value.

use super::{SourceBlock, OUTPUT, VARIABLES};
use crate::components::spec::{ComponentSpec, ParamSpec, ParamType};
use crate::components::{Component, ParamSet, SignalSource};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "BlockComponents.TimeTable",
    doc: "Signal interpolated linearly in a table of [time, value] rows (times increasing), constant outside it.",
    params: &[ParamSpec::required("table", ParamType::Matrix(2), "", "Rows [time, value], times increasing")],
    connectors: &OUTPUT,
    variables: &VARIABLES,
    build,
    shapes: crate::components::shapes::none,
};

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let points: Vec<(f64, f64)> = p.matrix("table").iter().map(|r| (r[0], r[1])).collect();
    if points.is_empty() {
        return Err(p.invalid("table", "the table needs at least one row [time, value]"));
    }
    if points.windows(2).any(|w| w[1].0 < w[0].0) {
        return Err(p.invalid("table", "the times (first column) must not decrease"));
    }
    Ok(Box::new(SourceBlock { signal: SignalSource::Table { points } }))
}
