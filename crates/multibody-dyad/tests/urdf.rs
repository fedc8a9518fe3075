//! URDF robots imported as Dyad models, checked against Pinocchio: the
//! forward dynamics, mass matrix, inverse dynamics and link poses at ten
//! random states of each file in `tests/urdf/`, with a fixed and a floating
//! base and with the file's joint damping (golden values made by
//! `scripts/urdf_goldens.py` with PyPI's `pin`); mimic joints held through
//! a run; and bad files, each with its message at file:line:col.

use multibody::{JointSpace, Mechanism, SimulationOptions, Simulator};
use multibody_dyad::urdf::{self, ImportOptions};
use multibody_dyad::Package;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::sync::Arc;

fn folder() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/urdf")
}

/// Each URDF name of a joint or link and its component's.
#[derive(Default)]
struct Names {
    joints: Vec<(String, String)>,
    links: Vec<(String, String)>,
    root: String,
}

impl Names {
    /// A joint of Pinocchio's: the floating base is its root link.
    fn joint(&self, pinocchio: &str) -> Option<&str> {
        if pinocchio == "root_joint" {
            return Some(&self.root);
        }
        self.joints.iter().find(|(u, _)| u == pinocchio).map(|(_, d)| d.as_str())
    }

    fn link(&self, urdf: &str) -> Option<&str> {
        self.links.iter().find(|(u, _)| u == urdf).map(|(_, d)| d.as_str())
    }
}

/// The robot of the file at `path` imported and assembled, and the Dyad
/// names of the URDF's joints and links.
fn mechanism(path: &Path, options: &ImportOptions) -> Result<(Arc<Mechanism>, Names), String> {
    let file = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let robot = urdf::parse(&text).map_err(|e| e.render(&file))?;
    let (link_ids, joint_ids) = urdf::dyad_names(&robot);
    let names = Names {
        joints: robot.joints.iter().map(|j| j.name.clone()).zip(joint_ids).collect(),
        root: link_ids[robot.root].clone(),
        links: robot.links.iter().map(|l| l.name.clone()).zip(link_ids).collect(),
    };
    let dyad = urdf::to_dyad(&robot, &file, options);
    let mut package = Package::new();
    package.add_source(format!("{file}.dyad"), dyad).map_err(|d| package.render(&[d]))?;
    let target = package.choose_target(None, None)?;
    let lowered = package.lower_target(&target, &[]).map_err(|d| package.render(&[d]))?;
    let mechanism = lowered.assemble().map_err(|d| package.render(&[d]))?;
    Ok((Arc::new(mechanism), names))
}

fn numbers(x: &Value) -> Vec<f64> {
    x.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// The worst differences between our dynamics and Pinocchio's `golden`
/// ones, each relative to the largest value of its kind at a state:
/// forward dynamics (the simulator's and the joint space's), mass matrix,
/// inverse dynamics and link poses; an error when the file does not load.
fn compare(path: &Path, golden: &Value) -> Result<[f64; 4], String> {
    let options = ImportOptions {
        floating: golden["floating"].as_bool().unwrap_or(false),
        // Pinocchio's dynamics leave joint damping out: the golden values
        // of a damped variant have its torques as joint forces.
        damping: golden["damped"].as_bool().unwrap_or(false),
        // Nor mimic joints, unless asked (mimic_joints_hold_through_a_run).
        mimic: false,
        ..Default::default()
    };
    let (mechanism, names) = mechanism(path, &options)?;
    let mut sim = Simulator::for_host(mechanism.clone(), &SimulationOptions::default()).map_err(|s| s.reason)?;
    let mut space = JointSpace::new(mechanism.clone())?;
    let (nq, nv) = (space.coordinates().len(), space.velocities().len());
    // Where each of Pinocchio's coordinates is in ours, in its order.
    let (mut q_at, mut v_at) = (Vec::new(), Vec::new());
    for joint in golden["joints"].as_array().unwrap() {
        let name = joint["name"].as_str().unwrap();
        let ours = names.joint(name).ok_or_else(|| format!("Pinocchio's joint {name} is not in the file"))?;
        let (q, v) = space.joint(ours).ok_or_else(|| format!("`{ours}` is not in the joint space"))?;
        if q.len() as u64 != joint["nq"].as_u64().unwrap() || v.len() as u64 != joint["nv"].as_u64().unwrap() {
            return Err(format!("`{ours}` has {} and {} coordinates, Pinocchio's {joint}", q.len(), v.len()));
        }
        q_at.extend(q);
        v_at.extend(v);
    }
    if q_at.len() != nq || v_at.len() != nv {
        return Err(format!("{nq} and {nv} coordinates for Pinocchio's {} and {}", q_at.len(), v_at.len()));
    }
    let ours = |x: &[f64], at: &[usize]| -> Vec<f64> {
        let mut o = vec![0.0; at.len()];
        for (k, &i) in at.iter().enumerate() {
            o[i] = x[k];
        }
        o
    };
    let largest = |x: &[f64]| x.iter().fold(1.0_f64, |s, x| s.max(x.abs()));
    let mut worst = [0.0_f64; 4];
    for state in golden["states"].as_array().unwrap() {
        let (q, v, a) = (
            ours(&numbers(&state["q"]), &q_at),
            ours(&numbers(&state["v"]), &v_at),
            ours(&numbers(&state["a"]), &v_at),
        );
        let (ddq, tau) = (numbers(&state["ddq"]), numbers(&state["tau"]));
        let mass: Vec<f64> = state["M"].as_array().unwrap().iter().flat_map(numbers).collect();
        let mut m = vec![0.0; nv * nv];
        space.mass_matrix(&q, &mut m)?;
        let scale = largest(&mass);
        for i in 0..nv {
            for j in 0..nv {
                worst[1] = worst[1].max((m[v_at[i] * nv + v_at[j]] - mass[i * nv + j]).abs() / scale);
            }
        }
        let mut t = vec![0.0; nv];
        space.inverse_dynamics(&q, &v, &a, &mut t)?;
        for k in 0..nv {
            worst[2] = worst[2].max((t[v_at[k]] - tau[k]).abs() / largest(&tau));
        }
        let mut fd = vec![0.0; nv];
        space.forward_dynamics(&q, &v, &vec![0.0; nv], &mut fd)?;
        // Accelerations are compared relative to their largest, and within
        // what rounding allows: solving M x = b loses up to cond(M) times
        // the precision (iCub's M reaches 1.2e8), so the tolerance 1e-10
        // stands for cond(M) up to 1e5 and grows with it past that.
        let cond = state["cond"].as_f64().unwrap_or(1.0);
        let scale = largest(&ddq) * (cond / 1e5).max(1.0);
        for k in 0..nv {
            worst[0] = worst[0].max((fd[v_at[k]] - ddq[k]).abs() / scale);
        }
        // The simulator's derivatives at the same state.
        let y: Vec<f64> = q.iter().chain(&v).copied().collect();
        sim.set_continuous_state(&y)?;
        let mut dy = vec![0.0; y.len()];
        sim.derivatives(&mut dy)?;
        for k in 0..nv {
            worst[0] = worst[0].max((dy[nq + v_at[k]] - ddq[k]).abs() / scale);
        }
        for (link, pose) in state["poses"].as_object().unwrap() {
            let frame = names.link(link).ok_or_else(|| format!("Pinocchio's link {link} is not in the file"))?;
            let pose = numbers(pose);
            let ours = space.frame_pose(frame, &q)?;
            let flat: Vec<f64> = ours.r_0.iter().chain(ours.rotation.iter().flatten()).copied().collect();
            for k in 0..12 {
                worst[3] = worst[3].max((flat[k] - pose[k]).abs() / largest(&pose[..3]).max(1.0));
            }
        }
    }
    Ok(worst)
}

const KINDS: [&str; 4] = ["forward dynamics", "mass matrix", "inverse dynamics", "link poses"];

fn describe(error: &[f64; 4]) -> String {
    KINDS.iter().zip(error).map(|(k, e)| format!("{k} {e:.1e}")).collect::<Vec<_>>().join(", ")
}

#[test]
fn dynamics_and_poses_equal_pinocchios_with_fixed_and_floating_bases() {
    let goldens: Value =
        serde_json::from_str(&std::fs::read_to_string(folder().join("goldens.json")).unwrap()).unwrap();
    let mut worst = [0.0_f64; 4];
    for (variant, golden) in goldens.as_object().unwrap() {
        let file = variant.split(' ').next().unwrap();
        let error = compare(&folder().join(file), golden).unwrap_or_else(|e| panic!("{variant}: {e}"));
        assert!(
            error.iter().all(|&e| e < 1e-10),
            "{variant}: differs from Pinocchio by {} (relative)",
            describe(&error)
        );
        for k in 0..4 {
            worst[k] = worst[k].max(error[k]);
        }
    }
    let variants: Vec<&String> = goldens.as_object().unwrap().keys().collect();
    assert!(
        variants.iter().any(|v| v.ends_with("floating")) && variants.iter().any(|v| v.ends_with("damped")),
        "the golden values lack a floating or a damped variant: {variants:?}"
    );
    println!(
        "vs Pinocchio ({} variants), worst relative differences: {} (tolerance 1e-10)",
        variants.len(),
        describe(&worst)
    );
}

/// The robots `scripts/fetch-robots.sh` fetched (example-robot-data from
/// PyPI, with Pinocchio's golden values): `$MULTIBODY_ROBOTS`, by default
/// the workspace's `target/robots`; `None`, said, when they are not there.
fn robots() -> Option<(PathBuf, Value)> {
    let folder = std::env::var_os("MULTIBODY_ROBOTS")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/robots"));
    let Ok(text) = std::fs::read_to_string(folder.join("pinocchio-goldens.json")) else {
        println!(
            "skipped: no robots in {} (scripts/fetch-robots.sh fetches them with Pinocchio's values)",
            folder.display()
        );
        return None;
    };
    Some((folder.join("example-robot-data"), serde_json::from_str(&text).unwrap()))
}

/// Every URDF file of example-robot-data, with a fixed and a floating
/// base: each either agrees with Pinocchio to 1e-10 or is refused with a
/// message; the counts are printed.
#[test]
fn a_corpus_of_real_robots_agrees_with_pinocchio_or_is_refused() {
    let Some((folder, goldens)) = robots() else { return };
    let files = count_urdf_files(&folder);
    let (mut agree, mut refused, mut worst, mut differ) = (0, Vec::new(), [0.0_f64; 4], Vec::new());
    for (variant, golden) in goldens.as_object().unwrap() {
        let path = folder.join(variant.split(" floating").next().unwrap());
        let name = format!(
            "{}{}",
            path.file_name().unwrap().to_string_lossy(),
            if variant.ends_with(" floating") { " (floating)" } else { "" }
        );
        let floating = golden["floating"].as_bool().unwrap_or(false);
        if golden["singular"].as_bool() == Some(true) {
            // Pinocchio's mass matrix is singular: ours must refuse the model.
            let refusal =
                mechanism(&path, &ImportOptions { floating, damping: false, mimic: false, ..Default::default() }).err();
            assert!(refusal.is_some(), "{name}: Pinocchio finds a singular mass matrix, but the model was accepted");
            refused
                .push(format!("{name} (singular in Pinocchio too): {}", refusal.unwrap().lines().next().unwrap_or("")));
            continue;
        }
        match compare(&path, golden) {
            Ok(error) if error.iter().all(|&e| e < 1e-10) => {
                for k in 0..4 {
                    worst[k] = worst[k].max(error[k]);
                }
                agree += 1;
            }
            Ok(error) => differ.push(format!("{name}: {}", describe(&error))),
            Err(message) => refused.push(format!("{name}: {}", message.lines().next().unwrap_or(""))),
        }
    }
    println!(
        "{files} URDF files, {} variants with Pinocchio's values (fixed and floating bases): {agree} agree \
         (worst: {}), {} refused:",
        agree + refused.len() + differ.len(),
        describe(&worst),
        refused.len()
    );
    for r in &refused {
        println!("  {r}");
    }
    assert!(differ.is_empty(), "differ from Pinocchio (relative): {differ:?}");
    // Most of the corpus must load: a regression that refuses files fails.
    assert!(agree >= 120, "only {agree} variants agree");
}

fn count_urdf_files(folder: &Path) -> usize {
    let mut count = 0;
    let mut stack = vec![folder.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "urdf") {
                count += 1;
            }
        }
    }
    count
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
        "{}\n{}\n<joint name=\"j\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 0\"/></joint>",
        link("a"),
        link("b")
    )));
    assert!(e.starts_with("bad.urdf:4:") && e.contains("the axis of `j` is zero"), "{e}");

    // A planar joint cannot be mimicked.
    let e = error_of(&robot(format!(
        "{}\n{}\n{}\n<joint name=\"p\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/></joint>\n\
         <joint name=\"m\" type=\"revolute\"><parent link=\"b\"/><child link=\"c\"/><mimic joint=\"p\"/></joint>",
        link("a"),
        link("b"),
        link("c")
    )));
    assert!(e.starts_with("bad.urdf:6:") && e.contains("`m` (revolute) mimics `p` (planar)"), "{e}");
}

/// A vector attribute is quoted whole, and commas get their own advice.
#[test]
fn a_vector_attribute_is_quoted_whole() {
    let with_origin = |xyz: &str| {
        format!(
            "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<joint name=\"j\" type=\"fixed\"><parent \
             link=\"a\"/><child link=\"b\"/><origin xyz=\"{xyz}\"/></joint>\n</robot>"
        )
    };
    let e = error_of(&with_origin("0.07, 0, -0.69"));
    assert!(
        e.contains("`xyz=\"0.07, 0, -0.69\"` of `<origin>` separates its numbers with commas")
            && e.contains("`xyz=\"0.07 0 -0.69\"`"),
        "{e}"
    );
    let e = error_of(&with_origin("0.07 zero -0.69"));
    assert!(e.contains("`xyz=\"0.07 zero -0.69\"` of `<origin>`: `zero` is not a finite number"), "{e}");
}

/// Damping on a fixed joint is listed as having no effect, apart from the
/// damping of planar and floating joints, which is not applied.
#[test]
fn damping_on_fixed_joints_is_listed_apart() {
    let text = "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n\
                <joint name=\"f\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/><dynamics damping=\"0.5\"/></joint>\n\
                <joint name=\"p\" type=\"planar\"><parent link=\"b\"/><child link=\"c\"/><dynamics damping=\"0.5\"/></joint>\n\
                </robot>";
    let robot = urdf::parse(text).unwrap();
    let tags: Vec<(&str, usize)> = robot.skipped.iter().map(|s| (s.tag.as_str(), s.count)).collect();
    assert!(
        tags.contains(&("dynamics damping of a fixed joint", 1)) && tags.contains(&("dynamics damping", 1)),
        "{tags:?}"
    );
    assert_eq!(
        urdf::skipped_effect("dynamics damping of a fixed joint"),
        "a fixed joint does not move, so its damping has no effect"
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

#[test]
fn mimic_joints_hold_through_a_run() {
    // Pinocchio's loader (4.1, mimic = true) refuses this file: a slide
    // mimics a revolute that itself mimics another, declared after it.
    let (mechanism, names) = mechanism(&folder().join("mimic.urdf"), &ImportOptions::default()).unwrap();
    assert_eq!(mechanism.degrees_of_freedom(), 1);
    let options = SimulationOptions { stop: 1.0, saveat: 0.001, reltol: 1e-8, abstol: 1e-8, ..Default::default() };
    let solution = mechanism.simulate(&options).unwrap();
    let column = |joint: &str, what: &str| solution.get(&format!("{}.{what}", names.joint(joint).unwrap())).unwrap();
    let (left, right, tip) = (column("left_finger", "phi"), column("right_finger", "phi"), column("tip", "s"));
    let (mut worst, mut travel) = (0.0_f64, 0.0_f64);
    for k in 0..left.len() {
        worst = worst.max((right[k] - (-left[k] + 0.01)).abs()).max((tip[k] - 0.02 * right[k]).abs());
        travel = travel.max(left[k].abs());
    }
    assert!(travel > 0.5, "the leader hardly moved ({travel} rad): the test would not see a loose coupling");
    assert!(worst < 1e-10, "the followers leave their leaders by {worst:.1e}");
    println!(
        "mimic joints: followers within {worst:.1e} of multiplier x leader + offset over 1 s ({} samples)",
        left.len()
    );
}

#[test]
fn bad_mimics_are_refused_with_their_place() {
    let text = std::fs::read_to_string(folder().join("mimic.urdf")).unwrap();
    let e = error_of(&text.replace("joint=\"left_finger\"", "joint=\"thumb\""));
    assert!(e.starts_with("bad.urdf:21:5") && e.contains("mimics the joint `thumb`, which does not exist"), "{e}");
    // The left finger mimicking the tip closes a circle of three.
    let circle = text.replace(
        "<limit lower=\"-1\" upper=\"1\" effort=\"5\" velocity=\"2\"/>\n  </joint>\n  <link name=\"left\">",
        "<limit lower=\"-1\" upper=\"1\" effort=\"5\" velocity=\"2\"/>\n    <mimic joint=\"tip\"/>\n  </joint>\n  <link name=\"left\">",
    );
    assert_ne!(circle, text);
    let e = error_of(&circle);
    assert!(e.contains("follow each other in a circle") && e.contains("right_finger -> left_finger -> tip"), "{e}");
}

#[test]
fn an_undamped_ur5_conserves_energy() {
    let Some((folder, _)) = robots() else { return };
    let path = folder.join("ur_description/urdf/ur5_robot.urdf");
    let text = std::fs::read_to_string(&path).unwrap();
    let robot = urdf::parse(&text).unwrap();
    assert!(robot.joints.iter().all(|j| j.damping == 0.0), "the UR5 file has damping: energy is not conserved");
    let dyad = urdf::to_dyad(&robot, "ur5_robot.urdf", &ImportOptions::default());
    let mut package = Package::new();
    package.add_source("ur5_robot.dyad", dyad).unwrap();
    let target = package.choose_target(None, None).unwrap();
    // Swinging from an arm stretched out sideways, every joint turned.
    let starts = [("shoulder_pan_joint", 0.3), ("shoulder_lift_joint", -0.4), ("elbow_joint", 0.6)];
    let starts = starts.iter().chain(&[("wrist_1_joint", -1.1), ("wrist_2_joint", 0.8), ("wrist_3_joint", 0.5)]);
    let overrides: Vec<_> = starts.map(|(j, x)| multibody_dyad::Override::initial(format!("{j}.phi"), *x)).collect();
    let lowered = package.lower_target(&target, &overrides).unwrap_or_else(|d| panic!("{}", package.render(&[d])));
    let mechanism = lowered.assemble().unwrap_or_else(|d| panic!("{}", package.render(&[d])));
    let options =
        SimulationOptions { stop: 5.0, saveat: 0.01, reltol: 1e-12, abstol: 1e-12, ..SimulationOptions::default() };
    let solution = mechanism.simulate(&options).unwrap();
    let sum = |suffix: &str| -> Vec<f64> {
        let columns: Vec<&[f64]> =
            solution.names().iter().filter(|n| n.ends_with(suffix)).map(|n| solution.get(n).unwrap()).collect();
        assert!(columns.len() >= 6, "{} columns end in {suffix}", columns.len());
        (0..solution.time().len()).map(|k| columns.iter().map(|c| c[k]).sum()).collect()
    };
    let (kinetic, potential) = (sum(".KE"), sum(".PE"));
    let energy: Vec<f64> = kinetic.iter().zip(&potential).map(|(k, p)| k + p).collect();
    // Relative to the energy that changes form: the largest kinetic energy.
    let scale = kinetic.iter().fold(0.0_f64, |m, k| m.max(*k));
    assert!(scale > 10.0, "the arm hardly moved (largest kinetic energy {scale} J)");
    let drift = energy.iter().map(|e| (e - energy[0]).abs()).fold(0.0, f64::max) / scale;
    assert!(drift < 1e-9, "the energy drifts by {drift:.1e} of the largest kinetic energy {scale:.1} J over 5 s");
    println!("UR5, 5 s undamped: energy within {drift:.1e} of the largest kinetic energy ({scale:.1} J)");
}

/// Places are counted as roxmltree counts them (columns in characters),
/// on a file of one line too, and for a place before the last one asked
/// for (the joints are read after every link).
#[test]
fn places_on_one_long_line_are_right() {
    let e = error_of("<robot name=\"ré\"><link name=\"a\"/><link name=\"a\"/></robot>");
    assert!(e.starts_with("bad.urdf:1:34: error: a second link named `a`"), "{e}");
    let e = error_of(
        "<robot name=\"ré\"><link name=\"a\"/><joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child \
         link=\"b\"/></joint><link name=\"c\"/></robot>",
    );
    assert!(e.starts_with("bad.urdf:1:81: error: the joint `j` names the child link `b`"), "{e}");
}

/// A robot whose shapes make its model too large is refused at `<robot>`,
/// with the count and the limit, before its model is made.
#[test]
fn a_robot_too_large_for_a_model_is_refused_with_the_count() {
    let mut text = String::from("<robot name=\"r\">\n<link name=\"l0\"/>\n");
    for i in 1..5000 {
        let shape = "<visual><geometry><sphere radius=\"0.1\"/></geometry></visual>";
        text += &format!(
            "<link name=\"l{i}\">{shape}{shape}{shape}</link><joint name=\"j{i}\" type=\"fixed\"><parent \
             link=\"l{}\"/><child link=\"l{i}\"/></joint>\n",
            i - 1
        );
    }
    text += "</robot>\n";
    let robot = urdf::parse(&text).unwrap();
    assert_eq!(urdf::component_count(&robot, &ImportOptions::default()), 1 + 5000 + 4999 + 3 * 4999);
    let e = urdf::check_size(&robot, &ImportOptions::default()).unwrap_err().render("r.urdf");
    assert!(
        e.starts_with(
            "r.urdf:1:1: error: the robot has 5000 links and 4999 joints: its model would have 24997 components, \
             and a model has at most 20000"
        ),
        "{e}"
    );
    // Fewer shapes fit.
    let smaller = text.replacen("<visual><geometry><sphere radius=\"0.1\"/></geometry></visual>", "", 4997 * 3);
    let robot = urdf::parse(&smaller).unwrap();
    assert!(urdf::check_size(&robot, &ImportOptions::default()).is_ok());
}
