//! Shortening a tape inside a region, from the [`Choice`]s an
//! [`IntervalEval`] recorded over it.
//!
//! The simplified tape is meant for the bulk evaluators (errors are NaN,
//! `Check` guards are ignored): in both modes `Check(g, v)` becomes `v`.
//!
//! ## [`SimplifyMode::Exact`]
//! Every output keeps its value bit for bit (NaN stays NaN) at every point of
//! the region. The rewrites:
//! - a decided `min`/`max` becomes the argument it returns;
//! - a decided `select` becomes its branch;
//! - a decided comparison or `and`/`or`/`not` becomes the constant 0 or 1;
//! - `and`/`or` with a decided side becomes the other side, when that one is
//!   itself a boolean (0/1-valued) operation.
//!
//! ## [`SimplifyMode::Sign`]
//! Output 0 (the defining function) only keeps its *sign* — positive, zero,
//! negative, or NaN (which meshing and rendering treat as outside) — and, at
//! its zeros, its gradient. Other outputs (attributes) stay exact. A node is
//! in *sign context* when output 0 is it, or every use of it is a sign use:
//! an argument of `min`, `max`, R-union, R-intersection, R-difference, `-`
//! (sign flipped) or a branch of `select`, in a parent in sign context. There:
//! * a node whose interval is strictly positive (negative) and never NaN
//!   becomes the constant `1` (`-1`): the sign is kept, and every sign-context
//!   parent is then itself decided or keeps the gradient of its other
//!   argument (see below);
//! * `a | b` becomes `a` where `b < 0` throughout: in exact arithmetic
//!   `a | b = a + b + sqrt(a² + b²)` has the sign of `max(a, b)`, so the sign
//!   of `a`, and where `a = 0` its partial derivatives are
//!   `(1 + a/r, 1 + b/r) = (1, 0)`: the gradient is `∇a`. Likewise `a & b`
//!   becomes `a` where `b > 0` (sign of `min(a, b)`, derivatives
//!   `(1 - a/r, 1 - b/r) = (1, 0)`), `a \ b` becomes `a` where `b < 0`;
//! * `min(a, b)` becomes `a` where `b > 0`, `max(a, b)` becomes `a` where
//!   `b < 0` (and symmetrically), both arguments never NaN.
//!
//! These rules only apply to moderate values (magnitude at most 1e150, never
//! NaN where that matters): a huge or infinite argument makes the squares of
//! an R-function overflow, and its computed sign then no longer follows the
//! exact-arithmetic rule.
//!
//! The sign is that of the exact-arithmetic function. The full tape's
//! computed value may be within rounding noise of 0, as when an R-function
//! of arguments of very different magnitudes cancels. There the simplified
//! tape can give the true sign where the full one gives 0.

use crate::eval::interval::{can_choose, Choice, Decided, IntervalEval, Pick};
use crate::graph::{Node, NodeId, Tape};
use crate::ops::{BinaryOp, UnaryOp};

/// What [`simplify`] must keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SimplifyMode {
    /// Values bit for bit.
    Exact,
    /// The sign (and NaN-ness) of output 0 and its gradient at its zeros;
    /// other outputs exactly.
    Sign,
}

/// Tape lengths before and after simplification.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SimplifyStats {
    /// Nodes of the input tape.
    pub before: usize,
    /// Nodes of the simplified tape.
    pub after: usize,
}

/// Whether the child at `pos` of `node` is used only for its sign when
/// `node` is.
fn is_sign_use(node: &Node, pos: usize) -> bool {
    match node {
        Node::Unary(UnaryOp::Neg, _) => true,
        Node::Binary(
            BinaryOp::Min | BinaryOp::Max | BinaryOp::RUnion | BinaryOp::RInter | BinaryOp::RDiff,
            _,
            _,
        ) => true,
        Node::Select(..) => pos > 0,
        _ => false,
    }
}

/// The argument a pick selects, for the nodes that support it.
fn picked(node: &Node, pick: Pick) -> Option<NodeId> {
    match (*node, pick) {
        (
            Node::Binary(
                BinaryOp::Min
                | BinaryOp::Max
                | BinaryOp::And
                | BinaryOp::Or
                | BinaryOp::RUnion
                | BinaryOp::RInter
                | BinaryOp::RDiff,
                a,
                b,
            ),
            Pick::Left | Pick::Right,
        ) => Some(if pick == Pick::Left { a } else { b }),
        (Node::Select(_, t, _), Pick::Left) => Some(t),
        (Node::Select(_, _, e), Pick::Right) => Some(e),
        (Node::Check(_, v), _) => Some(v),
        _ => None,
    }
}

/// The parts of a tape's [`Choice`]s that [`simplify`] can read, for
/// callers that cache simplified tapes by their choices.
///
/// The [`key`] of an evaluation holds only those. [`expand`] turns it back
/// into choices that simplify to the same tape as the evaluation's own. The signs of
/// nodes that are never used for their sign alone vary from box to box and
/// change nothing, and most nodes (arithmetic) have nothing to choose.
///
/// [`key`]: ChoiceMask::key
/// [`expand`]: ChoiceMask::expand
#[derive(Clone, Debug)]
pub struct ChoiceMask {
    /// Per node, whether it may be used only for its sign (then its
    /// `sign` and `decided` are read; otherwise only `exact`).
    sign_context: Vec<bool>,
    /// The nodes whose choice can differ from the default: those that may
    /// be used for their sign alone, and those that can pick an argument or
    /// a branch or be a decided boolean. In order.
    nodes: Vec<u32>,
    /// Per entry of `nodes`, whether that node can choose ([`can_choose`]):
    /// else only its `decided` can differ from the default.
    chooses: Vec<bool>,
    /// See [`ChoiceMask::can_shorten`].
    can_shorten: bool,
}

impl ChoiceMask {
    /// The mask of `tape` simplified in `mode`.
    pub fn new(tape: &Tape, mode: SimplifyMode) -> ChoiceMask {
        let n = tape.len();
        let mut may = vec![false; n];
        if mode == SimplifyMode::Sign {
            if let Some(o) = tape.outputs.first() {
                may[o.index()] = true;
            }
        }
        // Parents before children. A node may be used for its sign alone
        // only through a parent that may be. Either the parent uses that
        // argument for its sign, or a decided parent reduces to it (a
        // branch of `and`/`or`, the value of a `Check`). This
        // over-approximates, since which parents stay live depends on the
        // choices.
        for i in (0..n).rev() {
            if !may[i] {
                continue;
            }
            let node = &tape.nodes[i];
            for (pos, ch) in node.children().enumerate() {
                let alias = match node {
                    Node::Binary(BinaryOp::And | BinaryOp::Or, ..) => true,
                    Node::Check(..) => pos == 1,
                    _ => false,
                };
                if alias || is_sign_use(node, pos) {
                    may[ch.index()] = true;
                }
            }
        }
        // Nodes that cannot choose (`can_choose`) always have `exact`
        // `Both`.
        let nodes: Vec<u32> = (0..n)
            .filter(|&i| may[i] || can_choose(&tape.nodes[i]))
            .map(|i| i as u32)
            .collect();
        let chooses: Vec<bool> = nodes
            .iter()
            .map(|&i| can_choose(&tape.nodes[i as usize]))
            .collect();
        let can_shorten = chooses.contains(&true);
        ChoiceMask {
            sign_context: may,
            nodes,
            chooses,
            can_shorten,
        }
    }

    /// Whether simplifying can shorten the tape over some box where output
    /// 0 is not decided: only where a node can choose. Without one, the
    /// nodes used for their sign alone are output 0 under `-` signs, decided
    /// exactly where it is. A tape of plain arithmetic (a sphere's
    /// `r - sqrt(x² + y² + z²)`) never shortens, and its choices need not
    /// be looked at.
    pub fn can_shorten(&self) -> bool {
        self.can_shorten
    }

    /// The key of `ev`'s last evaluation (`ev` of this mask's tape): the
    /// choices of the nodes that can matter, with what [`simplify`] does
    /// not read set to the default (`sign`: [`Pick::Both`], `decided`:
    /// [`Decided::No`]), into `out`.
    pub fn key(&self, ev: &IntervalEval, out: &mut Vec<Choice>) {
        out.clear();
        out.extend(self.nodes.iter().zip(&self.chooses).map(|(&i, &chooses)| {
            let i = i as usize;
            if !chooses {
                // In the mask for its sign: only `decided` can be set.
                return Choice {
                    decided: ev.decided(i),
                    ..Choice::default()
                };
            }
            let c = ev.choice(i);
            if self.sign_context[i] {
                c
            } else {
                Choice {
                    exact: c.exact,
                    ..Choice::default()
                }
            }
        }));
    }

    /// Choices for [`simplify`] from a [`key`](ChoiceMask::key): the key's
    /// at its nodes, the default elsewhere, into `out`. They simplify the
    /// tape as the evaluation's own choices do.
    ///
    /// # Panics
    /// If `key` is not of this mask (another length).
    pub fn expand(&self, key: &[Choice], out: &mut Vec<Choice>) {
        assert_eq!(key.len(), self.nodes.len(), "key of another mask");
        out.clear();
        out.resize(self.sign_context.len(), Choice::default());
        for (&i, &c) in self.nodes.iter().zip(key) {
            out[i as usize] = c;
        }
    }
}

/// The tape shortened for the region `choices` were computed over (see the
/// module docs). `choices` must come from an evaluation of this very tape.
pub fn simplify(tape: &Tape, choices: &[Choice], mode: SimplifyMode) -> Tape {
    simplify_with_stats(tape, choices, mode).0
}

/// [`simplify`], also returning the tape lengths.
pub fn simplify_with_stats(
    tape: &Tape,
    choices: &[Choice],
    mode: SimplifyMode,
) -> (Tape, SimplifyStats) {
    Simplifier::default().simplify(tape, choices, mode)
}

/// [`simplify`] with its working buffers kept from call to call: for a
/// caller that shortens many tapes (a renderer, box after box).
#[derive(Clone, Debug, Default)]
pub struct Simplifier {
    /// Per node, [`LIVE`] and [`EXACT`].
    flags: Vec<u8>,
    /// Per live node, what it becomes: [`KEEP`], one of the constants
    /// [`CONSTS`] (`CONST_BASE + k`), or the id of the node it aliases.
    rewrite: Vec<u32>,
    /// Per live node, its id in the simplified tape.
    map: Vec<u32>,
}

/// The node is used (by a live parent, or as an output).
const LIVE: u8 = 1;
/// Its value is used exactly (not only its sign).
const EXACT: u8 = 2;
/// [`Simplifier::rewrite`]: the node stays, its children mapped.
const KEEP: u32 = u32::MAX;
/// The constants a node may become, by their code `CONST_BASE + k`.
const CONSTS: [f64; 3] = [1.0, -1.0, 0.0];
const CONST_BASE: u32 = u32::MAX - 3;

impl Simplifier {
    /// [`simplify_with_stats`]. Constants the tape holds once each stay so,
    /// and the constants simplifying brings in (0, 1, −1) are the tape's
    /// own where it has them.
    pub fn simplify(
        &mut self,
        tape: &Tape,
        choices: &[Choice],
        mode: SimplifyMode,
    ) -> (Tape, SimplifyStats) {
        let n = tape.len();
        assert_eq!(choices.len(), n, "choices of another tape");
        assert!(n < CONST_BASE as usize, "tape too long to simplify");
        self.mark(tape, choices, mode);
        let out = self.rebuild(tape);
        let stats = SimplifyStats {
            before: n,
            after: out.len(),
        };
        (out, stats)
    }

    /// Pass 1, parents before children: which nodes are live, whether their
    /// exact value or only their sign is used, and what each becomes.
    fn mark(&mut self, tape: &Tape, choices: &[Choice], mode: SimplifyMode) {
        let n = tape.len();
        let flags = &mut self.flags;
        flags.clear();
        flags.resize(n, 0);
        // Only live nodes' entries are written, then read.
        if self.rewrite.len() < n {
            self.rewrite.resize(n, KEEP);
            self.map.resize(n, 0);
        }
        let rewrite = &mut self.rewrite[..n];
        for (k, o) in tape.outputs.iter().enumerate() {
            let exact = k > 0 || mode == SimplifyMode::Exact;
            flags[o.index()] |= LIVE | if exact { EXACT } else { 0 };
        }
        // Parents before children: each node's context is known when reached.
        for i in (0..n).rev() {
            let f = flags[i];
            if f & LIVE == 0 {
                continue;
            }
            let node = &tape.nodes[i];
            let c = choices[i];
            let sign_only = f & EXACT == 0;
            let pick = if sign_only { c.sign } else { c.exact };
            let r = match (sign_only, c.decided) {
                (true, Decided::Positive) => CONST_BASE,
                (true, Decided::Negative) => CONST_BASE + 1,
                _ => match pick {
                    Pick::False => CONST_BASE + 2,
                    Pick::True => CONST_BASE,
                    Pick::Both => match node {
                        Node::Check(_, v) => v.0,
                        _ => KEEP,
                    },
                    _ => picked(node, pick).map_or(KEEP, |c| c.0),
                },
            };
            if r == KEEP {
                // Children used for their sign alone stay in sign context.
                let exact = if sign_only { 0 } else { EXACT };
                match *node {
                    Node::Const(_) | Node::X(_) | Node::Param(_) | Node::Error(_) => {}
                    Node::Unary(op, a) => {
                        let e = if op == UnaryOp::Neg { exact } else { EXACT };
                        flags[a.index()] |= LIVE | e;
                    }
                    Node::Binary(op, a, b) => {
                        let e = match op {
                            BinaryOp::Min
                            | BinaryOp::Max
                            | BinaryOp::RUnion
                            | BinaryOp::RInter
                            | BinaryOp::RDiff => exact,
                            _ => EXACT,
                        };
                        flags[a.index()] |= LIVE | e;
                        flags[b.index()] |= LIVE | e;
                    }
                    _ => {
                        for (pos, ch) in node.children().enumerate() {
                            let e = if is_sign_use(node, pos) { exact } else { EXACT };
                            flags[ch.index()] |= LIVE | e;
                        }
                    }
                }
            } else if r < CONST_BASE {
                flags[r as usize] |= LIVE | if sign_only { 0 } else { EXACT };
            }
            rewrite[i] = r;
        }
    }

    /// Pass 2, in tape order: the simplified tape from the marks of
    /// [`Simplifier::mark`].
    fn rebuild(&mut self, tape: &Tape) -> Tape {
        let n = tape.len();
        let flags = &self.flags;
        let rewrite = &self.rewrite[..n];
        let mut nodes = Vec::with_capacity(n);
        let map = &mut self.map[..n];
        // The ids of the constants `CONSTS` in the new tape, once pushed.
        let mut consts = [u32::MAX; 3];
        let const_slot = |bits: u64| CONSTS.iter().position(|c| c.to_bits() == bits);
        for i in 0..n {
            if flags[i] & LIVE == 0 {
                continue;
            }
            let r = rewrite[i];
            let node = if r == KEEP {
                let node = &tape.nodes[i];
                match *node {
                    Node::Const(bits) => match const_slot(bits) {
                        Some(k) if consts[k] != u32::MAX => {
                            map[i] = consts[k];
                            continue;
                        }
                        Some(k) => {
                            consts[k] = nodes.len() as u32;
                            *node
                        }
                        None => *node,
                    },
                    Node::Unary(op, a) => Node::Unary(op, NodeId(map[a.index()])),
                    Node::Binary(op, a, b) => {
                        Node::Binary(op, NodeId(map[a.index()]), NodeId(map[b.index()]))
                    }
                    _ => node.map_children(|c| NodeId(map[c.index()])),
                }
            } else if r >= CONST_BASE {
                let k = (r - CONST_BASE) as usize;
                if consts[k] != u32::MAX {
                    map[i] = consts[k];
                    continue;
                }
                consts[k] = nodes.len() as u32;
                Node::constant(CONSTS[k])
            } else {
                map[i] = map[r as usize];
                continue;
            };
            map[i] = nodes.len() as u32;
            nodes.push(node);
        }
        let outputs: Vec<NodeId> = tape
            .outputs
            .iter()
            .map(|o| NodeId(map[o.index()]))
            .collect();
        // Every node pushed is reachable from an output (a live node is used
        // by a live parent, or is what one aliases to), in order: the tape as
        // it stands, no compaction needed.
        let out = Tape { nodes, outputs };
        debug_assert_eq!(out, Tape::from_nodes(&out.nodes, &out.outputs));
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::interval::{Interval, IntervalEval};
    use crate::eval::testutil::*;
    use crate::eval::Inputs;
    use crate::graph::Graph;
    use crate::ops;
    use proptest::prelude::*;

    fn boxed(lo: [f64; 3], hi: [f64; 3]) -> [Interval; 3] {
        [0, 1, 2].map(|k| Interval::new(lo[k], hi[k]))
    }

    fn simplified(
        tape: &Tape,
        lo: [f64; 3],
        hi: [f64; 3],
        inputs: &Inputs,
        mode: SimplifyMode,
    ) -> Tape {
        let mut ev = IntervalEval::new(tape);
        let [x, y, z] = boxed(lo, hi);
        ev.eval(x, y, z, inputs);
        let (t, stats) = simplify_with_stats(tape, ev.choices(), mode);
        assert!(stats.after <= stats.before);
        assert_eq!(stats.after, t.len());
        // Compact as built: every node reachable, in order.
        assert_eq!(t, Tape::from_nodes(&t.nodes, &t.outputs));
        assert_unique_constants(&t);
        t
    }

    /// Each constant once (a tape from a graph holds each once, and so must
    /// its simplified tapes).
    fn assert_unique_constants(t: &Tape) {
        let mut bits: Vec<u64> = t
            .nodes
            .iter()
            .filter_map(|n| match n {
                Node::Const(b) => Some(*b),
                _ => None,
            })
            .collect();
        let n = bits.len();
        bits.sort_unstable();
        bits.dedup();
        assert_eq!(bits.len(), n, "a constant twice in {t:?}");
    }

    #[test]
    fn constants_brought_in_are_the_tapes_own() {
        // `select(x > 0, x + 3, y - 1)` over x in [-1, 1]: the branch
        // `x + 3` is positive throughout and becomes the constant 1, which
        // the tape already holds (for `y - 1`; made first, or after the
        // branch's nodes).
        for one_first in [true, false] {
            let mut g = Graph::new();
            let one = one_first.then(|| g.constant(1.0));
            let (x, y) = (g.x(0), g.x(1));
            let (zero, three) = (g.constant(0.0), g.constant(3.0));
            let c = g.binary(BinaryOp::Gt, x, zero);
            let t = g.binary(BinaryOp::Add, x, three);
            let one = one.unwrap_or_else(|| g.constant(1.0));
            let e = g.binary(BinaryOp::Sub, y, one);
            let out = g.select(c, t, e);
            let tape = g.tape(&[out]);
            let simp = simplified(
                &tape,
                [-1.0, -1.0, -1.0],
                [1.0, 1.0, 1.0],
                &Inputs::default(),
                SimplifyMode::Sign,
            );
            assert!(simp.len() < tape.len(), "{simp:?}");
            assert!(simp.nodes.contains(&Node::constant(1.0)));
            for p in [[0.5, 0.2, 0.0], [-0.5, 0.2, 0.0], [-0.5, 3.0, 0.0]] {
                assert_same_sign(&tape, &simp, p, &Inputs::default());
            }
        }
    }

    /// -2 for NaN, else the sign.
    fn class(v: f64) -> i8 {
        if v.is_nan() {
            -2
        } else if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            0
        }
    }

    /// Same sign class, or the full value is within rounding noise of 0.
    fn assert_same_sign(full: &Tape, simp: &Tape, p: [f64; 3], inputs: &Inputs) {
        let all = eval_point_all(full, p, inputs);
        let f = all[full.outputs[0].index()];
        let s = eval_point(simp, p, inputs);
        if class(f) == class(s) {
            return;
        }
        let scale = all
            .iter()
            .filter(|v| v.is_finite())
            .fold(1.0f64, |m, v| m.max(v.abs()));
        assert!(
            !f.is_nan() && !s.is_nan() && f.abs() <= 1e-9 * scale,
            "sign differs at {p:?}: full {f:e}, simplified {s:e}\n{full:?}\n{simp:?}"
        );
    }

    /// A random CSG tree of spheres, planes and random expressions.
    #[derive(Clone, Debug)]
    enum Csg {
        Sphere([f64; 3], f64),
        Plane([f64; 3], f64),
        Random(Vec<Instr>),
        Op(u8, Box<Csg>, Box<Csg>),
        Select(u8, f64, Box<Csg>, Box<Csg>),
    }

    fn csg(allow_random: bool) -> impl Strategy<Value = Csg> {
        let c = || -1.5..1.5f64;
        let leaf = prop_oneof![
            4 => ([c(), c(), c()], 0.05..1.0f64).prop_map(|(c, r)| Csg::Sphere(c, r)),
            1 => ([c(), c(), c()], c()).prop_map(|(n, d)| Csg::Plane(n, d)),
            (if allow_random { 1 } else { 0 }) => instrs(10).prop_map(Csg::Random),
        ];
        leaf.prop_recursive(5, 40, 2, move |inner| {
            prop_oneof![
                6 => (0u8..6, inner.clone(), inner.clone())
                    .prop_map(|(k, a, b)| Csg::Op(k, Box::new(a), Box::new(b))),
                (if allow_random { 1 } else { 0 }) => (0u8..3, -1.0..1.0f64, inner.clone(), inner)
                    .prop_map(|(k, v, a, b)| Csg::Select(k, v, Box::new(a), Box::new(b))),
            ]
        })
    }

    fn build_csg(g: &mut Graph, t: &Csg) -> NodeId {
        let (x, y, z) = (g.x(0), g.x(1), g.x(2));
        match t {
            Csg::Sphere(c, r) => {
                let mut sum = g.constant(r * r);
                for (k, v) in [x, y, z].into_iter().enumerate() {
                    let ck = g.constant(c[k]);
                    let d = g.binary(BinaryOp::Sub, v, ck);
                    let sq = g.pow_int(d, 2);
                    sum = g.binary(BinaryOp::Sub, sum, sq);
                }
                sum
            }
            Csg::Plane(n, d) => {
                let mut s = g.constant(*d);
                for (k, v) in [x, y, z].into_iter().enumerate() {
                    let nk = g.constant(n[k]);
                    let t = g.binary(BinaryOp::Mul, v, nk);
                    s = g.binary(BinaryOp::Sub, s, t);
                }
                s
            }
            Csg::Random(ins) => build_random(g, ins),
            Csg::Op(k, a, b) => {
                let (a, b) = (build_csg(g, a), build_csg(g, b));
                match k {
                    0 => g.binary(BinaryOp::RUnion, a, b),
                    1 => g.binary(BinaryOp::RInter, a, b),
                    2 => g.binary(BinaryOp::RDiff, a, b),
                    3 => g.binary(BinaryOp::Min, a, b),
                    4 => g.binary(BinaryOp::Max, a, b),
                    _ => {
                        let n = g.unary(UnaryOp::Neg, b);
                        g.binary(BinaryOp::RUnion, a, n)
                    }
                }
            }
            Csg::Select(k, v, a, b) => {
                let axis = g.x(u32::from(*k));
                let c = g.constant(*v);
                let cond = g.binary(BinaryOp::Lt, axis, c);
                let (a, b) = (build_csg(g, a), build_csg(g, b));
                g.select(cond, a, b)
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 1000, ..ProptestConfig::default() })]
        #[test]
        fn exact_mode_keeps_values(
            ins in instrs(24),
            (c, h) in boxes(),
            pts in fracs(8),
            a0 in constant(),
        ) {
            let mut g = Graph::new();
            let out = build_random(&mut g, &ins);
            let tape = g.tape(&[out]);
            let (lo, hi) = corners_of(c, h);
            let inputs = Inputs::with_params(&[a0]);
            let simp = simplified(&tape, lo, hi, &inputs, SimplifyMode::Exact);
            for t in pts {
                let p = at(lo, hi, t);
                let (f, s) = (eval_point(&tape, p, &inputs), eval_point(&simp, p, &inputs));
                prop_assert!(f.to_bits() == s.to_bits() || (f.is_nan() && s.is_nan()),
                    "at {:?}: {} vs {}\n{:?}\n{:?}", p, f, s, tape, simp);
            }
        }

        #[test]
        fn masked_choices_simplify_alike(
            t in csg(true),
            ins in instrs(24),
            (c, h) in boxes(),
            a0 in constant(),
        ) {
            // What the key drops changes no simplified tape, in either
            // mode, on CSG trees and on random tapes; the nodes left out
            // have the default choice, and those kept their own.
            for random in [false, true] {
                let mut g = Graph::new();
                let out = if random { build_random(&mut g, &ins) } else { build_csg(&mut g, &t) };
                let tape = g.tape(&[out]);
                let (lo, hi) = corners_of(c, h);
                let mut ev = IntervalEval::new(&tape);
                let [x, y, z] = boxed(lo, hi);
                ev.eval(x, y, z, &Inputs::with_params(&[a0]));
                for mode in [SimplifyMode::Sign, SimplifyMode::Exact] {
                    let mask = ChoiceMask::new(&tape, mode);
                    let (mut key, mut full) = (Vec::new(), Vec::new());
                    mask.key(&ev, &mut key);
                    mask.expand(&key, &mut full);
                    let simp = simplify(&tape, ev.choices(), mode);
                    prop_assert_eq!(&simp, &simplify(&tape, &full, mode));
                    // A tape that cannot shorten does not, wherever output 0
                    // is not decided.
                    let out = tape.outputs[0].index();
                    if mode == SimplifyMode::Sign
                        && !mask.can_shorten()
                        && ev.choices()[out].decided == Decided::No
                    {
                        prop_assert_eq!(simp.len(), tape.len());
                    }
                    for (i, (f, c)) in full.iter().zip(ev.choices()).enumerate() {
                        prop_assert_eq!(f.exact, c.exact, "node {}", i);
                        if mask.sign_context[i] {
                            prop_assert_eq!(f, c, "node {}", i);
                        }
                    }
                }
            }
        }

        #[test]
        fn exact_mode_on_csg_keeps_values(
            t in csg(true),
            (c, h) in boxes(),
            pts in fracs(8),
        ) {
            let mut g = Graph::new();
            let out = build_csg(&mut g, &t);
            let tape = g.tape(&[out]);
            let (lo, hi) = corners_of(c, h);
            let inputs = Inputs::default();
            let simp = simplified(&tape, lo, hi, &inputs, SimplifyMode::Exact);
            for t in pts {
                let p = at(lo, hi, t);
                let (f, s) = (eval_point(&tape, p, &inputs), eval_point(&simp, p, &inputs));
                prop_assert!(f.to_bits() == s.to_bits() || (f.is_nan() && s.is_nan()));
            }
        }

        #[test]
        fn sign_mode_keeps_signs(
            t in csg(true),
            (c, h) in boxes(),
            pts in fracs(12),
        ) {
            let mut g = Graph::new();
            let out = build_csg(&mut g, &t);
            let tape = g.tape(&[out]);
            let (lo, hi) = corners_of(c, h);
            let inputs = Inputs::default();
            let simp = simplified(&tape, lo, hi, &inputs, SimplifyMode::Sign);
            for t in pts {
                assert_same_sign(&tape, &simp, at(lo, hi, t), &inputs);
            }
        }

        #[test]
        fn sign_mode_keeps_gradients_at_zeros(
            t in csg(false),
            c in [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64],
            h in 0.05..1.0f64,
            segs in prop::collection::vec(([0.0..1.0f64, 0.0..1.0, 0.0..1.0], [0.0..1.0f64, 0.0..1.0, 0.0..1.0]), 16),
        ) {
            let mut g = Graph::new();
            let out = build_csg(&mut g, &t);
            let tape = g.tape(&[out]);
            let (lo, hi) = corners_of(c, [h; 3]);
            let inputs = Inputs::default();
            let simp = simplified(&tape, lo, hi, &inputs, SimplifyMode::Sign);
            let step = 1e-6 * h;
            // Stay 2 steps inside the box.
            let (ilo, ihi) = corners_of(c, [h - 2.0 * step; 3]);
            let f = |tp: &Tape, p: [f64; 3]| eval_point(tp, p, &inputs);
            for (s, e) in segs {
                let (mut p, mut q) = (at(ilo, ihi, s), at(ilo, ihi, e));
                let (fp, fq) = (f(&tape, p), f(&tape, q));
                if !(fp > 0.0 && fq < 0.0 || fp < 0.0 && fq > 0.0) {
                    continue;
                }
                for _ in 0..60 {
                    let m = [0, 1, 2].map(|k| 0.5 * (p[k] + q[k]));
                    let fm = f(&tape, m);
                    if fm.is_nan() { break; }
                    if (fm > 0.0) == (fp > 0.0) { p = m; } else { q = m; }
                }
                let grad = |tp: &Tape| {
                    [0, 1, 2].map(|k| {
                        let (mut a, mut b) = (p, p);
                        a[k] += step;
                        b[k] -= step;
                        (f(tp, a) - f(tp, b)) / (2.0 * step)
                    })
                };
                let (gf, gs) = (grad(&tape), grad(&simp));
                let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                let (nf, ns) = (norm(gf), norm(gs));
                if !(nf > 1e-3 && ns.is_finite()) {
                    continue; // a kink or a flat zero
                }
                let cos = (gf[0] * gs[0] + gf[1] * gs[1] + gf[2] * gs[2]) / (nf * ns);
                // Kinks of min/max within a step of the zero are the only
                // exception; they are rare.
                prop_assert!(cos > 0.999 || (cos.is_nan() && ns == 0.0) || kink_near(&tape, p, step),
                    "gradient {:?} vs {:?} at {:?}", gf, gs, p);
            }
        }
    }

    /// Whether the full function is not smooth within a few steps of `p`
    /// (one-sided differences disagree).
    fn kink_near(tape: &Tape, p: [f64; 3], step: f64) -> bool {
        let inputs = Inputs::default();
        let f0 = eval_point(tape, p, &inputs);
        (0..3).any(|k| {
            let (mut a, mut b) = (p, p);
            a[k] += 4.0 * step;
            b[k] -= 4.0 * step;
            let d1 = (eval_point(tape, a, &inputs) - f0) / (4.0 * step);
            let d2 = (f0 - eval_point(tape, b, &inputs)) / (4.0 * step);
            (d1 - d2).abs() > 1e-3 * (1.0 + d1.abs().max(d2.abs()))
        })
    }

    #[test]
    fn r_union_keeps_sign_and_gradient_of_the_decided_argument() {
        // a = 0 on the sphere of radius 0.5 at the origin; b < 0 near it.
        let a = |p: [f64; 3]| 0.25 - (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        let b = |p: [f64; 3]| 0.04 - ((p[0] - 2.0).powi(2) + p[1] * p[1] + p[2] * p[2]);
        type RFn = fn(f64, f64) -> f64;
        let fns: [(RFn, f64); 3] = [
            (ops::r_union, -1.0),
            (ops::r_inter, 1.0),
            (ops::r_diff, -1.0),
        ];
        for (u, bsign) in fns {
            let bb = |p: [f64; 3]| if bsign < 0.0 { b(p) } else { -b(p) };
            for k in 0..50 {
                let th = 0.3 + 0.05 * k as f64;
                let ph = 0.1 * k as f64;
                let dir = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
                // Points on, inside and outside a's zero set.
                for r in [0.5, 0.45, 0.55] {
                    let p = dir.map(|v| v * r);
                    assert!(bb(p) * bsign > 0.0);
                    let (fa, fu) = (a(p), u(a(p), bb(p)));
                    // On the surface, both are 0 up to rounding.
                    assert!(
                        class(fa) == class(fu) || (fa.abs() < 1e-15 && fu.abs() < 1e-15),
                        "{p:?}: {fa} vs {fu}"
                    );
                }
                let p = dir.map(|v| v * 0.5);
                let h = 1e-6;
                for axis in 0..3 {
                    let (mut q, mut s) = (p, p);
                    q[axis] += h;
                    s[axis] -= h;
                    let ga = (a(q) - a(s)) / (2.0 * h);
                    let gu = (u(a(q), bb(q)) - u(a(s), bb(s))) / (2.0 * h);
                    assert!((ga - gu).abs() < 1e-6 * (1.0 + ga.abs()), "{ga} vs {gu}");
                }
            }
        }
    }

    #[derive(Default, Debug)]
    struct OctStats {
        evals: usize,
        leaves: usize,
        leaf_len_sum: usize,
    }

    fn octree(
        tape: &Tape,
        lo: [f64; 3],
        hi: [f64; 3],
        depth: u32,
        shorten: bool,
        st: &mut OctStats,
    ) {
        st.evals += 1;
        let mut ev = IntervalEval::new(tape);
        let [x, y, z] = boxed(lo, hi);
        let r = ev.eval(x, y, z, &Inputs::default());
        if r.is_positive() || r.is_negative() {
            return;
        }
        if depth == 0 {
            st.leaves += 1;
            st.leaf_len_sum += tape.len();
            return;
        }
        let sub;
        let tape = if shorten {
            sub = simplify(tape, ev.choices(), SimplifyMode::Sign);
            &sub
        } else {
            tape
        };
        let mid = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
        for i in 0..8 {
            let mut l = lo;
            let mut h = hi;
            for k in 0..3 {
                if i >> k & 1 == 0 {
                    h[k] = mid[k];
                } else {
                    l[k] = mid[k];
                }
            }
            octree(tape, l, h, depth - 1, shorten, st);
        }
    }

    /// The pruning regression check of the notes: the M4 R-union chain of
    /// ten spheres on a depth-6 octree over [-1, 1]³. With R-unions written
    /// out as `a + b + sqrt(a² + b²)` none of the 262,144 cells is pruned.
    #[test]
    fn m4_octree_pruning() {
        let mut g = Graph::new();
        let f = m4(&mut g, 10);
        let tape = g.tape(&[f]);
        let mut plain = OctStats::default();
        octree(&tape, [-1.0; 3], [1.0; 3], 6, false, &mut plain);
        let mut short = OctStats::default();
        octree(&tape, [-1.0; 3], [1.0; 3], 6, true, &mut short);
        eprintln!(
            "M4 depth 6: {} interval evaluations, {} surviving cells (of 262144); \
             with sign simplification {} evaluations, {} cells, mean leaf tape {:.1} of {}",
            plain.evals,
            plain.leaves,
            short.evals,
            short.leaves,
            short.leaf_len_sum as f64 / short.leaves as f64,
            tape.len()
        );
        // 9,364 cells really cross the surface: the survivors are few more.
        assert!(plain.leaves >= 9_364 && plain.leaves < 20_000, "{plain:?}");
        assert!(plain.evals < 40_000, "{plain:?}");
        assert!(short.leaves <= plain.leaves && short.evals <= plain.evals);
        assert!(short.leaf_len_sum < short.leaves * tape.len() / 3);

        // The same model with the R-unions written out, at depth 4: hardly
        // anything is pruned.
        let mut g = Graph::new();
        let f = m4_written_out(&mut g, 10);
        let written = g.tape(&[f]);
        let (mut w4, mut r4) = (OctStats::default(), OctStats::default());
        octree(&written, [-1.0; 3], [1.0; 3], 4, false, &mut w4);
        octree(&tape, [-1.0; 3], [1.0; 3], 4, false, &mut r4);
        eprintln!(
            "M4 depth 4: written-out R-unions {} evaluations, {} of 4096 cells survive; \
             R-union ops {} evaluations, {} cells",
            w4.evals, w4.leaves, r4.evals, r4.leaves
        );
        assert!(w4.leaves > 4 * r4.leaves, "{w4:?} {r4:?}");
    }

    /// M4 with `a | b` spelled `a + b + sqrt(a*a + b*b)`.
    fn m4_written_out(g: &mut Graph, n: usize) -> NodeId {
        let spheres: Vec<NodeId> = (0..n)
            .map(|i| {
                let (x, y, z) = (g.x(0), g.x(1), g.x(2));
                let t = 0.6 * i as f64;
                let c = [0.6 * t.cos(), 0.6 * t.sin(), -0.8 + 0.16 * i as f64];
                let mut s = g.constant(0.0625);
                for (k, v) in [x, y, z].into_iter().enumerate() {
                    let ck = g.constant(c[k]);
                    let d = g.binary(BinaryOp::Sub, v, ck);
                    let sq = g.pow_int(d, 2);
                    s = g.binary(BinaryOp::Sub, s, sq);
                }
                s
            })
            .collect();
        let mut acc = spheres[0];
        for &b in &spheres[1..] {
            let s = g.binary(BinaryOp::Add, acc, b);
            let aa = g.binary(BinaryOp::Mul, acc, acc);
            let bb = g.binary(BinaryOp::Mul, b, b);
            let q = g.binary(BinaryOp::Add, aa, bb);
            let r = g.unary(UnaryOp::Sqrt, q);
            acc = g.binary(BinaryOp::Add, s, r);
        }
        acc
    }
}
