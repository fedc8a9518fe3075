//! What the FMI 2.0 and 3.0 functions share: the instance a host holds,
//! its logger, and the guard every call runs in (an error is logged and
//! gives Error; a panic is caught and gives Fatal, never crossing into the
//! host). Null pointers are accepted where their size is zero.

use crate::instance::Instance;
use std::collections::HashSet;
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;
use std::sync::Mutex;

/// The instances handed out and not yet freed, by address: a handle freed
/// twice, or used after it was freed, is refused instead of touching freed
/// memory (a second `fmi2FreeInstance` aborted the host with a double free).
static LIVE: Mutex<Option<HashSet<usize>>> = Mutex::new(None);

fn live() -> std::sync::MutexGuard<'static, Option<HashSet<usize>>> {
    LIVE.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

fn is_live(c: *mut c_void) -> bool {
    live().as_ref().is_some_and(|set| set.contains(&(c as usize)))
}

/// `fmi2Status` and `fmi3Status` have the same values.
pub type Status = c_int;
pub const OK: Status = 0;
pub const WARNING: Status = 1;
pub const DISCARD: Status = 2;
pub const ERROR: Status = 3;
pub const FATAL: Status = 4;

pub type Logger2 = unsafe extern "C" fn(*mut c_void, *const c_char, Status, *const c_char, *const c_char, ...);
pub type Logger3 = unsafe extern "C" fn(*mut c_void, Status, *const c_char, *const c_char);

/// How to tell the host something.
#[derive(Clone, Copy)]
pub enum Logger {
    /// FMI 2.0: variadic, the message a format string.
    Fmi2(Logger2),
    Fmi3(Logger3),
    None,
}

/// What the host holds: the instance and how to talk to the host.
pub struct Component {
    pub name: CString,
    pub logger: Logger,
    pub environment: *mut c_void,
    pub logging: bool,
    pub instance: Instance,
}

impl Component {
    pub fn log(&self, status: Status, category: &str, message: &str) {
        log(self.logger, self.environment, &self.name, status, category, message);
    }
}

pub fn log(logger: Logger, environment: *mut c_void, name: &CStr, status: Status, category: &str, message: &str) {
    let category = CString::new(category.replace('\0', " ")).unwrap_or_default();
    match logger {
        Logger::Fmi2(logger) => {
            // The message is the format string: a percent sign must not
            // start a conversion.
            let message = CString::new(message.replace('%', "%%").replace('\0', " ")).unwrap_or_default();
            unsafe { logger(environment, name.as_ptr(), status, category.as_ptr(), message.as_ptr()) };
        }
        Logger::Fmi3(logger) => {
            let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
            unsafe { logger(environment, status, category.as_ptr(), message.as_ptr()) };
        }
        Logger::None => {}
    }
}

/// Runs `f` on the instance behind `c`: an error is logged and gives
/// Error (the instance then refuses to go on until reset); a panic Fatal.
pub unsafe fn with(c: *mut c_void, call: &str, f: impl FnOnce(&mut Component) -> Result<Status, String>) -> Status {
    if !is_live(c) {
        return ERROR;
    }
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

/// Makes the instance (or says why not, through the logger) and gives the
/// host its handle, or null.
pub fn instantiate(
    name: &str,
    logger: Logger,
    environment: *mut c_void,
    logging: bool,
    call: &str,
    make: impl FnOnce() -> Result<Instance, String>,
) -> *mut c_void {
    let name = CString::new(name.replace('\0', " ")).unwrap_or_default();
    match catch_unwind(AssertUnwindSafe(make)) {
        Ok(Ok(instance)) => {
            let component = Box::new(Component { name, logger, environment, logging, instance });
            if component.logging {
                for w in component.instance.warnings() {
                    component.log(WARNING, "logStatusWarning", w);
                }
            }
            let handle = Box::into_raw(component) as *mut c_void;
            live().get_or_insert_with(HashSet::new).insert(handle as usize);
            handle
        }
        Ok(Err(message)) => {
            log(logger, environment, &name, ERROR, "logStatusError", &format!("{call}: {message}"));
            std::ptr::null_mut()
        }
        Err(_) => {
            log(
                logger,
                environment,
                &name,
                FATAL,
                "logStatusFatal",
                &format!("{call}: internal error while loading the model"),
            );
            std::ptr::null_mut()
        }
    }
}

pub unsafe fn free(c: *mut c_void) {
    let known = live().as_mut().is_some_and(|set| set.remove(&(c as usize)));
    if known {
        let _ = catch_unwind(|| drop(Box::from_raw(c as *mut Component)));
    }
}

/// A slice from a C array, empty for a null pointer with size zero.
pub unsafe fn slice<'a, T>(p: *const T, n: usize) -> Result<&'a [T], String> {
    match (p.is_null(), n) {
        (_, 0) => Ok(&[]),
        (true, _) => Err(format!("a null array of {n} values")),
        (false, _) => Ok(std::slice::from_raw_parts(p, n)),
    }
}

pub unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Result<&'a mut [T], String> {
    match (p.is_null(), n) {
        (_, 0) => Ok(&mut []),
        (true, _) => Err(format!("a null array of {n} values")),
        (false, _) => Ok(std::slice::from_raw_parts_mut(p, n)),
    }
}

pub unsafe fn text<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        None
    } else {
        CStr::from_ptr(p).to_str().ok()
    }
}

/// Sets `*p` where the host gave a place.
pub unsafe fn put<T>(p: *mut T, value: T) {
    if let Some(p) = p.as_mut() {
        *p = value;
    }
}

/// The folder of the resources: a `file:` URI (FMI 2.0, percent escapes
/// decoded) or a path (FMI 3.0).
pub fn folder_of(location: &str) -> Result<PathBuf, String> {
    if !location.contains(':') || location.starts_with('/') {
        return Ok(PathBuf::from(location));
    }
    let path = location
        .strip_prefix("file://localhost")
        .or_else(|| location.strip_prefix("file://"))
        .or_else(|| location.strip_prefix("file:"))
        .ok_or_else(|| format!("the resource location `{location}` is not a file: URI"))?;
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
    let path = String::from_utf8(out).map_err(|_| format!("the resource location `{location}` is not UTF-8"))?;
    Ok(PathBuf::from(path))
}

#[cfg(test)]
mod tests {
    use super::folder_of;

    #[test]
    fn resource_locations() {
        assert_eq!(folder_of("file:///tmp/a%20b/resources").unwrap().to_str(), Some("/tmp/a b/resources"));
        assert_eq!(folder_of("file:/tmp/x").unwrap().to_str(), Some("/tmp/x"));
        assert_eq!(folder_of("file://localhost/tmp/x").unwrap().to_str(), Some("/tmp/x"));
        assert_eq!(folder_of("/tmp/x/resources/").unwrap().to_str(), Some("/tmp/x/resources/"));
        assert!(folder_of("http://x").is_err());
    }
}
