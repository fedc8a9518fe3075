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
    // `describe` is for library kinds: it points at `check` for a file.
    let out = multibody(&dir, &["describe", "two_parents.urdf"]);
    assert_eq!(code(&out), 2, "{}", stderr(&out));
    assert!(stderr(&out).contains("`multibody check two_parents.urdf` describes a model file"), "{}", stderr(&out));
    // `run` reads the same messages.
    let out = multibody(&dir, &["run", "two_parents.urdf"]);
    assert_eq!(code(&out), 1, "{}", stderr(&out));
    assert!(stderr(&out).contains("two_parents.urdf:6:1"), "{}", stderr(&out));
}

/// A robot package laid out as ROS has it, in `dir`: `pkg/arm_description`
/// with its package.xml, a mesh (a tetrahedron, ASCII STL) and a URDF that
/// names the mesh `package://arm_description/...`, and one more visual
/// naming `mesh` (as written in the file).
fn robot_package(dir: &std::path::Path, mesh: &str) -> std::path::PathBuf {
    let package = dir.join("pkg/arm_description");
    std::fs::create_dir_all(package.join("meshes")).unwrap();
    std::fs::create_dir_all(package.join("urdf")).unwrap();
    std::fs::write(
        package.join("package.xml"),
        "<?xml version=\"1.0\"?>\n<package format=\"2\">\n  <name>arm_description</name>\n  <version>0.1.0</version>\n</package>\n",
    )
    .unwrap();
    std::fs::write(
        package.join("meshes/tip.stl"),
        "solid tip\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n\
         facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n\
         facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n\
         facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid tip\n",
    )
    .unwrap();
    let urdf = format!(
        "<robot name=\"meshed\">\n  <link name=\"base\"/>\n  <joint name=\"hinge\" type=\"continuous\">\n    \
         <parent link=\"base\"/><child link=\"arm\"/><axis xyz=\"0 1 0\"/>\n  </joint>\n  <link name=\"arm\">\n    \
         <inertial><origin xyz=\"0.5 0 0\"/><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial>\n    \
         <visual><geometry><mesh filename=\"package://arm_description/meshes/tip.stl\" scale=\"0.1 0.2 0.3\"/></geometry></visual>\n    \
         <visual><geometry><mesh filename=\"{mesh}\"/></geometry></visual>\n  </link>\n</robot>\n"
    );
    let path = package.join("urdf/meshed.urdf");
    std::fs::write(&path, urdf).unwrap();
    path
}

/// A `package://` name that climbs out of its package (`..`) is not read
/// (it resolved upward to any file, `/etc/passwd` included, without a word).
#[test]
fn a_package_path_that_leaves_its_package_is_refused_at_its_place() {
    let dir = scratch("urdf-mesh-upward");
    // A file the climb would reach: pkg/secret.stl, beside the package.
    let urdf = robot_package(&dir, "package://arm_description/../secret.stl");
    std::fs::copy(dir.join("pkg/arm_description/meshes/tip.stl"), dir.join("pkg/secret.stl")).unwrap();
    for mesh in ["package://arm_description/../secret.stl", "package://../../../../etc/passwd"] {
        let text = std::fs::read_to_string(&urdf).unwrap();
        let text = text.replace("package://arm_description/../secret.stl", mesh);
        let path = urdf.with_file_name(format!("upward{}.urdf", mesh.len()));
        std::fs::write(&path, text).unwrap();
        let out = multibody(&dir, &["import", &path.display().to_string(), "-o", "upward.dyad"]);
        assert_eq!(code(&out), 1, "{}", stderr(&out));
        let err = stderr(&out);
        assert!(
            err.contains(&format!(":9:23: error: the mesh `{mesh}` is not read: a `package://NAME/...` path")),
            "{err}"
        );
        assert!(!dir.join("upward.dyad").exists());
    }
}

#[test]
fn meshes_are_found_through_their_package_or_reported_at_their_place() {
    let dir = scratch("urdf-meshes");
    // A missing mesh stops the import, at the mesh's place, with what to do.
    let urdf = robot_package(&dir, "package://gripper_description/meshes/finger.dae");
    let urdf = urdf.display().to_string();
    let out = multibody(&dir, &["import", &urdf, "-o", "meshed.dyad"]);
    assert_eq!(code(&out), 1, "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains(
            "meshed.urdf:9:23: error: the mesh `package://gripper_description/meshes/finger.dae` is not found"
        ),
        "{err}"
    );
    assert!(err.contains("--package-dir") && err.contains("--no-meshes"), "{err}");
    assert!(!dir.join("meshed.dyad").exists());
    // Without meshes it imports; `run` notes the missing one and goes on.
    let out = multibody(&dir, &["import", &urdf, "-o", "meshed.dyad", "--no-meshes"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    assert!(!std::fs::read_to_string(dir.join("meshed.dyad")).unwrap().contains("ShapefileVisualizer"));
    let out = multibody(&dir, &["run", &urdf, "--stop", "0.1", "-o", "meshed.csv"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    assert!(stderr(&out).contains("note: the mesh `package://gripper_description/meshes/finger.dae` is not found"));

    // The other package, elsewhere, named by --package-dir: both meshes are
    // found, named from the model file's folder, the scale in the transform.
    let other = dir.join("elsewhere/gripper_description/meshes");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::copy(dir.join("pkg/arm_description/meshes/tip.stl"), other.join("finger.dae")).unwrap();
    std::fs::remove_file(dir.join("meshed.dyad")).unwrap();
    let out = multibody(&dir, &["import", &urdf, "-o", "meshed.dyad", "--package-dir", "elsewhere"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    let text = std::fs::read_to_string(dir.join("meshed.dyad")).unwrap();
    assert!(
        text.contains(
            "ShapefileVisualizer(shapefile = \"pkg/arm_description/meshes/tip.stl\", shape_transform = [[0.1, 0, 0, 0], \
             [0, 0.2, 0, 0], [0, 0, 0.3, 0], [0, 0, 0, 1]])"
        ),
        "{text}"
    );
    assert!(text.contains("shapefile = \"elsewhere/gripper_description/meshes/finger.dae\""), "{text}");
    let out = multibody(&dir, &["run", "meshed.dyad", "--stop", "0.1", "-o", "imported.csv"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
}

#[test]
fn mimic_joints_are_imported_as_couplings() {
    let dir = scratch("urdf-mimic");
    let mimic = crate_path("../multibody-dyad/tests/urdf/mimic.urdf");
    let out = multibody(&dir, &["import", &mimic, "-o", "mimic.dyad"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    assert!(stderr(&out).contains("(1 degree of freedom;"), "{}", stderr(&out));
    let text = std::fs::read_to_string(dir.join("mimic.dyad")).unwrap();
    assert!(text.contains("right_finger.axis.phi = -1.0 * left_finger.axis.phi + 0.01"), "{text}");
    assert!(text.contains("tip.axis.s = 0.02 * right_finger.axis.phi + 0"), "{text}");
}

/// A chain of `n` links after a massless base, each on a revolute joint.
fn chain_urdf(n: usize) -> String {
    let mut s = format!("<robot name=\"chain{n}\">\n<link name=\"base\"/>\n");
    for i in 0..n {
        let parent = if i == 0 { "base".to_string() } else { format!("l{}", i - 1) };
        s += &format!(
            "<link name=\"l{i}\"><inertial><mass value=\"1\"/><origin xyz=\"0 0 0.05\"/><inertia ixx=\"0.01\" \
             ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\n<joint name=\"j{i}\" \
             type=\"revolute\"><parent link=\"{parent}\"/><child link=\"l{i}\"/><origin xyz=\"0 0 0.1\"/><axis \
             xyz=\"0 1 0\"/></joint>\n"
        );
    }
    s + "</robot>\n"
}

/// Reading a robot took n² steps (each place counted from the start of the
/// file): 20,000 links took half a minute before being refused, in the
/// model file that was never written. The limit is said about the URDF.
#[test]
fn a_robot_too_large_for_a_model_is_refused_at_its_urdf() {
    let dir = scratch("urdf-too-large");
    std::fs::write(dir.join("chain20000.urdf"), chain_urdf(20_000)).unwrap();
    let out = multibody(&dir, &["import", "chain20000.urdf"]);
    let err = stderr(&out);
    assert_eq!(code(&out), 1, "{err}");
    assert!(
        err.contains(
            "chain20000.urdf:1:1: error: the robot has 20001 links and 20000 joints: its model would have 40002 \
             components, and a model has at most 20000"
        ),
        "{err}"
    );
    assert!(err.contains("help: the world, each link, each joint, each shape and each damper is a component"), "{err}");
    assert!(!err.contains("chain20000.dyad"), "{err}");
    assert!(!dir.join("chain20000.dyad").exists());
    // `run` reads the URDF the same way.
    let out = multibody(&dir, &["run", "chain20000.urdf"]);
    assert_eq!(code(&out), 1, "{}", stderr(&out));
    assert!(stderr(&out).contains("chain20000.urdf:1:1: error: the robot has 20001 links"), "{}", stderr(&out));
}

/// The largest chain a model holds (10,000 links, 9,999 joints and the
/// world) imports: the import is linear in the links.
#[test]
fn the_largest_robot_a_model_holds_imports() {
    let dir = scratch("urdf-largest");
    std::fs::write(dir.join("chain.urdf"), chain_urdf(9_999)).unwrap();
    let out = multibody(&dir, &["import", "chain.urdf"]);
    assert_eq!(code(&out), 0, "{}", stderr(&out));
    assert!(stderr(&out).contains("chain9999: 10000 links, 9999 joints → chain.dyad (9999 degrees of freedom"));
    assert!(std::fs::read_to_string(dir.join("chain.dyad")).unwrap().contains("j9998 = MultibodyComponents"));
}

/// A link's inertia no rigid body can have (Modelica's robot has one) is
/// imported as given, with a warning at its `<inertial>` naming the link
/// and the moments; `run` on the URDF says it once, about the URDF.
#[test]
fn an_inertia_no_rigid_body_has_is_warned_about_at_its_link() {
    let dir = scratch("urdf-inertia");
    let urdf = "<robot name=\"r\">\n<link name=\"base\"/>\n<link name=\"arm\">\n  <inertial><mass value=\"1\"/>\
                <inertia ixx=\"0.001\" ixy=\"0\" ixz=\"0\" iyy=\"1.16\" iyz=\"0\" izz=\"0.001\"/></inertial>\n</link>\n\
                <link name=\"plate\">\n  <inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" \
                iyy=\"0.2\" iyz=\"0\" izz=\"0.3\"/></inertial>\n</link>\n\
                <joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"arm\"/><axis xyz=\"0 0 1\"/></joint>\n\
                <joint name=\"k\" type=\"fixed\"><parent link=\"arm\"/><child link=\"plate\"/></joint>\n</robot>\n";
    std::fs::write(dir.join("r.urdf"), urdf).unwrap();
    let out = multibody(&dir, &["import", "r.urdf"]);
    let err = stderr(&out);
    assert_eq!(code(&out), 0, "{err}");
    assert!(
        err.contains(
            "r.urdf:4:3: warning: no rigid mass distribution has the inertia of the link `arm`: its principal moments \
             0.001, 0.001 and 1.16 kg.m2 break the triangle inequality (1.16 > 0.001 + 0.001)"
        ),
        "{err}"
    );
    assert!(err.contains("the robot is imported with the inertia as given"), "{err}");
    assert_eq!(err.matches("warning").count(), 1, "{err}");
    assert!(dir.join("r.dyad").exists());
    let out = multibody(&dir, &["run", "r.urdf", "--stop", "0.1"]);
    let err = stderr(&out);
    assert_eq!(code(&out), 0, "{err}");
    assert_eq!(err.matches("no rigid mass distribution").count(), 1, "{err}");
    assert!(err.contains("r.urdf:4:3: warning"), "{err}");
    // The model file the import wrote says it at the body.
    let out = multibody(&dir, &["check", "r.dyad"]);
    assert!(stderr(&out).contains("warning: no rigid mass distribution has the inertia of `arm`"), "{}", stderr(&out));
}
