//! The scalar reference walk of a tape: every node in order, one `match` per
//! node per point, errors as NaN, guards ignored (the value is the checked
//! value). An oracle independent of every evaluator in `src/eval`.

use frep_core::eval::Inputs;
use frep_core::ops::{self, BinaryOp, UnaryOp};
use frep_core::{Node, NodeId, Tape};

/// Walks `tape` at `p` into `v` (cleared first: one value per node) with the
/// given unary and binary kernels.
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

/// The exact scalar kernels of [`ops`] with errors as NaN.
pub fn exact_unary(op: UnaryOp, a: f64) -> f64 {
    ops::unary(op, a).unwrap_or(f64::NAN)
}

/// See [`exact_unary`].
pub fn exact_binary(op: BinaryOp, a: f64, b: f64) -> f64 {
    ops::binary(op, a, b).unwrap_or(f64::NAN)
}
