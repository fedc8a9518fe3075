//! Reports: diagnostics that point at the source, the source map that
//! leads from a lowered model back to it, and the engine's errors told in
//! the terms of the model files.

pub mod diagnostics;
pub(crate) mod engine_errors;
pub mod source_map;
