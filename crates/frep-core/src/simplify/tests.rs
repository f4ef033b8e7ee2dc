//! Tests of tape simplification: values kept bit for bit, signs kept in
//! sign mode, and the choice keys.

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

fn octree(tape: &Tape, lo: [f64; 3], hi: [f64; 3], depth: u32, shorten: bool, st: &mut OctStats) {
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
