//! What the Rosenbrock methods ([`super::rodas`], [`super::rosw`]) share:
//! `∂f/∂y` and `∂f/∂t` by forward differences, the matrix
//! `W = I/(hγ) - J` factored, and the step-size control.

use super::integrator::{initial_step, OdeSystem, Stats, Tolerances};
use crate::math::dense::lu;

/// `∂f/∂y` at `(t, y)` into `jac` (n x n, row-major): the system's own
/// where it has one, else one evaluation per column with the increment
/// `sqrt(eps · max(|y_j|, 1e-5))` of Hairer's codes, from `f = f(t, y)`.
/// `y` is restored; `scratch` holds an evaluation.
pub(super) fn jacobian<S: OdeSystem>(
    sys: &mut S,
    t: f64,
    y: &mut [f64],
    f: &[f64],
    jac: &mut [f64],
    scratch: &mut [f64],
    stats: &mut Stats,
) -> Result<(), S::Error> {
    let n = y.len();
    if sys.jacobian(t, y, jac)? {
        return Ok(());
    }
    for j in 0..n {
        let yj = y[j];
        y[j] = yj + (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
        // The increment as represented, so the quotient is exact for a linear f.
        let delta = y[j] - yj;
        stats.evaluations += 1;
        let evaluated = sys.rhs(t, y, scratch);
        y[j] = yj;
        evaluated?;
        for i in 0..n {
            jac[i * n + j] = (scratch[i] - f[i]) / delta;
        }
    }
    Ok(())
}

/// `∂f/∂t` at `(t, y)` into `f_t`, by a forward difference from `f = f(t, y)`.
pub(super) fn time_derivative<S: OdeSystem>(
    sys: &mut S,
    t: f64,
    y: &[f64],
    f: &[f64],
    f_t: &mut [f64],
    scratch: &mut [f64],
    stats: &mut Stats,
) -> Result<(), S::Error> {
    let t1 = t + (f64::EPSILON * t.abs().max(1e-5)).sqrt();
    let dt = t1 - t;
    stats.evaluations += 1;
    sys.rhs(t1, y, scratch)?;
    for ((d, a), b) in f_t.iter_mut().zip(scratch.iter()).zip(f) {
        *d = (a - b) / dt;
    }
    Ok(())
}

/// Forms `W = I/(hγ) - J` in `w` and factors it; false if it is singular.
pub(super) fn factor(jac: &[f64], w: &mut [f64], pivots: &mut [usize], h_gamma: f64) -> bool {
    let n = pivots.len();
    for (w, j) in w.iter_mut().zip(jac) {
        *w = -j;
    }
    for i in 0..n {
        w[i * n + i] += 1.0 / h_gamma;
    }
    lu(w, n, pivots)
}

const SAFETY: f64 = 0.9;
/// The smallest and largest step ratios `h_new / h`.
const FAC_MIN: f64 = 0.2;
const FAC_MAX: f64 = 6.0;

/// The divisor `fac` of the step, `h_new = h / fac`, for an error estimate
/// `err` (in tolerances) whose local error goes as `h^(1/exponent)`.
pub(super) fn step_factor(err: f64, exponent: f64) -> f64 {
    (err.powf(exponent) / SAFETY).clamp(1.0 / FAC_MAX, 1.0 / FAC_MIN)
}

/// [`step_factor`] for an accepted step of size `h`, with Gustafsson's
/// predictive correction (as Hairer's `rodas.f` does by default): also how
/// the error changed since the last accepted step `previous` (its step and
/// error), taking the more cautious step; `previous` becomes this one.
pub(super) fn accepted_factor(err: f64, h: f64, previous: &mut Option<(f64, f64)>, exponent: f64) -> f64 {
    let mut fac = step_factor(err, exponent);
    if let Some((h_prev, err_prev)) = *previous {
        let predicted =
            (h_prev / h * (err * err / err_prev).powf(exponent) / SAFETY).clamp(1.0 / FAC_MAX, 1.0 / FAC_MIN);
        fac = fac.max(predicted);
    }
    *previous = Some((h, err.max(1e-2)));
    fac
}

/// A (re)start at `(t, y)`: `f(t, y)` into `f`, and the largest step and
/// Hairer's first step for an estimate of exponent `exponent`, as
/// `(h_max, h)`; `horizon` is the largest step without `dtmax`.
#[allow(clippy::too_many_arguments)]
pub(super) fn begin<S: OdeSystem>(
    sys: &mut S,
    t: f64,
    y: &[f64],
    f: &mut [f64],
    tol: &Tolerances,
    horizon: f64,
    exponent: f64,
    scratch: (&mut [f64], &mut [f64]),
    stats: &mut Stats,
) -> Result<(f64, f64), S::Error> {
    stats.evaluations += 1;
    sys.rhs(t, y, f)?;
    let h_max = if tol.dtmax > 0.0 { tol.dtmax } else { horizon.abs() };
    let h = initial_step(sys, t, y, f, tol, h_max, exponent, scratch, stats)?;
    Ok((h_max, h))
}
