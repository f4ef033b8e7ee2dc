//! Throughput of the batch evaluator against a per-point scalar walk of the
//! tape. Run with
//! `cargo test --release -p frep-core --test batch_bench -- --ignored --nocapture`.

mod common;

use std::time::Instant;

use frep_core::eval::batch::BatchEval;
use frep_core::eval::grad::{Grad, GradEval};
use frep_core::eval::Inputs;
use frep_core::ops::{BinaryOp, UnaryOp};
use frep_core::{Graph, NodeId, Tape};

use common::walk;

/// The straightforward per-point interpreter: one `match` per node per point.
fn scalar_walk(tape: &Tape, p: [f64; 3], inputs: &Inputs, v: &mut Vec<f64>) -> f64 {
    walk::walk_into(tape, p, inputs, walk::exact_unary, walk::exact_binary, v);
    v[tape.outputs[0].index()]
}

fn sq_dist(g: &mut Graph, c: [f64; 3]) -> NodeId {
    let mut acc = None;
    for (k, &ck) in c.iter().enumerate() {
        let x = g.x(k as u32);
        let cc = g.constant(ck);
        let d = g.binary(BinaryOp::Sub, x, cc);
        let s = g.pow_int(d, 2);
        acc = Some(match acc {
            None => s,
            Some(a) => g.binary(BinaryOp::Add, a, s),
        });
    }
    acc.expect("three terms")
}

/// M3: max(sin(8x)cos(8y) + sin(8y)cos(8z) + sin(8z)cos(8x), |p| - 0.9).
fn gyroid() -> Tape {
    let mut g = Graph::new();
    let eight = g.constant(8.0);
    let s: Vec<NodeId> = (0..3)
        .map(|k| {
            let x = g.x(k);
            g.binary(BinaryOp::Mul, x, eight)
        })
        .collect();
    let mut acc = None;
    for k in 0..3 {
        let a = g.unary(UnaryOp::Sin, s[k]);
        let b = g.unary(UnaryOp::Cos, s[(k + 1) % 3]);
        let t = g.binary(BinaryOp::Mul, a, b);
        acc = Some(match acc {
            None => t,
            Some(p) => g.binary(BinaryOp::Add, p, t),
        });
    }
    let r2 = sq_dist(&mut g, [0.0; 3]);
    let r = g.unary(UnaryOp::Sqrt, r2);
    let c = g.constant(0.9);
    let sph = g.binary(BinaryOp::Sub, r, c);
    let f = g.binary(BinaryOp::Max, acc.expect("terms"), sph);
    g.tape(&[f])
}

/// M4: R-intersection chain (negative inside) of 10 spheres.
fn r_chain() -> Tape {
    let mut g = Graph::new();
    let r2 = g.constant(0.0625);
    let mut acc = None;
    for i in 0..10 {
        let t = 0.6 * i as f64;
        let d = sq_dist(
            &mut g,
            [0.6 * t.cos(), 0.6 * t.sin(), -0.8 + 0.16 * i as f64],
        );
        let s = g.binary(BinaryOp::Sub, d, r2);
        acc = Some(match acc {
            None => s,
            Some(a) => g.binary(BinaryOp::RInter, a, s),
        });
    }
    g.tape(&[acc.expect("spheres")])
}

/// M2: min of 100 spheres.
fn min_spheres() -> Tape {
    let mut g = Graph::new();
    let rad = g.constant(0.2);
    let mut acc = None;
    for a in 0..5 {
        for b in 0..5 {
            for c in 0..4 {
                let d = sq_dist(
                    &mut g,
                    [
                        -0.72 + 0.36 * a as f64,
                        -0.72 + 0.36 * b as f64,
                        -0.54 + 0.36 * c as f64,
                    ],
                );
                let r = g.unary(UnaryOp::Sqrt, d);
                let s = g.binary(BinaryOp::Sub, r, rad);
                acc = Some(match acc {
                    None => s,
                    Some(p) => g.binary(BinaryOp::Min, p, s),
                });
            }
        }
    }
    g.tape(&[acc.expect("spheres")])
}

#[test]
#[ignore = "benchmark; run in release with --ignored --nocapture"]
fn throughput() {
    let n = 1 << 20;
    let mut state = 0x1234_5678_u64;
    let mut rnd = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    };
    let xs: Vec<f64> = (0..n).map(|_| rnd()).collect();
    let ys: Vec<f64> = (0..n).map(|_| rnd()).collect();
    let zs: Vec<f64> = (0..n).map(|_| rnd()).collect();
    let inputs = Inputs::default();
    for (name, tape) in [
        ("M3 gyroid", gyroid()),
        ("M4 R-chain", r_chain()),
        ("M2 100 spheres", min_spheres()),
    ] {
        let mut be = BatchEval::new(&tape);
        let (instrs, regs) = be.program_size();
        let mut out = vec![0.0; n];
        be.eval(&xs, &ys, &zs, &inputs, &mut out); // warm-up
        let reps = 5;
        let t = Instant::now();
        for _ in 0..reps {
            be.eval(&xs, &ys, &zs, &inputs, &mut out);
        }
        let batch = (reps * n) as f64 / t.elapsed().as_secs_f64();

        let mut v = Vec::new();
        let m = n / 4;
        let t = Instant::now();
        let mut max_diff: f64 = 0.0;
        for i in 0..m {
            let s = scalar_walk(&tape, [xs[i], ys[i], zs[i]], &inputs, &mut v);
            max_diff = max_diff.max((s - out[i]).abs() / s.abs().max(1.0));
        }
        let scalar = m as f64 / t.elapsed().as_secs_f64();

        let mut ge = GradEval::new(&tape);
        let mut gout = vec![Grad::default(); m];
        let t = Instant::now();
        ge.eval_batch(&xs[..m], &ys[..m], &zs[..m], &inputs, &mut gout);
        let grad = m as f64 / t.elapsed().as_secs_f64();

        eprintln!(
            "{name}: {} nodes, {instrs} instrs, {regs} regs; batch {:.1} Mpts/s, scalar walk {:.1} Mpts/s ({:.1}x), \
             grad {:.1} Mpts/s; max rel diff {max_diff:.1e}",
            tape.len(),
            batch / 1e6,
            scalar / 1e6,
            batch / scalar,
            grad / 1e6
        );
    }
}

#[test]
#[ignore = "benchmark; run in release with --ignored --nocapture"]
fn vector_math_throughput() {
    use frep_core::eval::simd_math as sm;
    let n = 1 << 16;
    let xs: Vec<f64> = (0..n)
        .map(|i| (i as f64 * 0.618_033_988_7) % 20.0 - 10.0)
        .collect();
    let mut out = vec![0.0; n];
    let reps = 100;
    let time = |f: &mut dyn FnMut(&[f64], &mut [f64]), out: &mut [f64]| {
        let t = Instant::now();
        for _ in 0..reps {
            f(&xs, out);
        }
        (reps * n) as f64 / t.elapsed().as_secs_f64() / 1e6
    };
    type SliceFn = fn(&[f64], &mut [f64]);
    type Row = (&'static str, SliceFn, fn(f64) -> f64);
    let rows: [Row; 5] = [
        ("sin", sm::sin_slice, f64::sin),
        ("cos", sm::cos_slice, f64::cos),
        ("exp", |a, o| sm::map(a, o, sm::exp), f64::exp),
        (
            "ln",
            |a, o| sm::map(a, o, |x| sm::ln(x.abs())),
            |x| x.abs().ln(),
        ),
        ("atan", |a, o| sm::map(a, o, sm::atan), f64::atan),
    ];
    for (name, vec_f, std_f) in rows {
        let v = time(&mut |a, o| vec_f(a, o), &mut out);
        let s = time(&mut |a, o| sm::map(a, o, std_f), &mut out);
        eprintln!(
            "{name}: vectorised {v:.0} M/s, std per lane {s:.0} M/s ({:.1}x)",
            v / s
        );
    }
}
