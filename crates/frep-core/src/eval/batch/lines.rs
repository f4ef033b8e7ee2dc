//! Batch evaluation of points on lines parallel to a coordinate axis
//! ([`BatchEval::eval_lines`]): the points come in runs that share two
//! coordinates (and, on a grid, every run has the same values of the third,
//! in the same order).
//!
//! An expensive operation is a transcendental function (see
//! [`expensive`]). One whose operands do not depend on the third
//! coordinate is computed once per run instead of once per point. On a
//! grid, one whose operands depend on the third coordinate only is computed
//! once per position in a run.
//! Cheap operations are recomputed per point: spreading a value over the
//! lanes costs about as much as recomputing an addition.
//!
//! The program is split once per axis and kind ([`LinePlan`]):
//! * the **run head**, the instructions that do not depend on the axis, run
//!   in order over one lane per run (the first point's coordinates); after
//!   each expensive one, its registers are saved in run slots;
//! * on a grid, the **depth head**, the instructions that depend on the axis
//!   coordinate only, over one lane per position in a run (the first run's
//!   values), saved in depth slots;
//! * the **steps**: every instruction in order, each expensive head one
//!   replaced by filling its registers from their slots. Registers are
//!   reused by the program, so a fill stands exactly where its instruction
//!   stood: between a write and its readers no other instruction writes the
//!   register.
//!
//! Every lane computes what [`BatchEval::eval`] computes at the same point
//! (the same operations on the same values): the results are the same bits.

use super::{
    exec, fill_missing, load_block, run, run_header, store_block, BatchEval, Block, Instr, Program,
    Src, LANES,
};
use crate::eval::Inputs;
use crate::ops::UnaryOp;

/// A program split for lines along one axis (see the module docs).
#[derive(Clone, Debug)]
pub(super) struct LinePlan {
    /// The run head: instruction indices, each with the run slots its
    /// destination registers are saved in (register, slot; none for a cheap
    /// one).
    runs: Vec<(u32, Vec<(u32, u32)>)>,
    /// The depth head (grids only), with depth slots.
    depths: Vec<(u32, Vec<(u32, u32)>)>,
    steps: Vec<Step>,
    run_slots: usize,
    depth_slots: usize,
}

#[derive(Clone, Copy, Debug)]
enum Step {
    Exec(u32),
    /// A register from a run slot.
    Run(u32, u32),
    /// A register from a depth slot.
    Depth(u32, u32),
}

/// What a value depends on: the axis coordinate, the two others.
#[derive(Clone, Copy, Default, PartialEq)]
struct Dep {
    axis: bool,
    fixed: bool,
}

fn sources(ins: &Instr) -> impl Iterator<Item = u32> {
    let (a, n): ([u32; 5], usize) = match *ins {
        Instr::Unary(_, _, a) | Instr::PowI(_, a, _) | Instr::SinCos(_, _, a) => {
            ([a, 0, 0, 0, 0], 1)
        }
        Instr::Binary(_, _, a, b) => {
            let mut r = [0; 5];
            let mut n = 0;
            for s in [a, b] {
                if let Src::Reg(x) = s {
                    r[n] = x;
                    n += 1;
                }
            }
            (r, n)
        }
        Instr::Select(_, s) => ([s[0], s[1], s[2], 0, 0], 3),
        Instr::Blend(_, _, s) => (s, 5),
    };
    a.into_iter().take(n)
}

fn destinations(ins: &Instr) -> impl Iterator<Item = u32> {
    let (d, n) = match *ins {
        Instr::SinCos(s, c, _) => ([s, c], 2),
        Instr::Unary(_, d, _)
        | Instr::Binary(_, d, _, _)
        | Instr::PowI(d, _, _)
        | Instr::Select(d, _)
        | Instr::Blend(_, d, _) => ([d, 0], 1),
    };
    d.into_iter().take(n)
}

/// Whether an instruction costs clearly more per lane than spreading its
/// result over the lanes (a gather): the transcendental functions.
fn expensive(ins: &Instr) -> bool {
    match *ins {
        Instr::SinCos(..) => true,
        Instr::Unary(op, ..) => matches!(
            op,
            UnaryOp::Exp
                | UnaryOp::Log
                | UnaryOp::Logd
                | UnaryOp::Sin
                | UnaryOp::Cos
                | UnaryOp::Tan
                | UnaryOp::Asin
                | UnaryOp::Acos
                | UnaryOp::Atan
                | UnaryOp::Sinh
                | UnaryOp::Cosh
                | UnaryOp::Tanh
        ),
        _ => false,
    }
}

/// The class of an instruction in a plan.
#[derive(Clone, Copy, PartialEq)]
enum Class {
    /// Does not depend on the axis coordinate (uniform operands only
    /// included: the compiler folds those, but should one come).
    Run,
    /// Depends on the axis coordinate only (grids).
    Depth,
    Point,
}

impl LinePlan {
    /// Splits `prog` for lines along `axis` (0, 1, 2: x, y, z); `grid`: the
    /// runs share their values of the axis coordinate. `None` where no
    /// expensive instruction can be hoisted (a plain run is as fast).
    pub(super) fn new(prog: &Program, axis: usize, grid: bool) -> Option<LinePlan> {
        let class = |d: Dep| match (d.axis, d.fixed) {
            (false, _) => Class::Run,
            (true, false) if grid => Class::Depth,
            _ => Class::Point,
        };
        let mut dep = vec![Dep::default(); prog.regs.len()];
        for (k, d) in dep.iter_mut().enumerate().take(3) {
            *d = Dep {
                axis: k == axis,
                fixed: k != axis,
            };
        }
        let (mut run_slots, mut depth_slots) = (0u32, 0u32);
        let (mut runs, mut depths, mut steps) = (Vec::new(), Vec::new(), Vec::new());
        let mut hoisted = false;
        for (i, ins) in prog.instrs.iter().enumerate() {
            let d = sources(ins).fold(Dep::default(), |d, r| {
                let o = dep[r as usize];
                Dep {
                    axis: d.axis || o.axis,
                    fixed: d.fixed || o.fixed,
                }
            });
            for o in destinations(ins) {
                dep[o as usize] = d;
            }
            let c = class(d);
            let i = i as u32;
            if c == Class::Point {
                steps.push(Step::Exec(i));
                continue;
            }
            if d == Dep::default() {
                // Uniform operands only: wherever it is read.
                runs.push((i, Vec::new()));
                depths.push((i, Vec::new()));
                steps.push(Step::Exec(i));
                continue;
            }
            let mut saves = Vec::new();
            if expensive(ins) {
                hoisted = true;
                for r in destinations(ins) {
                    if c == Class::Depth {
                        saves.push((r, depth_slots));
                        steps.push(Step::Depth(r, depth_slots));
                        depth_slots += 1;
                    } else {
                        saves.push((r, run_slots));
                        steps.push(Step::Run(r, run_slots));
                        run_slots += 1;
                    }
                }
            } else {
                steps.push(Step::Exec(i));
            }
            if c == Class::Depth {
                depths.push((i, saves));
            } else {
                runs.push((i, saves));
            }
        }
        // The heads need only what leads to a saved value, the steps only
        // what leads to the output (a cheap operand of a hoisted
        // instruction is not needed per point).
        let head = |(i, saves): &(u32, Vec<(u32, u32)>)| {
            (Use::Exec(&prog.instrs[*i as usize]), !saves.is_empty())
        };
        retain_live(prog, None, &mut runs, head);
        retain_live(prog, None, &mut depths, head);
        let out = match prog.outputs.first() {
            Some(Src::Reg(r)) => Some(*r),
            _ => None,
        };
        retain_live(prog, out, &mut steps, |s| match *s {
            Step::Exec(i) => (Use::Exec(&prog.instrs[i as usize]), false),
            Step::Run(r, _) | Step::Depth(r, _) => (Use::Fill(r), false),
        });
        hoisted.then_some(LinePlan {
            runs,
            depths,
            steps,
            run_slots: run_slots as usize,
            depth_slots: depth_slots as usize,
        })
    }
}

/// What an item of a head or of the steps does with the registers.
enum Use<'p> {
    Exec(&'p Instr),
    /// Writes the register (a fill from a slot).
    Fill(u32),
}

/// Keeps the items whose registers a later kept item reads (or that `out`
/// reads at the end), and those the view marks as needed anyway: a backward
/// pass over the registers as the items write and read them.
fn retain_live<'p, T>(
    prog: &'p Program,
    out: Option<u32>,
    items: &mut Vec<T>,
    view: impl Fn(&T) -> (Use<'p>, bool),
) {
    let mut live = vec![false; prog.regs.len()];
    if let Some(r) = out {
        live[r as usize] = true;
    }
    let mut keep = vec![false; items.len()];
    for (k, item) in items.iter().enumerate().rev() {
        let (u, needed) = view(item);
        let (writes, reads): (Vec<u32>, Vec<u32>) = match u {
            Use::Exec(ins) => (destinations(ins).collect(), sources(ins).collect()),
            Use::Fill(r) => (vec![r], Vec::new()),
        };
        keep[k] = needed || writes.iter().any(|&r| live[r as usize]);
        // Written here: readers before it read other values.
        for &r in &writes {
            live[r as usize] = false;
        }
        if keep[k] {
            for &r in &reads {
                live[r as usize] = true;
            }
        }
    }
    let mut k = 0;
    items.retain(|_| {
        k += 1;
        keep[k - 1]
    });
}

impl BatchEval {
    /// Evaluates output 0 at the points `(xs[i], ys[i], zs[i])` into
    /// `out[i]`, as [`BatchEval::eval`] does (the same bits).
    ///
    /// The points lie on lines parallel to coordinate axis `axis` (0, 1, 2:
    /// x, y, z). In every run of `len` points (the last may be shorter) the
    /// two other coordinates are the same bits. With `grid`, every run also
    /// has the first run's values of the axis coordinate, in the same order.
    /// Expensive functions of the two other coordinates are then computed
    /// once per run, and on a grid those of the axis coordinate once per
    /// position in a run (see the module docs).
    ///
    /// The points must have that shape; where they do not, each value is
    /// unspecified. Expensive operations read each run's first point, and on
    /// a grid the first run, while cheap ones read the point's own
    /// coordinates. Without a split plan every point is evaluated alone.
    ///
    /// # Panics
    /// If `axis > 2`, `len` is 0, or the four slices differ in length.
    #[allow(clippy::too_many_arguments)]
    pub fn eval_lines(
        &mut self,
        axis: usize,
        len: usize,
        grid: bool,
        xs: &[f64],
        ys: &[f64],
        zs: &[f64],
        inputs: &Inputs,
        out: &mut [f64],
    ) {
        assert!(axis < 3, "BatchEval::eval_lines: axis {axis}");
        assert!(len > 0, "BatchEval::eval_lines: empty runs");
        assert!(
            xs.len() == out.len() && ys.len() == out.len() && zs.len() == out.len(),
            "BatchEval::eval_lines: slices of different lengths"
        );
        self.update_uniforms(inputs);
        let uni = std::mem::take(&mut self.uni);
        let mut vals = std::mem::take(&mut self.line_slots);
        let prog = self.program(false);
        let k = axis + 3 * usize::from(grid);
        if prog.lines[k].is_none() {
            prog.lines[k] = Some(LinePlan::new(prog, axis, grid).map(Box::new));
        }
        let plan = prog.lines[k].as_mut().and_then(Option::take);
        match plan {
            Some(plan) => {
                let pts = Points {
                    axis,
                    len,
                    grid,
                    c: [xs, ys, zs],
                };
                run_lines(prog, &plan, &uni, &pts, out, &mut vals);
                prog.lines[k] = Some(Some(plan));
            }
            None => {
                prog.lines[k] = Some(None);
                run(prog, &uni, xs, ys, zs, &mut [out]);
            }
        }
        self.uni = uni;
        self.line_slots = vals;
    }
}

/// The points of one call (see [`BatchEval::eval_lines`]).
struct Points<'a> {
    axis: usize,
    len: usize,
    grid: bool,
    c: [&'a [f64]; 3],
}

/// Runs a head over `count` lanes, the input registers loaded by `load`
/// per block; saves into `vals` (slot `s` at `s·count..`).
fn run_head(
    prog: &mut Program,
    uni: &[f64],
    head: &[(u32, Vec<(u32, u32)>)],
    count: usize,
    vals: &mut [f64],
    load: impl Fn(&mut [Block], usize, usize),
) {
    let mut start = 0;
    while start < count {
        let m = LANES.min(count - start);
        load(&mut prog.regs, start, m);
        for (i, saves) in head {
            exec(&prog.instrs[*i as usize], &mut prog.regs, uni, m, prog.trig);
            for &(r, s) in saves {
                let o = s as usize * count + start;
                vals[o..o + m].copy_from_slice(&prog.regs[r as usize][..m]);
            }
        }
        start += m;
    }
}

fn run_lines(
    prog: &mut Program,
    plan: &LinePlan,
    uni: &[f64],
    pts: &Points,
    out: &mut [f64],
    vals: &mut Vec<f64>,
) {
    let (axis, len) = (pts.axis, pts.len);
    let n = out.len();
    let runs = n.div_ceil(len);
    let depths = len.min(n);
    run_header(prog, uni);
    // Every slot value is written by the heads before it is read: no
    // clearing. Run slots first, then depth slots.
    let (nr, nd) = (plan.run_slots * runs, plan.depth_slots * depths);
    if vals.len() < nr + nd {
        vals.resize(nr + nd, 0.0);
    }
    let (rv, dv) = vals[..nr + nd].split_at_mut(nr);
    let xyz = prog.xyz;
    // The run head on each run's first point; the depth head on the first
    // run's points.
    run_head(prog, uni, &plan.runs, runs, rv, |regs, start, m| {
        for (k, c) in pts.c.iter().enumerate() {
            if xyz[k] && k != axis {
                for (j, d) in regs[k][..m].iter_mut().enumerate() {
                    *d = c[(start + j) * len];
                }
            }
        }
    });
    if pts.grid {
        run_head(prog, uni, &plan.depths, depths, dv, |regs, start, m| {
            if xyz[axis] {
                regs[axis][..m].copy_from_slice(&pts.c[axis][start..start + m]);
            }
        });
    }
    let (rv, dv) = (&*rv, &*dv);
    // The steps, one lane per point; per block, each lane's run (from the
    // block's first) and position in its run, for the fills.
    let mut run_of = [0u32; LANES];
    let mut pos_of = [0u32; LANES];
    let mut start = 0;
    while start < n {
        let m = LANES.min(n - start);
        let first = start / len;
        let (mut run, mut pos) = (0u32, (start % len) as u32);
        for j in 0..m {
            run_of[j] = run;
            pos_of[j] = pos;
            pos += 1;
            if pos as usize == len {
                pos = 0;
                run += 1;
            }
        }
        load_block(prog, pts.c, start, m);
        for step in &plan.steps {
            match *step {
                Step::Exec(i) => exec(&prog.instrs[i as usize], &mut prog.regs, uni, m, prog.trig),
                Step::Run(r, s) => {
                    let v = &rv[s as usize * runs + first..(s as usize + 1) * runs];
                    gather(&mut prog.regs[r as usize][..m], v, &run_of[..m]);
                }
                Step::Depth(r, s) => {
                    let v = &dv[s as usize * depths..(s as usize + 1) * depths];
                    gather(&mut prog.regs[r as usize][..m], v, &pos_of[..m]);
                }
            }
        }
        store_block(prog, uni, &mut [&mut *out], start, m);
        start += m;
    }
    fill_missing(prog, &mut [out]);
}

/// `d[j] = v[at[j]]` for every lane (`at` is within `v`; clamped all the
/// same, which changes nothing and leaves no bounds check in the loop).
#[inline]
fn gather(d: &mut [f64], v: &[f64], at: &[u32]) {
    let Some(last) = v.len().checked_sub(1) else {
        return;
    };
    for (o, &k) in d.iter_mut().zip(at) {
        *o = v[(k as usize).min(last)];
    }
}
