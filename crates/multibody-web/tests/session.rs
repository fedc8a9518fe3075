//! The live page's session, run natively: the same results and the same
//! messages as `multibody run` for the same values.

use multibody_web::{handle, Session, Values};
use serde_json::Value;
use std::path::PathBuf;

fn example(name: &str) -> (String, String) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples").join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    (format!("examples/{name}"), text)
}

fn double_pendulum() -> Session {
    Session::load(&[example("double_pendulum.dyad")], None, None, Vec::new()).unwrap()
}

fn values(params: &[&str], stop: Option<&str>) -> Values {
    Values {
        params: params.iter().map(|s| s.to_string()).collect(),
        initials: Vec::new(),
        stop: stop.map(str::to_string),
    }
}

#[test]
fn timing() {
    let session = double_pendulum();
    for _ in 0..5 {
        let t = std::time::Instant::now();
        let run = session.run(&values(&["link2.length=0.7"], Some("5"))).unwrap();
        eprintln!("{:?} {}", t.elapsed(), run.finals["link2.joint.phi"]);
    }
}
