//! Visual-only components: they draw a shape fixed in the frame they are
//! connected to, and add no mass and no force (their frame's cut force
//! and torque are zero).
//!
//! - The shape primitives SphereShape, BoxShape, CylinderShape, ConeShape
//!   and ArrowShape. In the Dyad library a parent places them by equations
//!   on their `r` and `R`; here they carry a `frame_a` that places them
//!   (`r = frame_a.r_0`, `R = transpose(frame_a.R)`, which they output), and
//!   their sizes and directions are parameters.
//! - BoxVisualizer, CylinderVisualizer, SphereVisualizer: what a URDF
//!   importer emits for a link without mass.
//! - FrameVisualizer: the three axes of a frame, red x, green y, blue z.
//! - ShapefileVisualizer: a mesh read from a file (STL, OBJ, Collada).

use super::shapes::{LocalShape, ShapeKind};
use super::spec::{concat, ComponentSpec, ConnectorSpec, ParamSpec, ParamType, Shape, VarSpec};
use super::urdf_body::set_width_direction;
use super::{Component, EvalContext, ParamSet, Part};
use crate::math::Vec3;

const FRAME: [ConnectorSpec; 1] = [ConnectorSpec::frame("frame_a", "The frame the shape is fixed in")];

/// The look every shape primitive has.
const LOOK: [ParamSpec; 3] = [
    ParamSpec::boolean("render", true, "Whether this shape should be rendered"),
    ParamSpec::vector("color", &[0.5, 0.5, 0.5, 1.0], "", "RGBA color of the shape"),
    ParamSpec::real("specular_coefficient", 0.7, "", "Specular reflection coefficient (0 = fully diffuse)"),
];

/// Where the shape is and how big, in frame_a.
const PLACEMENT: [ParamSpec; 6] = [
    ParamSpec::vector("r_shape", &[0.0, 0.0, 0.0], "m", "Offset from frame_a to the shape origin, resolved in frame_a"),
    ParamSpec::vector("length_direction", &[1.0, 0.0, 0.0], "", "Primary axis direction, resolved in frame_a"),
    ParamSpec::vector("width_direction", &[0.0, 1.0, 0.0], "", "Secondary axis direction, resolved in frame_a"),
    ParamSpec::required("length", ParamType::Real, "m", "Dimension along length_direction"),
    ParamSpec::required("width", ParamType::Real, "m", "Dimension along width_direction"),
    ParamSpec::required("height", ParamType::Real, "m", "Dimension perpendicular to both length and width"),
];

static SHAPE_PARAMS: [ParamSpec; 9] = concat(&LOOK, &PLACEMENT);

/// The shape primitives' outputs: where their frame puts them.
const SHAPE_VARIABLES: [VarSpec; 2] = [
    VarSpec::vector("r", 3, "m", "Position of the shape's frame in the world (= frame_a.r_0)"),
    VarSpec {
        name: "R",
        shape: Shape::Matrix(3, 3),
        unit: "",
        doc: "Orientation of the shape in the world: shape frame to world (= transpose(frame_a.R))",
    },
];

macro_rules! shape_primitive {
    ($name:ident, $kind:literal, $doc:literal, $shapes:ident) => {
        pub static $name: ComponentSpec = ComponentSpec {
            kind: $kind,
            doc: $doc,
            params: &SHAPE_PARAMS,
            connectors: &FRAME,
            variables: &SHAPE_VARIABLES,
            build: |_| Ok(Box::new(Visual { outputs_pose: true })),
            shapes: $shapes,
        };
    };
}

shape_primitive!(
    SPHERE_SHAPE,
    "SphereShape",
    "Sphere shape primitive, fixed in frame_a: a sphere of diameter length centred on r_shape. Visual only.",
    sphere_primitive
);
shape_primitive!(
    BOX_SHAPE,
    "BoxShape",
    "Box shape primitive, fixed in frame_a: from r_shape, length along length_direction, width along \
     width_direction, height along the third axis. Visual only.",
    box_primitive
);
shape_primitive!(
    CYLINDER_SHAPE,
    "CylinderShape",
    "Cylinder shape primitive, fixed in frame_a: from r_shape, length along length_direction, diameter width. \
     Visual only.",
    cylinder_primitive
);
shape_primitive!(
    CONE_SHAPE,
    "ConeShape",
    "Cone shape primitive, fixed in frame_a: its base of diameter width at r_shape, its tip at length along \
     length_direction. Visual only.",
    cone_primitive
);
shape_primitive!(
    ARROW_SHAPE,
    "ArrowShape",
    "Arrow shape primitive, fixed in frame_a: from r_shape, length along length_direction, shaft diameter \
     width. Visual only.",
    arrow_primitive
);

/// `kind` from r_shape along length_direction, with the shape parameters.
fn primitive(p: &ParamSet, kind: ShapeKind) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let e = p.vec3("length_direction").try_normalize(1e-12).unwrap_or_else(Vec3::x);
    let (width, height) = (p.real("width"), p.real("height"));
    let mut shape = LocalShape::in_frame(kind, "frame_a", p.vec3("r_shape"), e * p.real("length"), width, height)
        .colored(p.color("color"), p.real("specular_coefficient"));
    set_width_direction(&mut shape, p.vec3("width_direction"));
    vec![shape]
}

fn sphere_primitive(p: &ParamSet) -> Vec<LocalShape> {
    let mut shapes = primitive(p, ShapeKind::Sphere);
    for s in &mut shapes {
        // Our sphere's diameter is its width.
        s.width = p.real("length");
        s.height = p.real("length");
    }
    shapes
}

fn box_primitive(p: &ParamSet) -> Vec<LocalShape> {
    primitive(p, ShapeKind::Box)
}

fn cylinder_primitive(p: &ParamSet) -> Vec<LocalShape> {
    primitive(p, ShapeKind::Cylinder)
}

fn cone_primitive(p: &ParamSet) -> Vec<LocalShape> {
    primitive(p, ShapeKind::Cone)
}

fn arrow_primitive(p: &ParamSet) -> Vec<LocalShape> {
    primitive(p, ShapeKind::Arrow)
}

const VISUALIZER_LOOK: [ParamSpec; 2] = [
    ParamSpec::boolean("render", true, "Whether to render"),
    ParamSpec::vector("color", &[1.0, 0.0, 0.0, 1.0], "", "RGBA color"),
];

pub static BOX_VISUALIZER: ComponentSpec = ComponentSpec {
    kind: "BoxVisualizer",
    doc: "A box drawn in frame_a, with no mass (a massless URDF link with box geometry): from r_shape, length \
          along length_direction, width along width_direction, height along the third axis.",
    params: &concat::<ParamSpec, 8>(
        &VISUALIZER_LOOK,
        &[
            ParamSpec::real("length", 0.1, "m", "Length of the box"),
            ParamSpec::real("width", 0.1, "m", "Width of the box"),
            ParamSpec::real("height", 0.1, "m", "Height of the box"),
            ParamSpec::vector("length_direction", &[1.0, 0.0, 0.0], "", "Direction of the box length, in frame_a"),
            ParamSpec::vector("width_direction", &[0.0, 1.0, 0.0], "", "Direction of the box width, in frame_a"),
            ParamSpec::vector("r_shape", &[0.0, 0.0, 0.0], "m", "Position of the box origin relative to frame_a"),
        ],
    ),
    connectors: &FRAME,
    variables: &[],
    build: |_| Ok(Box::new(Visual { outputs_pose: false })),
    shapes: |p: &ParamSet| {
        if !p.boolean("render") {
            return Vec::new();
        }
        let e = p.vec3("length_direction").try_normalize(1e-12).unwrap_or_else(Vec3::x);
        let mut shape = LocalShape::in_frame(
            ShapeKind::Box,
            "frame_a",
            p.vec3("r_shape"),
            e * p.real("length"),
            p.real("width"),
            p.real("height"),
        )
        .colored(p.color("color"), 0.7);
        set_width_direction(&mut shape, p.vec3("width_direction"));
        vec![shape]
    },
};

pub static CYLINDER_VISUALIZER: ComponentSpec = ComponentSpec {
    kind: "CylinderVisualizer",
    doc: "A cylinder drawn in frame_a, with no mass (a massless URDF link with cylinder geometry): from r_shape, \
          length along length_direction.",
    params: &concat::<ParamSpec, 6>(
        &VISUALIZER_LOOK,
        &[
            ParamSpec::real("radius", 0.1, "m", "Radius of the cylinder"),
            ParamSpec::real("length", 1.0, "m", "Length of the cylinder"),
            ParamSpec::vector("length_direction", &[1.0, 0.0, 0.0], "", "Direction of the cylinder axis, in frame_a"),
            ParamSpec::vector("r_shape", &[0.0, 0.0, 0.0], "m", "Position of the cylinder start relative to frame_a"),
        ],
    ),
    connectors: &FRAME,
    variables: &[],
    build: |_| Ok(Box::new(Visual { outputs_pose: false })),
    shapes: |p: &ParamSet| {
        if !p.boolean("render") {
            return Vec::new();
        }
        let e = p.vec3("length_direction").try_normalize(1e-12).unwrap_or_else(Vec3::x);
        let d = 2.0 * p.real("radius");
        vec![LocalShape::in_frame(ShapeKind::Cylinder, "frame_a", p.vec3("r_shape"), e * p.real("length"), d, d)
            .colored(p.color("color"), 0.7)]
    },
};

pub static SPHERE_VISUALIZER: ComponentSpec = ComponentSpec {
    kind: "SphereVisualizer",
    doc: "A sphere drawn in frame_a, with no mass (a massless URDF link with sphere geometry), centred on r_shape.",
    params: &concat::<ParamSpec, 4>(
        &VISUALIZER_LOOK,
        &[
            ParamSpec::real("radius", 0.1, "m", "Radius of the sphere"),
            ParamSpec::vector("r_shape", &[0.0, 0.0, 0.0], "m", "Position of the sphere centre relative to frame_a"),
        ],
    ),
    connectors: &FRAME,
    variables: &[],
    build: |_| Ok(Box::new(Visual { outputs_pose: false })),
    shapes: |p: &ParamSet| {
        if !p.boolean("render") {
            return Vec::new();
        }
        let d = 2.0 * p.real("radius");
        vec![LocalShape::in_frame(ShapeKind::Sphere, "frame_a", p.vec3("r_shape"), Vec3::x() * d, d, d)
            .colored(p.color("color"), 0.7)]
    },
};

pub static FRAME_VISUALIZER: ComponentSpec = ComponentSpec {
    kind: "FrameVisualizer",
    doc: "The axes of frame_a drawn as three arrows from its origin: x red, y green, z blue. Visual only.",
    params: &[
        ParamSpec::boolean("render", true, "Render the axes in animations"),
        ParamSpec::real("specular_coefficient", 0.7, "", "Reflection of light in animations"),
        ParamSpec::world("axis_length", ParamType::Real, "default_joint_length", 1.0, "m", "Length of the axis arrows"),
        ParamSpec::derived("axis_radius", ParamType::Real, "axis_length / 20", "m", "Radius of the axis arrows"),
    ],
    connectors: &FRAME,
    variables: &[],
    build: |_| Ok(Box::new(Visual { outputs_pose: false })),
    shapes: frame_axes,
};

fn frame_axes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let length = p.real("axis_length");
    let d = 2.0 * p.real_opt("axis_radius").unwrap_or(length / 20.0);
    let specular = p.real("specular_coefficient");
    let colors = [[1.0, 0.0, 0.0, 1.0], [0.0, 0.8, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0]];
    (0..3)
        .map(|k| {
            LocalShape::in_frame(ShapeKind::Arrow, "frame_a", Vec3::zeros(), crate::math::unit(k) * length, d, d)
                .colored(colors[k], specular)
        })
        .collect()
}

const IDENTITY_4: &[&[f64]] =
    &[&[1.0, 0.0, 0.0, 0.0], &[0.0, 1.0, 0.0, 0.0], &[0.0, 0.0, 1.0, 0.0], &[0.0, 0.0, 0.0, 1.0]];

pub static SHAPEFILE_VISUALIZER: ComponentSpec = ComponentSpec {
    kind: "ShapefileVisualizer",
    doc: "A mesh read from a file (STL, ASCII or binary; OBJ; Collada .dae) drawn in frame_a, with no mass or \
          inertia. A point p of the file is drawn at shape_transform * (shape_scale * p) in frame_a \
          coordinates: shape_transform is the 4x4 homogeneous transform from mesh coordinates to frame_a, \
          written as rows. A relative shapefile path is taken from the folder of the model file being run (the \
          file given on the command line that holds the analysis or component); an absolute path is used as it \
          is, and `~` is not expanded. shapefile = \"\" or render = false draws nothing. The file is read when \
          the animation page is written: a file that is missing or unreadable leaves the shape out with a \
          warning, and the run's results are kept.",
    params: &[
        ParamSpec::boolean("render", true, "Whether to draw the mesh"),
        ParamSpec::vector("color", &[0.5, 0.5, 0.5, 1.0], "", "RGBA color of the mesh"),
        ParamSpec::text("shapefile", "", "Path of the mesh file (.stl, .obj, .dae); \"\" draws nothing"),
        ParamSpec::matrix(
            "shape_transform",
            IDENTITY_4,
            "",
            "Homogeneous transform from mesh coordinates to frame_a (rows; translation in m)",
        ),
        ParamSpec::real("shape_scale", 1.0, "", "Uniform scale of the mesh, applied before shape_transform"),
        ParamSpec::real("specular_coefficient", 0.7, "", "Specular reflection coefficient (0 = fully diffuse)"),
    ],
    connectors: &FRAME,
    variables: &[],
    build: |p| {
        p.non_negative("shape_scale", false)?;
        let t = p.matrix("shape_transform");
        if t[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(p.invalid("shape_transform", "its last row must be [0, 0, 0, 1] (a rigid or affine transform)"));
        }
        Ok(Box::new(Visual { outputs_pose: false }))
    },
    shapes: shapefile_mesh,
};

fn shapefile_mesh(p: &ParamSet) -> Vec<LocalShape> {
    let path = p.text("shapefile");
    if !p.boolean("render") || path.is_empty() {
        return Vec::new();
    }
    let rows = p.matrix("shape_transform");
    let mut transform = [[0.0; 4]; 4];
    for (i, row) in rows.iter().take(4).enumerate() {
        for (j, x) in row.iter().take(4).enumerate() {
            transform[i][j] = *x;
        }
    }
    let kind = ShapeKind::Mesh { path: path.to_string(), transform, scale: p.real("shape_scale") };
    vec![LocalShape::in_frame(kind, "frame_a", Vec3::zeros(), Vec3::x(), 0.0, 0.0)
        .colored(p.color("color"), p.real("specular_coefficient"))]
}

/// A component that only draws: no parts; the shape primitives output
/// their frame's pose as `r` and `R`.
#[derive(Debug)]
struct Visual {
    outputs_pose: bool,
}

impl Component for Visual {
    fn parts(&self) -> Vec<Part> {
        Vec::new()
    }

    fn variables(&self) -> Vec<VarSpec> {
        if self.outputs_pose {
            SHAPE_VARIABLES.to_vec()
        } else {
            Vec::new()
        }
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        if !self.outputs_pose {
            return;
        }
        let frame = &ctx.frames[0];
        out.extend_from_slice(frame.r_0.as_slice());
        // R of the shape maps shape to world: the transpose of the frame's.
        for i in 0..3 {
            for j in 0..3 {
                out.push(frame.rot[(j, i)]);
            }
        }
    }
}
