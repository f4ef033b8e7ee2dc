//! Building blocks of the library port: IEEE graph arithmetic and argument
//! checks.
//!
//! - [`C`] wraps the graph with short names for the C code's operators.
//! - The argument helpers turn a wrong kind or a short array into a
//!   [`LibError`] naming the argument.

use super::{LibArg, LibError, SENTINEL};
use crate::graph::{Graph, NodeId};
use crate::ops::{BinaryOp, UnaryOp, EPS};

/// Shorthands for IEEE graph arithmetic.
pub(super) struct C<'g> {
    pub(super) g: &'g mut Graph,
}

impl C<'_> {
    pub(super) fn k(&mut self, v: f64) -> NodeId {
        self.g.constant(v)
    }
    pub(super) fn bin(&mut self, op: BinaryOp, a: NodeId, b: NodeId) -> NodeId {
        self.g.binary(op, a, b)
    }
    pub(super) fn add(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Add, a, b)
    }
    pub(super) fn sub(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Sub, a, b)
    }
    pub(super) fn mul(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Mul, a, b)
    }
    pub(super) fn div(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::DivF, a, b)
    }
    pub(super) fn pow(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::PowF, a, b)
    }
    /// `a * a`, as the C code's `SQ(a)` / `a*a`.
    pub(super) fn sq(&mut self, a: NodeId) -> NodeId {
        self.mul(a, a)
    }
    /// `k + a` with a constant `k`.
    pub(super) fn kadd(&mut self, k: f64, a: NodeId) -> NodeId {
        let k = self.k(k);
        self.add(k, a)
    }
    /// `k - a` with a constant `k`.
    pub(super) fn ksub(&mut self, k: f64, a: NodeId) -> NodeId {
        let k = self.k(k);
        self.sub(k, a)
    }
    /// `k * a` with a constant `k`.
    pub(super) fn kmul(&mut self, k: f64, a: NodeId) -> NodeId {
        let k = self.k(k);
        self.mul(k, a)
    }
    fn un(&mut self, op: UnaryOp, a: NodeId) -> NodeId {
        self.g.unary(op, a)
    }
    pub(super) fn neg(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Neg, a)
    }
    pub(super) fn abs(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Abs, a)
    }
    pub(super) fn sqrt(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::SqrtF, a)
    }
    pub(super) fn sin(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Sin, a)
    }
    pub(super) fn cos(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Cos, a)
    }
    pub(super) fn exp(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Exp, a)
    }
    pub(super) fn atan(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Atan, a)
    }
    /// C `log`: `ln` for positive arguments, `-inf` at 0, NaN below or NaN.
    pub(super) fn log(&mut self, a: NodeId) -> NodeId {
        let z = self.k(0.0);
        let pos = self.bin(BinaryOp::Gt, a, z);
        let zero = self.bin(BinaryOp::Ge, a, z);
        let ln = self.un(UnaryOp::Log, a);
        let ninf = self.k(f64::NEG_INFINITY);
        let nan = self.k(f64::NAN);
        let rest = self.g.select(zero, ninf, nan);
        self.g.select(pos, ln, rest)
    }
    /// C `tan`: libm's where the checked `tan` accepts the argument, `sin/cos`
    /// where `|cos| < 1e-6`.
    pub(super) fn tan(&mut self, a: NodeId) -> NodeId {
        let c = self.cos(a);
        let ac = self.abs(c);
        let eps = self.k(EPS);
        let ok = self.bin(BinaryOp::Ge, ac, eps);
        let t = self.un(UnaryOp::Tan, a);
        let s = self.sin(a);
        let q = self.div(s, c);
        self.g.select(ok, t, q)
    }
    /// `archyp.h`'s `atanh(z) = log((1+z)*sqrt(1/(1-(z*z))))`.
    pub(super) fn atanh(&mut self, z: NodeId) -> NodeId {
        let opz = self.kadd(1.0, z);
        let zz = self.sq(z);
        let omz = self.ksub(1.0, zz);
        let one = self.k(1.0);
        let inv = self.div(one, omz);
        let r = self.sqrt(inv);
        let p = self.mul(opz, r);
        self.log(p)
    }
    pub(super) fn lt(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Lt, a, b)
    }
    pub(super) fn le(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Le, a, b)
    }
    pub(super) fn gt(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Gt, a, b)
    }
    pub(super) fn ge(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Ge, a, b)
    }
    pub(super) fn or(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Or, a, b)
    }
    pub(super) fn and(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::And, a, b)
    }
    pub(super) fn sel(&mut self, c: NodeId, t: NodeId, e: NodeId) -> NodeId {
        self.g.select(c, t, e)
    }
    /// `|a| < EPS`, as 1/0.
    pub(super) fn tiny(&mut self, a: NodeId) -> NodeId {
        let aa = self.abs(a);
        let eps = self.k(EPS);
        self.lt(aa, eps)
    }
    /// `cond ? SENTINEL : f` for a list of conditions or'ed together.
    pub(super) fn sentinel_if(&mut self, conds: &[NodeId], f: NodeId) -> NodeId {
        let mut c = conds[0];
        for &d in &conds[1..] {
            c = self.or(c, d);
        }
        let s = self.k(SENTINEL);
        self.sel(c, s, f)
    }
}

pub(super) fn err(arg: usize, message: String) -> LibError {
    LibError { arg, message }
}

pub(super) fn scalar(args: &[LibArg], i: usize) -> Result<NodeId, LibError> {
    match &args[i] {
        LibArg::Scalar(n) => Ok(*n),
        LibArg::Array(_) => Err(err(i, "expected a number, found an array".into())),
    }
}

pub(super) fn array(args: &[LibArg], i: usize) -> Result<Vec<NodeId>, LibError> {
    match &args[i] {
        LibArg::Array(v) => Ok(v.clone()),
        LibArg::Scalar(_) => Err(err(i, "expected an array, found a number".into())),
    }
}

/// The array argument `i`, which must have at least `n` items.
pub(super) fn array_min(
    args: &[LibArg],
    i: usize,
    n: usize,
    func: &str,
    what: &str,
) -> Result<Vec<NodeId>, LibError> {
    let v = array(args, i)?;
    if v.len() < n {
        return Err(err(
            i,
            format!(
                "{func}: array `{what}` has {} items, at least {n} are needed",
                v.len()
            ),
        ));
    }
    Ok(v)
}

pub(super) fn set_array(args: &mut [LibArg], i: usize, v: Vec<NodeId>) {
    args[i] = LibArg::Array(v);
}

/// The point argument (0) if it has exactly 3 items.
pub(super) fn point(args: &[LibArg]) -> Result<Option<[NodeId; 3]>, LibError> {
    let x = array(args, 0)?;
    Ok(if x.len() == 3 {
        Some([x[0], x[1], x[2]])
    } else {
        None
    })
}

/// `x - centre` of a centred primitive (`x` argument 0, centre argument 1),
/// or `None` when `x` has not 3 items (the sentinel case).
pub(super) fn centred(
    args: &[LibArg],
    c: &mut C,
    func: &str,
) -> Result<Option<[NodeId; 3]>, LibError> {
    let centre = array_min(args, 1, 3, func, "center")?;
    let Some(x) = point(args)? else {
        return Ok(None);
    };
    Ok(Some([
        c.sub(x[0], centre[0]),
        c.sub(x[1], centre[1]),
        c.sub(x[2], centre[2]),
    ]))
}

macro_rules! centred_or_sentinel {
    ($args:expr, $c:expr, $func:expr) => {
        match centred($args, &mut $c, $func)? {
            Some(d) => d,
            None => return Ok($c.k(SENTINEL)),
        }
    };
}

pub(super) use centred_or_sentinel;

/// `xt*xt + yt*yt + zt*zt`
pub(super) fn norm2(c: &mut C, d: [NodeId; 3]) -> NodeId {
    let a = c.sq(d[0]);
    let b = c.sq(d[1]);
    let s = c.add(a, b);
    let z = c.sq(d[2]);
    c.add(s, z)
}

pub(super) fn triple(v: &[NodeId], at: usize) -> [NodeId; 3] {
    [v[at], v[at + 1], v[at + 2]]
}
