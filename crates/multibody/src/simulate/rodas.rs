//! Rodas4: an L-stable, stiffly accurate Rosenbrock method of order 4 with
//! an embedded order-3 error estimate and an order-3 continuous output, for
//! stiff mechanisms (stiff springs and dampers, fast drive trains).
//!
//! The name is the engine's (`Method::Rodas4`); the tableau is **Rodas4P**,
//! Steinebach's variant of Hairer & Wanner's Rodas4 with the same structure
//! (six stages, stiffly accurate, `γ = 1/4`, embedded order 3, continuous
//! output of order 3) but coefficients chosen so that the order does not
//! drop on Prothero-Robinson problems `y' = λ (y - φ(t)) + φ'(t)` with
//! large `|hλ|` nor on index-1 DAEs. Rodas4's does drop there, and its
//! estimate with it: on a stiff, periodically forced spring-damper it
//! under-reported the error and missed the tolerance by a factor of 4 to 9.
//!
//! - Method: G. Steinebach, *Order-reduction of ROW-methods for DAEs and
//!   method of lines applications*, Preprint 1741, FB Mathematik, TH
//!   Darmstadt, 1995 (the method called RODASP there).
//! - Numbers: the transformed coefficients `a_ij`, `g_ij`, `c_i`, `γ_i`
//!   and the continuous output's `p`, `q` weights as tabulated for
//!   `Rodas4P` in OrdinaryDiffEq.jl's Rosenbrock tableaus (whose Rodas4
//!   entries are exactly Hairer's `rodas.f` numbers used before, so the
//!   conventions agree). Checked against Steinebach's untransformed
//!   `α_ij`, `β_ij` for RODASP (from his MATLAB code `rodasp2.m`): with
//!   `Γ = β - α + γ I`, `a = α Γ⁻¹`, `g = I/γ - Γ⁻¹`, `c_i = Σ_j α_ij`,
//!   `γ_i = Σ_j Γ_ij` reproduce them to about 1e-13, and by the convergence
//!   tests below (a wrong digit shows up as lost order).
//!
//! (Hairer & Wanner's book, *Solving Ordinary Differential Equations II*,
//! 2nd ed., Springer 1996, sections IV.7 and VI.4, describes the scheme.)
//!
//! # The scheme
//!
//! With `J = ∂f/∂y` and `f_t = ∂f/∂t` at the start `(t, y)` of a step of
//! size `h`, and `W = I/(hγ) - J`, the six stages `k_1..k_6` solve
//!
//! ```text
//! W k_i = f(t + c_i h, y + Σ_{j<i} a_ij k_j) + γ_i h f_t + Σ_{j<i} (g_ij / h) k_j
//! ```
//!
//! (the first stage uses `f(t, y)` itself). The method is stiffly accurate:
//! the last stage's argument `y + Σ_{j<6} a_6j k_j` is the order-3 solution,
//! the order-4 solution is that plus `k_6`, so `k_6` is the error estimate.
//! Between `y_0` and `y_1` the continuous output is
//! `u(θ) = (1-θ) y_0 + θ (y_1 + (1-θ) (p + θ q))` with `p`, `q` fixed
//! combinations of `k_1..k_5`.
//!
//! # Choices made here
//!
//! - `J` by forward differences, one right-hand side per column, with the
//!   increment `sqrt(eps · max(|y_j|, 1e-5))` of Hairer's codes, and `f_t`
//!   by a forward difference in `t` with the same rule: `n + 1` evaluations,
//!   counted in [`Stats::evaluations`]. `J` is evaluated afresh at the start
//!   of every step; a rejected step keeps it (same `(t, y)`) and only
//!   factors `W` again for the new `h`.
//! - One more evaluation per accepted step gives `f` at the step's end: the
//!   first stage and the Jacobian of the next step use it, and it is the
//!   derivative [`finish_step`] refreshes when the system moves the state.
//! - Step control: the scaled RMS norm of `k_6` (`abstol + reltol ·
//!   max(|y|, |y_new|)`), `h_new = h · clamp(0.9 · err^(-1/4), 0.2, 6)`,
//!   with Gustafsson's predictive correction after accepted steps (as
//!   `rodas.f` does by default), never growing right after a rejection.
//!   A non-finite estimate (a stage that blew up) rejects with `h / 10`; a
//!   singular `W` rejects with `h / 2`.
//! - The continuous output is checked too. For a stiff component that
//!   follows a slow forcing (`y ≈ φ(t)`, `hλ → -∞`) a stiffly accurate
//!   method lands on `φ(t + h)` whatever `h`, and so does its order-3
//!   solution: `k_6` tends to zero and says nothing about the output in
//!   between, so the steps grow until no cubic can follow `φ` (on
//!   Prothero-Robinson's problem with `λ = -1e8` and tolerance 1e-6: 7
//!   steps over two periods, the output off by 1e6 tolerances). So a step
//!   whose `k_6` passes also evaluates the defect of its output at
//!   `θ* = 3/4`, `δ = u'(t*) - f(t*, u(t*))` (one more evaluation), and
//!   filters it with `W`: `e = W⁻¹ δ`. In a stiff direction (`hλ → -∞`)
//!   `e` is the output's error at `t*` itself; in a non-stiff one it is
//!   about `hγ δ`; both go as `h^4` like the local error `k_6` measures.
//!   `2 e`, scaled like `k_6`, must also be at most 1: the larger of the
//!   two decides acceptance and the next step. (The factor 2: `e` estimates
//!   the output's own error, not a lower-order one as `k_6` does, and
//!   `θ* = 3/4` is near, not at, where that error peaks.)
//! - Starting step: Hairer's heuristic (an explicit Euler probe of the
//!   second derivative, as in Dormand-Prince), with the exponent of an
//!   order-4 error estimate.
//!
//! All memory is allocated in [`Rodas4::new`]; `integrate` allocates nothing.

use super::integrator::{finish_step, DenseStep, Failure, Observer, OdeSystem, Reached, Stats, Stopped, Tolerances};
use super::rosenbrock;
use crate::math::dense::lu_solve;

/// The diagonal of the method: `W = I/(hγ) - J`.
const GAMMA: f64 = 0.25;
/// Stage times as fractions of the step.
const C: [f64; 6] = [0.0, 0.75, 0.21, 0.63, 1.0, 1.0];
/// `γ_i`: the weight of `h f_t` in each stage (zero in the last two).
const D: [f64; 6] = [0.25, -0.5, -0.023504, -0.0362, 0.0, 0.0];
/// Stage arguments: `y + Σ_j A[i][j] k_j`. The last row is also the order-3
/// solution.
const A: [[f64; 5]; 6] = [
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0, 0.0, 0.0, 0.0, 0.0],
    [1.831036793486759, 0.4955183967433795, 0.0, 0.0, 0.0],
    [2.304376582692669, -0.05249275245743001, -1.176798761832782, 0.0, 0.0],
    [-7.170454962423024, -4.741636671481785, -16.31002631330971, -1.062004044111401, 0.0],
    [-7.170454962423024, -4.741636671481785, -16.31002631330971, -1.062004044111401, 1.0],
];
/// Coupling of the earlier stages into a stage's right-hand side:
/// `Σ_j G[i][j] k_j / h`.
const G: [[f64; 5]; 6] = [
    [0.0, 0.0, 0.0, 0.0, 0.0],
    [-12.0, 0.0, 0.0, 0.0, 0.0],
    [-8.791795173947035, -2.207865586973518, 0.0, 0.0, 0.0],
    [10.81793056857153, 6.780270611428266, 19.5348594464241, 0.0, 0.0],
    [34.19095006749676, 15.49671153725963, 54.7476087596413, 14.16005392148534, 0.0],
    [34.62605830930532, 15.30084976114473, 56.99955578662667, 18.40807009793095, -5.714285714285717],
];
/// The continuous output's `p` and `q` from `k_1..k_5`.
const P: [[f64; 5]; 2] = [
    [25.09876703708589, 11.62013104361867, 28.49148307714626, -5.664021568594133, 0.0],
    [1.638054557396973, -0.7373619806678748, 8.47791821923899, 15.9925314877952, -1.882352941176471],
];

/// Where in the step the continuous output is checked: near where its
/// error on Prothero-Robinson's problem with `hλ → -∞` peaks (`θ ≈ 0.72`).
const DENSE_CHECK: f64 = 0.75;
/// The continuous output's estimated error counts double: it is held to
/// half the tolerance.
const DENSE_WEIGHT: f64 = 2.0;

/// The error estimate is of order 3: its local error goes as `h^4`.
const EXPONENT: f64 = 0.25;

/// The integrator's memory, allocated once.
pub struct Rodas4 {
    pub(crate) tol: Tolerances,
    /// `∂f/∂y` at the start of the current step (n x n, row-major).
    jac: Vec<f64>,
    /// The LU factors of `W = I/(hγ) - J`, and their row pivots.
    w: Vec<f64>,
    pivots: Vec<usize>,
    /// `∂f/∂t` at the start of the current step.
    f_t: Vec<f64>,
    k: [Vec<f64>; 6],
    /// The state at the end of the last accepted step, and `f` there.
    y: Vec<f64>,
    f: Vec<f64>,
    /// A stage's argument (and scratch for the difference quotients).
    arg: Vec<f64>,
    y_new: Vec<f64>,
    /// Scratch of the triangular solves.
    work: Vec<f64>,
    /// The filtered defect of the continuous output (see `dense_error`).
    defect: Vec<f64>,
    /// Continuous output of the last accepted step: `y_0`, `y_1`, `p`, `q`.
    cont: [Vec<f64>; 4],
    t_old: f64,
    h_old: f64,
    /// Where the integration stands, and the step it will try next.
    t: f64,
    h: f64,
    h_max: f64,
    rejected_last: bool,
    /// Step and error of the last accepted step, for the predictive control.
    previous: Option<(f64, f64)>,
    stats: Stats,
}

impl DenseStep for Rodas4 {
    fn span(&self) -> (f64, f64) {
        (self.t_old, self.t_old + self.h_old)
    }
    fn y(&self) -> &[f64] {
        &self.y
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        // Only the stored coefficients: `self.y` may be moved out while the
        // system projects it and reads this output.
        let theta = (t - self.t_old) / self.h_old;
        let theta1 = 1.0 - theta;
        let [y0, y1, p, q] = &self.cont;
        for (i, x) in out.iter_mut().enumerate() {
            *x = theta1 * y0[i] + theta * (y1[i] + theta1 * (p[i] + theta * q[i]));
        }
    }
}

impl Rodas4 {
    pub fn new(n: usize, tol: Tolerances) -> Self {
        let v = || vec![0.0; n];
        Self {
            tol,
            jac: vec![0.0; n * n],
            w: vec![0.0; n * n],
            pivots: vec![0; n],
            f_t: v(),
            k: [v(), v(), v(), v(), v(), v()],
            y: v(),
            f: v(),
            arg: v(),
            y_new: v(),
            work: v(),
            defect: v(),
            cont: [v(), v(), v(), v()],
            t_old: 0.0,
            h_old: 0.0,
            t: 0.0,
            h: 0.0,
            h_max: 0.0,
            rejected_last: false,
            previous: None,
            stats: Stats::default(),
        }
    }

    /// Integrates from `t0` to `tf` starting at `y0`, calling `observe`
    /// after every accepted step; stops like [`super::dopri5::DormandPrince`].
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

    /// Starts at `(t, y)` (or starts again there after an event), as
    /// [`super::dopri5::DormandPrince::start`].
    pub fn start<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        horizon: f64,
    ) -> Result<(), Stopped<S::Error>> {
        self.y.copy_from_slice(y);
        self.t = t;
        let scratch = (&mut self.arg[..], &mut self.k[0][..]);
        let begun =
            rosenbrock::begin(sys, t, &self.y, &mut self.f, &self.tol, horizon, EXPONENT, scratch, &mut self.stats);
        (self.h_max, self.h) = begun.map_err(|e| Stopped { t, failure: Failure::Rhs(e), stats: self.stats })?;
        self.rejected_last = false;
        self.previous = None;
        Ok(())
    }

    /// Steps from the current time to exactly `tf`, or to the first event
    /// inside a step, as [`super::dopri5::DormandPrince::advance`].
    pub fn advance<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        tf: f64,
        observe: &mut Observer<S::Error>,
    ) -> Result<Reached, Stopped<S::Error>> {
        let stop = |t: f64, failure, stats| Err(Stopped { t, failure, stats });
        let mut h = self.h;
        // Whether `jac` and `f_t` belong to the current `(t, y)`.
        let mut jacobian_current = false;
        while self.t < tf {
            let t = self.t;
            if 0.1 * h.abs() <= t.abs() * f64::EPSILON * 4.0 {
                return stop(t, Failure::StepTooSmall { h, attempt: self.y_new.clone() }, self.stats);
            }
            let last = t + 1.01 * h >= tf;
            if last {
                h = tf - t;
            }
            if !jacobian_current {
                let mut stats = self.stats;
                let computed = self.jacobian(sys, t, &mut stats);
                self.stats = stats;
                if let Err(e) = computed {
                    return stop(t, Failure::Rhs(e), self.stats);
                }
                jacobian_current = true;
            }
            if !self.factor(h) {
                // 1/(hγ) is an eigenvalue of J: any other step will do.
                self.stats.rejected += 1;
                h *= 0.5;
                self.rejected_last = true;
                continue;
            }
            let mut stats = self.stats;
            let staged = self.stages(sys, t, h, &mut stats);
            self.stats = stats;
            if let Err(e) = staged {
                return stop(t, Failure::Rhs(e), self.stats);
            }
            let mut err = self.error_norm(&self.k[5]);
            if err <= 1.0 {
                // The end of the step is good enough; is the continuous
                // output in between?
                let mut stats = self.stats;
                let dense = self.dense_error(sys, t, h, &mut stats);
                self.stats = stats;
                match dense {
                    Ok(dense) if dense.is_nan() || dense > err => err = dense,
                    Ok(_) => {}
                    Err(e) => return stop(t, Failure::Rhs(e), self.stats),
                }
            }
            if !err.is_finite() {
                // A step too large for the dynamics: try a much smaller one.
                self.stats.rejected += 1;
                h *= 0.1;
                self.rejected_last = true;
                continue;
            }
            if err > 1.0 {
                self.stats.rejected += 1;
                h /= rosenbrock::step_factor(err, EXPONENT);
                self.rejected_last = true;
                continue;
            }
            // h_new = h / fac
            let fac = rosenbrock::accepted_factor(err, h, &mut self.previous, EXPONENT);
            self.dense_coefficients();
            std::mem::swap(&mut self.y, &mut self.y_new);
            let t_end = if last { tf } else { t + h };
            // The derivative at the new point starts the next step.
            self.stats.evaluations += 1;
            if let Err(e) = sys.rhs(t_end, &self.y, &mut self.f) {
                return stop(t, Failure::Rhs(e), self.stats);
            }
            self.stats.accepted += 1;
            self.stats.error_sum += err;
            self.t_old = t;
            self.h_old = h;
            self.t = t_end;
            let mut h_new = (h / fac).min(self.h_max);
            if self.rejected_last {
                h_new = h_new.min(h);
            }
            self.rejected_last = false;
            self.h = h_new;
            let end = finish_step(sys, self, t_end, |s| (&mut s.y, &mut s.f, &mut s.stats), observe, true)?;
            jacobian_current = false;
            if let Some(te) = end {
                self.t = te;
                return Ok(Reached::Event(te));
            }
            h = self.h;
        }
        self.h = h;
        Ok(Reached::End)
    }

    /// The counts of the work done so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// `∂f/∂y` (the system's own where it has one) and `∂f/∂t` at
    /// `(t, self.y)`, by forward differences from `self.f = f(t, y)`.
    fn jacobian<S: OdeSystem>(&mut self, sys: &mut S, t: f64, stats: &mut Stats) -> Result<(), S::Error> {
        rosenbrock::jacobian(sys, t, &mut self.y, &self.f, &mut self.jac, &mut self.arg, stats)?;
        rosenbrock::time_derivative(sys, t, &self.y, &self.f, &mut self.f_t, &mut self.arg, stats)
    }

    /// Forms `W = I/(hγ) - J` and factors it; false if it is singular.
    fn factor(&mut self, h: f64) -> bool {
        rosenbrock::factor(&self.jac, &mut self.w, &mut self.pivots, h * GAMMA)
    }

    /// The six stages of a step of size `h` from `(t, self.y)`, and the
    /// order-4 solution in `y_new`.
    fn stages<S: OdeSystem>(&mut self, sys: &mut S, t: f64, h: f64, stats: &mut Stats) -> Result<(), S::Error> {
        let n = self.y.len();
        let inv_h = 1.0 / h;
        for s in 0..6 {
            let (done, rest) = self.k.split_at_mut(s);
            let ks = &mut rest[0];
            if s == 0 {
                ks.copy_from_slice(&self.f);
            } else {
                for i in 0..n {
                    let mut x = self.y[i];
                    for (a, kj) in A[s].iter().zip(done.iter()) {
                        x += a * kj[i];
                    }
                    self.arg[i] = x;
                }
                stats.evaluations += 1;
                sys.rhs(t + C[s] * h, &self.arg, ks)?;
            }
            let ht = h * D[s];
            for i in 0..n {
                let mut x = ks[i] + ht * self.f_t[i];
                for (g, kj) in G[s].iter().zip(done.iter()) {
                    x += g * inv_h * kj[i];
                }
                ks[i] = x;
            }
            lu_solve(&self.w, n, &self.pivots, ks, &mut self.work);
        }
        // `arg` holds the last stage's argument: the order-3 solution.
        for i in 0..n {
            self.y_new[i] = self.arg[i] + self.k[5][i];
        }
        Ok(())
    }

    /// The RMS of `e` scaled by `abstol + reltol max(|y|, |y_new|)`.
    fn error_norm(&self, e: &[f64]) -> f64 {
        let n = self.y.len();
        let mut sum = 0.0;
        for i in 0..n {
            let sk = self.tol.abstol + self.tol.reltol * self.y[i].abs().max(self.y_new[i].abs());
            let e = e[i] / sk;
            sum += e * e;
        }
        (sum / n.max(1) as f64).sqrt()
    }

    /// The estimated error of the continuous output of the step just
    /// computed, scaled like the step's error and weighted by
    /// `DENSE_WEIGHT`: the output's defect at `θ = DENSE_CHECK` (its
    /// derivative minus `f` there) filtered by `W⁻¹`, as the module
    /// documentation explains. Leaves `cont` (the last accepted step's
    /// output) and the stages alone.
    fn dense_error<S: OdeSystem>(&mut self, sys: &mut S, t: f64, h: f64, stats: &mut Stats) -> Result<f64, S::Error> {
        let n = self.y.len();
        let (theta, theta1) = (DENSE_CHECK, 1.0 - DENSE_CHECK);
        for i in 0..n {
            let (mut p, mut q) = (0.0, 0.0);
            for (j, kj) in self.k[..5].iter().enumerate() {
                p += P[0][j] * kj[i];
                q += P[1][j] * kj[i];
            }
            let (y0, y1) = (self.y[i], self.y_new[i]);
            // The output and its time derivative at θ.
            self.arg[i] = theta1 * y0 + theta * (y1 + theta1 * (p + theta * q));
            self.work[i] = (y1 - y0 + (1.0 - 2.0 * theta) * p + theta * (2.0 - 3.0 * theta) * q) / h;
        }
        stats.evaluations += 1;
        sys.rhs(t + theta * h, &self.arg, &mut self.defect)?;
        for (d, derivative) in self.defect.iter_mut().zip(&self.work) {
            *d = derivative - *d;
        }
        lu_solve(&self.w, n, &self.pivots, &mut self.defect, &mut self.work);
        Ok(DENSE_WEIGHT * self.error_norm(&self.defect))
    }

    fn dense_coefficients(&mut self) {
        let [y0, y1, p, q] = &mut self.cont;
        y0.copy_from_slice(&self.y);
        y1.copy_from_slice(&self.y_new);
        for i in 0..self.y.len() {
            let (mut pi, mut qi) = (0.0, 0.0);
            for (j, kj) in self.k[..5].iter().enumerate() {
                pi += P[0][j] * kj[i];
                qi += P[1][j] * kj[i];
            }
            p[i] = pi;
            q[i] = qi;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::dopri5::DormandPrince;
    use super::super::integrator::test_systems::{assert_stopped_at_the_failure, FailsAfter, Oscillator};
    use super::*;

    fn tol(tol: f64) -> Tolerances {
        Tolerances { abstol: tol, reltol: tol, dtmax: 0.0 }
    }

    /// A nonlinear, non-autonomous system whose solution is
    /// `(cos t, 1 + sin(2t)/2)`: every order condition matters.
    struct Manufactured;
    impl Manufactured {
        fn exact(t: f64) -> [f64; 2] {
            [t.cos(), 1.0 + 0.5 * (2.0 * t).sin()]
        }
    }
    impl OdeSystem for Manufactured {
        type Error = ();
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
            let [p, q] = Self::exact(t);
            let (dp, dq) = (-t.sin(), (2.0 * t).cos());
            dy[0] = -y[0] * y[1] + dp + p * q;
            dy[1] = -y[1].powi(3) + y[0] + dq + q.powi(3) - p;
            Ok(())
        }
    }

    /// One step of size `h` from `(t, y)`: the order-4 solution and the error estimate `k_6`.
    fn one_step<S: OdeSystem>(r: &mut Rodas4, sys: &mut S, t: f64, y: &[f64], h: f64) -> (Vec<f64>, Vec<f64>) {
        let mut stats = Stats::default();
        r.y.copy_from_slice(y);
        sys.rhs(t, &r.y, &mut r.f).ok().unwrap();
        r.jacobian(sys, t, &mut stats).ok().unwrap();
        assert!(r.factor(h));
        r.stages(sys, t, h, &mut stats).ok().unwrap();
        (r.y_new.clone(), r.k[5].clone())
    }

    /// The largest error against the exact solution with `steps` fixed steps over [0, 2].
    fn fixed_steps(steps: usize) -> f64 {
        let mut r = Rodas4::new(2, tol(1e-6));
        let h = 2.0 / steps as f64;
        let mut y = Manufactured::exact(0.0).to_vec();
        let mut worst = 0.0f64;
        for i in 0..steps {
            let t = i as f64 * h;
            y = one_step(&mut r, &mut Manufactured, t, &y, h).0;
            let exact = Manufactured::exact(t + h);
            worst = worst.max((y[0] - exact[0]).abs()).max((y[1] - exact[1]).abs());
        }
        worst
    }

    #[test]
    fn fixed_steps_converge_with_order_four_and_the_estimate_with_order_three() {
        // From 20 steps: at 10 (h = 0.2) Rodas4P's errors are not yet asymptotic.
        let errors: Vec<f64> = [20, 40, 80, 160].iter().map(|&s| fixed_steps(s)).collect();
        let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
        eprintln!("global errors {errors:?}, observed orders {orders:?}");
        for p in &orders {
            assert!((3.7..4.4).contains(p), "global order {p} (errors {errors:?})");
        }
        // Local errors from the exact state at t = 0.3: order 5 for the
        // solution, order 4 for the estimate (the local error of the
        // embedded order-3 solution).
        let mut r = Rodas4::new(2, tol(1e-6));
        // The continuous output, order 3, has local errors of order 4.
        let (mut local, mut estimate, mut dense) = (vec![], vec![], vec![]);
        for h in [0.1, 0.05, 0.025] {
            let (y, k6) = one_step(&mut r, &mut Manufactured, 0.3, &Manufactured::exact(0.3), h);
            let exact = Manufactured::exact(0.3 + h);
            local.push((y[0] - exact[0]).hypot(y[1] - exact[1]));
            estimate.push(k6[0].hypot(k6[1]));
            r.dense_coefficients();
            (r.t_old, r.h_old) = (0.3, h);
            let mut worst = 0.0f64;
            for theta in [0.2, 0.5, 0.7] {
                let mut y = [0.0; 2];
                r.interpolate(0.3 + theta * h, &mut y);
                let exact = Manufactured::exact(0.3 + theta * h);
                worst = worst.max((y[0] - exact[0]).hypot(y[1] - exact[1]));
            }
            dense.push(worst);
        }
        let order = |e: &[f64]| -> Vec<f64> { e.windows(2).map(|e| (e[0] / e[1]).log2()).collect() };
        let (local_orders, estimate_orders, dense_orders) = (order(&local), order(&estimate), order(&dense));
        eprintln!("local errors {local:?} orders {local_orders:?}; estimates {estimate:?} orders {estimate_orders:?}");
        eprintln!("dense errors {dense:?} orders {dense_orders:?}");
        for p in &dense_orders {
            assert!((3.5..4.6).contains(p), "dense order {p}");
        }
        for p in &local_orders {
            assert!((4.5..5.6).contains(p), "local order {p}");
        }
        for p in &estimate_orders {
            assert!((3.5..4.5).contains(p), "estimate order {p}");
        }
    }

    fn run_oscillator(tol_: f64) -> (f64, f64, Stats) {
        let mut r = Rodas4::new(2, tol(tol_));
        let mut worst_dense = 0.0f64;
        let mut buf = [0.0; 2];
        let stats = r
            .integrate(&mut Oscillator, 0.0, 10.0, &[0.0, 1.0], |s| {
                let (a, b) = s.span();
                for k in 1..10 {
                    let t = a + (b - a) * k as f64 / 10.0;
                    s.interpolate(t, &mut buf);
                    worst_dense = worst_dense.max((buf[0] - t.sin()).abs()).max((buf[1] - t.cos()).abs());
                }
                Ok(())
            })
            .unwrap();
        let end = (r.y()[0] - 10f64.sin()).abs().max((r.y()[1] - 10f64.cos()).abs());
        (end, worst_dense, stats)
    }

    #[test]
    fn error_follows_the_tolerance_with_few_steps() {
        let (end, _, stats) = run_oscillator(1e-8);
        eprintln!("oscillator at tol 1e-8: end error {end:.2e}, {stats:?}");
        assert!(end < 1e-6, "end error {end}");
        assert!(stats.accepted < 400, "{stats:?}");
        let (end_loose, _, s_loose) = run_oscillator(1e-4);
        let (end_tight, _, s_tight) = run_oscillator(1e-10);
        eprintln!("tol 1e-4: {end_loose:.2e} {s_loose:?}; tol 1e-10: {end_tight:.2e} {s_tight:?}");
        assert!(end_loose > end && end > end_tight);
        assert!(s_tight.accepted > stats.accepted && stats.accepted > s_loose.accepted);
    }

    #[test]
    fn dense_output_is_as_accurate_as_the_steps() {
        for t in [1e-5, 1e-8] {
            let (end, dense, stats) = run_oscillator(t);
            eprintln!("tol {t:e}: end {end:.2e}, dense {dense:.2e}, {} steps", stats.accepted);
            assert!(dense < 10.0 * t.max(end), "dense {dense} at tol {t}, end error {end}");
        }
    }

    /// `y' = -1e5 (y - cos t) - sin t`, solution `cos t` from `y(0) = 1`.
    struct StiffScalar;
    impl OdeSystem for StiffScalar {
        type Error = ();
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
            dy[0] = -1e5 * (y[0] - t.cos()) - t.sin();
            Ok(())
        }
    }

    #[test]
    fn stiff_scalar_follows_its_slow_solution() {
        let mut r = Rodas4::new(1, tol(1e-6));
        let mut worst = 0.0f64;
        let stats = r
            .integrate(&mut StiffScalar, 0.0, 1.0, &[1.0], |s| {
                worst = worst.max((s.y()[0] - s.span().1.cos()).abs());
                Ok(())
            })
            .unwrap();
        let dopri = DormandPrince::new(1, tol(1e-6)).integrate(&mut StiffScalar, 0.0, 1.0, &[1.0], |_| Ok(())).unwrap();
        eprintln!("stiff scalar: error {worst:.2e}, Rodas {stats:?}, dopri {dopri:?}");
        assert!(worst < 1e-5, "error {worst}");
        assert!(stats.accepted < 100, "{stats:?}");
        assert!(stats.evaluations * 20 < dopri.evaluations, "Rodas {stats:?}, dopri {dopri:?}");
    }

    /// `x'' = -(c x + d x') / m + g` with `m = 1, c = 1e8, d = 2e5`: real
    /// eigenvalues near -501 and -2e5.
    struct SpringDamper;
    const M: f64 = 1.0;
    const STIFFNESS: f64 = 1e8;
    const DAMPING: f64 = 2e5;
    const GRAVITY: f64 = 9.80665;
    impl SpringDamper {
        /// Position and velocity at `t` from `x(0) = x0, v(0) = 0`.
        fn exact(t: f64, x0: f64) -> [f64; 2] {
            let (b, c) = (DAMPING / M, STIFFNESS / M);
            let root = (b * b - 4.0 * c).sqrt();
            let (l1, l2) = ((-b + root) / 2.0, (-b - root) / 2.0);
            let rest = GRAVITY / c;
            let u0 = x0 - rest;
            // u = A e^(l1 t) + B e^(l2 t), A + B = u0, l1 A + l2 B = 0
            let a = -l2 * u0 / (l1 - l2);
            let bb = u0 - a;
            let (e1, e2) = ((l1 * t).exp(), (l2 * t).exp());
            [rest + a * e1 + bb * e2, l1 * a * e1 + l2 * bb * e2]
        }
    }
    impl OdeSystem for SpringDamper {
        type Error = ();
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
            dy[0] = y[1];
            dy[1] = -(STIFFNESS * y[0] + DAMPING * y[1]) / M + GRAVITY;
            Ok(())
        }
    }

    #[test]
    fn stiff_spring_damper_matches_its_closed_form_with_far_fewer_evaluations_than_dopri() {
        let x0 = 0.01;
        let mut r = Rodas4::new(2, tol(1e-6));
        let (mut worst_x, mut worst_v) = (0.0f64, 0.0f64);
        let stats = r
            .integrate(&mut SpringDamper, 0.0, 1.0, &[x0, 0.0], |s| {
                let exact = SpringDamper::exact(s.span().1, x0);
                worst_x = worst_x.max((s.y()[0] - exact[0]).abs());
                worst_v = worst_v.max((s.y()[1] - exact[1]).abs());
                Ok(())
            })
            .unwrap();
        let mut dp = DormandPrince::new(2, tol(1e-6));
        let dopri = dp.integrate(&mut SpringDamper, 0.0, 1.0, &[x0, 0.0], |_| Ok(())).unwrap();
        eprintln!(
            "spring-damper: |x err| {worst_x:.2e}, |v err| {worst_v:.2e} (v up to 5), Rodas {stats:?}, dopri {dopri:?}"
        );
        assert!(worst_x < 1e-5, "x error {worst_x}");
        assert!(worst_v < 1e-3, "v error {worst_v}");
        assert!(stats.accepted < 300, "{stats:?}");
        assert!(stats.evaluations * 20 < dopri.evaluations, "Rodas {stats:?}, dopri {dopri:?}");
        let end = SpringDamper::exact(1.0, x0);
        assert!((r.y()[0] - end[0]).abs() < 1e-9);
    }

    /// Van der Pol with `mu = 1000`: `y1' = y2, y2' = mu (1 - y1^2) y2 - y1`.
    struct VanDerPol;
    impl OdeSystem for VanDerPol {
        type Error = ();
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
            dy[0] = y[1];
            dy[1] = 1000.0 * (1.0 - y[0] * y[0]) * y[1] - y[0];
            Ok(())
        }
    }

    #[test]
    fn van_der_pol_at_mu_1000_matches_the_test_set_reference() {
        // The IVP test set (Mazzia & Magherini, Bari; problem VDPOL, the
        // same problem with time scaled by mu) gives at t = 2000:
        let reference = [1.706167732170469, -0.8928097010248125e-3];
        let mut r = Rodas4::new(2, tol(1e-6));
        let mut at_2000 = [0.0; 2];
        let mut largest = 0.0f64;
        // Downward zero crossings of y1, located with the dense output.
        let mut crossings = vec![];
        let stats = r
            .integrate(&mut VanDerPol, 0.0, 3000.0, &[2.0, 0.0], |s| {
                let (a, b) = s.span();
                if (a..=b).contains(&2000.0) {
                    s.interpolate(2000.0, &mut at_2000);
                }
                largest = largest.max(s.y()[0].abs());
                let mut ya = [0.0; 2];
                s.interpolate(a, &mut ya);
                if ya[0] > 0.0 && s.y()[0] <= 0.0 {
                    let (mut lo, mut hi) = (a, b);
                    let mut y = [0.0; 2];
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        s.interpolate(mid, &mut y);
                        if y[0] > 0.0 {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    crossings.push(lo);
                }
                Ok(())
            })
            .unwrap();
        let errors = [(at_2000[0] - reference[0]).abs(), (at_2000[1] - reference[1]).abs()];
        eprintln!(
            "van der Pol: y(2000) = {at_2000:?}, errors {:.2e} {:.2e}, |y1| <= {largest}, {stats:?}",
            errors[0], errors[1]
        );
        eprintln!("downward crossings {crossings:?}");
        assert!(errors[0] < 1e-3 && errors[1] < 1e-5, "y(2000) = {at_2000:?}");
        assert!(stats.accepted < 2000, "{stats:?}");
        assert!(largest < 2.01, "|y1| up to {largest}");
        // The limit cycle's period, Dorodnitsyn's asymptotic formula:
        // (3 - 2 ln 2) mu + 3 a mu^(-1/3) with a = 2.338 (first zero of the
        // Airy function), 1614.4 at mu = 1000.
        assert_eq!(crossings.len(), 2, "{crossings:?}");
        let period = crossings[1] - crossings[0];
        assert!((period - 1614.4).abs() < 0.5, "period {period}");
    }

    #[test]
    fn stops_with_the_error_and_the_time_reached() {
        let mut r = Rodas4::new(1, Tolerances { abstol: 1e-6, reltol: 1e-6, dtmax: 0.1 });
        let mut last = 0.0;
        let stopped = r.integrate(&mut FailsAfter, 0.0, 5.0, &[0.0], |s| {
            last = s.span().1;
            Ok(())
        });
        assert_stopped_at_the_failure(stopped.unwrap_err(), last);
    }

    #[test]
    fn hits_the_end_time_exactly_and_keeps_dtmax() {
        let mut r = Rodas4::new(2, Tolerances { abstol: 1e-6, reltol: 1e-6, dtmax: 0.3 });
        let mut widest = 0.0f64;
        let mut end = 0.0;
        r.integrate(&mut Oscillator, 0.0, 3.7, &[0.0, 1.0], |s| {
            let (a, b) = s.span();
            widest = widest.max(b - a);
            end = b;
            Ok(())
        })
        .unwrap();
        assert!(widest <= 0.3 + 1e-15, "widest step {widest}");
        assert_eq!(end, 3.7);
    }

    #[test]
    fn finite_difference_jacobian_matches_the_analytic_one() {
        struct Known;
        impl OdeSystem for Known {
            type Error = ();
            fn dim(&self) -> usize {
                2
            }
            fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
                dy[0] = y[0].sin() * y[1] + t * t;
                dy[1] = y[0].powi(3) - y[1].exp() * t;
                Ok(())
            }
        }
        let (t, y) = (0.7, [0.4, -1.3]);
        let mut r = Rodas4::new(2, tol(1e-6));
        let mut stats = Stats::default();
        r.y.copy_from_slice(&y);
        Known.rhs(t, &y, &mut r.f).unwrap();
        r.jacobian(&mut Known, t, &mut stats).unwrap();
        let jac = [y[0].cos() * y[1], y[0].sin(), 3.0 * y[0] * y[0], -y[1].exp() * t];
        let f_t = [2.0 * t, -y[1].exp()];
        for (fd, exact) in r.jac.iter().zip(jac).chain(r.f_t.iter().zip(f_t)) {
            assert!((fd - exact).abs() < 1e-6 * exact.abs().max(1.0), "{fd} vs {exact}");
        }
        assert_eq!(stats.evaluations, 3);
        assert_eq!(r.y, y, "the state is restored");
    }

    #[test]
    fn a_singular_w_is_refused_and_an_unusable_jacobian_ends_in_step_too_small() {
        // y' = y: W = 1/(h/4) - 1 vanishes at h = 4.
        struct Growth;
        impl OdeSystem for Growth {
            type Error = ();
            fn dim(&self) -> usize {
                1
            }
            fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
                dy[0] = y[0];
                Ok(())
            }
        }
        let mut r = Rodas4::new(1, tol(1e-6));
        r.y[0] = 1.0;
        r.f[0] = 1.0;
        r.jacobian(&mut Growth, 0.0, &mut Stats::default()).unwrap();
        assert_eq!(r.jac[0], 1.0);
        assert!(!r.factor(4.0));
        assert!(r.factor(2.0));

        // A right-hand side that is NaN next to the state: every W is
        // singular, the step halves until it is too small.
        struct NanAround;
        impl OdeSystem for NanAround {
            type Error = ();
            fn dim(&self) -> usize {
                1
            }
            fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
                dy[0] = if y[0] == 1.0 { 0.0 } else { f64::NAN };
                Ok(())
            }
        }
        let stopped = Rodas4::new(1, tol(1e-6)).integrate(&mut NanAround, 0.0, 1.0, &[1.0], |_| Ok(())).unwrap_err();
        assert!(matches!(stopped.failure, Failure::StepTooSmall { .. }), "{:?}", stopped.failure);
        assert_eq!((stopped.t, stopped.stats.accepted), (0.0, 0));
        assert!(stopped.stats.rejected > 10);
    }

    #[test]
    fn a_system_that_moves_the_state_gets_a_fresh_derivative() {
        // A rotating unit vector, renormalised after every step; the
        // dense output stays usable while the state is moved out.
        struct Circle {
            mid: f64,
        }
        impl OdeSystem for Circle {
            type Error = ();
            fn dim(&self) -> usize {
                2
            }
            fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
                dy[0] = -y[1];
                dy[1] = y[0];
                Ok(())
            }
            fn accept(&mut self, step: &dyn DenseStep, y: &mut [f64]) -> Result<bool, ()> {
                let (a, b) = step.span();
                let mut m = [0.0; 2];
                step.interpolate(0.5 * (a + b), &mut m);
                self.mid = self.mid.max((m[0].hypot(m[1]) - 1.0).abs());
                let norm = y[0].hypot(y[1]);
                y[0] /= norm;
                y[1] /= norm;
                Ok(true)
            }
        }
        let mut sys = Circle { mid: 0.0 };
        let mut r = Rodas4::new(2, tol(1e-6));
        let stats = r.integrate(&mut sys, 0.0, 5.0, &[1.0, 0.0], |_| Ok(())).unwrap();
        assert!(sys.mid < 1e-5, "midpoint radius off by {}", sys.mid);
        assert!((r.y()[0].hypot(r.y()[1]) - 1.0).abs() < 1e-15);
        assert!((r.y()[0] - 5f64.cos()).abs() < 1e-5);
        // f at the end of each step, again after each projection.
        assert!((r.f[0] + r.y[1]).abs() < 1e-15 && (r.f[1] - r.y[0]).abs() < 1e-15);
        assert!(stats.evaluations >= stats.accepted * 10, "{stats:?}");
    }

    /// The worst error of an integration over `[0, tf]` at `abstol = reltol
    /// = tol_`, in tolerances (`abstol + reltol |exact|`, per component):
    /// at the step ends, and on the dense output every `grid` seconds.
    fn errors_in_tolerances<S: OdeSystem<Error = ()>>(
        sys: &mut S,
        exact: impl Fn(f64) -> Vec<f64>,
        tf: f64,
        tol_: f64,
        grid: f64,
    ) -> (f64, f64, Stats) {
        let y0 = exact(0.0);
        let in_tolerances = |y: &[f64], t: f64| -> f64 {
            let x = exact(t);
            y.iter().zip(&x).map(|(y, x)| (y - x).abs() / (tol_ + tol_ * x.abs())).fold(0.0, f64::max)
        };
        let points = (tf / grid).round() as usize;
        let (mut ends, mut dense, mut next) = (0.0f64, 0.0f64, 1);
        let mut buf = vec![0.0; y0.len()];
        let stats = Rodas4::new(y0.len(), tol(tol_))
            .integrate(sys, 0.0, tf, &y0, |s| {
                let (a, b) = s.span();
                ends = ends.max(in_tolerances(s.y(), b));
                while next <= points && next as f64 * grid <= b {
                    let t = next as f64 * grid;
                    if t >= a {
                        s.interpolate(t, &mut buf);
                        dense = dense.max(in_tolerances(&buf, t));
                    }
                    next += 1;
                }
                Ok(())
            })
            .unwrap();
        assert_eq!(next, points + 1, "the grid is covered");
        (ends, dense, stats)
    }

    /// Prothero and Robinson's problem `y' = λ (y - φ(t)) + φ'(t)` with
    /// `φ(t) = sin(2πt)`: from `y(0) = φ(0)` the solution is `φ` itself, and
    /// for large `-λ` methods whose inner stages are only of low order lose
    /// order (and their error estimates with it).
    struct ProtheroRobinson {
        lambda: f64,
    }
    impl OdeSystem for ProtheroRobinson {
        type Error = ();
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
            let w = 2.0 * std::f64::consts::PI;
            dy[0] = self.lambda * (y[0] - (w * t).sin()) + w * (w * t).cos();
            Ok(())
        }
    }

    #[test]
    fn prothero_robinson_stays_within_the_tolerance_at_the_steps_and_between_them() {
        // With Hairer's Rodas4 tableau and control by k_6 alone, at
        // lambda = -1e5: 0.91 tolerances at the steps but 765 between them
        // (64 steps); at -1e8: 0.09 and 2e6 (8 steps). The Rodas4P tableau
        // alone: 0.25 and 4537 (17 steps), 0.13 and 2.7e6 (7 steps).
        let w = 2.0 * std::f64::consts::PI;
        let mut results = vec![];
        for lambda in [-1e2, -1e5, -1e8] {
            let (ends, dense, stats) =
                errors_in_tolerances(&mut ProtheroRobinson { lambda }, |t| vec![(w * t).sin()], 2.0, 1e-6, 1e-3);
            eprintln!(
                "Prothero-Robinson, lambda {lambda:e}: worst error {ends:.2} (steps) {dense:.2} (dense) tolerances, {stats:?}"
            );
            results.push((lambda, ends, dense, stats));
        }
        for (lambda, ends, dense, stats) in results {
            assert!(ends < 1.0 && dense < 1.0, "lambda {lambda}: {ends} at the steps, {dense} between them");
            assert!(stats.accepted < 200, "lambda {lambda}: {stats:?}");
        }
    }

    /// One step of Prothero and Robinson's problem from the exact state at
    /// `t = 0.3`: the output check's estimate (unweighted, in tolerances
    /// of 1e-6) and the output's actual error at `θ*`, in the same units.
    fn output_check(lambda: f64, h: f64) -> (f64, f64) {
        let (w, t) = (2.0 * std::f64::consts::PI, 0.3);
        let mut sys = ProtheroRobinson { lambda };
        let mut r = Rodas4::new(1, tol(1e-6));
        one_step(&mut r, &mut sys, t, &[(w * t).sin()], h);
        let estimate = r.dense_error(&mut sys, t, h, &mut Stats::default()).ok().unwrap() / DENSE_WEIGHT;
        r.dense_coefficients();
        (r.t_old, r.h_old) = (t, h);
        let t_check = t + DENSE_CHECK * h;
        let mut u = [0.0];
        r.interpolate(t_check, &mut u);
        let scale = 1e-6 * (1.0 + r.y[0].abs().max(r.y_new[0].abs()));
        (estimate, (u[0] - (w * t_check).sin()).abs() / scale)
    }

    #[test]
    fn the_output_check_measures_the_output_error_in_stiff_directions_and_goes_as_h4() {
        for lambda in [-1e5, -1e8] {
            let (estimate, actual) = output_check(lambda, 0.025);
            eprintln!("lambda {lambda:e}: output check {estimate:.4}, actual error {actual:.4} tolerances");
            assert!((estimate / actual - 1.0).abs() < 0.05, "{estimate} vs {actual}");
        }
        for lambda in [0.0, -1e2, -1e8] {
            let estimates: Vec<f64> = [0.04, 0.02, 0.01].iter().map(|&h| output_check(lambda, h).0).collect();
            let orders: Vec<f64> = estimates.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
            eprintln!("lambda {lambda:e}: output checks {estimates:?}, orders {orders:?}");
            for p in orders {
                assert!((3.5..4.6).contains(&p), "lambda {lambda}: order {p}");
            }
        }
    }

    /// A 1 kg slider on a spring (1e8 N/m) and a damper (1e5 N s/m) to a
    /// wall, pushed by `1e6 sin(2πt)` N: a stiff, forced problem with two
    /// real decaying modes (near -1010 and -98990 1/s) and a slow steady
    /// response.
    struct ForcedSlider;
    const FORCED_STIFFNESS: f64 = 1e8;
    const FORCED_DAMPING: f64 = 1e5;
    const FORCE: f64 = 1e6;
    impl ForcedSlider {
        /// Position and velocity at `t` from `s(0) = s0`, `v(0) = 0`.
        fn exact(t: f64, s0: f64) -> [f64; 2] {
            let w = 2.0 * std::f64::consts::PI;
            let (c, d) = (FORCED_STIFFNESS, FORCED_DAMPING);
            // Steady response a sin(wt) + b cos(wt).
            let (k, dw) = (c - w * w, d * w);
            let den = k * k + dw * dw;
            let (a, b) = (FORCE * k / den, -FORCE * dw / den);
            // The rest: u = A e^(l1 t) + B e^(l2 t) with u(0) = s0 - b, u'(0) = -a w.
            let root = (d * d - 4.0 * c).sqrt();
            let (l1, l2) = ((-d + root) / 2.0, (-d - root) / 2.0);
            let (u0, du0) = (s0 - b, -a * w);
            let big_a = (du0 - l2 * u0) / (l1 - l2);
            let big_b = u0 - big_a;
            let (e1, e2) = ((l1 * t).exp(), (l2 * t).exp());
            let (sn, cs) = ((w * t).sin(), (w * t).cos());
            [a * sn + b * cs + big_a * e1 + big_b * e2, w * (a * cs - b * sn) + l1 * big_a * e1 + l2 * big_b * e2]
        }
    }
    impl OdeSystem for ForcedSlider {
        type Error = ();
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
            dy[0] = y[1];
            dy[1] = FORCE * (2.0 * std::f64::consts::PI * t).sin() - FORCED_STIFFNESS * y[0] - FORCED_DAMPING * y[1];
            Ok(())
        }
    }

    #[test]
    fn forced_stiff_slider_stays_within_the_tolerance_at_the_steps_and_between_them() {
        // With Hairer's Rodas4 tableau and control by k_6 alone, at tol
        // 1e-6: 3.7 tolerances at the steps and 7.8 between them, with
        // 1307 steps (7 to 28 tolerances from 1e-4 to 1e-7). The Rodas4P
        // tableau alone: 0.59 and 2.3, with 167 steps.
        let s0 = 0.002;
        let exact = |t| ForcedSlider::exact(t, s0).to_vec();
        let mut results = vec![];
        for tol_ in [1e-4, 1e-5, 1e-6, 1e-7, 1e-8] {
            let (ends, dense, stats) = errors_in_tolerances(&mut ForcedSlider, exact, 2.0, tol_, 1e-3);
            eprintln!(
                "forced slider at tol {tol_:e}: worst error {ends:.2} (steps) {dense:.2} (dense) tolerances, {stats:?}"
            );
            results.push((tol_, ends, dense, stats));
        }
        for (tol_, ends, dense, stats) in results {
            assert!(ends < 1.0 && dense < 1.0, "tol {tol_}: {ends} at the steps, {dense} between them");
            if tol_ == 1e-6 {
                assert!(stats.accepted < 400, "{stats:?}");
            }
        }
    }
}
