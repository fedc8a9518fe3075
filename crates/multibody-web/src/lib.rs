//! The engine and the Dyad front end for a web page, compiled to
//! WebAssembly (`scripts/build-web.sh`): the live page loads a model once,
//! then runs it again with each value the user changes, in the page.
//!
//! The module speaks JSON through its memory, with five exports and no
//! generated bindings:
//!
//! - `mb_alloc(len) -> ptr` and `mb_free(ptr, len)`: the page writes a
//!   request there;
//! - `mb_call(ptr, len) -> len`: handles the request; the reply is at
//!   `mb_reply()`, valid until the next call;
//! - `mb_panic()`: after a trap, the panic's message (`mb_reply()` holds it).
//!
//! Requests:
//! - `{"op": "load", "files": [[name, text], ...], "analysis": name?,
//!   "model": name?, "signals": [pattern, ...]}` first;
//! - `{"op": "run", "params": ["link2.length=0.7", ...], "initials": [...],
//!   "stop": "5"?}`: a whole run;
//! - `{"op": "start", ...the same values}`, then `{"op": "step", "until": t,
//!   "inputs": {name: value}}` again and again: a run advanced in real
//!   time while the page sets the model's inputs.
//!
//! Replies: `{"ok": true, ...}` or `{"ok": false, "error": message}`, the
//! message being what `multibody run` prints for the same files and values.
//! The same [`Session`] runs natively in the tests.

mod session;

pub use session::{Run, Session, Values};

use serde_json::{json, Value};
use std::cell::RefCell;

/// What the module answers to one request, as JSON text.
pub fn handle(session: &mut Option<Session>, request: &str) -> String {
    let reply = match serde_json::from_str::<Value>(request) {
        Err(e) => Err(format!("the page sent a request that is not JSON: {e}")),
        Ok(request) => match request["op"].as_str() {
            Some("load") => load(session, &request),
            Some(op @ ("run" | "start" | "step")) => match session {
                Some(session) if op == "run" => run(session, &request),
                Some(session) if op == "start" => start(session, &request),
                Some(session) => step(session, &request),
                None => Err("no model is loaded: send `load` first".into()),
            },
            other => Err(format!("unknown request {other:?}: the requests are `load`, `run`, `start` and `step`")),
        },
    };
    match reply {
        Ok(text) => text,
        Err(message) => json!({ "ok": false, "error": message }).to_string(),
    }
}

fn strings(value: &Value) -> Vec<String> {
    value.as_array().map(|a| a.iter().filter_map(|s| s.as_str().map(str::to_string)).collect()).unwrap_or_default()
}

fn load(session: &mut Option<Session>, request: &Value) -> Result<String, String> {
    let files: Vec<(String, String)> = request["files"]
        .as_array()
        .map(|files| {
            files
                .iter()
                .filter_map(|f| Some((f.get(0)?.as_str()?.to_string(), f.get(1)?.as_str()?.to_string())))
                .collect()
        })
        .unwrap_or_default();
    if files.is_empty() {
        return Err("`load` needs `files`: [[name, text], ...]".into());
    }
    let loaded =
        Session::load(&files, request["analysis"].as_str(), request["model"].as_str(), strings(&request["signals"]))?;
    let reply = json!({ "ok": true, "model": loaded.describe() }).to_string();
    *session = Some(loaded);
    Ok(reply)
}

fn values(request: &Value) -> Values {
    Values {
        params: strings(&request["params"]),
        initials: strings(&request["initials"]),
        stop: request["stop"].as_str().map(str::to_string),
    }
}

fn run(session: &Session, request: &Value) -> Result<String, String> {
    reply(session.run(&values(request))?)
}

fn start(session: &mut Session, request: &Value) -> Result<String, String> {
    let inputs = session.start(&values(request))?;
    let inputs: Vec<Value> = inputs.into_iter().map(|(name, value)| json!({ "name": name, "value": value })).collect();
    Ok(json!({ "ok": true, "inputs": inputs }).to_string())
}

fn step(session: &mut Session, request: &Value) -> Result<String, String> {
    let until = request["until"].as_f64().ok_or("`step` needs `until`, a time")?;
    let inputs: Vec<(String, f64)> = request["inputs"]
        .as_object()
        .map(|o| o.iter().filter_map(|(k, v)| Some((k.clone(), v.as_f64()?))).collect())
        .unwrap_or_default();
    reply(session.step(until, &inputs)?)
}

/// A run's reply; its `stop` is the time reached.
fn reply(run: Run) -> Result<String, String> {
    // The scene is JSON already: it goes in as it is.
    Ok(format!(
        r#"{{"ok":true,"stop":{},"warnings":{},"final":{},"scene":{}}}"#,
        json!(run.stop),
        json!(run.warnings),
        Value::Object(run.finals),
        run.scene
    ))
}

thread_local! {
    static SESSION: RefCell<Option<Session>> = const { RefCell::new(None) };
    static REPLY: RefCell<Vec<u8>> = const { RefCell::new(Vec::new()) };
    static PANIC: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Room for `len` bytes in the module's memory, for the page to write into.
#[no_mangle]
pub extern "C" fn mb_alloc(len: usize) -> *mut u8 {
    let mut buffer = Vec::<u8>::with_capacity(len.max(1));
    let ptr = buffer.as_mut_ptr();
    std::mem::forget(buffer);
    ptr
}

/// Gives back what [`mb_alloc`] gave.
///
/// # Safety
/// `ptr` and `len` are those of one earlier `mb_alloc`, not freed yet.
#[no_mangle]
pub unsafe extern "C" fn mb_free(ptr: *mut u8, len: usize) {
    drop(Vec::from_raw_parts(ptr, 0, len.max(1)));
}

/// Handles the request of `len` bytes at `ptr` (UTF-8 JSON) and gives the
/// length of the reply, which is at [`mb_reply`].
///
/// # Safety
/// `ptr..ptr + len` is memory the page wrote (from [`mb_alloc`]).
#[no_mangle]
pub unsafe extern "C" fn mb_call(ptr: *const u8, len: usize) -> usize {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        // A panic traps the module; its message is kept for the page.
        std::panic::set_hook(Box::new(|info| PANIC.with(|p| *p.borrow_mut() = info.to_string())));
    });
    let bytes = std::slice::from_raw_parts(ptr, len);
    let reply = match std::str::from_utf8(bytes) {
        Ok(request) => SESSION.with(|s| handle(&mut s.borrow_mut(), request)),
        Err(_) => json!({ "ok": false, "error": "the request is not UTF-8 text" }).to_string(),
    };
    REPLY.with(|r| {
        let mut r = r.borrow_mut();
        *r = reply.into_bytes();
        r.len()
    })
}

/// The last reply (see [`mb_call`]).
#[no_mangle]
pub extern "C" fn mb_reply() -> *const u8 {
    REPLY.with(|r| r.borrow().as_ptr())
}

/// After a trap: the panic's message is put in the reply; gives its length.
#[no_mangle]
pub extern "C" fn mb_panic() -> usize {
    let message = PANIC.with(|p| p.borrow().clone());
    REPLY.with(|r| {
        let mut r = r.borrow_mut();
        *r = message.into_bytes();
        r.len()
    })
}
