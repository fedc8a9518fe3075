//! The native part of the `multibody` Python package: load a `.dyad`
//! model, simulate it with other parameters, start values and options,
//! and sweep it over many sets of values on every core. The Python layer
//! (`python/multibody/__init__.py`) turns the samples into numpy arrays.
//!
//! The GIL is released while simulating, so that Python threads (and a
//! Dask worker's other tasks) go on meanwhile.

use multibody::simulate::Shared;
use multibody::SimulationOptions;
use multibody_dyad::{DefinitionKind, Diagnostic, OptionOverrides, Override, Package, RunError, Samples, Target};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use rayon::prelude::*;
use std::sync::{Arc, Mutex, MutexGuard, TryLockError};

create_exception!(_multibody, MultibodyError, PyException, "Base of the errors of this package.");
create_exception!(
    _multibody,
    ModelError,
    MultibodyError,
    "The model files have an error: `args` holds the message (rendered with its place), the file, the line and the column."
);
create_exception!(
    _multibody,
    LinearizationError,
    MultibodyError,
    "No linear model or steady state at the operating point: a singular configuration, a model the derivatives do not cover, or no steady state (the message names the rates that did not settle)."
);
create_exception!(
    _multibody,
    SimulationError,
    MultibodyError,
    "The simulation stopped part way: `args` holds the message, the time it stopped, and the samples computed until then."
);

/// A parsed `.dyad` package and what of it to simulate.
#[pyclass(frozen, module = "multibody._multibody")]
struct Model {
    package: Package,
    target: Target,
    /// The analysis's (or component's) name.
    #[pyo3(get)]
    name: String,
    options: SimulationOptions,
}

/// Parses model text; `file` names it in messages.
#[pyfunction]
#[pyo3(signature = (text, file, analysis = None, model = None))]
fn load_text(text: String, file: String, analysis: Option<String>, model: Option<String>) -> PyResult<Model> {
    load_sources(vec![(file, text)], analysis, model)
}

/// Parses several model files together, `(file, text)` each (the files of
/// a folder: one may use what another defines).
#[pyfunction]
#[pyo3(signature = (sources, analysis = None, model = None))]
fn load_sources(sources: Vec<(String, String)>, analysis: Option<String>, model: Option<String>) -> PyResult<Model> {
    let mut package = Package::new();
    for (file, text) in sources {
        if let Err(d) = package.add_source(file, text) {
            return Err(model_error(&package, &d));
        }
    }
    let target = choose(&package, analysis, model)?;
    let lowered = package.lower_target(&target, &[]).map_err(|d| model_error(&package, &d))?;
    lowered.assemble().map_err(|d| model_error(&package, &d))?;
    Ok(Model { name: lowered.name.clone(), options: lowered.options.clone(), package, target })
}

/// Reads a URDF robot's text as the model `multibody import` writes (mesh
/// visuals left out: Python draws nothing); `file` names it in messages.
#[pyfunction]
#[pyo3(signature = (text, file, floating = false))]
fn load_urdf(text: String, file: String, floating: bool) -> PyResult<Model> {
    use multibody_dyad::urdf;
    let error = |e: urdf::UrdfError| {
        ModelError::new_err((e.render(&file), file.clone(), e.at.line as usize, e.at.col as usize))
    };
    let robot = urdf::parse(&text).map_err(error)?;
    let options = urdf::ImportOptions { floating, ..Default::default() };
    urdf::check_size(&robot, &options).map_err(error)?;
    let dyad = urdf::to_dyad(&robot, &file, &options);
    load_text(dyad, format!("{file}.dyad"), None, None)
}

/// The analysis or component asked for, or the only one.
fn choose(package: &Package, analysis: Option<String>, model: Option<String>) -> PyResult<Target> {
    if let Some(name) = analysis {
        return Ok(Target::Analysis(name));
    }
    if let Some(name) = model {
        return Ok(Target::Component(name));
    }
    let definitions = package.definitions();
    let analyses: Vec<String> =
        definitions.iter().filter(|d| d.kind == DefinitionKind::Analysis).map(|d| d.name.clone()).collect();
    match analyses.as_slice() {
        [one] => Ok(Target::Analysis(one.clone())),
        [] => match package.top_components().as_slice() {
            [one] => Ok(Target::Component(one.name.clone())),
            _ => Err(PyValueError::new_err("the model has no analysis and no single component: pass model=NAME")),
        },
        many => Err(PyValueError::new_err(format!(
            "the model has {} analyses ({}): pass analysis=NAME",
            many.len(),
            many.join(", ")
        ))),
    }
}

fn model_error(package: &Package, d: &Diagnostic) -> PyErr {
    let rendered = d.render(package.sources(), false);
    let place = d.primary_span().map(|span| {
        let (line, column) = package.sources().line_column(span).unwrap_or((0, 0));
        (package.sources().name(span.file).to_string(), line, column)
    });
    match place {
        Some((file, line, column)) => ModelError::new_err((rendered, file, line, column)),
        None => ModelError::new_err((rendered, Option::<String>::None, 0usize, 0usize)),
    }
}

/// Values by path, as Python gives them: `[("body.m", 2.0)]`.
type Values = Vec<(String, f64)>;

fn overrides(params: Values, initial: Values) -> Vec<Override> {
    let params = params.into_iter().map(|(path, x)| Override::parameter(path, x));
    params.chain(initial.into_iter().map(|(path, x)| Override::initial(path, x))).collect()
}

/// A run's samples as `(names, time bytes, values bytes, warnings)`: the
/// bytes are native f64, row-major values.
type Columns<'py> = (Vec<String>, Bound<'py, PyBytes>, Bound<'py, PyBytes>, Vec<String>);

fn to_python<'py>(py: Python<'py>, samples: &Samples) -> PyResult<Columns<'py>> {
    // Written straight into the Python object: one copy, no intermediate buffer.
    let bytes = |xs: &[f64]| {
        PyBytes::new_with(py, std::mem::size_of_val(xs), |buf| {
            for (chunk, x) in buf.chunks_exact_mut(8).zip(xs) {
                chunk.copy_from_slice(&x.to_ne_bytes());
            }
            Ok(())
        })
    };
    Ok((samples.names.clone(), bytes(&samples.time)?, bytes(&samples.values)?, samples.warnings.clone()))
}

/// How often a run with the GIL released looks for Ctrl-C.
const SIGNAL_CHECKS: std::time::Duration = std::time::Duration::from_millis(20);

/// Ctrl-C, seen from work that released the GIL on the interpreter's
/// thread: Python runs its signal handlers only when a thread holds the
/// GIL, so the work asks every [`SIGNAL_CHECKS`]; the handler's exception
/// (KeyboardInterrupt) is kept to be raised when the work has stopped.
struct Interrupts {
    raised: std::cell::RefCell<Option<PyErr>>,
    last: std::cell::Cell<std::time::Instant>,
}

impl Interrupts {
    fn new() -> Self {
        Self { raised: std::cell::RefCell::new(None), last: std::cell::Cell::new(std::time::Instant::now()) }
    }

    /// Whether Ctrl-C came (asking Python at most every `SIGNAL_CHECKS`).
    fn came(&self) -> bool {
        if self.raised.borrow().is_some() {
            return true;
        }
        if self.last.get().elapsed() < SIGNAL_CHECKS {
            return false;
        }
        self.last.set(std::time::Instant::now());
        match Python::attach(|py| py.check_signals()) {
            Ok(()) => false,
            Err(e) => {
                *self.raised.borrow_mut() = Some(e);
                true
            }
        }
    }

    fn into_raised(self) -> Option<PyErr> {
        self.raised.into_inner()
    }
}

impl Model {
    fn run(&self, overrides: &[Override], given: &OptionOverrides, signals: &[String]) -> Result<Samples, RunError> {
        self.package.run(&self.target, overrides, |analysis| given.over(analysis).map_err(|e| e.describe()), signals)
    }

    /// [`Model::run`] on the interpreter's thread with the GIL released,
    /// looking for Ctrl-C every [`SIGNAL_CHECKS`] (Python runs its signal
    /// handlers only when it has the GIL): an interrupted run ends after
    /// its current step with the exception the handler raised.
    fn run_interruptibly(
        &self,
        py: Python<'_>,
        overrides: &[Override],
        given: &OptionOverrides,
        signals: &[String],
    ) -> (Result<Samples, RunError>, Option<PyErr>) {
        py.detach(|| {
            let interrupts = Interrupts::new();
            let stop = || interrupts.came();
            let options = |analysis: &SimulationOptions| given.over(analysis).map_err(|e| e.describe());
            let result = self.package.run_until(&self.target, overrides, options, signals, Some(&stop));
            (result, interrupts.into_raised())
        })
    }

    fn error(&self, py: Python<'_>, e: RunError) -> PyErr {
        match e {
            RunError::Model(d) => model_error(&self.package, &d),
            RunError::Options(why) => PyValueError::new_err(why),
            RunError::Stopped { time, reason, partial } => {
                let message = format!("the simulation stopped at t = {time}: {reason}");
                let partial = to_python(py, &partial).ok().and_then(|c| c.into_pyobject(py).ok()).map(Bound::unbind);
                SimulationError::new_err((message, time, partial))
            }
        }
    }
}

#[pymethods]
impl Model {
    /// The analysis's options: start, stop, abstol, reltol, saveat, dtmax.
    #[getter]
    fn options(&self) -> Vec<(&'static str, f64)> {
        let o = &self.options;
        vec![
            ("start", o.start),
            ("stop", o.stop),
            ("abstol", o.abstol),
            ("reltol", o.reltol),
            ("saveat", o.saveat),
            ("dtmax", o.dtmax),
        ]
    }

    /// The joint-space dynamics of the model with these parameters (see
    /// `multibody::JointSpace`).
    fn joint_space(&self, params: Values) -> PyResult<JointSpace> {
        let lowered = self
            .package
            .lower_target(&self.target, &overrides(params, Vec::new()))
            .map_err(|d| model_error(&self.package, &d))?;
        let mechanism = lowered.assemble().map_err(|d| model_error(&self.package, &d))?;
        let space = multibody::JointSpace::new(Arc::new(mechanism)).map_err(PyValueError::new_err)?;
        Ok(JointSpace { space })
    }

    /// Every signal of the model, by name.
    fn signals(&self) -> PyResult<Vec<String>> {
        let lowered = self.package.lower_target(&self.target, &[]).map_err(|d| model_error(&self.package, &d))?;
        let mechanism = lowered.assemble().map_err(|d| model_error(&self.package, &d))?;
        Ok(mechanism.signals().into_iter().map(|s| s.name).collect())
    }

    /// One simulation; the GIL is released meanwhile.
    #[pyo3(signature = (params, initial, signals, stop = None, saveat = None, abstol = None, reltol = None, alg = None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        params: Values,
        initial: Values,
        signals: Vec<String>,
        stop: Option<f64>,
        saveat: Option<f64>,
        abstol: Option<f64>,
        reltol: Option<f64>,
        alg: Option<String>,
    ) -> PyResult<Columns<'py>> {
        let given = OptionOverrides { stop, saveat, abstol, reltol, alg };
        let overrides = overrides(params, initial);
        match self.run_interruptibly(py, &overrides, &given, &signals) {
            (Ok(samples), _) => to_python(py, &samples),
            // Ctrl-C: the handler's exception, with the time reached and
            // what was computed until then as its arguments.
            (Err(RunError::Stopped { time, partial, .. }), Some(raised)) => {
                let partial = to_python(py, &partial)?;
                let message = format!("interrupted at t = {time}");
                raised.value(py).setattr("args", (message, time, partial))?;
                Err(raised)
            }
            (Err(e), _) => Err(self.error(py, e)),
        }
    }

    /// The simulation of `simulate` with the analysis's values, without
    /// handing the samples to Python: the cost of the Rust call alone, for
    /// the benchmark of the Python layer's overhead. Returns the number of
    /// samples.
    fn _simulate_in_rust(&self, py: Python<'_>, signals: Vec<String>) -> PyResult<usize> {
        let run = py.detach(|| self.run(&[], &OptionOverrides::default(), &signals));
        run.map(|samples| samples.time.len()).map_err(|e| self.error(py, e))
    }

    /// A simulator of the model with these values and options, at its
    /// start: the host steps it, sets its inputs and reads its state.
    #[pyo3(signature = (params, initial, stop = None, saveat = None, abstol = None, reltol = None, alg = None))]
    #[allow(clippy::too_many_arguments)]
    fn simulator(
        &self,
        py: Python<'_>,
        params: Values,
        initial: Values,
        stop: Option<f64>,
        saveat: Option<f64>,
        abstol: Option<f64>,
        reltol: Option<f64>,
        alg: Option<String>,
    ) -> PyResult<Simulator> {
        let given = OptionOverrides { stop, saveat, abstol, reltol, alg };
        let overrides = overrides(params, initial);
        let lowered =
            self.package.lower_target(&self.target, &overrides).map_err(|d| model_error(&self.package, &d))?;
        let options = given.over(&lowered.options).map_err(|e| PyValueError::new_err(e.describe()))?;
        let mechanism = lowered.assemble().map_err(|d| model_error(&self.package, &d))?;
        let mechanism = Arc::new(mechanism);
        let sim = py.detach(|| multibody::Simulator::new(Shared::Owned(mechanism), &options));
        match sim {
            Ok(sim) => Ok(Simulator { sim: Mutex::new(sim) }),
            Err(stopped) => Err(stopped_error(py, &stopped, None)),
        }
    }

    /// Many simulations, one per set of (params, initial), on `threads`
    /// threads (all cores by default); a failed set gives its exception in
    /// its place, the others their samples.
    #[pyo3(signature = (sets, signals, threads = None, stop = None, saveat = None, abstol = None, reltol = None, alg = None))]
    #[allow(clippy::too_many_arguments)]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        sets: Vec<(Values, Values)>,
        signals: Vec<String>,
        threads: Option<usize>,
        stop: Option<f64>,
        saveat: Option<f64>,
        abstol: Option<f64>,
        reltol: Option<f64>,
        alg: Option<String>,
    ) -> PyResult<Vec<Bound<'py, PyAny>>> {
        let given = OptionOverrides { stop, saveat, abstol, reltol, alg };
        let sets: Vec<Vec<Override>> = sets.into_iter().map(|(p, i)| overrides(p, i)).collect();
        // Every run's samples are held until all are handed to Python: refused
        // before any starts when they cannot fit.
        let options = given.over(&self.options).map_err(|e| PyValueError::new_err(e.describe()))?;
        let columns = if signals.is_empty() {
            let lowered = self.package.lower_target(&self.target, &[]).map_err(|d| model_error(&self.package, &d))?;
            lowered.assemble().map_err(|d| model_error(&self.package, &d))?.states().names.len()
        } else {
            signals.len()
        };
        multibody_dyad::study::check_memory(
            &options,
            sets.len(),
            columns + 1,
            2.0,
            multibody_dyad::study::memory_budget(),
        )
        .map_err(PyValueError::new_err)?;
        // Never more threads than sets or cores (threads=100000 started a thread each).
        let threads = multibody_dyad::study::threads_for(sets.len(), threads);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| PyValueError::new_err(format!("threads={threads}: {e}")))?;
        // The runs go on other threads while this one looks for Ctrl-C,
        // which stops the runs under way; the finished ones are kept.
        let stopped = std::sync::atomic::AtomicBool::new(false);
        let (results, raised): (Vec<Result<Samples, RunError>>, Option<PyErr>) = py.detach(|| {
            std::thread::scope(|scope| {
                let runs = scope.spawn(|| {
                    let stop = || stopped.load(std::sync::atomic::Ordering::Relaxed);
                    let options = |analysis: &SimulationOptions| given.over(analysis).map_err(|e| e.describe());
                    pool.install(|| {
                        sets.par_iter()
                            .map(|set| self.package.run_until(&self.target, set, options, &signals, Some(&stop)))
                            .collect()
                    })
                });
                let interrupts = Interrupts::new();
                while !runs.is_finished() {
                    std::thread::sleep(SIGNAL_CHECKS);
                    if interrupts.came() {
                        stopped.store(true, std::sync::atomic::Ordering::Relaxed);
                    }
                }
                (runs.join().expect("the runs do not panic"), interrupts.into_raised())
            })
        });
        let interrupted = raised.is_some();
        let mut finished = 0;
        let out: Vec<Bound<'py, PyAny>> = results
            .into_iter()
            .map(|r| match r {
                Ok(samples) => {
                    finished += 1;
                    to_python(py, &samples)?.into_pyobject(py).map(|t| t.into_any())
                }
                // A run Ctrl-C stopped: no result (None) in its place.
                Err(RunError::Stopped { .. }) if interrupted => Ok(py.None().into_bound(py)),
                Err(e) => Ok(self.error(py, e).into_value(py).into_bound(py).into_any()),
            })
            .collect::<PyResult<_>>()?;
        match raised {
            None => Ok(out),
            Some(raised) => {
                let message = format!("interrupted: {finished} of {} runs finished", out.len());
                raised.value(py).setattr("args", (message, out))?;
                Err(raised)
            }
        }
    }
}

/// A model being simulated, advanced on request (the Rust `Simulator`
/// over a mechanism it shares). One thread uses it at a time: a call from
/// another thread while one runs (a step releases the GIL) is refused
/// with a `RuntimeError` that says so, not pyo3's "Already borrowed".
#[pyclass(frozen, module = "multibody._multibody")]
struct Simulator {
    sim: Mutex<multibody::Simulator<'static>>,
}

impl Simulator {
    /// The simulator, or the error of a simulator in use elsewhere. A
    /// call that panicked left it usable (each call leaves it whole or
    /// reports its own error), so a poisoned lock is taken as it is.
    fn sim(&self) -> PyResult<MutexGuard<'_, multibody::Simulator<'static>>> {
        match self.sim.try_lock() {
            Ok(sim) => Ok(sim),
            Err(TryLockError::Poisoned(poisoned)) => Ok(poisoned.into_inner()),
            Err(TryLockError::WouldBlock) => Err(PyRuntimeError::new_err(
                "this Simulator is being used by another thread (a step releases the GIL while it runs); a \
                 Simulator is not shared between threads: make one per thread, or hold a lock around its use",
            )),
        }
    }
}

/// The `SimulationError` of a simulator that stopped: its message, time,
/// and the states recorded until then.
fn stopped_error(py: Python<'_>, stopped: &multibody::Stopped, sim: Option<&multibody::Simulator>) -> PyErr {
    let message = format!("the simulation stopped at t = {}: {}", stopped.time, stopped.reason);
    let partial = sim
        .and_then(|sim| columns_of(py, sim, sim.state_names()).ok())
        .and_then(|c| c.into_pyobject(py).ok())
        .map(Bound::unbind);
    SimulationError::new_err((message, stopped.time, partial))
}

/// The samples of `names` that `sim` recorded, row-major, as `to_python`
/// gives them: gathered from its rows, without making columns.
fn columns_of<'py>(py: Python<'py>, sim: &multibody::Simulator, names: &[String]) -> PyResult<Columns<'py>> {
    let mut picks = Vec::with_capacity(names.len());
    for name in names {
        match sim.signal_index(name) {
            Some(k) => picks.push(k),
            None => {
                let hint = multibody::closest(name, sim.signal_names().iter().map(String::as_str))
                    .first()
                    .map_or(String::new(), |c| format!("; did you mean `{c}`?"));
                return Err(PyValueError::new_err(format!("the model has no signal `{name}`{hint}")));
            }
        }
    }
    let rows = sim.recorded();
    let width = picks.len();
    let all = rows.width() == width && picks.iter().enumerate().all(|(j, &k)| j == k);
    let values = PyBytes::new_with(py, rows.len() * width * 8, |buf| {
        if all {
            // Every signal in order: the rows as they are.
            for (chunk, x) in buf.chunks_exact_mut(8).zip(rows.values()) {
                chunk.copy_from_slice(&x.to_ne_bytes());
            }
        } else {
            for (i, out) in buf.chunks_exact_mut(8 * width.max(1)).enumerate() {
                let row = rows.row(i);
                for (chunk, &k) in out.chunks_exact_mut(8).zip(&picks) {
                    chunk.copy_from_slice(&row[k].to_ne_bytes());
                }
            }
        }
        Ok(())
    })?;
    let time = PyBytes::new_with(py, rows.len() * 8, |buf| {
        for (chunk, x) in buf.chunks_exact_mut(8).zip(rows.time()) {
            chunk.copy_from_slice(&x.to_ne_bytes());
        }
        Ok(())
    })?;
    Ok((names.to_vec(), time, values, sim.notes().to_vec()))
}

#[pymethods]
impl Simulator {
    /// Integrates to exactly `t`, handling the events on the way; the GIL
    /// is released meanwhile.
    fn step_until(&self, py: Python<'_>, t: f64) -> PyResult<()> {
        let mut guard = self.sim()?;
        let sim: &mut multibody::Simulator<'static> = &mut guard;
        // The samples it would record must fit in memory, as simulate()'s do.
        if let Some((samples, values)) = sim.samples_until(t) {
            let (needed, budget) = (samples * values as f64 * 8.0, multibody_dyad::study::memory_budget());
            if needed > budget {
                let when = if (1e-4..1e6).contains(&t.abs()) { format!("{t}") } else { format!("{t:e}") };
                return Err(PyValueError::new_err(format!(
                    "step_until({when}) would record {samples:.3e} samples of {values} values ({}) from t = {}, more \
                     than this process may fill ({}): step to an earlier time, read the results and call \
                     reset() or go on in shorter stretches, or give a longer saveat",
                    multibody_dyad::study::bytes(needed),
                    sim.time(),
                    multibody_dyad::study::bytes(budget)
                )));
            }
        }
        let (result, raised) = py.detach(|| {
            let interrupts = Interrupts::new();
            let mut progress = |_t: f64| if interrupts.came() { Err("interrupted".to_string()) } else { Ok(()) };
            let result = sim.step_until_with(t, Some(&mut progress));
            (result, interrupts.into_raised())
        });
        match (result, raised) {
            (Ok(()), _) => Ok(()),
            // Ctrl-C: the handler's exception with the time reached and the
            // states recorded; the simulator stays there and can go on.
            (Err(stopped), Some(raised)) => {
                let partial = columns_of(py, sim, sim.state_names())?;
                let message = format!("interrupted at t = {}", stopped.time);
                raised.value(py).setattr("args", (message, stopped.time, partial))?;
                Err(raised)
            }
            (Err(stopped), None) => Err(stopped_error(py, &stopped, Some(sim))),
        }
    }

    /// Sets an input; it holds this value until set again.
    fn set_input(&self, name: &str, value: f64) -> PyResult<()> {
        self.sim()?.set_input(name, value).map_err(PyValueError::new_err)
    }

    /// The inputs and the values they hold, in model order.
    fn inputs(&self) -> PyResult<Vec<(String, f64)>> {
        let sim = self.sim()?;
        let names: Vec<String> = sim.input_names().iter().map(|n| n.to_string()).collect();
        Ok(names.into_iter().map(|n| (n.clone(), sim.input(&n).unwrap_or(f64::NAN))).collect())
    }

    /// The outputs at the time and state reached.
    fn outputs(&self) -> PyResult<Vec<(String, f64)>> {
        self.sim()?.outputs().map_err(PyValueError::new_err)
    }

    /// The time reached.
    fn time(&self) -> PyResult<f64> {
        Ok(self.sim()?.time())
    }

    /// The state reached (in the order of `state_names`).
    fn state(&self) -> PyResult<Vec<f64>> {
        Ok(self.sim()?.state().to_vec())
    }

    fn state_names(&self) -> PyResult<Vec<String>> {
        Ok(self.sim()?.state_names().to_vec())
    }

    /// Sets the whole state; the integrator starts again from it.
    fn set_state(&self, y: Vec<f64>) -> PyResult<()> {
        self.sim()?.set_state(&y).map_err(PyValueError::new_err)
    }

    /// Sets one state by its name.
    fn set_state_value(&self, name: &str, value: f64) -> PyResult<()> {
        self.sim()?.set_state_value(name, value).map_err(PyValueError::new_err)
    }

    /// Any variable of the model (a column of the results) now.
    fn get(&self, name: &str) -> PyResult<f64> {
        self.sim()?.value(name).map_err(PyValueError::new_err)
    }

    /// Several variables at once (one evaluation).
    fn get_many(&self, names: Vec<String>) -> PyResult<Vec<f64>> {
        self.sim()?.values(&names).map_err(PyValueError::new_err)
    }

    /// Every signal of the model, by name.
    fn signals(&self) -> PyResult<Vec<String>> {
        Ok(self.sim()?.signal_names().to_vec())
    }

    /// The samples recorded so far of `names` (the states when empty).
    fn result<'py>(&self, py: Python<'py>, names: Vec<String>) -> PyResult<Columns<'py>> {
        let sim = self.sim()?;
        let names = if names.is_empty() { sim.state_names().to_vec() } else { names };
        columns_of(py, &sim, &names)
    }

    /// Back to the start: state, time, inputs; the samples are dropped.
    fn reset(&self) -> PyResult<()> {
        let mut sim = self.sim()?;
        sim.reset().map_err(|why| SimulationError::new_err((why, sim.time(), Option::<()>::None)))
    }

    /// How many events were handled.
    fn event_count(&self) -> PyResult<usize> {
        Ok(self.sim()?.event_count())
    }

    /// The linear model at the time and state reached: state, input and
    /// output names, A, B, C, D (lists of rows), whether exact, the
    /// accuracy check, the notes, and the rates there.
    #[pyo3(signature = (inputs = None, outputs = None, derivatives = "auto"))]
    fn linearize(
        &self,
        py: Python<'_>,
        inputs: Option<Vec<String>>,
        outputs: Option<Vec<String>>,
        derivatives: &str,
    ) -> PyResult<LinearTuple> {
        let derivatives = match derivatives {
            "auto" => multibody::Derivatives::Auto,
            "exact" => multibody::Derivatives::Exact,
            "differences" => multibody::Derivatives::Differences,
            other => {
                return Err(PyValueError::new_err(format!(
                    "derivatives={other:?}: use \"auto\", \"exact\" or \"differences\""
                )))
            }
        };
        let options = multibody::LinearizeOptions { inputs, outputs, derivatives };
        let guard = self.sim()?;
        let sim: &multibody::Simulator<'static> = &guard;
        let lin = py.detach(|| sim.linearize(&options)).map_err(linearize_error)?;
        let rows = |m: &nalgebra::DMatrix<f64>| -> Vec<Vec<f64>> {
            (0..m.nrows()).map(|r| (0..m.ncols()).map(|c| m[(r, c)]).collect()).collect()
        };
        Ok((
            (lin.state_names.clone(), lin.input_names.clone(), lin.output_names.clone()),
            (rows(&lin.a), rows(&lin.b), rows(&lin.c), rows(&lin.d)),
            (lin.exact, lin.accuracy, lin.notes.clone(), lin.rates.clone(), lin.time),
        ))
    }

    /// Moves to a steady state near the state reached (Newton's method),
    /// setting the free inputs there: the largest rate left, the Newton
    /// steps taken, and the free inputs' values.
    #[pyo3(signature = (free_inputs, fixed_outputs, abstol = 1e-8, reltol = 1e-8))]
    fn steady_state(
        &self,
        py: Python<'_>,
        free_inputs: Vec<String>,
        fixed_outputs: Vec<(String, f64)>,
        abstol: f64,
        reltol: f64,
    ) -> PyResult<SteadyTuple> {
        let options =
            multibody::SteadyStateOptions { free_inputs, fixed_outputs, abstol, reltol, ..Default::default() };
        let mut guard = self.sim()?;
        let sim: &mut multibody::Simulator<'static> = &mut guard;
        let found = py.detach(|| sim.steady_state(&options)).map_err(linearize_error)?;
        Ok((found.residual, found.iterations, found.inputs))
    }
}

/// A linear model as the Python layer takes it apart.
type LinearTuple = (
    (Vec<String>, Vec<String>, Vec<String>),
    (Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<f64>>),
    (bool, Option<f64>, Vec<String>, Vec<f64>, f64),
);

/// The largest rate left, the Newton steps, and the free inputs' values.
type SteadyTuple = (f64, usize, Vec<(String, f64)>);

/// Bad names are `ValueError`s; the rest `LinearizationError`s.
/// A mechanism's mass matrix, forward and inverse dynamics and frame
/// poses by joint coordinate (the Python layer makes numpy arrays).
#[pyclass(module = "multibody._multibody")]
struct JointSpace {
    space: multibody::JointSpace,
}

#[pymethods]
impl JointSpace {
    #[getter]
    fn joints(&self) -> Vec<String> {
        self.space.joints().to_vec()
    }

    #[getter]
    fn coordinates(&self) -> Vec<String> {
        self.space.coordinates().to_vec()
    }

    #[getter]
    fn velocities(&self) -> Vec<String> {
        self.space.velocities().to_vec()
    }

    fn mass_matrix(&mut self, q: Vec<f64>) -> PyResult<Vec<f64>> {
        let n = self.space.velocities().len();
        let mut out = vec![0.0; n * n];
        self.space.mass_matrix(&q, &mut out).map_err(PyValueError::new_err)?;
        Ok(out)
    }

    fn forward_dynamics(&mut self, q: Vec<f64>, v: Vec<f64>, tau: Vec<f64>) -> PyResult<Vec<f64>> {
        let mut a = vec![0.0; self.space.velocities().len()];
        self.space.forward_dynamics(&q, &v, &tau, &mut a).map_err(PyValueError::new_err)?;
        Ok(a)
    }

    fn inverse_dynamics(&mut self, q: Vec<f64>, v: Vec<f64>, a: Vec<f64>) -> PyResult<Vec<f64>> {
        let mut tau = vec![0.0; self.space.velocities().len()];
        self.space.inverse_dynamics(&q, &v, &a, &mut tau).map_err(PyValueError::new_err)?;
        Ok(tau)
    }

    /// The frame's origin (3) and its `R` (9, row-major).
    fn frame_pose(&mut self, frame: &str, q: Vec<f64>) -> PyResult<(Vec<f64>, Vec<f64>)> {
        let pose = self.space.frame_pose(frame, &q).map_err(PyValueError::new_err)?;
        Ok((pose.r_0.to_vec(), pose.rotation.iter().flatten().copied().collect()))
    }
}

fn linearize_error(e: multibody::LinearizeError) -> PyErr {
    match e {
        multibody::LinearizeError::UnknownInput { .. } | multibody::LinearizeError::UnknownOutput { .. } => {
            PyValueError::new_err(e.to_string())
        }
        other => LinearizationError::new_err(other.to_string()),
    }
}

#[pymodule]
fn _multibody(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Model>()?;
    m.add_class::<Simulator>()?;
    m.add_class::<JointSpace>()?;
    m.add_function(wrap_pyfunction!(load_text, m)?)?;
    m.add_function(wrap_pyfunction!(load_sources, m)?)?;
    m.add_function(wrap_pyfunction!(load_urdf, m)?)?;
    m.add("MultibodyError", m.py().get_type::<MultibodyError>())?;
    m.add("ModelError", m.py().get_type::<ModelError>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    m.add("LinearizationError", m.py().get_type::<LinearizationError>())?;
    Ok(())
}
