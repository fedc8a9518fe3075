//! The live page's session, run natively: the same numbers as the engine's
//! own run of the same model with the same values, the command's messages
//! for bad values, and a protocol that answers every request.

use multibody_dyad::{Override, Package, Target};
use multibody_web::{handle, Session, Values};
use serde_json::Value;
use std::path::PathBuf;

fn example(name: &str) -> (String, String) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(name);
    (format!("examples/{name}"), std::fs::read_to_string(&path).unwrap())
}

fn double_pendulum() -> Session {
    Session::load(&[example("double_pendulum.dyad")], None, None, Vec::new()).unwrap()
}

fn values(params: &[&str], initials: &[&str], stop: Option<&str>) -> Values {
    Values {
        params: params.iter().map(|s| s.to_string()).collect(),
        initials: initials.iter().map(|s| s.to_string()).collect(),
        stop: stop.map(str::to_string),
    }
}

/// The same model lowered with the same values as Rust overrides, assembled
/// and simulated without the session: the session must add nothing.
fn direct(overrides: &[Override], stop: f64) -> multibody::Solution {
    let mut package = Package::new();
    let (name, text) = example("double_pendulum.dyad");
    package.add_source(name, text).unwrap();
    let lowered = package.lower_target(&Target::Analysis("DoublePendulumSimulation".into()), overrides).unwrap();
    let mut options = lowered.options.clone();
    options.stop = stop;
    lowered.assemble().unwrap().simulate(&options).unwrap()
}

#[test]
fn a_changed_length_and_start_give_the_engines_own_run() {
    let session = double_pendulum();
    let run = session.run(&values(&["link2.length=0.7"], &["link1.joint.phi=0.3"], Some("5"))).unwrap();
    assert_eq!(run.stop, 5.0);
    let expected = direct(&[Override::parameter("link2.length", 0.7), Override::initial("link1.joint.phi", 0.3)], 5.0);
    for name in ["link1.joint.phi", "link2.joint.phi", "link1.joint.w", "link2.joint.w", "link2.box.r_0[1]"] {
        let got = run.finals[name].as_f64().unwrap();
        assert_eq!(got, expected.last(name).unwrap(), "{name}");
    }
    // And the change mattered: the unchanged model ends elsewhere.
    let unchanged = session.run(&values(&[], &[], Some("5"))).unwrap();
    let moved =
        (unchanged.finals["link2.joint.phi"].as_f64().unwrap() - run.finals["link2.joint.phi"].as_f64().unwrap()).abs();
    assert!(moved > 0.1, "{moved}");
    // The scene is the viewer's JSON, with the run's length in time.
    let scene: Value = serde_json::from_str(&run.scene).unwrap();
    assert_eq!(scene["title"], "DoublePendulumSimulation");
    assert!(scene["shapes"].as_array().unwrap().len() >= 4);
}

#[test]
fn the_panel_lists_the_models_own_values() {
    let session = double_pendulum();
    let model = session.describe();
    let tunables = model["tunables"].as_array().unwrap();
    let paths: Vec<&str> = tunables.iter().map(|t| t["path"].as_str().unwrap()).collect();
    assert_eq!(
        paths,
        [
            "link1.length",
            "link1.width",
            "link1.d",
            "link1.joint.phi",
            "link1.joint.w",
            "link2.length",
            "link2.width",
            "link2.d",
            "link2.joint.phi",
            "link2.joint.w"
        ]
    );
    let d = &tunables[2];
    assert_eq!(
        (d["kind"].as_str(), d["value"].as_f64(), d["unit"].as_str()),
        (Some("parameter"), Some(0.1), Some("N.m.s/rad"))
    );
    assert_eq!(tunables[3]["kind"], "start");
    assert_eq!(model["stop"], 3.0);
}

/// Each bad value gets the message `multibody run` prints for the same
/// value (the command's own tests check these texts at the command).
#[test]
fn bad_values_get_the_commands_messages() {
    let session = double_pendulum();
    let cases = [
        (values(&["link2.length=abc"], &[], None), "`--param link2.length=abc`: `abc` is not a number (write --param link2.length=2.5)"),
        (values(&["link2.width=-0.1"], &[], None), "`--param link2.width=-0.1`: `link2.box.width` = -0.1 is not allowed: a size must not be negative"),
        (values(&["link2.box.density=-1"], &[], None), "`--param link2.box.density=-1`: `link2.box.density` = -1 is not allowed: it must not be negative"),
        (values(&["link2.lenght=1"], &[], None), "`--param link2.lenght=1`: `Link` has no parameter `lenght`; did you mean `length`? its parameters are: length, width, d"),
        (values(&["=1"], &[], None), "`--param =1`: write NAME=VALUE, e.g. --param body.m=2"),
        (values(&[], &[], Some("x")), "`--stop x`: `x` is not a number (write --stop 5)"),
    ];
    for (v, message) in cases {
        assert_eq!(session.run(&v).err().as_deref(), Some(message), "{v:?}");
    }
    let stop = session.run(&values(&[], &[], Some("-1"))).err().unwrap();
    assert!(stop.starts_with("--stop -1: "), "{stop}");
}

#[test]
fn files_that_do_not_read_are_refused_at_their_place() {
    let files = [("broken.dyad".to_string(), "component A\n  x = 1 +\nend\n".to_string())];
    let message = Session::load(&files, None, None, Vec::new()).err().unwrap();
    assert!(message.contains("┌─ broken.dyad:2:7"), "{message}");
    let message = Session::load(&[example("double_pendulum.dyad")], Some("Nope"), None, Vec::new()).err().unwrap();
    assert!(message.starts_with("there is no analysis `Nope` in the files"), "{message}");
}

#[test]
fn the_protocol_answers_every_request() {
    let mut session = None;
    let reply = |s: &mut Option<Session>, request: &str| serde_json::from_str::<Value>(&handle(s, request)).unwrap();
    assert!(reply(&mut session, "{").as_object().unwrap()["error"].as_str().unwrap().contains("not JSON"));
    assert!(reply(&mut session, r#"{"op":"run"}"#)["error"].as_str().unwrap().contains("send `load` first"));
    assert!(reply(&mut session, r#"{"op":"fly"}"#)["error"].as_str().unwrap().contains("unknown request"));
    assert!(reply(&mut session, r#"{"op":"load","files":[]}"#)["error"].as_str().unwrap().contains("needs `files`"));
    let (name, text) = example("double_pendulum.dyad");
    let load = serde_json::json!({ "op": "load", "files": [[name, text]] }).to_string();
    let loaded = reply(&mut session, &load);
    assert_eq!(loaded["ok"], true, "{loaded}");
    assert_eq!(loaded["model"]["tunables"].as_array().unwrap().len(), 10);
    let ran = reply(&mut session, r#"{"op":"run","params":["link1.d=0.2"],"stop":"1"}"#);
    assert_eq!((ran["ok"].as_bool(), ran["stop"].as_f64()), (Some(true), Some(1.0)), "{}", &ran.to_string()[..200]);
    assert!(ran["final"]["link1.joint.phi"].is_f64());
    assert!(ran["scene"]["poses"].is_string());
    let bad = reply(&mut session, r#"{"op":"run","params":["link1.d=x"]}"#);
    assert_eq!(bad["ok"], false);
    // A failed run leaves the session as it was.
    assert_eq!(reply(&mut session, r#"{"op":"run","stop":"1"}"#)["ok"], true);
}

/// A run stepped while its input torque changes: the pendulum's energy
/// gains exactly the work of the torque, `tau` times the angle turned in
/// each step (it has no damping), and the scene covers the motion so far.
#[test]
fn a_stepped_run_takes_the_inputs_set_between_steps() {
    let mut session = Session::load(&[example("controlled_pendulum.dyad")], None, None, Vec::new()).unwrap();
    let inputs = session.start(&values(&[], &[], Some("3"))).unwrap();
    assert_eq!(inputs, [("tau".to_string(), 0.0)]);
    // The model's body: m = 1, r_cm = 0.5 along the link, I_33 = 0.02.
    let (m, r, g, inertia) = (1.0, 0.5, 9.80665, 1.0 * 0.25 + 0.02);
    let energy = |phi: f64, w: f64| 0.5 * inertia * w * w + m * g * r * phi.sin();
    let (mut phi, mut w) = (0.0, 0.0);
    let start = energy(phi, w);
    let mut work = 0.0;
    let mut last = None;
    for k in 1..=30 {
        let t = 0.1 * k as f64;
        let tau = if t <= 1.0 + 1e-9 {
            2.0
        } else if t <= 2.0 + 1e-9 {
            -1.5
        } else {
            3.0
        };
        let run = session.step(t, &[("tau".into(), tau)]).unwrap();
        assert!((run.stop - t).abs() < 1e-12, "reached {} instead of {t}", run.stop);
        let next = run.finals["rev.phi"].as_f64().unwrap();
        work += tau * (next - phi);
        phi = next;
        w = run.finals["rev.w"].as_f64().unwrap();
        last = Some(run);
    }
    let error = (energy(phi, w) - start - work).abs();
    eprintln!("energy gained minus the torque's work: {error:.1e} J (of {work:.3} J of work)");
    assert!(error < 1e-7, "{error}");
    // Past the stop time nothing more happens; the scene spans the run.
    let scene: Value = serde_json::from_str(&last.unwrap().scene).unwrap();
    assert!(scene["times"].is_string());
    let after = session.step(10.0, &[]).unwrap();
    assert_eq!(after.stop, 3.0);
    // A bad input name ends the stepped run with the simulator's message.
    let bad = session.step(3.0, &[("torque".into(), 1.0)]).err().unwrap();
    assert!(bad.contains("torque"), "{bad}");
    assert!(session.step(3.0, &[]).err().unwrap().contains("send `start` first"));
}
