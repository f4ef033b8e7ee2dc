//! The scalar reference walk: the bulk evaluators' semantics in plain code.
//!
//! - Every node of the tape in order, one `match` per node per point.
//! - Runtime errors become NaN and `Check` guards are ignored: the guarded
//!   value is the value. This is what the batch, interval and gradient
//!   evaluators compute.
//! - The unary and binary kernels are parameters. With [`exact_unary`] and
//!   [`exact_binary`] it is an oracle independent of every evaluator; with
//!   the batch lane functions it predicts their bits.
//!
//! It is slow on purpose. Tests of every backend compare against it, and
//! [`ulps`] measures how far they land.

use super::Inputs;
use crate::graph::{Node, NodeId, Tape};
use crate::ops::{self, BinaryOp, UnaryOp};

/// Walks `tape` at `p` into `v` (cleared first: one value per node) with
/// the given unary and binary kernels.
pub fn walk_into(
    tape: &Tape,
    p: [f64; 3],
    inputs: &Inputs,
    un: impl Fn(UnaryOp, f64) -> f64,
    bin: impl Fn(BinaryOp, f64, f64) -> f64,
    v: &mut Vec<f64>,
) {
    v.clear();
    v.reserve(tape.nodes.len());
    for node in &tape.nodes {
        let g = |id: NodeId| v[id.index()];
        let r = match *node {
            Node::Const(b) => f64::from_bits(b),
            Node::X(i) if i < 3 => p[i as usize],
            Node::X(i) => inputs.extra_x(i),
            Node::Param(i) => inputs.param(i),
            Node::Error(_) => f64::NAN,
            Node::Unary(op, a) => un(op, g(a)),
            Node::Binary(op, a, b) => bin(op, g(a), g(b)),
            Node::PowI(b, n) => ops::pow_int(g(b), n).unwrap_or(f64::NAN),
            Node::Select(c, t, e) => {
                if ops::truthy(g(c)) {
                    g(t)
                } else {
                    g(e)
                }
            }
            Node::Blend(op, a) => ops::blend(op, g(a[0]), g(a[1]), g(a[2]), g(a[3]), g(a[4])),
            Node::Check(_, b) => g(b),
        };
        v.push(r);
    }
}

/// Every node's value at `p` with the exact kernels of [`ops`].
pub fn eval_all(tape: &Tape, p: [f64; 3], inputs: &Inputs) -> Vec<f64> {
    let mut v = Vec::new();
    walk_into(tape, p, inputs, exact_unary, exact_binary, &mut v);
    v
}

/// [`ops::unary`] with errors as NaN.
pub fn exact_unary(op: UnaryOp, a: f64) -> f64 {
    ops::unary(op, a).unwrap_or(f64::NAN)
}

/// [`ops::binary`] with errors as NaN.
pub fn exact_binary(op: BinaryOp, a: f64, b: f64) -> f64 {
    ops::binary(op, a, b).unwrap_or(f64::NAN)
}

/// The distance between `a` and `b` in units in the last place.
///
/// Two NaNs, and two equal values (infinities included), are 0 apart. A
/// NaN against a number, or an infinity against anything else, is
/// `u64::MAX` apart. The two signed zeros are one point.
pub fn ulps(a: f64, b: f64) -> u64 {
    if (a.is_nan() && b.is_nan()) || a == b {
        return 0;
    }
    if a.is_nan() || b.is_nan() || a.is_infinite() || b.is_infinite() {
        return u64::MAX;
    }
    // Map the bits onto one monotone integer line: negative numbers count
    // down from zero.
    let key = |v: f64| {
        let i = v.to_bits() as i64;
        if i < 0 {
            i64::MIN - i
        } else {
            i
        }
    };
    key(a).abs_diff(key(b))
}

#[cfg(test)]
mod tests {
    use super::ulps;

    #[test]
    fn ulp_distances() {
        assert_eq!(ulps(1.0, 1.0), 0);
        assert_eq!(ulps(f64::NAN, f64::NAN), 0);
        assert_eq!(ulps(f64::INFINITY, f64::INFINITY), 0);
        assert_eq!(ulps(1.0, f64::from_bits(1.0f64.to_bits() + 3)), 3);
        assert_eq!(ulps(-0.0, 0.0), 0);
        assert_eq!(ulps(-f64::from_bits(1), f64::from_bits(1)), 2);
        assert_eq!(ulps(1.0, f64::NAN), u64::MAX);
        assert_eq!(ulps(1.0, f64::INFINITY), u64::MAX);
    }
}
