//! Compliant contact in the 1-D libraries, after Modelica:
//! `RotationalComponents.ElastoBacklash` (a spring and damper behind a
//! backlash) and `TranslationalComponents.ElastoGap` (a spring and damper
//! that act only once a gap has closed). Both are [`Law1D::Contact`]: out
//! of contact they transmit nothing; in contact the damping force is
//! bounded by the spring force, so the contact force starts from zero and
//! never pulls. Entering and leaving contact are events.

use super::spec::{ComponentSpec, ConnectorSpec, ConnectorType, ParamSpec, ParamType, VarSpec};
use super::{Component, EvalContext, Law1D, ParamSet, Part};
use crate::Error;

/// Below this backlash (rad) ElastoBacklash is a plain spring and damper
/// (Modelica's `bEps`): no endless events in a gap of nothing.
const B_EPS: f64 = 1e-10;

#[derive(Debug)]
struct Contact1D {
    law: Law1D,
    variables: &'static [VarSpec],
}

impl Component for Contact1D {
    fn parts(&self) -> Vec<Part> {
        vec![Part::Element1D { a: 0, b: 1, law: self.law }]
    }

    fn variables(&self) -> Vec<VarSpec> {
        self.variables.to_vec()
    }

    fn evaluate(&self, ctx: &EvalContext, out: &mut Vec<f64>) {
        let st = &ctx.elements[0];
        let (f_c, f_d) = match self.law {
            // ElastoBacklash without backlash.
            Law1D::SpringDamper { c, d, s_rel0 } => (c * (st.s_rel - s_rel0), d * st.v_rel),
            law => law.contact_parts(st.s_rel, st.v_rel),
        };
        let contact = match self.law {
            Law1D::Contact { s_rel0, lo, hi, .. } => {
                let x = st.s_rel - s_rel0;
                x > hi || x < lo
            }
            _ => true,
        };
        for var in self.variables {
            out.push(match var.name {
                "phi_rel" | "s_rel" => st.s_rel,
                "w_rel" | "v_rel" => st.v_rel,
                "a_rel" => st.a_rel,
                "tau" | "f" => st.force,
                "tau_c" | "f_c" => f_c,
                "tau_d" | "f_d" => f_d,
                "contact" => contact as i32 as f64,
                "lossPower" => f_d * st.v_rel,
                _ => f64::NAN,
            });
        }
    }
}

fn spring(p: &ParamSet, positive: bool) -> Result<(f64, f64), Error> {
    Ok((p.non_negative("c", !positive)?, p.non_negative("d", true)?))
}

fn elasto_backlash(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    // Modelica requires c > 0: in the backlash nothing else holds the shafts.
    let (c, d) = spring(p, true)?;
    let b = p.non_negative("b", true)?;
    let s_rel0 = p.real("phi_rel0");
    let law = if b <= B_EPS {
        Law1D::SpringDamper { c, d, s_rel0 }
    } else {
        Law1D::Contact { c, d, s_rel0, lo: -b / 2.0, hi: b / 2.0, n: 1.0 }
    };
    Ok(Box::new(Contact1D { law, variables: ELASTO_BACKLASH.variables }))
}

fn elasto_gap(p: &ParamSet) -> Result<Box<dyn Component>, Error> {
    let (c, d) = spring(p, false)?;
    let n = p.real("n");
    if n.is_nan() || n < 1.0 {
        return Err(p.invalid("n", "the exponent of the spring force must be at least 1"));
    }
    let law = Law1D::Contact { c, d, s_rel0: p.real("s_rel0"), lo: 0.0, hi: f64::INFINITY, n };
    Ok(Box::new(Contact1D { law, variables: ELASTO_GAP.variables }))
}

pub static ELASTO_BACKLASH: ComponentSpec = ComponentSpec {
    kind: "RotationalComponents.ElastoBacklash",
    doc: "A backlash b in series with a spring c and damper d in parallel (Modelica's ElastoBacklash): \
          no torque while |phi_rel - phi_rel0| <= b/2; beyond, tau_c = c * (phi_rel - phi_rel0 -+ b/2) and \
          tau = tau_c + tau_d, the damper's torque d * w_rel bounded by |tau_c| so that the contact torque \
          starts from zero and never pulls. Contact begins and ends at events. b = 0: a spring and damper.",
    params: &[
        ParamSpec::required("c", ParamType::Real, "N.m/rad", "Spring constant (c > 0)"),
        ParamSpec::required("d", ParamType::Real, "N.m.s/rad", "Damping constant"),
        ParamSpec::real("b", 0.0, "rad", "Total backlash"),
        ParamSpec::real("phi_rel0", 0.0, "rad", "Unstretched spring angle"),
    ],
    connectors: &[
        ConnectorSpec::flange("spline_a", ConnectorType::Spline, "First spline"),
        ConnectorSpec::flange("spline_b", ConnectorType::Spline, "Second spline"),
    ],
    variables: &[
        VarSpec::scalar("phi_rel", "rad", "Relative angle (spline_b - spline_a)"),
        VarSpec::scalar("w_rel", "rad/s", "Relative angular velocity"),
        VarSpec::scalar("a_rel", "rad/s2", "Relative angular acceleration"),
        VarSpec::scalar("tau", "N.m", "Contact torque (pushes spline_b back)"),
        VarSpec::scalar("tau_c", "N.m", "The spring's torque"),
        VarSpec::scalar("tau_d", "N.m", "The damper's torque, bounded by |tau_c|"),
        VarSpec::scalar("contact", "", "1 in contact (outside the backlash)"),
        VarSpec::scalar("lossPower", "W", "Power turned into heat"),
    ],
    build: elasto_backlash,
    shapes: super::shapes::none,
};

pub static ELASTO_GAP: ComponentSpec = ComponentSpec {
    kind: "TranslationalComponents.ElastoGap",
    doc: "A spring and damper that can lift off (Modelica's ElastoGap): no force while s_rel > s_rel0; in \
          contact f_c = -c * |s_rel - s_rel0|^n and f = f_c + f_d, the damper's force d * v_rel bounded by \
          |f_c| so that the contact force starts from zero and only pushes. Contact begins and ends at events.",
    params: &[
        ParamSpec::required("c", ParamType::Real, "N/m", "Spring constant"),
        ParamSpec::required("d", ParamType::Real, "N.s/m", "Damping constant"),
        ParamSpec::real("s_rel0", 0.0, "m", "Unstretched spring length: contact below it"),
        ParamSpec::real("n", 1.0, "", "Exponent of the spring force (n >= 1; 1.5 for Hertzian spheres)"),
    ],
    connectors: &[
        ConnectorSpec::flange("flange_a", ConnectorType::Flange, "Left flange"),
        ConnectorSpec::flange("flange_b", ConnectorType::Flange, "Right flange"),
    ],
    variables: &[
        VarSpec::scalar("s_rel", "m", "Relative position (flange_b - flange_a)"),
        VarSpec::scalar("v_rel", "m/s", "Relative velocity"),
        VarSpec::scalar("a_rel", "m/s2", "Relative acceleration"),
        VarSpec::scalar("f", "N", "Contact force (negative: pushes the flanges apart)"),
        VarSpec::scalar("f_c", "N", "The spring's force"),
        VarSpec::scalar("f_d", "N", "The damper's force, bounded by |f_c|"),
        VarSpec::scalar("contact", "", "1 in contact (s_rel < s_rel0)"),
        VarSpec::scalar("lossPower", "W", "Power turned into heat"),
    ],
    build: elasto_gap,
    shapes: super::shapes::none,
};
