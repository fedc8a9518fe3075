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
