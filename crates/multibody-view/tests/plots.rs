//! Plots as PNG and SVG: the expected size, not blank, labelled; and the
//! errors a user meets.

mod common;

use common::models;
use common::pixels::Image;
use multibody_view::{plot_png, plot_svg, write_plot, PlotOptions, ViewError};
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("plots");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn png_has_the_expected_size_and_is_not_blank() {
    let mechanism = models::double_pendulum();
    let solution = models::simulate(&mechanism, 2.0);
    let path = scratch("double_pendulum.png");
    let options = PlotOptions { signals: vec!["*.phi".into(), "revolute1.w".into()], width: 900, ..Default::default() };
    let summary = write_plot(&path, "Double pendulum", &solution, &options).unwrap();
    // Two units, two panels: 60 + 2 * 260 pixels high.
    assert_eq!((summary.width, summary.height), (900, 580));
    assert_eq!(
        summary.panels,
        [
            ("rad".to_string(), vec!["revolute1.phi".to_string(), "revolute2.phi".to_string()]),
            ("rad/s".to_string(), vec!["revolute1.w".to_string()]),
        ]
    );
    let image = Image::read(&path);
    assert_eq!((image.width, image.height), (900, 580));
    assert_eq!(image.background(), [255, 255, 255]);
    let drawn = image.drawn_fraction();
    assert!(drawn > 0.02, "the plot is nearly blank: {:.2}% drawn", drawn * 100.0);
    // The first line of each panel is blue, the second orange.
    let blue = image.find(|[r, g, b]| b > 150 && r < 80 && g < 130).0;
    let orange = image.find(|[r, g, b]| r > 200 && g > 90 && g < 150 && b < 60).0;
    assert!(blue > 500 && orange > 500, "lines missing: {blue} blue and {orange} orange pixels");
    // Text is drawn (dark grey pixels of labels and ticks) with the shipped font.
    let text = image.find(|[r, g, b]| r < 90 && g < 90 && b < 90).0;
    assert!(text > 500, "no text: {text} dark pixels");
}

#[test]
fn explicit_height_and_png_bytes() {
    let mechanism = models::pendulum();
    let solution = models::simulate(&mechanism, 1.0);
    let (bytes, summary) =
        plot_png("pendulum", &solution, &PlotOptions { width: 640, height: 400, ..Default::default() }).unwrap();
    assert_eq!(summary.panels.len(), 2, "default signals rev.phi and rev.w: {:?}", summary.panels);
    let image = Image::decode(bytes.as_slice());
    assert_eq!((image.width, image.height), (640, 400));
    assert!(image.drawn_fraction() > 0.02);
}

#[test]
fn svg_is_labelled() {
    let mechanism = models::pendulum();
    let solution = models::simulate(&mechanism, 1.0);
    let (svg, summary) = plot_svg(
        "pendulum <1>",
        &solution,
        &PlotOptions { signals: vec!["rev.phi".into()], width: 700, ..Default::default() },
    )
    .unwrap();
    assert_eq!((summary.width, summary.height), (700, 320));
    assert!(svg.starts_with("<svg"), "{}", &svg[..100.min(svg.len())]);
    assert!(svg.contains(r#"width="700""#) && svg.contains(r#"height="320""#));
    assert!(svg.contains("<polyline") || svg.contains("<path"), "no line in the SVG");
    for label in ["rev.phi", "time [s]", "[rad]", "pendulum &lt;1&gt;"] {
        assert!(svg.contains(label), "the SVG has no `{label}`");
    }
    let path = scratch("pendulum.svg");
    write_plot(&path, "pendulum", &solution, &PlotOptions::default()).unwrap();
    assert!(std::fs::read_to_string(&path).unwrap().starts_with("<svg"));
}

#[test]
fn errors_say_what_to_do() {
    let mechanism = models::pendulum();
    let solution = models::simulate(&mechanism, 0.1);
    let err =
        plot_png("p", &solution, &PlotOptions { signals: vec!["rev.pih".into()], ..Default::default() }).unwrap_err();
    assert!(matches!(err, ViewError::NoSignal { .. }));
    assert!(err.to_string().contains("did you mean rev.phi"), "{err}");
    let err = write_plot(scratch("p.pdf"), "p", &solution, &PlotOptions::default()).unwrap_err();
    assert!(err.to_string().contains(".png or .svg"), "{err}");
    let err = plot_png("p", &solution, &PlotOptions { signals: vec!["*".into()], ..Default::default() }).unwrap_err();
    assert!(err.to_string().contains("choose fewer"), "{err}");
}
