//! The shapes components declare for animations. A shape is placed by its
//! component's frames, whose `r_0` and `R` are in every solution, so a view
//! can draw the motion from a solution and these declarations alone.

use crate::math::{Transform, Vec3};

/// What to draw.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeKind {
    /// A sphere of diameter `width`, centred on the placement's origin.
    Sphere,
    /// A cylinder of diameter `width` from the origin along the length vector.
    Cylinder,
    /// A box from the origin along the length vector, `width` along the
    /// width direction and `height` along the third axis.
    Box,
    /// A cone with base diameter `width` at the origin and its tip at the
    /// end of the length vector.
    Cone,
    /// A coil spring of coil diameter `width` and wire diameter `height`.
    Helix { windings: f64 },
    /// A thin line of diameter `width`.
    Line,
    /// An arrow (shaft and head) of shaft diameter `width`.
    Arrow,
    /// A triangle mesh read from a file (STL, OBJ or Collada) when the view
    /// is made. A point `p` of the file is drawn at `transform * (scale * p)`
    /// in the frame the shape is fixed in. `path` is as the model gives it:
    /// the view resolves a relative path (see `multibody_view`).
    Mesh { path: String, transform: [[f64; 4]; 4], scale: f64 },
}

/// Where a shape is, relative to its component's frames. Frame names are
/// full connector names (`body.frame_a`); the solution holds their
/// `r_0[1..3]` and `R[1,1]..R[3,3]` (`v_frame = R v_world`).
#[derive(Clone, Debug, PartialEq)]
pub enum Placement {
    /// Fixed in a frame: origin, length vector and width direction resolved
    /// in that frame.
    InFrame { frame: String, origin: Vec3, length: Vec3, width_dir: Vec3 },
    /// From one frame's origin to another's (springs, dampers, rods).
    Between { from: String, to: String },
    /// From a frame's origin along a vector signal (world coordinates)
    /// times `scale`: the signal names are `{vector}[1..3]`.
    Vector { frame: String, vector: String, scale: f64 },
}

/// A shape a component declares.
#[derive(Clone, Debug, PartialEq)]
pub struct Shape {
    /// The component that draws it (for `render = false` and for picking).
    pub component: String,
    pub kind: ShapeKind,
    /// RGBA, each 0..1.
    pub color: [f64; 4],
    pub specular: f64,
    pub width: f64,
    pub height: f64,
    pub placement: Placement,
    /// Where planar frames lie (world to plane): a planar frame's `x`, `y`
    /// and `phi` are in this plane (the identity: the world's x-y plane).
    pub plane: Transform,
}

/// A shape before its component's name is known: frames are connector
/// names of the component (`frame_a`).
#[derive(Clone, Debug, PartialEq)]
pub struct LocalShape {
    pub kind: ShapeKind,
    pub color: [f64; 4],
    pub specular: f64,
    pub width: f64,
    pub height: f64,
    pub placement: Placement,
}

impl LocalShape {
    /// A shape fixed in `frame` from `origin` along `length` (frame coordinates).
    pub fn in_frame(kind: ShapeKind, frame: &str, origin: Vec3, length: Vec3, width: f64, height: f64) -> Self {
        Self {
            kind,
            color: [0.5, 0.5, 0.5, 1.0],
            specular: 0.7,
            width,
            height,
            placement: Placement::InFrame {
                frame: frame.into(),
                origin,
                length,
                width_dir: crate::math::width_direction(&length),
            },
        }
    }

    pub fn colored(mut self, color: [f64; 4], specular: f64) -> Self {
        self.color = color;
        self.specular = specular;
        self
    }

    /// The shape with its frame names made full (`component.frame`).
    pub fn named(self, component: &str) -> Shape {
        let full = |f: String| format!("{component}.{f}");
        let placement = match self.placement {
            Placement::InFrame { frame, origin, length, width_dir } => {
                Placement::InFrame { frame: full(frame), origin, length, width_dir }
            }
            Placement::Between { from, to } => Placement::Between { from: full(from), to: full(to) },
            Placement::Vector { frame, vector, scale } => {
                Placement::Vector { frame: full(frame), vector: full(vector), scale }
            }
        };
        Shape {
            component: component.into(),
            kind: self.kind,
            color: self.color,
            specular: self.specular,
            width: self.width,
            height: self.height,
            placement,
            plane: Transform::IDENTITY,
        }
    }
}

/// For components that draw nothing.
pub fn none(_: &crate::components::ParamSet) -> Vec<LocalShape> {
    Vec::new()
}

/// A shape's colour and specular coefficient from the usual parameters.
pub fn look(p: &crate::components::ParamSet) -> ([f64; 4], f64) {
    (p.color("color"), p.real("specular_coefficient"))
}

/// A shape between two frames' origins.
pub fn between(kind: ShapeKind, from: &str, to: &str, width: f64, height: f64) -> LocalShape {
    LocalShape {
        kind,
        color: [0.5, 0.5, 0.5, 1.0],
        specular: 0.7,
        width,
        height,
        placement: Placement::Between { from: from.into(), to: to.into() },
    }
}

/// A joint's cylinder along `axis` (unit, resolved in `frame`), centred on the frame's origin.
pub fn joint_cylinder(
    p: &crate::components::ParamSet,
    frame: &str,
    axis: Vec3,
    length: f64,
    diameter: f64,
) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let (color, specular) = look(p);
    vec![LocalShape::in_frame(ShapeKind::Cylinder, frame, -axis * (length / 2.0), axis * length, diameter, diameter)
        .colored(color, specular)]
}
