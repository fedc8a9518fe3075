//! URDF files through the built command: `multibody import` writes a model
//! file named after the URDF's links and joints, which simulates as the
//! URDF read directly by `multibody run` does; bad files give file:line:col.

mod common;

use common::{code, crate_path, multibody, scratch, stderr};

fn arm() -> String {
    crate_path("../multibody-dyad/tests/urdf/arm6.urdf")
}

#[test]
fn import_writes_a_model_that_runs_as_the_urdf_does() {
    let dir = scratch("urdf-import");
    let out = multibody(&dir, &["import", &arm(), "-o", "arm.dyad"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let text = std::fs::read_to_string(dir.join("arm.dyad")).unwrap();
    for name in [
        "turn = MultibodyComponents.URDFRevolute",
        "slide = MultibodyComponents.URDFPrismatic",
        "World(n = [0, 0, -1])",
    ] {
        assert!(text.contains(name), "{name} missing from\n{text}");
    }
    // Each unmapped tag is noted once, with its place.
    let err = stderr(&out);
    assert_eq!(err.matches("`<limit>` is not mapped").count(), 1, "{err}");
    assert!(err.contains("arm6.urdf:24:5: note: `<limit>` is not mapped (4 of them)"), "{err}");
    assert!(err.contains("5 degrees of freedom; gravity along -z"), "{err}");

    let a = multibody(&dir, &["run", "arm.dyad", "--stop", "1", "-o", "a.csv", "--signals", "elbow.*"]);
    let b = multibody(&dir, &["run", &arm(), "--stop", "1", "-o", "b.csv", "--signals", "elbow.*"]);
    assert_eq!(code(&a), 0, "{}", stderr(&a));
    assert_eq!(code(&b), 0, "{}", stderr(&b));
    let (a, b) =
        (std::fs::read_to_string(dir.join("a.csv")).unwrap(), std::fs::read_to_string(dir.join("b.csv")).unwrap());
    assert!(a.starts_with("\"time\",\"elbow.phi\",\"elbow.w\""), "{}", &a[..80]);
    assert_eq!(a, b);
}

#[test]
fn import_refuses_bad_files_and_outputs() {
    let dir = scratch("urdf-bad");
    std::fs::write(dir.join("two_parents.urdf"), "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n<joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/></joint>\n<joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/></joint>\n</robot>\n").unwrap();
    let out = multibody(&dir, &["import", "two_parents.urdf"]);
    assert_eq!(code(&out), 1, "{}", stderr(&out));
    assert!(stderr(&out).contains("two_parents.urdf:6:1: error: the link `c` has two parents"), "{}", stderr(&out));
    assert!(!dir.join("two_parents.dyad").exists());
    // The output may not be the input.
    let out = multibody(&dir, &["import", "two_parents.urdf", "-o", "two_parents.urdf"]);
    assert_eq!(code(&out), 2, "{}", stderr(&out));
    // `run` reads the same messages.
    let out = multibody(&dir, &["run", "two_parents.urdf"]);
    assert_eq!(code(&out), 1, "{}", stderr(&out));
    assert!(stderr(&out).contains("two_parents.urdf:6:1"), "{}", stderr(&out));
}
