//! The animation page without a browser: self-contained, and the data in
//! it is what the solution says.

mod common;

use common::models;
use multibody_view::{animation_html, write_animation_to, AnimationOptions};

#[test]
fn page_is_self_contained() {
    let mechanism = models::spring_mass();
    let solution = models::simulate(&mechanism, 1.0);
    let page = animation_html("spring </script> & mass", &mechanism.shapes(), &solution, &AnimationOptions::default())
        .unwrap();
    let html = &page.html;
    // No network: nothing is loaded from anywhere.
    for needle in ["http:", "https:", "//cdn", "<script src", "<link", "@import", "url(", "import(", "fetch("] {
        assert!(!html.contains(needle), "the page refers to `{needle}`");
    }
    // The title is escaped, in the page and in the embedded scene.
    assert!(html.contains("spring &lt;/script&gt; &amp; mass"));
    assert_eq!(html.matches("</script>").count(), 3, "one early script, the scene and the viewer");
    assert_eq!(page.summary.bytes, html.len());
    // A helix, a force arrow and the world's axes.
    for kind in [r#""kind":"helix""#, r#""place":"vector""#, r#""kind":"arrow""#, r#""kind":"sphere""#] {
        assert!(html.contains(kind), "no {kind} in the scene");
    }
    assert!(page.summary.left_out.is_empty(), "{:?}", page.summary.left_out);
}

#[test]
fn frames_follow_fps_and_connected_frames_share_poses() {
    let mechanism = models::double_pendulum();
    let solution = models::simulate(&mechanism, 2.0);
    let mut out = Vec::new();
    let summary = write_animation_to(
        &mut out,
        "double pendulum",
        &mechanism.shapes(),
        &solution,
        &AnimationOptions { fps: 25.0, signals: vec!["revolute2.*".into()], ..Default::default() },
    )
    .unwrap();
    assert_eq!(summary.bytes, out.len());
    assert_eq!(summary.frames, 51, "2 s at 25 frames per second");
    // Shapes sit in world.frame_b, revolute1.frame_a (the same frame, as
    // they are connected), boxBody1.frame_a, revolute2.frame_a (the end of
    // box 1) and boxBody2.frame_a (same origin, turned by the joint).
    assert_eq!(summary.poses, 4);
    assert_eq!(summary.shapes, 7);
    assert!(summary.signals.iter().all(|s| s.starts_with("revolute2.")) && summary.signals.len() >= 4);
}

#[test]
fn unknown_signal_pattern_is_an_error() {
    let mechanism = models::pendulum();
    let solution = models::simulate(&mechanism, 0.1);
    let err = animation_html(
        "p",
        &mechanism.shapes(),
        &solution,
        &AnimationOptions { signals: vec!["body.r0[*]".into()], ..Default::default() },
    )
    .unwrap_err();
    assert!(err.to_string().contains("body.r0[*]"), "{err}");
}

#[test]
fn missing_frames_are_left_out_and_reported() {
    let mechanism = models::pendulum();
    let solution = models::simulate(&mechanism, 0.1);
    let mut shapes = mechanism.shapes();
    let mut extra = shapes[0].clone();
    extra.component = "ghost".into();
    extra.placement =
        multibody::components::shapes::Placement::Between { from: "ghost.frame_a".into(), to: "body.frame_a".into() };
    shapes.push(extra);
    let page = animation_html("p", &shapes, &solution, &AnimationOptions::default()).unwrap();
    assert_eq!(page.summary.left_out.len(), 1);
    assert!(page.summary.left_out[0].contains("ghost.frame_a"), "{:?}", page.summary.left_out);
}

/// A mesh shape alone: the page's bounds, which frame the camera, are the
/// box the file's geometry makes through shape_scale and shape_transform
/// (an absolute path, read whatever the mesh folder is).
#[test]
fn bounds_hold_the_mesh_as_placed() {
    let dir = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("page_mesh_bounds");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("block.stl");
    std::fs::write(&file, models::box_stl(0.5, 0.15, 0.15)).unwrap();
    let mut model = multibody::Model::new("LoneMesh");
    model.add("world", "World").set("render", false);
    let moved =
        vec![vec![0.0, -1.0, 0.0, 2.0], vec![1.0, 0.0, 0.0, 0.0], vec![0.0, 0.0, 1.0, -1.0], vec![0.0, 0.0, 0.0, 1.0]];
    model
        .add("part", "ShapefileVisualizer")
        .set("shapefile", file.display().to_string())
        .set("shape_transform", multibody::Value::Matrix(moved))
        .set("shape_scale", 0.5);
    model.connect(["world.frame_b", "part.frame_a"]);
    let mechanism = model.assemble().unwrap();
    let solution = models::simulate(&mechanism, 0.1);
    let options = AnimationOptions { mesh_folder: Some("/nowhere".into()), ..Default::default() };
    let page = animation_html("lone mesh", &mechanism.shapes(), &solution, &options).unwrap();
    assert!(page.summary.left_out.is_empty(), "{:?}", page.summary.left_out);
    let html = &page.html;
    let start = html.find("id=\"mb-scene\">").unwrap() + "id=\"mb-scene\">".len();
    let scene: serde_json::Value =
        serde_json::from_str(&html[start..start + html[start..].find("</script>").unwrap()]).unwrap();
    // Half sizes 0.25, 0.075, 0.075 after the scale; x and y swapped by the
    // quarter turn; centred on (2, 0, -1).
    let (lo, hi) = ([1.925, -0.25, -1.075], [2.075, 0.25, -0.925]);
    for i in 0..3 {
        let (a, b) = (scene["bbox"]["min"][i].as_f64().unwrap(), scene["bbox"]["max"][i].as_f64().unwrap());
        assert!((a - lo[i]).abs() < 1e-6 && (b - hi[i]).abs() < 1e-6, "axis {i}: {a} .. {b}");
    }
    assert_eq!(scene["meshes"].as_array().unwrap().len(), 1);
}
