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
mod tests;
