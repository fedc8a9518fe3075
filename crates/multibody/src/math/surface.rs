//! A road surface: its height `y = h(x, z)`, an expression in the
//! variables `x` and `z` (the world's), compiled into a fixed-size program
//! (plain `Copy` data, so that a wheel's contact law can carry it) and
//! evaluated with its gradient and second derivatives, allocating nothing.

use super::expr::{Expr, Func};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    X,
    Z,
    Const(f64),
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Call(Func),
}

/// Longest program (instructions) and deepest stack of a surface formula.
pub const MAX_OPS: usize = 48;
pub const MAX_DEPTH: usize = 12;

/// A compiled surface formula.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    ops: [Op; MAX_OPS],
    len: usize,
}

/// A value with its gradient `[d/dx, d/dz]` and second derivatives
/// `[d2/dx2, d2/dxdz, d2/dz2]`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Height {
    pub value: f64,
    pub grad: [f64; 2],
    pub hess: [f64; 3],
}

impl Height {
    fn constant(value: f64) -> Self {
        Height { value, ..Default::default() }
    }

    /// `g(self)` for `g` with the derivatives `[g, g', g'']` at `self.value`.
    fn chain(self, [g, g1, g2]: [f64; 3]) -> Self {
        let [ux, uz] = self.grad;
        let [hxx, hxz, hzz] = self.hess;
        Height {
            value: g,
            grad: [g1 * ux, g1 * uz],
            hess: [g2 * ux * ux + g1 * hxx, g2 * ux * uz + g1 * hxz, g2 * uz * uz + g1 * hzz],
        }
    }

    fn add(self, b: Self, sign: f64) -> Self {
        Height {
            value: self.value + sign * b.value,
            grad: [self.grad[0] + sign * b.grad[0], self.grad[1] + sign * b.grad[1]],
            hess: [0, 1, 2].map(|i| self.hess[i] + sign * b.hess[i]),
        }
    }

    fn mul(self, b: Self) -> Self {
        let (a, ag, ah) = (self.value, self.grad, self.hess);
        let (c, cg, ch) = (b.value, b.grad, b.hess);
        Height {
            value: a * c,
            grad: [ag[0] * c + a * cg[0], ag[1] * c + a * cg[1]],
            hess: [
                ah[0] * c + 2.0 * ag[0] * cg[0] + a * ch[0],
                ah[1] * c + ag[0] * cg[1] + ag[1] * cg[0] + a * ch[1],
                ah[2] * c + 2.0 * ag[1] * cg[1] + a * ch[2],
            ],
        }
    }

    fn is_constant(&self) -> bool {
        self.grad == [0.0; 2] && self.hess == [0.0; 3]
    }
}

impl Surface {
    /// Compiles `expr`, or says why it cannot be.
    pub fn new(expr: &Expr) -> Result<Self, String> {
        let mut ops = [Op::Const(0.0); MAX_OPS];
        let mut len = 0;
        let depth = compile(expr, &mut ops, &mut len)?;
        if depth > MAX_DEPTH {
            return Err(format!("the road's formula nests {depth} levels deep; at most {MAX_DEPTH} are supported"));
        }
        Ok(Surface { ops, len })
    }

    /// The height at `(x, z)` with its derivatives.
    pub fn height(&self, x: f64, z: f64) -> Height {
        let mut stack = [Height::default(); MAX_DEPTH];
        let mut n = 0;
        for op in &self.ops[..self.len] {
            let value = match *op {
                Op::X => Height { value: x, grad: [1.0, 0.0], hess: [0.0; 3] },
                Op::Z => Height { value: z, grad: [0.0, 1.0], hess: [0.0; 3] },
                Op::Const(c) => Height::constant(c),
                Op::Neg => {
                    n -= 1;
                    stack[n].chain([-stack[n].value, -1.0, 0.0])
                }
                Op::Call(f) => {
                    n -= 1;
                    stack[n].chain(f.derivatives(stack[n].value))
                }
                binary => {
                    n -= 2;
                    let (a, b) = (stack[n], stack[n + 1]);
                    match binary {
                        Op::Add => a.add(b, 1.0),
                        Op::Sub => a.add(b, -1.0),
                        Op::Mul => a.mul(b),
                        // a / b = a * (1 / b).
                        Op::Div => a.mul(b.chain({
                            let r = 1.0 / b.value;
                            [r, -r * r, 2.0 * r * r * r]
                        })),
                        Op::Pow if b.is_constant() => {
                            let p = b.value;
                            let d1 = if p == 0.0 { 0.0 } else { p * a.value.powf(p - 1.0) };
                            let d2 = if p == 0.0 || p == 1.0 { 0.0 } else { p * (p - 1.0) * a.value.powf(p - 2.0) };
                            a.chain([a.value.powf(p), d1, d2])
                        }
                        // a^b = exp(b ln a).
                        _ => b
                            .mul(a.chain(Func::Log.derivatives(a.value)))
                            .chain(Func::Exp.derivatives(b.value * a.value.ln())),
                    }
                }
            };
            stack[n] = value;
            n += 1;
        }
        stack[0]
    }
}

/// Postfix code of `expr` appended to `ops`; returns the stack depth it needs.
fn compile(expr: &Expr, ops: &mut [Op; MAX_OPS], len: &mut usize) -> Result<usize, String> {
    Ok(match expr {
        Expr::Var(name) if name == "x" || name == "z" => {
            put(ops, len, if name == "x" { Op::X } else { Op::Z })?;
            1
        }
        Expr::Var(name) => return Err(format!("a road's height is a formula of x and z only, not of `{name}`")),
        Expr::Const(c) => {
            put(ops, len, Op::Const(*c))?;
            1
        }
        Expr::Neg(a) => {
            let d = compile(a, ops, len)?;
            put(ops, len, Op::Neg)?;
            d
        }
        Expr::Call(f, a) => {
            let d = compile(a, ops, len)?;
            put(ops, len, Op::Call(*f))?;
            d
        }
        Expr::Add(a, b) | Expr::Sub(a, b) | Expr::Mul(a, b) | Expr::Div(a, b) | Expr::Pow(a, b) => {
            let da = compile(a, ops, len)?;
            let db = compile(b, ops, len)?;
            let op = match expr {
                Expr::Add(..) => Op::Add,
                Expr::Sub(..) => Op::Sub,
                Expr::Mul(..) => Op::Mul,
                Expr::Div(..) => Op::Div,
                _ => Op::Pow,
            };
            put(ops, len, op)?;
            da.max(db + 1)
        }
        Expr::Call2(f, ..) => {
            let name = format!("{f:?}").to_lowercase();
            return Err(format!("`{name}` has no second derivatives everywhere, which a road needs"));
        }
        _ => {
            return Err("a road's height uses numbers, x, z, + - * / ^ and functions of one argument (sin, exp, ...); \
                        not time, der, comparisons or if"
                .into())
        }
    })
}

fn put(ops: &mut [Op; MAX_OPS], len: &mut usize, op: Op) -> Result<(), String> {
    if *len == MAX_OPS {
        return Err(format!("the road's formula is too long: at most {MAX_OPS} numbers, names and operations"));
    }
    ops[*len] = op;
    *len += 1;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
        for _ in 0..40 {
            e = e + 1.0;
        }
        assert!(Surface::new(&e).unwrap_err().contains("too long"));
    }
}
