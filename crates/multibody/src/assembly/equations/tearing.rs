//! Tearing of a nonlinear algebraic loop: most unknowns of a block that
//! must be solved simultaneously follow one after another from a few
//! others, the tearing variables, by equations solved in closed form;
//! Newton's method then works on the tearing variables alone, with the
//! residual equations left over. (A linear block keeps its one pivoted
//! sparse factorization, which rounds better than chains of closed forms.) The choice is the greedy one of Modelica tools (solve what
//! can be solved; when stuck, tear the unknown that the most remaining
//! equations mention).

use crate::math::symbolic::{self as sym, VarId, S};
use std::collections::HashMap;

/// Blocks torn to more tearing variables than this keep their sparse
/// Newton system: the torn one would be dense.
const MAX_TEARS: usize = 16;

/// How a block is torn.
pub(super) struct Tearing {
    /// `(equation, unknown, value)` in order: the unknown is `value`, a
    /// formula of the tearing variables and of the unknowns before it.
    pub assigned: Vec<(usize, VarId, S)>,
    /// The tearing variables: Newton's unknowns.
    pub tears: Vec<VarId>,
    /// The equations left over, as many as the tearing variables: Newton's
    /// residuals (indices into the block's equations).
    pub residuals: Vec<usize>,
}

/// Tears the block of `equations` (residuals) in `unknowns`, if that makes
/// Newton's system smaller and small. An unknown is assigned only by an
/// equation linear in it with a constant slope, so that no division can
/// vanish. Cost: about the size of the block's incidence.
pub(super) fn tear(equations: &[&S], unknowns: &[VarId]) -> Option<Tearing> {
    let column: HashMap<VarId, usize> = unknowns.iter().enumerate().map(|(j, &x)| (x, j)).collect();
    // Which unknowns each equation mentions, and the reverse.
    let mut incidence: Vec<Vec<usize>> = Vec::with_capacity(equations.len());
    let mut occurs: Vec<Vec<usize>> = vec![Vec::new(); unknowns.len()];
    for (e, r) in equations.iter().enumerate() {
        let mut own = Vec::new();
        r.each_var(&mut |v| {
            if let Some(&j) = column.get(v) {
                if !own.contains(&j) {
                    own.push(j);
                    occurs[j].push(e);
                }
            }
        });
        incidence.push(own);
    }
    let mut left: Vec<usize> = incidence.iter().map(Vec::len).collect();
    let (mut open, mut known) = (vec![true; equations.len()], vec![false; unknowns.len()]);
    let mut ready: Vec<usize> = (0..equations.len()).filter(|&e| left[e] == 1).collect();
    let (mut assigned, mut tears) = (Vec::new(), Vec::new());
    let settle = |j: usize, known: &mut Vec<bool>, left: &mut Vec<usize>, ready: &mut Vec<usize>| {
        known[j] = true;
        for &e in &occurs[j] {
            left[e] -= 1;
            if left[e] == 1 {
                ready.push(e);
            }
        }
    };
    let mut done = 0;
    while done < unknowns.len() {
        if let Some(e) = ready.pop() {
            let Some(&j) = incidence[e].iter().find(|&&j| !known[j]) else { continue };
            if !open[e] || left[e] != 1 {
                continue;
            }
            if let Some(value) = explicit_with_constant_slope(equations[e], unknowns[j]) {
                open[e] = false;
                assigned.push((e, unknowns[j], value));
                settle(j, &mut known, &mut left, &mut ready);
                done += 1;
            }
            continue;
        }
        // Stuck: tear the unknown the most open equations mention.
        let j = (0..unknowns.len())
            .filter(|&j| !known[j])
            .max_by_key(|&j| (occurs[j].iter().filter(|&&e| open[e]).count(), usize::MAX - j))?;
        tears.push(unknowns[j]);
        if tears.len() > MAX_TEARS {
            return None;
        }
        settle(j, &mut known, &mut left, &mut ready);
        done += 1;
    }
    let residuals: Vec<usize> = (0..equations.len()).filter(|&e| open[e]).collect();
    (tears.len() < unknowns.len() && residuals.len() == tears.len()).then_some(Tearing { assigned, tears, residuals })
}

impl Tearing {
    /// The Jacobian of the residual equations by the tearing variables:
    /// `(row, column, entry)` for the entries that are not zero, each the
    /// total derivative through the assigned unknowns (chain rule, in the
    /// order they were assigned).
    pub(super) fn jacobian(&self, equations: &[&S]) -> Vec<(usize, usize, S)> {
        let position: HashMap<VarId, usize> = self.assigned.iter().enumerate().map(|(k, (_, x, _))| (*x, k)).collect();
        // Row k: d(assigned unknown k)/d(each tear).
        let mut rates: Vec<Vec<S>> = Vec::with_capacity(self.assigned.len());
        let total = |e: &S, rates: &[Vec<S>]| -> Vec<S> {
            let mut d: Vec<S> = self.tears.iter().map(|t| sym::derivative(e, t)).collect();
            let mut through = Vec::new();
            e.each_var(&mut |y| {
                if let Some(&k) = position.get(y) {
                    if k < rates.len() && !through.contains(&k) {
                        through.push(k);
                    }
                }
            });
            for k in through {
                let de = sym::derivative(e, &self.assigned[k].1);
                for (dj, rate) in d.iter_mut().zip(&rates[k]) {
                    *dj = sym::add(dj.clone(), sym::mul(de.clone(), rate.clone()));
                }
            }
            d
        };
        for (_, _, value) in &self.assigned {
            let row = total(value, &rates);
            rates.push(row);
        }
        let mut entries = Vec::new();
        for (i, &e) in self.residuals.iter().enumerate() {
            for (j, d) in total(equations[e], &rates).into_iter().enumerate() {
                if d.as_const() != Some(0.0) {
                    entries.push((i, j, d));
                }
            }
        }
        entries
    }
}

/// `x` from `e = 0` if `e` is linear in `x` with a constant slope other
/// than zero.
fn explicit_with_constant_slope(e: &S, x: VarId) -> Option<S> {
    let (slope, rest) = sym::affine_in(e, &x)?;
    match slope.as_const()? {
        0.0 => None,
        k => Some(sym::div(sym::neg(rest), sym::constant(k))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::symbolic::{add, constant, evaluate, mul, sub, var};

    /// A chain of four unknowns closed by one nonlinear equation tears to
    /// one tearing variable, and the total derivative is the chain's.
    #[test]
    fn a_chain_tears_to_one_variable_with_the_chain_rule() {
        // x1 = 2 x0, x2 = x1 + 1, x3 = 3 x2, x0 * x0 + x3 = 10.
        let x = |k: usize| var(VarId::new(k));
        let eqs = [
            sub(x(1), mul(constant(2.0), x(0))),
            sub(x(2), add(x(1), constant(1.0))),
            sub(x(3), mul(constant(3.0), x(2))),
            sub(add(mul(x(0), x(0)), x(3)), constant(10.0)),
        ];
        let refs: Vec<&S> = eqs.iter().collect();
        let t = tear(&refs, &[0, 1, 2, 3].map(VarId::new)).expect("torn");
        assert_eq!(t.tears.len(), 1);
        assert_eq!(t.residuals.len(), 1);
        // With the tear at x0 = 1.5 (any other tear works the same way):
        // the residual is a function of the tear alone; its derivative by
        // finite differences matches the Jacobian's entry.
        let residual = |tear: f64| {
            let mut values = [0.0; 4];
            values[t.tears[0]] = tear;
            for (_, v, value) in &t.assigned {
                values[*v] = evaluate(value, 0.0, &|&w| values[w]);
            }
            evaluate(refs[t.residuals[0]], 0.0, &|&w| values[w])
        };
        let jacobian = t.jacobian(&refs);
        let at = 1.5;
        let mut values = [0.0; 4];
        values[t.tears[0]] = at;
        for (_, v, value) in &t.assigned {
            values[*v] = evaluate(value, 0.0, &|&w| values[w]);
        }
        let exact = evaluate(&jacobian[0].2, 0.0, &|&w| values[w]);
        let h = 1e-6;
        let fd = (residual(at + h) - residual(at - h)) / (2.0 * h);
        assert!((exact - fd).abs() < 1e-6 * (1.0 + fd.abs()), "{exact} vs {fd}");
    }

    /// An unknown whose slope is not constant is not assigned (it could
    /// vanish): such a block stays whole.
    #[test]
    fn no_division_by_a_variable_slope() {
        // x0 * x1 = 1, x0 + x1 = 3: neither has a constant slope in the first.
        let x = |k: usize| var(VarId::new(k));
        let eqs = [sub(mul(x(0), x(1)), constant(1.0)), sub(add(x(0), x(1)), constant(3.0))];
        let refs: Vec<&S> = eqs.iter().collect();
        let t = tear(&refs, &[0, 1].map(VarId::new)).expect("torn");
        assert_eq!(t.assigned.len(), 1);
        assert_eq!(t.residuals, [0]);
    }

    /// Assembled, the loop `x = 2 w + 1, y = x + u, z = 3 y, w^3 + z = 10`
    /// runs Newton's method on one unknown, and its residual ops compute
    /// the other three first.
    #[test]
    fn an_assembled_loop_runs_newton_on_its_tearing_variable_alone() {
        use crate::math::expr::Expr;
        use crate::system::equations::Solve;
        let v = |n: &str| Expr::var(n);
        let mut m = crate::Model::new("loop");
        m.add("source", "BlockComponents.Ramp").set("height", 1.0).set("duration", 1.0);
        for name in ["w", "x", "y", "z"] {
            m.variable(name);
        }
        m.equation(v("x"), 2.0 * v("w") + 1.0);
        m.equation(v("y"), v("x") + v("source.y"));
        m.equation(v("z"), 3.0 * v("y"));
        m.equation(v("w").pow(Expr::Const(3.0)) + v("z"), Expr::Const(10.0));
        let mechanism = m.assemble().unwrap();
        let newton: Vec<(usize, usize)> = mechanism
            .system
            .equations
            .blocks
            .iter()
            .filter_map(|b| match &b.solve {
                Solve::Newton { unknowns, torn, .. } => Some((unknowns.len(), *torn)),
                Solve::Explicit => None,
            })
            .collect();
        assert_eq!(newton.len(), 1, "{newton:?}");
        assert_eq!(newton[0].0, 1, "one tearing variable");
        assert!(newton[0].1 >= 3, "the torn unknowns are computed first: {} ops", newton[0].1);
    }
}
