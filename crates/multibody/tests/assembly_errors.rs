//! Each error of model validation and assembly: its variant, the
//! components it names and the fix its message gives. Every message is
//! printed (run with --nocapture to read them).

use multibody::{Error, Model, OrientationState};

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
    assert_mentions(&message, &["`pm1`", "`rod`", "`pm2`", "World", "Body", "orientation_state = Quaternion"]);
}

/// A free Body with the default orientation_state (None) owns nothing.
#[test]
fn free_body_without_orientation_state_has_no_owner() {
    let mut model = world("free_body_default_state");
    model.add("body", "Body").set("m", 2.0);
    let (err, message) = failure(&model);
    assert!(matches!(&err, Error::NoOrientationOwner { components } if components == &["body".to_string()]), "{err:?}");
    assert_mentions(&message, &["`body`", "World", "orientation_state = Quaternion"]);
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
