//! Formulas of time (what a model's `x.u = sin(2*time)` gives a signal
//! input), evaluated with their first two derivatives, which prescribed
//! motion needs.
//!
//! A formula is compiled into a postfix program over jets `[f, f', f'']`;
//! evaluating it allocates nothing.

/// A formula of time: plain data.
#[derive(Clone, Debug, PartialEq)]
pub enum TimeExpr {
    Time,
    Const(f64),
    Neg(Box<TimeExpr>),
    Add(Box<TimeExpr>, Box<TimeExpr>),
    Sub(Box<TimeExpr>, Box<TimeExpr>),
    Mul(Box<TimeExpr>, Box<TimeExpr>),
    Div(Box<TimeExpr>, Box<TimeExpr>),
    Pow(Box<TimeExpr>, Box<TimeExpr>),
    Call(Func, Box<TimeExpr>),
}

/// The functions of one argument a formula may call.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Exp,
    Log,
    Sqrt,
    Abs,
    Asin,
    Acos,
    Atan,
    Sinh,
    Cosh,
    Tanh,
}

impl Func {
    /// The function called `name` in a model file.
    pub fn from_name(name: &str) -> Option<Func> {
        Some(match name {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "exp" => Func::Exp,
            "log" => Func::Log,
            "sqrt" => Func::Sqrt,
            "abs" => Func::Abs,
            "asin" => Func::Asin,
            "acos" => Func::Acos,
            "atan" => Func::Atan,
            "sinh" => Func::Sinh,
            "cosh" => Func::Cosh,
            "tanh" => Func::Tanh,
            _ => return None,
        })
    }

    /// `f(x), f'(x), f''(x)`.
    pub(crate) fn derivatives(self, x: f64) -> [f64; 3] {
        match self {
            Func::Sin => [x.sin(), x.cos(), -x.sin()],
            Func::Cos => [x.cos(), -x.sin(), -x.cos()],
            Func::Tan => {
                let t = x.tan();
                let d = 1.0 + t * t;
                [t, d, 2.0 * t * d]
            }
            Func::Exp => [x.exp(); 3],
            Func::Log => [x.ln(), 1.0 / x, -1.0 / (x * x)],
            Func::Sqrt => {
                let s = x.sqrt();
                [s, 0.5 / s, -0.25 / (s * x)]
            }
            Func::Abs => [x.abs(), x.signum(), 0.0],
            Func::Asin => {
                let r = 1.0 - x * x;
                [x.asin(), 1.0 / r.sqrt(), x / (r * r.sqrt())]
            }
            Func::Acos => {
                let r = 1.0 - x * x;
                [x.acos(), -1.0 / r.sqrt(), -x / (r * r.sqrt())]
            }
            Func::Atan => {
                let r = 1.0 + x * x;
                [x.atan(), 1.0 / r, -2.0 * x / (r * r)]
            }
            Func::Sinh => [x.sinh(), x.cosh(), x.sinh()],
            Func::Cosh => [x.cosh(), x.sinh(), x.cosh()],
            Func::Tanh => {
                let t = x.tanh();
                let d = 1.0 - t * t;
                [t, d, -2.0 * t * d]
            }
        }
    }
}

/// One instruction of a compiled formula.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Op {
    Time,
    Const(f64),
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Call(Func),
}

/// A formula compiled for evaluation, with the stack depth it needs.
#[derive(Clone, Debug, PartialEq)]
pub struct TimeFunction {
    ops: Vec<Op>,
    depth: usize,
}

/// Formulas deeper than this are refused (they would need a larger stack).
pub const MAX_DEPTH: usize = 32;

type Jet = [f64; 3];

impl TimeFunction {
    /// Compiles `expr`, or says it nests too deeply.
    pub fn new(expr: &TimeExpr) -> Result<Self, String> {
        let mut ops = Vec::new();
        let depth = compile(expr, &mut ops);
        if depth > MAX_DEPTH {
            return Err(format!("the formula nests {depth} levels deep; at most {MAX_DEPTH} are supported"));
        }
        Ok(Self { ops, depth })
    }

    /// The value and its first two time derivatives at `t`.
    pub fn jet(&self, t: f64) -> [f64; 3] {
        let mut stack = [[0.0; 3]; MAX_DEPTH];
        let mut n = 0;
        for op in &self.ops {
            let jet = match *op {
                Op::Time => [t, 1.0, 0.0],
                Op::Const(c) => [c, 0.0, 0.0],
                Op::Neg => {
                    n -= 1;
                    stack[n].map(|x| -x)
                }
                Op::Call(f) => {
                    n -= 1;
                    let [u, u1, u2] = stack[n];
                    let [g, g1, g2] = f.derivatives(u);
                    [g, g1 * u1, g2 * u1 * u1 + g1 * u2]
                }
                binary => {
                    n -= 2;
                    binary_jet(binary, stack[n], stack[n + 1])
                }
            };
            stack[n] = jet;
            n += 1;
        }
        debug_assert!(n == 1 && self.depth <= MAX_DEPTH);
        stack[0]
    }

    /// The value at `t`.
    pub fn value(&self, t: f64) -> f64 {
        self.jet(t)[0]
    }
}

/// Postfix code of `expr` into `ops`; returns the stack depth it needs.
fn compile(expr: &TimeExpr, ops: &mut Vec<Op>) -> usize {
    let binary = |a: &TimeExpr, b: &TimeExpr, op: Op, ops: &mut Vec<Op>| {
        let da = compile(a, ops);
        let db = compile(b, ops);
        ops.push(op);
        da.max(db + 1)
    };
    match expr {
        TimeExpr::Time => {
            ops.push(Op::Time);
            1
        }
        TimeExpr::Const(c) => {
            ops.push(Op::Const(*c));
            1
        }
        TimeExpr::Neg(a) => {
            let d = compile(a, ops);
            ops.push(Op::Neg);
            d
        }
        TimeExpr::Call(f, a) => {
            let d = compile(a, ops);
            ops.push(Op::Call(*f));
            d
        }
        TimeExpr::Add(a, b) => binary(a, b, Op::Add, ops),
        TimeExpr::Sub(a, b) => binary(a, b, Op::Sub, ops),
        TimeExpr::Mul(a, b) => binary(a, b, Op::Mul, ops),
        TimeExpr::Div(a, b) => binary(a, b, Op::Div, ops),
        TimeExpr::Pow(a, b) => binary(a, b, Op::Pow, ops),
    }
}

/// The jet of `a op b`.
fn binary_jet(op: Op, a: Jet, b: Jet) -> Jet {
    match op {
        Op::Add => [a[0] + b[0], a[1] + b[1], a[2] + b[2]],
        Op::Sub => [a[0] - b[0], a[1] - b[1], a[2] - b[2]],
        Op::Mul => [a[0] * b[0], a[1] * b[0] + a[0] * b[1], a[2] * b[0] + 2.0 * a[1] * b[1] + a[0] * b[2]],
        Op::Div => {
            let y = a[0] / b[0];
            let y1 = (a[1] - y * b[1]) / b[0];
            [y, y1, (a[2] - 2.0 * y1 * b[1] - y * b[2]) / b[0]]
        }
        Op::Pow if b[1] == 0.0 && b[2] == 0.0 => {
            // A constant exponent: defined for negative bases too.
            let p = b[0];
            let y = a[0].powf(p);
            let d1 = if p == 0.0 { 0.0 } else { p * a[0].powf(p - 1.0) };
            let d2 = if p == 0.0 || p == 1.0 { 0.0 } else { p * (p - 1.0) * a[0].powf(p - 2.0) };
            [y, d1 * a[1], d2 * a[1] * a[1] + d1 * a[2]]
        }
        Op::Pow => {
            // a^b = exp(b ln a).
            let [l, l1, l2] = Func::Log.derivatives(a[0]);
            let ln = [l, l1 * a[1], l2 * a[1] * a[1] + l1 * a[2]];
            let e = binary_jet(Op::Mul, b, ln);
            let y = e[0].exp();
            [y, y * e[1], y * (e[2] + e[1] * e[1])]
        }
        _ => unreachable!("not a binary operation"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(e: TimeExpr) -> Box<TimeExpr> {
        Box::new(e)
    }

    #[test]
    fn jets_are_the_derivatives_of_the_formula() {
        use TimeExpr::*;
        // 2 sin(3 t) + t^2 / (1 + t) - exp(-t) cos(t) + t^1.5 + (1 + t)^t
        let formula = Add(
            b(Add(
                b(Sub(
                    b(Add(
                        b(Mul(b(Const(2.0)), b(Call(Func::Sin, b(Mul(b(Const(3.0)), b(Time))))))),
                        b(Div(b(Pow(b(Time), b(Const(2.0)))), b(Add(b(Const(1.0)), b(Time))))),
                    )),
                    b(Mul(b(Call(Func::Exp, b(Neg(b(Time))))), b(Call(Func::Cos, b(Time))))),
                )),
                b(Pow(b(Time), b(Const(1.5)))),
            )),
            b(Pow(b(Add(b(Const(1.0)), b(Time))), b(Time))),
        );
        let f = TimeFunction::new(&formula).unwrap();
        let exact =
            |t: f64| 2.0 * (3.0 * t).sin() + t * t / (1.0 + t) - (-t).exp() * t.cos() + t.powf(1.5) + (1.0 + t).powf(t);
        // Central differences of step 1e-4: truncation ~1e-8 |f'''|, rounding ~1e-16/h^2.
        let h = 1e-4;
        for t in [0.3, 1.1, 2.7] {
            let [y, d1, d2] = f.jet(t);
            assert!((y - exact(t)).abs() < 1e-13);
            let fd1 = (exact(t + h) - exact(t - h)) / (2.0 * h);
            let fd2 = (exact(t + h) - 2.0 * exact(t) + exact(t - h)) / (h * h);
            assert!((d1 - fd1).abs() < 1e-6, "t = {t}: {d1} vs {fd1}");
            assert!((d2 - fd2).abs() < 1e-5, "t = {t}: {d2} vs {fd2}");
        }
    }

    #[test]
    fn every_function_differentiates_correctly() {
        let h = 1e-5;
        for name in ["sin", "cos", "tan", "exp", "log", "sqrt", "abs", "asin", "acos", "atan", "sinh", "cosh", "tanh"] {
            let f = Func::from_name(name).unwrap();
            for x in [0.3, 0.7] {
                let value = |x: f64| f.derivatives(x)[0];
                let [_, d1, d2] = f.derivatives(x);
                let fd1 = (value(x + h) - value(x - h)) / (2.0 * h);
                let fd2 = (f.derivatives(x + h)[1] - f.derivatives(x - h)[1]) / (2.0 * h);
                // Truncation h^2 |f''''| / 6 reaches 1e-8 for log at 0.3.
                let close = |a: f64, b: f64| (a - b).abs() < 1e-7 * (1.0 + a.abs());
                assert!(close(d1, fd1) && close(d2, fd2), "{name} at {x}: {d1} {fd1}, {d2} {fd2}");
            }
        }
    }
}
