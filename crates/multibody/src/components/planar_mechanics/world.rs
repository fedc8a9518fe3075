//! PlanarMechanics.World: the plane's inertial frame and its gravity.

use super::super::shapes::{LocalShape, ShapeKind};
use super::super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, ParamType};
use super::super::{world, Component, ParamSet, Part, WorldSettings};
use crate::math::rotation::axes_rotations;
use crate::math::{Transform, Vec3};
use crate::{ComponentInstance, Error, Value};

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "PlanarMechanics.World",
    doc: "The root of a planar model: frame_b is fixed at x = y = phi = 0. Gravity g*n acts on every planar \
          body (n in the plane). A model with planar bodies needs one; with a 3-D World too, both must give \
          the same gravity. r_0_3d and rot_3d place the plane in 3-D: planar quantities stay in the plane's \
          coordinates, 3-D parts joined through PlanarToMultiBody and the animation see the plane there.",
    params: &[
        ParamSpec::boolean("render", true, "Draw the world axes in animations"),
        ParamSpec::vector("n", &[0.0, -1.0], "", "Direction of gravity in the plane (normalised)"),
        ParamSpec::real("g", 9.80665, "m/s2", "Magnitude of gravity"),
        ParamSpec::real("nominal_length", 1.0, "m", "Nominal size of the model; scales the visual defaults"),
        ParamSpec::derived("default_joint_length", ParamType::Real, "nominal_length / 10", "m", "Default joint length"),
        ParamSpec::derived("default_joint_width", ParamType::Real, "nominal_length / 20", "m", "Default joint width"),
        ParamSpec::derived(
            "default_body_diameter",
            ParamType::Real,
            "nominal_length / 9",
            "m",
            "Default diameter of bodies",
        ),
        ParamSpec::real("default_width_fraction", 20.0, "", "Default width of rods as a fraction of length"),
        ParamSpec::derived("default_arrow_diameter", ParamType::Real, "nominal_length / 40", "m", "Arrow diameter"),
        ParamSpec::derived("default_force_length", ParamType::Real, "nominal_length / 10", "m", "Force length"),
        ParamSpec::derived("default_force_width", ParamType::Real, "nominal_length / 20", "m", "Force width"),
        ParamSpec::real("default_N_to_m", 1000.0, "N/m", "Force arrows: newtons per metre of arrow"),
        ParamSpec::real("default_Nm_to_m", 1000.0, "N.m/m", "Torque arrows: newton metres per metre of arrow"),
        ParamSpec::real("default_z_position", 0.0, "m", "Default z at which planar components are drawn"),
        ParamSpec::vector("r_0_3d", &[0.0, 0.0, 0.0], "m", "Where the plane's origin sits in 3-D (world coordinates)"),
        ParamSpec::vector(
            "rot_3d",
            &[0.0, 0.0, 0.0],
            "rad",
            "How the plane is turned in 3-D: angles of rotations about x, then the new y, then the new z",
        ),
    ],
    connectors: &[ConnectorSpec::frame_2d("frame_b", "The world frame: x = y = phi = 0")],
    variables: &[],
    build,
    shapes,
};

/// The plane's axes: red x, green y.
fn shapes(p: &ParamSet) -> Vec<LocalShape> {
    if !p.boolean("render") {
        return Vec::new();
    }
    let length = p.real("nominal_length");
    let d = length / 40.0;
    let colors = [[1.0, 0.0, 0.0, 1.0], [0.0, 0.6, 0.0, 1.0]];
    (0..2)
        .map(|k| {
            LocalShape::in_frame(ShapeKind::Arrow, "frame_b", Vec3::zeros(), crate::math::unit(k) * length, d, d)
                .colored(colors[k], 0.7)
        })
        .collect()
}

/// frame_b is at x = y = phi = 0 of the plane; where the plane sits
/// (`r_0_3d`, `rot_3d`) is the model's, in [`WorldSettings::plane`], and
/// assembly puts every ground of a planar frame there.
fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    plane(p)?;
    Ok(Box::new(PlanarWorld))
}

/// The plane's pose in the world: `rot_3d` as rotations about x, y, then z
/// (the sequence [1, 2, 3]), its origin at `r_0_3d`.
fn plane(p: &ParamSet) -> Result<Transform, Error> {
    for name in ["r_0_3d", "rot_3d"] {
        if p.vector(name).iter().any(|x| !x.is_finite()) {
            return Err(p.invalid(name, "every entry must be a finite number"));
        }
    }
    let angles = Vec3::from_column_slice(&p.vector("rot_3d"));
    Ok(Transform::new(axes_rotations([1, 2, 3], &angles), Vec3::from_column_slice(&p.vector("r_0_3d"))))
}

#[derive(Debug)]
struct PlanarWorld;

impl Component for PlanarWorld {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Ground { frame: 0, pose: Transform::IDENTITY }]
    }
}

/// The settings a planar World gives the whole model: those of a 3-D World
/// with gravity `[n, 0] g` in the plane (turned with it into the world)
/// and the same visual defaults, and the plane's pose.
pub fn settings(instance: &ComponentInstance) -> Result<WorldSettings, Error> {
    let planar_only = ["r_0_3d", "rot_3d", "default_z_position"];
    let plane = plane(&super::super::ParamSet::resolve(instance, &SPEC, &WorldSettings::default())?)?;
    let mut params = Vec::new();
    for (name, value) in &instance.params {
        match (name.as_str(), value) {
            ("n", Value::Array(n)) if n.len() == 2 => {
                let n = plane.rot.tr_mul(&Vec3::new(n[0], n[1], 0.0));
                params.push((name.clone(), Value::Array(n.as_slice().to_vec())))
            }
            ("n", _) => {
                return Err(Error::InvalidValue {
                    component: instance.name.clone(),
                    name: "n".into(),
                    value: value.to_string(),
                    reason: "the direction of gravity in the plane takes 2 numbers, e.g. [0, -1]".into(),
                })
            }
            (name, _) if planar_only.contains(&name) => {}
            _ => params.push((name.clone(), value.clone())),
        }
    }
    // Gravity along the plane's y when `n` is not given: [0, -1] in the plane.
    if !params.iter().any(|(name, _)| name == "n") {
        let n = plane.rot.tr_mul(&Vec3::new(0.0, -1.0, 0.0));
        params.push(("n".into(), Value::Array(n.as_slice().to_vec())));
    }
    let as_3d = ComponentInstance { kind: world::SPEC.kind.into(), params, ..instance.clone() };
    Ok(WorldSettings::from_instance(&as_3d)?.with_plane(plane))
}
