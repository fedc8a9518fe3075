//! Each error of model validation and assembly: its variant, the
//! components it names and the fix its message gives. Every message is
//! printed (run with --nocapture to read them).

use multibody::{Error, Model, OrientationState};

#[path = "common/four_bar.rs"]
mod four_bar;

/// Assembles a model that must fail, prints the message and returns the
/// error with its text.
fn failure(model: &Model) -> (Error, String) {
    let err = match model.assemble() {
        Ok(_) => panic!("{}: assembly should fail", model.name),
        Err(e) => e,
    };
    let message = err.to_string();
    println!("{}:\n  {err:?}\n  {message}\n", model.name);
    (err, message)
}

fn assert_mentions(message: &str, words: &[&str]) {
    for w in words {
        assert!(message.contains(w), "the message should mention {w:?}: {message}");
    }
}

fn world(name: &str) -> Model {
    let mut model = Model::new(name);
    model.add("world", "World");
    model
}

// ------------------------------------------------------ orientation owners

/// The PointMass seed's case: a rigid assembly of PointMass and
/// FixedTranslation with no Body and no anchor to the world.
#[test]
fn point_masses_on_a_rod_have_no_owner_of_their_orientation() {
    let mut model = world("point_masses_on_a_free_rod");
    model.add("pm1", "PointMass");
    model.add("rod", "FixedTranslation").set("r", [1.0, 0.0, 0.0]);
    model.add("pm2", "PointMass");
    model.connect(["pm1.frame_a", "rod.frame_a"]);
    model.connect(["rod.frame_b", "pm2.frame_a"]);
    let (err, message) = failure(&model);
    match &err {
        Error::NoOrientationOwner { components } => {
            for name in ["pm1", "rod", "pm2"] {
                assert!(components.iter().any(|c| c == name), "{name} is in the assembly: {components:?}");
            }
        }
        other => panic!("expected NoOrientationOwner, got {other:?}"),
    }
    // The fix: anchor it to the World, or give it a Body with an orientation state.
    assert_mentions(
        &message,
        &["`pm1`", "`rod`", "`pm2`", "World", "Body", "orientation_state = OrientationState.Quaternion()"],
    );
}

/// A free Body with the default orientation_state (None) owns nothing.
#[test]
fn free_body_without_orientation_state_has_no_owner() {
    let mut model = world("free_body_default_state");
    model.add("body", "Body").set("m", 2.0);
    let (err, message) = failure(&model);
    assert!(matches!(&err, Error::NoOrientationOwner { components } if components == &["body".to_string()]), "{err:?}");
    assert_mentions(&message, &["`body`", "World", "orientation_state = OrientationState.Quaternion()"]);
}

/// Two Quaternion Bodies joined rigidly: two owners of one orientation.
#[test]
fn two_owners_in_one_rigid_group() {
    let mut model = world("two_owners");
    model.add("body1", "Body").set("orientation_state", OrientationState::Quaternion);
    model.add("rod", "FixedTranslation").set("r", [0.5, 0.0, 0.0]);
    model.add("body2", "Body").set("orientation_state", OrientationState::Quaternion);
    model.connect(["body1.frame_a", "rod.frame_a"]);
    model.connect(["rod.frame_b", "body2.frame_a"]);
    let (err, message) = failure(&model);
    match &err {
        Error::TwoOwners { first, second, group } => {
            let mut owners = [first.as_str(), second.as_str()];
            owners.sort();
            assert_eq!(owners, ["body1", "body2"]);
            assert!(group.iter().any(|c| c == "rod"), "the group includes the rod: {group:?}");
        }
        other => panic!("expected TwoOwners, got {other:?}"),
    }
    assert_mentions(&message, &["`body1`", "`body2`", "keep exactly one", "orientation_state", "None"]);
}

/// An isroot PointMass that is connected to something (a rod here, with a
/// Body on the other end that owns nothing).
#[test]
fn connected_root_point_mass_is_refused() {
    let mut model = world("connected_root_point_mass");
    model.add("pm", "PointMass").set("isroot", true);
    model.add("rod", "FixedTranslation").set("r", [0.5, 0.0, 0.0]);
    model.add("body", "Body");
    model.connect(["pm.frame_a", "rod.frame_a"]);
    model.connect(["rod.frame_b", "body.frame_a"]);
    let (err, message) = failure(&model);
    match &err {
        Error::ConnectedRootPointMass { component, connected_to } => {
            assert_eq!(component, "pm");
            assert!(connected_to.iter().any(|c| c == "rod"), "{connected_to:?}");
        }
        other => panic!("expected ConnectedRootPointMass, got {other:?}"),
    }
    assert_mentions(&message, &["`pm`", "`rod`", "isroot = false"]);
}

/// An isroot PointMass connected straight to the World: still a connected
/// root point mass, and the fix is `isroot = false` (a PointMass has no
/// orientation_state to set to None).
#[test]

fn root_point_mass_connected_to_the_world_is_told_to_drop_isroot() {
    let mut model = world("root_point_mass_on_the_world");
    model.add("pm", "PointMass").set("isroot", true);
    model.connect(["world.frame_b", "pm.frame_a"]);
    let (err, message) = failure(&model);
    match &err {
        Error::ConnectedRootPointMass { component, connected_to } => {
            assert_eq!(component, "pm");
            assert!(connected_to.iter().any(|c| c == "world"), "{connected_to:?}");
        }
        other => panic!("expected ConnectedRootPointMass, got {other:?}"),
    }
    assert_mentions(&message, &["`pm`", "`world`", "isroot = false"]);
    assert!(!message.contains("orientation_state"), "a PointMass has no orientation_state: {message}");
}

/// A Body with an orientation state that a joint chain from the World also
/// positions.
#[test]
fn body_with_orientation_state_positioned_by_joints() {
    let mut model = world("owner_positioned_by_joints");
    model.add("rev", "Revolute");
    model.add("body", "Body").set("r_cm", [0.5, 0.0, 0.0]).set("orientation_state", OrientationState::Quaternion);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    let (err, message) = failure(&model);
    match &err {
        Error::OwnerPositionedByJoints { component, through } => {
            assert_eq!(component, "body");
            assert!(through.iter().any(|c| c == "rev"), "{through:?}");
        }
        other => panic!("expected OwnerPositionedByJoints, got {other:?}"),
    }
    assert_mentions(&message, &["`body`", "`rev`", "orientation_state", "None"]);
}

/// A degree of freedom with no inertia behind it: a lone PointMass on the
/// axis of a Revolute.
#[test]
fn degree_of_freedom_without_inertia() {
    let mut model = world("point_mass_on_the_axis");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("pm", "PointMass").set("m", 3.0);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "pm.frame_a"]);
    let (err, message) = failure(&model);
    match &err {
        Error::NoInertia { joint, moved, .. } => {
            assert_eq!(joint, "rev");
            assert!(moved.iter().any(|c| c == "pm"), "{moved:?}");
        }
        other => panic!("expected NoInertia, got {other:?}"),
    }
    assert_mentions(&message, &["`rev`", "`pm`", "axis", "mass", "inertia"]);
}

// ------------------------------------------------------------ validation

#[test]
fn unknown_kind_suggests_the_closest() {
    let mut model = world("unknown_kind");
    model.add("rev", "Revolut");
    let (err, message) = failure(&model);
    match &err {
        Error::UnknownKind { component, kind, suggestions } => {
            assert_eq!((component.as_str(), kind.as_str()), ("rev", "Revolut"));
            assert_eq!(suggestions.first().map(String::as_str), Some("Revolute"));
        }
        other => panic!("expected UnknownKind, got {other:?}"),
    }
    assert_mentions(&message, &["`rev`", "`Revolut`", "Did you mean `Revolute`?"]);
}

#[test]
fn unknown_parameter_suggests_the_closest_and_lists_them() {
    let mut model = world("unknown_parameter");
    model.add("body", "Body").set("r_mc", [0.5, 0.0, 0.0]);
    let (err, message) = failure(&model);
    match &err {
        Error::UnknownParameter { component, param, suggestions, valid, .. } => {
            assert_eq!((component.as_str(), param.as_str()), ("body", "r_mc"));
            assert!(suggestions.iter().any(|s| s == "r_cm"), "{suggestions:?}");
            assert!(valid.iter().any(|s| s == "I_11"), "{valid:?}");
        }
        other => panic!("expected UnknownParameter, got {other:?}"),
    }
    assert_mentions(&message, &["`body`", "`r_mc`", "`r_cm`", "Body"]);
}

#[test]
fn wrong_size_is_reported() {
    let mut model = world("wrong_size");
    model.add("body", "Body").set("r_cm", [0.5, 0.0]);
    let (err, message) = failure(&model);
    assert!(
        matches!(&err, Error::WrongSize { component, name, expected: 3, got: 2 } if component == "body" && name == "r_cm"),
        "{err:?}"
    );
    assert_mentions(&message, &["body.r_cm", "3", "2"]);
}

#[test]
fn wrong_type_is_reported() {
    let mut model = world("wrong_type");
    model.add("body", "Body").set("m", true);
    let (err, message) = failure(&model);
    assert!(matches!(&err, Error::WrongType { component, name, .. } if component == "body" && name == "m"), "{err:?}");
    assert_mentions(&message, &["body.m", "a number", "a boolean"]);
}

#[test]
fn unknown_connector_suggests_the_closest() {
    let mut model = world("unknown_connector");
    model.add("body", "Body");
    model.connect(["world.frame_b", "body.frame_b"]);
    let (err, message) = failure(&model);
    match &err {
        Error::UnknownConnector { component, connector, suggestions, .. } => {
            assert_eq!((component.as_str(), connector.as_str()), ("body", "frame_b"));
            assert!(suggestions.iter().any(|s| s == "frame_a"), "{suggestions:?}");
        }
        other => panic!("expected UnknownConnector, got {other:?}"),
    }
    assert_mentions(&message, &["`body`", "`frame_b`", "frame_a"]);
}

#[test]
fn incompatible_connectors_are_refused() {
    let mut model = world("incompatible_connectors");
    model.add("rev", "Revolute").set("axisflange", true);
    model.add("body", "Body");
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.axis", "body.frame_a"]);
    let (err, message) = failure(&model);
    assert!(matches!(&err, Error::IncompatibleConnectors { .. }), "{err:?}");
    let mut names = err.components();
    names.sort();
    assert_eq!(names, ["body", "rev"]);
    assert_mentions(&message, &["rev.axis", "body.frame_a", "Frame3D", "same type"]);
}

#[test]
fn model_without_world() {
    let mut model = Model::new("no_world");
    model.add("body", "Body").set("orientation_state", OrientationState::Quaternion);
    let (err, message) = failure(&model);
    assert!(matches!(err, Error::NoWorld), "{err:?}");
    assert_mentions(&message, &["no World", "add one"]);
}

#[test]
fn model_with_two_worlds() {
    let mut model = world("two_worlds");
    model.add("world2", "World");
    let (err, message) = failure(&model);
    match &err {
        Error::SeveralWorlds { names } => assert_eq!(names, &["world".to_string(), "world2".to_string()]),
        other => panic!("expected SeveralWorlds, got {other:?}"),
    }
    assert_mentions(&message, &["world", "world2", "keep exactly one"]);
}

#[test]
fn duplicate_names_are_refused() {
    let mut model = world("duplicate_name");
    model.add("body", "Body").set("orientation_state", OrientationState::Quaternion);
    model.add("body", "PointMass").set("isroot", true);
    let (err, message) = failure(&model);
    assert!(matches!(&err, Error::DuplicateName { name } if name == "body"), "{err:?}");
    assert_mentions(&message, &["`body`", "own name"]);
}

/// r_0 of a Body that joints position is computed, not a state.
#[test]
fn initial_value_on_a_non_state() {
    let mut model = world("initial_on_non_state");
    model.add("rev", "Revolute");
    model.add("body", "Body").set("r_cm", [0.5, 0.0, 0.0]).initial("r_0", [1.0, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    let (err, message) = failure(&model);
    assert!(
        matches!(&err, Error::NotAState { component, variable, .. } if component == "body" && variable == "r_0"),
        "{err:?}"
    );
    assert_mentions(&message, &["body.r_0", "not a state", "joints"]);
}

/// A start value for a variable the component does not have: did-you-mean.
#[test]
fn initial_value_on_an_unknown_variable() {
    let mut model = world("initial_on_unknown_variable");
    model.add("rev", "Revolute").initial("phii", 0.3);
    model.add("body", "Body").set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    let (err, message) = failure(&model);
    match &err {
        Error::UnknownVariable { component, variable, suggestions, .. } => {
            assert_eq!((component.as_str(), variable.as_str()), ("rev", "phii"));
            assert!(suggestions.iter().any(|s| s == "phi"), "{suggestions:?}");
        }
        other => panic!("expected UnknownVariable, got {other:?}"),
    }
    assert_mentions(&message, &["`rev`", "`phii`", "`phi`"]);
}

/// Each did-you-mean suggestion appears once.
#[test]

fn unknown_variable_suggestions_are_not_repeated() {
    let mut model = world("unknown_variable_suggestions");
    model.add("rev", "Revolute").initial("phii", 0.3);
    model.add("body", "Body").set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    let (err, message) = failure(&model);
    let Error::UnknownVariable { suggestions, .. } = &err else { panic!("expected UnknownVariable, got {err:?}") };
    let mut unique = suggestions.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(unique.len(), suggestions.len(), "repeated suggestions {suggestions:?}: {message}");
}

// ------------------------------------------------------------ kinematic loops

/// A planar four-bar of plain revolutes `j1` to `j4` (no start values, no
/// damper), for `setup` to change.
fn four_bar_loop(name: &str, setup: &dyn Fn(&mut Model)) -> Model {
    let mut model = four_bar::four_bar_linkage(name, 1.0);
    setup(&mut model);
    model
}

/// A rotational damper on the axis of `joint`.
fn damp(model: &mut Model, joint: &str) {
    model.component_mut(joint).expect("a joint").set("axisflange", true);
    let damper = format!("damper_{joint}");
    model.add(&damper, "RotationalComponents.Damper").set("d", 0.1);
    model.connect([format!("{damper}.spline_a"), format!("{joint}.support")]);
    model.connect([format!("{damper}.spline_b"), format!("{joint}.axis")]);
}

/// Every joint of the loop carries a damper, so the joint that must be cut
/// carries one: the message is one sentence that names the loop, and says
/// what to do after what is not supported.
#[test]
fn loop_whose_every_joint_has_elements_names_the_loop() {
    let model = four_bar_loop("damped_everywhere", &|m| {
        for j in ["j1", "j2", "j3", "j4"] {
            damp(m, j);
        }
    });
    let (err, message) = failure(&model);
    let Error::Unsupported { component, what, fix } = &err else { panic!("expected Unsupported, got {err:?}") };
    assert_eq!(component, "j4");
    assert_mentions(what, &["every joint", "`j1`", "`j2`", "`j3`", "`j4`"]);
    assert_mentions(fix, &["Remove the 1-D elements from one joint"]);
    // "... is not supported yet; <what to do>", never "<what to do> is not supported yet".
    assert!(message.ends_with(fix.as_str()) && message.contains("is not supported yet; "), "{message}");
}

/// The joint marked `iscut` has a start value: the fix is to remove
/// `iscut` (not to mark another joint).
#[test]
fn start_value_on_the_joint_marked_iscut() {
    let model = four_bar_loop("iscut_with_start_value", &|m| {
        m.component_mut("j1").unwrap().set("iscut", true).initial("phi", 0.1);
    });
    let (err, message) = failure(&model);
    let Error::NotAState { component, variable, reason } = &err else { panic!("expected NotAState, got {err:?}") };
    assert_eq!((component.as_str(), variable.as_str()), ("j1", "phi"));
    assert_mentions(reason, &["marked `iscut = true`", "Remove `iscut = true`", "`j2`", "`j3`", "`j4`"]);
    assert!(!message.contains("mark another joint"), "{message}");
}

/// Start values on every joint of a loop: one of them must go, and no
/// joint is left to mark with `iscut`.
#[test]
fn start_values_on_every_joint_of_a_loop() {
    let model = four_bar_loop("every_joint_started", &|m| {
        for j in ["j1", "j2", "j3", "j4"] {
            m.component_mut(j).unwrap().initial("phi", 0.0);
        }
    });
    let (err, message) = failure(&model);
    let Error::NotAState { reason, .. } = &err else { panic!("expected NotAState, got {err:?}") };
    assert_mentions(
        reason,
        &["every joint of this loop that could be cut has start values", "Remove the start values"],
    );
    assert!(!message.contains("iscut"), "no joint is free to be marked iscut: {message}");
}

/// A guess (not a start value that holds) on the joint the engine cuts:
/// another joint of the loop is free, and marking it `iscut` cuts it instead.
#[test]
fn guess_on_the_cut_joint_suggests_a_free_joint_of_the_loop() {
    let model = four_bar_loop("guess_on_cut_joint", &|m| {
        m.component_mut("j4").unwrap().guess("phi", 0.1);
    });
    let (err, _) = failure(&model);
    let Error::NotAState { component, reason, .. } = &err else { panic!("expected NotAState, got {err:?}") };
    assert_eq!(component, "j4");
    assert_mentions(reason, &["mark one of `j1`, `j2` or `j3` with `iscut = true`"]);
}

/// A joint whose two frames are also joined by a rod closes a loop of one
/// joint: there is no other joint to cut.
#[test]
fn joint_whose_frames_are_joined_rigidly() {
    let mut model = world("joint_beside_a_rod");
    model.add("rev", "Revolute").initial("phi", 0.3);
    model.add("rod", "FixedTranslation").set("r", [0.5, 0.0, 0.0]);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a", "rod.frame_a"]);
    model.connect(["rev.frame_b", "rod.frame_b", "body.frame_a"]);
    let (err, message) = failure(&model);
    let Error::NotAState { component, reason, .. } = &err else { panic!("expected NotAState, got {err:?}") };
    assert_eq!(component, "rev");
    assert_mentions(reason, &["joined rigidly", "Remove the joint"]);
    assert!(!message.contains("iscut"), "there is no other joint to mark: {message}");
}

/// A joint with elements on its axis stays in the tree before joints with
/// start values, so the loop is cut at one of those (and the message says
/// which start values to drop), not at the damped joint.
#[test]
fn joint_with_elements_is_kept_before_joints_with_start_values() {
    let model = four_bar_loop("damped_and_started", &|m| {
        for j in ["j1", "j2", "j3"] {
            m.component_mut(j).unwrap().initial("phi", 0.0);
        }
        damp(m, "j4");
    });
    let (err, _) = failure(&model);
    let Error::NotAState { component, reason, .. } = &err else { panic!("expected NotAState, got {err:?}") };
    assert_ne!(component, "j4", "the damped joint is not cut: {reason}");
    assert_mentions(reason, &["Remove the start values"]);
}

// ------------------------------------------------------ physical parameters

/// Each (kind, parameter, value) must be refused, naming the component and
/// the parameter.
fn refused(cases: &[(&str, &str, f64)]) {
    for &(kind, param, value) in cases {
        let model = if kind == "World" {
            let mut model = Model::new("world_parameter");
            model.add("world", "World").set(param, value);
            model
        } else {
            let mut model = world(&format!("{kind}_{param}"));
            let part = model.add("part", kind);
            if kind == "BodyBox" || kind == "BodyCylinder" {
                part.set("r", [0.5, 0.0, 0.0]);
            }
            part.set(param, value);
            model
        };
        let err = model.assemble().err().unwrap_or_else(|| panic!("{kind} {param} = {value} should be refused"));
        let message = err.to_string();
        let named = if kind == "World" { "world" } else { "part" };
        match &err {
            Error::InvalidValue { component, name, .. } => {
                assert_eq!((component.as_str(), name.as_str()), (named, param), "{message}")
            }
            other => panic!("{kind} {param} = {value}: expected InvalidValue, got {other:?}"),
        }
        assert_mentions(&message, &[&format!("`{named}.{param}`")]);
    }
}

#[test]
fn negative_sizes_of_a_box_are_refused() {
    refused(&[("BodyBox", "width", -0.1), ("BodyBox", "height", -0.1), ("BodyBox", "inner_height", -0.01)]);
}

#[test]
fn negative_point_gravity_constant_is_refused() {
    refused(&[("World", "mu", -1.0)]);
}

#[test]
fn negative_stiffness_damping_mass_and_density_are_refused() {
    refused(&[
        ("Spring", "c", -1.0),
        ("Damper", "d", -1.0),
        ("SpringDamperParallel", "c", -1.0),
        ("SpringDamperParallel", "d", -1.0),
        ("Body", "m", -1.0),
        ("BodyShape", "m", -1.0),
        ("PointMass", "m", -1.0),
        ("BodyBox", "density", -1.0),
        ("BodyCylinder", "density", -1.0),
        ("BodyCylinder", "diameter", -0.1),
        ("RotationalComponents.Inertia", "J", -1.0),
        ("TranslationalComponents.Mass", "m", -1.0),
        ("Rotor1D", "J", 0.0),
        ("RotationalComponents.IdealGear", "ratio", 0.0),
        ("BevelGear1D", "ratio", 0.0),
        ("RotationalComponents.Spring", "c", -1.0),
        ("TranslationalComponents.Damper", "d", -1.0),
    ]);
}

#[test]
fn non_finite_parameters_are_refused() {
    refused(&[
        ("Spring", "c", f64::NAN),
        ("Damper", "d", f64::INFINITY),
        ("Body", "m", f64::NAN),
        ("Body", "I_11", f64::NEG_INFINITY),
        ("BodyBox", "density", f64::INFINITY),
        ("RotationalComponents.IdealGear", "ratio", f64::NAN),
        ("World", "g", f64::INFINITY),
    ]);
}

/// Signed parameters stay signed: a negative gear ratio, a zero unstretched
/// length, a negative gravity (pointing along `n` reversed).
#[test]
fn legitimately_signed_parameters_are_accepted() {
    let mut model = world("signed_parameters");
    model.component_mut("world").unwrap().set("g", -9.81);
    model.add("gear", "RotationalComponents.IdealGear").set("ratio", -2.0);
    model.add("spring", "Spring").set("c", 10.0).set("s_unstretched", 0.0);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.add("rev", "Revolute").set("axisflange", true);
    model.add("inertia", "RotationalComponents.Inertia").set("J", 1.0);
    model.connect(["world.frame_b", "rev.frame_a", "spring.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a", "spring.frame_b"]);
    model.connect(["rev.axis", "gear.spline_a"]);
    model.connect(["gear.spline_b", "inertia.spline_a"]);
    model.connect(["rev.support", "gear.support"]);
    if let Err(e) = model.assemble() {
        panic!("signed parameters are allowed: {e}");
    }
}
