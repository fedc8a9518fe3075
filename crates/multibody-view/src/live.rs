//! The live page: the animation page of a first run, plus the model's
//! files and the engine compiled to WebAssembly (crates/multibody-web),
//! so that the page runs the model again whenever a value changes.

use crate::base64::encode;
use crate::html::{animation_scene, page};
use crate::json::Json;
use crate::{Animation, AnimationOptions, ViewError};
use multibody::components::shapes::{Shape, ShapeKind};
use multibody::Solution;
use std::io::Write;

const LIVE_SCRIPT: &str = include_str!("../assets/live.js");
const LIVE_STYLE: &str = include_str!("../assets/live.css");

/// What a live page runs: the files as `multibody run` read them, what to
/// run of them, and the values the page starts from.
#[derive(Clone, Debug, Default)]
pub struct LiveModel {
    /// Name and text of each model file.
    pub files: Vec<(String, String)>,
    pub analysis: Option<String>,
    pub model: Option<String>,
    /// `NAME=VALUE` texts, as `--param` takes them.
    pub params: Vec<String>,
    /// `NAME=VALUE` texts, as `--initial` takes them.
    pub initials: Vec<String>,
    /// The stop time, when not the analysis's.
    pub stop: Option<f64>,
}

/// The live page of `model`, showing `solution` (its first run) until the
/// page has run it itself. `wasm` is the module of crates/multibody-web;
/// it is embedded compressed (raw DEFLATE, base64), and the page inflates
/// it without any network.
pub fn live_html(
    title: &str,
    shapes: &[Shape],
    solution: &Solution,
    options: &AnimationOptions,
    model: &LiveModel,
    wasm: &[u8],
) -> Result<Animation, ViewError> {
    // The page's own runs (WebAssembly) read no files: mesh shapes are left
    // out from the first view too, so that the picture does not change.
    let (meshes, shapes): (Vec<Shape>, Vec<Shape>) =
        shapes.iter().cloned().partition(|s| matches!(s.kind, ShapeKind::Mesh { .. }));
    let (scene, mut summary) = animation_scene(title, &shapes, solution, options)?;
    for s in &meshes {
        summary
            .left_out
            .push(format!("{}: the live page draws no mesh files (`multibody run --animate` does)", s.component));
    }
    let mut deflate = flate2::write::DeflateEncoder::new(Vec::new(), flate2::Compression::best());
    let compressed = deflate.write_all(wasm).and_then(|_| deflate.finish());
    let compressed = compressed.map_err(|e| ViewError::Io { path: "<the WebAssembly module>".into(), source: e })?;

    let mut j = Json::new();
    j.begin_object();
    j.key("files").begin_array();
    for (name, text) in &model.files {
        j.begin_array();
        j.string(name).string(text);
        j.end_array();
    }
    j.end_array();
    if let Some(a) = &model.analysis {
        j.key("analysis").string(a);
    }
    if let Some(m) = &model.model {
        j.key("model").string(m);
    }
    for (key, list) in [("params", &model.params), ("initials", &model.initials), ("signals", &options.signals)] {
        j.key(key).begin_array();
        for s in list {
            j.string(s);
        }
        j.end_array();
    }
    if let Some(stop) = model.stop {
        j.key("stop").number(stop);
    }
    j.key("moduleBytes").number(wasm.len() as f64);
    j.key("module").string(&encode(&compressed));
    j.end_object();

    // The JSON writer escapes `<`, so no `</script>` in a model file ends the element early.
    let extra = format!(
        "<style>{LIVE_STYLE}</style>\n<script type=\"application/json\" id=\"mb-live\">{}</script>\n<script>\n{LIVE_SCRIPT}\n</script>",
        j.finish()
    );
    let html = page(title, &scene, &extra);
    summary.bytes = html.len();
    Ok(Animation { html, summary })
}
