//! Test helpers shared by the evaluator tests: the reference walk's values
//! (see [`reference`](super::reference)) and random graph construction.

use super::Inputs;
use crate::graph::{Graph, NodeId, Tape};
use crate::ops::{BinaryOp, BlendOp, UnaryOp};
use proptest::prelude::*;

/// Every node's value at a point, as the bulk evaluators define it.
pub(crate) fn eval_point_all(tape: &Tape, p: [f64; 3], inputs: &Inputs) -> Vec<f64> {
    super::reference::eval_all(tape, p, inputs)
}

/// Output 0 at a point.
pub(crate) fn eval_point(tape: &Tape, p: [f64; 3], inputs: &Inputs) -> f64 {
    let v = eval_point_all(tape, p, inputs);
    v[tape.outputs[0].index()]
}

/// One instruction of a random graph: kind, three operand choices, a number.
pub(crate) type Instr = (u8, u16, u16, u16, f64);

/// Interesting constants.
pub(crate) fn constant() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -3.0..3.0f64,
        1 => Just(0.0),
        1 => Just(1.0),
        1 => Just(-1.0),
        1 => Just(2.0),
        1 => Just(1e-7),
        1 => Just(0.5),
        1 => Just(1e300),
        1 => Just(f64::INFINITY),
        1 => Just(-f64::INFINITY),
        1 => -40.0..40.0f64,
    ]
}

pub(crate) fn instrs(max: usize) -> impl Strategy<Value = Vec<Instr>> {
    prop::collection::vec(
        (
            any::<u8>(),
            any::<u16>(),
            any::<u16>(),
            any::<u16>(),
            constant(),
        ),
        1..max,
    )
}

/// Builds a random graph over x, y, z and a parameter; returns its last node.
pub(crate) fn build_random(g: &mut Graph, instrs: &[Instr]) -> NodeId {
    let mut pool = vec![g.x(0), g.x(1), g.x(2), g.param(0), g.constant(0.5)];
    for &(k, i, j, l, c) in instrs {
        let len = pool.len();
        let pick = |s: u16| {
            if s.is_multiple_of(3) {
                pool[s as usize % len]
            } else {
                pool[len - 1 - (s as usize / 3) % len.min(6)]
            }
        };
        let (a, b, d) = (pick(i), pick(j), pick(l));
        let k = k as usize % 52;
        let id = match k {
            0..=21 => g.unary(UnaryOp::ALL[k], a),
            22..=43 => g.binary(BinaryOp::ALL[k - 22], a, b),
            44 => g.pow_int(a, (c as i32).rem_euclid(9) - 4),
            45 => g.select(a, b, d),
            46 | 47 => {
                let e = pick(i.wrapping_add(j));
                let op = if k == 46 {
                    BlendOp::Union
                } else {
                    BlendOp::Inter
                };
                g.blend(op, [a, b, d, e, pick(l.wrapping_add(7))])
            }
            48 => g.constant(c),
            49 => g.check(a, b),
            // More of the modelling operations.
            50 => g.binary(BinaryOp::RUnion, a, b),
            _ => {
                let cc = g.constant(c);
                g.binary(BinaryOp::Mul, a, cc)
            }
        };
        pool.push(id);
    }
    *pool.last().unwrap()
}

/// A random box: centre and half-widths.
pub(crate) fn boxes() -> impl Strategy<Value = ([f64; 3], [f64; 3])> {
    let half = prop_oneof![
        1 => Just(0.0),
        2 => 1e-9..1e-3f64,
        4 => 0.01..2.0f64,
        1 => 2.0..50.0f64,
    ];
    (
        [-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64],
        [half.clone(), half.clone(), half],
    )
}

/// Fractions of a box: endpoints are favoured.
pub(crate) fn fracs(n: usize) -> impl Strategy<Value = Vec<[f64; 3]>> {
    let t = prop_oneof![1 => Just(0.0), 1 => Just(1.0), 1 => Just(0.5), 5 => 0.0..1.0f64];
    prop::collection::vec([t.clone(), t.clone(), t], n)
}

/// The point at fractions `t` of the box `lo..hi`.
pub(crate) fn at(lo: [f64; 3], hi: [f64; 3], t: [f64; 3]) -> [f64; 3] {
    let mut p = [0.0; 3];
    for k in 0..3 {
        let w = hi[k] - lo[k];
        p[k] = if w.is_finite() {
            (lo[k] + t[k] * w).clamp(lo[k], hi[k])
        } else if t[k] < 0.5 {
            lo[k]
        } else {
            hi[k]
        };
    }
    p
}

/// The box of a centre and half-widths, as corners.
pub(crate) fn corners_of(c: [f64; 3], h: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let mut lo = [0.0; 3];
    let mut hi = [0.0; 3];
    for k in 0..3 {
        lo[k] = c[k] - h[k];
        hi[k] = c[k] + h[k];
    }
    (lo, hi)
}

/// The M4 model, positive inside: an R-union chain of `n` spheres.
pub(crate) fn m4(g: &mut Graph, n: usize) -> NodeId {
    let (x, y, z) = (g.x(0), g.x(1), g.x(2));
    let r2 = g.constant(0.0625);
    let mut acc: Option<NodeId> = None;
    for i in 0..n {
        let t = 0.6 * i as f64;
        let c = [0.6 * t.cos(), 0.6 * t.sin(), -0.8 + 0.16 * i as f64];
        let mut sum = None;
        for (k, v) in [x, y, z].into_iter().enumerate() {
            let ck = g.constant(c[k]);
            let d = g.binary(BinaryOp::Sub, v, ck);
            let sq = g.pow_int(d, 2);
            sum = Some(match sum {
                None => sq,
                Some(s) => g.binary(BinaryOp::Add, s, sq),
            });
        }
        let s = g.binary(BinaryOp::Sub, r2, sum.unwrap());
        acc = Some(match acc {
            None => s,
            Some(a) => g.binary(BinaryOp::RUnion, a, s),
        });
    }
    acc.unwrap()
}
