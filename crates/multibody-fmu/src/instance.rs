//! One instance of an FMU: its model, the values set before
//! initialization, and the simulator it runs, in safe Rust. The C
//! functions (`fmi2`, `fmi3`) only translate to and from this, and put
//! their own name before its messages (which name no function).

use crate::model::{check_token, Loaded, Settings, Source, DESCRIPTION_FILE, MODEL_FOLDER, SETTINGS_FILE};
use multibody::{Mechanism, SimulationOptions, Simulator};
use std::path::Path;
use std::sync::Arc;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    ModelExchange,
    CoSimulation,
}

/// Where the instance is in FMI's state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    Instantiated,
    Initialization,
    /// Model exchange: event mode; co-simulation: between steps.
    Event,
    /// Model exchange: continuous-time mode.
    Continuous,
    Terminated,
    /// A call failed: only freeing, resetting and reading work.
    Failed,
}

/// What an event changed (FMI 2's `fmi2EventInfo`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct EventInfo {
    pub values_changed: bool,
    pub next_event_time: Option<f64>,
}

pub struct Instance {
    pub kind: Kind,
    pub phase: Phase,
    loaded: Loaded,
    /// The value of each variable set before initialization (parameters
    /// and start values), by value reference.
    set: Vec<Option<f64>>,
    /// The inputs' names and values, in input order.
    input_names: Vec<String>,
    inputs: Vec<f64>,
    start: f64,
    stop: Option<f64>,
    tolerance: Option<f64>,
    simulator: Option<Simulator<'static>>,
    /// Scratch for reading values without allocating per call.
    columns: Vec<usize>,
    values: Vec<f64>,
    dy: Vec<f64>,
    g: Vec<f64>,
}

impl Instance {
    /// Loads the model stored in `resources`, checking that it and the
    /// description beside `resources` are the ones the FMU was exported
    /// with (`token`).
    pub fn new(resources: &Path, expected_token: &str, kind: Kind) -> Result<Instance, String> {
        let read = |path: &Path| {
            std::fs::read_to_string(path).map_err(|e| format!("cannot read the FMU's {}: {e}", path.display()))
        };
        let settings_json = read(&resources.join(SETTINGS_FILE))?;
        let settings = Settings::from_json(&settings_json)?;
        let mut files = Vec::with_capacity(settings.files.len());
        for name in &settings.files {
            // Only files of the FMU's model folder.
            if name.contains(['/', '\\']) || name.starts_with('.') {
                return Err(format!(
                    "`{SETTINGS_FILE}` names the model file `{name}`, which is not in resources/{MODEL_FOLDER}"
                ));
            }
            files.push((name.clone(), read(&resources.join(MODEL_FOLDER).join(name))?));
        }
        // The description is beside resources/ in the unzipped FMU, unless
        // the host unpacked only what the FMI standard says the FMU reads.
        let beside = resources.parent().map(|folder| folder.join(DESCRIPTION_FILE)).filter(|path| path.is_file());
        let description = beside.as_deref().map(read).transpose()?;
        check_token(expected_token, &settings_json, &files, description.as_deref())?;
        let mut loaded = Loaded::load(&files, &settings)?;
        if description.is_none() {
            loaded.warnings.push(format!(
                "{DESCRIPTION_FILE} is not beside resources/ (the host unpacked only part of the FMU): the token \
                 checked the model files, not the description"
            ));
        }
        let n = loaded.interface.variables.len();
        let inputs =
            loaded.interface.inputs.iter().map(|&vr| loaded.interface.variables[vr].start.unwrap_or(0.0)).collect();
        let start = loaded.options.start;
        let states = loaded.mechanism.states().names.len();
        let indicators = loaded.interface.indicators.len();
        let input_names = loaded.mechanism.input_names().into_iter().map(String::from).collect();
        Ok(Instance {
            input_names,
            kind,
            phase: Phase::Instantiated,
            loaded,
            set: vec![None; n],
            inputs,
            start,
            stop: None,
            tolerance: None,
            simulator: None,
            columns: Vec::new(),
            values: Vec::new(),
            dy: vec![0.0; states],
            g: vec![0.0; indicators],
        })
    }

    pub fn warnings(&self) -> &[String] {
        &self.loaded.warnings
    }

    pub fn state_count(&self) -> usize {
        self.loaded.interface.states.len()
    }

    pub fn indicator_count(&self) -> usize {
        self.loaded.interface.indicators.len()
    }

    pub fn setup_experiment(&mut self, tolerance: Option<f64>, start: f64, stop: Option<f64>) -> Result<(), String> {
        self.expect(&[Phase::Instantiated])?;
        if let Some(tol) = tolerance {
            if !(tol > 0.0 && tol < 1.0) {
                return Err(format!("the tolerance must be between 0 and 1, not {tol}"));
            }
        }
        if let Some(stop) = stop {
            if stop <= start || stop.is_nan() {
                return Err(format!("the stop time {stop} is not after the start time {start}"));
            }
        }
        (self.tolerance, self.start, self.stop) = (tolerance, start, stop);
        Ok(())
    }

    pub fn enter_initialization(&mut self) -> Result<(), String> {
        self.expect(&[Phase::Instantiated])?;
        self.phase = Phase::Initialization;
        Ok(())
    }

    /// Builds the simulator from the values set (the model lowered and
    /// assembled again if any parameter or start value changed).
    pub fn exit_initialization(&mut self) -> Result<(), String> {
        self.expect(&[Phase::Initialization])?;
        self.simulator = None;
        self.ensure_simulator()?;
        self.phase = Phase::Event;
        Ok(())
    }

    fn options(&self) -> SimulationOptions {
        let mut options = self.loaded.options.clone();
        let span = options.stop - options.start;
        options.start = self.start;
        options.stop = self.stop.unwrap_or(self.start + span.max(1.0));
        if let Some(tol) = self.tolerance {
            (options.reltol, options.abstol) = (tol, tol);
        }
        // The analysis's saveat stays: nothing is recorded, but with
        // friction it bounds the steps, as in a run.
        options
    }

    fn ensure_simulator(&mut self) -> Result<&mut Simulator<'static>, String> {
        if self.simulator.is_none() {
            let overrides: Vec<_> = self
                .set
                .iter()
                .zip(&self.loaded.interface.variables)
                .filter_map(|(value, v)| Some(v.sets.as_ref()?.clone()).zip(*value))
                .map(|(mut o, value)| {
                    o.value = multibody_dyad::eval::Val::Number(value);
                    o
                })
                .collect();
            let mechanism: Arc<Mechanism> = self.loaded.with(&overrides)?;
            let mut simulator = Simulator::for_host(mechanism, &self.options())
                .map_err(|stopped| format!("the model cannot start: {}", stopped.reason))?;
            for (name, &value) in self.input_names.iter().zip(&self.inputs) {
                simulator.set_input(name, value)?;
            }
            self.simulator = Some(simulator);
        }
        Ok(self.simulator.as_mut().expect("made just now"))
    }

    /// The call is allowed in `phases`. The message names no function:
    /// the C function the host called (FMI 2 or 3) is put before it.
    fn expect(&self, phases: &[Phase]) -> Result<(), String> {
        if phases.contains(&self.phase) {
            Ok(())
        } else {
            Err(self.not_now())
        }
    }

    fn not_now(&self) -> String {
        let state = match (self.phase, self.kind) {
            (Phase::Instantiated, _) => "instantiated, and its initialization has not begun",
            (Phase::Initialization, _) => "in initialization mode",
            (Phase::Event, Kind::ModelExchange) => "in event mode",
            (Phase::Event, Kind::CoSimulation) => "in step mode",
            (Phase::Continuous, _) => "in continuous-time mode",
            (Phase::Terminated, _) => "terminated",
            (Phase::Failed, _) => "stopped by an earlier error: reset it or free it",
        };
        format!("not allowed now: the instance is {state}")
    }

    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        if vrs.len() != out.len() {
            return Err("the value references and values differ in number".into());
        }
        let n = self.loaded.interface.variables.len();
        if let Some(&bad) = vrs.iter().find(|&&vr| vr as usize >= n) {
            return Err(format!("no variable has the value reference {bad} (the FMU has {n})"));
        }
        let before = matches!(self.phase, Phase::Instantiated | Phase::Initialization);
        // The values fixed before the run: parameters, inputs, and (before
        // initialization ends) start values.
        let mut computed = false;
        for (o, &vr) in out.iter_mut().zip(vrs) {
            let v = &self.loaded.interface.variables[vr as usize];
            match v.source {
                Source::Parameter(_) => *o = self.set[vr as usize].or(v.start).unwrap_or(0.0),
                Source::Input(i) => *o = self.inputs[i],
                Source::Time if before => *o = self.start,
                _ if before && v.exact => *o = self.set[vr as usize].or(v.start).unwrap_or(0.0),
                _ => computed = true,
            }
        }
        if !computed {
            return Ok(());
        }
        self.ensure_simulator()?;
        let Instance { loaded, simulator, columns, values, dy, g, .. } = self;
        let simulator = simulator.as_mut().expect("made above");
        columns.clear();
        let (mut derivatives, mut indicators) = (false, false);
        for &vr in vrs {
            match loaded.interface.variables[vr as usize].source {
                Source::Signal(k) => columns.push(k),
                Source::Derivative(_) => derivatives = true,
                Source::Indicator(_) => indicators = true,
                _ => {}
            }
        }
        if indicators {
            simulator.indicators(g)?;
        }
        values.resize(columns.len(), 0.0);
        if !columns.is_empty() {
            simulator.signal_values(columns, values)?;
        }
        if derivatives {
            simulator.derivatives(dy)?;
        }
        let mut next = 0;
        for (o, &vr) in out.iter_mut().zip(vrs) {
            match loaded.interface.variables[vr as usize].source {
                Source::Signal(_) => {
                    *o = values[next];
                    next += 1;
                }
                Source::State(j) => *o = simulator.state()[j],
                Source::Derivative(j) => *o = dy[j],
                Source::Indicator(k) => *o = g[k],
                Source::Time => *o = simulator.time(),
                _ => {}
            }
        }
        Ok(())
    }

    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Result<(), String> {
        if vrs.len() != values.len() {
            return Err("the value references and values differ in number".into());
        }
        let n = self.loaded.interface.variables.len();
        for (&vr, &x) in vrs.iter().zip(values) {
            let Some(v) = self.loaded.interface.variables.get(vr as usize) else {
                return Err(format!("no variable has the value reference {vr} (the FMU has {n})"));
            };
            if !x.is_finite() {
                return Err(format!("`{}` cannot be set to {x}", v.name));
            }
            match v.source {
                Source::Input(i) => self.set_input_value(i, x)?,
                _ if v.exact && matches!(self.phase, Phase::Instantiated | Phase::Initialization) => {
                    self.set[vr as usize] = Some(x);
                    self.simulator = None;
                }
                _ if v.exact => {
                    return Err(format!(
                        "`{}` can only be set before initialization ends (it is a {})",
                        v.name,
                        if matches!(v.source, Source::Parameter(_)) { "fixed parameter" } else { "start value" }
                    ))
                }
                _ => return Err(format!("`{}` is computed by the model and cannot be set", v.name)),
            }
        }
        Ok(())
    }

    fn running(&mut self) -> Result<&mut Simulator<'static>, String> {
        if matches!(self.phase, Phase::Instantiated | Phase::Terminated | Phase::Failed) {
            return Err(self.not_now());
        }
        self.ensure_simulator()
    }

    // Model exchange.

    pub fn set_time(&mut self, t: f64) -> Result<(), String> {
        self.running()?.set_time(t);
        Ok(())
    }

    pub fn set_states(&mut self, x: &[f64]) -> Result<(), String> {
        self.running()?.set_continuous_state(x)
    }

    pub fn get_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        let sim = self.running()?;
        if x.len() != sim.state().len() {
            return Err(format!("the model has {} states, not {}", sim.state().len(), x.len()));
        }
        x.copy_from_slice(sim.state());
        Ok(())
    }

    pub fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        self.running()?.derivatives(dx)
    }

    pub fn indicators(&mut self, g: &mut [f64]) -> Result<(), String> {
        self.running()?.indicators(g)
    }

    pub fn enter_event_mode(&mut self) -> Result<(), String> {
        self.expect(&[Phase::Continuous, Phase::Event])?;
        self.phase = Phase::Event;
        Ok(())
    }

    pub fn new_discrete_states(&mut self) -> Result<EventInfo, String> {
        self.expect(&[Phase::Event])?;
        let update = self.running()?.update_at_event()?;
        Ok(EventInfo { values_changed: update.state_changed, next_event_time: update.next_time_event })
    }

    pub fn enter_continuous_time_mode(&mut self) -> Result<(), String> {
        self.expect(&[Phase::Event])?;
        self.phase = Phase::Continuous;
        Ok(())
    }

    /// The derivative of the variables `unknowns` (derivatives, outputs,
    /// any computed variable) along `seed` on the `knowns` (states and
    /// inputs), at the time, state and inputs set: central differences,
    /// Richardson-extrapolated (error about 1e-10 relative on smooth
    /// models). The state and inputs are restored.
    pub fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        seed: &[f64],
        out: &mut [f64],
    ) -> Result<(), String> {
        if knowns.len() != seed.len() || unknowns.len() != out.len() {
            return Err("the seed and the knowns, or the result and the unknowns, differ in number".into());
        }
        let interface = &self.loaded.interface;
        // Each known: a state (its position) or an input.
        let mut moved = Vec::with_capacity(knowns.len());
        for &vr in knowns {
            let state = interface.states.iter().position(|&k| k == vr as usize);
            match (state, interface.variables.get(vr as usize).map(|v| v.source)) {
                (Some(j), _) => moved.push((true, j)),
                (None, Some(Source::Input(i))) => moved.push((false, i)),
                (None, Some(_)) => {
                    let name = &interface.variables[vr as usize].name;
                    return Err(format!("`{name}` is neither a state nor an input, so not a known of a derivative"));
                }
                (None, None) => return Err(format!("no variable has the value reference {vr}")),
            }
        }
        let x0 = self.running()?.state().to_vec();
        let u0 = self.inputs.clone();
        let size = |v: &[f64]| v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let scale =
            moved.iter().map(|&(state, k)| if state { x0[k] } else { u0[k] }).fold(1.0_f64, |m, x| m.max(x.abs()));
        let h = 1e-3 * scale / size(seed).max(f64::MIN_POSITIVE);
        let mut at = |step: f64, values: &mut [f64]| -> Result<(), String> {
            let mut x = x0.clone();
            for (&(state, k), &d) in moved.iter().zip(seed) {
                if state {
                    x[k] += step * d;
                } else {
                    self.set_input_value(k, u0[k] + step * d)?;
                }
            }
            self.running()?.set_continuous_state(&x)?;
            self.get_real(unknowns, values)
        };
        let n = unknowns.len();
        let mut f = vec![0.0; 4 * n];
        let (plus, rest) = f.split_at_mut(n);
        let (minus, rest) = rest.split_at_mut(n);
        let (half_plus, half_minus) = rest.split_at_mut(n);
        let evaluated = at(h, plus)
            .and_then(|_| at(-h, minus))
            .and_then(|_| at(h / 2.0, half_plus))
            .and_then(|_| at(-h / 2.0, half_minus));
        // Back to where the host stood, whatever happened.
        for (i, &u) in u0.iter().enumerate() {
            self.set_input_value(i, u)?;
        }
        self.running()?.set_continuous_state(&x0)?;
        evaluated?;
        for (k, o) in out.iter_mut().enumerate() {
            let d_h = (plus[k] - minus[k]) / (2.0 * h);
            let d_half = (half_plus[k] - half_minus[k]) / h;
            *o = (4.0 * d_half - d_h) / 3.0;
        }
        Ok(())
    }

    fn set_input_value(&mut self, i: usize, x: f64) -> Result<(), String> {
        self.inputs[i] = x;
        match self.simulator.as_mut() {
            Some(sim) => sim.set_input(&self.input_names[i], x),
            None => Ok(()),
        }
    }

    // Co-simulation.

    /// One communication step from `t` (the time reached) by `h`.
    pub fn do_step(&mut self, t: f64, h: f64) -> Result<(), String> {
        self.expect(&[Phase::Event])?;
        if !(h >= 0.0 && h.is_finite()) {
            return Err(format!("the communication step must be 0 or positive, not {h}"));
        }
        let sim = self.running()?;
        let now = sim.time();
        if (t - now).abs() > 1e-9 * now.abs().max(1.0) {
            return Err(format!("the step starts at t = {t}, but the FMU stands at t = {now}"));
        }
        // `t` may round a little below where the FMU stands: never back.
        sim.advance_to((t + h).max(now))
            .map_err(|stopped| format!("the simulation stopped at t = {}: {}", stopped.time, stopped.reason))
    }

    pub fn time(&self) -> f64 {
        self.simulator.as_ref().map_or(self.start, |s| s.time())
    }

    pub fn terminate(&mut self) -> Result<(), String> {
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// Back to just after instantiation.
    pub fn reset(&mut self) {
        self.phase = Phase::Instantiated;
        self.set.iter_mut().for_each(|x| *x = None);
        let interface = &self.loaded.interface;
        self.inputs = interface.inputs.iter().map(|&vr| interface.variables[vr].start.unwrap_or(0.0)).collect();
        self.simulator = None;
        (self.start, self.stop, self.tolerance) = (self.loaded.options.start, None, None);
    }

    pub fn fail(&mut self) {
        self.phase = Phase::Failed;
    }
}
