//! [`IntervalEval`]: the interval evaluator of one tape.
//!
//! - [`IntervalEval::new`] lowers the tape once into a flat list of
//!   operations over registers, one per node.
//! - Each evaluation runs the list once.
//! - The per-node intervals and choices are assembled lazily, on first
//!   request after an evaluation.

use super::{arith::*, binary::*, choice::*, fast::*, functions::*};
use crate::eval::Inputs;
use crate::graph::{Node, NodeId, Tape};
use crate::ops::{BinaryOp, BlendOp, UnaryOp};
use std::collections::HashMap;
use std::sync::{Mutex, OnceLock, PoisonError};

/// One operation of the lowered tape, its arguments as node indices. The
/// common operations have variants of their own; leaves are not here
/// (constants are stored once, inputs set at the start of each evaluation).
#[derive(Clone, Copy, Debug)]
pub(super) enum Op {
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    /// `a * a`.
    Sqr(u32),
    Neg(u32),
    /// `Sqrt` and `SqrtF` (the same interval rule).
    Sqrt(u32),
    /// `PowI(a, 2)`.
    PowI2(u32),
    Min(u32, u32),
    Max(u32, u32),
    RUnion(u32, u32),
    RInter(u32, u32),
    RDiff(u32, u32),
    Unary(UnaryOp, u32),
    /// Any other binary operation; the flag tells whether both arguments
    /// are the same node.
    Binary(BinaryOp, u32, u32, bool),
    PowI(u32, i32),
    Select(u32, u32, u32),
    /// A blend; its arguments are `blends[i]`.
    Blend(BlendOp, u32),
    /// `Check(_, v)`: the value of `v`.
    Copy(u32),
    /// `sin a` into the first node and `cos a` into the second: the two
    /// nodes of one argument, computed together at the first of them (the
    /// second emits nothing).
    SinCos(u32, u32, u32),
}

/// The bit of input `x[k]` in a mask of inputs: `x`, `y` and `z` one each,
/// every other input (extra coordinates, parameters) the fourth.
fn input_bit(k: u32) -> u8 {
    if k < 3 {
        1 << k
    } else {
        OTHER_INPUTS
    }
}

/// The bit of every input but `x`, `y` and `z` (see [`input_bit`]).
const OTHER_INPUTS: u8 = 1 << 3;

/// Every input's bit.
const ALL_INPUTS: u8 = 0b1111;

/// An operation and the node it computes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Instr {
    pub(super) op: Op,
    out: u32,
}

/// Interval evaluator of one tape, reusable across boxes.
///
/// [`new`](IntervalEval::new) lowers the tape once into a flat list of
/// operations. The per-node intervals and [`Choice`]s are assembled when
/// [`intervals`](IntervalEval::intervals) or
/// [`choices`](IntervalEval::choices) is first called after an evaluation.
#[derive(Debug)]
pub struct IntervalEval {
    tape: Tape,
    pub(super) code: Vec<Instr>,
    /// The input leaves (`X`, `Param`), set at the start of each evaluation.
    leaves: Vec<(u32, Node)>,
    blends: Vec<[u32; 5]>,
    regs: Regs,
    /// Per operation of `code`, the inputs it depends on ([`input_bit`]).
    deps: Vec<u8>,
    /// Per set of changed inputs (a mask of [`input_bit`]s, neither empty
    /// nor all), the operations of `code` that depend on one of them, built
    /// when first needed. Every node has a register of its own, so the
    /// others still hold their values from the last evaluation.
    partial: Vec<Option<Box<[Instr]>>>,
    /// Whether an evaluation has set every register.
    primed: bool,
    /// The intervals of the last evaluation, once asked for.
    values: OnceLock<Vec<Interval>>,
    /// The choices of the last evaluation, once asked for.
    choices: OnceLock<Vec<Choice>>,
    /// Buffers for the next intervals and choices.
    spare: Mutex<(Vec<Interval>, Vec<Choice>)>,
}

impl Clone for IntervalEval {
    fn clone(&self) -> Self {
        IntervalEval {
            tape: self.tape.clone(),
            code: self.code.clone(),
            leaves: self.leaves.clone(),
            blends: self.blends.clone(),
            regs: self.regs.clone(),
            deps: self.deps.clone(),
            partial: self.partial.clone(),
            primed: self.primed,
            values: self.values.clone(),
            choices: self.choices.clone(),
            spare: Mutex::default(),
        }
    }
}

/// The `sin a` / `cos a` pairs of one argument `a`, both computed at the
/// first of the two. Maps the first's index to `Some((sin, cos))` and the
/// second's to `None`.
fn trig_pairs(tape: &Tape) -> HashMap<u32, Option<(u32, u32)>> {
    let mut trig: HashMap<u32, [Option<u32>; 2]> = HashMap::new();
    for (i, node) in tape.nodes.iter().enumerate() {
        if let Node::Unary(op @ (UnaryOp::Sin | UnaryOp::Cos), a) = *node {
            trig.entry(a.index() as u32).or_default()[usize::from(op == UnaryOp::Cos)] =
                Some(i as u32);
        }
    }
    let mut paired = HashMap::new();
    for [s, c] in trig.into_values() {
        if let (Some(s), Some(c)) = (s, c) {
            paired.insert(s.min(c), Some((s, c)));
            paired.insert(s.max(c), None);
        }
    }
    paired
}

/// Which inputs each instruction of `code` depends on (bits of
/// [`input_bit`] and [`OTHER_INPUTS`]).
fn instr_deps(tape: &Tape, code: &[Instr]) -> Vec<u8> {
    let mut node_deps = vec![0u8; tape.len()];
    for (i, node) in tape.nodes.iter().enumerate() {
        node_deps[i] = match *node {
            Node::X(k) => input_bit(k),
            Node::Param(_) => OTHER_INPUTS,
            _ => node.children().fold(0, |m, c| m | node_deps[c.index()]),
        };
    }
    code.iter()
        .map(|ins| match ins.op {
            // The pair's argument (`out` is one of the two results).
            Op::SinCos(a, _, _) => node_deps[a as usize],
            _ => node_deps[ins.out as usize],
        })
        .collect()
}

impl IntervalEval {
    /// An evaluator for `tape`.
    pub fn new(tape: &Tape) -> Self {
        let n = tape.len();
        let mut regs = Regs {
            r: vec![Interval::EMPTY; n],
        };
        let mut code = Vec::with_capacity(n);
        let mut leaves = Vec::with_capacity(4);
        let mut blends = Vec::new();
        let ix = |id: NodeId| id.index() as u32;
        let paired = trig_pairs(tape);
        for (i, node) in tape.nodes.iter().enumerate() {
            if let Some(&pair) = paired.get(&(i as u32)) {
                if let (Some((s, c)), Node::Unary(_, a)) = (pair, *node) {
                    code.push(Instr {
                        op: Op::SinCos(ix(a), s, c),
                        out: i as u32,
                    });
                }
                continue;
            }
            let op = match *node {
                Node::Const(bits) => {
                    regs.set(i, Interval::point(f64::from_bits(bits)));
                    continue;
                }
                Node::Error(_) => {
                    regs.set(i, Interval::NAN);
                    continue;
                }
                Node::X(_) | Node::Param(_) => {
                    leaves.push((i as u32, *node));
                    continue;
                }
                Node::Unary(op, a) => match op {
                    UnaryOp::Neg => Op::Neg(ix(a)),
                    UnaryOp::Sqrt | UnaryOp::SqrtF => Op::Sqrt(ix(a)),
                    _ => Op::Unary(op, ix(a)),
                },
                Node::PowI(a, 2) => Op::PowI2(ix(a)),
                Node::PowI(a, n) => Op::PowI(ix(a), n),
                Node::Binary(op, a, b) => {
                    let (a, b) = (ix(a), ix(b));
                    match op {
                        BinaryOp::Add => Op::Add(a, b),
                        BinaryOp::Sub => Op::Sub(a, b),
                        BinaryOp::Mul if a == b => Op::Sqr(a),
                        BinaryOp::Mul => Op::Mul(a, b),
                        BinaryOp::Min => Op::Min(a, b),
                        BinaryOp::Max => Op::Max(a, b),
                        BinaryOp::RUnion => Op::RUnion(a, b),
                        BinaryOp::RInter => Op::RInter(a, b),
                        BinaryOp::RDiff => Op::RDiff(a, b),
                        _ => Op::Binary(op, a, b, a == b),
                    }
                }
                Node::Select(c, t, e) => Op::Select(ix(c), ix(t), ix(e)),
                Node::Blend(op, args) => {
                    blends.push(args.map(ix));
                    Op::Blend(op, (blends.len() - 1) as u32)
                }
                Node::Check(_, v) => Op::Copy(ix(v)),
            };
            code.push(Instr { op, out: i as u32 });
        }
        let deps = instr_deps(tape, &code);
        IntervalEval {
            tape: tape.clone(),
            code,
            leaves,
            blends,
            regs,
            deps,
            partial: vec![None; ALL_INPUTS as usize],
            primed: false,
            values: OnceLock::new(),
            choices: OnceLock::new(),
            spare: Mutex::default(),
        }
    }

    /// The tape evaluated.
    pub fn tape(&self) -> &Tape {
        &self.tape
    }

    /// Evaluates every node over the box `x × y × z` and returns output 0's
    /// interval ([`Interval::NAN`] for a tape without outputs).
    pub fn eval(&mut self, x: Interval, y: Interval, z: Interval, inputs: &Inputs) -> Interval {
        self.run(x, y, z, inputs);
        self.tape
            .outputs
            .first()
            .map_or(Interval::NAN, |o| self.regs.get(o.index() as u32))
    }

    /// Evaluates every node and returns every output's interval.
    pub fn eval_outputs(
        &mut self,
        x: Interval,
        y: Interval,
        z: Interval,
        inputs: &Inputs,
    ) -> Vec<Interval> {
        self.run(x, y, z, inputs);
        self.tape
            .outputs
            .iter()
            .map(|o| self.regs.get(o.index() as u32))
            .collect()
    }

    /// Each node's interval from the last evaluation.
    pub fn intervals(&self) -> &[Interval] {
        self.values.get_or_init(|| {
            let mut v = std::mem::take(&mut self.spare().0);
            v.clear();
            v.extend((0..self.tape.len() as u32).map(|i| self.regs.get(i)));
            v
        })
    }

    /// Each node's [`Choice`] from the last evaluation (for
    /// [`simplify`](crate::simplify::simplify)).
    pub fn choices(&self) -> &[Choice] {
        self.choices.get_or_init(|| {
            let values = self.intervals();
            let mut c = std::mem::take(&mut self.spare().1);
            c.clear();
            let nodes = &self.tape.nodes;
            c.extend((0..nodes.len()).map(|i| choice_of(nodes, |k| values[k], i)));
            c
        })
    }

    /// Node `i`'s [`Choice`] from the last evaluation, as
    /// [`choices`](IntervalEval::choices)`()[i]` (computed alone).
    ///
    /// # Panics
    /// If `i` is not a node of the tape.
    pub fn choice(&self, i: usize) -> Choice {
        choice_of(&self.tape.nodes, |k| self.regs.get(k as u32), i)
    }

    /// Node `i`'s [`Choice::decided`] from the last evaluation: all of its
    /// [`choice`](IntervalEval::choice) for a node that cannot choose (an
    /// arithmetic operation: its picks are [`Pick::Both`]).
    ///
    /// # Panics
    /// If `i` is not a node of the tape.
    pub fn decided(&self, i: usize) -> Decided {
        decided_of(self.regs.get(i as u32))
    }

    fn spare(&self) -> std::sync::MutexGuard<'_, (Vec<Interval>, Vec<Choice>)> {
        self.spare.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn run(&mut self, x: Interval, y: Interval, z: Interval, inputs: &Inputs) {
        let spare = self.spare.get_mut().unwrap_or_else(PoisonError::into_inner);
        if let Some(v) = self.values.take() {
            spare.0 = v;
        }
        if let Some(c) = self.choices.take() {
            spare.1 = c;
        }
        let v = &mut self.regs;
        // The inputs that differ from the last evaluation's (bit for bit).
        let mut changed = 0u8;
        for &(i, node) in &self.leaves {
            let (r, bit) = match node {
                Node::X(0) => (x, input_bit(0)),
                Node::X(1) => (y, input_bit(1)),
                Node::X(2) => (z, input_bit(2)),
                Node::X(k) => (Interval::point(inputs.extra_x(k)), OTHER_INPUTS),
                Node::Param(k) => (Interval::point(inputs.param(k)), OTHER_INPUTS),
                _ => unreachable!("not an input leaf"),
            };
            let old = v.get(i);
            if (old.lo.to_bits(), old.hi.to_bits(), old.nan)
                != (r.lo.to_bits(), r.hi.to_bits(), r.nan)
            {
                changed |= bit;
            }
            v.set(i as usize, r);
        }
        // Only the operations that depend on a changed input run; the
        // others' registers hold what they would compute.
        let code: &[Instr] = if !self.primed || changed == ALL_INPUTS {
            self.primed = true;
            &self.code
        } else if changed == 0 {
            &[]
        } else {
            let (code, deps) = (&self.code, &self.deps);
            self.partial[changed as usize].get_or_insert_with(|| {
                code.iter()
                    .zip(deps)
                    .filter(|&(_, &d)| d & changed != 0)
                    .map(|(ins, _)| *ins)
                    .collect()
            })
        };
        for ins in code {
            let out = ins.out as usize;
            let g = |i: u32| v.get(i);
            match ins.op {
                Op::Add(a, b) => add_at(v, out, a, b),
                Op::Sub(a, b) => sub_at(v, out, a, b),
                Op::Mul(a, b) => mul_at(v, out, a, b),
                Op::Sqr(a) => sqr_at(v, out, a),
                Op::Neg(a) => neg_at(v, out, a),
                Op::Sqrt(a) => sqrt_at(v, out, a),
                Op::PowI2(a) => powi2_at(v, out, a),
                Op::Min(a, b) => min_at(v, out, a, b),
                Op::Max(a, b) => max_at(v, out, a, b),
                Op::RUnion(a, b) => rfun_at(v, out, BinaryOp::RUnion, a, b),
                Op::RInter(a, b) => rfun_at(v, out, BinaryOp::RInter, a, b),
                Op::RDiff(a, b) => rfun_at(v, out, BinaryOp::RDiff, a, b),
                Op::Unary(op, a) => v.set(out, unary(op, g(a))),
                Op::Binary(op, a, b, same) => v.set(out, binary(op, g(a), g(b), same)),
                Op::PowI(a, n) => v.set(out, powi_iv(g(a), n)),
                Op::Select(c, t, e) => v.set(out, select_iv(g(c), g(t), g(e))),
                Op::Blend(op, k) => v.set(out, blend_iv(op, self.blends[k as usize].map(g))),
                Op::Copy(a) => v.set(out, g(a)),
                Op::SinCos(a, s, c) => {
                    let (si, co) = sin_cos_pair(g(a));
                    v.set(s as usize, si);
                    v.set(c as usize, co);
                }
            }
        }
    }
}
