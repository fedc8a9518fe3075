//! The animation page: one HTML file with the viewer (our own WebGL2
//! renderer and canvas plots, in `assets/`) and the sampled motion embedded
//! as base64 `Float32Array`s.

use crate::base64::{encode_f32, encode_u32};
use crate::json::Json;
use crate::scene::{sample, Scene, ScenePlacement};
use crate::signals::choose_signals;
use crate::ViewError;
use multibody::components::shapes::Shape;
use multibody::Solution;
use std::io::Write;
use std::path::{Path, PathBuf};

const TEMPLATE: &str = include_str!("../assets/viewer.html");
const STYLE: &str = include_str!("../assets/viewer.css");
const SCRIPT: &str = include_str!("../assets/viewer.js");

/// How the animation page samples and plays the motion.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationOptions {
    /// Signals plotted beside the 3-D view, as patterns (`*` any text, `?`
    /// one character: `*.phi`, `body.r_0[*]`). Empty: a guess (joint
    /// coordinates and rates, else free bodies' positions), at most six.
    pub signals: Vec<String>,
    /// Animation frames per simulated second (at most; a coarser solution
    /// is used sample by sample). The page interpolates between frames.
    pub fps: f64,
    /// The most frames the page holds; longer runs get a lower frame rate.
    pub max_frames: usize,
    /// The most samples per plotted signal (evenly thinned beyond).
    pub max_plot_points: usize,
    /// The most signals plotted (the rest are left out and reported).
    pub max_signals: usize,
    /// Initial playback speed (simulated seconds per second).
    pub speed: f64,
    /// Start again at the end.
    pub looping: bool,
    /// Start playing when the page opens.
    pub autoplay: bool,
    /// The folder relative mesh paths (ShapefileVisualizer's `shapefile`)
    /// are read from: the folder of the model file being run. `None`: the
    /// current directory.
    pub mesh_folder: Option<PathBuf>,
    /// The world's up, drawn upwards on the page: against gravity
    /// ([`AnimationOptions::up_of`]); `[0, 1, 0]` by default.
    pub up: [f64; 3],
}

impl AnimationOptions {
    /// The up of a mechanism's world: against uniform gravity, else y.
    pub fn up_of(mechanism: &multibody::Mechanism) -> [f64; 3] {
        let world = mechanism.world();
        let n = world.n;
        if world.point_gravity || n.norm() < 1e-12 || !n.iter().all(|x| x.is_finite()) {
            return [0.0, 1.0, 0.0];
        }
        let n = -n / n.norm();
        [n.x, n.y, n.z]
    }
}

impl Default for AnimationOptions {
    fn default() -> Self {
        Self {
            signals: Vec::new(),
            fps: 30.0,
            max_frames: 3000,
            max_plot_points: 4000,
            max_signals: 24,
            speed: 1.0,
            looping: true,
            autoplay: true,
            mesh_folder: None,
            up: [0.0, 1.0, 0.0],
        }
    }
}

/// What went into a page.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimationSummary {
    /// Size of the page in bytes.
    pub bytes: usize,
    /// Animation frames embedded.
    pub frames: usize,
    /// Distinct frame poses embedded per animation frame.
    pub poses: usize,
    /// Shapes drawn.
    pub shapes: usize,
    /// The signals plotted.
    pub signals: Vec<String>,
    /// Shapes or signals left out, each with the reason.
    pub left_out: Vec<String>,
}

/// A page and what went into it.
#[derive(Clone, Debug)]
pub struct Animation {
    pub html: String,
    pub summary: AnimationSummary,
}

/// The animation page of `shapes` moving as in `solution`, as text.
pub fn animation_html(
    title: &str,
    shapes: &[Shape],
    solution: &Solution,
    options: &AnimationOptions,
) -> Result<Animation, ViewError> {
    let (scene, mut summary) = animation_scene(title, shapes, solution, options)?;
    let html = page(title, &scene, "");
    summary.bytes = html.len();
    Ok(Animation { html, summary })
}

/// What the page draws, as the JSON it reads (`#mb-scene`): a live page
/// swaps a new one in after each run (`window.__multibody.setScene`). The
/// summary's `bytes` counts the JSON.
pub fn animation_scene(
    title: &str,
    shapes: &[Shape],
    solution: &Solution,
    options: &AnimationOptions,
) -> Result<(String, AnimationSummary), ViewError> {
    let scene = sample(shapes, solution, options.fps, options.max_frames, options.mesh_folder.as_deref())?;
    let mut signals = choose_signals(solution, &options.signals)?;
    let mut left_out = scene.skipped.clone();
    if signals.len() > options.max_signals {
        left_out.push(format!(
            "{} of {} matching signals not plotted (at most {}): {}{}",
            signals.len() - options.max_signals,
            signals.len(),
            options.max_signals,
            signals[options.max_signals..].iter().take(5).cloned().collect::<Vec<_>>().join(", "),
            if signals.len() > options.max_signals + 5 { ", ..." } else { "" }
        ));
        signals.truncate(options.max_signals);
    }
    let json = scene_json(title, &scene, solution, &signals, options);
    let summary = AnimationSummary {
        bytes: json.len(),
        frames: scene.times.len(),
        poses: scene.pose_names.len(),
        shapes: scene.shapes.len(),
        signals,
        left_out,
    };
    Ok((json, summary))
}

/// The page around a scene; `extra` goes at the end of the body (the live
/// page's panel and module).
pub(crate) fn page(title: &str, scene_json: &str, extra: &str) -> String {
    fill(
        TEMPLATE,
        &[
            ("TITLE", &escape_html(title)),
            ("STYLE", STYLE),
            // The JSON writer escapes `<`, so no `</script>` ends the element early.
            ("SCENE", scene_json),
            ("SCRIPT", SCRIPT),
            ("EXTRA", extra),
        ],
    )
}

/// Writes the animation page to `out`.
pub fn write_animation_to(
    out: &mut impl Write,
    title: &str,
    shapes: &[Shape],
    solution: &Solution,
    options: &AnimationOptions,
) -> Result<AnimationSummary, ViewError> {
    let animation = animation_html(title, shapes, solution, options)?;
    out.write_all(animation.html.as_bytes()).map_err(|e| ViewError::io(Path::new("<writer>"), e))?;
    Ok(animation.summary)
}

/// Writes the animation page to the file `path` (a self-contained `.html`
/// that works offline), creating its folder if needed.
pub fn write_animation(
    path: impl AsRef<Path>,
    title: &str,
    shapes: &[Shape],
    solution: &Solution,
    options: &AnimationOptions,
) -> Result<AnimationSummary, ViewError> {
    let path = path.as_ref();
    let animation = animation_html(title, shapes, solution, options)?;
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| ViewError::io(dir, e))?;
    }
    std::fs::write(path, animation.html.as_bytes()).map_err(|e| ViewError::io(path, e))?;
    Ok(animation.summary)
}

fn scene_json(
    title: &str,
    scene: &Scene,
    solution: &Solution,
    signals: &[String],
    options: &AnimationOptions,
) -> String {
    let mut j = Json::new();
    j.begin_object();
    j.key("title").string(title);
    j.key("version").number(1.0);
    j.key("times").string(&encode_f32(&scene.times.iter().map(|&t| t as f32).collect::<Vec<_>>()));
    j.key("poseCount").number(scene.pose_names.len() as f64);
    j.key("poseNames").begin_array();
    for n in &scene.pose_names {
        j.string(n);
    }
    j.end_array();
    j.key("poses").string(&encode_f32(&scene.poses));
    j.key("vectorCount").number(scene.vector_names.len() as f64);
    j.key("vectors").string(&encode_f32(&scene.vectors));
    j.key("up").numbers(&options.up);
    j.key("bbox").begin_object();
    j.key("min").numbers(&scene.bbox.0);
    j.key("max").numbers(&scene.bbox.1);
    j.end_object();
    j.key("shapes").begin_array();
    for s in &scene.shapes {
        j.begin_object();
        j.key("component").string(&s.component);
        j.key("kind").string(s.kind);
        j.key("color").numbers(&s.color);
        j.key("specular").number(s.specular);
        j.key("width").number(s.width);
        j.key("height").number(s.height);
        if s.kind == "helix" {
            j.key("windings").number(s.windings);
        }
        if let Some(mesh) = &s.mesh {
            j.key("mesh").number(mesh.index as f64);
            j.key("transform").numbers(&mesh.transform.concat());
            j.key("scale").number(mesh.scale);
        }
        match &s.placement {
            ScenePlacement::Frame { pose, origin, length, width_dir } => {
                j.key("place").string("frame");
                j.key("pose").number(*pose as f64);
                j.key("origin").numbers(origin);
                j.key("length").numbers(length);
                j.key("widthDir").numbers(width_dir);
            }
            ScenePlacement::Between { from, to } => {
                j.key("place").string("between");
                j.key("from").number(*from as f64);
                j.key("to").number(*to as f64);
            }
            ScenePlacement::Vector { pose, vector, scale } => {
                j.key("place").string("vector");
                j.key("pose").number(*pose as f64);
                j.key("vector").number(*vector as f64);
                j.key("scale").number(*scale);
            }
        }
        j.end_object();
    }
    j.end_array();
    // Each mesh file once; shapes name it by its place here.
    j.key("meshes").begin_array();
    for (path, mesh) in &scene.meshes {
        j.begin_object();
        j.key("path").string(path);
        j.key("positions").string(&encode_f32(&mesh.positions));
        j.key("normals").string(&encode_f32(&mesh.normals));
        j.key("indices").string(&encode_u32(&mesh.indices));
        j.end_object();
    }
    j.end_array();

    // Plots: the solution's own samples, evenly thinned.
    let time = solution.time();
    let stride = time.len().div_ceil(options.max_plot_points.max(2)).max(1);
    let mut picks: Vec<usize> = (0..time.len()).step_by(stride).collect();
    if picks.last() != Some(&(time.len() - 1)) {
        picks.push(time.len() - 1);
    }
    j.key("signalTimes").string(&encode_f32(&picks.iter().map(|&k| time[k] as f32).collect::<Vec<_>>()));
    j.key("signals").begin_array();
    for name in signals {
        let column = solution.get(name).unwrap_or(&[]);
        let values: Vec<f32> = picks.iter().map(|&k| column.get(k).copied().unwrap_or(f64::NAN) as f32).collect();
        j.begin_object();
        j.key("name").string(name);
        j.key("unit").string(solution.unit(name).unwrap_or(""));
        j.key("data").string(&encode_f32(&values));
        j.end_object();
    }
    j.end_array();
    j.key("speed").number(if options.speed > 0.0 { options.speed } else { 1.0 });
    j.key("loop").boolean(options.looping);
    j.key("autoplay").boolean(options.autoplay);
    j.end_object();
    j.finish()
}

/// Replaces each `{{NAME}}` in `template` once, in one pass (so text put in
/// is never scanned for markers).
pub(crate) fn fill(template: &str, values: &[(&str, &str)]) -> String {
    let extra: usize = values.iter().map(|(_, v)| v.len()).sum();
    let mut out = String::with_capacity(template.len() + extra);
    let mut rest = template;
    while let Some(start) = rest.find("{{") {
        out.push_str(&rest[..start]);
        let after = &rest[start + 2..];
        match after.find("}}").map(|end| (&after[..end], end)) {
            Some((name, end)) if values.iter().any(|(n, _)| *n == name) => {
                let value = values.iter().find(|(n, _)| *n == name).map(|(_, v)| *v).unwrap_or("");
                out.push_str(value);
                rest = &after[end + 2..];
            }
            _ => {
                out.push_str("{{");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

pub(crate) fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fills_markers_once() {
        assert_eq!(fill("a{{X}}b{{Y}}c{{Z}}", &[("X", "{{Y}}"), ("Y", "2")]), "a{{Y}}b2c{{Z}}");
    }
}
