//! Steady states (trim): a state where every coordinate's rate is zero,
//! with the inputs given, or with some inputs free and as many outputs
//! fixed. Newton's method on the rates in the linear model's coordinates,
//! with least-norm steps (coordinates nothing restores, such as a cart's
//! position, stay where they are) and a backtracking line search.

use super::{Derivatives, Evaluator, LinearizeError, LinearizeOptions, Point};
use crate::Simulator;
use nalgebra::DVector;

/// What to solve for, with Dyad's SteadyStateAnalysis tolerances.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyStateOptions {
    /// Inputs the solve may change (the others hold their values).
    pub free_inputs: Vec<String>,
    /// Outputs held at values: as many as there are free inputs.
    pub fixed_outputs: Vec<(String, f64)>,
    pub abstol: f64,
    pub reltol: f64,
    pub max_iterations: usize,
}

impl Default for SteadyStateOptions {
    fn default() -> Self {
        Self { free_inputs: Vec::new(), fixed_outputs: Vec::new(), abstol: 1e-8, reltol: 1e-8, max_iterations: 50 }
    }
}

/// A steady state found.
#[derive(Clone, Debug, PartialEq)]
pub struct SteadyState {
    /// The whole state there.
    pub state: Vec<f64>,
    /// The free inputs' values there, by name.
    pub inputs: Vec<(String, f64)>,
    /// The largest rate (or output error) left.
    pub residual: f64,
    pub iterations: usize,
}

impl Simulator<'_> {
    /// Moves the simulator to a steady state near the state reached (and
    /// sets the free inputs there): Newton's method on the rates.
    pub fn steady_state(&mut self, options: &SteadyStateOptions) -> Result<SteadyState, LinearizeError> {
        let found = {
            let (mechanism, ws, time, y) = self.point();
            solve(Point { mechanism, ws: ws.clone(), time, state: y.to_vec() }, options)?
        };
        self.set_state(&found.state).map_err(LinearizeError::Dynamics)?;
        for (name, value) in &found.inputs {
            self.set_input(name, *value).map_err(LinearizeError::Dynamics)?;
        }
        Ok(found)
    }
}

fn solve(mut point: Point<'_>, options: &SteadyStateOptions) -> Result<SteadyState, LinearizeError> {
    if options.free_inputs.len() != options.fixed_outputs.len() {
        return Err(LinearizeError::NoSteadyState(format!(
            "{} free inputs need as many fixed outputs, not {}",
            options.free_inputs.len(),
            options.fixed_outputs.len()
        )));
    }
    let lin = LinearizeOptions {
        inputs: Some(options.free_inputs.clone()),
        outputs: Some(options.fixed_outputs.iter().map(|(n, _)| n.clone()).collect()),
        derivatives: if point.mechanism.system.derivatives_unsupported().is_none() {
            Derivatives::Exact
        } else {
            Derivatives::Differences
        },
    };
    let targets: Vec<f64> = options.fixed_outputs.iter().map(|(_, v)| *v).collect();
    let within = |r: &DVector<f64>, ev: &Evaluator<'_>| {
        let scales = scales(ev);
        r.iter().zip(&scales).all(|(r, s)| r.abs() <= options.abstol + options.reltol * s)
    };
    let mut iterations = 0;
    // Once within the tolerance, one more step (Newton's last one takes
    // the error to rounding) when it helps.
    let mut polished = false;
    loop {
        let (ws, state) = (point.ws.clone(), point.state.clone());
        let mut ev = Evaluator::new(Point { mechanism: point.mechanism, ws, time: point.time, state }, &lin)?;
        let (n, m, p) = ev.sizes();
        let residual = residual_at(&mut ev, &vec![0.0; n], &vec![0.0; m], &targets)?;
        let settled = within(&residual, &ev);
        if settled && (polished || residual.amax() == 0.0) {
            let inputs = ev
                .ports
                .inputs
                .iter()
                .zip(&ev.ports.input_names)
                .map(|(&k, name)| (name.clone(), ev.inputs0[k]))
                .collect();
            return Ok(SteadyState { state: point.state, inputs, residual: residual.amax(), iterations });
        }
        if iterations == options.max_iterations {
            return Err(unsettled(&ev, &residual, iterations, "no steady state was found"));
        }
        iterations += 1;
        let jac = if lin.derivatives == Derivatives::Exact { super::exact(&mut ev)? } else { ev.differences()? };
        debug_assert_eq!(jac.shape(), (n + p, n + m));
        // Least-norm Newton step through the pseudo-inverse.
        let svd = jac.svd(true, true);
        let largest = svd.singular_values.max();
        let step = svd
            .solve(&(-&residual), 1e-10 * largest.max(f64::MIN_POSITIVE))
            .map_err(|e| LinearizeError::NoSteadyState(e.to_string()))?;
        let norm = residual.norm();
        let mut lambda = 1.0;
        let moved = loop {
            let dx: Vec<f64> = step.rows(0, n).iter().map(|s| s * lambda).collect();
            let du: Vec<f64> = step.rows(n, m).iter().map(|s| s * lambda).collect();
            let tried = residual_at(&mut ev, &dx, &du, &targets);
            if let Ok(r) = tried {
                if r.norm() < (1.0 - 1e-4 * lambda) * norm {
                    break Some((dx, du));
                }
            }
            lambda *= 0.5;
            if lambda < 1e-6 {
                break None;
            }
        };
        if settled {
            polished = true;
        }
        let Some((dx, du)) = moved else {
            if settled {
                continue;
            }
            return Err(unsettled(
                &ev,
                &residual,
                iterations,
                "no steady state was found near the start: Newton's steps no longer reduce the rates",
            ));
        };
        let mut y = point.state.clone();
        ev.tangent
            .retract(&point.mechanism.system, &mut point.ws, &point.state, &dx, &mut y)
            .map_err(|e| LinearizeError::Dynamics(point.mechanism.describe(&e)))?;
        point.state = y;
        for (j, &k) in ev.ports.inputs.iter().enumerate() {
            point.ws.inputs[k] = ev.inputs0[k] + du[j];
        }
    }
}

/// The rates and the outputs' errors at a displacement.
fn residual_at(
    ev: &mut Evaluator<'_>,
    dx: &[f64],
    du: &[f64],
    targets: &[f64],
) -> Result<DVector<f64>, LinearizeError> {
    let (n, _, p) = ev.sizes();
    let mut r = vec![0.0; n + p];
    let (rates, outs) = r.split_at_mut(n);
    ev.eval(dx, du, rates, outs)?;
    for (o, t) in outs.iter_mut().zip(targets) {
        *o -= t;
    }
    Ok(DVector::from_vec(r))
}

/// The scale each residual is judged against: its coordinate's size (at
/// least 1) for rates, the target's for outputs.
fn scales(ev: &Evaluator<'_>) -> Vec<f64> {
    let names = &ev.point.mechanism.system.states.names;
    let mut s: Vec<f64> = ev
        .tangent
        .names
        .iter()
        .map(|name| names.iter().position(|x| x == name).map_or(1.0, |k| ev.point.state[k].abs().max(1.0)))
        .collect();
    s.extend(ev.ports.output_names.iter().map(|_| 1.0));
    s
}

/// The failure, with the residual and the variables that did not settle.
fn unsettled(ev: &Evaluator<'_>, residual: &DVector<f64>, iterations: usize, what: &str) -> LinearizeError {
    let n = ev.tangent.len();
    let mut worst: Vec<(usize, f64)> = residual.iter().copied().enumerate().collect();
    worst.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    let named: Vec<String> = worst
        .iter()
        .take(5)
        .filter(|(_, r)| *r != 0.0)
        .map(|&(i, r)| {
            if i < n {
                format!("der({}) = {r:.3e}", ev.tangent.names[i])
            } else {
                format!("{} - target = {r:.3e}", ev.ports.output_names[i - n])
            }
        })
        .collect();
    LinearizeError::NoSteadyState(format!(
        "{what} (after {iterations} Newton steps the largest rate left is {:.3e}); not settled: {}",
        residual.amax(),
        named.join(", ")
    ))
}
