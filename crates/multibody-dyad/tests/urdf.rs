//! URDF robots imported as Dyad models, checked against Pinocchio: the
//! forward dynamics at ten random states of each file in `tests/urdf/`
//! (golden values made by `scripts/urdf_goldens.py` with PyPI's `pin`),
//! and bad files, each with its message at file:line:col.

use multibody::{JointSpace, Mechanism, SimulationOptions, Simulator};
use multibody_dyad::urdf::{self, ImportOptions};
use multibody_dyad::Package;
use serde_json::Value;
use std::path::PathBuf;
use std::sync::Arc;

fn folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/urdf")
}

/// Each URDF joint's name and its component's.
type JointNames = Vec<(String, String)>;

/// The robot of the file at `path` imported and assembled, and the Dyad
/// names of the URDF's joints.
fn mechanism(path: &std::path::Path) -> Result<(Arc<Mechanism>, JointNames), String> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let robot = urdf::parse(&text).map_err(|e| e.render(&file))?;
    let (_, joint_ids) = urdf::dyad_names(&robot);
    let names = robot.joints.iter().map(|j| j.name.clone()).zip(joint_ids).collect();
    // Pinocchio's dynamics leave joint damping out.
    let dyad = urdf::to_dyad(&robot, &file, &ImportOptions { damping: false, ..Default::default() });
    let mut package = Package::new();
    package.add_source(format!("{file}.dyad"), dyad).map_err(|d| package.render(&[d]))?;
    let target = package.choose_target(None, None)?;
    let lowered = package.lower_target(&target, &[]).map_err(|d| package.render(&[d]))?;
    let mechanism = lowered.assemble().map_err(|d| package.render(&[d]))?;
    Ok((Arc::new(mechanism), names))
}

/// The worst differences, relative to the largest value of each state,
/// between our dynamics and Pinocchio's `golden` ones: forward dynamics
/// (the simulator's and the joint space's), the mass matrix and the
/// inverse dynamics; an error when the file does not load.
fn compare(path: &std::path::Path, golden: &Value) -> Result<[f64; 3], String> {
    let (mechanism, dyad_names) = mechanism(path)?;
    let mut sim = Simulator::for_host(mechanism.clone(), &SimulationOptions::default()).map_err(|s| s.reason)?;
    let mut space = JointSpace::new(&mechanism)?;
    let dyad = |urdf_name: &str| dyad_names.iter().find(|(u, _)| u == urdf_name).map(|(_, d)| d.clone());
    let names: Vec<String> = sim.state_names().to_vec();
    let joints: Vec<String> = golden["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| dyad(j.as_str().unwrap()).ok_or_else(|| format!("Pinocchio's joint {j} is not in the file")))
        .collect::<Result<_, _>>()?;
    let coordinate = |joint: &str, what: &[&str]| {
        what.iter()
            .find_map(|w| names.iter().position(|n| *n == format!("{joint}.{w}")))
            .ok_or_else(|| format!("no state of `{joint}` among {names:?}"))
    };
    let q_at: Vec<usize> = joints.iter().map(|j| coordinate(j, &["phi", "s"])).collect::<Result<_, _>>()?;
    let v_at: Vec<usize> = joints.iter().map(|j| coordinate(j, &["w", "v"])).collect::<Result<_, _>>()?;
    if names.len() != 2 * joints.len() {
        return Err(format!("{} states for {} joints of Pinocchio's", names.len(), joints.len()));
    }
    // Pinocchio's joint k is the joint space's at[k].
    let at: Vec<usize> = joints
        .iter()
        .map(|j| space.joints().iter().position(|s| s == j).ok_or_else(|| format!("`{j}` is not in the joint space")))
        .collect::<Result<_, _>>()?;
    let n = joints.len();
    let mut worst = [0.0_f64; 3];
    for state in golden["states"].as_array().unwrap() {
        let numbers =
            |key: &str| -> Vec<f64> { state[key].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect() };
        let (q, v, ddq) = (numbers("q"), numbers("v"), numbers("ddq"));
        let (a, tau) = (numbers("a"), numbers("tau"));
        let mass: Vec<f64> = state["M"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|r| r.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
            .collect();
        // Vectors in the joint space's order.
        let ours = |x: &[f64]| -> Vec<f64> {
            let mut o = vec![0.0; n];
            for k in 0..n {
                o[at[k]] = x[k];
            }
            o
        };
        let (qs, vs, accelerations) = (ours(&q), ours(&v), ours(&a));
        let mut m = vec![0.0; n * n];
        space.mass_matrix(&qs, &mut m)?;
        let scale = mass.iter().fold(f64::MIN_POSITIVE, |s, x| s.max(x.abs()));
        for i in 0..n {
            for j in 0..n {
                worst[1] = worst[1].max((m[at[i] * n + at[j]] - mass[i * n + j]).abs() / scale);
            }
        }
        let mut t = vec![0.0; n];
        space.inverse_dynamics(&qs, &vs, &accelerations, &mut t)?;
        let scale = tau.iter().fold(1.0_f64, |s, x| s.max(x.abs()));
        for k in 0..n {
            worst[2] = worst[2].max((t[at[k]] - tau[k]).abs() / scale);
        }
        let mut fd = vec![0.0; n];
        space.forward_dynamics(&qs, &vs, &vec![0.0; n], &mut fd)?;
        // Accelerations are compared relative to their largest, and within
        // what rounding allows: solving M x = b loses up to cond(M) times
        // the precision (iCub's M reaches 1.2e8), so the tolerance 1e-10
        // stands for cond(M) up to 1e5 and grows with it past that.
        let cond = state["cond"].as_f64().unwrap_or(1.0);
        let scale = ddq.iter().fold(1.0_f64, |s, x| s.max(x.abs())) * (cond / 1e5).max(1.0);
        for k in 0..n {
            worst[0] = worst[0].max((fd[at[k]] - ddq[k]).abs() / scale);
        }
        let mut y = vec![0.0; names.len()];
        for k in 0..joints.len() {
            y[q_at[k]] = q[k];
            y[v_at[k]] = v[k];
        }
        sim.set_continuous_state(&y)?;
        let mut dy = vec![0.0; y.len()];
        sim.derivatives(&mut dy)?;
        for k in 0..joints.len() {
            assert_eq!(dy[q_at[k]], v[k]);
            worst[0] = worst[0].max((dy[v_at[k]] - ddq[k]).abs() / scale);
        }
    }
    Ok(worst)
}

#[test]
fn forward_dynamics_equal_pinocchios() {
    let goldens: Value =
        serde_json::from_str(&std::fs::read_to_string(folder().join("goldens.json")).unwrap()).unwrap();
    let mut worst = [0.0_f64; 3];
    for (file, golden) in goldens.as_object().unwrap() {
        let error = compare(&folder().join(file), golden).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(
            error.iter().all(|&e| e < 1e-10),
            "{file}: forward dynamics, mass matrix, inverse dynamics differ from Pinocchio's by {error:?} (relative)"
        );
        for k in 0..3 {
            worst[k] = worst[k].max(error[k]);
        }
    }
    println!(
        "vs Pinocchio, worst relative differences: forward dynamics {:.1e}, mass matrix {:.1e}, inverse dynamics \
         {:.1e} (tolerance 1e-10)",
        worst[0], worst[1], worst[2]
    );
}

/// Every URDF of a corpus (example-robot-data from PyPI) whose golden
/// values `scripts/urdf_goldens.py` wrote to `$MULTIBODY_URDF_CORPUS`
/// (keys: the files' paths): each either agrees with Pinocchio to 1e-10 or
/// is refused with a message; the counts are printed.
#[test]
fn a_corpus_of_real_robots_agrees_with_pinocchio_or_is_refused() {
    let Some(goldens) = std::env::var_os("MULTIBODY_URDF_CORPUS") else {
        println!("skipped: set MULTIBODY_URDF_CORPUS to golden values of a URDF corpus (scripts/urdf_goldens.py)");
        return;
    };
    let goldens: Value = serde_json::from_str(&std::fs::read_to_string(goldens).unwrap()).unwrap();
    let (mut agree, mut refused, mut worst, mut differ) = (0, Vec::new(), [0.0_f64; 3], Vec::new());
    for (path, golden) in goldens.as_object().unwrap() {
        let name = std::path::Path::new(path).file_name().unwrap().to_string_lossy().into_owned();
        if golden["singular"].as_bool() == Some(true) {
            // Pinocchio's mass matrix is singular: ours must refuse the model.
            let refusal = mechanism(std::path::Path::new(path)).err();
            assert!(refusal.is_some(), "{name}: Pinocchio finds a singular mass matrix, but the model was accepted");
            refused
                .push(format!("{name} (singular in Pinocchio too): {}", refusal.unwrap().lines().next().unwrap_or("")));
            continue;
        }
        match compare(std::path::Path::new(path), golden) {
            Ok(error) if error.iter().all(|&e| e < 1e-10) => {
                for k in 0..3 {
                    worst[k] = worst[k].max(error[k]);
                }
                agree += 1;
            }
            Ok(error) => differ.push(format!("{name}: {error:?}")),
            Err(message) => refused.push(format!("{name}: {}", message.lines().next().unwrap_or(""))),
        }
    }
    println!(
        "{} files: {agree} agree with Pinocchio (worst: forward dynamics {:.1e}, mass matrix {:.1e}, inverse \
         dynamics {:.1e}), {} refused:",
        agree + refused.len(),
        worst[0],
        worst[1],
        worst[2],
        refused.len()
    );
    for r in &refused {
        println!("  {r}");
    }
    assert!(differ.is_empty(), "forward dynamics differ from Pinocchio's (relative): {differ:?}");
}

fn error_of(text: &str) -> String {
    match urdf::parse(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.render("bad.urdf"),
    }
}

#[test]
fn bad_files_are_refused_with_their_place() {
    let link = |name: &str| {
        format!("<link name=\"{name}\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>")
    };
    let joint = |name: &str, parent: &str, child: &str| {
        format!("<joint name=\"{name}\" type=\"revolute\"><parent link=\"{parent}\"/><child link=\"{child}\"/><axis xyz=\"0 0 1\"/></joint>")
    };
    let robot = |body: String| format!("<robot name=\"r\">\n{body}\n</robot>");

    let e = error_of("<robot name=\"r\">\n  <link name=\"a\">\n</robot>");
    assert!(e.starts_with("bad.urdf:3:") && e.contains("not well-formed XML"), "{e}");

    let e = error_of(&robot(format!(
        "{}\n{}\n{}\n{}\n{}",
        link("a"),
        link("b"),
        link("c"),
        joint("j1", "a", "c"),
        joint("j2", "b", "c")
    )));
    assert!(
        e.starts_with("bad.urdf:6:1") && e.contains("the link `c` has two parents: joint `j1` (line 5) and joint `j2`"),
        "{e}"
    );

    let e = error_of(&robot(format!("{}\n{}", link("a"), joint("j", "a", "hand"))));
    assert!(e.starts_with("bad.urdf:3:") && e.contains("names the child link `hand`, which does not exist"), "{e}");

    let e = error_of(&robot("<link name=\"a\"><inertial><mass value=\"-2\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>".into()));
    assert!(e.starts_with("bad.urdf:2:") && e.contains("a negative mass (-2 kg)"), "{e}");

    let e = error_of(&robot("<link name=\"a\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"2\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>".into()));
    assert!(e.contains("is not positive semi-definite"), "{e}");

    let e = error_of(&robot(format!(
        "{}\n{}\n{}\n{}\n{}",
        link("a"),
        link("b"),
        link("c"),
        joint("j1", "b", "c"),
        joint("j2", "c", "b")
    )));
    assert!(e.contains("form a loop") && e.contains("`j1`") && e.contains("`j2`"), "{e}");

    let e = error_of(&robot(format!(
        "{}\n<joint name=\"j\" type=\"hinge\"><parent link=\"a\"/><child link=\"a\"/></joint>",
        link("a")
    )));
    assert!(e.contains("the type `hinge`") && e.contains("revolute, continuous, prismatic"), "{e}");

    let e = error_of(&robot(format!(
        "{}\n{}\n<joint name=\"j\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/></joint>",
        link("a"),
        link("b")
    )));
    assert!(
        e.starts_with("bad.urdf:4:1") && e.contains("the joint `j` is planar, which the import does not map yet"),
        "{e}"
    );
}

#[test]
fn unmapped_elements_are_listed_once_with_their_place() {
    let text = std::fs::read_to_string(folder().join("arm6.urdf")).unwrap();
    let with_extras = text.replace(
        "</robot>",
        "  <transmission name=\"t\"><type>x</type></transmission>\n  <transmission name=\"t2\"/>\n  <gazebo/>\n</robot>",
    );
    let robot = urdf::parse(&with_extras).unwrap();
    let tags: Vec<(&str, usize)> = robot.skipped.iter().map(|s| (s.tag.as_str(), s.count)).collect();
    assert!(tags.contains(&("transmission", 2)) && tags.contains(&("gazebo", 1)), "{tags:?}");
    let transmission = robot.skipped.iter().find(|s| s.tag == "transmission").unwrap();
    assert_eq!(
        with_extras.lines().nth(transmission.at.line as usize - 1).map(str::trim_start).map(|l| &l[..13]),
        Some("<transmission")
    );
    assert!(tags.contains(&("limit", 4)), "{tags:?}");
}

#[test]
fn a_floating_robot_at_rest_falls_as_one_body() {
    // In uniform gravity, with no other force, every part of a free robot
    // at rest accelerates with g: the joints do not move relative to each other.
    let text = std::fs::read_to_string(folder().join("arm6.urdf")).unwrap();
    let robot = urdf::parse(&text).unwrap();
    let dyad = urdf::to_dyad(&robot, "arm6.urdf", &ImportOptions { floating: true, ..Default::default() });
    let mut package = Package::new();
    package.add_source("arm6.dyad", dyad).unwrap();
    let target = package.choose_target(None, None).unwrap();
    let lowered = package.lower_target(&target, &[]).unwrap_or_else(|d| panic!("{}", package.render(&[d])));
    let mechanism = lowered.assemble().unwrap_or_else(|d| panic!("{}", package.render(&[d])));
    let mut sim = Simulator::for_host(Arc::new(mechanism), &SimulationOptions::default()).unwrap();
    let names = sim.state_names().to_vec();
    let mut y = sim.state().to_vec();
    // Joints turned somewhere, at rest.
    for (k, n) in names.iter().enumerate() {
        if n.ends_with(".phi") || n.ends_with(".s") {
            y[k] = 0.1 * (k as f64 + 1.0);
        }
    }
    sim.set_continuous_state(&y).unwrap();
    let mut dy = vec![0.0; y.len()];
    sim.derivatives(&mut dy).unwrap();
    for (k, n) in names.iter().enumerate() {
        let want = if n == "base.v_0[3]" { -9.80665 } else { 0.0 };
        if n.ends_with(".w") || n.ends_with(".v") || n.contains(".v_0[") || n.contains(".w_a[") {
            assert!((dy[k] - want).abs() < 1e-10, "{n}: {} (states {names:?})", dy[k]);
        }
    }
    assert!(names.iter().any(|n| n == "base.v_0[3]"), "{names:?}");
}
