//! The model graph: a hash-consed DAG of operations over the point `x[]` and
//! the parameters `a[]`, and [`Tape`], its compacted, topologically ordered
//! form that every evaluator runs.
//!
//! Nodes are created through [`Graph`]'s methods, which
//! * fold constants (an operation of constants becomes a constant, or an
//!   [`Node::Error`] where the reference interpreter would stop);
//! * apply value-exact identities (`a + 0`, `a * 1`, `--a`, ...);
//! * hash-cons: a structurally equal node is created once.
//!
//! R-functions, blends, `min` and `max` are operations of their own: they are
//! never expanded into `+`, `sqrt` and squares, so that interval evaluation
//! can bound them tightly.
//!
//! Children always have smaller ids than their parents, so a graph (and a
//! tape) is in evaluation order.
//!
//! ## Errors and evaluation order
//! The reference interpreter stops at the first runtime error, evaluating the
//! right operand of a binary operation (and the last argument of a call)
//! first. [`Node::Check`] records that order: `Check(g, v)` has the value of
//! `v`, but reports `g`'s error first. The compiler threads a chain of
//! `Check`s through the statements, so that the point evaluator reports the
//! same error as the reference even when the erroneous value is never used.
//! Bulk evaluators produce NaN for errors and ignore the guard of a `Check`.

use std::collections::HashMap;

use crate::ops::{self, BinaryOp, BlendOp, EvalError, UnaryOp};

/// Index of a node in a [`Graph`] or a [`Tape`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct NodeId(pub u32);

impl NodeId {
    /// The index as `usize`.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// One operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// A constant, stored as its bits (use [`Node::const_value`]).
    Const(u64),
    /// Coordinate `x[i + 1]` (0 = x, 1 = y, 2 = z; further slots for models
    /// that declare `x[4]` or more).
    X(u32),
    /// Parameter `a[i + 1]`.
    Param(u32),
    /// A value that is always the given runtime error.
    Error(EvalError),
    /// A one-argument operation.
    Unary(UnaryOp, NodeId),
    /// A two-argument operation `op(a, b)`.
    Binary(BinaryOp, NodeId, NodeId),
    /// HyperFun's `b ^ n` for a constant integer `n` ([`ops::pow_int`]).
    PowI(NodeId, i32),
    /// `if truthy(c) then t else e` — only the chosen branch's error counts.
    Select(NodeId, NodeId, NodeId),
    /// `hfBlendUni` / `hfBlendInt` of `(f1, f2, a0, a1, a2)`.
    Blend(BlendOp, [NodeId; 5]),
    /// The value of `v` (second); the error of `g` (first) is reported before
    /// `v`'s. Bulk evaluators ignore `g`.
    Check(NodeId, NodeId),
}

impl Node {
    /// A constant node.
    pub fn constant(v: f64) -> Node {
        Node::Const(v.to_bits())
    }

    /// The value of a constant node.
    pub fn const_value(&self) -> Option<f64> {
        match *self {
            Node::Const(b) => Some(f64::from_bits(b)),
            _ => None,
        }
    }

    /// The node's children, in argument order.
    pub fn children(&self) -> impl Iterator<Item = NodeId> {
        let (arr, n): ([NodeId; 5], usize) = match *self {
            Node::Const(_) | Node::X(_) | Node::Param(_) | Node::Error(_) => ([NodeId(0); 5], 0),
            Node::Unary(_, a) | Node::PowI(a, _) => ([a, a, a, a, a], 1),
            Node::Binary(_, a, b) | Node::Check(a, b) => ([a, b, b, b, b], 2),
            Node::Select(c, t, e) => ([c, t, e, e, e], 3),
            Node::Blend(_, args) => (args, 5),
        };
        arr.into_iter().take(n)
    }

    /// The same operation with each child mapped through `f`.
    pub fn map_children(&self, mut f: impl FnMut(NodeId) -> NodeId) -> Node {
        match *self {
            Node::Const(_) | Node::X(_) | Node::Param(_) | Node::Error(_) => *self,
            Node::Unary(op, a) => Node::Unary(op, f(a)),
            Node::PowI(a, n) => Node::PowI(f(a), n),
            Node::Binary(op, a, b) => Node::Binary(op, f(a), f(b)),
            Node::Check(a, b) => Node::Check(f(a), f(b)),
            Node::Select(c, t, e) => Node::Select(f(c), f(t), f(e)),
            Node::Blend(op, args) => Node::Blend(op, args.map(f)),
        }
    }

    /// Whether this operation itself can produce a runtime error.
    pub fn op_fallible(&self) -> bool {
        match *self {
            Node::Error(_) => true,
            Node::Unary(op, _) => op.fallible(),
            Node::Binary(op, _, _) => op.fallible(),
            Node::PowI(_, n) => n <= 0,
            _ => false,
        }
    }
}

/// A hash-consed graph under construction (see the module docs).
#[derive(Clone, Debug, Default)]
pub struct Graph {
    nodes: Vec<Node>,
    /// Whether each node can evaluate to an error at some point.
    fallible: Vec<bool>,
    dedup: HashMap<Node, NodeId>,
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the graph has no node.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The node with this id.
    pub fn node(&self, id: NodeId) -> &Node {
        &self.nodes[id.index()]
    }

    /// All nodes, in evaluation order.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// The value of a constant node, if it is one.
    pub fn const_value(&self, id: NodeId) -> Option<f64> {
        self.node(id).const_value()
    }

    /// The error of an error node, if it is one.
    pub fn error_value(&self, id: NodeId) -> Option<EvalError> {
        match *self.node(id) {
            Node::Error(e) => Some(e),
            _ => None,
        }
    }

    /// The constant value of `id` once its guards are set aside: for
    /// `Check(g, Check(h, c))` with a constant `c`, the value `c` (whatever
    /// errors `g` and `h` may raise first).
    pub fn const_under_checks(&self, mut id: NodeId) -> Option<f64> {
        loop {
            match *self.node(id) {
                Node::Check(_, v) => id = v,
                Node::Const(b) => return Some(f64::from_bits(b)),
                _ => return None,
            }
        }
    }

    /// Whether the node can evaluate to a runtime error at some point.
    pub fn is_fallible(&self, id: NodeId) -> bool {
        self.fallible[id.index()]
    }

    /// Adds a node as it is (no folding), or finds its twin.
    fn intern(&mut self, node: Node) -> NodeId {
        if let Some(&id) = self.dedup.get(&node) {
            return id;
        }
        // A checked division by a constant that is not ~0 cannot fail.
        let safe_div = matches!(node, Node::Binary(BinaryOp::Div, _, b)
            if self.const_value(b).is_some_and(|v| v.abs() >= ops::EPS));
        let fallible =
            (node.op_fallible() && !safe_div) || node.children().any(|c| self.fallible[c.index()]);
        let id = NodeId(u32::try_from(self.nodes.len()).expect("graph exceeds u32 nodes"));
        self.nodes.push(node);
        self.fallible.push(fallible);
        self.dedup.insert(node, id);
        id
    }

    /// A constant.
    pub fn constant(&mut self, v: f64) -> NodeId {
        self.intern(Node::constant(v))
    }

    /// Coordinate `x[i + 1]`.
    pub fn x(&mut self, i: u32) -> NodeId {
        self.intern(Node::X(i))
    }

    /// Parameter `a[i + 1]`.
    pub fn param(&mut self, i: u32) -> NodeId {
        self.intern(Node::Param(i))
    }

    /// A node that is always the error `e`.
    pub fn error(&mut self, e: EvalError) -> NodeId {
        self.intern(Node::Error(e))
    }

    #[allow(clippy::wrong_self_convention)]
    fn from_result(&mut self, r: Result<f64, EvalError>) -> NodeId {
        match r {
            Ok(v) => self.constant(v),
            Err(e) => self.error(e),
        }
    }

    /// Folds the arguments' errors, given in the order the reference evaluates
    /// them: the first argument that is an error node makes the result that
    /// error, once the arguments evaluated before it have had their chance to
    /// fail first.
    fn fold_errors(&mut self, eval_order: &[NodeId]) -> Option<NodeId> {
        let k = eval_order
            .iter()
            .position(|&a| matches!(self.node(a), Node::Error(_)))?;
        let mut r = eval_order[k];
        for &g in eval_order[..k].iter().rev() {
            r = self.check(g, r);
        }
        Some(r)
    }

    /// `op(a)`, folded.
    pub fn unary(&mut self, op: UnaryOp, a: NodeId) -> NodeId {
        if let Some(e) = self.fold_errors(&[a]) {
            return e;
        }
        if let Some(v) = self.const_value(a) {
            return self.from_result(ops::unary(op, v));
        }
        match (op, *self.node(a)) {
            (UnaryOp::Neg, Node::Unary(UnaryOp::Neg, inner)) => return inner,
            (UnaryOp::Abs, Node::Unary(UnaryOp::Abs | UnaryOp::Neg, inner))
                if op == UnaryOp::Abs =>
            {
                return self.unary(UnaryOp::Abs, inner)
            }
            _ => {}
        }
        self.intern(Node::Unary(op, a))
    }

    /// `op(a, b)`, folded.
    #[allow(clippy::redundant_guards)]
    pub fn binary(&mut self, op: BinaryOp, a: NodeId, b: NodeId) -> NodeId {
        if let Some(e) = self.fold_errors(&[b, a]) {
            return e;
        }
        let (ca, cb) = (self.const_value(a), self.const_value(b));
        if let (Some(x), Some(y)) = (ca, cb) {
            return self.from_result(ops::binary(op, x, y));
        }
        // Value-exact identities (up to the sign of a zero result).
        match (op, ca, cb) {
            (BinaryOp::Add, _, Some(z)) | (BinaryOp::Sub, _, Some(z)) if z == 0.0 => return a,
            (BinaryOp::Add, Some(z), _) if z == 0.0 => return b,
            (BinaryOp::Mul, _, Some(o))
            | (BinaryOp::Div, _, Some(o))
            | (BinaryOp::DivF, _, Some(o))
                if o == 1.0 =>
            {
                return a
            }
            (BinaryOp::Mul, Some(o), _) if o == 1.0 => return b,
            (BinaryOp::Sub, Some(z), _) if z == 0.0 => return self.unary(UnaryOp::Neg, b),
            (BinaryOp::Pow, _, Some(e))
                if e - e.floor() < ops::EPS
                    && ops::round_half_up(e.abs()) <= f64::from(i32::MAX) =>
            {
                // The reference's "integer power": |e| rounded half up, inverted
                // for e < 0. For such e, `e <= EPS` (an error at |b| < EPS)
                // holds exactly when the rounded exponent is <= 0.
                let n = ops::round_half_up(e.abs()) as i32;
                return self.pow_int(a, if e < 0.0 { -n } else { n });
            }
            _ => {}
        }
        // `and` / `or` with a constant side that decides them: the other side
        // still runs (no short circuit), so its errors are kept.
        for (c, other) in [(ca, b), (cb, a)] {
            match (op, c) {
                (BinaryOp::And, Some(v)) if !ops::truthy(v) => {
                    let zero = self.constant(0.0);
                    return self.check(other, zero);
                }
                (BinaryOp::Or, Some(v)) if ops::truthy(v) => {
                    let one = self.constant(1.0);
                    return self.check(other, one);
                }
                _ => {}
            }
        }
        if a == b {
            match op {
                BinaryOp::Min | BinaryOp::Max => return a,
                BinaryOp::Sub if !self.is_fallible(a) => {
                    // a - a is 0 for finite a, NaN for inf/NaN: keep it.
                }
                _ => {}
            }
        }
        let (a, b) = if op.commutative() && a > b && !self.is_fallible(a) && !self.is_fallible(b) {
            (b, a)
        } else {
            (a, b)
        };
        self.intern(Node::Binary(op, a, b))
    }

    /// HyperFun's `b ^ n` for a constant integer `n` ([`ops::pow_int`]).
    pub fn pow_int(&mut self, b: NodeId, n: i32) -> NodeId {
        if let Some(err) = self.fold_errors(&[b]) {
            return err;
        }
        if let Some(v) = self.const_value(b) {
            return self.from_result(ops::pow_int(v, n));
        }
        self.intern(Node::PowI(b, n))
    }

    /// `if truthy(c) then t else e`, folded.
    pub fn select(&mut self, c: NodeId, t: NodeId, e: NodeId) -> NodeId {
        if let Some(cv) = self.const_value(c) {
            return if ops::truthy(cv) { t } else { e };
        }
        if matches!(self.node(c), Node::Error(_)) {
            return c;
        }
        if t == e {
            return self.check(c, t);
        }
        self.intern(Node::Select(c, t, e))
    }

    /// A blend of `(f1, f2, a0, a1, a2)`, folded.
    pub fn blend(&mut self, op: BlendOp, args: [NodeId; 5]) -> NodeId {
        let [f1, f2, a0, a1, a2] = args;
        if let Some(e) = self.fold_errors(&[a2, a1, a0, f2, f1]) {
            return e;
        }
        let consts: Option<Vec<f64>> = args.iter().map(|&a| self.const_value(a)).collect();
        if let Some(v) = consts {
            return self.constant(ops::blend(op, v[0], v[1], v[2], v[3], v[4]));
        }
        self.intern(Node::Blend(op, args))
    }

    /// The value of `v`, with `g`'s error reported first (see the module docs).
    pub fn check(&mut self, g: NodeId, v: NodeId) -> NodeId {
        if !self.is_fallible(g) || g == v {
            return v;
        }
        if matches!(self.node(g), Node::Error(_)) {
            return g;
        }
        // A guard already inside v's own checks need not be repeated.
        if let Node::Check(g2, _) = *self.node(v) {
            if g2 == g {
                return v;
            }
        }
        self.intern(Node::Check(g, v))
    }

    /// The compacted tape computing `outputs`: only the nodes they need, in
    /// evaluation order, renumbered.
    pub fn tape(&self, outputs: &[NodeId]) -> Tape {
        Tape::from_nodes(&self.nodes, outputs)
    }
}

/// A compacted, topologically ordered list of nodes with designated outputs;
/// what the evaluators run. Node ids inside a tape refer to tape positions.
/// Equal and hashed by content (caches of compiled evaluators key on it).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Tape {
    /// The operations in evaluation order; children precede parents.
    pub nodes: Vec<Node>,
    /// The positions of the outputs (value first, then attributes).
    pub outputs: Vec<NodeId>,
}

impl Tape {
    /// Extracts the nodes needed by `outputs` from an ordered node list.
    pub fn from_nodes(nodes: &[Node], outputs: &[NodeId]) -> Tape {
        let mut live = vec![false; nodes.len()];
        for o in outputs {
            live[o.index()] = true;
        }
        for i in (0..nodes.len()).rev() {
            if live[i] {
                for c in nodes[i].children() {
                    live[c.index()] = true;
                }
            }
        }
        let mut remap = vec![u32::MAX; nodes.len()];
        let mut out = Vec::with_capacity(live.iter().filter(|&&l| l).count());
        for (i, n) in nodes.iter().enumerate() {
            if live[i] {
                remap[i] = out.len() as u32;
                out.push(n.map_children(|c| NodeId(remap[c.index()])));
            }
        }
        Tape {
            nodes: out,
            outputs: outputs.iter().map(|o| NodeId(remap[o.index()])).collect(),
        }
    }

    /// Number of operations.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the tape is empty.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// The number of coordinate slots read (1 + the largest `X` index).
    pub fn x_slots(&self) -> usize {
        self.nodes
            .iter()
            .filter_map(|n| match n {
                Node::X(i) => Some(*i as usize + 1),
                _ => None,
            })
            .max()
            .unwrap_or(0)
    }

    /// The degree of output 0 as a polynomial in the point `x[1..3]`, where
    /// the tape computes one.
    ///
    /// A polynomial uses only constants, parameters, the other coordinate
    /// slots (constant while a point varies), `+`, `−`, `*`, negation,
    /// integer powers `^ n` with `n ≥ 0`, division by a value that does not
    /// depend on the point, and `if` on such a value. Any other operation on
    /// the point, or a degree above 64, gives `None`.
    ///
    /// Along a ray `p = o + t·d` such a field is a polynomial of this degree
    /// in `t`, up to rounding, so a ray caster may find its crossings in
    /// closed form (and check them), not by sampling.
    pub fn polynomial_degree(&self) -> Option<u32> {
        let deg = self.degrees();
        self.outputs.first().and_then(|o| deg[o.index()])
    }

    /// `Some(k)` where output 0 is `k − sqrt(p)`, `k` a positive constant
    /// and `p` a polynomial of degree 2 in the point (see
    /// [`Tape::polynomial_degree`]): a sphere or a cylinder written as a
    /// distance, `r − |x − c|`. Wherever `f = k − sqrt(p)` is defined,
    /// `f·(2k − f) = k² − p` has its sign (`2k − f = k + sqrt(p) > 0`) and is a
    /// polynomial of degree 2, so along a ray a ray caster may find `f`'s
    /// crossings in closed form from samples of `f`.
    pub fn root_gap(&self) -> Option<f64> {
        let out = self.outputs.first()?;
        let Node::Binary(BinaryOp::Sub, k, r) = self.nodes[out.index()] else {
            return None;
        };
        let k = self.nodes[k.index()]
            .const_value()
            .filter(|k| *k > 0.0 && k.is_finite())?;
        let Node::Unary(UnaryOp::Sqrt | UnaryOp::SqrtF, p) = self.nodes[r.index()] else {
            return None;
        };
        (self.degrees()[p.index()] == Some(2)).then_some(k)
    }

    /// Per node, its degree as a polynomial in the point, where it is one
    /// ([`Tape::polynomial_degree`]).
    fn degrees(&self) -> Vec<Option<u32>> {
        const MAX: u32 = 64;
        let mut deg: Vec<Option<u32>> = Vec::with_capacity(self.nodes.len());
        for n in &self.nodes {
            let d = |c: &NodeId| deg[c.index()];
            let v = match n {
                Node::Const(_) | Node::Param(_) => Some(0),
                Node::X(i) => Some(u32::from(*i < 3)),
                Node::Error(_) => None,
                Node::Unary(UnaryOp::Neg, a) => d(a),
                Node::Unary(_, a) => d(a).filter(|&x| x == 0),
                Node::Binary(op, a, b) => match (op, d(a), d(b)) {
                    (BinaryOp::Add | BinaryOp::Sub, Some(x), Some(y)) => Some(x.max(y)),
                    (BinaryOp::Mul, Some(x), Some(y)) => Some(x + y),
                    (BinaryOp::Div | BinaryOp::DivF, Some(x), Some(0)) => Some(x),
                    (_, Some(0), Some(0)) => Some(0),
                    _ => None,
                },
                Node::PowI(a, k) => match (d(a), u32::try_from(*k)) {
                    (Some(x), Ok(k)) => x.checked_mul(k),
                    (Some(0), Err(_)) => Some(0),
                    _ => None,
                },
                Node::Select(c, t, e) => match (d(c), d(t), d(e)) {
                    (Some(0), Some(x), Some(y)) => Some(x.max(y)),
                    _ => None,
                },
                Node::Blend(_, args) => args.iter().all(|a| d(a) == Some(0)).then_some(0),
                Node::Check(_, v) => d(v),
            };
            deg.push(v.filter(|&v| v <= MAX));
        }
        deg
    }

    /// For each node, the position of its last use (its own position when
    /// only an output or unused): what a register allocator needs.
    pub fn last_uses(&self) -> Vec<u32> {
        let mut last: Vec<u32> = (0..self.nodes.len() as u32).collect();
        for (i, n) in self.nodes.iter().enumerate() {
            for c in n.children() {
                last[c.index()] = i as u32;
            }
        }
        for o in &self.outputs {
            last[o.index()] = u32::MAX;
        }
        last
    }
}

#[cfg(test)]
mod tests;
