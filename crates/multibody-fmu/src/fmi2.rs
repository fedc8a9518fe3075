//! The FMI 2.0 C functions. Each translates its arguments and calls the
//! [`Instance`] inside [`crate::host::with`]: an error becomes a message
//! through the host's logger and `fmi2Error`, a panic `fmi2Fatal`.

#![allow(non_snake_case, clippy::missing_safety_doc)]

use crate::host::{folder_of, instantiate, put, slice, slice_mut, text, with, Logger, Logger2};
pub use crate::host::{Status, DISCARD, ERROR, FATAL, OK, WARNING};
use crate::instance::{Instance, Kind, Phase};
use std::ffi::{c_char, c_int, c_uint, c_void};

const TRUE: c_int = 1;
const FALSE: c_int = 0;

#[repr(C)]
pub struct CallbackFunctions {
    logger: Option<Logger2>,
    allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    step_finished: Option<unsafe extern "C" fn(*mut c_void, Status)>,
    component_environment: *mut c_void,
}

#[repr(C)]
pub struct EventInfo {
    new_discrete_states_needed: c_int,
    terminate_simulation: c_int,
    nominals_of_continuous_states_changed: c_int,
    values_of_continuous_states_changed: c_int,
    next_event_time_defined: c_int,
    next_event_time: f64,
}

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    resource_location: *const c_char,
    functions: *const CallbackFunctions,
    _visible: c_int,
    logging_on: c_int,
) -> *mut c_void {
    let functions = functions.as_ref();
    let logger = functions.and_then(|f| f.logger).map_or(Logger::None, Logger::Fmi2);
    let environment = functions.map_or(std::ptr::null_mut(), |f| f.component_environment);
    let name = text(instance_name).unwrap_or("instance");
    instantiate(name, logger, environment, logging_on != 0, "fmi2Instantiate", || {
        let kind = match fmu_type {
            0 => Kind::ModelExchange,
            1 => Kind::CoSimulation,
            other => return Err(format!("fmuType {other} is neither model exchange (0) nor co-simulation (1)")),
        };
        let guid = text(guid).ok_or("no GUID was given")?;
        let location = text(resource_location).ok_or("no resource location was given")?;
        Instance::new(&folder_of(location)?, guid, kind)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: *mut c_void) {
    crate::host::free(c)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: *mut c_void,
    logging_on: c_int,
    _n: usize,
    _categories: *const *const c_char,
) -> Status {
    with(c, "fmi2SetDebugLogging", |c| {
        c.logging = logging_on != 0;
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: *mut c_void,
    tolerance_defined: c_int,
    tolerance: f64,
    start: f64,
    stop_defined: c_int,
    stop: f64,
) -> Status {
    with(c, "fmi2SetupExperiment", |c| {
        let tolerance = (tolerance_defined != 0).then_some(tolerance);
        c.instance.setup_experiment(tolerance, start, (stop_defined != 0).then_some(stop))?;
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: *mut c_void) -> Status {
    with(c, "fmi2EnterInitializationMode", |c| c.instance.enter_initialization().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: *mut c_void) -> Status {
    with(c, "fmi2ExitInitializationMode", |c| c.instance.exit_initialization().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Terminate(c: *mut c_void) -> Status {
    with(c, "fmi2Terminate", |c| c.instance.terminate().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2Reset(c: *mut c_void) -> Status {
    with(c, "fmi2Reset", |c| {
        c.instance.reset();
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetReal(c: *mut c_void, vr: *const c_uint, n: usize, value: *mut f64) -> Status {
    with(c, "fmi2GetReal", |c| {
        c.instance.get_real(slice(vr, n)?, slice_mut(value, n)?)?;
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetReal(c: *mut c_void, vr: *const c_uint, n: usize, value: *const f64) -> Status {
    with(c, "fmi2SetReal", |c| {
        c.instance.set_real(slice(vr, n)?, slice(value, n)?)?;
        Ok(OK)
    })
}

/// The FMU has only Real variables: any other type's reference is wrong.
unsafe fn none_of_type(c: *mut c_void, call: &str, n: usize) -> Status {
    with(c, call, |_| if n == 0 { Ok(OK) } else { Err("the FMU has only Real variables".into()) })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetInteger(c: *mut c_void, _vr: *const c_uint, n: usize, _v: *mut c_int) -> Status {
    none_of_type(c, "fmi2GetInteger", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBoolean(c: *mut c_void, _vr: *const c_uint, n: usize, _v: *mut c_int) -> Status {
    none_of_type(c, "fmi2GetBoolean", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetString(c: *mut c_void, _vr: *const c_uint, n: usize, _v: *mut *const c_char) -> Status {
    none_of_type(c, "fmi2GetString", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetInteger(c: *mut c_void, _vr: *const c_uint, n: usize, _v: *const c_int) -> Status {
    none_of_type(c, "fmi2SetInteger", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetBoolean(c: *mut c_void, _vr: *const c_uint, n: usize, _v: *const c_int) -> Status {
    none_of_type(c, "fmi2SetBoolean", n)
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetString(
    c: *mut c_void,
    _vr: *const c_uint,
    n: usize,
    _v: *const *const c_char,
) -> Status {
    none_of_type(c, "fmi2SetString", n)
}

/// What the FMU does not offer (its description says so).
unsafe fn unsupported(c: *mut c_void, call: &str) -> Status {
    with(c, call, |_| Err("not supported by this FMU (see its modelDescription.xml)".into()))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetFMUstate(c: *mut c_void, _s: *mut *mut c_void) -> Status {
    unsupported(c, "fmi2GetFMUstate")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetFMUstate(c: *mut c_void, _s: *mut c_void) -> Status {
    unsupported(c, "fmi2SetFMUstate")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: *mut c_void, _s: *mut *mut c_void) -> Status {
    unsupported(c, "fmi2FreeFMUstate")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(c: *mut c_void, _s: *mut c_void, _n: *mut usize) -> Status {
    unsupported(c, "fmi2SerializedFMUstateSize")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SerializeFMUstate(c: *mut c_void, _s: *mut c_void, _b: *mut c_char, _n: usize) -> Status {
    unsupported(c, "fmi2SerializeFMUstate")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: *mut c_void,
    _b: *const c_char,
    _n: usize,
    _s: *mut *mut c_void,
) -> Status {
    unsupported(c, "fmi2DeSerializeFMUstate")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: *mut c_void,
    unknowns: *const c_uint,
    n_unknowns: usize,
    knowns: *const c_uint,
    n_knowns: usize,
    seed: *const f64,
    sensitivity: *mut f64,
) -> Status {
    with(c, "fmi2GetDirectionalDerivative", |c| {
        let (unknowns, knowns) = (slice(unknowns, n_unknowns)?, slice(knowns, n_knowns)?);
        let (seed, out) = (slice(seed, n_knowns)?, slice_mut(sensitivity, n_unknowns)?);
        c.instance.directional_derivative(unknowns, knowns, seed, out).map(|_| OK)
    })
}

// Model exchange.

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterEventMode(c: *mut c_void) -> Status {
    with(c, "fmi2EnterEventMode", |c| c.instance.enter_event_mode().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2NewDiscreteStates(c: *mut c_void, info: *mut EventInfo) -> Status {
    with(c, "fmi2NewDiscreteStates", |c| {
        let info = info.as_mut().ok_or("no event info to fill")?;
        let update = c.instance.new_discrete_states()?;
        *info = EventInfo {
            new_discrete_states_needed: FALSE,
            terminate_simulation: FALSE,
            nominals_of_continuous_states_changed: FALSE,
            values_of_continuous_states_changed: if update.values_changed { TRUE } else { FALSE },
            next_event_time_defined: if update.next_event_time.is_some() { TRUE } else { FALSE },
            next_event_time: update.next_event_time.unwrap_or(0.0),
        };
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: *mut c_void) -> Status {
    with(c, "fmi2EnterContinuousTimeMode", |c| c.instance.enter_continuous_time_mode().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
    c: *mut c_void,
    _no_set_prior: c_int,
    enter_event_mode: *mut c_int,
    terminate: *mut c_int,
) -> Status {
    with(c, "fmi2CompletedIntegratorStep", |c| {
        if c.instance.phase != Phase::Continuous {
            return Err("only in continuous-time mode".into());
        }
        put(enter_event_mode, FALSE);
        put(terminate, FALSE);
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetTime(c: *mut c_void, time: f64) -> Status {
    with(c, "fmi2SetTime", |c| c.instance.set_time(time).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2SetContinuousStates(c: *mut c_void, x: *const f64, n: usize) -> Status {
    with(c, "fmi2SetContinuousStates", |c| c.instance.set_states(slice(x, n)?).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetDerivatives(c: *mut c_void, dx: *mut f64, n: usize) -> Status {
    with(c, "fmi2GetDerivatives", |c| c.instance.derivatives(slice_mut(dx, n)?).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetEventIndicators(c: *mut c_void, g: *mut f64, n: usize) -> Status {
    with(c, "fmi2GetEventIndicators", |c| c.instance.indicators(slice_mut(g, n)?).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetContinuousStates(c: *mut c_void, x: *mut f64, n: usize) -> Status {
    with(c, "fmi2GetContinuousStates", |c| c.instance.get_states(slice_mut(x, n)?).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(c: *mut c_void, x: *mut f64, n: usize) -> Status {
    with(c, "fmi2GetNominalsOfContinuousStates", |c| {
        let x = slice_mut(x, n)?;
        if n != c.instance.state_count() {
            return Err(format!("the model has {} states, not {n}", c.instance.state_count()));
        }
        x.fill(1.0);
        Ok(OK)
    })
}

// Co-simulation.

#[no_mangle]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: *mut c_void,
    _vr: *const c_uint,
    _n: usize,
    _order: *const c_int,
    _v: *const f64,
) -> Status {
    unsupported(c, "fmi2SetRealInputDerivatives")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: *mut c_void,
    _vr: *const c_uint,
    _n: usize,
    _order: *const c_int,
    _v: *mut f64,
) -> Status {
    unsupported(c, "fmi2GetRealOutputDerivatives")
}

#[no_mangle]
pub unsafe extern "C" fn fmi2DoStep(c: *mut c_void, t: f64, h: f64, _no_set_prior: c_int) -> Status {
    with(c, "fmi2DoStep", |c| {
        if c.instance.kind != Kind::CoSimulation {
            return Err("fmi2DoStep needs an instance for co-simulation".into());
        }
        c.instance.do_step(t, h).map(|_| OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2CancelStep(c: *mut c_void) -> Status {
    with(c, "fmi2CancelStep", |_| Ok(OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStatus(c: *mut c_void, _kind: c_int, value: *mut Status) -> Status {
    with(c, "fmi2GetStatus", |_| {
        if let Some(v) = value.as_mut() {
            *v = OK;
        }
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetRealStatus(c: *mut c_void, kind: c_int, value: *mut f64) -> Status {
    with(c, "fmi2GetRealStatus", |c| {
        // fmi2LastSuccessfulTime is 2.
        if kind != 2 {
            return Ok(DISCARD);
        }
        if let Some(v) = value.as_mut() {
            *v = c.instance.time();
        }
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetIntegerStatus(c: *mut c_void, _kind: c_int, _value: *mut c_int) -> Status {
    with(c, "fmi2GetIntegerStatus", |_| Ok(DISCARD))
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetBooleanStatus(c: *mut c_void, _kind: c_int, value: *mut c_int) -> Status {
    with(c, "fmi2GetBooleanStatus", |_| {
        // Only fmi2Terminated (3) is asked of a co-simulation FMU: never.
        if let Some(v) = value.as_mut() {
            *v = FALSE;
        }
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi2GetStringStatus(c: *mut c_void, _kind: c_int, _value: *mut *const c_char) -> Status {
    with(c, "fmi2GetStringStatus", |_| Ok(DISCARD))
}
