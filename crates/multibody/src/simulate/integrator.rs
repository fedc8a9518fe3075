//! What the integrators share: the system they integrate, the step they
//! report to an observer, and how they fail.

/// An ODE `dy/dt = f(t, y)` whose evaluation can fail.
pub trait OdeSystem {
    type Error;
    fn dim(&self) -> usize;
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Self::Error>;

    /// `df/dy` at `(t, y)` into `jac` (row-major, `dim` x `dim`) where the
    /// system has it without differences of the whole right-hand side;
    /// `false` leaves them to the integrator.
    fn jacobian(&mut self, _t: f64, _y: &[f64], _jac: &mut [f64]) -> Result<bool, Self::Error> {
        Ok(false)
    }

    /// Called after every accepted step (after the observer saw it), with
    /// the step's dense output: may move the end state `y` (onto
    /// constraints) and returns whether it did, or stops the integration.
    fn accept(&mut self, _step: &dyn DenseStep, _y: &mut [f64]) -> Result<bool, Self::Error> {
        Ok(false)
    }

    /// Called after every accepted step, before the observer sees it: the
    /// time of the first event inside the step (an indicator changing
    /// sign), if any; the step then ends there. `end_evaluated` says that
    /// the integrator's last evaluation was at the step's end state.
    fn locate(&mut self, _step: &dyn DenseStep, _end_evaluated: bool) -> Result<Option<f64>, Self::Error> {
        Ok(None)
    }
}

/// How far [`advance`](super::dopri5::DormandPrince::advance) went.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reached {
    /// The time asked for.
    End,
    /// An event at this time, inside a step: the state there is the
    /// integrator's, and it must start again from there.
    Event(f64),
}

/// Sees every accepted step; an error stops the integration.
pub type Observer<'a, E> = dyn FnMut(&dyn DenseStep) -> Result<(), E> + 'a;

/// An integrator's end state, its derivative there and its counts.
pub(crate) type Ends<D> = fn(&mut D) -> (&mut Vec<f64>, &mut Vec<f64>, &mut Stats);

/// An accepted step cut short at an event: the observer sees it end there.
struct Truncated<'a> {
    step: &'a dyn DenseStep,
    end: f64,
    y: &'a [f64],
}

impl DenseStep for Truncated<'_> {
    fn span(&self) -> (f64, f64) {
        (self.step.span().0, self.end)
    }
    fn y(&self) -> &[f64] {
        self.y
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        self.step.interpolate(t, out)
    }
}

/// A solution between two accepted steps, as an observer sees it.
pub trait DenseStep {
    /// Start and end time of the step.
    fn span(&self) -> (f64, f64);
    /// The state at the end of the step.
    fn y(&self) -> &[f64];
    /// The state at `t` within the step.
    fn interpolate(&self, t: f64, out: &mut [f64]);
}

/// Counts of the work an integration did, and what it saw on the way.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stats {
    pub accepted: usize,
    pub rejected: usize,
    pub evaluations: usize,
    /// The sum over accepted steps of their error estimates, in units of
    /// the tolerance (each at most 1): a rough bound on how the errors of
    /// single steps add up.
    pub error_sum: f64,
    /// Where an explicit method first found its steps bounded by
    /// stability rather than accuracy.
    pub stiff: Option<StiffStretch>,
}

/// A stretch where the steps of an explicit method were bounded by
/// stability: the dynamics have a fast decaying mode, `h * |lambda|` at
/// the edge of the method's stability region.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StiffStretch {
    /// When it was detected.
    pub time: f64,
    /// The step size then.
    pub h: f64,
    /// The estimated rate of the fast mode, `|lambda|` [1/s].
    pub rate: f64,
    /// The state that moves most in that mode (index into the state vector).
    pub state: usize,
}

/// Why an integration stopped early.
#[derive(Debug)]
pub enum Failure<E> {
    /// The right-hand side failed.
    Rhs(E),
    /// The observer asked to stop.
    Observer(E),
    /// The step size fell below what the floating-point time can resolve;
    /// `attempt` is the end state of the last step tried.
    StepTooSmall { h: f64, attempt: Vec<f64> },
    /// The state became infinite or NaN.
    NotFinite,
}

/// A failure and the time of the last accepted step before it.
#[derive(Debug)]
pub struct Stopped<E> {
    pub t: f64,
    pub failure: Failure<E>,
    pub stats: Stats,
}

/// What every integrator does with a step it has accepted, ending at
/// `t_end`: check that the state is finite, let the system locate events
/// inside it (the step then ends at the first, with the state there),
/// show the step to the observer, let the system move the end state (onto
/// constraints), and evaluate the derivative there again when it moved.
/// `ends` gives the integrator's end state, its derivative at the end
/// (carried into the next step) and its counts. Returns the event's time.
pub(crate) fn finish_step<S: OdeSystem, D: DenseStep>(
    sys: &mut S,
    step: &mut D,
    t_end: f64,
    ends: Ends<D>,
    observe: &mut Observer<S::Error>,
    end_evaluated: bool,
) -> Result<Option<f64>, Stopped<S::Error>> {
    let stopped = |t, failure, stats: &mut Stats| Stopped { t, failure, stats: *stats };
    if step.y().iter().any(|x| !x.is_finite()) {
        let t0 = step.span().0;
        return Err(stopped(t0, Failure::NotFinite, ends(step).2));
    }
    let event = sys.locate(&*step, end_evaluated);
    match event {
        Err(e) => return Err(stopped(t_end, Failure::Rhs(e), ends(step).2)),
        Ok(Some(te)) => {
            let mut y = std::mem::take(ends(step).0);
            step.interpolate(te, &mut y);
            let seen = observe(&Truncated { step: &*step, end: te, y: &y });
            *ends(step).0 = y;
            seen.map_err(|e| stopped(te, Failure::Observer(e), ends(step).2))?;
            return Ok(Some(te));
        }
        Ok(None) => {}
    }
    if let Err(e) = observe(&*step) {
        return Err(stopped(t_end, Failure::Observer(e), ends(step).2));
    }
    // The end state moves out while the system looks at the step's dense output.
    let mut end = std::mem::take(ends(step).0);
    let moved = sys.accept(&*step, &mut end);
    *ends(step).0 = end;
    match moved {
        Err(e) => Err(stopped(t_end, Failure::Rhs(e), ends(step).2)),
        Ok(true) => {
            // The derivative carried over to the next step is stale.
            let (y, f, stats) = ends(step);
            stats.evaluations += 1;
            sys.rhs(t_end, y, f).map_err(|e| stopped(t_end, Failure::Rhs(e), stats))?;
            Ok(None)
        }
        Ok(false) => Ok(None),
    }
}

/// Hairer's starting step for an adaptive method whose error estimate
/// goes as `h^(1/exponent)`: an explicit Euler probe of the second
/// derivative from `(t, y)` with derivative `f`. `probe` and `f_probe` are
/// scratch of the state's size.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<S: OdeSystem>(
    sys: &mut S,
    t: f64,
    y: &[f64],
    f: &[f64],
    tol: &Tolerances,
    h_max: f64,
    exponent: f64,
    (probe, f_probe): (&mut [f64], &mut [f64]),
    stats: &mut Stats,
) -> Result<f64, S::Error> {
    let scale = |y: f64| tol.abstol + tol.reltol * y.abs();
    let (mut dnf, mut dny) = (0.0, 0.0);
    for (&yi, &fi) in y.iter().zip(f) {
        dnf += (fi / scale(yi)).powi(2);
        dny += (yi / scale(yi)).powi(2);
    }
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 { 1e-6 } else { (dny / dnf).sqrt() * 0.01 };
    h = h.min(h_max);
    for ((p, &yi), &fi) in probe.iter_mut().zip(y).zip(f) {
        *p = yi + h * fi;
    }
    sys.rhs(t + h, probe, f_probe)?;
    stats.evaluations += 1;
    let mut der2 = 0.0;
    for ((&f1, &f0), &yi) in f_probe.iter().zip(f).zip(y) {
        der2 += ((f1 - f0) / scale(yi)).powi(2);
    }
    let der2 = der2.sqrt() / h;
    let der12 = der2.abs().max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 { (h.abs() * 1e-3).max(1e-6) } else { (0.01 / der12).powf(exponent) };
    // Hairer's first guess goes as |y| / |y'|: a state just off zero (a
    // friction element's speed of 1e-15 after its break-away's second
    // event) gives a step the time cannot resolve, which stops the run
    // before the error control could grow it. Runs with a step bound (the
    // simulator sets one, of any size, for models with friction) start at least at a
    // resolvable step; unbounded runs keep Hairer's guess, whose collapse
    // is how events that pile up (a ball bouncing to rest) are noticed.
    let first = if tol.dtmax > 0.0 { (100.0 * h).max(1e3 * f64::EPSILON * t.abs()) } else { 100.0 * h };
    Ok(first.min(h1).min(h_max))
}

/// Settings of the adaptive integrators.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerances {
    pub abstol: f64,
    pub reltol: f64,
    /// Largest step; 0 for no limit.
    pub dtmax: f64,
}

/// Small systems with known solutions, for the integrators' tests.
#[cfg(test)]
pub(crate) mod test_systems {
    use super::{Failure, OdeSystem, Stopped};

    /// `y'' = -y` as `(y, y')`: `(sin t, cos t)` from `(0, 1)`.
    pub struct Oscillator;
    impl OdeSystem for Oscillator {
        type Error = ();
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
            dy[0] = y[1];
            dy[1] = -y[0];
            Ok(())
        }
    }

    /// `y' = 1`, whose evaluation fails after t = 2.5.
    pub struct FailsAfter;
    impl OdeSystem for FailsAfter {
        type Error = &'static str;
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), &'static str> {
            dy[0] = 1.0;
            if t > 2.5 {
                Err("past 2.5")
            } else {
                Ok(())
            }
        }
    }

    /// An integration of [`FailsAfter`] (with `dtmax = 0.1`) stopped with
    /// its error at the last step the observer saw, just before 2.5.
    pub fn assert_stopped_at_the_failure(stopped: Stopped<&'static str>, last_observed: f64) {
        assert!(matches!(stopped.failure, Failure::Rhs("past 2.5")));
        assert!(stopped.t <= 2.5 && stopped.t > 2.3, "stopped at {}", stopped.t);
        assert_eq!(stopped.t, last_observed);
    }
}
