//! Writes animation pages and plots of a few models for a person to look
//! at: `cargo run -p multibody-view --example view_demo [--release] [OUT_DIR]`
//! (default `target/view-demo/`). The 100-body chain is simulated for 10 s,
//! which takes about a minute without `--release`.

#[path = "../tests/common/models.rs"]
mod models;

use multibody_view::{write_animation, write_plot, AnimationOptions, PlotOptions};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out: PathBuf = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/view-demo"));
    let chain_links: usize = std::env::var("VIEW_DEMO_CHAIN").ok().and_then(|s| s.parse().ok()).unwrap_or(100);
    let cases: Vec<(&str, multibody::Mechanism, f64, Vec<String>)> = vec![
        ("pendulum", models::pendulum(), 10.0, vec![]),
        ("double_pendulum", models::double_pendulum(), 10.0, vec![]),
        ("spring_mass", models::spring_mass(), 4.0, vec!["body.r_0[*]".into(), "spring.f".into()]),
        ("chain100", models::chain(chain_links), 10.0, vec![]),
    ];
    for (name, mechanism, stop, signals) in cases {
        let started = std::time::Instant::now();
        let solution = models::simulate(&mechanism, stop);
        let simulated = started.elapsed();
        let html = out.join(format!("{name}.html"));
        let summary = write_animation(
            &html,
            name,
            &mechanism.shapes(),
            &solution,
            &AnimationOptions { signals: signals.clone(), ..Default::default() },
        )?;
        let png = out.join(format!("{name}.png"));
        let plot = write_plot(&png, name, &solution, &PlotOptions { signals, ..Default::default() })?;
        println!(
            "{}: {:.1} kB, {} frames, {} poses, {} shapes, signals {:?}; plot {}x{} {}; simulated in {:.2?}",
            html.display(),
            summary.bytes as f64 / 1e3,
            summary.frames,
            summary.poses,
            summary.shapes,
            summary.signals,
            plot.width,
            plot.height,
            png.display(),
            simulated
        );
        for note in &summary.left_out {
            println!("  left out: {note}");
        }
    }
    Ok(())
}
