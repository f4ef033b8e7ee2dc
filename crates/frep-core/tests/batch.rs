//! Batch and gradient evaluators against a straightforward scalar walk of
//! the tape with `ops::*`.

use frep_core::eval::batch::{binary_lane, unary_lane, BatchEval, GradRegs, Trig, LANES};
use frep_core::eval::grad::{Grad, GradEval};
use frep_core::eval::reference::{self as walk, ulps};
use frep_core::eval::Inputs;
use frep_core::ops::{self, BinaryOp, BlendOp, EvalError, UnaryOp};
use frep_core::{Graph, Node, NodeId, Tape};

use proptest::prelude::*;

/// The reference: every node in order with `ops::*`, errors as NaN, guards
/// ignored. Returns every output.
fn reference(tape: &Tape, p: [f64; 3], inputs: &Inputs) -> Vec<f64> {
    outputs(tape, p, inputs, walk::exact_unary, walk::exact_binary)
}

/// The same walk with the batch evaluator's lane functions (bit-exact
/// expectations for tapes with transcendental functions).
fn lane_walk(tape: &Tape, p: [f64; 3], inputs: &Inputs) -> Vec<f64> {
    outputs(tape, p, inputs, unary_lane, binary_lane)
}

fn outputs(
    tape: &Tape,
    p: [f64; 3],
    inputs: &Inputs,
    un: impl Fn(UnaryOp, f64) -> f64,
    bin: impl Fn(BinaryOp, f64, f64) -> f64,
) -> Vec<f64> {
    let mut v = Vec::new();
    walk::walk_into(tape, p, inputs, un, bin, &mut v);
    tape.outputs.iter().map(|o| v[o.index()]).collect()
}

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545F4914F6CDD1D)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn sym(&mut self, m: f64) -> f64 {
        (2.0 * self.unit() - 1.0) * m
    }
    /// A mix of ordinary values, special values and values near HyperFun's
    /// thresholds.
    fn value(&mut self) -> f64 {
        const SPECIAL: [f64; 22] = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            -0.5,
            2.5,
            -2.5,
            1e-6,
            -1e-6,
            9.999e-7,
            1e-7,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            5e-324,
            1e300,
            -1e300,
            3.0,
            7.0,
            1e7,
        ];
        match self.next() % 8 {
            0 => SPECIAL[(self.next() % SPECIAL.len() as u64) as usize],
            1 => self.sym(1000.0),
            2 => self.sym(8.0).round(),
            3 => f64::from_bits(self.next()),
            _ => self.sym(4.0),
        }
    }
}

/// Evaluates output 0 with the batch evaluator at the points.
fn batch(tape: &Tape, pts: &[[f64; 3]], inputs: &Inputs) -> Vec<f64> {
    let xs: Vec<f64> = pts.iter().map(|p| p[0]).collect();
    let ys: Vec<f64> = pts.iter().map(|p| p[1]).collect();
    let zs: Vec<f64> = pts.iter().map(|p| p[2]).collect();
    let mut out = vec![0.0; pts.len()];
    let mut be = BatchEval::new(tape);
    be.eval(&xs, &ys, &zs, inputs, &mut out);
    // A second call reuses the cached uniforms and registers.
    let mut out2 = vec![0.0; pts.len()];
    be.eval(&xs, &ys, &zs, inputs, &mut out2);
    assert!(out.iter().zip(&out2).all(|(a, b)| same(*a, *b)));
    out
}

fn points(rng: &mut Rng, n: usize) -> Vec<[f64; 3]> {
    (0..n)
        .map(|_| [rng.value(), rng.value(), rng.value()])
        .collect()
}

fn inputs(rng: &mut Rng) -> Inputs {
    Inputs {
        params: (0..3).map(|_| rng.value()).collect(),
        extra_x: vec![rng.sym(2.0)],
    }
}

/// Transcendental functions computed by the vectorised kernels.
fn approx_unary(op: UnaryOp) -> bool {
    matches!(
        op,
        UnaryOp::Exp
            | UnaryOp::Log
            | UnaryOp::Logd
            | UnaryOp::Sin
            | UnaryOp::Cos
            | UnaryOp::Tan
            | UnaryOp::Atan
    )
}

fn check_points(name: &str, tape: &Tape, pts: &[[f64; 3]], inp: &Inputs, max_ulps: u64) {
    let got = batch(tape, pts, inp);
    for (p, g) in pts.iter().zip(&got) {
        let want = reference(tape, *p, inp)[0];
        if name.starts_with("tan") {
            // The pole check |cos| < 1e-6 may flip on the last bit of cos.
            let c = p[0].cos().abs();
            if (c - ops::EPS).abs() < 1e-12 {
                continue;
            }
        }
        let u = ulps(*g, want);
        assert!(
            u <= max_ulps,
            "{name} at {p:?} {inp:?}: batch {g:e}, ops {want:e} ({u} ulp)"
        );
    }
}

#[test]
fn every_unary_op() {
    let mut rng = Rng(0x1111_2222_3333_4444);
    for op in UnaryOp::ALL {
        let tol = if approx_unary(op) { 2 } else { 0 };
        let mut g = Graph::new();
        let x = g.x(0);
        let a = g.param(0);
        let fx = g.unary(op, x);
        let fa = g.unary(op, a);
        let fx = g.tape(&[fx]);
        let fa = g.tape(&[fa]);
        for n in [1, 7, 129, 1000] {
            let pts = points(&mut rng, n);
            let inp = inputs(&mut rng);
            check_points(&format!("{}(x)", op.name()), &fx, &pts, &inp, tol);
            check_points(&format!("{}(a)", op.name()), &fa, &pts, &inp, tol);
        }
    }
}

#[test]
fn every_binary_op() {
    let mut rng = Rng(0x5555_6666_7777_8888);
    for op in BinaryOp::ALL {
        let mut g = Graph::new();
        let x = g.x(0);
        let y = g.x(1);
        let a = g.param(0);
        let c = g.constant(rng.sym(3.0));
        let roots = [
            g.binary(op, x, y),
            g.binary(op, x, a),
            g.binary(op, a, y),
            g.binary(op, x, x),
            g.binary(op, c, y),
            g.binary(op, a, c),
        ];
        for r in roots {
            let tape = g.tape(&[r]);
            for n in [1, 7, 129, 1000] {
                let pts = points(&mut rng, n);
                let inp = inputs(&mut rng);
                check_points(op.name(), &tape, &pts, &inp, 0);
            }
        }
    }
}

#[test]
fn other_nodes() {
    let mut rng = Rng(0x9999_aaaa_bbbb_cccc);
    let mut g = Graph::new();
    let x = g.x(0);
    let y = g.x(1);
    let z = g.x(2);
    let w = g.x(3);
    let a = g.param(0);
    let b = g.param(7); // missing: 0
    let k = g.constant(1.5);
    let e = g.error(EvalError::DivisionByZero);
    let s = g.unary(UnaryOp::Sqrt, x);
    let mut roots = vec![k, a, b, w, e, x, y, z];
    for n in [-5, -2, -1, 0, 1, 2, 3, 4, 7, 5000, -5000] {
        roots.push(g.pow_int(x, n));
        roots.push(g.pow_int(s, n));
    }
    roots.push(g.select(x, y, z));
    roots.push(g.select(x, a, z));
    roots.push(g.select(a, y, z));
    roots.push(g.select(x, k, a));
    roots.push(g.select(x, e, y));
    for op in [BlendOp::Union, BlendOp::Inter] {
        roots.push(g.blend(op, [x, y, z, a, k]));
        roots.push(g.blend(op, [x, y, a, z, k]));
        roots.push(g.blend(op, [x, y, z, x, y]));
    }
    // A check whose guard is unused elsewhere: ignored in bulk.
    let chk = g.check(s, y);
    assert!(matches!(g.node(chk), Node::Check(..)));
    roots.push(chk);
    let sum = g.binary(BinaryOp::Add, chk, z);
    roots.push(sum);
    let chk_u = g.check(s, a);
    roots.push(chk_u);
    for r in roots {
        let tape = g.tape(&[r]);
        for n in [1, 7, 129, 1000] {
            let pts = points(&mut rng, n);
            let inp = inputs(&mut rng);
            check_points(&format!("{:?}", g.node(r)), &tape, &pts, &inp, 0);
        }
    }
}

#[test]
fn empty_and_zero_points() {
    let mut g = Graph::new();
    let x = g.x(0);
    let tape = g.tape(&[x]);
    let mut be = BatchEval::new(&tape);
    be.eval(&[], &[], &[], &Inputs::default(), &mut []);
    be.eval_outputs_into(&[], &[], &[], &Inputs::default(), &mut []);
    let tape = Tape {
        nodes: vec![],
        outputs: vec![],
    };
    let mut be = BatchEval::new(&tape);
    let mut out = [0.0; 3];
    be.eval(
        &[1.0; 3],
        &[1.0; 3],
        &[1.0; 3],
        &Inputs::default(),
        &mut out,
    );
    assert!(out.iter().all(|v| v.is_nan()));
}

/// One random operation for [`build`].
#[derive(Clone, Debug)]
struct Op {
    kind: u8,
    sel: usize,
    args: [usize; 5],
    c: f64,
    n: i32,
}

fn op_strategy() -> impl Strategy<Value = Op> {
    (
        any::<u8>(),
        any::<usize>(),
        any::<[usize; 5]>(),
        -4.0..4.0f64,
        -4i32..6,
    )
        .prop_map(|(kind, sel, args, c, n)| Op {
            kind,
            sel,
            args,
            c,
            n,
        })
}

/// Builds a random graph; `full` allows every operation, otherwise only the
/// bit-exact ones (no vectorised transcendental function). Returns the tape
/// of the last two nodes.
fn build(ops_: &[Op], full: bool) -> Tape {
    let mut g = Graph::new();
    let mut pool = vec![g.x(0), g.x(1), g.x(2), g.param(0), g.param(1), g.x(3)];
    for o in ops_ {
        let a = |i: usize| pool[o.args[i] % pool.len()];
        let id = match o.kind % 16 {
            0 => g.constant(o.c),
            1 => g.error(EvalError::ALL[o.sel % EvalError::ALL.len()]),
            2..=4 => {
                let mut op = UnaryOp::ALL[o.sel % UnaryOp::ALL.len()];
                if !full && approx_unary(op) {
                    op = UnaryOp::Abs;
                }
                g.unary(op, a(0))
            }
            5..=10 => g.binary(BinaryOp::ALL[o.sel % BinaryOp::ALL.len()], a(0), a(1)),
            11 => g.pow_int(a(0), o.n),
            12 => g.select(a(0), a(1), a(2)),
            13 => g.blend(
                if o.sel % 2 == 0 {
                    BlendOp::Union
                } else {
                    BlendOp::Inter
                },
                [a(0), a(1), a(2), a(3), a(4)],
            ),
            14 => g.check(a(0), a(1)),
            _ => g.binary(BinaryOp::RUnion, a(0), a(1)),
        };
        pool.push(id);
    }
    let n = pool.len();
    g.tape(&[pool[n - 1], pool[n - 2]])
}

fn random_points(seed: u64, n: usize) -> (Vec<[f64; 3]>, Inputs) {
    let mut rng = Rng(seed | 1);
    (points(&mut rng, n), inputs(&mut rng))
}

fn check_all_outputs(
    tape: &Tape,
    pts: &[[f64; 3]],
    inp: &Inputs,
    r: impl Fn(&Tape, [f64; 3], &Inputs) -> Vec<f64>,
) {
    let xs: Vec<f64> = pts.iter().map(|p| p[0]).collect();
    let ys: Vec<f64> = pts.iter().map(|p| p[1]).collect();
    let zs: Vec<f64> = pts.iter().map(|p| p[2]).collect();
    let mut be = BatchEval::new(tape);
    let mut outs = vec![Vec::new(); tape.outputs.len()];
    be.eval_outputs(&xs, &ys, &zs, inp, &mut outs);
    let mut out0 = vec![0.0; pts.len()];
    be.eval(&xs, &ys, &zs, inp, &mut out0);
    // In place, output-major, over a buffer holding stale values.
    let n = pts.len();
    let mut flat = vec![f64::INFINITY; tape.outputs.len() * n];
    be.eval_outputs_into(&xs, &ys, &zs, inp, &mut flat);
    for (i, p) in pts.iter().enumerate() {
        let want = r(tape, *p, inp);
        for (k, w) in want.iter().enumerate() {
            assert!(
                same(outs[k][i], *w),
                "output {k} at {p:?}: batch {:e}, reference {w:e}\n{tape:?}",
                outs[k][i]
            );
            assert!(
                same(flat[k * n + i], *w),
                "in place, output {k} at {p:?}: {:e} vs {w:e}\n{tape:?}",
                flat[k * n + i]
            );
        }
        assert!(
            same(out0[i], want[0]),
            "eval at {p:?}: {:e} vs {:e}\n{tape:?}",
            out0[i],
            want[0]
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_exact_tapes(ops_ in prop::collection::vec(op_strategy(), 1..40), seed in any::<u64>(), n in prop::sample::select(vec![1usize, 7, 129, 1000])) {
        let tape = build(&ops_, false);
        let (pts, inp) = random_points(seed, n);
        check_all_outputs(&tape, &pts, &inp, reference);
    }

    #[test]
    fn random_full_tapes(ops_ in prop::collection::vec(op_strategy(), 1..40), seed in any::<u64>(), n in prop::sample::select(vec![1usize, 7, 129, 1000])) {
        let tape = build(&ops_, true);
        let (pts, inp) = random_points(seed, n);
        // Bit-exact against the lane functions...
        check_all_outputs(&tape, &pts, &inp, lane_walk);
        // ...and close to ops::* (errors of a few ulp may be amplified or
        // flip a comparison: require agreement at most points).
        let got = batch(&tape, &pts, &inp);
        let mut bad = 0;
        for (p, g) in pts.iter().zip(&got) {
            let w = reference(&tape, *p, &inp)[0];
            let ok = same(*g, w) || (g - w).abs() <= 1e-9 * w.abs().max(1e-300) || ulps(*g, w) <= 4;
            if !ok {
                bad += 1;
            }
        }
        prop_assert!(bad * 20 <= pts.len().max(20), "{bad} of {} points differ", pts.len());
    }
}

/// [`BatchEval::eval_lines`] at runs of `len` points along `axis` (the two
/// other coordinates random per run, the axis coordinate random per point;
/// the last run shorter when `short`) against [`BatchEval::eval`] at the
/// same points: the same bits, twice (the second call reuses the split
/// program), on the same evaluator as plain calls before and after; then
/// as a grid likewise, every run with the first run's axis values. `sin`
/// and `cos` as `trig` says.
fn check_lines(
    tape: &Tape,
    trig: Trig,
    seed: u64,
    axis: usize,
    runs: usize,
    len: usize,
    short: bool,
) {
    let mut rng = Rng(seed | 1);
    let inp = inputs(&mut rng);
    let n = (runs * len).saturating_sub(usize::from(short && len > 1));
    let fixed: [Vec<f64>; 2] = std::array::from_fn(|_| (0..runs).map(|_| rng.value()).collect());
    let along: Vec<f64> = (0..n).map(|_| rng.value()).collect();
    let mut c: [Vec<f64>; 3] = Default::default();
    let others: Vec<usize> = (0..3).filter(|&k| k != axis).collect();
    c[axis] = along.clone();
    for (j, &k) in others.iter().enumerate() {
        c[k] = (0..n).map(|i| fixed[j][i / len]).collect();
    }
    let mut be = BatchEval::new(tape);
    be.set_trig(trig);
    for grid in [false, true] {
        if grid {
            c[axis] = (0..n).map(|i| along[i % len]).collect();
        }
        let mut want = vec![0.0; n];
        be.eval(&c[0], &c[1], &c[2], &inp, &mut want);
        for round in 0..2 {
            let mut got = vec![0.0; n];
            be.eval_lines(axis, len, grid, &c[0], &c[1], &c[2], &inp, &mut got);
            for (i, (g, w)) in got.iter().zip(&want).enumerate() {
                assert!(
                    same(*g, *w),
                    "axis {axis}, grid {grid}, run {} of {runs}×{len}, point {i}, round {round}: lines {g:e}, eval {w:e}\n{tape:?}",
                    i / len
                );
            }
        }
        let mut again = vec![0.0; n];
        be.eval(&c[0], &c[1], &c[2], &inp, &mut again);
        assert!(again.iter().zip(&want).all(|(a, b)| same(*a, *b)));
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn lines_equal_points(ops_ in prop::collection::vec(op_strategy(), 1..40), seed in any::<u64>(), axis in 0usize..3, runs in prop::sample::select(vec![1usize, 3, 40, 200]), len in prop::sample::select(vec![1usize, 2, 7, 129]), short in any::<bool>()) {
        let tape = build(&ops_, true);
        check_lines(&tape, Trig::Exact, seed, axis, runs, len, short);
    }
}

/// A field whose parts depend on one axis, two, or none (a gyroid in a
/// ball, with a uniform term and a coordinate read raw by a dependent
/// operation), along every axis, in runs that do and do not fill blocks.
#[test]
fn lines_of_a_gyroid() {
    let mut g = Graph::new();
    let (x, y, z) = (g.x(0), g.x(1), g.x(2));
    let eight = g.constant(8.0);
    let [ax, ay, az] = [x, y, z].map(|c| g.binary(BinaryOp::Mul, eight, c));
    let [sx, sy, sz] = [ax, ay, az].map(|a| g.unary(UnaryOp::Sin, a));
    let [cx, cy, cz] = [ax, ay, az].map(|a| g.unary(UnaryOp::Cos, a));
    let t1 = g.binary(BinaryOp::Mul, sx, cy);
    let t2 = g.binary(BinaryOp::Mul, sy, cz);
    let t3 = g.binary(BinaryOp::Mul, sz, cx);
    let s = g.binary(BinaryOp::Add, t1, t2);
    let gy = g.binary(BinaryOp::Add, s, t3);
    let [qx, qy, qz] = [x, y, z].map(|c| g.pow_int(c, 2));
    let q = g.binary(BinaryOp::Add, qx, qy);
    let q = g.binary(BinaryOp::Add, q, qz);
    let r = g.unary(UnaryOp::Sqrt, q);
    let p = g.param(0);
    let ball = g.binary(BinaryOp::Sub, p, r);
    let xz = g.binary(BinaryOp::Mul, x, z);
    let ng = g.unary(UnaryOp::Neg, gy);
    let f = g.binary(BinaryOp::Min, ng, ball);
    let f = g.binary(BinaryOp::Add, f, xz);
    let tape = g.tape(&[f]);
    for trig in [Trig::Exact, Trig::Fast] {
        for axis in 0..3 {
            for (runs, len) in [(1, 1), (5, 9), (64, 2), (300, 7), (2, 200)] {
                for short in [false, true] {
                    check_lines(&tape, trig, 0x5eed + axis as u64, axis, runs, len, short);
                }
            }
        }
    }
    // Fields that do not depend on the axis at all, a constant one, and
    // one with nothing worth hoisting.
    for f in [sx, qx, eight, ball] {
        let tape = g.tape(&[f]);
        check_lines(&tape, Trig::Fast, 7, 2, 10, 3, true);
    }
}

/// `sin a` and `cos a` of one argument are computed together (one argument
/// reduction): the same bits as the lane functions, whichever comes first,
/// with the argument, a coordinate or a computed value, used again after
/// both, and with arguments beyond the vectorised range (1e7, ±∞, NaN).
#[test]
fn sin_and_cos_of_one_argument() {
    let mut g = Graph::new();
    let (x, y, z) = (g.x(0), g.x(1), g.x(2));
    let three = g.constant(3.0);
    let a = g.binary(BinaryOp::Mul, x, three);
    let sa = g.unary(UnaryOp::Sin, a);
    let ca = g.unary(UnaryOp::Cos, a);
    let cy = g.unary(UnaryOp::Cos, y);
    let sy = g.unary(UnaryOp::Sin, y);
    let sz = g.unary(UnaryOp::Sin, z);
    let css = g.unary(UnaryOp::Cos, sa);
    let sss = g.unary(UnaryOp::Sin, sa);
    let t1 = g.binary(BinaryOp::Mul, sa, ca);
    let t2 = g.binary(BinaryOp::Mul, cy, css);
    let t3 = g.binary(BinaryOp::Add, sy, sss);
    let t4 = g.binary(BinaryOp::Sub, a, sz);
    let s1 = g.binary(BinaryOp::Add, t1, t2);
    let s2 = g.binary(BinaryOp::Add, t3, t4);
    let out = g.binary(BinaryOp::Add, s1, s2);
    let tape = g.tape(&[out, ca]);
    // 15 varying operations, three pairs among them.
    assert_eq!(BatchEval::new(&tape).program_size().0, 12);
    let mut rng = Rng(0x9999_aaaa_bbbb_cccc);
    for n in [1, 7, 129, 1000] {
        let pts = points(&mut rng, n);
        let inp = inputs(&mut rng);
        check_all_outputs(&tape, &pts, &inp, lane_walk);
    }
}

#[test]
fn lanes_constant_is_reasonable() {
    const { assert!(LANES >= 8 && LANES.is_power_of_two()) };
}

// ------------------------------------------------------------------ gradients

fn fd_check(tape: &Tape, p: [f64; 3], inp: &Inputs) -> Option<()> {
    let mut ge = GradEval::new(tape);
    let gr = ge.eval(p[0], p[1], p[2], inp);
    let want_v = reference(tape, p, inp)[0];
    assert!(same(gr.v, want_v), "value {} vs {}", gr.v, want_v);
    if !gr.v.is_finite() {
        return None;
    }
    let f = |q: [f64; 3]| reference(tape, q, inp)[0];
    let all = Tape {
        nodes: tape.nodes.clone(),
        outputs: (0..tape.nodes.len() as u32).map(NodeId).collect(),
    };
    let big = reference(&all, p, inp)
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    for axis in 0..3 {
        let fd = |h: f64| {
            let mut a = p;
            let mut b = p;
            a[axis] += h;
            b[axis] -= h;
            (f(a) - f(b)) / (2.0 * h)
        };
        let (d1, d2) = (fd(1e-5), fd(2e-5));
        let ad = gr.gradient()[axis];
        let tol = 1e-4 * d1.abs().max(1.0);
        // Rounding noise of the difference quotient: cancellation anywhere
        // in the tape (e.g. an R-function of a huge and a small value).
        let noise = big * f64::EPSILON / 1e-5;
        if !d1.is_finite()
            || !d2.is_finite()
            || (d1 - d2).abs() > tol
            || noise > 1e-5 * ad.abs().max(1.0)
            || ad.abs() > 1e6
        // ill-conditioned (e.g. a saturated tanh of a steep value)
        {
            continue; // unstable here
        }
        assert!(
            (ad - d1).abs() <= 1e-3 * d1.abs().max(1.0),
            "axis {axis} at {p:?}: AD {ad}, FD {d1} ({d2})\n{tape:?}"
        );
    }
    Some(())
}

/// Smooth operations only.
fn build_smooth(ops_: &[Op]) -> Tape {
    let mut g = Graph::new();
    let mut pool = vec![g.x(0), g.x(1), g.x(2), g.param(0)];
    for o in ops_ {
        let a = |i: usize| pool[o.args[i] % pool.len()];
        let id = match o.kind % 12 {
            0 => g.constant(o.c),
            1 => {
                let op = [
                    UnaryOp::Sin,
                    UnaryOp::Cos,
                    UnaryOp::Atan,
                    UnaryOp::Neg,
                    UnaryOp::Tanh,
                ][o.sel % 5];
                g.unary(op, a(0))
            }
            2 => {
                // exp of a bounded value; sqrt / log of a positive one.
                let s = g.unary(UnaryOp::Sin, a(0));
                let op = [UnaryOp::Exp, UnaryOp::Sqrt, UnaryOp::Log, UnaryOp::Logd][o.sel % 4];
                let two = g.constant(2.0);
                let s = if op == UnaryOp::Exp {
                    s
                } else {
                    g.binary(BinaryOp::Add, s, two)
                };
                g.unary(op, s)
            }
            3..=6 => {
                let op = [
                    BinaryOp::Add,
                    BinaryOp::Sub,
                    BinaryOp::Mul,
                    BinaryOp::RUnion,
                    BinaryOp::RInter,
                    BinaryOp::RDiff,
                    BinaryOp::Min,
                    BinaryOp::Max,
                    BinaryOp::Atan2,
                ][o.sel % 9];
                g.binary(op, a(0), a(1))
            }
            7 => {
                // Of a bounded value, so that nested powers stay moderate.
                let t = g.unary(UnaryOp::Atan, a(0));
                g.pow_int(t, o.n.clamp(1, 4))
            }
            8 => {
                let c = g.constant(o.c.abs() + 1.0);
                let d = g.pow_int(a(1), 2);
                let den = g.binary(BinaryOp::Add, d, c);
                g.binary(
                    if o.sel % 2 == 0 {
                        BinaryOp::Div
                    } else {
                        BinaryOp::DivF
                    },
                    a(0),
                    den,
                )
            }
            9 => {
                let c = g.constant(o.c.abs() + 0.5);
                let e = g.constant(0.5 + o.c.abs() / 8.0);
                let sq = g.pow_int(a(0), 2);
                let b = g.binary(BinaryOp::Add, sq, c);
                g.binary(
                    if o.sel % 2 == 0 {
                        BinaryOp::Pow
                    } else {
                        BinaryOp::PowF
                    },
                    b,
                    e,
                )
            }
            10 => {
                let c1 = g.constant(o.c + 0.1);
                let c2 = g.constant(o.c.abs() + 0.5);
                g.blend(
                    if o.sel % 2 == 0 {
                        BlendOp::Union
                    } else {
                        BlendOp::Inter
                    },
                    [a(0), a(1), c1, c2, a(2)],
                )
            }
            _ => g.select(a(2), a(0), a(1)),
        };
        pool.push(id);
    }
    let n = pool.len();
    g.tape(&[pool[n - 1]])
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn gradients_match_finite_differences(ops_ in prop::collection::vec(op_strategy(), 1..25), seed in any::<u64>()) {
        let tape = build_smooth(&ops_);
        let mut rng = Rng(seed | 1);
        let inp = Inputs::with_params(&[rng.sym(2.0)]);
        for _ in 0..10 {
            let p = [rng.sym(2.0), rng.sym(2.0), rng.sym(2.0)];
            fd_check(&tape, p, &inp);
        }
    }
}

/// The tape of `op(x·y)`.
fn unary_of_product(op: UnaryOp) -> Tape {
    let mut g = Graph::new();
    let x = g.x(0);
    let y = g.x(1);
    let s = g.binary(BinaryOp::Mul, x, y);
    let r = g.unary(op, s);
    g.tape(&[r])
}

#[test]
fn gradient_of_every_op_matches_finite_differences() {
    let mut rng = Rng(0xabcdef);
    for op in UnaryOp::ALL {
        let tape = unary_of_product(op);
        for _ in 0..200 {
            fd_check(&tape, [rng.sym(1.5), rng.sym(1.5), 0.0], &Inputs::default());
        }
    }
    for op in BinaryOp::ALL {
        let mut g = Graph::new();
        let x = g.x(0);
        let y = g.x(1);
        let z = g.x(2);
        let s = g.binary(BinaryOp::Add, x, z);
        let r = g.binary(op, s, y);
        let tape = g.tape(&[r]);
        for _ in 0..200 {
            fd_check(
                &tape,
                [rng.sym(3.0), rng.sym(3.0), rng.sym(3.0)],
                &Inputs::default(),
            );
        }
    }
}

#[test]
fn analytic_gradients() {
    // Sphere 1 - x² - y² - z².
    let mut g = Graph::new();
    let (x, y, z) = (g.x(0), g.x(1), g.x(2));
    let one = g.constant(1.0);
    let sq = [x, y, z].map(|c| g.pow_int(c, 2));
    let s1 = g.binary(BinaryOp::Sub, one, sq[0]);
    let s2 = g.binary(BinaryOp::Sub, s1, sq[1]);
    let sphere = g.binary(BinaryOp::Sub, s2, sq[2]);
    let tape = g.tape(&[sphere]);
    let mut ge = GradEval::new(&tape);
    let r = ge.eval(0.3, -0.5, 2.0, &Inputs::default());
    assert_eq!(r.v, 1.0 - 0.09 - 0.25 - 4.0);
    assert_eq!(r.gradient(), [-0.6, 1.0, -4.0]);

    // R-union of two planes f1 = x, f2 = y: ∇ = (1 + x/r, 1 + y/r).
    let u = g.binary(BinaryOp::RUnion, x, y);
    let tape = g.tape(&[u]);
    let mut ge = GradEval::new(&tape);
    let r = ge.eval(3.0, 4.0, 7.0, &Inputs::default());
    assert_eq!(r.v, 12.0);
    assert_eq!(r.gradient(), [1.6, 1.8, 0.0]);
    // Convention at the origin.
    let r = ge.eval(0.0, 0.0, 0.0, &Inputs::default());
    assert_eq!(
        r,
        Grad {
            v: 0.0,
            dx: 1.0,
            dy: 1.0,
            dz: 0.0
        }
    );
    // R-intersection and R-difference.
    let i = g.binary(BinaryOp::RInter, x, y);
    let d = g.binary(BinaryOp::RDiff, x, y);
    let r = GradEval::new(&g.tape(&[i])).eval(3.0, 4.0, 0.0, &Inputs::default());
    assert_eq!(r.gradient(), [1.0 - 0.6, 1.0 - 0.8, 0.0]);
    let r = GradEval::new(&g.tape(&[d])).eval(3.0, 4.0, 0.0, &Inputs::default());
    assert_eq!(r.gradient(), [1.0 - 0.6, -1.0 - 0.8, 0.0]);

    // Errors give NaN; batch form agrees with the point form.
    let zero = g.constant(0.0);
    let dz = g.binary(BinaryOp::Div, x, z);
    let t = g.tape(&[dz]);
    let mut ge = GradEval::new(&t);
    assert!(ge.eval(1.0, 0.0, 0.0, &Inputs::default()).v.is_nan());
    let _ = zero;
    let xs = [1.0, 2.0, 3.0];
    let zs = [0.0, 2.0, 1e-7];
    let mut out = [Grad::default(); 3];
    ge.eval_batch(&xs, &xs, &zs, &Inputs::default(), &mut out);
    assert!(out[0].v.is_nan() && out[2].dx.is_nan());
    assert_eq!(
        out[1],
        Grad {
            v: 1.0,
            dx: 0.5,
            dy: 0.0,
            dz: -0.5
        }
    );
}

#[test]
fn uniform_cache_sees_signed_zero_and_changes() {
    let mut g = Graph::new();
    let x = g.x(0);
    let a = g.param(0);
    let one = g.constant(1.0);
    let inv = g.binary(BinaryOp::DivF, one, a);
    let f = g.binary(BinaryOp::Add, x, inv);
    let tape = g.tape(&[f]);
    let mut be = BatchEval::new(&tape);
    let mut out = [0.0];
    be.eval(
        &[0.0],
        &[0.0],
        &[0.0],
        &Inputs::with_params(&[0.0]),
        &mut out,
    );
    assert_eq!(out[0], f64::INFINITY);
    be.eval(
        &[0.0],
        &[0.0],
        &[0.0],
        &Inputs::with_params(&[-0.0]),
        &mut out,
    );
    assert_eq!(out[0], f64::NEG_INFINITY);
    be.eval(
        &[0.0],
        &[0.0],
        &[0.0],
        &Inputs::with_params(&[4.0]),
        &mut out,
    );
    assert_eq!(out[0], 0.25);
}

#[test]
fn large_tapes_reuse_registers() {
    // A long chain of R-unions of spheres: few values live at any time.
    let mut g = Graph::new();
    let (x, y, z) = (g.x(0), g.x(1), g.x(2));
    let r2 = g.constant(0.01);
    let mut acc = None;
    for i in 0..1000 {
        let t = i as f64 * 0.37;
        let mut s = None;
        for (v, c) in [(x, t.cos()), (y, t.sin()), (z, (t * 0.3).cos())] {
            let cc = g.constant(c);
            let d = g.binary(BinaryOp::Sub, v, cc);
            let q = g.pow_int(d, 2);
            s = Some(match s {
                None => q,
                Some(p) => g.binary(BinaryOp::Add, p, q),
            });
        }
        let f = g.binary(BinaryOp::Sub, r2, s.expect("terms"));
        acc = Some(match acc {
            None => f,
            Some(p) => g.binary(BinaryOp::RUnion, p, f),
        });
    }
    let tape = g.tape(&[acc.expect("spheres")]);
    assert!(tape.len() > 10_000);
    let mut be = BatchEval::new(&tape);
    let (instrs, regs) = be.program_size();
    assert!(regs <= 8, "{instrs} instructions use {regs} registers");
    let mut rng = Rng(77);
    let pts: Vec<[f64; 3]> = (0..300)
        .map(|_| [rng.sym(1.5), rng.sym(1.5), rng.sym(1.5)])
        .collect();
    let inp = Inputs::default();
    let got = batch(&tape, &pts, &inp);
    for (p, v) in pts.iter().zip(&got) {
        assert!(same(*v, reference(&tape, *p, &inp)[0]));
    }

    // Random wide tapes (many live values).
    let mut rng = Rng(99);
    for _ in 0..5 {
        let ops_: Vec<Op> = (0..3000)
            .map(|_| Op {
                kind: (rng.next() % 256) as u8,
                sel: rng.next() as usize,
                args: [0; 5].map(|_| rng.next() as usize),
                c: rng.sym(4.0),
                n: (rng.next() % 9) as i32 - 3,
            })
            .collect();
        let tape = build(&ops_, false);
        let (pts, inp) = random_points(rng.next(), 200);
        check_all_outputs(&tape, &pts, &inp, reference);
    }
}

// ------------------------------------------------- batched gradients

/// [`BatchEval::eval_grad`] at the points: values bit for bit those of
/// [`BatchEval::eval`]; derivatives those of [`GradEval`] (whose values come
/// from `std`, within 2 ulp of the batch kernels) within `1e-9` relative,
/// at all but `slack` of the points (a last-bit difference may flip a
/// comparison, a pick or a select).
fn check_grad(tape: &Tape, pts: &[[f64; 3]], inp: &Inputs, slack: f64) -> Result<(), String> {
    let xs: Vec<f64> = pts.iter().map(|p| p[0]).collect();
    let ys: Vec<f64> = pts.iter().map(|p| p[1]).collect();
    let zs: Vec<f64> = pts.iter().map(|p| p[2]).collect();
    let mut be = BatchEval::new(tape);
    let mut vals = vec![0.0; pts.len()];
    be.eval(&xs, &ys, &zs, inp, &mut vals);
    let mut grads = vec![Grad::default(); pts.len()];
    let mut regs = GradRegs::default();
    be.eval_grad(&xs, &ys, &zs, inp, &mut regs, &mut grads);
    // Again, with the registers of the first call (and their old values).
    let mut again = vec![Grad::default(); pts.len()];
    be.eval_grad(&xs, &ys, &zs, inp, &mut regs, &mut again);
    for (a, b) in grads.iter().zip(&again) {
        let s = |x: f64, y: f64| same(x, y);
        assert!(s(a.v, b.v) && s(a.dx, b.dx) && s(a.dy, b.dy) && s(a.dz, b.dz));
    }
    let mut ge = GradEval::new(tape);
    let mut bad = 0;
    let mut first_bad = String::new();
    for (i, p) in pts.iter().enumerate() {
        let g = grads[i];
        if !same(g.v, vals[i]) {
            return Err(format!(
                "value at {p:?}: {} vs eval {}\n{tape:?}",
                g.v, vals[i]
            ));
        }
        let w = ge.eval(p[0], p[1], p[2], inp);
        let close =
            |a: f64, b: f64| same(a, b) || (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
        // Values are the batch kernels' (checked against them above; where
        // they differ from `std`'s, e.g. `sin` of 1e188, other tests cover
        // it); the derivatives of a NaN or infinite value mean nothing; and
        // where GradEval's overflow (a huge argument squared in an
        // R-function), the order of the chain rule's products decides
        // between ±∞ and NaN.
        let finite = [w.dx, w.dy, w.dz].iter().all(|d| d.is_finite());
        let ok = !close(g.v, w.v)
            || !w.v.is_finite()
            || !finite
            || close(g.v, w.v) && close(g.dx, w.dx) && close(g.dy, w.dy) && close(g.dz, w.dz);
        if !ok {
            if bad == 0 {
                first_bad = format!("at {p:?}: batch {g:?}, GradEval {w:?}\n{tape:?}");
            }
            bad += 1;
        }
    }
    if bad as f64 > slack * pts.len() as f64 {
        return Err(format!(
            "{bad} of {} points differ; first {first_bad}",
            pts.len()
        ));
    }
    Ok(())
}

#[test]
fn batched_gradient_of_every_op() {
    let mut rng = Rng(0x6a6a_5b5b_4c4c_3d3d);
    for op in UnaryOp::ALL {
        let tape = unary_of_product(op);
        let pts: Vec<[f64; 3]> = (0..300)
            .map(|_| [rng.sym(1.5), rng.sym(1.5), 0.0])
            .collect();
        check_grad(&tape, &pts, &Inputs::default(), 0.0).unwrap();
    }
    for op in BinaryOp::ALL {
        let mut g = Graph::new();
        let x = g.x(0);
        let y = g.x(1);
        let z = g.x(2);
        let c = g.constant(0.7);
        let r = g.binary(op, x, y);
        let ru = g.binary(op, z, c);
        let ur = g.binary(op, c, z);
        let s = g.binary(BinaryOp::Add, r, ru);
        let s = g.binary(BinaryOp::Add, s, ur);
        let tape = g.tape(&[s]);
        let pts: Vec<[f64; 3]> = (0..300)
            .map(|_| [rng.sym(2.0), rng.sym(2.0), rng.sym(2.0)])
            .collect();
        check_grad(&tape, &pts, &Inputs::default(), 0.0).unwrap();
    }
    for (n, op) in [
        (1, None),
        (2, None),
        (3, None),
        (5, None),
        (-3, None),
        (0, None),
        (1, Some(BlendOp::Union)),
        (1, Some(BlendOp::Inter)),
    ] {
        let mut g = Graph::new();
        let x = g.x(0);
        let y = g.x(1);
        let z = g.x(2);
        let r = match op {
            None => g.pow_int(x, n),
            Some(op) => {
                let a0 = g.constant(0.3);
                let a1 = g.constant(0.8);
                g.blend(op, [x, y, a0, a1, z])
            }
        };
        let sel = g.select(z, r, y);
        let tape = g.tape(&[sel]);
        let pts: Vec<[f64; 3]> = (0..300)
            .map(|_| [rng.sym(2.0), rng.sym(2.0), rng.sym(2.0)])
            .collect();
        check_grad(&tape, &pts, &Inputs::default(), 0.0).unwrap();
    }
    // sin and cos of one argument (one instruction computes both).
    let mut g = Graph::new();
    let x = g.x(0);
    let y = g.x(1);
    let a = g.binary(BinaryOp::Mul, x, y);
    let s = g.unary(UnaryOp::Sin, a);
    let c = g.unary(UnaryOp::Cos, a);
    let r = g.binary(BinaryOp::Mul, s, c);
    let tape = g.tape(&[r]);
    let pts: Vec<[f64; 3]> = (0..300)
        .map(|_| [rng.sym(9.0), rng.sym(9.0), 0.0])
        .collect();
    check_grad(&tape, &pts, &Inputs::default(), 0.0).unwrap();
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn batched_gradients_of_smooth_tapes(ops_ in prop::collection::vec(op_strategy(), 1..25), seed in any::<u64>(), n in prop::sample::select(vec![1usize, 7, 129, 300])) {
        let tape = build_smooth(&ops_);
        let mut rng = Rng(seed | 1);
        let inp = Inputs::with_params(&[rng.sym(2.0)]);
        let pts: Vec<[f64; 3]> = (0..n).map(|_| [rng.sym(2.0), rng.sym(2.0), rng.sym(2.0)]).collect();
        prop_assert!(check_grad(&tape, &pts, &inp, 0.05).is_ok(), "{}", check_grad(&tape, &pts, &inp, 0.05).unwrap_err());
    }

    #[test]
    fn batched_gradients_of_any_tape(ops_ in prop::collection::vec(op_strategy(), 1..40), seed in any::<u64>(), n in prop::sample::select(vec![1usize, 7, 129, 300])) {
        let tape = build(&ops_, true);
        let (pts, inp) = random_points(seed, n);
        prop_assert!(check_grad(&tape, &pts, &inp, 0.1).is_ok(), "{}", check_grad(&tape, &pts, &inp, 0.1).unwrap_err());
    }
}

/// With [`Trig::Fast`] the gyroid's `sin`/`cos` pairs and a lone `sin` and
/// `cos` give values within `1e-12` of [`Trig::Exact`]'s (and not all the
/// same bits: the fast kernels are in use); the gradient evaluator's values
/// are the fast values bit for bit and its derivatives within `1e-10`;
/// set back to exact, the evaluator gives the exact bits again.
#[test]
fn fast_trig_stays_close() {
    let src = "my_model(x[3], a[1]) { my_model = sin(8 * x[1]) * cos(8 * x[2]) \
               + sin(8 * x[2]) * cos(8 * x[3]) + sin(8 * x[3]) * cos(8 * x[1]) \
               + cos(40 * x[1] * x[2]) - sin(x[3]); }";
    let tape = frep_core::Model::compile(src).unwrap().tape();
    let mut rng = Rng(0xfa57_7419);
    let n = 3000;
    let c: [Vec<f64>; 3] = std::array::from_fn(|_| (0..n).map(|_| rng.sym(3.0)).collect());
    let inp = Inputs::default();
    let mut be = BatchEval::new(&tape);
    assert_eq!(be.trig(), Trig::Exact, "exact by default");
    let mut exact = vec![0.0; n];
    be.eval(&c[0], &c[1], &c[2], &inp, &mut exact);
    let mut regs = GradRegs::default();
    let mut exact_g = vec![Grad::default(); n];
    be.eval_grad(&c[0], &c[1], &c[2], &inp, &mut regs, &mut exact_g);
    be.set_trig(Trig::Fast);
    let mut fast = vec![0.0; n];
    be.eval(&c[0], &c[1], &c[2], &inp, &mut fast);
    let mut fast_g = vec![Grad::default(); n];
    be.eval_grad(&c[0], &c[1], &c[2], &inp, &mut regs, &mut fast_g);
    let mut differ = 0;
    for i in 0..n {
        let e = (fast[i] - exact[i]).abs();
        assert!(
            e <= 1e-12,
            "point {i}: fast {:e}, exact {:e}",
            fast[i],
            exact[i]
        );
        differ += usize::from(fast[i].to_bits() != exact[i].to_bits());
        assert!(same(fast_g[i].v, fast[i]), "point {i}: gradient's value");
        for (a, b) in [
            (fast_g[i].dx, exact_g[i].dx),
            (fast_g[i].dy, exact_g[i].dy),
            (fast_g[i].dz, exact_g[i].dz),
        ] {
            assert!(
                (a - b).abs() <= 1e-10,
                "point {i}: derivative {a:e} vs {b:e}"
            );
        }
    }
    assert!(
        differ > n / 10,
        "only {differ} of {n} values differ in any bit"
    );
    be.set_trig(Trig::Exact);
    let mut again = vec![0.0; n];
    be.eval(&c[0], &c[1], &c[2], &inp, &mut again);
    assert!(again.iter().zip(&exact).all(|(a, b)| same(*a, *b)));
}
