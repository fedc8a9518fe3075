//! 1-D nodes without mass held by the forces on them (a `Mass(m = 0)`, or
//! a spring and a damper joined with nothing between them), as Modelica
//! solves them: the forces on the node balance at every instant.
//!
//! Each such node is a coordinate `x` of its own, driven like a prescribed
//! one. Its elements are linear (springs, dampers, spring-dampers, forces
//! of time): the one at `s = offset + k x` gives `f = c (s_rel - s_rel0) +
//! d v_rel + g(t)`. Their balance on the coordinate is then
//! `C x + D v = R` with `C = sum c k^2`, `D = sum d k^2`, and `R` from the
//! other ends. With damping (`D > 0`) the position is a state and the
//! balance gives the speed (a first-order node); without, it gives the
//! position, and its derivatives the speed and acceleration.

/// One element on a node: where it meets the node, and how it acts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BalanceTerm {
    /// The element (`System::axis_elements`).
    pub element: usize,
    /// Whether the node is the element's flange_b (else flange_a).
    pub at_b: bool,
    /// `s = offset + k x` of the element's end on the node.
    pub k: f64,
    pub offset: f64,
}

/// A node without mass, on the coordinate `(q, v)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Balance {
    pub q: usize,
    pub v: usize,
    pub terms: Vec<BalanceTerm>,
    /// `sum c k^2` and `sum d k^2` over the terms.
    pub stiffness: f64,
    pub damping: f64,
}
