//! Models the view tests and the demo draw, built with the Rust API.
#![allow(dead_code)]

use multibody::{Mechanism, Model, SimulationOptions, Solution};

/// A pendulum: a revolute about z and a body of 1 kg at 0.5 m, released
/// horizontally.
pub fn pendulum() -> Mechanism {
    let mut model = Model::new("Pendulum");
    model.add("world", "World");
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]);
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a"]);
    model.assemble().expect("the pendulum assembles")
}

/// Modelica's DoublePendulum with BodyBoxes (0.5 m long, 0.06 m wide) and a
/// damped first joint: the repository's examples/msl/DoublePendulum.dyad.
pub fn double_pendulum() -> Mechanism {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/msl/DoublePendulum.dyad");
    let mut package = multibody_dyad::Package::new();
    package.add_source(path.display().to_string(), std::fs::read_to_string(&path).unwrap()).unwrap();
    let lowered = package.lower_component("DoublePendulum").expect("the example lowers");
    lowered.assemble().expect("the double pendulum assembles")
}

/// A double pendulum of two Bodies on rods, the second body pure magenta
/// (drawn only with `render_second`); everything else is blue-grey.
pub fn magenta_double_pendulum(render_second: bool) -> Mechanism {
    let grey = [0.35, 0.45, 0.6, 1.0];
    let mut model = Model::new("MagentaDoublePendulum");
    model.add("world", "World").set("render", false);
    for k in ["1", "2"] {
        model.add(format!("rev{k}"), "Revolute").set("n", [0.0, 0.0, 1.0]).set("color", grey);
        model.add(format!("rod{k}"), "FixedTranslation").set("r", [0.5, 0.0, 0.0]).set("color", grey);
    }
    model.add("body1", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]).set("color", grey);
    model
        .add("body2", "Body")
        .set("m", 1.0)
        .set("r_cm", [0.5, 0.0, 0.0])
        .set("radius", 0.1)
        .set("color", [1.0, 0.0, 1.0, 1.0])
        .set("render", render_second);
    model.connect(["world.frame_b", "rev1.frame_a"]);
    model.connect(["rev1.frame_b", "body1.frame_a", "rod1.frame_a"]);
    model.connect(["rod1.frame_b", "rev2.frame_a"]);
    model.connect(["rev2.frame_b", "body2.frame_a", "rod2.frame_a"]);
    model.assemble().expect("the magenta double pendulum assembles")
}

/// A chain of `n` revolutes about z, each with a Body (at the middle of its
/// link) and a 0.05 m rod to the next joint.
pub fn chain(n: usize) -> Mechanism {
    let mut model = Model::new("Chain");
    model.add("world", "World");
    let mut previous = "world.frame_b".to_string();
    for k in 1..=n {
        model.add(format!("rev{k}"), "Revolute").set("n", [0.0, 0.0, 1.0]);
        model.add(format!("body{k}"), "Body").set("m", 0.1).set("r_cm", [0.025, 0.0, 0.0]).set("radius", 0.015);
        model.add(format!("rod{k}"), "FixedTranslation").set("r", [0.05, 0.0, 0.0]);
        model.connect([previous.clone(), format!("rev{k}.frame_a")]);
        model.connect([format!("rev{k}.frame_b"), format!("body{k}.frame_a"), format!("rod{k}.frame_a")]);
        previous = format!("rod{k}.frame_b");
    }
    model.assemble().expect("the chain assembles")
}

/// A free body on a spring below the world origin, pushed sideways by a
/// constant world force (a helix and a force arrow to draw).
pub fn spring_mass() -> Mechanism {
    let mut model = Model::new("SpringMass");
    model.add("world", "World");
    model.add("spring", "Spring").set("c", 40.0).set("s_unstretched", 0.3);
    model
        .add("body", "Body")
        .set("m", 1.0)
        .set("I_11", 0.01)
        .set("I_22", 0.01)
        .set("I_33", 0.01)
        .set("orientation_state", multibody::OrientationState::Quaternion)
        .initial("r_0", [0.2, -0.6, 0.1]);
    model.add("push", "WorldForce").set("scale", 0.1);
    model.connect(["world.frame_b", "spring.frame_a"]);
    model.connect(["spring.frame_b", "body.frame_a", "push.frame_b"]);
    for (axis, k) in [("x", 3.0), ("y", 0.0), ("z", 0.0)] {
        model.add(format!("f{axis}"), "BlockComponents.Constant").set("k", k);
        model.connect([format!("f{axis}.y"), format!("push.force_{axis}")]);
    }
    model.assemble().expect("the spring-mass model assembles")
}

pub fn simulate(mechanism: &Mechanism, stop: f64) -> Solution {
    mechanism.simulate(&SimulationOptions { stop, saveat: 0.01, ..Default::default() }).expect("the model simulates")
}

/// What draws the magenta block of [`mesh_or_box`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Block {
    /// A ShapefileVisualizer of the mesh file `box.stl` (a relative path).
    Mesh { render: bool },
    /// A BoxShape primitive of the same size in the same place.
    Primitive,
}

/// A pendulum at phi = 0.4 about z carrying a magenta block of 0.4 x 0.12 x
/// 0.12 m, long along the pendulum's y, centred at (0.5, 0.1, 0) in its
/// frame; two grey spheres far out fix the bounds (and so the camera)
/// whatever draws the block. With `Block::Mesh`, the file `box.stl` must
/// be the box [-0.5, 0.5] x [-0.15, 0.15] x [-0.15, 0.15]: shape_scale 0.4
/// and a quarter turn about z in shape_transform make it the same block.
pub fn mesh_or_box(block: Block) -> Mechanism {
    let grey = [0.35, 0.45, 0.6, 1.0];
    let magenta = [1.0, 0.0, 1.0, 1.0];
    let mut model = Model::new("MeshOrBox");
    model.add("world", "World").set("render", false);
    model.add("rev", "Revolute").set("n", [0.0, 0.0, 1.0]).set("color", grey).initial("phi", 0.4);
    model.add("body", "Body").set("m", 1.0).set("r_cm", [0.5, 0.0, 0.0]).set("render", false);
    for (name, at) in [("low", [-0.8, -0.8, -0.3]), ("high", [0.8, 0.8, 0.3])] {
        model.add(name, "SphereVisualizer").set("radius", 0.1).set("r_shape", at).set("color", grey);
        model.connect(["world.frame_b", &format!("{name}.frame_a")]);
    }
    match block {
        Block::Mesh { render } => {
            let quarter_turn = vec![
                vec![0.0, -1.0, 0.0, 0.5],
                vec![1.0, 0.0, 0.0, 0.1],
                vec![0.0, 0.0, 1.0, 0.0],
                vec![0.0, 0.0, 0.0, 1.0],
            ];
            model
                .add("block", "ShapefileVisualizer")
                .set("shapefile", "box.stl")
                .set("shape_transform", multibody::Value::Matrix(quarter_turn))
                .set("shape_scale", 0.4)
                .set("color", magenta)
                .set("render", render);
        }
        Block::Primitive => {
            model
                .add("block", "BoxShape")
                .set("r_shape", [0.5, -0.1, 0.0])
                .set("length_direction", [0.0, 1.0, 0.0])
                .set("width_direction", [1.0, 0.0, 0.0])
                .set("length", 0.4)
                .set("width", 0.12)
                .set("height", 0.12)
                .set("color", magenta);
        }
    }
    model.connect(["world.frame_b", "rev.frame_a"]);
    model.connect(["rev.frame_b", "body.frame_a", "block.frame_a"]);
    model.assemble().expect("the mesh-or-box model assembles")
}

/// A binary STL of the box [-a, a] x [-b, b] x [-c, c]: 12 triangles wound
/// outwards, zero facet normals.
pub fn box_stl(a: f32, b: f32, c: f32) -> Vec<u8> {
    let half = [a, b, c];
    let corner = |i: usize| [0, 1, 2].map(|k| if i & (1 << k) != 0 { half[k] } else { -half[k] });
    let faces = [[0, 2, 6, 4], [1, 5, 7, 3], [0, 4, 5, 1], [2, 3, 7, 6], [0, 1, 3, 2], [4, 6, 7, 5]];
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&12u32.to_le_bytes());
    for mut f in faces {
        let [p, q, r] = [f[0], f[1], f[2]].map(corner);
        let u = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
        let v = [r[0] - p[0], r[1] - p[1], r[2] - p[2]];
        let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
        let centre: Vec<f32> = (0..3).map(|k| f.iter().map(|&i| corner(i)[k]).sum::<f32>()).collect();
        if n[0] * centre[0] + n[1] * centre[1] + n[2] * centre[2] < 0.0 {
            f.reverse();
        }
        for tri in [[f[0], f[1], f[2]], [f[0], f[2], f[3]]] {
            bytes.extend_from_slice(&[0u8; 12]);
            for i in tri {
                for x in corner(i) {
                    bytes.extend_from_slice(&x.to_le_bytes());
                }
            }
            bytes.extend_from_slice(&[0, 0]);
        }
    }
    bytes
}
