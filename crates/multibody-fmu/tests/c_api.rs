//! The FMI 2.0 functions called as a host calls them, on an FMU's files
//! laid out in a temporary folder: the derivatives against the pendulum's
//! closed form, and bad calls that must give `fmi2Error` with a message
//! through the logger, never a crash. (FMPy drives whole simulations in
//! tests/test_fmu.py.)

use multibody_fmu::fmi2::*;
use multibody_fmu::model::{DESCRIPTION_FILE, MODEL_FOLDER, SETTINGS_FILE};
use multibody_fmu::Export;
use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

static MESSAGES: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// The logger, written without variadic arguments: the runtime passes the
/// message as the format string with none (x86-64 and AArch64 pass these
/// pointer arguments alike for both kinds of call).
extern "C" fn logger(_env: *mut c_void, _name: *const c_char, _status: c_int, _cat: *const c_char, msg: *const c_char) {
    let text = unsafe { CStr::from_ptr(msg) }.to_string_lossy().replace("%%", "%");
    MESSAGES.lock().unwrap().push(text);
}

#[repr(C)]
struct Callbacks {
    logger: *const c_void,
    allocate: *const c_void,
    free: *const c_void,
    step_finished: *const c_void,
    environment: *mut c_void,
}

fn callbacks() -> Callbacks {
    Callbacks {
        logger: logger as *const c_void,
        allocate: std::ptr::null(),
        free: std::ptr::null(),
        step_finished: std::ptr::null(),
        environment: std::ptr::null_mut(),
    }
}

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples")
}

/// The export of an example model, as `multibody fmu` prepares it.
fn export_of(model: &str) -> Export {
    let text = std::fs::read_to_string(examples().join(model)).unwrap();
    Export::prepare(&[(model.to_string(), text)], None, None, Vec::new(), None, None).unwrap()
}

/// The resources folder of an FMU of `model` (its description beside
/// it), and its token.
fn unpacked(model: &str, dir: &Path) -> (PathBuf, String) {
    let export = export_of(model);
    std::fs::write(dir.join(DESCRIPTION_FILE), export.model_description()).unwrap();
    let resources = dir.join("resources");
    std::fs::create_dir_all(resources.join(MODEL_FOLDER)).unwrap();
    std::fs::write(resources.join(SETTINGS_FILE), &export.settings_json).unwrap();
    for (name, text) in &export.files {
        std::fs::write(resources.join(MODEL_FOLDER).join(name), text).unwrap();
    }
    (resources, export.token.clone())
}

fn instantiate(resources: &Path, token: &str, kind: c_int) -> *mut c_void {
    let name = CString::new("test").unwrap();
    let guid = CString::new(token).unwrap();
    let uri = CString::new(format!("file://{}", resources.display())).unwrap();
    let cb = Box::leak(Box::new(callbacks()));
    unsafe {
        fmi2Instantiate(name.as_ptr(), kind, guid.as_ptr(), uri.as_ptr(), cb as *const Callbacks as *const _, 0, 0)
    }
}

fn logged(part: &str) -> bool {
    MESSAGES.lock().unwrap().iter().any(|m| m.contains(part))
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("multibody-fmu-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn derivatives_of_the_controlled_pendulum_have_the_closed_form() {
    let dir = temp("closed-form");
    let (resources, token) = unpacked("controlled_pendulum.dyad", &dir);
    let c = instantiate(&resources, &token, 0);
    assert!(!c.is_null());
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        let mut info = std::mem::zeroed::<[u8; 32]>();
        assert_eq!(fmi2NewDiscreteStates(c, info.as_mut_ptr() as *mut _), OK);
        assert_eq!(fmi2EnterContinuousTimeMode(c), OK);
        // (m r^2 + I_33) phi'' = -m g r cos(phi) + tau, with m = 1, r = 0.5, I_33 = 0.02.
        let (j, g) = (0.5 * 0.5 + 0.02, 9.80665);
        let md = export_of("controlled_pendulum.dyad");
        let vr = |name: &str| md.loaded.interface.variables.iter().position(|v| v.name == name).unwrap() as c_uint;
        for (phi, w, tau) in [(0.3, -1.0, 2.0), (-2.0, 0.5, -1.5)] {
            let x = [phi, w];
            assert_eq!(fmi2SetTime(c, 0.25), OK);
            assert_eq!(fmi2SetContinuousStates(c, x.as_ptr(), 2), OK);
            assert_eq!(fmi2SetReal(c, [vr("tau")].as_ptr(), 1, [tau].as_ptr()), OK);
            let mut dx = [0.0; 2];
            assert_eq!(fmi2GetDerivatives(c, dx.as_mut_ptr(), 2), OK);
            let exact = (-g * 0.5 * f64::cos(phi) + tau) / j;
            assert!((dx[0] - w).abs() < 1e-14, "{dx:?}");
            assert!((dx[1] - exact).abs() < 1e-12 * exact.abs().max(1.0), "{} vs {exact}", dx[1]);
            // The outputs read the state set, and der(rev.w) is the derivative.
            let mut y = [0.0; 3];
            let vrs = [vr("angle"), vr("speed"), vr("der(rev.w)")];
            assert_eq!(fmi2GetReal(c, vrs.as_ptr(), 3, y.as_mut_ptr()), OK);
            assert_eq!([y[0], y[1]], [phi, w]);
            assert!((y[2] - exact).abs() < 1e-12 * exact.abs().max(1.0));
            // Directional derivatives, column by column: the Jacobian of
            // (der(rev.phi), der(rev.w), angle) by (rev.phi, rev.w, tau).
            let unknowns = [vr("der(rev.phi)"), vr("der(rev.w)"), vr("angle")];
            let knowns = [vr("rev.phi"), vr("rev.w"), vr("tau")];
            let columns = [[0.0, g * 0.5 * f64::sin(phi) / j, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0 / j, 0.0]];
            for (k, want) in columns.iter().enumerate() {
                let mut seed = [0.0; 3];
                seed[k] = 1.0;
                let mut got = [0.0; 3];
                let status = fmi2GetDirectionalDerivative(
                    c,
                    unknowns.as_ptr(),
                    3,
                    knowns.as_ptr(),
                    3,
                    seed.as_ptr(),
                    got.as_mut_ptr(),
                );
                assert_eq!(status, OK);
                for (g, w) in got.iter().zip(want) {
                    assert!((g - w).abs() < 1e-9 * w.abs().max(1.0), "column {k}: {got:?} vs {want:?}");
                }
            }
            // The state and the input are where they were.
            let mut back = [0.0; 2];
            assert_eq!(fmi2GetContinuousStates(c, back.as_mut_ptr(), 2), OK);
            assert_eq!(back, x);
            assert_eq!(fmi2GetReal(c, [vr("tau")].as_ptr(), 1, back.as_mut_ptr()), OK);
            assert_eq!(back[0], tau);
        }
        assert_eq!(fmi2Terminate(c), OK);
        fmi2FreeInstance(c);
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bad_calls_give_errors_with_messages_never_a_crash() {
    let dir = temp("bad-calls");
    let (resources, token) = unpacked("double_pendulum.dyad", &dir);
    // A wrong token: no instance, and the logger says why.
    assert!(instantiate(&resources, "{not-the-token}", 1).is_null());
    assert!(logged("token mismatch"));
    // A resource location that is not a file URI.
    let (name, guid, uri) =
        (CString::new("x").unwrap(), CString::new(token.clone()).unwrap(), CString::new("http://example.com").unwrap());
    let cb = callbacks();
    let c = unsafe {
        fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), uri.as_ptr(), &cb as *const Callbacks as *const _, 0, 0)
    };
    assert!(c.is_null() && logged("is not a file: URI"));
    // An unknown interface type.
    assert!(instantiate(&resources, &token, 7).is_null() && logged("fmuType 7"));
    // A settings file that names a file outside the model folder.
    let elsewhere = dir.join("elsewhere");
    std::fs::create_dir_all(elsewhere.join("resources")).unwrap();
    std::fs::write(elsewhere.join("resources").join(SETTINGS_FILE), r#"{"files": ["../../secret.dyad"]}"#).unwrap();
    assert!(instantiate(&elsewhere.join("resources"), &token, 1).is_null());
    assert!(logged("names the model file `../../secret.dyad`, which is not in resources/model"));

    let c = instantiate(&resources, &token, 1);
    assert!(!c.is_null());
    unsafe {
        // Null arrays are fine with a size of zero, an error otherwise.
        assert_eq!(fmi2GetReal(c, std::ptr::null(), 0, std::ptr::null_mut()), OK);
        assert_eq!(fmi2SetReal(c, std::ptr::null(), 0, std::ptr::null()), OK);
        assert_eq!(fmi2GetInteger(c, std::ptr::null(), 0, std::ptr::null_mut()), OK);
        assert_eq!(fmi2GetReal(c, std::ptr::null(), 2, std::ptr::null_mut()), ERROR);
        assert!(logged("fmi2GetReal: a null array of 2 values"));
        fmi2Reset(c);
        // A value reference past the last.
        let mut x = [0.0];
        assert_eq!(fmi2GetReal(c, [100_000].as_ptr(), 1, x.as_mut_ptr()), ERROR);
        assert!(logged("no variable has the value reference 100000"));
        fmi2Reset(c);
        // Steps before initialization.
        assert_eq!(fmi2DoStep(c, 0.0, 0.1, 1), ERROR);
        assert!(logged(
            "fmi2DoStep: not allowed now: the instance is instantiated, and its initialization has not begun"
        ));
        fmi2Reset(c);
        // A parameter refused by the model: the model's own message.
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        let md = export_of("double_pendulum.dyad");
        let width = md.loaded.interface.variables.iter().position(|v| v.name == "link2.width").unwrap() as c_uint;
        assert_eq!(fmi2SetReal(c, [width].as_ptr(), 1, [-0.1].as_ptr()), OK);
        assert_eq!(fmi2ExitInitializationMode(c), ERROR);
        assert!(logged("link2.width"));
        // A communication point that is not where the FMU stands.
        fmi2Reset(c);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        assert_eq!(fmi2DoStep(c, 0.0, 0.1, 1), OK);
        assert_eq!(fmi2DoStep(c, 0.5, 0.1, 1), ERROR);
        assert!(logged("the step starts at t = 0.5, but the FMU stands at t = 0.1"));
        fmi2FreeInstance(c);
        // Freed twice, or used once freed: refused, not a double free
        // (which aborted the host).
        fmi2FreeInstance(c);
        assert_eq!(fmi2DoStep(c, 0.1, 0.1, 1), ERROR);
        // Null instances.
        fmi2FreeInstance(std::ptr::null_mut());
        assert_eq!(fmi2DoStep(std::ptr::null_mut(), 0.0, 0.1, 1), ERROR);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// A description whose value references were swapped ran with the
/// variables mixed up: the token covered `resources/` only.
#[test]
fn an_edited_description_is_refused_at_instantiation() {
    let dir = temp("edited-description");
    let (resources, token) = unpacked("double_pendulum.dyad", &dir);
    let description = std::fs::read_to_string(dir.join(DESCRIPTION_FILE)).unwrap();
    let swapped = description
        .replacen("valueReference=\"1\"", "valueReference=\"@\"", 1)
        .replacen("valueReference=\"2\"", "valueReference=\"1\"", 1)
        .replacen("valueReference=\"@\"", "valueReference=\"2\"", 1);
    assert_ne!(swapped, description);
    std::fs::write(dir.join(DESCRIPTION_FILE), &swapped).unwrap();
    assert!(instantiate(&resources, &token, 1).is_null());
    assert!(logged("token mismatch: the FMU's modelDescription.xml was edited after the export"));
    // A description without the token is refused too.
    std::fs::write(dir.join(DESCRIPTION_FILE), description.replace(&token, "")).unwrap();
    assert!(instantiate(&resources, &token, 0).is_null());
    // No description beside resources/ (FMPy unpacks only resources/ and
    // binaries/): the files are checked, and they are the exported ones.
    std::fs::remove_file(dir.join(DESCRIPTION_FILE)).unwrap();
    let c = instantiate(&resources, &token, 1);
    assert!(!c.is_null());
    unsafe { fmi2FreeInstance(c) };
    // The description as exported is accepted.
    std::fs::write(dir.join(DESCRIPTION_FILE), &description).unwrap();
    let c = instantiate(&resources, &token, 1);
    assert!(!c.is_null());
    unsafe { fmi2FreeInstance(c) };
    let _ = std::fs::remove_dir_all(dir);
}

static MESSAGES3: Mutex<Vec<String>> = Mutex::new(Vec::new());

extern "C" fn logger3(_env: *mut c_void, _status: c_int, _cat: *const c_char, msg: *const c_char) {
    MESSAGES3.lock().unwrap().push(unsafe { CStr::from_ptr(msg) }.to_string_lossy().into_owned());
}

#[test]
fn fmi_3_steps_as_fmi_2_does_and_refuses_a_wrong_token() {
    use multibody_fmu::fmi3::*;
    let dir = temp("fmi3");
    let (resources, token) = unpacked("double_pendulum.dyad", &dir);
    let path = CString::new(format!("{}/", resources.display())).unwrap();
    let name = CString::new("three").unwrap();
    // An FMI 3.0 co-simulation instance with the token `token`.
    let co_simulation = |token: &str| co_simulation3(&name, &CString::new(token).unwrap(), &path);
    unsafe {
        assert!(co_simulation("{wrong}").is_null());
        assert!(MESSAGES3.lock().unwrap().iter().any(|m| m.contains("token mismatch")));
        let three = co_simulation(&token);
        let two = instantiate(&resources, &token, 1);
        assert!(!three.is_null() && !two.is_null());
        assert_eq!(fmi3EnterInitializationMode(three, false, 0.0, 0.0, false, 0.0), OK);
        assert_eq!(fmi3ExitInitializationMode(three), OK);
        assert_eq!(fmi2EnterInitializationMode(two), OK);
        assert_eq!(fmi2ExitInitializationMode(two), OK);
        let (mut a, mut b) = ([0.0; 4], [0.0; 4]);
        let (mut event, mut stop, mut early, mut reached) = (true, true, true, 0.0);
        for k in 0..20 {
            let t = k as f64 * 0.05;
            assert_eq!(fmi3DoStep(three, t, 0.05, true, &mut event, &mut stop, &mut early, &mut reached), OK);
            assert_eq!(fmi2DoStep(two, t, 0.05, 1), OK);
        }
        assert!(!event && !stop && !early && (reached - 1.0).abs() < 1e-12);
        let e = export_of("double_pendulum.dyad");
        let states: Vec<c_uint> = ["link1.joint.phi", "link2.joint.phi", "link1.joint.w", "link2.joint.w"]
            .iter()
            .map(|n| e.loaded.interface.variables.iter().position(|v| &v.name == n).unwrap() as c_uint)
            .collect();
        assert_eq!(fmi3GetFloat64(three, states.as_ptr(), 4, a.as_mut_ptr(), 4), OK);
        assert_eq!(fmi2GetReal(two, states.as_ptr(), 4, b.as_mut_ptr()), OK);
        assert_eq!(a, b);
        // Types the FMU has none of: fine for no values, an error otherwise.
        assert_eq!(fmi3GetInt32(three, std::ptr::null(), 0, std::ptr::null_mut(), 0), OK);
        assert_eq!(fmi3GetInt32(three, states.as_ptr(), 1, std::ptr::null_mut(), 1), ERROR);
        assert!(MESSAGES3.lock().unwrap().iter().any(|m| m.contains("only Float64 variables")));
        fmi3FreeInstance(three);
        fmi2FreeInstance(two);
    }
    let _ = std::fs::remove_dir_all(dir);
}

/// FMI 3.0 calls refused for the instance's state named FMI 2.0 functions
/// (`fmi3DoStep: fmi2DoStep is not allowed now`): each message names the
/// function the host called.
#[test]
fn fmi_3_messages_name_the_fmi_3_function_called() {
    use multibody_fmu::fmi3::*;
    let dir = temp("fmi3-names");
    let (resources, token) = unpacked("double_pendulum.dyad", &dir);
    let path = CString::new(format!("{}/", resources.display())).unwrap();
    let (name, token) = (CString::new("names").unwrap(), CString::new(token).unwrap());
    let logger = Some(logger3 as multibody_fmu::fmi3::LogMessage);
    let env = std::ptr::null_mut();
    let said = |part: &str| MESSAGES3.lock().unwrap().iter().any(|m| m.contains(part));
    unsafe {
        let me = fmi3InstantiateModelExchange(name.as_ptr(), token.as_ptr(), path.as_ptr(), false, false, env, logger);
        assert!(!me.is_null());
        let mut dx = [0.0; 4];
        assert_eq!(fmi3GetContinuousStateDerivatives(me, dx.as_mut_ptr(), 4), ERROR);
        assert!(said("fmi3GetContinuousStateDerivatives: not allowed now: the instance is instantiated"));
        fmi3Reset(me);
        assert_eq!(fmi3SetTime(me, 0.5), ERROR);
        assert!(said("fmi3SetTime: not allowed now: the instance is instantiated"));
        fmi3Reset(me);
        assert_eq!(fmi3EnterInitializationMode(me, false, 0.0, 0.0, false, 0.0), OK);
        assert_eq!(fmi3EnterInitializationMode(me, false, 0.0, 0.0, false, 0.0), ERROR);
        assert!(said("fmi3EnterInitializationMode: not allowed now: the instance is in initialization mode"));
        fmi3Reset(me);
        assert_eq!(fmi3EnterInitializationMode(me, false, 0.0, 0.0, false, 0.0), OK);
        assert_eq!(fmi3ExitInitializationMode(me), OK);
        assert_eq!(fmi3EnterContinuousTimeMode(me), OK);
        let (mut a, mut b, mut c, mut d, mut e, mut t) = (false, false, false, false, false, 0.0);
        assert_eq!(fmi3UpdateDiscreteStates(me, &mut a, &mut b, &mut c, &mut d, &mut e, &mut t), ERROR);
        assert!(said("fmi3UpdateDiscreteStates: not allowed now: the instance is in continuous-time mode"));
        fmi3FreeInstance(me);

        let cs = co_simulation3(&name, &token, &path);
        assert!(!cs.is_null());
        let (mut event, mut stop, mut early, mut reached) = (false, false, false, 0.0);
        assert_eq!(fmi3DoStep(cs, 0.0, 0.1, true, &mut event, &mut stop, &mut early, &mut reached), ERROR);
        assert!(said("fmi3DoStep: not allowed now: the instance is instantiated"));
        fmi3Reset(cs);
        assert_eq!(fmi3GetBinary(cs, [0].as_ptr(), 1, std::ptr::null_mut(), std::ptr::null_mut(), 1), ERROR);
        assert!(said("fmi3GetBinary: the FMU has only Float64 variables"));
        fmi3FreeInstance(cs);
    }
    let messages = MESSAGES3.lock().unwrap();
    assert!(!messages.iter().any(|m| m.contains("fmi2")), "{messages:?}");
    drop(messages);
    let _ = std::fs::remove_dir_all(dir);
}

/// An FMI 3.0 co-simulation instance of the FMU unpacked at `path` (its
/// resources folder), logging to `logger3`.
fn co_simulation3(name: &std::ffi::CStr, token: &std::ffi::CStr, path: &std::ffi::CStr) -> *mut std::ffi::c_void {
    let logger = Some(logger3 as multibody_fmu::fmi3::LogMessage);
    let (none, env) = (std::ptr::null(), std::ptr::null_mut());
    unsafe {
        multibody_fmu::fmi3::fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            path.as_ptr(),
            false,
            false,
            false,
            false,
            none,
            0,
            env,
            logger,
            std::ptr::null(),
        )
    }
}
