//! Nodes without mass (see [`crate::system::balance`]): what their balance
//! gives before the dynamics (the speed, and without damping the position)
//! and after it (the acceleration, from the others').

use super::Workspace;
use crate::system::balance::Balance;
use crate::system::{Law1D, System};

/// `(c, d, s_rel0, [g, g', g''])` of a linear law `f = c (s_rel - s_rel0)
/// + d v_rel + g(t)`; assembly admits no other laws at a node.
#[inline]
fn linear(law: &Law1D, ws: &Workspace) -> (f64, f64, f64, [f64; 3]) {
    let jet = |slot: usize, sign: f64| {
        let [d1, d2] = ws.signal_rates[slot];
        [sign * ws.signals[slot], sign * d1, sign * d2]
    };
    match *law {
        Law1D::Spring { c, s_rel0 } => (c, 0.0, s_rel0, [0.0; 3]),
        Law1D::Damper { d } => (0.0, d, 0.0, [0.0; 3]),
        Law1D::SpringDamper { c, d, s_rel0 } => (c, d, s_rel0, [0.0; 3]),
        Law1D::Source { value } => (0.0, 0.0, 0.0, [-value, 0.0, 0.0]),
        Law1D::Input { signal } => (0.0, 0.0, 0.0, jet(signal, -1.0)),
        Law1D::Flow { signal } => (0.0, 0.0, 0.0, jet(signal, 1.0)),
        Law1D::Contact { .. } => (0.0, 0.0, 0.0, [f64::NAN; 3]),
    }
}

impl System {
    /// The position and speed of node `b` at `(q, u)`: the balance
    /// `C x + D v = R` gives the speed where there is damping (the position
    /// is the state's), and otherwise the position and, differentiated,
    /// the speed.
    #[inline]
    pub(crate) fn balance_motion(&self, ws: &Workspace, b: &Balance, q: &[f64], u: &[f64]) -> (f64, f64) {
        let (mut r, mut r_rate) = (0.0, 0.0);
        for t in &b.terms {
            let e = &self.axis_elements[t.element];
            let (other, beta) = if t.at_b { (e.a, 1.0) } else { (e.b, -1.0) };
            let (s_o, v_o) = other.motion(q, u, &ws.lines);
            let (c, d, s_rel0, g) = linear(&e.law, ws);
            r += t.k * (c * (s_o - t.offset) + d * v_o + beta * (c * s_rel0 - g[0]));
            r_rate += t.k * (c * v_o - beta * g[1]);
        }
        if b.damping > 0.0 {
            let x = q[b.q];
            (x, (r - b.stiffness * x) / b.damping)
        } else {
            (r / b.stiffness, r_rate / b.stiffness)
        }
    }

    /// The accelerations of the nodes without mass into `ud`, from the
    /// balance differentiated once more and the others' accelerations.
    pub(crate) fn balance_accelerations(&self, ws: &Workspace, q: &[f64], u: &[f64], ud: &mut [f64]) {
        for b in &self.balances {
            let mut r = 0.0;
            for t in &b.terms {
                let e = &self.axis_elements[t.element];
                let (other, beta) = if t.at_b { (e.a, 1.0) } else { (e.b, -1.0) };
                let (_, v_o) = other.motion(q, u, &ws.lines);
                let a_o = other.acceleration(ud, &[]);
                let (c, d, _, g) = linear(&e.law, ws);
                r += t.k * if b.damping > 0.0 { c * v_o + d * a_o - beta * g[1] } else { c * a_o - beta * g[2] };
            }
            ud[b.v] = if b.damping > 0.0 { (r - b.stiffness * u[b.v]) / b.damping } else { r / b.stiffness };
        }
    }
}
