//! A road surface: its height `y = h(x, z)`, an expression in the
//! variables `x` and `z` (the world's), compiled with its gradient and
//! second derivatives (from the one symbolic differentiation) into a
//! [`Tape`], evaluated allocating nothing.

use super::expr::{Expr, Node};
use super::symbolic::{derivative, rewrite, var};
use super::tape::Tape;

/// A compiled surface formula.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// `h, dh/dx, dh/dz, d2h/dx2, d2h/dxdz, d2h/dz2`.
    tape: Tape,
}

/// A value with its gradient `[d/dx, d/dz]` and second derivatives
/// `[d2/dx2, d2/dxdz, d2/dz2]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Height {
    pub value: f64,
    pub grad: [f64; 2],
    pub hess: [f64; 3],
}

impl Surface {
    /// Compiles `expr`, or says why it cannot be.
    pub fn new(expr: &Expr) -> Result<Self, String> {
        let h: Node<usize> = rewrite(expr, &mut |node| match node {
            Expr::Var(name) if name == "x" => Ok(Some(var(0))),
            Expr::Var(name) if name == "z" => Ok(Some(var(1))),
            Expr::Var(name) => Err(format!("a road's height is a formula of x and z only, not of `{name}`")),
            Expr::Call2(f, ..) => {
                let name = format!("{f:?}").to_lowercase();
                Err(format!("`{name}` has no second derivatives everywhere, which a road needs"))
            }
            Expr::Const(_)
            | Expr::Neg(_)
            | Expr::Add(..)
            | Expr::Sub(..)
            | Expr::Mul(..)
            | Expr::Div(..)
            | Expr::Pow(..)
            | Expr::Call(..) => Ok(None),
            _ => Err("a road's height uses numbers, x, z, + - * / ^ and functions of one argument (sin, exp, ...); \
                      not time, der, comparisons or if"
                .into()),
        })?;
        let (hx, hz) = (derivative(&h, &0), derivative(&h, &1));
        let (hxx, hxz, hzz) = (derivative(&hx, &0), derivative(&hx, &1), derivative(&hz, &1));
        Ok(Surface { tape: Tape::new(&[h, hx, hz, hxx, hxz, hzz], 2, "the road's formula")? })
    }

    /// The height at `(x, z)` with its derivatives.
    pub fn height(&self, x: f64, z: f64) -> Height {
        let mut o = [0.0; 6];
        self.tape.eval(&[x, z], &mut o);
        Height { value: o[0], grad: [o[1], o[2]], hess: [o[3], o[4], o[5]] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::expr::Func;

    #[test]
    fn heights_come_with_their_derivatives() {
        use Expr as S;
        let b = std::sync::Arc::new;
        let (x, z) = (|| S::Var("x".into()), || S::Var("z".into()));
        // h = 0.3 sin(2x) z^2 / (1 + x^2) + 0.1 x, checked against central differences
        // (step 1e-4: truncation ~1e-8, rounding ~1e-12 / 1e-8 on second derivatives).
        let h = S::Add(
            b(S::Div(
                b(S::Mul(
                    b(S::Mul(b(S::Const(0.3)), b(S::Call(Func::Sin, b(S::Mul(b(S::Const(2.0)), b(x()))))))),
                    b(S::Pow(b(z()), b(S::Const(2.0)))),
                )),
                b(S::Add(b(S::Const(1.0)), b(S::Mul(b(x()), b(x()))))),
            )),
            b(S::Mul(b(S::Const(0.1)), b(x()))),
        );
        let s = Surface::new(&h).unwrap();
        let f = |x: f64, z: f64| 0.3 * (2.0 * x).sin() * z * z / (1.0 + x * x) + 0.1 * x;
        let (x, z, e) = (0.7, -1.3, 1e-4);
        let got = s.height(x, z);
        assert!((got.value - f(x, z)).abs() < 1e-15);
        let fx = (f(x + e, z) - f(x - e, z)) / (2.0 * e);
        let fz = (f(x, z + e) - f(x, z - e)) / (2.0 * e);
        let fxx = (f(x + e, z) - 2.0 * f(x, z) + f(x - e, z)) / (e * e);
        let fzz = (f(x, z + e) - 2.0 * f(x, z) + f(x, z - e)) / (e * e);
        let fxz = (f(x + e, z + e) - f(x + e, z - e) - f(x - e, z + e) + f(x - e, z - e)) / (4.0 * e * e);
        for (a, b) in [(got.grad[0], fx), (got.grad[1], fz)] {
            assert!((a - b).abs() < 1e-7, "{a} vs {b}");
        }
        for (a, b) in [(got.hess[0], fxx), (got.hess[1], fxz), (got.hess[2], fzz)] {
            assert!((a - b).abs() < 1e-5, "{a} vs {b}");
        }
    }

    #[test]
    fn long_formulas_are_refused() {
        let mut e = Expr::Var("x".into());
        for k in 0..100 {
            e = e * Expr::Var("z".into()) + k as f64;
        }
        assert!(Surface::new(&e).unwrap_err().contains("too long"));
    }
}
