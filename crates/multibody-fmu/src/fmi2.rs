//! The FMI 2.0 C functions. Each translates its arguments, calls the
//! [`Instance`], and turns an error into a message through the host's
//! logger and `fmi2Error`; a panic is caught here and never crosses into
//! the host (it is reported as `fmi2Fatal`). Null pointers are accepted
//! where their size is zero.

#![allow(non_snake_case, clippy::missing_safety_doc)]

use crate::instance::{Instance, Kind, Phase};
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

pub type Status = c_int;
pub const OK: Status = 0;
pub const WARNING: Status = 1;
pub const DISCARD: Status = 2;
pub const ERROR: Status = 3;
pub const FATAL: Status = 4;

const TRUE: c_int = 1;
const FALSE: c_int = 0;

type Logger = unsafe extern "C" fn(*mut c_void, *const c_char, Status, *const c_char, *const c_char, ...);

#[repr(C)]
pub struct CallbackFunctions {
    logger: Option<Logger>,
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

/// What the host holds: the instance and how to talk to the host.
pub struct Component {
    name: CString,
    logger: Option<Logger>,
    environment: *mut c_void,
    logging: bool,
    instance: Instance,
}

impl Component {
    fn log(&self, status: Status, category: &str, message: &str) {
        let Some(logger) = self.logger else { return };
        // The message is the format string: a percent sign must not start
        // a conversion.
        let message = CString::new(message.replace('%', "%%").replace('\0', " ")).expect("no NUL left");
        let category = CString::new(category).expect("a plain category");
        unsafe { logger(self.environment, self.name.as_ptr(), status, category.as_ptr(), message.as_ptr()) };
    }
}

/// Runs `f` on the instance behind `c`: an error is logged and gives
/// `fmi2Error` (the instance then refuses to go on); a panic `fmi2Fatal`.
unsafe fn with(c: *mut c_void, call: &str, f: impl FnOnce(&mut Component) -> Result<Status, String>) -> Status {
    let Some(component) = (c as *mut Component).as_mut() else { return ERROR };
    match catch_unwind(AssertUnwindSafe(|| f(component))) {
        Ok(Ok(status)) => status,
        Ok(Err(message)) => {
            component.log(ERROR, "logStatusError", &format!("{call}: {message}"));
            component.instance.fail();
            ERROR
        }
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .map(String::as_str)
                .or_else(|| panic.downcast_ref::<&str>().copied())
                .unwrap_or("a panic");
            component.log(FATAL, "logStatusFatal", &format!("{call}: internal error: {what}"));
            component.instance.fail();
            FATAL
        }
    }
}

/// A slice from a C array, empty for a null pointer with size zero.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Result<&'a [T], String> {
    match (p.is_null(), n) {
        (_, 0) => Ok(&[]),
        (true, _) => Err(format!("a null array of {n} values")),
        (false, _) => Ok(std::slice::from_raw_parts(p, n)),
    }
}

unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Result<&'a mut [T], String> {
    match (p.is_null(), n) {
        (_, 0) => Ok(&mut []),
        (true, _) => Err(format!("a null array of {n} values")),
        (false, _) => Ok(std::slice::from_raw_parts_mut(p, n)),
    }
}

unsafe fn text<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        None
    } else {
        CStr::from_ptr(p).to_str().ok()
    }
}

/// The folder a `file:` URI names (percent escapes decoded).
fn folder_of(uri: &str) -> Result<PathBuf, String> {
    let path = uri
        .strip_prefix("file://localhost")
        .or_else(|| uri.strip_prefix("file://"))
        .or_else(|| uri.strip_prefix("file:"))
        .ok_or_else(|| format!("the resource location `{uri}` is not a file: URI"))?;
    let bytes = path.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut k = 0;
    while k < bytes.len() {
        if bytes[k] == b'%' && k + 2 < bytes.len() {
            if let Ok(b) = u8::from_str_radix(&path[k + 1..k + 3], 16) {
                out.push(b);
                k += 3;
                continue;
            }
        }
        out.push(bytes[k]);
        k += 1;
    }
    let path = String::from_utf8(out).map_err(|_| format!("the resource location `{uri}` is not UTF-8"))?;
    Ok(PathBuf::from(path))
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
    let logger = functions.and_then(|f| f.logger);
    let environment = functions.map_or(std::ptr::null_mut(), |f| f.component_environment);
    let name = text(instance_name).unwrap_or("instance").to_string();
    let report = |message: &str| {
        if let Some(logger) = logger {
            let name = CString::new(name.replace('\0', " ")).unwrap_or_default();
            let message = CString::new(message.replace('%', "%%").replace('\0', " ")).unwrap_or_default();
            logger(environment, name.as_ptr(), ERROR, c"logStatusError".as_ptr(), message.as_ptr());
        }
    };
    let made = catch_unwind(|| -> Result<Instance, String> {
        let kind = match fmu_type {
            0 => Kind::ModelExchange,
            1 => Kind::CoSimulation,
            other => return Err(format!("fmuType {other} is neither model exchange (0) nor co-simulation (1)")),
        };
        let guid = text(guid).ok_or("no GUID was given")?;
        let location = text(resource_location).ok_or("no resource location was given")?;
        Instance::new(&folder_of(location)?, guid, kind)
    });
    match made {
        Ok(Ok(instance)) => {
            let component = Box::new(Component {
                name: CString::new(name.replace('\0', " ")).unwrap_or_default(),
                logger,
                environment,
                logging: logging_on != 0,
                instance,
            });
            for w in component.instance.warnings() {
                if component.logging {
                    component.log(WARNING, "logStatusWarning", w);
                }
            }
            Box::into_raw(component) as *mut c_void
        }
        Ok(Err(message)) => {
            report(&format!("fmi2Instantiate: {message}"));
            std::ptr::null_mut()
        }
        Err(_) => {
            report("fmi2Instantiate: internal error while loading the model");
            std::ptr::null_mut()
        }
    }
}

#[no_mangle]
pub unsafe extern "C" fn fmi2FreeInstance(c: *mut c_void) {
    if !c.is_null() {
        let _ = catch_unwind(|| drop(Box::from_raw(c as *mut Component)));
    }
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
    _unknown: *const c_uint,
    _nu: usize,
    _known: *const c_uint,
    _nk: usize,
    _dv_known: *const f64,
    _dv_unknown: *mut f64,
) -> Status {
    unsupported(c, "fmi2GetDirectionalDerivative")
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
        if let Some(e) = enter_event_mode.as_mut() {
            *e = FALSE;
        }
        if let Some(t) = terminate.as_mut() {
            *t = FALSE;
        }
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

#[cfg(test)]
mod tests {
    use super::folder_of;

    #[test]
    fn resource_locations() {
        assert_eq!(folder_of("file:///tmp/a%20b/resources").unwrap().to_str(), Some("/tmp/a b/resources"));
        assert_eq!(folder_of("file:/tmp/x").unwrap().to_str(), Some("/tmp/x"));
        assert_eq!(folder_of("file://localhost/tmp/x").unwrap().to_str(), Some("/tmp/x"));
        assert!(folder_of("http://x").is_err());
    }
}
