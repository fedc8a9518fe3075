//! Linear models and steady states of a simulated model:
//! `d(dx)/dt = A dx + B du`, `dy = C dx + D du` around an operating point
//! (a time, a state and the inputs), in the coordinates of
//! [`tangent`](self::tangent) (one position and one velocity per degree of
//! freedom, with names), and the states where nothing moves.
//!
//! Derivatives come two ways. Differences: central differences with
//! per-variable steps, extrapolated (Richardson) so that their error is
//! that of rounding for smooth models, for every model. Exact: where the
//! mechanism is a tree of one-coordinate joints, the analytic derivatives
//! of its rigid-body dynamics (`dynamics::derivatives`), with the loads
//! (springs, dampers, sources, inputs: everything but inertia and uniform
//! gravity) differentiated by the same differences: those are exact too
//! where the loads are affine in the state, as springs, dampers and
//! sources are. With both, the result reports their largest difference as
//! its own accuracy check.

mod joint_space;
mod steady;
mod tangent;

pub use joint_space::JointSpace;
pub use steady::{SteadyState, SteadyStateOptions};

use crate::outputs::OutputScratch;
use crate::simulate::did_you_mean;
use crate::{Mechanism, Simulator, Workspace};
use nalgebra::DMatrix;
use tangent::{Tangent, TangentError};

/// How the derivatives are taken.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Derivatives {
    /// Exact where the model allows it, differences elsewhere; with exact
    /// derivatives, differences too, as the accuracy check.
    #[default]
    Auto,
    /// Exact only (an error where the model does not allow it); no check.
    Exact,
    /// Central differences only.
    Differences,
}

/// What to linearize.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinearizeOptions {
    /// The inputs of B and D, by name (`None`: all the model's inputs).
    pub inputs: Option<Vec<String>>,
    /// The outputs of C and D: the model's outputs or any variable of the
    /// results (`None`: the model's outputs).
    pub outputs: Option<Vec<String>>,
    pub derivatives: Derivatives,
}

/// A linear model around an operating point.
#[derive(Clone, Debug)]
pub struct Linearization {
    pub a: DMatrix<f64>,
    pub b: DMatrix<f64>,
    pub c: DMatrix<f64>,
    pub d: DMatrix<f64>,
    /// The coordinates of `A`'s rows and columns.
    pub state_names: Vec<String>,
    pub input_names: Vec<String>,
    pub output_names: Vec<String>,
    /// The operating point: time, the whole state, the inputs' values, the
    /// outputs' values, and the rates of the coordinates there (zero at an
    /// equilibrium).
    pub time: f64,
    pub state: Vec<f64>,
    pub input_values: Vec<f64>,
    pub output_values: Vec<f64>,
    pub rates: Vec<f64>,
    /// Whether A and B are exact (analytic derivatives).
    pub exact: bool,
    /// With exact derivatives and the differences beside them: their
    /// largest difference over A, B, C, D, relative to the largest entry.
    pub accuracy: Option<f64>,
    /// What the coordinates are and how the result was made, in words.
    pub notes: Vec<String>,
}

/// A pole of a linear model with its damping ratio, natural frequency
/// (rad/s) and time constant (s; infinite on the imaginary axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pole {
    pub re: f64,
    pub im: f64,
    pub damping_ratio: f64,
    pub frequency: f64,
    pub time_constant: f64,
}

impl Linearization {
    /// The eigenvalues of `A`, slowest first, with their damping.
    pub fn poles(&self) -> Vec<Pole> {
        if self.a.is_empty() {
            return Vec::new();
        }
        let mut poles: Vec<Pole> = self
            .a
            .clone()
            .complex_eigenvalues()
            .iter()
            .map(|l| {
                let frequency = l.norm();
                Pole {
                    re: l.re,
                    im: l.im,
                    damping_ratio: if frequency > 0.0 { -l.re / frequency } else { -1.0f64.copysign(l.re) },
                    frequency,
                    time_constant: 1.0 / l.re.abs(),
                }
            })
            .collect();
        poles.sort_by(|a, b| a.frequency.total_cmp(&b.frequency).then(a.im.total_cmp(&b.im)));
        poles
    }

    /// The frequency response `C (j w I - A)^-1 B + D` from input `i` to
    /// output `o` at each `w` (rad/s): `(re, im)`.
    pub fn frequency_response(&self, i: usize, o: usize, w: &[f64]) -> Vec<(f64, f64)> {
        use nalgebra::Complex;
        let n = self.a.nrows();
        if n == 0 {
            // No dynamics: the feedthrough alone.
            return w.iter().map(|_| (self.d[(o, i)], 0.0)).collect();
        }
        w.iter()
            .map(|&w| {
                let m = DMatrix::from_fn(n, n, |r, c| Complex::new(-self.a[(r, c)], if r == c { w } else { 0.0 }));
                let b = DMatrix::from_fn(n, 1, |r, _| Complex::new(self.b[(r, i)], 0.0));
                let x = m.lu().solve(&b).unwrap_or_else(|| DMatrix::from_element(n, 1, Complex::new(f64::NAN, 0.0)));
                let mut g = Complex::new(self.d[(o, i)], 0.0);
                for r in 0..n {
                    g += x[(r, 0)] * self.c[(o, r)];
                }
                (g.re, g.im)
            })
            .collect()
    }
}

/// Why a model could not be linearized or brought to a steady state.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LinearizeError {
    #[error("`{name}` is not an input of the model{hint}")]
    UnknownInput { name: String, hint: String },
    #[error("the model has no variable `{name}` to use as an output{hint}")]
    UnknownOutput { name: String, hint: String },
    #[error("the dynamics cannot be evaluated at the operating point: {0}")]
    Dynamics(String),
    #[error("the operating point is a singular configuration of a loop: its constraints have rank {rank} there, {expected} elsewhere, so the loop's coordinates are not independent (move away from the dead point)")]
    SingularLoop { rank: usize, expected: usize },
    #[error("linearizing a loop through `{0}` is not supported: its joint has quaternion coordinates (use Euler angles for it, or cut the loop elsewhere)")]
    LoopThroughQuaternion(String),
    #[error("exact derivatives do not apply to this model: {0} (use differences)")]
    NoExactDerivatives(String),
    #[error("linearizing a model with friction elements is not supported: their sticking and sliding modes switch at zero speed, where no derivative exists")]
    Friction,
    #[error("{0}")]
    NoSteadyState(String),
}

/// The operating point and what is needed to evaluate around it.
pub(crate) struct Point<'a> {
    pub mechanism: &'a Mechanism,
    pub ws: Workspace,
    pub time: f64,
    pub state: Vec<f64>,
}

impl Simulator<'_> {
    /// The linear model at the time and state reached, with the inputs as
    /// set (see [`LinearizeOptions`]).
    pub fn linearize(&self, options: &LinearizeOptions) -> Result<Linearization, LinearizeError> {
        let (mechanism, ws, time, y) = self.point();
        linearize(Point { mechanism, ws: ws.clone(), time, state: y.to_vec() }, options)
    }
}

/// Where inputs and outputs are among the model's inputs and signals.
struct Ports {
    inputs: Vec<usize>,
    input_names: Vec<String>,
    outputs: Vec<usize>,
    output_names: Vec<String>,
    /// The components whose outputs are read.
    wanted: Vec<bool>,
}

fn ports(mechanism: &Mechanism, options: &LinearizeOptions) -> Result<Ports, LinearizeError> {
    let all_inputs = mechanism.input_names();
    let input_names: Vec<String> = match &options.inputs {
        Some(names) => names.clone(),
        None => all_inputs.iter().map(|s| s.to_string()).collect(),
    };
    let mut inputs = Vec::with_capacity(input_names.len());
    for name in &input_names {
        match all_inputs.iter().position(|n| n == name) {
            Some(k) => inputs.push(k),
            None => {
                return Err(LinearizeError::UnknownInput {
                    name: name.clone(),
                    hint: if all_inputs.is_empty() {
                        " (it has none: declare a RealInput at the top of the model)".into()
                    } else {
                        format!(
                            "{} (its inputs: {})",
                            did_you_mean(name, all_inputs.iter().copied()),
                            all_inputs.join(", ")
                        )
                    },
                })
            }
        }
    }
    let output_names: Vec<String> = match &options.outputs {
        Some(names) => names.clone(),
        None => mechanism.output_names().to_vec(),
    };
    let table = mechanism.signal_table();
    let mut wanted = vec![false; mechanism.components.len()];
    let mut outputs = Vec::with_capacity(output_names.len());
    for name in &output_names {
        let Some(k) = table.index(name) else {
            return Err(LinearizeError::UnknownOutput {
                name: name.clone(),
                hint: did_you_mean(name, table.names().iter().map(String::as_str)),
            });
        };
        if let Some(owner) = table.owner(k) {
            wanted[owner] = true;
        }
        outputs.push(k);
    }
    Ok(Ports { inputs, input_names, outputs, output_names, wanted })
}

/// Evaluates the rates of the coordinates and the outputs at a
/// displacement `dx` of the coordinates and `du` of the inputs.
struct Evaluator<'a> {
    point: Point<'a>,
    tangent: Tangent,
    ports: Ports,
    /// The inputs' values at the operating point (by model input).
    inputs0: Vec<f64>,
    scratch: OutputScratch,
    row: Vec<f64>,
    y: Vec<f64>,
    dy: Vec<f64>,
}

impl<'a> Evaluator<'a> {
    fn new(mut point: Point<'a>, options: &LinearizeOptions) -> Result<Self, LinearizeError> {
        let mechanism = point.mechanism;
        if !mechanism.system.frictions.is_empty() {
            return Err(LinearizeError::Friction);
        }
        let ports = ports(mechanism, options)?;
        let tangent = Tangent::new(&mechanism.system, &mut point.ws, &point.state).map_err(|e| match e {
            TangentError::Dynamics(e) => LinearizeError::Dynamics(mechanism.describe(&e)),
            TangentError::LoopThroughQuaternion(name) => LinearizeError::LoopThroughQuaternion(name),
            TangentError::SingularLoop { rank, expected } => LinearizeError::SingularLoop { rank, expected },
        })?;
        let n = point.state.len();
        let inputs0 = point.ws.inputs.clone();
        Ok(Self {
            point,
            tangent,
            ports,
            inputs0,
            scratch: OutputScratch::default(),
            row: Vec::new(),
            y: vec![0.0; n],
            dy: vec![0.0; n],
        })
    }

    fn sizes(&self) -> (usize, usize, usize) {
        (self.tangent.len(), self.ports.inputs.len(), self.ports.outputs.len())
    }

    /// Rates into `rates` (n) and outputs into `outs` (p).
    fn eval(&mut self, dx: &[f64], du: &[f64], rates: &mut [f64], outs: &mut [f64]) -> Result<(), LinearizeError> {
        let mechanism = self.point.mechanism;
        let ws = &mut self.point.ws;
        let fail = |e: crate::DynamicsError| LinearizeError::Dynamics(mechanism.describe(&e));
        self.tangent.retract(&mechanism.system, ws, &self.point.state, dx, &mut self.y).map_err(fail)?;
        for (j, &k) in self.ports.inputs.iter().enumerate() {
            ws.inputs[k] = self.inputs0[k] + du[j];
        }
        mechanism.rhs(ws, self.point.time, &self.y, &mut self.dy).map_err(fail)?;
        if self.dy.iter().any(|x| !x.is_finite()) {
            return Err(fail(crate::DynamicsError::NotFinite));
        }
        self.tangent.rates(dx, &self.y, &self.dy, rates);
        if !outs.is_empty() {
            mechanism
                .outputs_into(ws, &mut self.scratch, self.point.time, &self.y, &mut self.row, Some(&self.ports.wanted))
                .map_err(fail)?;
            for (o, &k) in outs.iter_mut().zip(&self.ports.outputs) {
                *o = self.row[k];
            }
        }
        ws.inputs.copy_from_slice(&self.inputs0);
        Ok(())
    }

    /// `[A B; C D]` by central differences (see [`richardson`]).
    fn differences(&mut self) -> Result<DMatrix<f64>, LinearizeError> {
        let (n, m, p) = self.sizes();
        let (mut dx, mut du) = (vec![0.0; n], vec![0.0; m]);
        let columns: Vec<usize> = (0..n + m).collect();
        richardson(self, n + p, n + m, &columns, |ev, col, step, out| {
            if col < n {
                dx[col] = step;
            } else {
                du[col - n] = step;
            }
            let (r, o) = out.split_at_mut(n);
            let evaluated = ev.eval(&dx, &du, r, o);
            dx.fill(0.0);
            du.fill(0.0);
            evaluated
        })
    }

    /// The step of column `col` (a coordinate, then an input): 1e-3 of its
    /// scale (see [`Evaluator::coordinate_scales`]).
    fn step(&self, scales: &[f64], col: usize) -> f64 {
        let n = scales.len();
        1e-3 * if col < n { scales[col] } else { self.inputs0[self.ports.inputs[col - n]].abs().max(1.0) }
    }

    /// The scale of each coordinate's steps: its size at the operating
    /// point, at least 1 (angles, lengths and speeds of order one move by
    /// 1e-3 at most).
    fn coordinate_scales(&mut self) -> Vec<f64> {
        let (n, _, _) = self.sizes();
        let mut scales = vec![1.0; n];
        // The value of each coordinate is the state it names, where it has one.
        let names = &self.point.mechanism.system.states.names;
        for (s, name) in scales.iter_mut().zip(&self.tangent.names) {
            if let Some(k) = names.iter().position(|x| x == name) {
                *s = self.point.state[k].abs().max(1.0);
            }
        }
        scales
    }
}

/// Linearizes around `point`.
pub(crate) fn linearize(point: Point<'_>, options: &LinearizeOptions) -> Result<Linearization, LinearizeError> {
    let mut ev = Evaluator::new(point, options)?;
    let (n, m, p) = ev.sizes();
    let mut rates = vec![0.0; n];
    let mut output_values = vec![0.0; p];
    ev.eval(&vec![0.0; n], &vec![0.0; m], &mut rates, &mut output_values)?;
    let unsupported = ev.point.mechanism.system.derivatives_unsupported();
    let exact_jac = match (options.derivatives, &unsupported) {
        (Derivatives::Differences, _) | (Derivatives::Auto, Some(_)) => None,
        (Derivatives::Exact, Some(why)) => return Err(LinearizeError::NoExactDerivatives(why.clone())),
        (_, None) => Some(exact(&mut ev)?),
    };
    let differences = match (options.derivatives, &exact_jac) {
        (Derivatives::Exact, _) => None,
        _ => Some(ev.differences()?),
    };
    let accuracy = match (&exact_jac, &differences) {
        (Some(e), Some(d)) => {
            let largest = e.iter().fold(0.0f64, |a, x| a.max(x.abs())).max(f64::MIN_POSITIVE);
            Some((e - d).iter().fold(0.0f64, |a, x| a.max(x.abs())) / largest)
        }
        _ => None,
    };
    let exact = exact_jac.is_some();
    let jac = exact_jac.or(differences).expect("one of the two is computed");
    let mut notes = ev.tangent.notes.clone();
    notes.push(match (exact, accuracy) {
        (true, Some(a)) => format!(
            "exact derivatives of the rigid-body dynamics, loads by differences; central differences beside them differ by {a:.1e} of the largest entry"
        ),
        (true, None) => "exact derivatives of the rigid-body dynamics, loads by differences".into(),
        (false, _) => match unsupported {
            Some(why) if options.derivatives == Derivatives::Auto => {
                format!("central differences (Richardson-extrapolated); exact derivatives do not apply: {why}")
            }
            _ => "central differences (Richardson-extrapolated)".into(),
        },
    });
    Ok(Linearization {
        a: jac.view((0, 0), (n, n)).into_owned(),
        b: jac.view((0, n), (n, m)).into_owned(),
        c: jac.view((n, 0), (p, n)).into_owned(),
        d: jac.view((n, n), (p, m)).into_owned(),
        state_names: ev.tangent.names.clone(),
        input_names: ev.ports.input_names.clone(),
        output_names: ev.ports.output_names.clone(),
        time: ev.point.time,
        state: ev.point.state.clone(),
        input_values: ev.ports.inputs.iter().map(|&k| ev.inputs0[k]).collect(),
        output_values,
        rates,
        exact,
        accuracy,
        notes,
    })
}

/// `[A B; C D]` with the rigid-body part exact. For a tree every velocity
/// coordinate is a coordinate of the linear model, and
/// `du/dt = M^-1 (Q - b)` with `Q` the loads, so
/// `d(du/dt)/dx = (dud/dx at fixed Q) + M^-1 dQ/dx` and
/// `d(du/dt)/du_in = M^-1 dQ/du_in`; the positions' rows are kinematics
/// (see [`Tangent::kinematic_rows`]). The loads' derivatives, and C and D,
/// are taken by differences.
fn exact(ev: &mut Evaluator<'_>) -> Result<DMatrix<f64>, LinearizeError> {
    let (n, m, p) = ev.sizes();
    let mechanism = ev.point.mechanism;
    let system = &mechanism.system;
    let (nq, nv) = (system.states.nq, system.states.nv);
    debug_assert_eq!(n, 2 * nv, "a tree without drives or equation states");
    let fail = |e: crate::DynamicsError| LinearizeError::Dynamics(mechanism.describe(&e));
    let (t, y) = (ev.point.time, ev.point.state.clone());
    let (q, u) = y.split_at(nq);
    let mut dy = vec![0.0; y.len()];
    mechanism.rhs(&mut ev.point.ws, t, &y, &mut dy).map_err(fail)?;
    let mut work = system.derivatives_work();
    system.aba_derivatives(&mut ev.point.ws, &mut work, q, &u[..nv], &dy[nq..nq + nv]).map_err(fail)?;
    let mut jac = DMatrix::zeros(n + p, n + m);
    ev.tangent.kinematic_rows(&y, |r, c, x| jac[(r, c)] = x);
    for i in 0..nv {
        for j in 0..nv {
            jac[(nv + i, j)] = work.ddq_dq()[i * nv + j];
            jac[(nv + i, nv + j)] = work.ddq_dv()[i * nv + j];
        }
    }
    // The loads' part, and C and D, by differences.
    if system.has_state_dependent_loads() || m > 0 {
        let minv = DMatrix::from_row_slice(nv, nv, work.minv());
        let rest = minv * load_jacobian(ev)?;
        for i in 0..nv {
            for j in 0..n + m {
                jac[(nv + i, j)] += rest[(i, j)];
            }
        }
    }
    if p > 0 {
        let outputs = ev.differences()?;
        for i in 0..p {
            for j in 0..n + m {
                jac[(n + i, j)] = outputs[(n + i, j)];
            }
        }
    }
    Ok(jac)
}

/// Central differences of `f` (`rows` values of a displacement of column
/// `col` by `step`) in the `columns` given, Richardson-extrapolated:
/// `(4 D(h/2) - D(h)) / 3` has error `O(h^4)`, so steps of 1e-3 of each
/// variable's scale leave rounding (~1e-13 relative) as the error.
fn richardson(
    ev: &mut Evaluator<'_>,
    rows: usize,
    cols: usize,
    columns: &[usize],
    mut f: impl FnMut(&mut Evaluator<'_>, usize, f64, &mut [f64]) -> Result<(), LinearizeError>,
) -> Result<DMatrix<f64>, LinearizeError> {
    let mut jac = DMatrix::zeros(rows, cols);
    let (mut plus, mut minus) = (vec![0.0; rows], vec![0.0; rows]);
    let scales = ev.coordinate_scales();
    for &col in columns {
        let h = ev.step(&scales, col);
        let mut estimate = [vec![0.0; rows], vec![0.0; rows]];
        for (e, step) in estimate.iter_mut().zip([h, 0.5 * h]) {
            f(ev, col, step, &mut plus)?;
            f(ev, col, -step, &mut minus)?;
            for i in 0..rows {
                e[i] = (plus[i] - minus[i]) / (2.0 * step);
            }
        }
        for i in 0..rows {
            jac[(i, col)] = (4.0 * estimate[1][i] - estimate[0][i]) / 3.0;
        }
    }
    Ok(jac)
}

/// `dQ/d[dx, inputs]` of the generalised loads (exact to rounding for
/// affine loads); the state's columns only where the loads depend on it.
fn load_jacobian(ev: &mut Evaluator<'_>) -> Result<DMatrix<f64>, LinearizeError> {
    let (n, m, _) = ev.sizes();
    let mechanism = ev.point.mechanism;
    let system = &mechanism.system;
    let (nq, nv) = (system.states.nq, system.states.nv);
    let fail = |e: crate::DynamicsError| LinearizeError::Dynamics(mechanism.describe(&e));
    let first = if system.has_state_dependent_loads() { 0 } else { n };
    let columns: Vec<usize> = (first..n + m).collect();
    let mut y = ev.point.state.clone();
    let mut dx = vec![0.0; n];
    richardson(ev, nv, n + m, &columns, |ev, col, step, out| {
        let ws = &mut ev.point.ws;
        if col < n {
            dx[col] = step;
            let moved = ev.tangent.retract(system, ws, &ev.point.state, &dx, &mut y);
            dx[col] = 0.0;
            moved.map_err(fail)?;
        } else {
            y.copy_from_slice(&ev.point.state);
            let k = ev.ports.inputs[col - n];
            ws.inputs[k] = ev.inputs0[k] + step;
        }
        let (q, u) = y.split_at(nq);
        let evaluated = system.generalized_forces(ws, ev.point.time, q, &u[..nv], out);
        ws.inputs.copy_from_slice(&ev.inputs0);
        evaluated.map_err(fail)
    })
}
