//! Views of a multibody simulation: a self-contained 3-D animation page and
//! plots of signals against time.
//!
//! Both take what the engine already gives: the shapes the components
//! declare ([`Mechanism::shapes`](multibody::Mechanism::shapes)) and the
//! [`Solution`], which holds every frame's `r_0` and `R` over time.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! # let mechanism: multibody::Mechanism = todo!();
//! # let solution: multibody::Solution = todo!();
//! use multibody_view::{write_animation, write_plot, AnimationOptions, PlotOptions};
//! let signals = vec!["*.phi".to_string()];
//! write_animation("out.html", "pendulum", &mechanism.shapes(), &solution,
//!     &AnimationOptions { signals: signals.clone(), ..Default::default() })?;
//! write_plot("out.png", "pendulum", &solution, &PlotOptions { signals, ..Default::default() })?;
//! # Ok(()) }
//! ```
//!
//! The page needs nothing but a browser with WebGL2: no network, no
//! third-party code. It is written by [`write_animation`] (or
//! [`animation_html`] for the text); plots by [`write_plot`] (PNG or SVG by
//! the file name) or [`plot_png`] / [`plot_svg`] for the bytes.

mod base64;
mod html;
mod json;
#[cfg(feature = "images")]
mod linear;
#[cfg(feature = "live")]
mod live;
pub mod mesh;
#[cfg(feature = "images")]
mod plot;
mod scene;
mod signals;

use std::path::{Path, PathBuf};

pub use html::{
    animation_html, animation_scene, write_animation, write_animation_to, Animation, AnimationOptions, AnimationSummary,
};
#[cfg(feature = "images")]
pub use linear::{
    bode_png, bode_response, bode_svg, damping_report, default_frequency_range, linearization_json, write_bode,
    BodeCurve, BodeOptions, BodeResponse, BodeSummary,
};
#[cfg(feature = "live")]
pub use live::{live_html, LiveModel};
#[cfg(feature = "images")]
pub use plot::{plot_png, plot_svg, write_plot, PlotFormat, PlotOptions, PlotSummary};
pub use scene::{mesh_path, MAX_MESH_TRIANGLES};
pub use signals::{choose_signals, default_signals};

pub use multibody::components::shapes::Shape;
pub use multibody::Solution;

/// What can go wrong while making a view.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    #[error("cannot write {path}: {source}", path = .path.display())]
    Io { path: PathBuf, source: std::io::Error },
    #[error("the solution has no samples: simulate before making a view")]
    EmptySolution,
    #[error("no signal matches `{pattern}`{hint}")]
    NoSignal { pattern: String, hint: String },
    #[error("no signals to plot: the solution has none")]
    NothingToPlot,
    #[error("cannot tell the plot format of {path}: name it .png or .svg", path = .path.display())]
    Format { path: PathBuf },
    #[error("plot: {0}")]
    Plot(String),
}

impl ViewError {
    fn io(path: &Path, source: std::io::Error) -> Self {
        ViewError::Io { path: path.to_path_buf(), source }
    }
}
