//! Tests of the interval evaluator: containment of sampled values, rules,
//! ulp steps and choices.

use super::*;
use super::{arith::*, binary::*, eval::*, functions::*};
use crate::eval::testutil::*;
use crate::eval::{simd_math, Inputs};
use crate::graph::{Graph, Node, Tape};
use crate::ops::{self, BinaryOp, UnaryOp};
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

fn iv(lo: f64, hi: f64) -> Interval {
    Interval::new(lo, hi)
}

fn ivs(lo: [f64; 3], hi: [f64; 3]) -> [Interval; 3] {
    [iv(lo[0], hi[0]), iv(lo[1], hi[1]), iv(lo[2], hi[2])]
}

/// Every node's point value lies in its interval.
fn check_contains(tape: &Tape, lo: [f64; 3], hi: [f64; 3], pts: &[[f64; 3]], inputs: &Inputs) {
    let mut ev = IntervalEval::new(tape);
    let [x, y, z] = ivs(lo, hi);
    ev.eval(x, y, z, inputs);
    for &t in pts {
        let p = at(lo, hi, t);
        let vals = eval_point_all(tape, p, inputs);
        for (i, &v) in vals.iter().enumerate() {
            let r = ev.intervals()[i];
            assert!(
                r.contains(v),
                "node {i} {:?} = {v:e} at {p:?} outside {r:?}; args {:?}",
                tape.nodes[i],
                tape.nodes[i]
                    .children()
                    .map(|c| (vals[c.index()], ev.intervals()[c.index()]))
                    .collect::<Vec<_>>()
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]
    #[test]
    fn intervals_contain_point_values(
        ins in instrs(24),
        (c, h) in boxes(),
        pts in fracs(8),
        a0 in constant(),
    ) {
        let mut g = Graph::new();
        let out = build_random(&mut g, &ins);
        let tape = g.tape(&[out]);
        let (lo, hi) = corners_of(c, h);
        check_contains(&tape, lo, hi, &pts, &Inputs::with_params(&[a0]));
    }

    #[test]
    fn reevaluation_equals_a_fresh_evaluation(
        ins in instrs(24),
        seq in prop::collection::vec((boxes(), 0u8..16, constant()), 2..8),
    ) {
        // Boxes in a row, each keeping some of the last one's inputs
        // (bits of `keep`: x, y, z, the parameter): only the operations
        // of the changed ones run again, and every node's interval and
        // choice must be what a fresh evaluator gives.
        let mut g = Graph::new();
        let out = build_random(&mut g, &ins);
        let tape = g.tape(&[out]);
        let mut ev = IntervalEval::new(&tape);
        let (mut b, mut a0) = (ivs([0.0; 3], [0.0; 3]), 0.0);
        for (k, ((c, h), keep, p)) in seq.into_iter().enumerate() {
            let (lo, hi) = corners_of(c, h);
            let nb = ivs(lo, hi);
            for j in 0..3 {
                if k == 0 || keep & (1 << j) == 0 {
                    b[j] = nb[j];
                }
            }
            if k == 0 || keep & 8 == 0 {
                a0 = p;
            }
            let inputs = Inputs::with_params(&[a0]);
            ev.eval(b[0], b[1], b[2], &inputs);
            let mut fresh = IntervalEval::new(&tape);
            fresh.eval(b[0], b[1], b[2], &inputs);
            let bits = |v: &[Interval]| -> Vec<(u64, u64, bool)> {
                v.iter().map(|i| (i.lo.to_bits(), i.hi.to_bits(), i.nan)).collect()
            };
            prop_assert_eq!(bits(ev.intervals()), bits(fresh.intervals()), "box {}", k);
            prop_assert_eq!(ev.choices(), fresh.choices(), "box {}", k);
            // Node by node, as the whole list gives them.
            for (i, c) in fresh.choices().iter().enumerate() {
                prop_assert_eq!(ev.choice(i), *c, "node {} of box {}", i, k);
                prop_assert_eq!(ev.decided(i), c.decided, "node {} of box {}", i, k);
            }
        }
    }

    #[test]
    fn extremes_from_the_reduction_equal_those_by_division(
        lo in -2000.0..2000.0f64,
        w in prop_oneof![
            2 => 0.0..1e-6f64,
            4 => 0.0..2.0f64,
            4 => 1.0..7.0f64,
        ],
        near in any::<bool>(),
        k in -1000i32..1000,
        d in -1e-6..1e-6f64,
    ) {
        // Either end may sit next to a multiple of π/2.
        let lo = if near { f64::from(k) * FRAC_PI_2 + d } else { lo };
        for a in [iv(lo, lo + w), iv(lo - w, lo)] {
            let t = simd_math::sin_cos_ends(a.lo, a.hi).unwrap();
            let m = extreme_margin(a);
            let want = [0.0, FRAC_PI_2, PI, -FRAC_PI_2].map(|off| hits(a, off, 2.0 * PI));
            prop_assert_eq!(quarter_extremes(&t, m), want, "{:?}", a);
            let (s, c) = simd_math::sin_cos(a.lo);
            prop_assert_eq!((t.sin[0], t.cos[0]), (s, c));
        }
    }

    #[test]
    fn unary_and_binary_ops_on_random_intervals(
        a in (constant(), 0.0..4.0f64),
        b in (constant(), 0.0..4.0f64),
        ts in prop::collection::vec((0.0..1.0f64, 0.0..1.0f64), 6),
        n in -5i32..6,
    ) {
        // Each op alone over a box of its two arguments (x and y).
        let mut g = Graph::new();
        let (x, y) = (g.x(0), g.x(1));
        let mut outs = vec![];
        for op in UnaryOp::ALL {
            outs.push(g.unary(op, x));
        }
        for op in BinaryOp::ALL {
            outs.push(g.binary(op, x, y));
        }
        outs.push(g.pow_int(x, n));
        outs.push(g.binary(BinaryOp::Mul, x, x));
        let tape = g.tape(&outs);
        let lo = [a.0, b.0, 0.0];
        let hi = [a.0 + a.1, b.0 + b.1, 0.0];
        let pts: Vec<[f64; 3]> = ts.iter().map(|&(s, t)| [s, t, 0.0])
            .chain([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
            .collect();
        check_contains(&tape, lo, hi, &pts, &Inputs::default());
    }
}

#[test]
fn next_up_down() {
    assert_eq!(next_up(0.0), f64::from_bits(1));
    assert_eq!(next_up(-0.0), f64::from_bits(1));
    assert_eq!(next_down(0.0), -f64::from_bits(1));
    assert_eq!(next_up(1.0), 1.0 + f64::EPSILON);
    assert_eq!(next_down(1.0), 1.0 - f64::EPSILON / 2.0);
    assert_eq!(next_up(f64::INFINITY), f64::INFINITY);
    assert_eq!(next_up(f64::NEG_INFINITY), f64::MIN);
    assert_eq!(next_down(f64::INFINITY), f64::MAX);
}

#[test]
fn lazy_intervals_and_choices_follow_the_last_evaluation() {
    let mut g = Graph::new();
    let f = m4(&mut g, 4);
    let tape = g.tape(&[f]);
    let boxes = [
        ivs([0.8, -1.0, 0.8], [1.0, -0.8, 1.0]),
        ivs([-1.0; 3], [1.0; 3]),
        ivs([0.84, -0.01, -0.81], [0.86, 0.01, -0.79]),
    ];
    let mut ev = IntervalEval::new(&tape);
    let mut copy = ev.clone();
    for (k, b) in boxes.iter().enumerate() {
        let r = ev.eval(b[0], b[1], b[2], &Inputs::default());
        copy.eval(b[0], b[1], b[2], &Inputs::default());
        if k == 1 {
            // This box's results stay unread.
            continue;
        }
        let mut fresh = IntervalEval::new(&tape);
        fresh.eval(b[0], b[1], b[2], &Inputs::default());
        assert_eq!(ev.intervals()[tape.outputs[0].index()], r);
        assert_eq!(ev.intervals(), fresh.intervals());
        assert_eq!(ev.choices(), fresh.choices());
        assert_eq!(copy.choices(), fresh.choices());
        // A clone keeps the results read so far.
        assert_eq!(ev.clone().intervals(), fresh.intervals());
        assert_eq!(ev.clone().choices(), fresh.choices());
    }
}

#[test]
fn sin_and_cos_of_one_argument_together() {
    // sin(3x)·cos(3x) + cos(y)·cos(sin 3x) + sin(y) + sin(sin 3x) − sin z:
    // pairs at 3x, y and sin 3x (cos first at y), sin z alone.
    let mut g = Graph::new();
    let (x, y, z) = (g.x(0), g.x(1), g.x(2));
    let three = g.constant(3.0);
    let a = g.binary(BinaryOp::Mul, x, three);
    let cy = g.unary(UnaryOp::Cos, y);
    let sa = g.unary(UnaryOp::Sin, a);
    let ca = g.unary(UnaryOp::Cos, a);
    let sy = g.unary(UnaryOp::Sin, y);
    let sz = g.unary(UnaryOp::Sin, z);
    let css = g.unary(UnaryOp::Cos, sa);
    let sss = g.unary(UnaryOp::Sin, sa);
    let t1 = g.binary(BinaryOp::Mul, sa, ca);
    let t2 = g.binary(BinaryOp::Mul, cy, css);
    let t3 = g.binary(BinaryOp::Add, sy, sss);
    let t4 = g.binary(BinaryOp::Sub, t3, sz);
    let s1 = g.binary(BinaryOp::Add, t1, t2);
    let out = g.binary(BinaryOp::Add, s1, t4);
    let tape = g.tape(&[out]);
    let ev = IntervalEval::new(&tape);
    let pairs = ev
        .code
        .iter()
        .filter(|i| matches!(i.op, Op::SinCos(..)))
        .count();
    let singles = ev
        .code
        .iter()
        .filter(|i| matches!(i.op, Op::Unary(..)))
        .count();
    assert_eq!((pairs, singles), (3, 1));
    // Each node's interval is the one the op gives alone, over boxes
    // around extremes, wide, huge, unbounded and NaN-carrying.
    let mut ev = ev;
    let h = std::f64::consts::FRAC_PI_2;
    for b in [
        ivs([0.1, 0.2, 0.3], [0.2, 0.4, 0.5]),
        ivs(
            [h / 3.0 - 1e-9, h - 1e-9, -h],
            [h / 3.0 + 1e-9, h + 1e-9, h],
        ),
        ivs([-1.0, 3.0, 2.0], [1.0, 3.2, 9.0]),
        ivs([-10.0, -7.0, 0.0], [10.0, -6.9, 1e-300]),
        ivs([1e8, 1e12, 5.0], [1e8 + 0.5, 1e12 + 1.0, 5.0]),
        ivs([0.0, f64::NEG_INFINITY, 1.0], [f64::INFINITY, 0.0, 1.0]),
    ] {
        ev.eval(b[0], b[1], b[2], &Inputs::default());
        let v = ev.intervals();
        for (i, node) in tape.nodes.iter().enumerate() {
            if let Node::Unary(op, a) = *node {
                assert_eq!(v[i], unary(op, v[a.index()]), "node {i} over {b:?}");
            }
        }
        let lo = [b[0].lo, b[1].lo, b[2].lo];
        let hi = [b[0].hi, b[1].hi, b[2].hi];
        if lo.iter().chain(&hi).all(|c| c.is_finite()) {
            let pts: Vec<[f64; 3]> = (0..=4)
                .map(|k| [k as f64 / 4.0, 1.0 - k as f64 / 4.0, 0.5])
                .collect();
            check_contains(&tape, lo, hi, &pts, &Inputs::default());
        }
    }
}

#[test]
fn ulp_steps() {
    // The bit shortcut of `up`/`down` agrees with single steps.
    let tiny = f64::from_bits(1);
    for x in [
        0.0,
        -0.0,
        tiny,
        -tiny,
        f64::MIN_POSITIVE,
        -f64::MIN_POSITIVE,
        1.0,
        -1.0,
        0.3,
        -2.5e-300,
        1e300,
        -1e300,
        1.1e300,
        f64::MAX,
        -f64::MAX,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ] {
        for n in 0..6 {
            let (mut d, mut u) = (x, x);
            for _ in 0..n {
                d = next_down(d);
                u = next_up(u);
            }
            assert_eq!(down(x, n).to_bits(), d.to_bits(), "down({x:e}, {n})");
            assert_eq!(up(x, n).to_bits(), u.to_bits(), "up({x:e}, {n})");
        }
    }
}

#[test]
fn rules() {
    // sin finds its extrema; a monotone piece stays tight.
    let s = unary(UnaryOp::Sin, iv(0.0, 2.0));
    assert_eq!(s.hi, 1.0);
    assert!(s.lo <= 0.0 && s.lo > -1e-300);
    let s = unary(UnaryOp::Sin, iv(-0.5, 0.5));
    assert!((s.hi - 0.5f64.sin()).abs() < 1e-15 && !s.nan);
    let c = unary(UnaryOp::Cos, iv(3.0, 3.5));
    assert_eq!(c.lo, -1.0);
    assert!(!unary(UnaryOp::Sin, iv(0.0, f64::INFINITY)).is_empty());
    assert!(unary(UnaryOp::Sin, iv(0.0, f64::INFINITY)).nan);
    // Checked sqrt/log/div set nan on their error regions only.
    assert!(unary(UnaryOp::Sqrt, iv(-1.0, 4.0)).nan);
    assert_eq!(unary(UnaryOp::Sqrt, iv(1.0, 4.0)), iv(1.0, 2.0));
    assert!(unary(UnaryOp::Log, iv(0.0, 1.0)).nan);
    let d = binary(BinaryOp::Div, iv(1.0, 2.0), iv(-1.0, 2.0), false);
    assert!(d.nan && d.lo == -2e6 && d.hi == 2e6);
    let d = binary(BinaryOp::Div, iv(1.0, 2.0), iv(1.0, 2.0), false);
    assert_eq!(d, iv(0.5, 2.0));
    let d = binary(BinaryOp::DivF, iv(1.0, 2.0), iv(-1.0, 2.0), false);
    assert!(!d.nan && d.lo == f64::NEG_INFINITY && d.hi == f64::INFINITY);
    // tan: pole inside.
    assert_eq!(unary(UnaryOp::Tan, iv(1.0, 2.0)), Interval::ENTIRE);
    assert!(!unary(UnaryOp::Tan, iv(-1.0, 1.0)).nan);
    // Integer powers.
    assert_eq!(powi_iv(iv(-2.0, 3.0), 2), iv(0.0, 9.0));
    assert_eq!(powi_iv(iv(-2.0, 3.0), 3), iv(-8.0, 27.0));
    let p = powi_iv(iv(-2.0, 3.0), -1);
    assert!(p.nan && p.lo == -1e6 && p.hi == 1e6);
    assert_eq!(powi_iv(iv(2.0, 4.0), -2), iv(1.0 / 16.0, 0.25));
    assert!(!powi_iv(iv(-2.0, 3.0), 2).nan);
    // Comparisons and logic.
    let lt = binary(BinaryOp::Lt, iv(0.0, 1.0), iv(2.0, 3.0), false);
    assert_eq!(lt, Interval::point(1.0));
    let lt = binary(BinaryOp::Lt, iv(0.0, 2.5), iv(2.0, 3.0), false);
    assert_eq!(lt, iv(0.0, 1.0));
    assert_eq!(not_iv(Interval::NAN), Interval::point(1.0));
    // R-functions: the notes' example (a, b in [1, 2]).
    let r = rfun(BinaryOp::RInter, iv(1.0, 2.0), iv(1.0, 2.0));
    assert!((r.lo - (2.0 - 2f64.sqrt())).abs() < 1e-14);
    assert!((r.hi - (4.0 - 8f64.sqrt())).abs() < 1e-14);
    let r = rfun(BinaryOp::RDiff, iv(1.0, 2.0), iv(1.0, 2.0));
    assert!((r.lo - ops::r_diff(1.0, 2.0)).abs() < 1e-14);
    assert!((r.hi - ops::r_diff(2.0, 1.0)).abs() < 1e-14);
    // min with a NaN first argument returns the second.
    let m = min_iv(Interval::NAN, iv(1.0, 2.0));
    assert_eq!(m, iv(1.0, 2.0));
}

fn sample_range(tape: &Tape, lo: [f64; 3], hi: [f64; 3], n: usize) -> (f64, f64) {
    let mut r = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..=n {
        for j in 0..=n {
            for k in 0..=n {
                let t = [i, j, k].map(|v| v as f64 / n as f64);
                let v = eval_point(tape, at(lo, hi, t), &Inputs::default());
                r = (r.0.min(v), r.1.max(v));
            }
        }
    }
    r
}

#[test]
fn m4_decided_far_and_tight_near_the_surface() {
    let mut g = Graph::new();
    let f = m4(&mut g, 10);
    let tape = g.tape(&[f]);
    let mut ev = IntervalEval::new(&tape);
    // Far from every sphere.
    let r = ev.eval(
        iv(0.8, 1.0),
        iv(-1.0, -0.8),
        iv(0.8, 1.0),
        &Inputs::default(),
    );
    assert!(r.is_negative(), "{r:?}");
    // The whole box: undecided.
    let r = ev.eval(
        iv(-1.0, 1.0),
        iv(-1.0, 1.0),
        iv(-1.0, 1.0),
        &Inputs::default(),
    );
    assert!(!r.is_negative() && !r.is_positive());
    // A small box on the surface of sphere 0 at (0.85, 0, -0.8).
    for (c, h) in [
        ([0.85, 0.0, -0.8], 0.01),
        ([0.6, 0.0, -0.55], 0.02),
        ([0.3, 0.4, 0.0], 0.05),
    ] {
        let lo = c.map(|v| v - h);
        let hi = c.map(|v| v + h);
        let [x, y, z] = ivs(lo, hi);
        let r = ev.eval(x, y, z, &Inputs::default());
        let (slo, shi) = sample_range(&tape, lo, hi, 8);
        assert!(r.lo <= slo && shi <= r.hi);
        let ratio = r.width() / (shi - slo);
        assert!(
            ratio < 2.0,
            "box at {c:?}: {r:?} vs sampled [{slo}, {shi}], ratio {ratio}"
        );
    }
}
