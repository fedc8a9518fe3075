//! Steady states (trim): a state where every coordinate's rate is zero,
//! with the inputs given, or with some inputs free and as many outputs
//! fixed, solved in the linear model's coordinates by pseudo-transient
//! continuation (implicit Euler steps that grow into Newton's).

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
        Self { free_inputs: Vec::new(), fixed_outputs: Vec::new(), abstol: 1e-8, reltol: 1e-8, max_iterations: 200 }
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
    // Pseudo-transient continuation: implicit Euler steps of the model's
    // own motion, `(I/dt - J) dx = f`, with `dt` growing as the rates fall
    // (by their ratio from step to step), so that the steps follow the
    // motion to where it comes to rest (a stable state, as Dyad's
    // `t -> infinity` asks, not the nearest unstable one) and end as
    // Newton's. Once within the tolerance, one plain Newton step more
    // takes the error to rounding when it helps.
    let mut dt = 0.1;
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
        let step = if settled {
            polished = true;
            newton_step(&jac, &residual)?
        } else {
            let mut w = -jac;
            for i in 0..n {
                w[(i, i)] += 1.0 / dt;
            }
            match w.clone().lu().solve(&residual) {
                Some(step) if step.iter().all(|x| x.is_finite()) => step,
                _ => newton_step(&w, &(-&residual))?,
            }
        };
        let (dx, du): (Vec<f64>, Vec<f64>) =
            (step.rows(0, n).iter().copied().collect(), step.rows(n, m).iter().copied().collect());
        let tried = residual_at(&mut ev, &dx, &du, &targets).ok().filter(|r| r.iter().all(|x| x.is_finite()));
        let norm = residual.norm();
        match tried {
            Some(r) if !settled || r.norm() < norm => {
                dt = (dt * (norm / r.norm().max(f64::MIN_POSITIVE)).clamp(0.2, 10.0)).min(1e12);
                let mut y = point.state.clone();
                ev.tangent
                    .retract(&point.mechanism.system, &mut point.ws, &point.state, &dx, &mut y)
                    .map_err(|e| LinearizeError::Dynamics(point.mechanism.describe(&e)))?;
                point.state = y;
                for (j, &k) in ev.ports.inputs.iter().enumerate() {
                    point.ws.inputs[k] = ev.inputs0[k] + du[j];
                }
            }
            // The polishing step did not help: the point is as good as it gets.
            Some(_) if settled => {}
            // A step the model cannot take (a singular place): shorter ones.
            _ => {
                dt *= 0.25;
                if dt < 1e-12 {
                    return Err(unsettled(
                        &ev,
                        &residual,
                        iterations,
                        "no steady state was found: the steps towards it fail",
                    ));
                }
            }
        }
    }
}

/// The least-norm solution of `jac step = -residual` (Newton's step where
/// some coordinates, such as a cart's position, are not restored by
/// anything and stay where they are).
fn newton_step(jac: &nalgebra::DMatrix<f64>, residual: &DVector<f64>) -> Result<DVector<f64>, LinearizeError> {
    let svd = jac.clone().svd(true, true);
    let largest = svd.singular_values.max();
    svd.solve(&(-residual), 1e-10 * largest.max(f64::MIN_POSITIVE))
        .map_err(|e| LinearizeError::NoSteadyState(e.to_string()))
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
        "{what} (after {iterations} steps the largest rate left is {:.3e}); not settled: {}",
        residual.amax(),
        named.join(", ")
    ))
}
