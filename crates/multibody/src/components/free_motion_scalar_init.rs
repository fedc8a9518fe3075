//! FreeMotionScalarInit: measures the motion of frame_b relative to
//! frame_a and lets the model start from given values of it (a tip's
//! position and speed, say), which the joints' start values then follow
//! from. It applies no force and constrains nothing during the run.

use super::spec::{ComponentSpec, ConnectorSpec, ParamSpec, VarSpec};
use super::{Component, EvalContext, ParamSet, Part};
use crate::Error;

pub static SPEC: ComponentSpec = ComponentSpec {
    kind: "FreeMotionScalarInit",
    doc: "Measures the position r_rel_a_k and velocity v_rel_a_k (k = 1, 2, 3) of frame_b's origin relative to \
          frame_a, resolved in frame_a. Giving any of them an initial value makes it an initial equation: the \
          joints' start values that are not fixed are solved so that it holds. No force acts through it.",
    params: &[
        ParamSpec::boolean("use_r", false, "Whether r_rel_a may be given initial values"),
        ParamSpec::boolean("use_v", false, "Whether v_rel_a may be given initial values"),
        ParamSpec::boolean("use_a", false, "Relative accelerations as initial conditions (not supported)"),
        ParamSpec::boolean("use_angle", false, "Relative angles as initial conditions (not supported)"),
        ParamSpec::boolean("use_w", false, "Relative angular velocities as initial conditions (not supported)"),
        ParamSpec::boolean("animation", true, "Kept for compatibility"),
    ],
    connectors: &[
        ConnectorSpec::frame("frame_a", "The reference frame"),
        ConnectorSpec::frame("frame_b", "The measured frame"),
    ],
    variables: &VARIABLES,
    build,
    shapes: super::shapes::none,
};

static VARIABLES: [VarSpec; 6] = [
    VarSpec::scalar("r_rel_a_1", "m", "x of frame_b's origin relative to frame_a, resolved in frame_a"),
    VarSpec::scalar("r_rel_a_2", "m", "y of the same"),
    VarSpec::scalar("r_rel_a_3", "m", "z of the same"),
    VarSpec::scalar("v_rel_a_1", "m/s", "Rate of r_rel_a_1"),
    VarSpec::scalar("v_rel_a_2", "m/s", "Rate of r_rel_a_2"),
    VarSpec::scalar("v_rel_a_3", "m/s", "Rate of r_rel_a_3"),
];

fn build(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    for name in ["use_a", "use_angle", "use_w"] {
        if p.boolean(name) {
            return Err(Error::Unsupported {
                component: p.component.into(),
                what: format!("initial conditions with {name} = true"),
                fix: "give positions and velocities (use_r, use_v), or the joints' start values".into(),
            });
        }
    }
    Ok(Box::new(FreeMotionScalarInit { use_r: p.boolean("use_r"), use_v: p.boolean("use_v") }))
}

#[derive(Debug)]
struct FreeMotionScalarInit {
    use_r: bool,
    use_v: bool,
}

impl Component for FreeMotionScalarInit {
    fn parts(&self) -> Vec<Part> {
        vec![Part::InitialMotion { a: 0, b: 1, position: self.use_r, velocity: self.use_v }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        VARIABLES.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let (a, b) = (&ctx.frames[0], &ctx.frames[1]);
        let r_rel = a.rot * (b.r_0 - a.r_0);
        // d/dt (R_a d) = R_a d' - w_a x (R_a d), with w_a in frame_a.
        let v_rel = a.rot * (b.v_0 - a.v_0) - a.w.cross(&r_rel);
        out.extend(r_rel.iter().chain(v_rel.iter()));
    }
}
