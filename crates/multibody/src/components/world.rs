//! World: the inertial frame, the gravity field and the visual defaults.

use super::spec::{ComponentSpec, ConnectorSpec, Default, ParamSpec, ParamType};
use super::{Component, ParamSet, Part};
use crate::math::{Transform, Vec3};
use crate::{Error, Value};

const COLOR: ParamType = ParamType::Vector(4);
const LENGTH_DEFAULTS: &[(&str, f64)] = &[
    ("axis_length", 1.0),
    ("axis_radius", 1.0 / 20.0),
    ("default_joint_length", 1.0 / 10.0),
    ("default_joint_width", 1.0 / 20.0),
    ("default_body_diameter", 1.0 / 9.0),
    ("default_arrow_diameter", 1.0 / 40.0),
    ("default_force_length", 1.0 / 10.0),
    ("default_force_width", 1.0 / 20.0),
];

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "World",
    doc: "The root of every model: frame_b is fixed at the origin with identity orientation. Gravity \
          (uniform g*n, or point gravity towards the origin with constant mu) and the visual defaults \
          of all other components are set here. Every model has exactly one World.",
    params: &[
        ParamSpec::boolean("render", true, "Draw the world axes in animations"),
        ParamSpec::vector("n", &[0.0, -1.0, 0.0], "", "Direction of uniform gravity (normalised)"),
        ParamSpec::real("g", 9.80665, "m/s2", "Magnitude of uniform gravity"),
        ParamSpec::real("mu", 3.986004418e14, "m3/s2", "Gravity field constant of point gravity"),
        ParamSpec::boolean(
            "point_gravity",
            false,
            "Use a point-gravity field pointing towards the origin for every mass, instead of the uniform field g*n",
        ),
        ParamSpec::real("nominal_length", 1.0, "m", "Nominal size of the model; scales the visual defaults"),
        ParamSpec::derived("axis_length", ParamType::Real, "nominal_length", "m", "Length of the world axes"),
        ParamSpec::derived("axis_radius", ParamType::Real, "nominal_length / 20", "m", "Radius of the world axes"),
        ParamSpec::derived("default_joint_length", ParamType::Real, "nominal_length / 10", "m", "Default joint length"),
        ParamSpec::derived("default_joint_width", ParamType::Real, "nominal_length / 20", "m", "Default joint width"),
        ParamSpec::derived(
            "default_body_diameter",
            ParamType::Real,
            "nominal_length / 9",
            "m",
            "Default diameter of the sphere of a body",
        ),
        ParamSpec::real("default_width_fraction", 20.0, "", "Default width of rods and shapes as a fraction of length"),
        ParamSpec::derived(
            "default_arrow_diameter",
            ParamType::Real,
            "nominal_length / 40",
            "m",
            "Default arrow diameter",
        ),
        ParamSpec::derived("default_force_length", ParamType::Real, "nominal_length / 10", "m", "Default force length"),
        ParamSpec::derived("default_force_width", ParamType::Real, "nominal_length / 20", "m", "Default force width"),
        ParamSpec::real("default_N_to_m", 1000.0, "N/m", "Force arrows: newtons per metre of arrow"),
        ParamSpec::real("default_Nm_to_m", 1000.0, "N.m/m", "Torque arrows: newton metres per metre of arrow"),
        ParamSpec::vector("default_body_color", &[0.6, 0.0, 0.5019608, 1.0], "", "Default colour of bodies (RGBA)"),
        ParamSpec::vector("default_rod_color", &[0.5019608, 0.0, 0.5019608, 1.0], "", "Default colour of rods"),
        ParamSpec::vector("default_joint_color", &[1.0, 0.0, 0.0, 1.0], "", "Default colour of joints"),
        ParamSpec::vector("default_prismatic_color", &[0.0, 0.8, 1.0, 1.0], "", "Default colour of prismatic joints"),
        ParamSpec::vector("default_spring_color", &[0.0, 0.0, 1.0, 1.0], "", "Default colour of springs"),
        ParamSpec::vector("default_force_color", &[0.0, 1.0, 0.0, 0.5], "", "Default colour of force arrows"),
        ParamSpec::vector("default_sensor_color", &[0.0, 1.0, 0.0, 0.5], "", "Default colour of sensors"),
        ParamSpec::boolean("render_ground", false, "Draw a ground plane"),
        ParamSpec::vector("ground_axis_u", &[1.0, 0.0, 0.0], "", "First axis of the ground plane"),
        ParamSpec::real("ground_length_u", 2.0, "m", "Length of the ground plane along its first axis"),
        ParamSpec::real("ground_length_v", 2.0, "m", "Length of the ground plane along its second axis"),
        ParamSpec {
            name: "ground_color",
            ty: COLOR,
            default: Default::Vector(&[0.784, 0.784, 0.784, 1.0]),
            unit: "",
            doc: "Colour of the ground plane",
        },
    ],
    connectors: &[ConnectorSpec::frame("frame_b", "The world frame: origin at 0, identity orientation")],
    variables: &[],
    build,
    shapes,
};

/// The world axes: red x, green y, blue z.
fn shapes(p: &ParamSet) -> Vec<super::shapes::LocalShape> {
    use super::shapes::{LocalShape, ShapeKind};
    if !p.boolean("render") {
        return Vec::new();
    }
    let length = p.real_opt("axis_length").unwrap_or(p.real("nominal_length"));
    let d = p.real_opt("axis_radius").unwrap_or(p.real("nominal_length") / 20.0) / 2.0;
    let colors = [[1.0, 0.0, 0.0, 1.0], [0.0, 0.6, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0]];
    (0..3)
        .map(|k| {
            LocalShape::in_frame(ShapeKind::Arrow, "frame_b", Vec3::zeros(), crate::math::unit(k) * length, d, d)
                .colored(colors[k], 0.7)
        })
        .collect()
}

/// The World's settings as every other component sees them.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldSettings {
    pub g: f64,
    /// Unit direction of uniform gravity.
    pub n: Vec3,
    pub mu: f64,
    pub point_gravity: bool,
    /// Where the planar World puts the plane of planar components (world
    /// to plane; the x-y plane unless its `r_0_3d` or `rot_3d` move it).
    pub plane: Transform,
    /// Every World parameter, defaults included, for the visual defaults.
    values: Vec<(&'static str, Value)>,
}

impl std::default::Default for WorldSettings {
    fn default() -> Self {
        let instance = crate::ComponentInstance {
            name: "world".into(),
            kind: "World".into(),
            params: vec![],
            initial: vec![],
            guess: vec![],
            surface: None,
        };
        Self::from_instance(&instance).expect("the World defaults are valid")
    }
}

impl WorldSettings {
    /// No values: used while resolving the World's own parameters, which
    /// have no World-dependent defaults.
    const BARE: WorldSettings = WorldSettings {
        g: 0.0,
        n: Vec3::new(0.0, 0.0, 0.0),
        mu: 0.0,
        point_gravity: false,
        plane: Transform::IDENTITY,
        values: Vec::new(),
    };

    /// The settings of a World component instance.
    pub fn from_instance(instance: &crate::ComponentInstance) -> Result<Self, Error> {
        let bare = Self::BARE;
        let p = ParamSet::resolve(instance, &SPEC, &bare)?;
        let n = p.direction("n")?;
        let nominal = p.non_negative("nominal_length", false)?;
        let mut values = Vec::with_capacity(SPEC.params.len());
        for spec in SPEC.params {
            let value = match spec.default {
                Default::Derived(_) if !p.is_given(spec.name) => {
                    let factor = LENGTH_DEFAULTS.iter().find(|(n, _)| *n == spec.name).map_or(1.0, |(_, f)| *f);
                    Value::Number(nominal * factor)
                }
                _ => match spec.ty {
                    ParamType::Bool => Value::Bool(p.boolean(spec.name)),
                    ParamType::Vector(_) => Value::Array(p.vector(spec.name)),
                    _ => Value::Number(p.real(spec.name)),
                },
            };
            values.push((spec.name, value));
        }
        // A negative field constant would make point gravity push away (Modelica: `mu(min = 0)`).
        let mu = p.non_negative("mu", true)?;
        Ok(Self {
            g: p.real("g"),
            n,
            mu,
            point_gravity: p.boolean("point_gravity"),
            plane: Transform::IDENTITY,
            values,
        })
    }

    /// These settings with the planar components' plane at `plane`.
    pub fn with_plane(self, plane: Transform) -> WorldSettings {
        WorldSettings { plane, ..self }
    }

    /// A World parameter times `factor` (factors apply to numbers only).
    pub fn scaled(&self, name: &str, factor: f64) -> Value {
        match self.values.iter().find(|(n, _)| *n == name).map(|(_, v)| v) {
            Some(Value::Number(x)) => Value::Number(x * factor),
            Some(v) => v.clone(),
            None => Value::Number(0.0),
        }
    }

    /// A numeric World parameter.
    pub fn number(&self, name: &str) -> f64 {
        match self.scaled(name, 1.0) {
            Value::Number(x) => x,
            _ => 0.0,
        }
    }

    /// The uniform gravity acceleration `g n` (zero when every mass feels
    /// point gravity).
    pub fn uniform_gravity(&self) -> Vec3 {
        if self.point_gravity {
            Vec3::zeros()
        } else {
            self.n * self.g
        }
    }

    /// The gravity acceleration at `r` (world coordinates) for a mass that
    /// asks for point gravity (`point`) or not.
    #[inline]
    pub fn gravity(&self, r: &Vec3, point: bool) -> Vec3 {
        if point || self.point_gravity {
            crate::math::point_gravity(self.mu, r)
        } else {
            self.n * self.g
        }
    }
}

#[derive(Debug)]
struct World;

fn build(_: &ParamSet) -> Result<Box<dyn Component>, Error> {
    Ok(Box::new(World))
}

impl Component for World {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Ground { frame: 0, pose: Transform::IDENTITY }]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_the_library_values() {
        let w = WorldSettings::default();
        assert_eq!(w.g, 9.80665);
        assert_eq!(w.n, Vec3::new(0.0, -1.0, 0.0));
        assert_eq!(w.number("default_body_diameter"), 1.0 / 9.0);
        assert_eq!(w.number("default_joint_width"), 1.0 / 20.0);
    }

    #[test]
    fn gravity_is_normalised_and_point_gravity_pulls_to_the_origin() {
        let mut instance = crate::ComponentInstance {
            name: "world".into(),
            kind: "World".into(),
            params: vec![("n".into(), Value::Array(vec![0.0, 0.0, -2.0])), ("mu".into(), Value::Number(2.0))],
            initial: vec![],
            guess: vec![],
            surface: None,
        };
        let w = WorldSettings::from_instance(&instance).unwrap();
        assert_eq!(w.uniform_gravity(), Vec3::new(0.0, 0.0, -9.80665));
        let g = w.gravity(&Vec3::new(2.0, 0.0, 0.0), true);
        assert!((g - Vec3::new(-0.5, 0.0, 0.0)).norm() < 1e-15);
        instance.params.push(("n".into(), Value::Array(vec![0.0, 0.0, 0.0])));
        assert!(WorldSettings::from_instance(&instance).is_err());
    }
}
