//! Batch evaluation: many points at once, in `f64`.
//!
//! [`BatchEval`] compiles a [`Tape`] once into a register program and runs it
//! over blocks of [`LANES`] points stored as structure-of-arrays. Each
//! instruction is one tight loop over the lanes of a block (the operation is
//! chosen once per instruction, never per lane), which LLVM vectorises;
//! transcendental functions use the branch-free kernels of
//! [`simd_math`](super::simd_math).
//!
//! * **Uniform values** are constants, parameters, extra coordinates
//!   `x[4..]`, errors and every operation of uniform values only. They are
//!   computed once per call with scalar code, cached while the [`Inputs`]
//!   stay the same. They enter the program as scalar operands of binary
//!   operations, or as registers filled once per call where another
//!   operation needs them.
//! * **Registers** are allocated by last use: memory is
//!   O(live values × block), not O(tape × block).
//! * **Guards** of [`Node::Check`] are ignored (the value is the checked
//!   value), and nodes only guards need are not evaluated at all.
//! * **`sin a` and `cos a`** of one argument are one instruction (one
//!   argument reduction for both; the gyroid has three such pairs).
//! * **Gradients**: [`BatchEval::eval_grad`] runs the same program carrying
//!   the three partial derivatives along (forward-mode automatic
//!   differentiation), for many points at once.
//! * **Lines**: [`BatchEval::eval_lines`] evaluates points on lines parallel
//!   to a coordinate axis, such as the rays of an axis-aligned orthographic
//!   view or the rows of a sampled grid. The transcendental functions of the
//!   other two coordinates are computed once per line. On a grid of such
//!   lines, those of the axis coordinate are computed once per position.
//!   The bits are those of `eval`.
//!
//! ## Semantics
//! Every operation computes what [`ops`] computes, except that runtime errors
//! give NaN. They are [`Node::Error`], checked `/` with `|b| < 1e-6`, `sqrt`
//! of a negative number, `log` at or below 0, `tan` where `|cos| < 1e-6`,
//! `asin` and `acos` outside [-1, 1], HyperFun's `^` errors, and `b ^ n`
//! with `|b| < 1e-6` and `n <= 0`. Arithmetic, comparisons, `min`/`max`,
//! R-functions, blends, selects, rounding and integer powers are bit-exact;
//! `exp`, `log`, `logd`, `sin`, `cos`, `tan` and `atan` use the vectorised
//! kernels (≤ 2 ulp from `std`; `sin` and `cos` within about `2e-14` of the
//! value instead with [`Trig::Fast`]); the other functions call `std` per
//! lane.
//!
//! A select picks its branch by [`ops::truthy`] of the condition, lane by
//! lane: `|c| >= 1e-6`. A NaN condition is false (`|NaN| >= 1e-6` is false),
//! so it picks the else branch, as the scalar evaluator does.

mod compile;
mod grad;
mod lines;

use compile::compile;
pub use grad::GradRegs;

use super::simd_math as sm;
use super::Inputs;
use crate::graph::{Node, NodeId, Tape};
use crate::ops::{self, binary_ops, unary_ops, BinaryOp, BlendOp, UnaryOp, EPS};

/// Number of points per block.
pub const LANES: usize = 128;

/// How a [`BatchEval`] computes `sin` and `cos` of varying values.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Trig {
    /// Within an ulp of `std` ([`simd_math::sin`](super::simd_math::sin)):
    /// the point evaluator's values.
    #[default]
    Exact,
    /// Within about `2e-14` of the value
    /// ([`simd_math::sin_cos_fast`](super::simd_math::sin_cos_fast)), with
    /// about 30 % fewer instructions: for callers that need the field's
    /// sign and rough size, not its last bits (a ray caster's samples).
    /// Uniform values stay exact.
    Fast,
}

type Block = [f64; LANES];

#[inline(always)]
fn sel(c: bool, a: f64, b: f64) -> f64 {
    if c {
        a
    } else {
        b
    }
}

#[inline(always)]
fn bool_f(b: bool) -> f64 {
    sel(b, 1.0, 0.0)
}

/// A unary operation on one value, with errors as NaN; exactly what the
/// batch kernels compute lane by lane.
#[inline(always)]
pub fn unary_lane(op: UnaryOp, a: f64) -> f64 {
    match op {
        UnaryOp::Neg => -a,
        UnaryOp::Abs => a.abs(),
        // IEEE sqrt is NaN below 0 and keeps -0: the checked form agrees.
        UnaryOp::Sqrt | UnaryOp::SqrtF => a.sqrt(),
        UnaryOp::Exp => sm::exp(a),
        UnaryOp::Log => sel(a > 0.0, sm::ln(a), f64::NAN),
        UnaryOp::Logd => sel(a > 0.0, sm::log10(a), f64::NAN),
        UnaryOp::Sin => sm::sin(a),
        UnaryOp::Cos => sm::cos(a),
        UnaryOp::Tan => sm::tan_checked(a),
        // std is NaN outside [-1, 1], like the checked form's error.
        UnaryOp::Asin => a.asin(),
        UnaryOp::Acos => a.acos(),
        UnaryOp::Atan => sm::atan(a),
        UnaryOp::Sinh => a.sinh(),
        UnaryOp::Cosh => a.cosh(),
        UnaryOp::Tanh => a.tanh(),
        UnaryOp::Ceil => sm::ceil(a),
        UnaryOp::Floor => sm::floor(a),
        UnaryOp::Trunc => sm::trunc(a),
        UnaryOp::Frac => a - sm::trunc(a),
        // NaN is not truthy, so `not NaN` is 1.
        UnaryOp::Not => sel(a.abs() >= EPS, 0.0, 1.0),
        UnaryOp::RoundHalfUp => {
            let r = sm::ceil(a);
            sel(r - a > 0.5, r - 1.0, r)
        }
    }
}

/// A binary operation on one pair of values, with errors as NaN; exactly
/// what the batch kernels compute lane by lane.
#[inline(always)]
pub fn binary_lane(op: BinaryOp, a: f64, b: f64) -> f64 {
    match op {
        BinaryOp::Add => a + b,
        BinaryOp::Sub => a - b,
        BinaryOp::Mul => a * b,
        BinaryOp::Div => sel(b.abs() < EPS, f64::NAN, a / b),
        BinaryOp::DivF => a / b,
        BinaryOp::Pow => ops::hf_pow(a, b).unwrap_or(f64::NAN),
        BinaryOp::PowF => a.powf(b),
        BinaryOp::Min => sel(a < b, a, b),
        BinaryOp::Max => sel(a > b, a, b),
        BinaryOp::Atan2 => a.atan2(b),
        BinaryOp::Mod => ops::round_half_up(a) % ops::round_half_up(b),
        BinaryOp::RUnion => ops::r_union(a, b),
        BinaryOp::RInter => ops::r_inter(a, b),
        BinaryOp::RDiff => ops::r_diff(a, b),
        BinaryOp::Lt => bool_f(a < b),
        BinaryOp::Gt => bool_f(a > b),
        BinaryOp::Le => bool_f(a <= b),
        BinaryOp::Ge => bool_f(a >= b),
        BinaryOp::Eq => bool_f((a - b).abs() < EPS),
        BinaryOp::Ne => bool_f((a - b).abs() >= EPS),
        BinaryOp::And => bool_f((a.abs() >= EPS) & (b.abs() >= EPS)),
        BinaryOp::Or => bool_f((a.abs() >= EPS) | (b.abs() >= EPS)),
    }
}

/// [`ops::pow_int`] with errors as NaN.
#[inline]
fn pow_int_lane(b: f64, n: i32) -> f64 {
    ops::pow_int(b, n).unwrap_or(f64::NAN)
}

/// [`Node::Select`] on one lane.
#[inline(always)]
fn select_lane(c: f64, t: f64, e: f64) -> f64 {
    sel(c.abs() >= EPS, t, e)
}

/// A binary operand: a register or a uniform scalar.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Src {
    Reg(u32),
    Uni(u32),
}

#[derive(Clone, Copy, Debug)]
enum Instr {
    Unary(UnaryOp, u32, u32),
    Binary(BinaryOp, u32, Src, Src),
    PowI(u32, u32, i32),
    Select(u32, [u32; 3]),
    Blend(BlendOp, u32, [u32; 5]),
    /// `sin` into the first register and `cos` into the second, of the
    /// third (one argument reduction for both).
    SinCos(u32, u32, u32),
}

/// A compiled register program for a subset of the outputs.
#[derive(Clone, Debug)]
struct Program {
    instrs: Vec<Instr>,
    /// `(register, uniform)`: registers holding a broadcast uniform value.
    bcast: Vec<(u32, u32)>,
    outputs: Vec<Src>,
    /// Whether x, y, z (registers 0, 1, 2) are read.
    xyz: [bool; 3],
    regs: Vec<Block>,
    /// How `sin` and `cos` are computed (the evaluator's, set on each use).
    trig: Trig,
    /// The program split for lines along each axis (`axis`) and for grids
    /// along each axis (`3 + axis`), once asked for (see
    /// [`BatchEval::eval_lines`]; `Some(None)`: nothing worth splitting).
    lines: [Option<Option<Box<lines::LinePlan>>>; 6],
}

/// Where a tape node's value lives.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Loc {
    /// Uniform value number.
    Uni(u32),
    /// Varies per point.
    Var,
}

/// Evaluates a [`Tape`] at many points at once (see the module docs).
#[derive(Clone, Debug)]
pub struct BatchEval {
    tape: Tape,
    /// For each node, the node whose value it has (through `Check`s).
    alias: Vec<u32>,
    loc: Vec<Loc>,
    /// Uniform nodes in order, children renumbered to uniform numbers.
    uni_nodes: Vec<Node>,
    uni: Vec<f64>,
    uni_inputs: Option<Inputs>,
    first: Option<Program>,
    all: Option<Program>,
    /// The saved values of [`BatchEval::eval_lines`], kept for their
    /// capacity.
    line_slots: Vec<f64>,
    trig: Trig,
}

impl BatchEval {
    /// Compiles a tape.
    pub fn new(tape: &Tape) -> Self {
        let n = tape.nodes.len();
        let mut alias = Vec::with_capacity(n);
        let mut loc = Vec::with_capacity(n);
        let mut uni_nodes = Vec::new();
        for (i, node) in tape.nodes.iter().enumerate() {
            if let Node::Check(_, v) = *node {
                let r = alias[v.index()] as usize;
                alias.push(r as u32);
                loc.push(loc[r]);
                continue;
            }
            alias.push(i as u32);
            let res = |c: NodeId| alias[c.index()] as usize;
            let uniform = match *node {
                Node::X(k) => k >= 3,
                Node::Const(_) | Node::Param(_) | Node::Error(_) => true,
                _ => node.children().all(|c| loc[res(c)] != Loc::Var),
            };
            if uniform {
                let mapped = node.map_children(|c| match loc[res(c)] {
                    Loc::Uni(u) => NodeId(u),
                    Loc::Var => unreachable!("uniform node with a varying child"),
                });
                loc.push(Loc::Uni(uni_nodes.len() as u32));
                uni_nodes.push(mapped);
            } else {
                loc.push(Loc::Var);
            }
        }
        BatchEval {
            tape: tape.clone(),
            alias,
            loc,
            uni: vec![0.0; uni_nodes.len()],
            uni_nodes,
            uni_inputs: None,
            first: None,
            all: None,
            line_slots: Vec::new(),
            trig: Trig::Exact,
        }
    }

    /// Sets how `sin` and `cos` are computed from now on ([`Trig`]; the
    /// default is [`Trig::Exact`]).
    pub fn set_trig(&mut self, trig: Trig) {
        self.trig = trig;
    }

    /// How `sin` and `cos` are computed.
    pub fn trig(&self) -> Trig {
        self.trig
    }

    /// The tape this evaluator runs.
    pub fn tape(&self) -> &Tape {
        &self.tape
    }

    /// Number of instructions run per block for output 0 (uniform values
    /// excluded), and number of registers used.
    pub fn program_size(&mut self) -> (usize, usize) {
        let p = self.program(false);
        (p.instrs.len(), p.regs.len())
    }

    fn program(&mut self, all: bool) -> &mut Program {
        let slot = if all { &mut self.all } else { &mut self.first };
        if slot.is_none() {
            let outs: Vec<NodeId> = if all {
                self.tape.outputs.clone()
            } else {
                self.tape.outputs.iter().take(1).copied().collect()
            };
            *slot = Some(compile(&self.tape, &self.alias, &self.loc, &outs));
        }
        let prog = slot.as_mut().expect("compiled above");
        prog.trig = self.trig;
        prog
    }

    fn update_uniforms(&mut self, inputs: &Inputs) {
        // Bitwise comparison: -0.0 and 0.0 are different inputs, a NaN the
        // same as itself.
        let same = |a: &[f64], b: &[f64]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
        };
        if let Some(prev) = &self.uni_inputs {
            if same(&prev.params, &inputs.params) && same(&prev.extra_x, &inputs.extra_x) {
                return;
            }
        }
        for i in 0..self.uni_nodes.len() {
            let u = &self.uni;
            let g = |c: NodeId| u[c.index()];
            let v = match self.uni_nodes[i] {
                Node::Const(b) => f64::from_bits(b),
                Node::X(k) => inputs.extra_x(k),
                Node::Param(k) => inputs.param(k),
                Node::Error(_) => f64::NAN,
                Node::Unary(op, a) => unary_lane(op, g(a)),
                Node::Binary(op, a, b) => binary_lane(op, g(a), g(b)),
                Node::PowI(a, n) => pow_int_lane(g(a), n),
                Node::Select(c, t, e) => select_lane(g(c), g(t), g(e)),
                Node::Blend(op, a) => ops::blend(op, g(a[0]), g(a[1]), g(a[2]), g(a[3]), g(a[4])),
                Node::Check(_, v) => g(v),
            };
            self.uni[i] = v;
        }
        self.uni_inputs = Some(inputs.clone());
    }

    /// Evaluates output 0 at the points `(xs[i], ys[i], zs[i])` into `out[i]`.
    ///
    /// # Panics
    /// If the four slices differ in length.
    pub fn eval(&mut self, xs: &[f64], ys: &[f64], zs: &[f64], inputs: &Inputs, out: &mut [f64]) {
        assert!(
            xs.len() == out.len() && ys.len() == out.len() && zs.len() == out.len(),
            "BatchEval::eval: slices of different lengths"
        );
        self.update_uniforms(inputs);
        let uni = std::mem::take(&mut self.uni);
        let prog = self.program(false);
        run(prog, &uni, xs, ys, zs, &mut [out]);
        self.uni = uni;
    }

    /// Evaluates every output of the tape (the value, then the attributes)
    /// at the points; `outs[k]` is resized to the number of points and
    /// receives output `k`.
    ///
    /// # Panics
    /// If `xs`, `ys`, `zs` differ in length, or `outs` does not have one
    /// vector per tape output.
    pub fn eval_outputs(
        &mut self,
        xs: &[f64],
        ys: &[f64],
        zs: &[f64],
        inputs: &Inputs,
        outs: &mut [Vec<f64>],
    ) {
        let n = xs.len();
        assert!(
            ys.len() == n && zs.len() == n,
            "BatchEval::eval_outputs: slices of different lengths"
        );
        assert_eq!(
            outs.len(),
            self.tape.outputs.len(),
            "BatchEval::eval_outputs: one vector per output"
        );
        self.update_uniforms(inputs);
        let uni = std::mem::take(&mut self.uni);
        let prog = self.program(true);
        for o in outs.iter_mut() {
            o.clear();
            o.resize(n, 0.0);
        }
        let mut slices: Vec<&mut [f64]> = outs.iter_mut().map(|o| o.as_mut_slice()).collect();
        run(prog, &uni, xs, ys, zs, &mut slices);
        self.uni = uni;
    }

    /// Evaluates every output of the tape into `out`, output-major:
    /// `out[k·n + i]` is output `k` at point `i` (n points). The same values
    /// as [`BatchEval::eval_outputs`], written in place: a caller that keeps
    /// `out` between calls allocates nothing.
    ///
    /// # Panics
    /// If `xs`, `ys`, `zs` differ in length, or `out` is not one slot per
    /// output and point.
    pub fn eval_outputs_into(
        &mut self,
        xs: &[f64],
        ys: &[f64],
        zs: &[f64],
        inputs: &Inputs,
        out: &mut [f64],
    ) {
        let n = xs.len();
        let k = self.tape.outputs.len();
        assert!(
            ys.len() == n && zs.len() == n,
            "BatchEval::eval_outputs_into: slices of different lengths"
        );
        assert_eq!(
            out.len(),
            k * n,
            "BatchEval::eval_outputs_into: one slot per output and point"
        );
        if n == 0 {
            return;
        }
        self.update_uniforms(inputs);
        let uni = std::mem::take(&mut self.uni);
        let prog = self.program(true);
        let mut slices: Vec<&mut [f64]> = out.chunks_mut(n).collect();
        run(prog, &uni, xs, ys, zs, &mut slices);
        self.uni = uni;
    }
}

/// Three distinct registers at once, in the order given.
///
/// # Panics
/// If two of the indices are equal.
#[inline]
fn three_mut<T>(regs: &mut [T], idx: [u32; 3]) -> [&mut T; 3] {
    let [i, j, k] = idx.map(|r| r as usize);
    assert!(
        i != j && j != k && i != k,
        "three_mut: registers not distinct"
    );
    // Split at the largest, then at the middle one.
    let mut order = [(i, 0), (j, 1), (k, 2)];
    order.sort_unstable();
    let (rest, hi) = regs.split_at_mut(order[2].0);
    let (lo, mid) = rest.split_at_mut(order[1].0);
    let mut refs: [Option<&mut T>; 3] = [None, None, None];
    refs[order[0].1] = Some(&mut lo[order[0].0]);
    refs[order[1].1] = Some(&mut mid[0]);
    refs[order[2].1] = Some(&mut hi[0]);
    refs.map(|r| r.expect("each slot set once"))
}

/// Disjoint access to a destination register and `K` source registers
/// (sources may repeat but never equal the destination).
#[inline]
fn split<T, const K: usize>(regs: &mut [T], dst: u32, srcs: [u32; K]) -> (&mut T, [&T; K]) {
    let dst = dst as usize;
    let (lo, rest) = regs.split_at_mut(dst);
    let (d, hi) = rest.split_first_mut().expect("destination register exists");
    let (lo, hi): (&[T], &[T]) = (lo, hi);
    let s = srcs.map(|s| {
        let s = s as usize;
        if s < dst {
            &lo[s]
        } else {
            &hi[s - dst - 1]
        }
    });
    (d, s)
}

/// Fills the registers of broadcast uniforms (every lane).
fn run_header(prog: &mut Program, uni: &[f64]) {
    for &(r, u) in &prog.bcast {
        prog.regs[r as usize] = [uni[u as usize]; LANES];
    }
}

fn run(
    prog: &mut Program,
    uni: &[f64],
    xs: &[f64],
    ys: &[f64],
    zs: &[f64],
    outs: &mut [&mut [f64]],
) {
    let n = xs.len();
    run_header(prog, uni);
    let mut start = 0;
    while start < n {
        let m = LANES.min(n - start);
        load_block(prog, [xs, ys, zs], start, m);
        for ins in &prog.instrs {
            exec(ins, &mut prog.regs, uni, m, prog.trig);
        }
        store_block(prog, uni, outs, start, m);
        start += m;
    }
    fill_missing(prog, outs);
}

/// Loads the `m` points from `start` of `c` (x, y, z) into the coordinate
/// registers the program reads.
fn load_block(prog: &mut Program, c: [&[f64]; 3], start: usize, m: usize) {
    for (k, input) in c.into_iter().enumerate() {
        if prog.xyz[k] {
            prog.regs[k][..m].copy_from_slice(&input[start..start + m]);
        }
    }
}

/// Stores the block's outputs (lanes `..m`) at `start` in `outs`.
fn store_block(prog: &Program, uni: &[f64], outs: &mut [&mut [f64]], start: usize, m: usize) {
    for (o, src) in outs.iter_mut().zip(&prog.outputs) {
        let o = &mut o[start..start + m];
        match *src {
            Src::Reg(r) => o.copy_from_slice(&prog.regs[r as usize][..m]),
            Src::Uni(u) => o.fill(uni[u as usize]),
        }
    }
}

/// NaN into the outputs the program does not have.
fn fill_missing(prog: &Program, outs: &mut [&mut [f64]]) {
    for o in outs.iter_mut().skip(prog.outputs.len()) {
        o.fill(f64::NAN);
    }
}

/// A binary operand over the active lanes: a register slice or a scalar.
trait Operand: Copy {
    fn lanes(self) -> impl Iterator<Item = f64>;
}

impl Operand for &[f64] {
    #[inline(always)]
    fn lanes(self) -> impl Iterator<Item = f64> {
        self.iter().copied()
    }
}

impl Operand for f64 {
    #[inline(always)]
    fn lanes(self) -> impl Iterator<Item = f64> {
        std::iter::repeat(self)
    }
}

#[inline(always)]
fn zip2(d: &mut [f64], a: impl Operand, b: impl Operand, f: impl Fn(f64, f64) -> f64) {
    for ((o, x), y) in d.iter_mut().zip(a.lanes()).zip(b.lanes()) {
        *o = f(x, y);
    }
}

fn binary_kernel(op: BinaryOp, d: &mut [f64], a: impl Operand, b: impl Operand) {
    macro_rules! each {
        ($($v:ident),*) => {
            match op {
                $(BinaryOp::$v => zip2(d, a, b, |x, y| binary_lane(BinaryOp::$v, x, y)),)*
            }
        };
    }
    binary_ops!(each);
}

fn unary_kernel(op: UnaryOp, d: &mut [f64], a: &[f64], trig: Trig) {
    macro_rules! each {
        ($($v:ident),*) => {
            // Sin, Cos and Tan have slice kernels of their own: their
            // stamped-out arms below never run.
            #[allow(unreachable_patterns)]
            match op {
                UnaryOp::Sin if trig == Trig::Fast => sm::sin_fast_slice(a, d),
                UnaryOp::Cos if trig == Trig::Fast => sm::cos_fast_slice(a, d),
                UnaryOp::Sin => sm::sin_slice(a, d),
                UnaryOp::Cos => sm::cos_slice(a, d),
                UnaryOp::Tan => sm::tan_checked_slice(a, d),
                $(UnaryOp::$v => sm::map(a, d, |x| unary_lane(UnaryOp::$v, x)),)*
            }
        };
    }
    unary_ops!(each);
}

fn pow_int_kernel(d: &mut [f64], a: &[f64], n: i32) {
    let m = n.unsigned_abs();
    // The common squares and cubes in one pass: the same products, in the
    // same order, and the same zero test as the general path below.
    match n {
        2 => {
            for (o, &x) in d.iter_mut().zip(a) {
                *o = sel(x.abs() < EPS, 0.0, x * x);
            }
            return;
        }
        3 => {
            for (o, &x) in d.iter_mut().zip(a) {
                *o = sel(x.abs() < EPS, 0.0, x * x * x);
            }
            return;
        }
        _ => {}
    }
    if m == 0 {
        d.fill(1.0);
    } else if f64::from(m) <= ops::POW_LOOP_MAX {
        // 1.0 * b == b exactly, so start from b.
        d.copy_from_slice(a);
        for _ in 1..m {
            for (o, &x) in d.iter_mut().zip(a) {
                *o *= x;
            }
        }
    } else {
        sm::map(a, d, |x| x.powf(f64::from(m)));
    }
    if n < 0 {
        for o in d.iter_mut() {
            *o = 1.0 / *o;
        }
    }
    let z = if n <= 0 { f64::NAN } else { 0.0 };
    for (o, &x) in d.iter_mut().zip(a) {
        *o = sel(x.abs() < EPS, z, *o);
    }
}

#[inline(always)]
fn exec(ins: &Instr, regs: &mut [Block], uni: &[f64], m: usize, trig: Trig) {
    match *ins {
        Instr::Unary(op, dst, a) => {
            let (d, [a]) = split(regs, dst, [a]);
            unary_kernel(op, &mut d[..m], &a[..m], trig);
        }
        Instr::Binary(op, dst, a, b) => match (a, b) {
            (Src::Reg(a), Src::Reg(b)) => {
                let (d, [a, b]) = split(regs, dst, [a, b]);
                binary_kernel(op, &mut d[..m], &a[..m], &b[..m]);
            }
            (Src::Reg(a), Src::Uni(u)) => {
                let (d, [a]) = split(regs, dst, [a]);
                binary_kernel(op, &mut d[..m], &a[..m], uni[u as usize]);
            }
            (Src::Uni(u), Src::Reg(b)) => {
                let (d, [b]) = split(regs, dst, [b]);
                binary_kernel(op, &mut d[..m], uni[u as usize], &b[..m]);
            }
            (Src::Uni(u), Src::Uni(v)) => {
                let r = binary_lane(op, uni[u as usize], uni[v as usize]);
                regs[dst as usize][..m].fill(r);
            }
        },
        Instr::PowI(dst, a, n) => {
            let (d, [a]) = split(regs, dst, [a]);
            pow_int_kernel(&mut d[..m], &a[..m], n);
        }
        Instr::Select(dst, s) => {
            let (d, [c, t, e]) = split(regs, dst, s);
            for (((o, &c), &t), &e) in d[..m].iter_mut().zip(&c[..m]).zip(&t[..m]).zip(&e[..m]) {
                *o = select_lane(c, t, e);
            }
        }
        Instr::SinCos(ds, dc, a) => {
            // Three distinct registers (the destinations are allocated while
            // the operand is live).
            let [s, c, x] = three_mut(regs, [ds, dc, a]);
            match trig {
                Trig::Exact => sm::sincos_slice(&x[..m], &mut s[..m], &mut c[..m]),
                Trig::Fast => sm::sincos_fast_slice(&x[..m], &mut s[..m], &mut c[..m]),
            }
        }
        Instr::Blend(op, dst, s) => {
            let (d, [f1, f2, a0, a1, a2]) = split(regs, dst, s);
            let it = d[..m]
                .iter_mut()
                .zip(&f1[..m])
                .zip(&f2[..m])
                .zip(&a0[..m])
                .zip(&a1[..m])
                .zip(&a2[..m]);
            match op {
                BlendOp::Union => {
                    for (((((o, &f1), &f2), &a0), &a1), &a2) in it {
                        *o = ops::blend(BlendOp::Union, f1, f2, a0, a1, a2);
                    }
                }
                BlendOp::Inter => {
                    for (((((o, &f1), &f2), &a0), &a1), &a2) in it {
                        *o = ops::blend(BlendOp::Inter, f1, f2, a0, a1, a2);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::three_mut;

    #[test]
    fn three_mut_gives_the_registers_asked_for_in_order() {
        for idx in [
            [0, 1, 2],
            [0, 2, 1],
            [1, 0, 2],
            [1, 2, 0],
            [2, 0, 1],
            [2, 1, 0],
            [4, 0, 7],
        ] {
            let mut regs: Vec<u32> = (0..8).collect();
            let [a, b, c] = three_mut(&mut regs, idx);
            assert_eq!([*a, *b, *c], idx, "{idx:?}");
            (*a, *b, *c) = (100, 200, 300);
            for (k, v) in [100, 200, 300].into_iter().enumerate() {
                assert_eq!(regs[idx[k] as usize], v, "{idx:?}");
            }
        }
    }

    #[test]
    #[should_panic(expected = "not distinct")]
    fn three_mut_refuses_a_repeated_register() {
        let mut regs = [0u8; 4];
        let _ = three_mut(&mut regs, [1, 3, 1]);
    }
}
