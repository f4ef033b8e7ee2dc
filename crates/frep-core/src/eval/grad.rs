//! Forward-mode automatic differentiation: the value and the gradient
//! `(∂/∂x, ∂/∂y, ∂/∂z)` of output 0.
//!
//! Values are computed exactly as [`ops`] computes them (with `std`'s
//! functions), runtime errors giving NaN (value and derivatives), and the
//! guard of a [`Node::Check`] ignored, as in every bulk evaluator.
//!
//! ## Derivative conventions
//! * Piecewise-constant operations (comparisons, `and`, `or`, `not`, `ceil`,
//!   `floor`, `int`, `round`, `mod`) have derivative 0; `frac` has the
//!   derivative of its argument.
//! * `min`, `max` and selects take the derivative of the argument or branch
//!   they pick (a select picks by [`ops::truthy`]); `abs` the sign of its
//!   argument, +1 at 0.
//! * R-functions: `d(a + b ± √(a²+b²)) = da + db ± (a·da + b·db)/√(a²+b²)`;
//!   at `a = b = 0` the last term is taken as 0 (so `∂/∂a = 1`).
//!   R-difference `a - b - √(a²+b²)` likewise. Blends add the derivative of
//!   `a0 / (1 + (f1/a1)² + (f2/a2)²)`, with the same convention at 0.
//! * Checked operations differentiate as their mathematical function
//!   (`sqrt`: `1/(2√a)`, infinite at 0).
//! * `b ^ n` with a constant integer `n` ([`Node::PowI`]): the value is the
//!   reference's repeated product, the derivative `n·b^(n-1)·db`.
//! * `b ^ e` and `pow(b, e)`: `e·b^(e-1)·db + ln(b)·b^e·de`; the second term
//!   is dropped where `de = 0`, so a negative base with a constant exponent
//!   stays finite. HyperFun's `^` with an exponent within 1e-6 above an
//!   integer uses that integer, as its value does.

use super::Inputs;
use crate::graph::{Node, Tape};
use crate::ops::{self, BinaryOp, BlendOp, UnaryOp};

/// A value and its gradient.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Grad {
    /// The value.
    pub v: f64,
    /// ∂v/∂x.
    pub dx: f64,
    /// ∂v/∂y.
    pub dy: f64,
    /// ∂v/∂z.
    pub dz: f64,
}

impl Grad {
    const NAN: Grad = Grad {
        v: f64::NAN,
        dx: f64::NAN,
        dy: f64::NAN,
        dz: f64::NAN,
    };

    fn constant(v: f64) -> Grad {
        Grad {
            v,
            dx: 0.0,
            dy: 0.0,
            dz: 0.0,
        }
    }

    /// `k·d` with value `v`.
    #[inline]
    fn chain(v: f64, k: f64, d: Grad) -> Grad {
        Grad {
            v,
            dx: k * d.dx,
            dy: k * d.dy,
            dz: k * d.dz,
        }
    }

    /// `ka·a' + kb·b'` with value `v`.
    #[inline]
    fn chain2(v: f64, ka: f64, a: Grad, kb: f64, b: Grad) -> Grad {
        Grad {
            v,
            dx: ka * a.dx + kb * b.dx,
            dy: ka * a.dy + kb * b.dy,
            dz: ka * a.dz + kb * b.dz,
        }
    }

    fn with_v(self, v: f64) -> Grad {
        Grad { v, ..self }
    }

    fn has_derivative(&self) -> bool {
        self.dx != 0.0 || self.dy != 0.0 || self.dz != 0.0
    }

    /// The gradient `(dx, dy, dz)`.
    pub fn gradient(&self) -> [f64; 3] {
        [self.dx, self.dy, self.dz]
    }
}

/// Evaluates the value and gradient of a [`Tape`]'s output 0.
#[derive(Clone, Debug)]
pub struct GradEval {
    tape: Tape,
    vals: Vec<Grad>,
}

impl GradEval {
    /// Prepares an evaluator for the tape.
    pub fn new(tape: &Tape) -> Self {
        GradEval {
            tape: tape.clone(),
            vals: vec![Grad::default(); tape.nodes.len()],
        }
    }

    /// The value and gradient of output 0 at `(x, y, z)` (NaN where the tape
    /// has no output).
    pub fn eval(&mut self, x: f64, y: f64, z: f64, inputs: &Inputs) -> Grad {
        let Some(&out) = self.tape.outputs.first() else {
            return Grad::NAN;
        };
        for i in 0..self.tape.nodes.len() {
            let g = node_grad(&self.tape.nodes[i], &self.vals, [x, y, z], inputs);
            self.vals[i] = g;
        }
        self.vals[out.index()]
    }

    /// [`GradEval::eval`] at every point `(xs[i], ys[i], zs[i])`.
    ///
    /// # Panics
    /// If the four slices differ in length.
    pub fn eval_batch(
        &mut self,
        xs: &[f64],
        ys: &[f64],
        zs: &[f64],
        inputs: &Inputs,
        out: &mut [Grad],
    ) {
        assert!(
            xs.len() == out.len() && ys.len() == out.len() && zs.len() == out.len(),
            "GradEval::eval_batch: slices of different lengths"
        );
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.eval(xs[i], ys[i], zs[i], inputs);
        }
    }
}

fn res(r: Result<f64, ops::EvalError>) -> f64 {
    r.unwrap_or(f64::NAN)
}

/// Derivative of `±√(a²+b²)`'s argument-weighted term: `(a·da + b·db)/r`,
/// 0 where `r = 0`.
fn hypot_term(a: Grad, b: Grad) -> Grad {
    let r = (a.v * a.v + b.v * b.v).sqrt();
    if r == 0.0 {
        Grad::constant(r)
    } else {
        Grad::chain2(r, a.v / r, a, b.v / r, b)
    }
}

fn add(v: f64, ka: f64, a: Grad, kb: f64, b: Grad) -> Grad {
    Grad::chain2(v, ka, a, kb, b)
}

fn node_grad(node: &Node, vals: &[Grad], p: [f64; 3], inputs: &Inputs) -> Grad {
    let g = |id: crate::NodeId| vals[id.index()];
    match *node {
        Node::Const(b) => Grad::constant(f64::from_bits(b)),
        Node::X(i) if i < 3 => {
            let mut d = [0.0; 3];
            d[i as usize] = 1.0;
            Grad {
                v: p[i as usize],
                dx: d[0],
                dy: d[1],
                dz: d[2],
            }
        }
        Node::X(i) => Grad::constant(inputs.extra_x(i)),
        Node::Param(i) => Grad::constant(inputs.param(i)),
        Node::Error(_) => Grad::NAN,
        Node::Check(_, v) => g(v),
        Node::Select(c, t, e) => {
            if ops::truthy(g(c).v) {
                g(t)
            } else {
                g(e)
            }
        }
        Node::Unary(op, a) => unary(op, g(a)),
        Node::Binary(op, a, b) => binary(op, g(a), g(b)),
        Node::PowI(b, n) => {
            let b = g(b);
            let v = res(ops::pow_int(b.v, n));
            if v.is_nan() {
                return Grad::NAN;
            }
            let k = if n == 0 {
                0.0
            } else {
                f64::from(n) * b.v.powi(n - 1)
            };
            Grad::chain(v, k, b)
        }
        Node::Blend(op, args) => {
            let [f1, f2, a0, a1, a2] = args.map(g);
            let v = ops::blend(op, f1.v, f2.v, a0.v, a1.v, a2.v);
            let h = hypot_term(f1, f2);
            let s = if op == BlendOp::Union { 1.0 } else { -1.0 };
            let base = add(0.0, 1.0, f1, 1.0, f2);
            let base = add(0.0, 1.0, base, s, h);
            // q = a0 / D, D = 1 + t1² + t2², t = f / a.
            let t1 = f1.v / a1.v;
            let t2 = f2.v / a2.v;
            let dd = 1.0 + t1 * t1 + t2 * t2;
            let q = a0.v / dd;
            // dt = (df - t·da) / a
            let dt1 = add(t1, 1.0 / a1.v, f1, -t1 / a1.v, a1);
            let dt2 = add(t2, 1.0 / a2.v, f2, -t2 / a2.v, a2);
            let d_dd = add(dd, 2.0 * t1, dt1, 2.0 * t2, dt2);
            // An infinite denominator (a1 or a2 = 0) makes the term 0 near here.
            let dq = if dd.is_infinite() {
                Grad::constant(q)
            } else {
                add(q, 1.0 / dd, a0, -q / dd, d_dd)
            };
            add(v, 1.0, base, 1.0, dq)
        }
    }
}

/// The derivative factor `dv/dx` of a unary operation at `x` with value
/// `v`, `None` for a piecewise-constant one (derivative 0). The rules of
/// [`GradEval`] and of the batch evaluator's gradients.
#[inline(always)]
pub(crate) fn unary_factor(op: UnaryOp, x: f64, v: f64) -> Option<f64> {
    Some(match op {
        UnaryOp::Neg => -1.0,
        UnaryOp::Abs => {
            if x < 0.0 {
                -1.0
            } else {
                1.0
            }
        }
        UnaryOp::Sqrt | UnaryOp::SqrtF => 0.5 / v,
        UnaryOp::Exp => v,
        UnaryOp::Log => 1.0 / x,
        UnaryOp::Logd => 1.0 / (x * std::f64::consts::LN_10),
        UnaryOp::Sin => x.cos(),
        UnaryOp::Cos => -x.sin(),
        UnaryOp::Tan => 1.0 + v * v,
        UnaryOp::Asin => 1.0 / (1.0 - x * x).sqrt(),
        UnaryOp::Acos => -1.0 / (1.0 - x * x).sqrt(),
        UnaryOp::Atan => 1.0 / (1.0 + x * x),
        UnaryOp::Sinh => x.cosh(),
        UnaryOp::Cosh => x.sinh(),
        UnaryOp::Tanh => 1.0 - v * v,
        UnaryOp::Frac => 1.0,
        UnaryOp::Ceil | UnaryOp::Floor | UnaryOp::Trunc | UnaryOp::Not | UnaryOp::RoundHalfUp => {
            return None
        }
    })
}

/// The factors `(∂v/∂b, ∂v/∂e)` of `b ^ e` (`pow` with `op` `Pow`, HyperFun's
/// integer snap of the exponent) or `pow(b, e)` with value `v`; the second is
/// 0 where `e` has no derivative (`de`), so a negative base with a constant
/// exponent stays finite.
#[inline(always)]
pub(crate) fn pow_factors(op: BinaryOp, b: f64, e: f64, v: f64, de: bool) -> (f64, f64) {
    let mut e = e;
    if op == BinaryOp::Pow && e - e.floor() < ops::EPS {
        let n = ops::round_half_up(e.abs());
        e = if e < 0.0 { -n } else { n };
    }
    let kb = if e == 0.0 { 0.0 } else { e * b.powf(e - 1.0) };
    let ke = if de { v * b.ln() } else { 0.0 };
    (kb, ke)
}

/// `(sb, sh)` of an R-function written `a + sb·b + sh·√(a² + b²)`.
#[inline(always)]
pub(crate) fn r_signs(op: BinaryOp) -> (f64, f64) {
    match op {
        BinaryOp::RUnion => (1.0, 1.0),
        BinaryOp::RInter => (1.0, -1.0),
        _ => (-1.0, -1.0),
    }
}

fn unary(op: UnaryOp, a: Grad) -> Grad {
    let x = a.v;
    let v = res(ops::unary(op, x));
    if v.is_nan() {
        return Grad::NAN;
    }
    match unary_factor(op, x, v) {
        Some(k) => Grad::chain(v, k, a),
        None => Grad::constant(v),
    }
}

fn binary(op: BinaryOp, a: Grad, b: Grad) -> Grad {
    let v = res(ops::binary(op, a.v, b.v));
    if v.is_nan() {
        return Grad::NAN;
    }
    match op {
        BinaryOp::Add => add(v, 1.0, a, 1.0, b),
        BinaryOp::Sub => add(v, 1.0, a, -1.0, b),
        BinaryOp::Mul => add(v, b.v, a, a.v, b),
        BinaryOp::Div | BinaryOp::DivF => add(v, 1.0 / b.v, a, -v / b.v, b),
        BinaryOp::Pow | BinaryOp::PowF => {
            let (ka, kb) = pow_factors(op, a.v, b.v, v, b.has_derivative());
            add(v, ka, a, kb, b)
        }
        BinaryOp::Min => (if a.v < b.v { a } else { b }).with_v(v),
        BinaryOp::Max => (if a.v > b.v { a } else { b }).with_v(v),
        BinaryOp::Atan2 => {
            let r2 = a.v * a.v + b.v * b.v;
            if r2 == 0.0 {
                Grad::constant(v)
            } else {
                add(v, b.v / r2, a, -a.v / r2, b)
            }
        }
        BinaryOp::RUnion | BinaryOp::RInter | BinaryOp::RDiff => {
            let h = hypot_term(a, b);
            let (sb, sh) = r_signs(op);
            let s = add(0.0, 1.0, a, sb, b);
            add(v, 1.0, s, sh, h)
        }
        BinaryOp::Mod
        | BinaryOp::Lt
        | BinaryOp::Gt
        | BinaryOp::Le
        | BinaryOp::Ge
        | BinaryOp::Eq
        | BinaryOp::Ne
        | BinaryOp::And
        | BinaryOp::Or => Grad::constant(v),
    }
}
