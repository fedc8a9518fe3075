//! Parameters the library accepts that change nothing here, and why. A
//! model that gives one another value than its default hears so, at the
//! component (issue 45: no parameter is dropped without a word).
//!
//! The walk over the library's parameters
//! (`crates/multibody-dyad/tests/parameters.rs`) holds this list to the
//! truth both ways: a parameter that leaves the compiled model as it was
//! must be said here, and one said here must leave it as it was.

use super::params::ParamSet;
use super::spec::Default;
use crate::Value;

/// What the rest of the model tells about a component's parameters.
pub(crate) struct Context<'a> {
    /// Whether the component draws anything in the animation as it is.
    pub draws: bool,
    /// Whether it would draw anything with `render = true`.
    pub draws_when_rendered: bool,
    /// The World's parameters that some component takes a default from.
    pub world_defaults_read: &'a [&'static str],
}

/// Why `param` of the component with parameters `p` has no effect, if it
/// has none.
pub(crate) fn reason(p: &ParamSet, param: &str, context: &Context) -> Option<&'static str> {
    let kind = p.spec.kind;
    let has = |name: &str| p.spec.param(name).is_some();
    let without = |flag: &str| has(flag) && !p.boolean(flag);
    match param {
        "statePriority" | "linearStatePriority" => {
            Some("the engine chooses the states itself (the joints' coordinates, a free body's motion)")
        }
        "initialize_orientation" => {
            Some("orientation states take their start values from `initial` (and `guess`) on them")
        }
        "rooted" => Some("the tree is found from the connections, rooted at the World"),
        "w_rel_a_fixed" | "z_rel_a_fixed" => Some("start values are given with `initial` on the joint's states"),
        "kinematic_constraint" | "constraint_residue_external" => {
            Some("the rod's length is always kept as a constraint of the loop it closes")
        }
        "checkTotalPower" => Some("the gear constraint passes power exactly (a test checks the balance)"),
        "s_guess" | "phi_guess" => Some("the branch the loop starts on gives the configuration (see positive_branch)"),
        "positive_branch" if kind != "JointRRP" => {
            Some("this assembly stays on the branch of the start configuration; give start values on that branch")
        }
        "has_mass" if has("rod1_mass") && p.real("rod1_mass") == 0.0 => Some("rod1_mass is 0"),
        "rod1_mass" if without("has_mass") => Some("has_mass is false"),
        "m" | "lengthfraction" if without("hasmass") => Some("hasmass is false: the line carries no point mass"),
        "n" | "n_a" | "n_b" if without("drive_train_mechanics_3d") => {
            Some("drive_train_mechanics_3d is false: the 1-D element has no 3-D effects, so its axis does not matter")
        }
        "n" | "n_a" | "n_b" if matches!(kind, "Mounting1D" | "BevelGear1D") => Some(
            "the reaction passes into the frame about the axes of the Rotor1D shafts the drive train turns (their n)",
        ),
        "width" | "height" if kind == "SphereShape" => Some("a sphere's diameter is its length"),
        "n" if kind.starts_with("URDF") && has("angle") && p.real("angle") == 0.0 => {
            Some("angle is 0: the axis n that the joint frame turns about does not matter")
        }
        "inner_height" if kind == "BodyBox" && p.real("inner_width") == 0.0 => {
            Some("inner_width is 0: the box is solid")
        }
        "c_phi" if kind == "PlanarMechanics.Spring" => Some("as in the library, the planar Spring applies no torque"),
        "k" if has("orientation_state") && p.variant("orientation_state") != "Quaternion" => Some(
            "the gain keeps a quaternion state at unit length, and this body's orientation states are not quaternions",
        ),
        // (`render = false` asks for nothing drawn, which such a component meets.)
        "render" if p.boolean("render") && !context.draws_when_rendered => {
            Some("the animation draws nothing for this component")
        }
        _ if param.starts_with("default_") && !context.world_defaults_read.contains(&param) => {
            Some("no component of the model takes its default from this World parameter")
        }
        "c_z" | "d_z" if without("elastic_contact") => Some("elastic_contact is false: the contact is rigid"),
        // Force arrows are drawn from the force as it acts, not as shapes.
        _ if is_visual(param) && !context.draws && !has("scale") => {
            Some("the animation draws nothing for this component (see its render)")
        }
        _ if not_drawn(kind, param) => Some("the animation does not draw this detail"),
        _ => None,
    }
}

/// Whether `param` of `p` was given another value than its default (or
/// given at all, for `render`).
pub(crate) fn changed_from_default(p: &ParamSet, param: &str) -> bool {
    let Some(spec) = p.spec.param(param) else { return false };
    if !p.is_given(param) {
        return false;
    }
    // Asking to draw what draws nothing is worth a word, default or not.
    if param == "render" {
        return true;
    }
    let given = p.raw(param);
    match (spec.default, given) {
        (Default::Number(x), Some(Value::Number(y))) => x != *y,
        (Default::Bool(x), Some(Value::Bool(y))) => x != *y,
        (Default::Vector(x), Some(Value::Array(y))) => x != y.as_slice(),
        _ => true,
    }
}

/// Parameters that only change how a component is drawn (`render` and the
/// World's defaults have rules of their own).
fn is_visual(param: &str) -> bool {
    matches!(
        param,
        "animation"
            | "color"
            | "specular_coefficient"
            | "arrow_diameter"
            | "scale"
            | "rod_radius"
            | "rod_color"
            | "sphere_diameter"
            | "sphere_color"
            | "box_width"
            | "box_height"
            | "rim_diameter"
            | "wheel_width"
            | "end_ratio"
            | "length_fraction"
            | "shape_scale"
    ) || param.starts_with("ground_")
        || param.starts_with("axis_")
}

/// Drawing details the animation leaves out where the component draws
/// other things (a spring's coil, a damper's proportions, the ground
/// plane; planar force arrows are not drawn at all).
pub(crate) fn not_drawn(kind: &str, param: &str) -> bool {
    let planar = kind.starts_with("PlanarMechanics.");
    let kind = kind.strip_prefix("PlanarMechanics.").unwrap_or(kind);
    matches!(
        (kind, param),
        ("Spring" | "SpringDamper" | "Damper" | "SpringDamperParallel", "N" | "end_ratio" | "length_fraction")
            | ("BodyShape", "shape_scale")
            | ("Spherical", "radius")
            | ("UniversalSpherical" | "SphericalSpherical", "sphere_diameter")
            | ("WorldForce" | "WorldTorque" | "WorldForceAndTorque", "specular_coefficient")
            | ("World", "render_ground" | "ground_axis_u" | "ground_length_u" | "ground_length_v" | "ground_color")
    ) || planar
        && (matches!(
            (kind, param),
            ("OneDOFRollingWheelJoint" | "OneDOFSlippingWheelJoint", "rim_diameter" | "z_position")
                | ("SlipBasedWheelJoint", "rim_diameter" | "wheel_width" | "z_position")
        ) || matches!(kind, "Spring" | "SpringDamper" | "Damper" | "Distance") && param == "z_position"
            || matches!(kind, "CutForce" | "CutTorque" | "WorldForceTorque" | "WorldForce")
                && matches!(param, "scale" | "arrow_diameter" | "z_position" | "color" | "specular_coefficient"))
}
