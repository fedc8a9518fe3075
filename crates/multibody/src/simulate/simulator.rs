//! The [`Simulator`]: a compiled model with a boundary. It owns the
//! integrator, the event handling and the recorder, and advances on
//! request ([`Simulator::step_until`]) while the host sets inputs and reads
//! or sets the state between calls. [`Mechanism::simulate`] is one call.
//!
//! Events: every evaluation of the dynamics writes its indicators
//! (`Workspace::indicators`); an event is where one changes sign against
//! its sign when the integration last started. It is located on the
//! step's dense output by bisection, the step is cut there, and the event
//! iteration runs the dynamics at that instant with relations evaluated as
//! they are until no discrete value changes (applying `reinit`s), the
//! state is moved back onto the constraints, and the integrator starts
//! again. Time events (a source's switching times) end a stretch of
//! integration exactly, the dynamics seeing the sources' left limits up to
//! them.
//!
//! The Euler-angle singularity is one indicator among the others: each
//! Euler-angle joint's middle angle must stay 0.1 rad away from its
//! singular values. Where it comes closer, the event moves the joint to a
//! chart (its orientation integrated as Euler angles from a turned base,
//! `dynamics::chart`), a note says so once, and the run goes on; the
//! outputs still report the library's angles.

use super::integrator::{DenseStep, Failure, Observer, OdeSystem, Reached, Stats, Tolerances};
use super::{dopri5, rk4, rodas, rosw, Method, Rows, RunReport, SampleSink, SimulationOptions, Solution, Stopped};
use crate::assembly::Mechanism;
use crate::dynamics::chart::{self, EulerChart};
use crate::dynamics::{DynamicsError, StateJacobian, Workspace};
use crate::math::rotation::{axes_rotations, axes_rotations_rate_matrix};
use crate::math::{Mat3, Transform, Vec3};
use crate::outputs::OutputScratch;
use crate::system::joint::RotationCoordinates;
use std::ops::Deref;
use std::sync::{Arc, OnceLock};

mod exchange;
pub use exchange::EventUpdate;

/// Passes of one event iteration before it is declared not to settle.
const EVENT_ITERATIONS: usize = 50;
/// At most this many rounds of the event iteration and the projection
/// onto the constraints that follows it, at one event.
const EVENT_PROJECTIONS: usize = 3;
/// Events within so short a time (relative to the time, at least 1 s)
/// that, this many in a row, mean the events pile up (Zeno behaviour, or an
/// indicator that chatters).
const ZENO_SPAN: f64 = 1e-9;
const ZENO_EVENTS: usize = 100;

/// The mechanism a simulator runs: borrowed, or shared (as a host that
/// keeps the simulator needs: Python, an FMU).
#[derive(Clone)]
pub enum Shared<'m> {
    Borrowed(&'m Mechanism),
    Owned(Arc<Mechanism>),
}

impl Deref for Shared<'_> {
    type Target = Mechanism;
    fn deref(&self) -> &Mechanism {
        match self {
            Shared::Borrowed(m) => m,
            Shared::Owned(m) => m,
        }
    }
}

impl<'m> From<&'m Mechanism> for Shared<'m> {
    fn from(m: &'m Mechanism) -> Self {
        Shared::Borrowed(m)
    }
}

impl From<Arc<Mechanism>> for Shared<'static> {
    fn from(m: Arc<Mechanism>) -> Self {
        Shared::Owned(m)
    }
}

/// The integrator of the chosen method.
enum Stepper {
    DormandPrince(dopri5::DormandPrince),
    Rk4(rk4::Rk4),
    Rodas4(rodas::Rodas4),
    RosW(rosw::RosW),
}

impl Stepper {
    fn new(n: usize, options: &SimulationOptions) -> Self {
        let tol = Tolerances { abstol: options.abstol, reltol: options.reltol, dtmax: options.dtmax };
        match options.method {
            Method::DormandPrince45 => Stepper::DormandPrince(dopri5::DormandPrince::new(n, tol)),
            Method::Rk4 { dt } => Stepper::Rk4(rk4::Rk4::new(n, dt)),
            Method::Rodas4 => Stepper::Rodas4(rodas::Rodas4::new(n, tol)),
            Method::Ros34Pw2 => Stepper::RosW(rosw::RosW::new(n, tol)),
        }
    }

    /// The largest step from the next start on (0: none).
    fn set_dtmax(&mut self, dtmax: f64) {
        match self {
            Stepper::DormandPrince(s) => s.tol.dtmax = dtmax,
            Stepper::Rk4(_) => {}
            Stepper::Rodas4(s) => s.tol.dtmax = dtmax,
            Stepper::RosW(s) => s.tol.dtmax = dtmax,
        }
    }

    fn start<S: OdeSystem>(&mut self, sys: &mut S, t: f64, y: &[f64], horizon: f64) -> Result<(), Stop<S::Error>> {
        match self {
            Stepper::DormandPrince(s) => s.start(sys, t, y, horizon),
            Stepper::Rk4(s) => s.start(sys, t, y),
            Stepper::Rodas4(s) => s.start(sys, t, y, horizon),
            Stepper::RosW(s) => s.start(sys, t, y, horizon),
        }
    }

    /// Starts again at `(t, y)` after an input changed, the state going on
    /// smoothly: the first step is the one the integrator would have taken
    /// next (the error control cuts it if the new input needs it), instead
    /// of a new estimate.
    fn restart<S: OdeSystem>(&mut self, sys: &mut S, t: f64, y: &[f64], horizon: f64) -> Result<(), Stop<S::Error>> {
        match self {
            Stepper::DormandPrince(s) => s.restart(sys, t, y, horizon),
            _ => self.start(sys, t, y, horizon),
        }
    }

    fn advance<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        tf: f64,
        observe: &mut Observer<S::Error>,
    ) -> Result<Reached, Stop<S::Error>> {
        match self {
            Stepper::DormandPrince(s) => s.advance(sys, tf, observe),
            Stepper::Rk4(s) => s.advance(sys, tf, observe),
            Stepper::Rodas4(s) => s.advance(sys, tf, observe),
            Stepper::RosW(s) => s.advance(sys, tf, observe),
        }
    }

    /// Advances to at least `tf` with steps not cut short at it (up to
    /// `limit`), where the method has a dense output to read `tf` on;
    /// otherwise to exactly `tf`.
    fn advance_past<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        tf: f64,
        limit: f64,
        observe: &mut Observer<S::Error>,
    ) -> Result<Reached, Stop<S::Error>> {
        match self {
            Stepper::DormandPrince(s) => s.advance_past(sys, tf, limit, observe),
            _ => self.advance(sys, tf, observe),
        }
    }

    /// The last step, when the integration may stand past the time the
    /// simulator reached (see [`Stepper::advance_past`]).
    fn ahead(&self) -> Option<&dyn DenseStep> {
        match self {
            Stepper::DormandPrince(s) => Some(s),
            _ => None,
        }
    }

    /// The state reached.
    fn state(&self) -> &[f64] {
        match self {
            Stepper::DormandPrince(s) => s.y(),
            Stepper::Rk4(s) => s.y(),
            Stepper::Rodas4(s) => s.y(),
            Stepper::RosW(s) => s.y(),
        }
    }

    fn stats(&self) -> Stats {
        match self {
            Stepper::DormandPrince(s) => s.stats(),
            Stepper::Rk4(s) => s.stats(),
            Stepper::Rodas4(s) => s.stats(),
            Stepper::RosW(s) => s.stats(),
        }
    }
}

type Stop<E> = super::integrator::Stopped<E>;

/// What stops a step: the dynamics, the caller (through the sink or the
/// progress callback), or events that do not settle.
#[derive(Debug)]
pub(crate) enum StepError {
    Dynamics(DynamicsError),
    Caller(String),
    Events(String),
}

impl From<DynamicsError> for StepError {
    fn from(e: DynamicsError) -> Self {
        StepError::Dynamics(e)
    }
}

/// Where the indicators stood when the integration last started, and
/// scratch for locating a change.
#[derive(Default)]
struct Indicators {
    /// Whether each indicator was positive.
    above: Vec<bool>,
    y: Vec<f64>,
    dy: Vec<f64>,
    /// The indicator that changed sign at the last event located: one of
    /// the model's, or past them, the Euler-angle joint of that number.
    last: Option<usize>,
    /// The earliest time after `since` at which an evaluation of the
    /// integrator (a stage) saw an indicator on the other sign: a step
    /// whose ends agree may still hold crossings (an even number of them).
    inside: Option<f64>,
    /// Where the step being taken starts.
    since: f64,
    /// Once a step held crossings its ends did not show, the steps are
    /// held to a quarter of the span to the stage that saw them, for the
    /// rest of the run: an indicator that swings that fast (a relation on
    /// `sin(w t)`) is then met once per step, each crossing found in turn.
    bound: Option<f64>,
    /// The indicator and time of a hidden crossing not yet told.
    untold: Option<(usize, f64)>,
}

impl Indicators {
    /// The first indicator whose sign differs from where it stood.
    fn changed(&self, values: &[f64]) -> Option<usize> {
        values.iter().zip(&self.above).position(|(&g, &above)| (g > 0.0) != above)
    }
}

/// The mechanism as an ODE for the integrators.
struct Dynamics<'a> {
    mechanism: &'a Mechanism,
    ws: &'a mut Workspace,
    /// The analytic Jacobian's work, for the implicit method where the
    /// model allows it.
    jacobian: Option<&'a mut StateJacobian>,
    /// The Euler-angle joints' distance from their singular configuration.
    charts: &'a [ChartWatch],
    indicators: &'a mut Indicators,
}

/// Points inside a step where the Euler-angle indicators are looked at
/// besides its end: a middle angle that enters the band around a singular
/// value and leaves it again within one step (a near touch) is found when
/// it stays in for more than a sixteenth of the step. (A pass through the
/// singular value, however long the step, ends outside the safe interval
/// and is found at the step's end.)
const CHART_PROBES: usize = 16;

/// An Euler-angle joint's indicator: its middle angle (state `at`) must
/// stay in `[lo, hi]`, [`chart::CHART_BAND`] from the singular values on either side
/// of where it stood when the integration last started. The indicator is
/// the signed distance to the nearer end, monotone in the angle, so that a
/// step that jumps over the singular value, or past several, still ends on
/// the other sign.
#[derive(Clone, Debug)]
struct ChartWatch {
    link: usize,
    at: usize,
    sequence: [usize; 3],
    lo: f64,
    hi: f64,
    /// A joint traversed from its frame_b: no chart, the run stops there.
    inverted: bool,
    /// Whether the note was given.
    noted: bool,
}

impl ChartWatch {
    fn indicator(&self, y: &[f64]) -> f64 {
        (y[self.at] - self.lo).min(self.hi - y[self.at])
    }

    /// Whether the indicator changed sign (a NaN angle counts).
    fn crossed(&self, y: &[f64]) -> bool {
        let g = self.indicator(y);
        g.is_nan() || g < 0.0
    }
}

/// The first Euler-angle joint whose indicator changed sign at `y`.
fn chart_crossed(charts: &[ChartWatch], y: &[f64]) -> Option<usize> {
    charts.iter().position(|c| c.crossed(y))
}

impl OdeSystem for Dynamics<'_> {
    type Error = StepError;
    fn dim(&self) -> usize {
        self.mechanism.system.states.start.len()
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), StepError> {
        self.mechanism.rhs(self.ws, t, y, dy)?;
        let ind = &mut *self.indicators;
        if t > ind.since && ind.inside.is_none_or(|at| t < at) && ind.changed(&self.ws.indicators).is_some() {
            ind.inside = Some(t);
        }
        Ok(())
    }

    fn jacobian(&mut self, t: f64, y: &[f64], jac: &mut [f64]) -> Result<bool, StepError> {
        let Some(work) = self.jacobian.as_deref_mut() else { return Ok(false) };
        self.mechanism.system.state_jacobian(self.ws, work, t, y, jac)?;
        Ok(true)
    }

    fn accept(&mut self, step: &dyn DenseStep, y: &mut [f64]) -> Result<bool, StepError> {
        Ok(self.mechanism.project(self.ws, step.span().1, y)?)
    }

    fn locate(&mut self, step: &dyn DenseStep, end_evaluated: bool) -> Result<Option<f64>, StepError> {
        if self.indicators.above.is_empty() && self.charts.is_empty() {
            return Ok(None);
        }
        let (t0, t1) = step.span();
        let mut ind = std::mem::take(self.indicators);
        let located = self.first_change(step, t0, t1, end_evaluated, &mut ind);
        // The next step's stages are looked at afresh.
        (ind.inside, ind.since) = (None, located.as_ref().ok().copied().flatten().unwrap_or(t1));
        *self.indicators = ind;
        located
    }
}

impl Dynamics<'_> {
    /// The time of the first sign change of an indicator in `[t0, t1]`,
    /// to the resolution of the time: bisection on the dense output
    /// (whether any indicator changed is monotone in time where the step
    /// meets a single crossing, as it does at the integrator's tolerance).
    /// The Euler-angle indicators, functions of the state alone, are also
    /// looked at inside the step ([`CHART_PROBES`]).
    fn first_change(
        &mut self,
        step: &dyn DenseStep,
        t0: f64,
        t1: f64,
        end_evaluated: bool,
        ind: &mut Indicators,
    ) -> Result<Option<f64>, StepError> {
        let model = !ind.above.is_empty();
        if model && !end_evaluated {
            self.mechanism.rhs(self.ws, t1, step.y(), &mut ind.dy)?;
        }
        let mut which = match chart_crossed(self.charts, step.y()) {
            Some(k) => Some(ind.above.len() + k),
            None if model => ind.changed(&self.ws.indicators),
            None => None,
        };
        let mut hi = t1;
        if which.is_none() && !self.charts.is_empty() {
            for j in 1..CHART_PROBES {
                let t = t0 + (t1 - t0) * j as f64 / CHART_PROBES as f64;
                step.interpolate(t, &mut ind.y);
                if let Some(k) = chart_crossed(self.charts, &ind.y) {
                    (hi, which) = (t, Some(ind.above.len() + k));
                    break;
                }
            }
        }
        // Ends that agree, but a stage inside saw the other sign: on the
        // dense output there too, the crossings between are found (the
        // first of them where the stage was the first past it).
        if which.is_none() && model {
            if let Some(at) = ind.inside.filter(|&at| at > t0 && at < t1) {
                step.interpolate(at, &mut ind.y);
                self.mechanism.rhs(self.ws, at, &ind.y, &mut ind.dy)?;
                if let Some(k) = ind.changed(&self.ws.indicators) {
                    (hi, which) = (at, Some(k));
                    let bound = 0.25 * (at - t0);
                    if ind.bound.is_none() {
                        ind.untold = Some((k, t0));
                    }
                    ind.bound = Some(ind.bound.map_or(bound, |b| b.min(bound)));
                }
            }
        }
        let Some(mut which) = which else { return Ok(None) };
        let mut lo = t0;
        let resolution = 4.0 * f64::EPSILON * t0.abs().max(t1.abs()).max(1.0);
        while hi - lo > resolution {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            step.interpolate(mid, &mut ind.y);
            let changed = match chart_crossed(self.charts, &ind.y) {
                Some(k) => Some(ind.above.len() + k),
                None if model => {
                    self.mechanism.rhs(self.ws, mid, &ind.y, &mut ind.dy)?;
                    ind.changed(&self.ws.indicators)
                }
                None => None,
            };
            match changed {
                Some(k) => {
                    hi = mid;
                    which = k;
                }
                None => lo = mid,
            }
        }
        ind.last = Some(which);
        Ok(Some(hi))
    }
}

/// What the recorder keeps between calls: the output grid's progress, its
/// own workspace, and the samples of the latest step while they wait to be
/// final (when `hold`).
struct RecorderState {
    ws: Workspace,
    scratch: OutputScratch,
    row: Vec<f64>,
    /// The components whose outputs the sink reads (`None`: all).
    wanted: Option<Vec<bool>>,
    /// Those a host asks for now ([`Simulator::signal_values`]).
    wanted_now: Vec<bool>,
    y: Vec<f64>,
    pending_time: Vec<f64>,
    pending_rows: Vec<f64>,
    /// Whether samples wait for their step to be final.
    hold: bool,
    saveat: f64,
    start: f64,
    stop: f64,
    /// The next grid point's number (0: the start).
    next: usize,
    /// Whether the stop was recorded (a simulator may go on past it).
    past_stop: bool,
    /// No grid point after this time is recorded (the integration may
    /// stand past the time asked for).
    until: f64,
    /// Nothing is recorded: a host reads the values it wants when it
    /// wants them ([`Simulator::for_host`]).
    off: bool,
}

/// The recorder during one call: its state, where samples go, and whom
/// to tell the progress.
struct Recorder<'a, 's, 'p, 'q> {
    mechanism: &'a Mechanism,
    state: &'a mut RecorderState,
    sink: &'s mut dyn SampleSink,
    progress: Option<&'p mut Progress<'q>>,
}

/// What a run calls with the time reached after every step; an error
/// stops the run with that reason.
pub type Progress<'q> = dyn FnMut(f64) -> Result<(), String> + 'q;

impl Recorder<'_, '_, '_, '_> {
    fn record(&mut self, t: f64, y: &[f64]) -> Result<(), StepError> {
        let s = &mut *self.state;
        let wanted = s.wanted.as_deref();
        self.mechanism.outputs_into(&mut s.ws, &mut s.scratch, t, y, &mut s.row, wanted)?;
        if !s.hold {
            return self.sink.sample(t, &s.row).map_err(StepError::Caller);
        }
        s.pending_time.push(t);
        s.pending_rows.extend_from_slice(&s.row);
        Ok(())
    }

    /// Gives the sink the pending samples up to time `until`, drops the rest.
    fn flush(&mut self, until: f64) -> Result<(), StepError> {
        let s = &mut *self.state;
        let width = s.row.len();
        let result = s
            .pending_time
            .iter()
            .zip(s.pending_rows.chunks_exact(width.max(1)))
            .take_while(|(&t, _)| t <= until)
            .try_for_each(|(&t, row)| self.sink.sample(t, row));
        s.pending_time.clear();
        s.pending_rows.clear();
        result.map_err(StepError::Caller)
    }

    /// Records the grid points that the step `step` covers.
    fn observe(&mut self, step: &dyn DenseStep) -> Result<(), StepError> {
        // The previous step was final: the integrator went on from it.
        self.flush(f64::INFINITY)?;
        let (_, t1) = step.span();
        if self.state.off {
            // Nothing to record.
        } else if self.state.saveat > 0.0 {
            loop {
                let s = &*self.state;
                let on_grid = s.start + s.next as f64 * s.saveat;
                // The stop is a sample even off the grid; past it the grid goes on.
                let t = if s.past_stop { on_grid } else { on_grid.min(s.stop) };
                if t > t1 + 1e-12 * s.saveat || t > s.until {
                    break;
                }
                if s.past_stop && on_grid <= s.stop {
                    self.state.next += 1;
                    continue;
                }
                let mut y = std::mem::take(&mut self.state.y);
                step.interpolate(t, &mut y);
                let recorded = self.record(t, &y);
                self.state.y = y;
                recorded?;
                self.state.next += 1;
                if t >= self.state.stop {
                    self.state.past_stop = true;
                }
            }
        } else {
            self.record(t1, step.y())?;
        }
        match self.progress.as_mut() {
            Some(p) => p(t1).map_err(StepError::Caller),
            None => Ok(()),
        }
    }
}

/// A model being simulated, advanced on request.
///
/// ```no_run
/// # use multibody::{Model, SimulationOptions, Simulator};
/// # let mechanism = Model::new("m").assemble().unwrap();
/// let options = SimulationOptions { stop: 5.0, saveat: 0.01, ..Default::default() };
/// let mut sim = Simulator::new(&mechanism, &options).unwrap();
/// while sim.time() < 5.0 {
///     let angle = sim.value("rev.phi").unwrap();
///     sim.set_input("torque", -4.0 * angle).unwrap();
///     sim.step_until(sim.time() + 0.001).unwrap();
/// }
/// let result = sim.solution();
/// ```
pub struct Simulator<'m> {
    mechanism: Shared<'m>,
    options: SimulationOptions,
    stepper: Stepper,
    ws: Workspace,
    indicators: Indicators,
    /// The Euler-angle joints, watched for their singular configuration.
    charts: Vec<ChartWatch>,
    /// The mechanism as given, before any joint moved to a chart (what
    /// [`Simulator::reset`] goes back to).
    original: Shared<'m>,
    recorder: RecorderState,
    /// The samples [`Simulator::step_until`] records, row by row.
    recorded: Rows,
    /// The same as columns, made when [`Simulator::solution`] asks and
    /// kept up to date from then on.
    columns: OnceLock<Solution>,
    /// What the run found worth saying once (a note each), given with the
    /// samples.
    notes: Vec<String>,
    /// The time and state reached.
    t: f64,
    y: Vec<f64>,
    /// The state to go back to on [`Simulator::reset`].
    y0: Vec<f64>,
    /// Whether the integrator holds `(t, y)` with its derivative, ready to
    /// step on (events, inputs and a new state make it start again).
    started: bool,
    /// The step bound while the states may stand frozen: without states
    /// nothing bounds the steps, and a relation of the signals could change
    /// and change back inside one; a stuck friction element freezes its
    /// states (the error estimate is zero, the steps grow) while the force
    /// it holds follows the sources and may pass its limit and fall back
    /// inside one long step. Steps no longer than the output interval then
    /// (with friction, only while an element is stuck).
    frozen_dtmax: Option<f64>,
    /// Whether only an input changed since the integrator stood ready: it
    /// starts again with the step it would have taken next, and (a host
    /// that sets an input before a call will likely do so before the next)
    /// the call does not step past the time asked for.
    input_changed: bool,
    /// Whether the integrator stands past `t`, its last step covering it
    /// (`y` read on that step's dense output): the next call goes on from
    /// there unless the host changed an input or the state.
    ahead: bool,
    /// Events in a row within `ZENO_SPAN`, and when the first of them was.
    piled: (usize, f64),
    events: usize,
    /// The time of the last event, and the indicator that made it (none
    /// for a time event).
    last_event: Option<(f64, Option<usize>)>,
    /// Work done by integrators that were replaced (on reset).
    stats: Stats,
    /// The analytic Jacobian's work, made for the implicit method where
    /// the model allows it.
    jacobian: Option<StateJacobian>,
}

impl<'m> Simulator<'m> {
    /// A simulator at the model's start values and `options.start`.
    pub fn new(mechanism: impl Into<Shared<'m>>, options: &SimulationOptions) -> Result<Self, Stopped> {
        let mechanism = mechanism.into();
        let y0 = mechanism.system.states.start.clone();
        let mut sim = Self::from_state(mechanism, &y0, options, None)?;
        sim.recorded.reserve(super::grid_samples(sim.recorded.width(), options));
        Ok(sim)
    }

    /// A simulator at the state `y0`, whose recorder computes only the
    /// components of the signals `columns` (all if `None`).
    pub(crate) fn from_state(
        mechanism: Shared<'m>,
        y0: &[f64],
        options: &SimulationOptions,
        columns: Option<&[usize]>,
    ) -> Result<Self, Stopped> {
        let fail = |reason: String| Stopped { time: options.start, reason, by_caller: false };
        if let Err(e) = options.validate() {
            return Err(fail(e.message));
        }
        let n = mechanism.system.states.start.len();
        // Without states nothing bounds the steps, and a relation of the
        // signals could change and change back inside one: steps no longer
        // than the output interval then. So too with friction: a stuck
        // element freezes its states (the error estimate is zero, the
        // steps grow), while the force it holds follows the sources and
        // may pass its limit and fall back inside one long step.
        // (Friction: only while an element is stuck; see `frozen_dtmax`.)
        let frozen = (n == 0 || !mechanism.system.frictions.is_empty())
            && !mechanism.system.events.indicators.is_empty()
            && options.saveat > 0.0;
        let frozen_dtmax =
            frozen.then(|| if options.dtmax > 0.0 { options.dtmax.min(options.saveat) } else { options.saveat });
        if y0.len() != n {
            return Err(fail(format!("the start state has {} values, the mechanism {n} states", y0.len())));
        }
        let wanted = columns.map(|columns| {
            let table = mechanism.signal_table();
            let mut wanted = vec![false; mechanism.components.len()];
            for owner in columns.iter().filter_map(|&k| table.owner(k)) {
                wanted[owner] = true;
            }
            wanted
        });
        let recorder = RecorderState {
            ws: mechanism.workspace(),
            scratch: OutputScratch::default(),
            row: Vec::new(),
            wanted,
            wanted_now: Vec::new(),
            y: vec![0.0; n],
            pending_time: Vec::new(),
            pending_rows: Vec::new(),
            hold: false,
            saveat: options.saveat,
            start: options.start,
            stop: options.stop,
            next: 0,
            past_stop: false,
            until: f64::INFINITY,
            off: false,
        };
        let mut sim = Simulator {
            stepper: Stepper::new(n, options),
            ws: mechanism.workspace(),
            indicators: Indicators::default(),
            charts: Vec::new(),
            original: mechanism.clone(),
            recorder,
            recorded: Rows::new(mechanism.signal_table().names().len()),
            columns: OnceLock::new(),
            notes: Vec::new(),
            t: options.start,
            y: y0.to_vec(),
            y0: y0.to_vec(),
            started: false,
            input_changed: false,
            ahead: false,
            piled: (0, f64::NEG_INFINITY),
            events: 0,
            last_event: None,
            stats: Stats::default(),
            jacobian: if matches!(options.method, Method::Rodas4 | Method::Ros34Pw2) {
                mechanism.system.state_jacobian_work()
            } else {
                None
            },
            frozen_dtmax,
            options: options.clone(),
            mechanism,
        };
        sim.begin().map_err(|e| sim.stopped(e, options.start))?;
        Ok(sim)
    }

    /// Puts the simulator at its start: the start state with prescribed
    /// coordinates where their signals are, the initial event iteration,
    /// and the Euler-angle joints' sides.
    fn begin(&mut self) -> Result<(), StepError> {
        self.t = self.options.start;
        self.y.copy_from_slice(&self.y0);
        // Prescribed positions and speeds start where their signals are.
        self.mechanism.impose_drives(&mut self.ws, self.t, &mut self.y);
        self.ws.discrete.copy_from_slice(&self.mechanism.system.events.discrete_start);
        self.refuse_start_past_stops()?;
        // Assembly started the state on the constraints already. What
        // `initial()` decides settles first; then the model goes on from
        // there as at any event (Modelica's first stored values).
        self.ws.initial = true;
        let settled = self.event_iteration(false);
        self.ws.initial = false;
        settled?;
        self.event_iteration(false)?;
        self.start_impact()?;
        self.charts = self.watch_charts();
        // A start near the singular configuration moves to a chart at once.
        self.switch_charts()?;
        self.recorder.hold = false;
        self.recorder.next = 0;
        self.recorder.past_stop = false;
        self.started = false;
        self.input_changed = false;
        self.ahead = false;
        self.piled = (0, f64::NEG_INFINITY);
        Ok(())
    }

    /// Speeds that the constraints holding at the start do not allow (a
    /// one-way clutch started with its load lagging, so locked at once)
    /// change at the start as in a plastic impact, which keeps the
    /// momentum (they were averaged at the end of the first step); a note
    /// says which speeds changed.
    fn start_impact(&mut self) -> Result<(), StepError> {
        let before = self.y.clone();
        if !self.mechanism.system.project(&mut self.ws, self.t, &mut self.y, true)? {
            return Ok(());
        }
        let names = &self.mechanism.system.states.names;
        let moved: Vec<String> = (0..self.y.len())
            .filter(|&i| (self.y[i] - before[i]).abs() > 1e-9 * (1.0 + before[i].abs()))
            .map(|i| format!("{} {} -> {}", names[i], before[i], self.y[i]))
            .collect();
        if !moved.is_empty() {
            self.notes.push(format!(
                "the start state does not meet the constraints that hold at the start (a friction element or \
                 clutch locked there, a loop): it was moved onto them at once, as by a plastic impact that keeps \
                 the momentum: {}",
                moved.join(", ")
            ));
        }
        Ok(())
    }

    /// A mass that starts past one of its hard stops would be put on it
    /// by the first event without a word (a start value lost): refused.
    fn refuse_start_past_stops(&mut self) -> Result<(), StepError> {
        let system = &self.mechanism.system;
        let stops: Vec<usize> = system.frictions.iter().filter_map(|f| f.stop_indicator).collect();
        if stops.is_empty() {
            return Ok(());
        }
        let mut dy = vec![0.0; self.y.len()];
        self.mechanism.rhs(&mut self.ws, self.t, &self.y, &mut dy)?;
        for slot in stops.into_iter().flat_map(|s| [s, s + 1]) {
            // The indicator is how far past the stop the mass stands.
            let past = self.ws.indicators[slot];
            if past > 1e-9 {
                return Err(StepError::Caller(format!(
                    "the start is {past:.6} past {}: a mass between hard stops must start between them (the \
                     stop would move it there at once and its start value would be lost); give it a start \
                     value inside",
                    self.indicator_name(slot)
                )));
            }
        }
        Ok(())
    }

    /// What a linearization starts from: the mechanism, the workspace that
    /// holds the inputs and modes, the time and the state reached.
    pub(crate) fn point(&self) -> (&Mechanism, &Workspace, f64, &[f64]) {
        (&self.mechanism, &self.ws, self.t, &self.y)
    }

    /// The time reached.
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The samples [`Simulator::step_until`] would record on the way to
    /// `t` (the output grid's points after the time reached), and the
    /// values each holds (time included); `None` where every step is
    /// recorded (`saveat = 0`, a count not known in advance). For a host
    /// to refuse a call its memory cannot hold before it starts.
    pub fn samples_until(&self, t: f64) -> Option<(f64, usize)> {
        let saveat = self.options.saveat;
        if self.recorder.off || saveat <= 0.0 {
            return None;
        }
        Some((((t - self.t) / saveat).ceil().max(0.0), self.recorded.width() + 1))
    }

    /// The state reached, in the order of [`Simulator::state_names`]. A
    /// body whose Euler angles came near their singular configuration is
    /// integrated in a chart from then on (a note says so): its states
    /// `phi`, `phid` (and a free body's `r_0`, `v_0`) hold the chart's
    /// coordinates, which [`Simulator::set_state`] takes back; its outputs
    /// (`phi`, `phid`, `r_0`, ...) stay the library's.
    pub fn state(&self) -> &[f64] {
        &self.y
    }

    /// The names of the states.
    pub fn state_names(&self) -> &[String] {
        &self.mechanism.system.states.names
    }

    /// Sets the whole state; the integrator starts again from it.
    pub fn set_state(&mut self, y: &[f64]) -> Result<(), String> {
        if y.len() != self.y.len() {
            return Err(format!("the state has {} values, not {}", self.y.len(), y.len()));
        }
        if let Some(k) = y.iter().position(|x| !x.is_finite()) {
            return Err(format!("the value of `{}` is not finite ({})", self.state_names()[k], y[k]));
        }
        self.y.copy_from_slice(y);
        self.started = false;
        self.input_changed = false;
        // The Euler-angle joints watch from the new state (in the
        // coordinates they are integrated in).
        self.switch_charts().map_err(|e| self.stopped(e, self.t).reason)
    }

    /// Sets one state by its name (`rev.phi`, `body.v_0[2]`).
    pub fn set_state_value(&mut self, name: &str, value: f64) -> Result<(), String> {
        let k = self.state_index(name)?;
        let mut y = self.y.clone();
        y[k] = value;
        self.set_state(&y)
    }

    /// A state's value by its name.
    pub fn state_value(&self, name: &str) -> Result<f64, String> {
        Ok(self.y[self.state_index(name)?])
    }

    fn state_index(&self, name: &str) -> Result<usize, String> {
        let names = self.state_names();
        names.iter().position(|n| n == name).ok_or_else(|| {
            let hint = did_you_mean(name, names.iter().map(String::as_str));
            format!("`{name}` is not a state of the model{hint} (its states: {})", names.join(", "))
        })
    }

    /// The names of the model's inputs.
    pub fn input_names(&self) -> Vec<&str> {
        self.mechanism.input_names()
    }

    /// The value an input holds now.
    pub fn input(&self, name: &str) -> Result<f64, String> {
        let k = self.input_index(name)?;
        Ok(self.ws.inputs[k])
    }

    fn input_index(&self, name: &str) -> Result<usize, String> {
        // Without collecting the names: a controller calls this every step.
        if let Some(k) = self.mechanism.system.events.inputs.iter().position(|(n, _)| n == name) {
            return Ok(k);
        }
        let names = self.mechanism.input_names();
        names.iter().position(|n| *n == name).ok_or_else(|| {
            if names.is_empty() {
                format!("the model has no inputs, so not `{name}`: declare one as a RealInput of the model")
            } else {
                let hint = did_you_mean(name, names.iter().copied());
                format!("`{name}` is not an input of the model{hint} (its inputs: {})", names.join(", "))
            }
        })
    }

    /// The names of the model's outputs.
    pub fn output_names(&self) -> &[String] {
        self.mechanism.output_names()
    }

    /// The model's outputs at the time and state reached, by name.
    pub fn outputs(&mut self) -> Result<Vec<(String, f64)>, String> {
        let names = self.mechanism.output_names().to_vec();
        let values = self.values(&names)?;
        Ok(names.into_iter().zip(values).collect())
    }

    /// Sets an input; it holds this value until set again.
    pub fn set_input(&mut self, name: &str, value: f64) -> Result<(), String> {
        let k = self.input_index(name)?;
        if !value.is_finite() {
            return Err(format!("the input `{name}` must be finite, not {value}"));
        }
        if self.ws.inputs[k] != value {
            self.ws.inputs[k] = value;
            self.recorder.ws.inputs[k] = value;
            // The derivative the integrator carries is stale.
            if self.started {
                self.input_changed = true;
            }
            self.started = false;
        }
        Ok(())
    }

    /// The value of any variable of the model (a column of the results)
    /// at the time and state reached.
    pub fn value(&mut self, name: &str) -> Result<f64, String> {
        Ok(self.values(&[name])?[0])
    }

    /// The values of several variables at once (one evaluation).
    pub fn values<S: AsRef<str>>(&mut self, names: &[S]) -> Result<Vec<f64>, String> {
        let table = self.mechanism.signal_table().clone();
        let mut columns = Vec::with_capacity(names.len());
        for name in names {
            let name = name.as_ref();
            let Some(k) = table.index(name) else {
                let hint = did_you_mean(name, table.names().iter().map(String::as_str));
                return Err(format!("the model has no variable `{name}`{hint}"));
            };
            columns.push(k);
        }
        let mut values = vec![0.0; columns.len()];
        self.signal_values(&columns, &mut values)?;
        Ok(values)
    }

    /// The values of the signals at `columns` (positions among
    /// [`Simulator::signal_names`]) at the time and state reached, into
    /// `out`: only the components that own them are evaluated.
    pub fn signal_values(&mut self, columns: &[usize], out: &mut [f64]) -> Result<(), String> {
        let table = self.mechanism.signal_table().clone();
        let width = table.names().len();
        if let Some(&k) = columns.iter().find(|&&k| k >= width) {
            return Err(format!("the model has {width} signals, so none at position {k}"));
        }
        let r = &mut self.recorder;
        r.wanted_now.clear();
        r.wanted_now.resize(self.mechanism.components.len(), false);
        for owner in columns.iter().filter_map(|&k| table.owner(k)) {
            r.wanted_now[owner] = true;
        }
        self.mechanism
            .outputs_into(&mut r.ws, &mut r.scratch, self.t, &self.y, &mut r.row, Some(&r.wanted_now))
            .map_err(|e| self.mechanism.describe(&e))?;
        for (o, &k) in out.iter_mut().zip(columns) {
            *o = r.row[k];
        }
        Ok(())
    }

    /// The samples recorded so far on the output grid (every `saveat`
    /// from `start`; at the end of each step with `saveat = 0`).
    pub fn solution(&self) -> &Solution {
        self.columns.get_or_init(|| {
            let mut solution = Solution::with_signals(self.mechanism.signal_table().clone());
            self.recorded.append_to(&mut solution, 0);
            solution.set_warnings(self.notes.clone());
            solution
        })
    }

    /// The names of the signals recorded (the columns of
    /// [`Simulator::solution`], the values of a row of [`Simulator::recorded`]).
    pub fn signal_names(&self) -> &[String] {
        self.mechanism.signal_table().names()
    }

    /// The position of a signal among [`Simulator::signal_names`].
    pub fn signal_index(&self, name: &str) -> Option<usize> {
        self.mechanism.signal_table().index(name)
    }

    /// What the run found worth a note so far (each said once), as
    /// [`Solution::warnings`] gives them.
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// The samples recorded so far, row by row (as [`Simulator::solution`]
    /// has them, without making columns).
    pub fn recorded(&self) -> &Rows {
        &self.recorded
    }

    /// Takes the samples recorded so far, leaving none.
    pub fn take_solution(&mut self) -> Solution {
        self.solution();
        let solution = self.columns.take().expect("made just now");
        self.recorded.clear();
        solution
    }

    /// How many events were handled (time events and state events).
    pub fn event_count(&self) -> usize {
        self.events
    }

    /// When the last event was, and what the indicator that made it
    /// watches (`None` for a source's switching time).
    pub fn last_event(&self) -> Option<(f64, Option<String>)> {
        self.last_event.map(|(t, k)| (t, k.map(|k| self.indicator_name(k))))
    }

    /// The name of indicator `k`: one of the model's, or past them, an
    /// Euler-angle joint's distance from its singular configuration.
    fn indicator_name(&self, k: usize) -> String {
        let names = &self.mechanism.system.events.indicators;
        match names.get(k) {
            Some(name) => name.clone(),
            None => match self.charts.get(k - names.len()) {
                Some(c) => format!("{} near its singular configuration", self.mechanism.system.states.names[c.at]),
                None => format!("indicator {k}"),
            },
        }
    }

    /// The name of the component whose states move link `link`.
    fn component_of(&self, link: usize) -> &str {
        &self.mechanism.components[self.mechanism.system.links[link].states_of].name
    }

    /// The names of the states of link `link`'s joint, a vector's once
    /// (`wheel.x`, `wheel.angles`, ...): the note on a chart names them as
    /// the component does (a Body's `phi`, a wheel's `angles`).
    fn joint_states(&self, link: usize) -> String {
        let system = &self.mechanism.system;
        let l = &system.links[link];
        let (nq, nv) = (l.joint.nq(), l.joint.nv());
        let at = (l.q_offset..l.q_offset + nq).chain(system.states.nq + l.v_offset..system.states.nq + l.v_offset + nv);
        let mut names: Vec<&str> = Vec::new();
        for k in at {
            let name = system.states.names[k].as_str();
            let base = name.split_once('[').map_or(name, |(base, _)| base);
            if !names.contains(&base) {
                names.push(base);
            }
        }
        names.iter().map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ")
    }

    /// Watches on the Euler-angle joints, each with the safe interval of
    /// its middle angle where it stands.
    fn watch_charts(&self) -> Vec<ChartWatch> {
        let mut charts = Vec::new();
        for (link, l) in self.mechanism.system.links.iter().enumerate().skip(1) {
            if let Some((offset, RotationCoordinates::Euler { sequence })) = l.joint.rotation_coordinates() {
                let at = l.q_offset + offset + 1;
                let (lo, hi) = chart::safe_interval(sequence, self.y[at]);
                charts.push(ChartWatch { link, at, sequence, lo, hi, inverted: l.inverted, noted: false });
            }
        }
        charts
    }

    /// Moves every Euler-angle joint whose middle angle is within the band
    /// of a singular value to a chart (see [`crate::dynamics::chart`]),
    /// saying so once per joint, and takes the safe intervals from where
    /// the angles stand. A joint traversed from its frame_b stops the run
    /// there.
    fn switch_charts(&mut self) -> Result<(), StepError> {
        for k in 0..self.charts.len() {
            // The safe interval where the angle stands: it leaves the angle
            // out only within the band of a singular value.
            let c = &mut self.charts[k];
            (c.lo, c.hi) = chart::safe_interval(c.sequence, self.y[c.at]);
            if !c.crossed(&self.y) {
                continue;
            }
            let ChartWatch { link, sequence, inverted, noted, .. } = self.charts[k];
            if inverted {
                return Err(StepError::Dynamics(DynamicsError::EulerSingularity { link, time: self.t }));
            }
            self.move_to_chart(link, sequence);
            if !noted {
                self.charts[k].noted = true;
                let note = format!(
                    "`{}` came near the singular configuration of its Euler angles (sequence {sequence:?}, the \
                     first and third axes lining up) at t = {:.6} s: the run went on with its orientation \
                     integrated in an internal chart (the same sequence from a turned base), and its angles and \
                     their rates are still reported from its orientation. From then on the states {} hold the \
                     chart's coordinates",
                    self.component_of(link),
                    self.t,
                    self.joint_states(link)
                );
                self.notes.push(note);
                if let Some(solution) = self.columns.get_mut() {
                    solution.set_warnings(self.notes.clone());
                }
            }
        }
        for c in &mut self.charts {
            (c.lo, c.hi) = chart::safe_interval(c.sequence, self.y[c.at]);
        }
        Ok(())
    }

    /// Moves the Euler-angle joint of `link` to a chart started at its
    /// present orientation: the new base goes into the joint's parent-side
    /// transform, and the state into the chart's coordinates.
    fn move_to_chart(&mut self, link: usize, sequence: [usize; 3]) {
        if let Shared::Borrowed(m) = self.mechanism {
            self.mechanism = Shared::Owned(Arc::new(m.clone()));
        }
        let Shared::Owned(mechanism) = &mut self.mechanism else { unreachable!("owned just now") };
        let mechanism = Arc::make_mut(mechanism);
        let nq = mechanism.system.states.nq;
        let l = &mut mechanism.system.links[link];
        let offset = l.joint.rotation_coordinates().map_or(0, |(offset, _)| offset);
        let (qa, ua) = (l.q_offset + offset, nq + l.v_offset + offset);
        let y = &mut self.y;
        let v3 = |y: &[f64], i: usize| Vec3::new(y[i], y[i + 1], y[i + 2]);
        let (psi, psid) = (v3(y, qa), v3(y, ua));
        let old = l.chart.map_or(Mat3::identity(), |c| c.base);
        let r = axes_rotations(sequence, &psi) * old;
        let w = axes_rotations_rate_matrix(sequence, &psi) * psid;
        let (base, psi_new, psid_new) = chart::chart_at(sequence, &r, &w);
        let turn = base * old.transpose();
        if offset == 3 {
            // A free joint's position and velocity are resolved in its frame_a, which turns.
            for at in [l.q_offset, nq + l.v_offset] {
                let turned = turn * v3(y, at);
                y[at..at + 3].copy_from_slice(turned.as_slice());
            }
        }
        y[qa..qa + 3].copy_from_slice(psi_new.as_slice());
        y[ua..ua + 3].copy_from_slice(psid_new.as_slice());
        l.x_tree = Transform::new(turn * l.x_tree.rot, l.x_tree.trans);
        // The library's angles are where their branch continues from.
        let phi = l.chart.map_or(psi, |c| c.phi);
        l.chart = Some(EulerChart { base, phi });
        self.started = false;
    }

    /// Back to the start state, time, inputs and discrete state; the
    /// samples recorded are dropped.
    pub fn reset(&mut self) -> Result<(), String> {
        self.stats = self.stats();
        // Joints moved to charts go back to the library's coordinates.
        self.mechanism = self.original.clone();
        self.recorder.scratch = OutputScratch::default();
        self.stepper = Stepper::new(self.y.len(), &self.options);
        let inputs: Vec<f64> = self.mechanism.system.events.inputs.iter().map(|i| i.1).collect();
        self.ws.inputs.copy_from_slice(&inputs);
        self.recorder.ws.inputs.copy_from_slice(&inputs);
        self.recorded.clear();
        self.columns = OnceLock::new();
        self.notes.clear();
        self.indicators = Indicators::default();
        self.events = 0;
        self.last_event = None;
        self.begin().map_err(|e| self.stopped(e, self.options.start).reason)
    }

    /// Counts of the integrators' work since the simulator was made.
    pub fn stats(&self) -> Stats {
        let now = self.stepper.stats();
        Stats {
            accepted: self.stats.accepted + now.accepted,
            rejected: self.stats.rejected + now.rejected,
            evaluations: self.stats.evaluations + now.evaluations,
            error_sum: self.stats.error_sum + now.error_sum,
            stiff: self.stats.stiff.or(now.stiff),
        }
    }

    /// Integrates to exactly `t` (handling the events on the way),
    /// recording the grid points passed into [`Simulator::solution`]. On
    /// failure the simulator stays at the last good time, and what was
    /// recorded is kept.
    pub fn step_until(&mut self, t: f64) -> Result<(), Stopped> {
        self.step_until_with(t, None)
    }

    /// As [`step_until`](Self::step_until), calling `progress` with the
    /// time reached after every step: an error from it (Ctrl-C in a host)
    /// stops there with that reason, and the simulator can go on later.
    pub fn step_until_with(&mut self, t: f64, progress: Option<&mut Progress>) -> Result<(), Stopped> {
        let mut recorded = std::mem::take(&mut self.recorded);
        let result = self.run_to(t, &mut recorded, progress, true);
        self.recorded = recorded;
        if let Some(solution) = self.columns.get_mut() {
            let from = solution.len();
            self.recorded.append_to(solution, from);
            if solution.warnings().len() != self.notes.len() {
                solution.set_warnings(self.notes.clone());
            }
        }
        result
    }

    /// Integrates to exactly `target`, giving the samples of the output
    /// grid to `sink` and the time reached after every step to `progress`.
    pub fn run(
        &mut self,
        target: f64,
        sink: &mut dyn SampleSink,
        progress: Option<&mut Progress>,
    ) -> Result<(), Stopped> {
        self.run_to(target, sink, progress, false)
    }

    /// Whether the integration may step past the time asked for and read
    /// the state there on its dense output, so that calls of a few steps
    /// each cost no more steps than one call: with the adaptive explicit
    /// method and without state events or Euler-angle joints, which a step
    /// past the time asked for could find before the host has its say.
    fn may_look_ahead(&self) -> bool {
        self.stepper.ahead().is_some()
            && self.mechanism.system.events.indicators.is_empty()
            && self.charts.is_empty()
            && !self.recorder.hold
    }

    /// [`Simulator::run`], looking ahead when `look_ahead` and allowed.
    fn run_to(
        &mut self,
        target: f64,
        sink: &mut dyn SampleSink,
        mut progress: Option<&mut Progress>,
        look_ahead: bool,
    ) -> Result<(), Stopped> {
        let look_ahead = look_ahead && self.may_look_ahead() && !self.input_changed;
        if !target.is_finite() {
            return Err(self.stopped(StepError::Caller(format!("cannot step until t = {target}")), self.t));
        }
        if target < self.t {
            // Doing nothing here would leave a host believing it stood at `target`.
            let reason = format!(
                "the simulator stands at t = {}, after t = {target}: it steps forward only (reset() starts it again \
                 from the start)",
                self.t
            );
            return Err(self.stopped(StepError::Caller(reason), self.t));
        }
        if self.recorder.next == 0 && !self.recorder.off {
            let mut recorder = Recorder { mechanism: &self.mechanism, state: &mut self.recorder, sink, progress: None };
            let (t, y) = (self.t, self.y.clone());
            if let Err(e) = recorder.record(t, &y).and_then(|_| recorder.flush(t)) {
                return Err(self.stopped(e, t));
            }
            self.recorder.next = 1;
        }
        if self.ahead && !self.started {
            // An input or the state changed: the step ahead is void.
            self.ahead = false;
        }
        while self.t < target {
            if self.ahead {
                self.catch_up(target, sink).map_err(|e| self.stopped(e, self.t))?;
                continue;
            }
            let time_event = self.mechanism.next_time_event(self.t);
            let tf = target.min(time_event);
            // Up to the stop, the steps are those of one call to the stop
            // (the last cut short at it), so that stepping records what
            // `simulate` records.
            let end = if tf <= self.options.stop { time_event.min(self.options.stop) } else { time_event };
            let limit = if look_ahead && tf < end { end } else { tf };
            let reached = match self.advance(tf, limit, sink, progress.as_deref_mut()) {
                Err(stopped) if limit > tf && !stopped.by_caller && self.may_retry(&stopped, tf) => {
                    // A step past `tf` failed: go again from where the
                    // integration stood, with steps cut short at `tf`.
                    self.t = stopped.time;
                    self.y.copy_from_slice(self.stepper.state());
                    self.advance(tf, tf, sink, progress.as_deref_mut())
                }
                reached => reached,
            };
            match reached {
                Ok(Reached::End) if self.ahead => self.t = tf,
                Ok(Reached::End) => {
                    self.t = tf;
                    if tf == time_event {
                        self.ws.left_limit_at = f64::NAN;
                        self.last_event = Some((tf, None));
                        if let Err(e) = self.event() {
                            return Err(self.stopped(e, tf));
                        }
                    }
                }
                Ok(Reached::Event(te)) => {
                    self.t = te;
                    self.last_event = Some((te, self.indicators.last));
                    if let Err(e) = self.event() {
                        return Err(self.stopped(e, te));
                    }
                }
                Err(stop) => return Err(stop),
            }
        }
        // The last step is final: its samples go out.
        let mut recorder = Recorder { mechanism: &self.mechanism, state: &mut self.recorder, sink, progress: None };
        recorder.flush(f64::INFINITY).map_err(|e| self.stopped(e, self.t))
    }

    /// Whether a stretch that looked ahead and failed may go again from
    /// where the integration stood: it stood before `tf`, in a finite state.
    fn may_retry(&self, stopped: &Stopped, tf: f64) -> bool {
        stopped.time >= self.t && stopped.time < tf && self.stepper.state().iter().all(|x| x.is_finite())
    }

    /// With the integration standing past the time reached: the grid
    /// points of its last step up to `target`, and the time and state
    /// there (or at the step's end, if `target` is past it).
    fn catch_up(&mut self, target: f64, sink: &mut dyn SampleSink) -> Result<(), StepError> {
        let Simulator { mechanism, stepper, recorder, .. } = self;
        let step = stepper.ahead().expect("only a method with dense output looks ahead");
        let (_, end) = step.span();
        recorder.until = target;
        let mut recorder = Recorder { mechanism, state: recorder, sink, progress: None };
        let recorded = recorder.observe(step);
        self.recorder.until = f64::INFINITY;
        recorded?;
        if target < end {
            step.interpolate(target, &mut self.y);
            self.t = target;
        } else {
            self.y.copy_from_slice(step.y());
            self.t = end;
            self.ahead = false;
        }
        Ok(())
    }

    /// One stretch of integration to `tf` (a target or a time event), or to
    /// the first state event before it; with `limit > tf`, its last step may
    /// end past `tf` (up to `limit`), and the state at `tf` is read on it.
    fn advance<'q>(
        &mut self,
        tf: f64,
        limit: f64,
        sink: &mut dyn SampleSink,
        progress: Option<&mut Progress<'q>>,
    ) -> Result<Reached, Stopped> {
        let Simulator { mechanism, stepper, ws, indicators, charts, recorder, jacobian, .. } = self;
        let mechanism: &Mechanism = mechanism;
        let time_event = mechanism.next_time_event(self.t) == tf;
        // Up to a time event the sources show their values before it.
        ws.left_limit_at = if time_event { tf } else { f64::NAN };
        let mut system = Dynamics { mechanism, ws, jacobian: jacobian.as_mut(), charts, indicators };
        let horizon = (self.options.stop - self.options.start).max(tf - self.t);
        if !self.started {
            let frozen =
                system.mechanism.system.states.start.is_empty() || system.mechanism.system.friction_holds(system.ws);
            let dtmax = match self.frozen_dtmax {
                Some(bound) if frozen => bound,
                // Sliding: no bound, but a bound all the same (of any
                // size), so that the first step after a break-away starts
                // at a step the time resolves (see `initial_step`).
                Some(_) if self.options.dtmax == 0.0 => f64::MAX,
                _ => self.options.dtmax,
            };
            stepper.set_dtmax(match system.indicators.bound {
                Some(bound) if dtmax == 0.0 || bound < dtmax => bound,
                _ => dtmax,
            });
            let started = if self.input_changed {
                stepper.restart(&mut system, self.t, &self.y, horizon)
            } else {
                stepper.start(&mut system, self.t, &self.y, horizon)
            };
            self.input_changed = false;
            if let Err(stop) = started {
                system.ws.left_limit_at = f64::NAN;
                return Err(self.stop_integration(stop));
            }
            self.started = true;
        }
        recorder.until = if limit > tf { tf } else { f64::INFINITY };
        let mut recorder = Recorder { mechanism, state: recorder, sink, progress };
        let result = stepper.advance_past(&mut system, tf, limit, &mut |s| recorder.observe(s));
        recorder.state.until = f64::INFINITY;
        system.ws.left_limit_at = f64::NAN;
        if let Err(stop) = &result {
            // The samples of the last step up to the failure are good.
            let t = failure_time(stop);
            if let Err(e) = recorder.flush(t) {
                return Err(self.stopped(e, t));
            }
        }
        match result {
            Ok(reached) => {
                match self.stepper.ahead().filter(|s| s.span().1 > tf) {
                    Some(step) if reached == Reached::End => {
                        step.interpolate(tf, &mut self.y);
                        self.ahead = true;
                    }
                    _ => self.y.copy_from_slice(self.stepper.state()),
                }
                if let Reached::Event(_) = reached {
                    self.started = false;
                }
                Ok(reached)
            }
            Err(stop) => {
                // The host stopped the run after an accepted step (Ctrl-C):
                // the simulator stands there, and goes on from there.
                if matches!(&stop.failure, Failure::Observer(StepError::Caller(_))) {
                    self.y.copy_from_slice(self.stepper.state());
                    self.t = failure_time(&stop);
                    self.ahead = false;
                }
                Err(self.stop_integration(stop))
            }
        }
    }

    /// The report of a failed stretch of integration, with the samples up
    /// to the failure given out.
    fn stop_integration(&mut self, stop: Stop<StepError>) -> Stopped {
        let t = failure_time(&stop);
        let failure = stop.failure;
        self.started = false;
        let reason = match failure {
            Failure::Rhs(e) | Failure::Observer(e) => return self.stopped(e, t),
            Failure::StepTooSmall { h, attempt } => match self.last_event {
                // Steps that collapse right after a state event: the events
                // pile up. (After a time event, a source's switch or a
                // sample, the steps collapse for a reason of their own.)
                Some((te, Some(k))) if t - te <= 1e-6 * t.abs().max(1.0) => self.piling_up(Some(k), t - te),
                _ => {
                    let y = self.stepper.state().to_vec();
                    self.mechanism.step_too_small(h, &self.options, &mut self.ws, t, &y, &attempt)
                }
            },
            Failure::NotFinite => self.mechanism.describe(&DynamicsError::NotFinite),
        };
        Stopped { time: t, reason, by_caller: false }
    }

    /// The report of an error at time `t`.
    fn stopped(&self, e: StepError, t: f64) -> Stopped {
        match e {
            StepError::Dynamics(e) => Stopped { time: t, reason: self.mechanism.describe(&e), by_caller: false },
            StepError::Caller(reason) => Stopped { time: t, reason, by_caller: true },
            StepError::Events(reason) => Stopped { time: t, reason, by_caller: false },
        }
    }

    /// Handles an event at the time reached: the event iteration, the state
    /// back onto the constraints, the indicators' new signs; the integrator
    /// starts again.
    fn event(&mut self) -> Result<(), StepError> {
        self.events += 1;
        let t = self.t;
        if t - self.piled.1 <= ZENO_SPAN * t.abs().max(1.0) {
            self.piled.0 += 1;
            if self.piled.0 >= ZENO_EVENTS {
                return Err(StepError::Events(self.piling_up(self.indicators.last, t - self.piled.1)));
            }
        } else {
            self.piled = (1, t);
        }
        self.event_iteration(true)?;
        self.switch_charts()?;
        self.started = false;
        if let Some((k, t0)) = self.indicators.untold.take() {
            let note = format!(
                "{} changed sign and back within one step from t = {t0:.6} s (its ends agreed): the crossings \
                 were found on the step's dense output, and the steps are held to {:.3e} s from then on so that \
                 each is met in turn",
                self.indicator_name(k),
                self.indicators.bound.unwrap_or(f64::NAN)
            );
            self.notes.push(note);
            if let Some(solution) = self.columns.get_mut() {
                solution.set_warnings(self.notes.clone());
            }
        }
        Ok(())
    }

    /// Why a run stopped where events pile up (the last made by indicator
    /// `k`, `span` seconds before).
    fn piling_up(&self, k: Option<usize>, span: f64) -> String {
        // A time event: a `sample` whose interval the time cannot resolve
        // here says so; else a source's switching time.
        let t = self.t;
        let resolution = 4.0 * f64::EPSILON * t.abs().max(1.0);
        let samples = &self.mechanism.system.equations.samples;
        if let (None, Some(sample)) = (k, samples.iter().find(|s| s.interval <= 1e3 * resolution)) {
            let short =
                |x: f64| if x == 0.0 || (1e-4..1e6).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") };
            return format!(
                "the events pile up ({} events so far) at `sample({}, {})`: its instants come every {} s, closer \
                 than the time of this run can be told apart (about {resolution:.1e} s); give `sample` an interval \
                 many times larger",
                self.events,
                short(sample.start),
                short(sample.interval),
                short(sample.interval)
            );
        }
        let which = k.map_or("a source's switching time".to_string(), |k| self.indicator_name(k));
        format!(
            "the events pile up ({} events so far, the last {span:.1e} s before, at {which}): a bounce that loses \
             energy geometrically, or a condition that switches back and forth. Stop it with a condition that \
             ends it (a rest threshold), or smooth the switch",
            self.events
        )
    }

    /// Evaluates the dynamics at the time and state reached with relations
    /// as they are, until no discrete value changes (applying `reinit`s);
    /// then moves the state onto the constraints (at the start, only where
    /// a `reinit` moved it) and, where that moved it, reads the relations
    /// again there: a relation at its crossing (two pistons turning at the
    /// same instant, one of them found by the other's event) may lie on
    /// either side before and after, and a mode taken on one side with the
    /// indicator's sign taken on the other would never be met again. The
    /// indicators' signs are taken from the final state.
    fn event_iteration(&mut self, project: bool) -> Result<(), StepError> {
        let n = self.y.len();
        self.indicators.dy.resize(n, 0.0);
        self.indicators.y.resize(n, 0.0);
        let events = &self.mechanism.system.events;
        let (discrete, relations) = (!events.discrete_start.is_empty(), !events.indicators.is_empty());
        let mut project = project;
        for _ in 0..EVENT_PROJECTIONS {
            let reinitialized = if discrete || relations { self.settle_discrete()? } else { false };
            if !(project || reinitialized) {
                break;
            }
            project = false;
            let moved = self.mechanism.system.project(&mut self.ws, self.t, &mut self.y, true)?;
            if !moved || !discrete {
                break;
            }
        }
        if relations {
            let ind = &mut self.indicators;
            self.mechanism.rhs(&mut self.ws, self.t, &self.y, &mut ind.dy)?;
            ind.above.clear();
            ind.above.extend(self.ws.indicators.iter().map(|&g| g > 0.0));
            (ind.inside, ind.since) = (None, self.t);
        }
        Ok(())
    }

    /// The event iteration proper: evaluations with relations as they are
    /// at the time and state reached, until no discrete value changes.
    /// Returns whether a `reinit` moved the state.
    fn settle_discrete(&mut self) -> Result<bool, StepError> {
        let mechanism = &*self.mechanism;
        let t = self.t;
        let dy = &mut self.indicators.dy;
        let mut reinitialized = false;
        self.ws.at_event = true;
        let mut settled = false;
        for _ in 0..EVENT_ITERATIONS {
            self.ws.discrete_pre.copy_from_slice(&self.ws.discrete);
            self.ws.reinits.clear();
            let evaluated = mechanism.rhs(&mut self.ws, t, &self.y, dy);
            if let Err(e) = evaluated {
                self.ws.at_event = false;
                return Err(e.into());
            }
            for &(k, value) in &self.ws.reinits {
                if !value.is_finite() {
                    self.ws.at_event = false;
                    let name = mechanism.system.states.names.get(k).map_or("?", String::as_str);
                    return Err(StepError::Events(format!(
                        "a `reinit` of `{name}` at t = {t} gives it {value}: the expression it is given is not \
                         finite there (0/0, a division by zero, a root of a negative number); check it"
                    )));
                }
                self.y[k] = value;
                reinitialized = true;
            }
            if self.ws.discrete == self.ws.discrete_pre && self.ws.reinits.is_empty() {
                settled = true;
                break;
            }
        }
        self.ws.at_event = false;
        if !settled {
            let names = &mechanism.system.events.indicators;
            let changing: Vec<&str> = (0..self.ws.discrete.len())
                .filter(|&k| self.ws.discrete[k] != self.ws.discrete_pre[k])
                .filter_map(|k| names.get(k).map(String::as_str))
                .collect();
            return Err(StepError::Events(format!(
                "the event iteration at t = {t} does not settle after {EVENT_ITERATIONS} passes: the modes keep \
                 changing ({}). The conditions contradict each other at this instant",
                if changing.is_empty() { "reinit".to_string() } else { changing.join(", ") }
            )));
        }
        self.recorder.ws.discrete.copy_from_slice(&self.ws.discrete);
        Ok(reinitialized)
    }

    /// The warnings and counts of a run that reached its end.
    pub(crate) fn report(&self) -> RunReport {
        let stats = self.stats();
        let mut warnings = self.notes.clone();
        warnings.extend(self.mechanism.doubts(&stats, &self.options));
        RunReport { stats, warnings }
    }
}

/// When a failed integration stopped: a singularity inside the last step
/// stops at its own time, whether the step's check or its outputs found it.
fn failure_time(stop: &Stop<StepError>) -> f64 {
    match stop.failure {
        Failure::Rhs(StepError::Dynamics(DynamicsError::EulerSingularity { time, .. }))
        | Failure::Observer(StepError::Dynamics(DynamicsError::EulerSingularity { time, .. }))
            if time.is_finite() && time <= stop.t =>
        {
            time
        }
        _ => stop.t,
    }
}

/// `; did you mean `x`?` for the candidate nearest `name`, if one is near.
pub(crate) fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    crate::error::closest(name, candidates).first().map_or(String::new(), |c| format!("; did you mean `{c}`?"))
}
