//! Per-node [`Choice`]s: which argument a node reduces to inside the box.
//!
//! [`simplify`](crate::simplify::simplify) uses them to shorten the tape.
//! A choice is `exact` when the pick holds at every point of the box.

use super::arith::*;
use crate::graph::{Node, NodeId};
use crate::ops::{BinaryOp, UnaryOp, EPS};

/// Which argument a node reduces to inside the box.
///
/// For `min`, `max`, `and`, `or`: `Left` is the first argument, `Right` the
/// second; for `select`: `Left` is the then-branch, `Right` the else-branch;
/// for the R-functions (sign sense only): the argument that keeps the sign;
/// for `Check(g, v)`: always `Right` (`v`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Pick {
    /// Not decided: keep the node.
    #[default]
    Both,
    /// The node reduces to its first value argument.
    Left,
    /// The node reduces to its second value argument.
    Right,
    /// The node is the constant 0 throughout (boolean operations).
    False,
    /// The node is the constant 1 throughout (boolean operations).
    True,
}

/// The sign of a node over the box, when decided.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Decided {
    /// Both signs, zero or NaN are possible.
    #[default]
    No,
    /// Strictly positive, never NaN, and at most 1e150 (so that a parent
    /// R-function cannot overflow when the node is replaced by 1).
    Positive,
    /// Strictly negative, never NaN, and at least -1e150.
    Negative,
}

/// What the interval evaluation learned about one node, for both
/// simplification modes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Choice {
    /// The reduction that keeps the value bit for bit.
    pub exact: Pick,
    /// The reduction that keeps the sign (and NaN-ness) when the node is
    /// used only for its sign; at least as strong as `exact`.
    pub sign: Pick,
    /// The node's sign over the box.
    pub decided: Decided,
}

/// Whether a node's values are exactly 0.0 or 1.0.
pub(crate) fn is_bool_node(n: &Node) -> bool {
    matches!(
        n,
        Node::Unary(UnaryOp::Not, _)
            | Node::Binary(
                BinaryOp::Lt
                    | BinaryOp::Gt
                    | BinaryOp::Le
                    | BinaryOp::Ge
                    | BinaryOp::Eq
                    | BinaryOp::Ne
                    | BinaryOp::And
                    | BinaryOp::Or,
                _,
                _
            )
    )
}

fn all_truthy(a: Interval) -> bool {
    !a.nan && !a.is_empty() && (a.lo >= EPS || a.hi <= -EPS)
}

/// `select(c, t, e)`: the branches `c` may choose.
pub(super) fn select_iv(c: Interval, t: Interval, e: Interval) -> Interval {
    let mut r = none(false);
    if c.may_truthy() {
        r = r.hull(t);
    }
    if c.may_falsy() {
        r = r.hull(e);
    }
    r
}

/// Whether [`choice_of`] can give node `n` an `exact` pick other than
/// [`Pick::Both`]: the nodes that pick an argument or a branch (`min`,
/// `max`, the R-functions, `select`, `Check`) and the booleans (a constant
/// once decided). Kept beside [`choice_of`] and [`binary_picks`], which it
/// must follow.
pub(crate) fn can_choose(n: &Node) -> bool {
    is_bool_node(n)
        || matches!(
            n,
            Node::Binary(
                BinaryOp::Min
                    | BinaryOp::Max
                    | BinaryOp::RUnion
                    | BinaryOp::RInter
                    | BinaryOp::RDiff,
                ..
            ) | Node::Select(..)
                | Node::Check(..)
        )
}

/// The [`Choice`] of node `i`, from the intervals of an evaluation
/// (`v(k)`: node `k`'s).
#[inline]
pub(super) fn choice_of(nodes: &[Node], v: impl Fn(usize) -> Interval, i: usize) -> Choice {
    let node = &nodes[i];
    let r = v(i);
    let g = |id: NodeId| v(id.index());
    let mut exact = Pick::Both;
    let mut sign = Pick::Both;
    match *node {
        Node::Binary(op, a, b) => {
            (exact, sign) = binary_picks(op, g(a), g(b), nodes, a, b);
        }
        Node::Select(c, _, _) => {
            let ic = g(c);
            if !ic.may_falsy() {
                exact = Pick::Left;
            } else if !ic.may_truthy() {
                exact = Pick::Right;
            }
        }
        Node::Check(..) => exact = Pick::Right,
        _ => {}
    }
    if sign == Pick::Both {
        sign = exact;
    }
    let decided = decided_of(r);
    if is_bool_node(node) && !r.nan && r.lo == r.hi {
        exact = if r.lo == 0.0 { Pick::False } else { Pick::True };
        sign = exact;
    }
    Choice {
        exact,
        sign,
        decided,
    }
}

/// The [`Choice::decided`] of a node of interval `r`.
#[inline]
pub(super) fn decided_of(r: Interval) -> Decided {
    // Only moderate values may become ±1: a huge or infinite one
    // overflows the squares of an R-function parent.
    if r.is_positive() && r.tame() {
        Decided::Positive
    } else if r.is_negative() && r.tame() {
        Decided::Negative
    } else {
        Decided::No
    }
}

/// The exact and sign picks of a binary node.
fn binary_picks(
    op: BinaryOp,
    a: Interval,
    b: Interval,
    nodes: &[Node],
    ia: NodeId,
    ib: NodeId,
) -> (Pick, Pick) {
    let ne = !a.is_empty() && !b.is_empty();
    let clean = !a.nan && !b.nan && ne;
    let mut exact = Pick::Both;
    let mut sign = Pick::Both;
    match op {
        BinaryOp::Min => {
            if clean && a.hi < b.lo {
                exact = Pick::Left;
            } else if !ne || a.lo >= b.hi {
                exact = Pick::Right;
            } else if a.tame() && b.tame() && b.lo > 0.0 {
                sign = Pick::Left;
            } else if a.tame() && b.tame() && a.lo > 0.0 {
                sign = Pick::Right;
            }
        }
        BinaryOp::Max => {
            if clean && a.lo > b.hi {
                exact = Pick::Left;
            } else if !ne || a.hi <= b.lo {
                exact = Pick::Right;
            } else if a.tame() && b.tame() && b.hi < 0.0 {
                sign = Pick::Left;
            } else if a.tame() && b.tame() && a.hi < 0.0 {
                sign = Pick::Right;
            }
        }
        BinaryOp::RUnion | BinaryOp::RInter | BinaryOp::RDiff => {
            // In exact arithmetic sign(a | b) = sign(max(a, b)),
            // sign(a & b) = sign(min(a, b)) and sign(a \ b) = sign(min(a, -b)).
            // Where the dropped argument has a fixed sign, the other one
            // decides. At its zero the gradient is its own (see the simplify
            // module).
            let (ta, tb) = (a.tame(), b.tame());
            // The kept argument may be NaN, but not too large (its square).
            let a_ok = a.lo.abs().max(a.hi.abs()) <= SQUARE_SAFE;
            let b_ok = b.lo.abs().max(b.hi.abs()) <= SQUARE_SAFE;
            match op {
                BinaryOp::RUnion if tb && a_ok && b.hi < 0.0 => sign = Pick::Left,
                BinaryOp::RUnion if ta && b_ok && a.hi < 0.0 => sign = Pick::Right,
                BinaryOp::RInter if tb && a_ok && b.lo > 0.0 => sign = Pick::Left,
                BinaryOp::RInter if ta && b_ok && a.lo > 0.0 => sign = Pick::Right,
                BinaryOp::RDiff if tb && a_ok && b.hi < 0.0 => sign = Pick::Left,
                _ => {}
            }
        }
        BinaryOp::And => {
            if all_truthy(a) && is_bool_node(&nodes[ib.index()]) {
                exact = Pick::Right;
            } else if all_truthy(b) && is_bool_node(&nodes[ia.index()]) {
                exact = Pick::Left;
            }
        }
        BinaryOp::Or => {
            if !a.may_truthy() && is_bool_node(&nodes[ib.index()]) {
                exact = Pick::Right;
            } else if !b.may_truthy() && is_bool_node(&nodes[ia.index()]) {
                exact = Pick::Left;
            }
        }
        _ => {}
    }
    (exact, sign)
}
