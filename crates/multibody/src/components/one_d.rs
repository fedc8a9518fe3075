//! What the 1-D elements of the rotational and translational libraries
//! share: a force law between two flanges and variables computed from the
//! relative motion.

use super::spec::VarSpec;
use super::{Component, Element1DState, EvalContext, Law1D, Part};

/// A 1-D element: `law` acts between connector `a` (flange_a, or a source's
/// support) and connector `b` (flange_b, or a source's driven flange).
#[derive(Debug)]
pub struct Element1D {
    pub law: Law1D,
    pub a: usize,
    pub b: usize,
    pub variables: &'static [VarSpec],
}

impl Component for Element1D {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Element1D { a: self.a, b: self.b, law: self.law }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let st = &ctx.elements[0];
        out.extend(self.variables.iter().map(|v| self.value(v.name, st)));
    }
}

impl Element1D {
    /// The value of a variable, by the names both libraries use.
    fn value(&self, name: &str, st: &Element1DState) -> f64 {
        let (c, d, s0) = match self.law {
            Law1D::Spring { c, s_rel0 } => (c, 0.0, s_rel0),
            Law1D::Damper { d } => (0.0, d, 0.0),
            Law1D::SpringDamper { c, d, s_rel0 } => (c, d, s_rel0),
            Law1D::Source { .. } => (0.0, 0.0, 0.0),
        };
        match name {
            "phi_rel" | "s_rel" | "phi" | "s" => st.s_rel,
            "w_rel" | "v_rel" | "w" | "v" => st.v_rel,
            "a_rel" => st.a_rel,
            // A source reports the force it drives with; a compliant element its internal force.
            "tau" | "f" if matches!(self.law, Law1D::Source { .. }) => -st.force,
            "tau" | "f" => st.force,
            "tau_c" | "f_c" => c * (st.s_rel - s0),
            "tau_d" | "f_d" => d * st.v_rel,
            "lossPower" => d * st.v_rel * st.v_rel,
            _ => f64::NAN,
        }
    }
}
