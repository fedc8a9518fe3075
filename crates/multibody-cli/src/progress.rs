//! A progress bar for long runs, drawn only on a terminal and only once a
//! run has taken long enough to want one.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

const SHOW_AFTER: Duration = Duration::from_millis(400);
const STEPS: u64 = 1000;

pub struct Progress {
    bar: ProgressBar,
    start: f64,
    span: f64,
    started: Instant,
    shown: bool,
    enabled: bool,
}

impl Progress {
    pub fn new(start: f64, stop: f64) -> Self {
        let bar = ProgressBar::with_draw_target(Some(STEPS), ProgressDrawTarget::hidden());
        let style =
            ProgressStyle::with_template("  {bar:40.cyan/blue} {percent:>3}%  {msg}  ({elapsed}, about {eta} left)")
                .unwrap_or_else(|_| ProgressStyle::default_bar());
        bar.set_style(style);
        Self {
            bar,
            start,
            span: (stop - start).max(f64::MIN_POSITIVE),
            started: Instant::now(),
            shown: false,
            enabled: std::io::stderr().is_terminal(),
        }
    }

    /// The simulation reached time `t`.
    pub fn update(&mut self, t: f64) {
        if !self.enabled {
            return;
        }
        if !self.shown && self.started.elapsed() > SHOW_AFTER {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
            self.shown = true;
        }
        let fraction = ((t - self.start) / self.span).clamp(0.0, 1.0);
        self.bar.set_position((fraction * STEPS as f64) as u64);
        self.bar.set_message(format!("t = {t:.4} s"));
    }

    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
