//! The FMI 3.0 C functions, over the same [`Instance`] as FMI 2.0's. Every
//! function of the standard's headers is exported (a host may look them
//! all up); those of features the description does not claim (clocks,
//! scheduled execution, FMU state, adjoint derivatives, types other
//! than Float64) give `fmi3Error` with a message, or `fmi3OK` when asked
//! for no values.

#![allow(non_snake_case, clippy::missing_safety_doc, clippy::too_many_arguments)]

use crate::host::{folder_of, instantiate, put, slice, slice_mut, text, with, Logger, Logger3};
pub use crate::host::{Status, DISCARD, ERROR, FATAL, OK, WARNING};
use crate::instance::{Instance, Kind, Phase};
use std::ffi::{c_char, c_void};

type Vr = u32;

/// `fmi3LogMessageCallback`.
pub type LogMessage = Logger3;

fn make(
    name: *const c_char,
    token: *const c_char,
    resources: *const c_char,
    logging: bool,
    environment: *mut c_void,
    logger: Option<Logger3>,
    kind: Kind,
    call: &str,
) -> *mut c_void {
    let logger = logger.map_or(Logger::None, Logger::Fmi3);
    let name = unsafe { text(name) }.unwrap_or("instance");
    instantiate(name, logger, environment, logging, call, || {
        let token = unsafe { text(token) }.ok_or("no instantiation token was given")?;
        let resources = unsafe { text(resources) }.ok_or("no resource path was given")?;
        Instance::new(&folder_of(resources)?, token, kind)
    })
}

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    name: *const c_char,
    token: *const c_char,
    resources: *const c_char,
    _visible: bool,
    logging: bool,
    environment: *mut c_void,
    logger: Option<Logger3>,
) -> *mut c_void {
    make(name, token, resources, logging, environment, logger, Kind::ModelExchange, "fmi3InstantiateModelExchange")
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    name: *const c_char,
    token: *const c_char,
    resources: *const c_char,
    _visible: bool,
    logging: bool,
    _event_mode_used: bool,
    _early_return_allowed: bool,
    _required_intermediate: *const Vr,
    _n_required_intermediate: usize,
    environment: *mut c_void,
    logger: Option<Logger3>,
    _intermediate_update: *const c_void,
) -> *mut c_void {
    make(name, token, resources, logging, environment, logger, Kind::CoSimulation, "fmi3InstantiateCoSimulation")
}

#[no_mangle]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    name: *const c_char,
    _token: *const c_char,
    _resources: *const c_char,
    _visible: bool,
    _logging: bool,
    environment: *mut c_void,
    logger: Option<Logger3>,
    _clock_update: *const c_void,
    _lock: *const c_void,
    _unlock: *const c_void,
) -> *mut c_void {
    let logger = logger.map_or(Logger::None, Logger::Fmi3);
    let name = text(name).unwrap_or("instance");
    instantiate(name, logger, environment, false, "fmi3InstantiateScheduledExecution", || {
        Err("this FMU offers model exchange and co-simulation, not scheduled execution".into())
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3FreeInstance(c: *mut c_void) {
    crate::host::free(c)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    c: *mut c_void,
    logging: bool,
    _n: usize,
    _categories: *const *const c_char,
) -> Status {
    with(c, "fmi3SetDebugLogging", |c| {
        c.logging = logging;
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    c: *mut c_void,
    tolerance_defined: bool,
    tolerance: f64,
    start: f64,
    stop_defined: bool,
    stop: f64,
) -> Status {
    with(c, "fmi3EnterInitializationMode", |c| {
        let tolerance = tolerance_defined.then_some(tolerance);
        c.instance.setup_experiment(tolerance, start, stop_defined.then_some(stop))?;
        c.instance.enter_initialization().map(|_| OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3ExitInitializationMode(c: *mut c_void) -> Status {
    with(c, "fmi3ExitInitializationMode", |c| c.instance.exit_initialization().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterEventMode(c: *mut c_void) -> Status {
    with(c, "fmi3EnterEventMode", |c| c.instance.enter_event_mode().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Terminate(c: *mut c_void) -> Status {
    with(c, "fmi3Terminate", |c| c.instance.terminate().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3Reset(c: *mut c_void) -> Status {
    with(c, "fmi3Reset", |c| {
        c.instance.reset();
        Ok(OK)
    })
}

/// Scalars only: as many values as value references.
fn scalars(nvr: usize, n: usize) -> Result<(), String> {
    if nvr == n {
        Ok(())
    } else {
        Err(format!("{nvr} value references but {n} values (every variable is a scalar)"))
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetFloat64(c: *mut c_void, vr: *const Vr, nvr: usize, v: *mut f64, n: usize) -> Status {
    with(c, "fmi3GetFloat64", |c| {
        scalars(nvr, n)?;
        c.instance.get_real(slice(vr, nvr)?, slice_mut(v, n)?).map(|_| OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetFloat64(c: *mut c_void, vr: *const Vr, nvr: usize, v: *const f64, n: usize) -> Status {
    with(c, "fmi3SetFloat64", |c| {
        scalars(nvr, n)?;
        c.instance.set_real(slice(vr, nvr)?, slice(v, n)?).map(|_| OK)
    })
}

/// A getter or setter of a type the FMU has no variables of: fine for no
/// values, an error otherwise.
unsafe fn only_float64(c: *mut c_void, call: &str, nvr: usize) -> Status {
    with(c, call, |_| if nvr == 0 { Ok(OK) } else { Err("the FMU has only Float64 variables".into()) })
}

/// The getters and setters of the types the FMU has no variables of.
macro_rules! only_float64 {
    ($($name:ident($value:ty);)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: *mut c_void, _vr: *const Vr, nvr: usize, _v: $value, _n: usize) -> Status {
            only_float64(c, stringify!($name), nvr)
        }
    )*};
}

only_float64! {
    fmi3GetFloat32(*mut f32);
    fmi3GetInt8(*mut i8);
    fmi3GetUInt8(*mut u8);
    fmi3GetInt16(*mut i16);
    fmi3GetUInt16(*mut u16);
    fmi3GetInt32(*mut i32);
    fmi3GetUInt32(*mut u32);
    fmi3GetInt64(*mut i64);
    fmi3GetUInt64(*mut u64);
    fmi3GetBoolean(*mut bool);
    fmi3GetString(*mut *const c_char);
    fmi3SetFloat32(*const f32);
    fmi3SetInt8(*const i8);
    fmi3SetUInt8(*const u8);
    fmi3SetInt16(*const i16);
    fmi3SetUInt16(*const u16);
    fmi3SetInt32(*const i32);
    fmi3SetUInt32(*const u32);
    fmi3SetInt64(*const i64);
    fmi3SetUInt64(*const u64);
    fmi3SetBoolean(*const bool);
    fmi3SetString(*const *const c_char);
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetBinary(
    c: *mut c_void,
    _vr: *const Vr,
    nvr: usize,
    _sizes: *mut usize,
    _v: *mut *const u8,
    _n: usize,
) -> Status {
    only_float64(c, "fmi3GetBinary", nvr)
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetBinary(
    c: *mut c_void,
    _vr: *const Vr,
    nvr: usize,
    _sizes: *const usize,
    _v: *const *const u8,
    _n: usize,
) -> Status {
    only_float64(c, "fmi3SetBinary", nvr)
}

/// What the description does not claim: an error with a message.
unsafe fn unsupported(c: *mut c_void, call: &str) -> Status {
    with(c, call, |_| Err("not supported by this FMU (see its modelDescription.xml)".into()))
}

/// Functions of features the FMU does not have, with their parameters.
macro_rules! not_offered {
    ($($name:ident($($arg:ident: $ty:ty),*);)*) => {$(
        #[no_mangle]
        pub unsafe extern "C" fn $name(c: *mut c_void $(, $arg: $ty)*) -> Status {
            $(let _ = $arg;)*
            unsupported(c, stringify!($name))
        }
    )*};
}

not_offered! {
    fmi3GetClock(vr: *const Vr, nvr: usize, v: *mut bool);
    fmi3SetClock(vr: *const Vr, nvr: usize, v: *const bool);
    fmi3GetFMUState(state: *mut *mut c_void);
    fmi3SetFMUState(state: *mut c_void);
    fmi3FreeFMUState(state: *mut *mut c_void);
    fmi3SerializedFMUStateSize(state: *mut c_void, size: *mut usize);
    fmi3SerializeFMUState(state: *mut c_void, bytes: *mut u8, size: usize);
    fmi3DeserializeFMUState(bytes: *const u8, size: usize, state: *mut *mut c_void);
    fmi3GetAdjointDerivative(unknowns: *const Vr, nu: usize, knowns: *const Vr, nk: usize, seed: *const f64,
        ns: usize, sensitivity: *mut f64, nsens: usize);
    fmi3EnterConfigurationMode();
    fmi3ExitConfigurationMode();
    fmi3GetIntervalDecimal(vr: *const Vr, nvr: usize, intervals: *mut f64, qualifiers: *mut i32);
    fmi3GetIntervalFraction(vr: *const Vr, nvr: usize, counters: *mut u64, resolutions: *mut u64,
        qualifiers: *mut i32);
    fmi3GetShiftDecimal(vr: *const Vr, nvr: usize, shifts: *mut f64);
    fmi3GetShiftFraction(vr: *const Vr, nvr: usize, counters: *mut u64, resolutions: *mut u64);
    fmi3SetIntervalDecimal(vr: *const Vr, nvr: usize, intervals: *const f64);
    fmi3SetIntervalFraction(vr: *const Vr, nvr: usize, counters: *const u64, resolutions: *const u64);
    fmi3SetShiftDecimal(vr: *const Vr, nvr: usize, shifts: *const f64);
    fmi3SetShiftFraction(vr: *const Vr, nvr: usize, counters: *const u64, resolutions: *const u64);
    fmi3ActivateModelPartition(clock: Vr, time: f64);
    fmi3GetOutputDerivatives(vr: *const Vr, nvr: usize, orders: *const i32, v: *mut f64, n: usize);
    fmi3GetVariableDependencies(dependent: Vr, element_dependent: *mut usize, independents: *mut Vr,
        element_independents: *mut usize, kinds: *mut i32, n: usize);
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
    c: *mut c_void,
    unknowns: *const Vr,
    n_unknowns: usize,
    knowns: *const Vr,
    n_knowns: usize,
    seed: *const f64,
    n_seed: usize,
    sensitivity: *mut f64,
    n_sensitivity: usize,
) -> Status {
    with(c, "fmi3GetDirectionalDerivative", |c| {
        scalars(n_knowns, n_seed)?;
        scalars(n_unknowns, n_sensitivity)?;
        let (unknowns, knowns) = (slice(unknowns, n_unknowns)?, slice(knowns, n_knowns)?);
        let (seed, out) = (slice(seed, n_seed)?, slice_mut(sensitivity, n_sensitivity)?);
        c.instance.directional_derivative(unknowns, knowns, seed, out).map(|_| OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(c: *mut c_void, _vr: Vr, n: *mut usize) -> Status {
    // No dependencies are given: every unknown may depend on every known.
    with(c, "fmi3GetNumberOfVariableDependencies", |_| {
        put(n, 0);
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(c: *mut c_void) -> Status {
    with(c, "fmi3EvaluateDiscreteStates", |_| Ok(OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
    c: *mut c_void,
    update_needed: *mut bool,
    terminate: *mut bool,
    nominals_changed: *mut bool,
    values_changed: *mut bool,
    next_defined: *mut bool,
    next_time: *mut f64,
) -> Status {
    with(c, "fmi3UpdateDiscreteStates", |c| {
        let update = c.instance.new_discrete_states()?;
        put(update_needed, false);
        put(terminate, false);
        put(nominals_changed, false);
        put(values_changed, update.values_changed);
        put(next_defined, update.next_event_time.is_some());
        put(next_time, update.next_event_time.unwrap_or(0.0));
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(c: *mut c_void) -> Status {
    with(c, "fmi3EnterContinuousTimeMode", |c| c.instance.enter_continuous_time_mode().map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
    c: *mut c_void,
    _no_set_prior: bool,
    enter_event_mode: *mut bool,
    terminate: *mut bool,
) -> Status {
    with(c, "fmi3CompletedIntegratorStep", |c| {
        if c.instance.phase != Phase::Continuous {
            return Err("only in continuous-time mode".into());
        }
        put(enter_event_mode, false);
        put(terminate, false);
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetTime(c: *mut c_void, time: f64) -> Status {
    with(c, "fmi3SetTime", |c| c.instance.set_time(time).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3SetContinuousStates(c: *mut c_void, x: *const f64, n: usize) -> Status {
    with(c, "fmi3SetContinuousStates", |c| c.instance.set_states(slice(x, n)?).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(c: *mut c_void, dx: *mut f64, n: usize) -> Status {
    with(c, "fmi3GetContinuousStateDerivatives", |c| c.instance.derivatives(slice_mut(dx, n)?).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetEventIndicators(c: *mut c_void, g: *mut f64, n: usize) -> Status {
    with(c, "fmi3GetEventIndicators", |c| c.instance.indicators(slice_mut(g, n)?).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetContinuousStates(c: *mut c_void, x: *mut f64, n: usize) -> Status {
    with(c, "fmi3GetContinuousStates", |c| c.instance.get_states(slice_mut(x, n)?).map(|_| OK))
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(c: *mut c_void, x: *mut f64, n: usize) -> Status {
    with(c, "fmi3GetNominalsOfContinuousStates", |c| {
        if n != c.instance.state_count() {
            return Err(format!("the model has {} states, not {n}", c.instance.state_count()));
        }
        slice_mut(x, n)?.fill(1.0);
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(c: *mut c_void, n: *mut usize) -> Status {
    with(c, "fmi3GetNumberOfEventIndicators", |c| {
        put(n, c.instance.indicator_count());
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(c: *mut c_void, n: *mut usize) -> Status {
    with(c, "fmi3GetNumberOfContinuousStates", |c| {
        put(n, c.instance.state_count());
        Ok(OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3EnterStepMode(c: *mut c_void) -> Status {
    with(c, "fmi3EnterStepMode", |c| {
        if c.instance.kind != Kind::CoSimulation {
            return Err("step mode needs an instance for co-simulation".into());
        }
        c.instance.enter_event_mode().map(|_| OK)
    })
}

#[no_mangle]
pub unsafe extern "C" fn fmi3DoStep(
    c: *mut c_void,
    t: f64,
    h: f64,
    _no_set_prior: bool,
    event_handling_needed: *mut bool,
    terminate: *mut bool,
    early_return: *mut bool,
    last_successful_time: *mut f64,
) -> Status {
    with(c, "fmi3DoStep", |c| {
        if c.instance.kind != Kind::CoSimulation {
            return Err("fmi3DoStep needs an instance for co-simulation".into());
        }
        // Events are handled inside the step.
        put(event_handling_needed, false);
        put(terminate, false);
        put(early_return, false);
        let stepped = c.instance.do_step(t, h);
        put(last_successful_time, c.instance.time());
        stepped.map(|_| OK)
    })
}
