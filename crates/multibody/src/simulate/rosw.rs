//! ROS34PW2: a Rosenbrock-W method of order 3 with an embedded order-2
//! estimate, L-stable and stiffly accurate, for stiff models whose
//! Jacobian is expensive next to a right-hand side (many states, each
//! column one evaluation): a W-method keeps its order with any matrix in
//! place of `∂f/∂y`, so the Jacobian is kept over many steps and only
//! `W = I/(hγ) - J` is factored again as the step changes. Rodas4 needs
//! the exact Jacobian at every step (`n + 1` evaluations each); here a
//! step costs four evaluations and one LU.
//!
//! - Method: J. Rang and L. Angermann, *New Rosenbrock W-methods of order
//!   3 for partial differential algebraic equations of index 1*, BIT 45
//!   (2005) 761-787, the method ROS34PW2.
//! - Numbers: its `α_ij`, `γ_ij`, `b` and `b̂` as the paper gives them
//!   (and as ODE.jl and OrdinaryDiffEq.jl tabulate them); the transformed
//!   coefficients (`a = α Γ⁻¹`, the coupling `-Γ⁻¹` below the diagonal,
//!   `m = b Γ⁻¹`) are computed from them in [`Tableau::new`]. The tests
//!   below check the order (3) and the estimate's (2) by convergence.
//!
//! # The scheme
//!
//! With `J` (kept) and `W = I/(hγ) - J`, the four stages solve
//!
//! ```text
//! W u_i = f(t + c_i h, y + Σ_{j<i} a_ij u_j) + γ_i h f_t - Σ_{j<i} (Γ⁻¹_ij / h) u_j
//! ```
//!
//! and `y_1 = y + Σ m_j u_j`, the embedded `ŷ_1 = y + Σ m̂_j u_j`; the
//! error estimate is `y_1 - ŷ_1`. `f_t` is computed at every step (one
//! evaluation): kept with `J`, as a W-method allows, it let a stiff
//! spring-damper following a sine force end its steps 1.5 tolerances off.
//! The continuous output is the cubic Hermite interpolant of `(y_0, f_0)`
//! and `(y_1, f_1)`, of the method's order. As in Rodas4, a step whose
//! estimate passes also checks that output: its defect at `θ = 3/4`,
//! filtered by `W⁻¹`, is held to half the tolerance (one evaluation more;
//! the end's `f`, needed anyway, comes first).
//!
//! # When the Jacobian is renewed
//!
//! At every start (events start again), after a rejected step whose
//! Jacobian was an earlier step's (the stale `J` may be why), and after
//! [`MAX_AGE`] accepted steps. A rejected step whose Jacobian is fresh only
//! factors `W` again for the smaller step; a step that could grow by less
//! than [`KEEP_STEP`] stays as it is, so that `W`'s factors serve again.
//!
//! All memory is allocated in [`RosW::new`]; stepping allocates nothing.

use super::integrator::{finish_step, DenseStep, Failure, Observer, OdeSystem, Reached, Stats, Stopped, Tolerances};
use super::rosenbrock;
use crate::math::dense::lu_solve;

const STAGES: usize = 4;
#[allow(clippy::excessive_precision)]
const GAMMA: f64 = 0.435_866_521_508_459;

/// ROS34PW2's `α_ij` (strictly lower), `γ_ij` (lower, `γ` on the
/// diagonal), `b` and `b̂`, untransformed, with the digits published.
#[allow(clippy::excessive_precision)]
const ALPHA: [[f64; STAGES]; STAGES] = [
    [0.0, 0.0, 0.0, 0.0],
    [8.717_330_430_169_180_1e-1, 0.0, 0.0, 0.0],
    [8.445_706_001_536_942_3e-1, -1.129_906_423_648_418_5e-1, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
];
#[allow(clippy::excessive_precision)]
const GAMMA_IJ: [[f64; STAGES]; STAGES] = [
    [GAMMA, 0.0, 0.0, 0.0],
    [-8.717_330_430_169_180_1e-1, GAMMA, 0.0, 0.0],
    [-9.033_805_701_304_408_2e-1, 5.418_067_238_809_532_6e-2, GAMMA, 0.0],
    [2.421_238_070_609_534_6e-1, -1.223_250_583_904_514_7, 5.452_602_553_351_021_4e-1, GAMMA],
];
#[allow(clippy::excessive_precision)]
const B: [f64; STAGES] = [2.421_238_070_609_534_6e-1, -1.223_250_583_904_514_7, 1.545_260_255_335_102, GAMMA];
#[allow(clippy::excessive_precision)]
const B_HAT: [f64; STAGES] =
    [3.781_090_314_581_936_9e-1, -9.604_229_221_242_317_8e-2, 5.0e-1, 2.179_332_607_542_295e-1];

/// The estimate counts double: held to the tolerance itself, the global
/// error of a stiff spring-damper following a sine force (the test in
/// `crates/multibody-cli/tests/stiff.rs`) ended 1.4 tolerances off.
const ESTIMATE_WEIGHT: f64 = 2.0;
/// Where in the step the continuous output is checked, and how much its
/// estimated error counts (as in Rodas4).
const DENSE_CHECK: f64 = 0.75;
const DENSE_WEIGHT: f64 = 2.0;
/// A step that could grow by at most this factor stays as it is (as in
/// Hairer's RADAU5): `W`'s factors then serve the next step too.
const KEEP_STEP: f64 = 1.2;
/// Accepted steps a Jacobian serves at most.
const MAX_AGE: usize = 50;
/// The estimate is of order 2: the local error goes as `h^3`.
const EXPONENT: f64 = 1.0 / 3.0;

/// The transformed coefficients.
struct Tableau {
    a: [[f64; STAGES]; STAGES],
    /// `-Γ⁻¹` below the diagonal.
    coupling: [[f64; STAGES]; STAGES],
    /// Stage times `c_i = Σ_j α_ij` and time-derivative weights `γ_i = Σ_j γ_ij`.
    c: [f64; STAGES],
    d: [f64; STAGES],
    m: [f64; STAGES],
    /// `m - m̂`: the weights of the error estimate.
    e: [f64; STAGES],
}

impl Tableau {
    fn new() -> Self {
        // Γ⁻¹ of the lower triangular Γ, column by column.
        let mut inv = [[0.0; STAGES]; STAGES];
        for j in 0..STAGES {
            for i in j..STAGES {
                let mut s = if i == j { 1.0 } else { 0.0 };
                for (k, row) in inv.iter().enumerate().take(i).skip(j) {
                    s -= GAMMA_IJ[i][k] * row[j];
                }
                inv[i][j] = s / GAMMA_IJ[i][i];
            }
        }
        let times = |row: &[f64; STAGES], j: usize| (0..STAGES).map(|k| row[k] * inv[k][j]).sum::<f64>();
        let mut t = Tableau {
            a: [[0.0; STAGES]; STAGES],
            coupling: [[0.0; STAGES]; STAGES],
            c: [0.0; STAGES],
            d: [0.0; STAGES],
            m: [0.0; STAGES],
            e: [0.0; STAGES],
        };
        for i in 0..STAGES {
            for (j, inverse) in inv[i].iter().enumerate().take(i) {
                t.a[i][j] = times(&ALPHA[i], j);
                t.coupling[i][j] = -inverse;
            }
            t.c[i] = ALPHA[i].iter().sum();
            t.d[i] = GAMMA_IJ[i].iter().sum();
            t.m[i] = times(&B, i);
            t.e[i] = t.m[i] - times(&B_HAT, i);
        }
        t
    }
}

/// The integrator's memory, allocated once.
pub struct RosW {
    pub(crate) tol: Tolerances,
    tableau: Box<Tableau>,
    /// The kept `∂f/∂y` (n x n, row-major), and `∂f/∂t` at the time `f_t_at`.
    jac: Vec<f64>,
    f_t: Vec<f64>,
    f_t_at: f64,
    /// Accepted steps since the Jacobian was computed (`None`: none yet,
    /// or it must be computed again).
    age: Option<usize>,
    /// The LU factors of `W` and their pivots, for the step `w_h` (NaN: none).
    w: Vec<f64>,
    pivots: Vec<usize>,
    w_h: f64,
    u: [Vec<f64>; STAGES],
    /// The state at the end of the last accepted step, and `f` there.
    y: Vec<f64>,
    f: Vec<f64>,
    arg: Vec<f64>,
    y_new: Vec<f64>,
    /// `f` at the end of the step tried, and the filtered defect of its output.
    f_new: Vec<f64>,
    defect: Vec<f64>,
    work: Vec<f64>,
    /// Continuous output of the last accepted step: `y_0`, `f_0`, `y_1`, `f_1`.
    cont: [Vec<f64>; 4],
    t_old: f64,
    h_old: f64,
    t: f64,
    h: f64,
    h_max: f64,
    rejected_last: bool,
    previous: Option<(f64, f64)>,
    stats: Stats,
}

impl DenseStep for RosW {
    fn span(&self) -> (f64, f64) {
        (self.t_old, self.t_old + self.h_old)
    }
    fn y(&self) -> &[f64] {
        &self.y
    }
    fn interpolate(&self, t: f64, out: &mut [f64]) {
        let h = self.h_old;
        let s = (t - self.t_old) / h;
        let (h00, h10, h01, h11) = (
            (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s),
            s * (1.0 - s) * (1.0 - s),
            s * s * (3.0 - 2.0 * s),
            s * s * (s - 1.0),
        );
        let [y0, f0, y1, f1] = &self.cont;
        for (i, x) in out.iter_mut().enumerate() {
            *x = h00 * y0[i] + h * h10 * f0[i] + h01 * y1[i] + h * h11 * f1[i];
        }
    }
}

impl RosW {
    pub fn new(n: usize, tol: Tolerances) -> Self {
        let v = || vec![0.0; n];
        Self {
            tol,
            tableau: Box::new(Tableau::new()),
            jac: vec![0.0; n * n],
            f_t: v(),
            f_t_at: f64::NAN,
            age: None,
            w: vec![0.0; n * n],
            pivots: vec![0; n],
            w_h: f64::NAN,
            u: [v(), v(), v(), v()],
            y: v(),
            f: v(),
            arg: v(),
            y_new: v(),
            f_new: v(),
            defect: v(),
            work: v(),
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

    /// Integrates from `t0` to `tf` starting at `y0` (tests).
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

    /// Starts at `(t, y)` (or starts again there after an event), with a
    /// Jacobian computed afresh at the first step.
    pub fn start<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64],
        horizon: f64,
    ) -> Result<(), Stopped<S::Error>> {
        self.y.copy_from_slice(y);
        self.t = t;
        let scratch = (&mut self.arg[..], &mut self.u[0][..]);
        let begun =
            rosenbrock::begin(sys, t, &self.y, &mut self.f, &self.tol, horizon, EXPONENT, scratch, &mut self.stats);
        (self.h_max, self.h) = begun.map_err(|e| Stopped { t, failure: Failure::Rhs(e), stats: self.stats })?;
        self.age = None;
        self.w_h = f64::NAN;
        self.f_t_at = f64::NAN;
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
        while self.t < tf {
            let t = self.t;
            if 0.1 * h.abs() <= t.abs() * f64::EPSILON * 4.0 {
                return stop(t, Failure::StepTooSmall { h, attempt: self.y_new.clone() }, self.stats);
            }
            let last = t + 1.01 * h >= tf;
            if last {
                h = tf - t;
            }
            if self.age.is_none() {
                let mut stats = self.stats;
                let computed = self.jacobian(sys, t, &mut stats);
                self.stats = stats;
                if let Err(e) = computed {
                    return stop(t, Failure::Rhs(e), self.stats);
                }
                self.age = Some(0);
                self.w_h = f64::NAN;
            }
            if t != self.f_t_at {
                let mut stats = self.stats;
                let computed = self.time_derivative(sys, t, &mut stats);
                self.stats = stats;
                if let Err(e) = computed {
                    return stop(t, Failure::Rhs(e), self.stats);
                }
                self.f_t_at = t;
            }
            if h != self.w_h && !self.factor(h) {
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
            let t_end = if last { tf } else { t + h };
            let mut err = self.error_norm();
            if err <= 1.0 {
                // The end is good enough; is the output in between?
                let mut stats = self.stats;
                let dense = self.dense_error(sys, t, t_end, h, &mut stats);
                self.stats = stats;
                match dense {
                    Ok(dense) if dense.is_nan() || dense > err => err = dense,
                    Ok(_) => {}
                    Err(e) => return stop(t, Failure::Rhs(e), self.stats),
                }
            }
            if !err.is_finite() || err > 1.0 {
                self.stats.rejected += 1;
                self.rejected_last = true;
                if self.age.is_some_and(|a| a > 0) {
                    // A kept Jacobian may be why: renew it, same step.
                    self.age = None;
                    continue;
                }
                h = if err.is_finite() { h / rosenbrock::step_factor(err, EXPONENT) } else { h * 0.1 };
                continue;
            }
            let fac = rosenbrock::accepted_factor(err, h, &mut self.previous, EXPONENT);
            let [y0, f0, ..] = &mut self.cont;
            y0.copy_from_slice(&self.y);
            f0.copy_from_slice(&self.f);
            std::mem::swap(&mut self.y, &mut self.y_new);
            std::mem::swap(&mut self.f, &mut self.f_new);
            let [_, _, y1, f1] = &mut self.cont;
            y1.copy_from_slice(&self.y);
            f1.copy_from_slice(&self.f);
            self.stats.accepted += 1;
            self.stats.error_sum += err;
            self.t_old = t;
            self.h_old = h;
            self.t = t_end;
            self.age = self.age.map(|a| a + 1).filter(|&a| a < MAX_AGE);
            let mut h_new = (h / fac).min(self.h_max);
            if self.rejected_last {
                h_new = h_new.min(h);
            }
            if (1.0..=KEEP_STEP).contains(&(h_new / h)) && !last {
                // Hardly longer: the same step keeps `W`'s factors.
                h_new = h;
            }
            self.rejected_last = false;
            self.h = h_new;
            let end = finish_step(sys, self, t_end, |s| (&mut s.y, &mut s.f, &mut s.stats), observe, true)?;
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

    /// `∂f/∂y` at `(t, self.y)` (the system's own where it has one).
    fn jacobian<S: OdeSystem>(&mut self, sys: &mut S, t: f64, stats: &mut Stats) -> Result<(), S::Error> {
        rosenbrock::jacobian(sys, t, &mut self.y, &self.f, &mut self.jac, &mut self.arg, stats)
    }

    /// `∂f/∂t` at `(t, self.y)`: at every step (a stiff component following
    /// a forcing needs the forcing's rate of the step itself).
    fn time_derivative<S: OdeSystem>(&mut self, sys: &mut S, t: f64, stats: &mut Stats) -> Result<(), S::Error> {
        rosenbrock::time_derivative(sys, t, &self.y, &self.f, &mut self.f_t, &mut self.arg, stats)
    }

    /// Forms `W = I/(hγ) - J` and factors it; false if it is singular.
    fn factor(&mut self, h: f64) -> bool {
        let factored = rosenbrock::factor(&self.jac, &mut self.w, &mut self.pivots, h * GAMMA);
        self.w_h = if factored { h } else { f64::NAN };
        factored
    }

    /// The four stages of a step of size `h` from `(t, self.y)`, and the
    /// order-3 solution in `y_new`.
    fn stages<S: OdeSystem>(&mut self, sys: &mut S, t: f64, h: f64, stats: &mut Stats) -> Result<(), S::Error> {
        let n = self.y.len();
        let tab = &self.tableau;
        for s in 0..STAGES {
            let (done, rest) = self.u.split_at_mut(s);
            let us = &mut rest[0];
            if s == 0 {
                us.copy_from_slice(&self.f);
            } else {
                for i in 0..n {
                    let mut x = self.y[i];
                    for (a, uj) in tab.a[s].iter().zip(done.iter()) {
                        x += a * uj[i];
                    }
                    self.arg[i] = x;
                }
                stats.evaluations += 1;
                sys.rhs(t + tab.c[s] * h, &self.arg, us)?;
            }
            let ht = h * tab.d[s];
            for i in 0..n {
                let mut x = us[i] + ht * self.f_t[i];
                for (c, uj) in tab.coupling[s].iter().zip(done.iter()) {
                    x += c / h * uj[i];
                }
                us[i] = x;
            }
            lu_solve(&self.w, n, &self.pivots, us, &mut self.work);
        }
        for i in 0..n {
            self.y_new[i] = self.y[i] + (0..STAGES).map(|s| tab.m[s] * self.u[s][i]).sum::<f64>();
        }
        Ok(())
    }

    /// The RMS of the estimate `Σ e_j u_j` scaled by `abstol + reltol max(|y|, |y_new|)`.
    fn error_norm(&self) -> f64 {
        let n = self.y.len();
        let mut sum = 0.0;
        for i in 0..n {
            let e: f64 = (0..STAGES).map(|s| self.tableau.e[s] * self.u[s][i]).sum();
            sum += (e / self.scale(i)) * (e / self.scale(i));
        }
        ESTIMATE_WEIGHT * (sum / n.max(1) as f64).sqrt()
    }

    fn scale(&self, i: usize) -> f64 {
        self.tol.abstol + self.tol.reltol * self.y[i].abs().max(self.y_new[i].abs())
    }

    /// `f` at the step's end (into `f_new`, which the next step starts
    /// from), and the estimated error of the step's continuous output:
    /// its defect at `θ = DENSE_CHECK` (the Hermite cubic's derivative minus
    /// `f` there) filtered by `W⁻¹`, weighted by `DENSE_WEIGHT`. A stiff
    /// component that follows a slow forcing lands on it at the step's end
    /// whatever the step, and the embedded estimate then says nothing of
    /// the output in between (Rodas4's documentation tells the story).
    fn dense_error<S: OdeSystem>(
        &mut self,
        sys: &mut S,
        t: f64,
        t_end: f64,
        h: f64,
        stats: &mut Stats,
    ) -> Result<f64, S::Error> {
        let n = self.y.len();
        stats.evaluations += 1;
        sys.rhs(t_end, &self.y_new, &mut self.f_new)?;
        let s = DENSE_CHECK;
        let (h00, h10, h01, h11) = (
            (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s),
            s * (1.0 - s) * (1.0 - s),
            s * s * (3.0 - 2.0 * s),
            s * s * (s - 1.0),
        );
        let (d00, d10, d11) = (6.0 * s * s - 6.0 * s, 3.0 * s * s - 4.0 * s + 1.0, 3.0 * s * s - 2.0 * s);
        for i in 0..n {
            let (y0, y1, f0, f1) = (self.y[i], self.y_new[i], self.f[i], self.f_new[i]);
            self.arg[i] = h00 * y0 + h * h10 * f0 + h01 * y1 + h * h11 * f1;
            self.work[i] = d00 * (y0 - y1) / h + d10 * f0 + d11 * f1;
        }
        stats.evaluations += 1;
        sys.rhs(t + s * h, &self.arg, &mut self.defect)?;
        for (d, derivative) in self.defect.iter_mut().zip(&self.work) {
            *d = derivative - *d;
        }
        lu_solve(&self.w, n, &self.pivots, &mut self.defect, &mut self.work);
        let sum: f64 = (0..n).map(|i| (self.defect[i] / self.scale(i)).powi(2)).sum();
        Ok(DENSE_WEIGHT * (sum / n.max(1) as f64).sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::super::dopri5::DormandPrince;
    use super::super::integrator::test_systems::Oscillator;
    use super::*;

    fn tol(tol: f64) -> Tolerances {
        Tolerances { abstol: tol, reltol: tol, dtmax: 0.0 }
    }

    /// One step of size `h` from (1, 0), with a fresh Jacobian: the error of
    /// the solution and of the embedded one.
    fn one_step(h: f64) -> (f64, f64) {
        let mut r = RosW::new(2, tol(1.0));
        r.y.copy_from_slice(&[1.0, 0.0]);
        r.f.copy_from_slice(&[0.0, -1.0]);
        r.jacobian(&mut Oscillator, 0.0, &mut Stats::default()).unwrap();
        r.time_derivative(&mut Oscillator, 0.0, &mut Stats::default()).unwrap();
        assert!(r.factor(h));
        r.stages(&mut Oscillator, 0.0, h, &mut Stats::default()).unwrap();
        let exact = [h.cos(), -h.sin()];
        let main = (r.y_new[0] - exact[0]).hypot(r.y_new[1] - exact[1]);
        let embedded: f64 = (0..2)
            .map(|i| {
                let e: f64 = (0..STAGES).map(|s| r.tableau.e[s] * r.u[s][i]).sum();
                (r.y_new[i] - e - exact[i]).powi(2)
            })
            .sum::<f64>()
            .sqrt();
        (main, embedded)
    }

    /// Local errors go as h^4 (order 3) and h^3 (the embedded order 2):
    /// halving the step divides them by about 16 and 8.
    #[test]
    fn the_local_errors_have_the_orders_of_the_method_and_its_estimate() {
        let (a, a_hat) = one_step(0.02);
        let (b, b_hat) = one_step(0.01);
        let (order, order_hat) = ((a / b).log2(), (a_hat / b_hat).log2());
        println!("local error orders: {order:.2} (4 expected), {order_hat:.2} (3 expected)");
        assert!((order - 4.0).abs() < 0.2 && (order_hat - 3.0).abs() < 0.2);
    }

    /// A stiff linear system, one mode at -1e4: the W-method follows the
    /// slow solution to the tolerance in far fewer evaluations than the
    /// explicit method, with a Jacobian kept over many steps.
    #[test]
    fn a_stiff_system_is_followed_with_few_jacobians() {
        struct Stiff;
        impl OdeSystem for Stiff {
            type Error = ();
            fn dim(&self) -> usize {
                2
            }
            fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), ()> {
                dy[0] = -1e4 * (y[0] - t.sin()) + t.cos();
                dy[1] = -y[1] + y[0];
                Ok(())
            }
        }
        // y0 = sin t exactly; y1' = -y1 + sin t from 0: (sin t - cos t + e^-t) / 2.
        let exact = |t: f64| [t.sin(), (t.sin() - t.cos() + (-t).exp()) / 2.0];
        let mut r = RosW::new(2, tol(1e-7));
        let stats = r.integrate(&mut Stiff, 0.0, 5.0, &[0.0, 0.0], |_| Ok(())).unwrap();
        let e = exact(5.0);
        let error = (r.y[0] - e[0]).abs().max((r.y[1] - e[1]).abs());
        let mut dp = DormandPrince::new(2, tol(1e-7));
        let explicit = dp.integrate(&mut Stiff, 0.0, 5.0, &[0.0, 0.0], |_| Ok(())).unwrap();
        println!(
            "W-method: {} steps, {} evaluations, error {error:.1e}; Dormand-Prince: {} evaluations",
            stats.accepted, stats.evaluations, explicit.evaluations
        );
        assert!(error < 1e-5, "error {error:e}");
        assert!(stats.evaluations * 20 < explicit.evaluations);
        // Jacobians (3 evaluations each) are rare: most evaluations are stages.
        // Per step: three stages, f at the end, the output's defect, f_t.
        assert!(stats.evaluations < 6 * (stats.accepted + stats.rejected) + 3 * (stats.accepted / MAX_AGE + 5));
    }

    /// The continuous output between steps is of the method's accuracy.
    #[test]
    fn the_continuous_output_follows_the_solution() {
        let mut r = RosW::new(2, tol(1e-8));
        let mut worst = 0.0f64;
        let mut out = [0.0; 2];
        r.integrate(&mut Oscillator, 0.0, 6.0, &[1.0, 0.0], |step| {
            let (a, b) = step.span();
            for k in 1..4 {
                let t = a + (b - a) * k as f64 / 4.0;
                step.interpolate(t, &mut out);
                worst = worst.max((out[0] - t.cos()).abs()).max((out[1] + t.sin()).abs());
            }
            Ok(())
        })
        .unwrap();
        println!("continuous output: worst {worst:.1e}");
        assert!(worst < 1e-6, "{worst:e}");
    }
}
