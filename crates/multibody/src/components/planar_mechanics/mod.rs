//! PlanarMechanics: the library's 2-D mechanics.
//!
//! A planar component is a 3-D component held in the planar World's plane
//! (the world's x-y plane unless its `r_0_3d` and `rot_3d` place it). Its
//! `Frame2D` connectors are frames like any other inside the engine, placed
//! at `(x, y, 0)` of the plane and turned by `phi` about its normal; its
//! joints are revolutes about z and prismatics in the plane, its bodies
//! have inertia about z only. So a planar mechanism gets everything a 3-D
//! one has (the tree, loop closing, outputs, views), and a planar frame
//! connected through `PlanarToMultiBody` drives 3-D parts directly. The
//! connectors read as the library's `x`, `y`, `phi`, `fx`, `fy`, `tau`, in
//! the plane's coordinates: assembly grounds planar components in the
//! plane, and their sensors, force laws, outputs and equations see their
//! frames in its coordinates ([`crate::components::WorldSettings::plane`]).

pub mod adapters;
pub mod body;
pub mod fixed;
pub mod forces;
pub mod joints;
pub mod prescribed;
pub mod sensors;
pub mod wheels;
pub mod world;

use super::spec::{ConnectorSpec, ParamSpec, ParamType};
use super::ParamSet;
use crate::math::rotation::axis_rotation;
use crate::math::{Transform, Vec3};

/// The plane's normal: planar frames turn about it.
pub(crate) const NORMAL: Vec3 = Vec3::new(0.0, 0.0, 1.0);

pub(crate) const RENDER: ParamSpec = ParamSpec::boolean("render", true, "Render the component in animations");
pub(crate) const SPECULAR: ParamSpec =
    ParamSpec::real("specular_coefficient", 1.5, "", "Reflection of light in animations");
pub(crate) const Z_POSITION: ParamSpec =
    ParamSpec::real("z_position", 0.0, "m", "Position along z where the component is drawn (drawing only)");
pub(crate) const FRAME_A: ConnectorSpec = ConnectorSpec::frame_2d("frame_a", "The first planar frame");
pub(crate) const FRAME_B: ConnectorSpec = ConnectorSpec::frame_2d("frame_b", "The second planar frame");

pub(crate) const fn color(default: &'static str) -> ParamSpec {
    ParamSpec::world("color", ParamType::Vector(4), default, 1.0, "", "Colour (RGBA)")
}

/// A planar vector parameter `[x, y]` as a 3-D vector in the plane.
pub(crate) fn in_plane(p: &ParamSet, name: &str) -> Vec3 {
    let v = p.vector(name);
    Vec3::new(v[0], v[1], 0.0)
}

/// The pose of a planar frame at `r` (in the plane) turned by `phi` about z,
/// relative to the frame it is given in.
pub(crate) fn planar_pose(r: Vec3, phi: f64) -> Transform {
    Transform::new(axis_rotation(2, phi), r)
}

/// The drawing offset along z of a shape in a planar frame.
pub(crate) fn lift(p: &ParamSet) -> Vec3 {
    NORMAL * p.real("z_position")
}
