//! Simulation: integrates a mechanism's ODE and samples every output on an
//! output grid.
//!
//! The integrators (Dormand-Prince 5(4) with dense output, and RK4) are
//! written here rather than taken from a crate. The crates we measured
//! (russell_ode, diffsol, differential-equations, ode_solvers; 2026-11)
//! either allocate in every step, or lack `dtmax` or a fixed-step RK4, or
//! cannot stop on a failed evaluation and keep the output. None lets the
//! caller move the state after an accepted step, and this engine needs that
//! to project kinematic loops back onto their constraints and to detect
//! Euler-angle singularities between steps ([`integrator::OdeSystem::accept`]).

mod dopri5;
pub mod integrator;
mod rk4;
mod rodas;
mod solution;

pub use integrator::Stats;
pub use solution::{glob, Solution};

use crate::assembly::Mechanism;
use crate::dynamics::{DynamicsError, Workspace};
use crate::outputs::OutputScratch;
use integrator::{DenseStep, Failure, OdeSystem, Stopped, Tolerances};

/// The integration method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Adaptive Dormand-Prince 5(4) with error control and dense output.
    DormandPrince45,
    /// Classical Runge-Kutta with a fixed step.
    Rk4 { dt: f64 },
}

/// What to simulate, with Dyad's TransientAnalysis defaults.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationOptions {
    pub start: f64,
    pub stop: f64,
    pub abstol: f64,
    pub reltol: f64,
    /// Output interval; 0 saves at every integrator step.
    pub saveat: f64,
    /// Largest step; 0 for no limit.
    pub dtmax: f64,
    pub method: Method,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        Self {
            start: 0.0,
            stop: 1.0,
            abstol: 1e-6,
            reltol: 1e-6,
            saveat: 0.0,
            dtmax: 0.0,
            method: Method::DormandPrince45,
        }
    }
}

impl SimulationOptions {
    /// Options for a run from 0 to `stop` with defaults otherwise.
    pub fn until(stop: f64) -> Self {
        Self { stop, ..Self::default() }
    }

    /// Checks the options, saying which one is wrong (by its analysis
    /// name: `stop`, `reltol`, ...) and why.
    pub fn validate(&self) -> Result<(), OptionError> {
        let named = [
            ("start", self.start),
            ("stop", self.stop),
            ("abstol", self.abstol),
            ("reltol", self.reltol),
            ("saveat", self.saveat),
            ("dtmax", self.dtmax),
        ];
        let bad = |option, message: String| Err(OptionError { option, message });
        if let Some((option, x)) = named.iter().find(|(_, x)| !x.is_finite()) {
            return bad(option, format!("`{option}` must be a finite number, not {x}"));
        }
        if self.stop <= self.start {
            return bad("stop", format!("`stop` ({}) must be after `start` ({})", self.stop, self.start));
        }
        for (option, x) in [("abstol", self.abstol), ("reltol", self.reltol)] {
            if x <= 0.0 {
                return bad(option, format!("`{option}` must be positive, not {x}"));
            }
        }
        if self.reltol < 4.0 * f64::EPSILON {
            let message =
                format!("`reltol` ({}) is below what double precision can resolve (about 1e-15)", self.reltol);
            return bad("reltol", message);
        }
        for (option, x) in [("saveat", self.saveat), ("dtmax", self.dtmax)] {
            if x < 0.0 {
                return bad(option, format!("`{option}` must not be negative, not {x}"));
            }
        }
        if let Method::Rk4 { dt } = self.method {
            if !(dt > 0.0 && dt.is_finite()) {
                return bad("dt", format!("the RK4 step must be positive, not {dt}"));
            }
        }
        Ok(())
    }
}

/// A simulation option that cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{message}")]
pub struct OptionError {
    /// The option, by its name in a TransientAnalysis: `stop`, `reltol`, ...
    pub option: &'static str,
    pub message: String,
}

/// A simulation that stopped before its end: why, when, and everything
/// computed until then.
#[derive(Debug, thiserror::Error)]
#[error("the simulation stopped at t = {time}: {reason}")]
pub struct SimulationError {
    pub time: f64,
    pub reason: String,
    /// The outputs up to `time`.
    pub partial: Solution,
}

/// The mechanism as an ODE for the integrators.
struct Dynamics<'a> {
    mechanism: &'a Mechanism,
    ws: Workspace,
    /// Side of the singular configuration of each Euler-angle joint.
    euler_sides: Vec<f64>,
    /// The same at the end of the step being accepted (scratch).
    euler_sides_now: Vec<f64>,
}

impl OdeSystem for Dynamics<'_> {
    type Error = DynamicsError;
    fn dim(&self) -> usize {
        self.mechanism.system.states.nq + self.mechanism.system.states.nv
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), DynamicsError> {
        self.mechanism.rhs(&mut self.ws, t, y, dy)
    }

    fn accept(&mut self, step: &dyn DenseStep, y: &mut [f64]) -> Result<bool, DynamicsError> {
        if !self.euler_sides.is_empty() {
            self.euler_crossing(step, y)?;
        }
        self.mechanism.project(&mut self.ws, y)
    }
}

impl Dynamics<'_> {
    /// Stops at an Euler-angle joint's singular configuration, also when the
    /// step went across it (the motion may pass smoothly, the angles not):
    /// the time is where `det J` changes sign, found on the dense output.
    fn euler_crossing(&mut self, step: &dyn DenseStep, y: &[f64]) -> Result<(), DynamicsError> {
        let (t0, t1) = step.span();
        let sides = |mech: &Mechanism, y: &[f64], out: &mut Vec<f64>| mech.system.euler_sides(y, out);
        let mut now = std::mem::take(&mut self.euler_sides_now);
        let crossed = match sides(self.mechanism, y, &mut now) {
            Err(link) => Some(link),
            Ok(()) => now.iter().zip(&self.euler_sides).position(|(a, b)| a != b).map(|k| self.euler_link(k)),
        };
        let Some(link) = crossed else {
            // Swap, so that accepted steps reuse both buffers.
            self.euler_sides_now = std::mem::replace(&mut self.euler_sides, now);
            return Ok(());
        };
        let (mut lo, mut hi) = (t0, t1);
        let mut mid_state = vec![0.0; y.len()];
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            step.interpolate(mid, &mut mid_state);
            match sides(self.mechanism, &mid_state, &mut now) {
                Ok(()) if now == self.euler_sides => lo = mid,
                _ => hi = mid,
            }
        }
        Err(DynamicsError::EulerSingularity { link, time: hi })
    }

    /// The link of the k-th Euler-angle joint.
    fn euler_link(&self, k: usize) -> usize {
        self.mechanism
            .system
            .links
            .iter()
            .enumerate()
            .filter(|(_, l)| {
                matches!(
                    l.joint.rotation_coordinates(),
                    Some((_, crate::system::joint::RotationCoordinates::Euler { .. }))
                )
            })
            .nth(k)
            .map_or(0, |(i, _)| i)
    }
}

/// Samples outputs on the grid as the integrator advances.
struct Recorder<'a, 'p> {
    mechanism: &'a Mechanism,
    ws: Workspace,
    scratch: OutputScratch,
    solution: Solution,
    row: Vec<f64>,
    y: Vec<f64>,
    saveat: f64,
    start: f64,
    stop: f64,
    next: usize,
    progress: Option<&'p mut dyn FnMut(f64)>,
}

impl Recorder<'_, '_> {
    fn record(&mut self, t: f64, y: &[f64]) -> Result<(), DynamicsError> {
        self.mechanism.outputs_into(&mut self.ws, &mut self.scratch, t, y, &mut self.row)?;
        self.solution.push(t, &self.row);
        Ok(())
    }

    /// Records the grid points that the step `step` covers.
    fn observe(&mut self, step: &dyn DenseStep) -> Result<(), DynamicsError> {
        let (_, t1) = step.span();
        if self.saveat > 0.0 {
            loop {
                let t = (self.start + self.next as f64 * self.saveat).min(self.stop);
                let last = t >= self.stop;
                if t > t1 + 1e-12 * self.saveat {
                    break;
                }
                let mut y = std::mem::take(&mut self.y);
                step.interpolate(t, &mut y);
                let recorded = self.record(t, &y);
                self.y = y;
                recorded?;
                self.next += 1;
                if last {
                    break;
                }
            }
        } else {
            self.record(t1, step.y())?;
        }
        if let Some(p) = self.progress.as_mut() {
            p(t1);
        }
        Ok(())
    }
}

// The error carries the partial solution by value; it is returned once per
// simulation, so its size costs nothing.
#[allow(clippy::result_large_err)]
impl Mechanism {
    /// Simulates from the start values of the model.
    pub fn simulate(&self, options: &SimulationOptions) -> Result<Solution, SimulationError> {
        self.simulate_from(&self.system.states.start, options, None)
    }

    /// Simulates from the state `y0`, calling `progress` with the time
    /// reached after every step.
    pub fn simulate_from(
        &self,
        y0: &[f64],
        options: &SimulationOptions,
        progress: Option<&mut dyn FnMut(f64)>,
    ) -> Result<Solution, SimulationError> {
        let mut solution = Solution::with_signals(self.signal_table().clone());
        if options.saveat > 0.0 && options.stop > options.start {
            // The grid is known: growing hundreds of columns sample by sample costs more than the dynamics.
            let samples = ((options.stop - options.start) / options.saveat).ceil() + 1.0;
            solution.reserve(samples.min(1e7) as usize);
        }
        let fail = |time: f64, reason: String, partial: Solution| SimulationError { time, reason, partial };
        if let Err(e) = options.validate() {
            return Err(fail(options.start, e.message, solution));
        }
        if y0.len() != self.system.states.start.len() {
            let reason = format!(
                "the start state has {} values, the mechanism {} states",
                y0.len(),
                self.system.states.start.len()
            );
            return Err(fail(options.start, reason, solution));
        }
        let mut recorder = Recorder {
            mechanism: self,
            ws: self.workspace(),
            scratch: OutputScratch::default(),
            solution,
            row: Vec::new(),
            y: vec![0.0; y0.len()],
            saveat: options.saveat,
            start: options.start,
            stop: options.stop,
            next: 1,
            progress,
        };
        if let Err(e) = recorder.record(options.start, y0) {
            return Err(fail(options.start, self.describe(&e), recorder.solution));
        }
        let mut system =
            Dynamics { mechanism: self, ws: self.workspace(), euler_sides: Vec::new(), euler_sides_now: Vec::new() };
        if let Err(link) = self.system.euler_sides(y0, &mut system.euler_sides) {
            let e = DynamicsError::EulerSingularity { link, time: options.start };
            return Err(fail(options.start, self.describe(&e), recorder.solution));
        }
        let (t0, tf) = (options.start, options.stop);
        let result = match options.method {
            Method::DormandPrince45 => {
                let tol = Tolerances { abstol: options.abstol, reltol: options.reltol, dtmax: options.dtmax };
                dopri5::DormandPrince::new(y0.len(), tol).integrate(&mut system, t0, tf, y0, |s| recorder.observe(s))
            }
            Method::Rk4 { dt } => {
                rk4::Rk4::new(y0.len(), dt).integrate(&mut system, t0, tf, y0, |s| recorder.observe(s))
            }
        };
        match result {
            Ok(_) => Ok(recorder.solution),
            Err(Stopped { t, failure, .. }) => {
                // A singularity inside the last step stops at its own time.
                let t = match failure {
                    Failure::Rhs(DynamicsError::EulerSingularity { time, .. }) if time.is_finite() => time,
                    _ => t,
                };
                recorder.solution.truncate_after(t);
                let reason = match failure {
                    Failure::Rhs(e) | Failure::Observer(e) => self.describe(&e),
                    Failure::StepTooSmall { h } => format!(
                        "the step size fell to {h:e}, too small to make progress: the motion is too fast or stiff here (check parameters for very stiff springs or tiny masses)"
                    ),
                    Failure::NotFinite => self.describe(&DynamicsError::NotFinite),
                };
                Err(fail(t, reason, recorder.solution))
            }
        }
    }
}
