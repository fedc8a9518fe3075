//! Dormand-Prince 5(4) with Hairer's step-size control (dopri5, PI control
//! with beta = 0.04) and 4th-order dense output (CONTD5).

use super::integrator::{
    finish_step, initial_step, DenseStep, Failure, Observer, OdeSystem, Reached, Stats, StiffStretch, Stopped,
    Tolerances,
};

const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

const SAFETY: f64 = 0.9;
const BETA: f64 = 0.04;
const FAC_MIN: f64 = 0.2; // smallest step ratio h_new / h
const FAC_MAX: f64 = 10.0; // largest step ratio
/// `h |lambda|` on the boundary of the method's stability region, along
/// the negative real axis (Hairer's dopri5 uses the same).
const STABILITY_EDGE: f64 = 3.25;
/// Accepted steps in a row at the stability edge that make a run stiff.
const STIFF_STEPS: usize = 15;
/// Steps away from the edge that clear the suspicion.
const NON_STIFF_STEPS: usize = 6;

/// The integrator's memory, allocated once per integration.
pub struct DormandPrince {
    pub(crate) tol: Tolerances,
    k: [Vec<f64>; 7],
    y: Vec<f64>,
    y_new: Vec<f64>,
    stage: Vec<f64>,
    /// Dense output coefficients of the last accepted step.
    cont: [Vec<f64>; 5],
    t_old: f64,
    h_old: f64,
    /// Where the integration stands, and the step it will try next.
    t: f64,
    h: f64,
    h_max: f64,
    /// The step-size controller's memory: the last accepted error, and
    /// whether the last try was rejected.
    fac_old: f64,
    rejected_last: bool,
    /// Steps in a row at (and away from) the stability edge.
    at_edge: usize,
    off_edge: usize,
    stats: Stats,
}

impl DenseStep for DormandPrince {
    fn span(&self) -> (f64, f64) {
        (self.t_old, self.t_old + self.h_old)
    }
    fn y(&self) -> &[f64] {
        &self.y
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let theta = (t - self.t_old) / self.h_old;
        let theta1 = 1.0 - theta;
        let [r0, r1, r2, r3, r4] = &self.cont;
        for i in 0..out.len() {
            out[i] = r0[i] + theta * (r1[i] + theta1 * (r2[i] + theta * (r3[i] + theta1 * r4[i])));
        }
    }
}

impl DormandPrince {
    pub fn new(n: usize, tol: Tolerances) -> Self {
        let v = || vec![0.0; n];
        Self {
            tol,
            k: [v(), v(), v(), v(), v(), v(), v()],
            y: v(),
            y_new: v(),
            stage: v(),
            cont: [v(), v(), v(), v(), v()],
            t_old: 0.0,
            h_old: 0.0,
            t: 0.0,
            h: 0.0,
            h_max: 0.0,
            fac_old: 1e-4,
            rejected_last: false,
            at_edge: 0,
            off_edge: 0,
            stats: Stats::default(),
        }
    }

    /// Integrates from `t0` to `tf` starting at `y0`, calling `observe`
    /// after every accepted step.
    #[cfg(test)]
    pub fn integrate<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t0: f64,
        tf: f64,
        y0: &[f64],
        mut observe: impl FnMut(&dyn DenseStep) -> Result<(), S::Error>,
    ) -> Result<Stats, Stopped<S::Error>> {
        self.start(sys, t0, y0, tf - t0)?;
        self.advance(sys, tf, &mut observe)?;
        Ok(self.stats)
    }

    /// Starts at `(t, y)` (or starts again there after an event): the
    /// derivative and a first step size. `horizon` is the length of the
    /// whole run, the largest step when `dtmax` is 0.
    pub fn start<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        horizon: f64,
    ) -> Result<(), Stopped<S::Error>> {
        self.y.copy_from_slice(y);
        self.t = t;
        let stop = |failure, stats| Err(Stopped { t, failure, stats });
        if let Err(e) = sys.rhs(t, &self.y, &mut self.k[0]) {
            return stop(Failure::Rhs(e), self.stats);
        }
        self.stats.evaluations += 1;
        self.h_max = if self.tol.dtmax > 0.0 { self.tol.dtmax } else { horizon.abs() };
        let [k1, k2, ..] = &mut self.k;
        let scratch = (&mut self.stage[..], &mut k2[..]);
        self.h = match initial_step(sys, t, &self.y, k1, &self.tol, self.h_max, 0.2, scratch, &mut self.stats) {
            Ok(h) => h,
            Err(e) => return stop(Failure::Rhs(e), self.stats),
        };
        self.fac_old = 1e-4;
        self.rejected_last = false;
        (self.at_edge, self.off_edge) = (0, 0);
        Ok(())
    }

    /// Starts again at `(t, y)` where the state goes on smoothly but its
    /// derivative may jump (an input of the host changed): the derivative
    /// anew, and as first step the one the integrator would have tried
    /// next, which the error control cuts if the jump needs it, rather than
    /// a new estimate. Never started yet, it is [`Self::start`].
    pub fn restart<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        horizon: f64,
    ) -> Result<(), Stopped<S::Error>> {
        if self.h.is_nan() || self.h <= 0.0 {
            return self.start(sys, t, y, horizon);
        }
        self.y.copy_from_slice(y);
        self.t = t;
        if let Err(e) = sys.rhs(t, &self.y, &mut self.k[0]) {
            return Err(Stopped { t, failure: Failure::Rhs(e), stats: self.stats });
        }
        self.stats.evaluations += 1;
        self.fac_old = 1e-4;
        self.rejected_last = false;
        Ok(())
    }

    /// Steps from the current time to exactly `tf`, calling `observe` after
    /// every accepted step, or to the first event the system locates
    /// inside a step; [`Self::start`] must follow an event.
    pub fn advance<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        tf: f64,
        observe: &mut Observer<S::Error>,
    ) -> Result<Reached, Stopped<S::Error>> {
        self.advance_past(sys, tf, tf, observe)
    }

    /// Steps until the time reached is at least `tf`, with steps as long as
    /// the error control allows up to `limit` (which the last step ends at
    /// exactly, when it reaches it): the caller reads the state at `tf` on
    /// the last step's dense output, and the integration may go on from
    /// where it stands without a step cut short at `tf`.
    pub fn advance_past<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        tf: f64,
        limit: f64,
        observe: &mut Observer<S::Error>,
    ) -> Result<Reached, Stopped<S::Error>> {
        let n = self.y.len();
        let stop = |t: f64, failure, stats| Err(Stopped { t, failure, stats });
        let mut h = self.h;
        while self.t < tf {
            let t = self.t;
            if 0.1 * h.abs() <= t.abs() * f64::EPSILON * 4.0 {
                return stop(t, Failure::StepTooSmall { h, attempt: self.y_new.clone() }, self.stats);
            }
            let last = t + 1.01 * h >= limit;
            if last {
                h = limit - t;
            }
            if let Err(e) = self.stages(sys, t, h, n) {
                return stop(t, Failure::Rhs(e), self.stats);
            }
            self.stats.evaluations += 6;
            let err = self.error_norm(h, n);
            if !err.is_finite() {
                // A step too large for the dynamics: try a much smaller one.
                self.stats.rejected += 1;
                h *= 0.1;
                self.rejected_last = true;
                continue;
            }
            let fac11 = err.powf(0.2 - BETA * 0.75);
            let fac = (fac11 / self.fac_old.powf(BETA) / SAFETY).clamp(1.0 / FAC_MAX, 1.0 / FAC_MIN);
            if err <= 1.0 {
                self.stats.accepted += 1;
                self.stats.error_sum += err;
                if self.stats.stiff.is_none() {
                    match self.stiff_mode(h, n) {
                        Some((h_lambda, state)) if h_lambda > STABILITY_EDGE => {
                            (self.at_edge, self.off_edge) = (self.at_edge + 1, 0);
                            if self.at_edge == STIFF_STEPS {
                                self.stats.stiff = Some(StiffStretch { time: t, h, rate: h_lambda / h, state });
                            }
                        }
                        _ => {
                            self.off_edge += 1;
                            if self.off_edge == NON_STIFF_STEPS {
                                self.at_edge = 0;
                            }
                        }
                    }
                }
                self.fac_old = err.max(1e-4);
                self.dense_coefficients(h, n);
                self.k.swap(0, 6);
                std::mem::swap(&mut self.y, &mut self.y_new);
                self.t_old = t;
                self.h_old = h;
                self.t = if last { limit } else { t + h };
                let mut h_new = (h / fac).min(self.h_max);
                if self.rejected_last {
                    h_new = h_new.min(h);
                }
                self.rejected_last = false;
                self.h = h_new;
                let end = finish_step(sys, self, self.t, |s| (&mut s.y, &mut s.k[0], &mut s.stats), observe, true)?;
                if let Some(te) = end {
                    self.t = te;
                    return Ok(Reached::Event(te));
                }
                h = self.h;
            } else {
                self.stats.rejected += 1;
                h /= (fac11 / SAFETY).min(1.0 / FAC_MIN);
                self.rejected_last = true;
            }
        }
        self.h = h;
        Ok(Reached::End)
    }

    /// The counts of the work done so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    fn stages<S: OdeSystem>(&mut self, sys: &mut S, t: f64, h: f64, n: usize) -> Result<(), S::Error> {
        let (y, s) = (&self.y, &mut self.stage);
        let [k1, k2, k3, k4, k5, k6, k7] = &mut self.k;
        for i in 0..n {
            s[i] = y[i] + h * A21 * k1[i];
        }
        sys.rhs(t + C2 * h, s, k2)?;
        for i in 0..n {
            s[i] = y[i] + h * (A31 * k1[i] + A32 * k2[i]);
        }
        sys.rhs(t + C3 * h, s, k3)?;
        for i in 0..n {
            s[i] = y[i] + h * (A41 * k1[i] + A42 * k2[i] + A43 * k3[i]);
        }
        sys.rhs(t + C4 * h, s, k4)?;
        for i in 0..n {
            s[i] = y[i] + h * (A51 * k1[i] + A52 * k2[i] + A53 * k3[i] + A54 * k4[i]);
        }
        sys.rhs(t + C5 * h, s, k5)?;
        for i in 0..n {
            s[i] = y[i] + h * (A61 * k1[i] + A62 * k2[i] + A63 * k3[i] + A64 * k4[i] + A65 * k5[i]);
        }
        sys.rhs(t + h, s, k6)?;
        let y_new = &mut self.y_new;
        for i in 0..n {
            y_new[i] = y[i] + h * (A71 * k1[i] + A73 * k3[i] + A74 * k4[i] + A75 * k5[i] + A76 * k6[i]);
        }
        sys.rhs(t + h, y_new, k7)
    }

    /// Hairer's estimate of `h |lambda|` for the dominant eigenvalue, from the
    /// last two stages (both at `t + h`): `h |k7 - k6| / |y_new - stage6|`,
    /// and the state that moves most in that mode.
    fn stiff_mode(&self, h: f64, n: usize) -> Option<(f64, usize)> {
        let (k6, k7) = (&self.k[5], &self.k[6]);
        let (mut num, mut den, mut state, mut most) = (0.0, 0.0, 0, 0.0);
        for i in 0..n {
            let dk = k7[i] - k6[i];
            num += dk * dk;
            den += (self.y_new[i] - self.stage[i]).powi(2);
            let scaled = dk.abs() / (self.tol.abstol + self.tol.reltol * self.y_new[i].abs());
            if scaled > most {
                (most, state) = (scaled, i);
            }
        }
        (den > 0.0).then(|| (h * (num / den).sqrt(), state))
    }

    /// RMS of the error estimate scaled by `abstol + reltol max(|y|, |y_new|)`.
    fn error_norm(&self, h: f64, n: usize) -> f64 {
        let [k1, _, k3, k4, k5, k6, k7] = &self.k;
        let mut sum = 0.0;
        for i in 0..n {
            let e = h * (E1 * k1[i] + E3 * k3[i] + E4 * k4[i] + E5 * k5[i] + E6 * k6[i] + E7 * k7[i]);
            let sk = self.tol.abstol + self.tol.reltol * self.y[i].abs().max(self.y_new[i].abs());
            sum += (e / sk) * (e / sk);
        }
        (sum / n.max(1) as f64).sqrt()
    }

    fn dense_coefficients(&mut self, h: f64, n: usize) {
        let [k1, _, k3, k4, k5, k6, k7] = &self.k;
        let [r0, r1, r2, r3, r4] = &mut self.cont;
        for i in 0..n {
            let ydiff = self.y_new[i] - self.y[i];
            let bspl = h * k1[i] - ydiff;
            r0[i] = self.y[i];
            r1[i] = ydiff;
            r2[i] = bspl;
            r3[i] = ydiff - h * k7[i] - bspl;
            r4[i] = h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::integrator::test_systems::{assert_stopped_at_the_failure, FailsAfter, Oscillator};
    use super::*;

    fn run(tol: f64) -> (f64, f64, Stats) {
        let mut dp = DormandPrince::new(2, Tolerances { abstol: tol, reltol: tol, dtmax: 0.0 });
        let mut worst_dense = 0.0f64;
        let mut buf = [0.0; 2];
        let stats = dp
            .integrate(&mut Oscillator, 0.0, 10.0, &[0.0, 1.0], |s| {
                let (a, b) = s.span();
                for k in 1..10 {
                    let t = a + (b - a) * k as f64 / 10.0;
                    s.interpolate(t, &mut buf);
                    worst_dense = worst_dense.max((buf[0] - t.sin()).abs());
                }
                Ok(())
            })
            .unwrap();
        ((dp.y()[0] - 10f64.sin()).abs(), worst_dense, stats)
    }

    #[test]
    fn error_follows_the_tolerance_and_dense_output_is_as_accurate_as_the_steps() {
        let (end, dense, _) = run(1e-8);
        assert!(end < 1e-6, "end error {end}");
        assert!(dense < 5.0 * end.max(1e-8), "dense {dense} vs end {end}");
        let (end_loose, _, s_loose) = run(1e-4);
        let (_, _, s_tight) = run(1e-10);
        assert!(end_loose > end);
        assert!(s_tight.accepted > s_loose.accepted);
    }

    #[test]
    fn stops_with_the_error_and_the_time_reached() {
        let mut dp = DormandPrince::new(1, Tolerances { abstol: 1e-6, reltol: 1e-6, dtmax: 0.1 });
        let mut last = 0.0;
        let stopped = dp.integrate(&mut FailsAfter, 0.0, 5.0, &[0.0], |s| {
            last = s.span().1;
            Ok(())
        });
        assert_stopped_at_the_failure(stopped.unwrap_err(), last);
    }
}
