//! frep's evaluators side by side, and its vectorised math against `std`.
//!
//! Run: `cargo bench -p frep-bench --bench evaluators` (extra arguments go
//! to criterion, e.g. a filter: `-- m3_gyroid`). Criterion ids:
//! - `evaluators/<model>/<batch|batch-grad|grad|point>`: the 32³ = 32,768
//!   cell centres of a grid over the anchor model's `-- bounds:` box
//!   (M1–M4). `batch` is `BatchEval::eval`, `batch-grad` is
//!   `BatchEval::eval_grad` (value and gradient, vectorised), `grad` is
//!   `GradEval::eval_batch` (value and gradient, one point at a time) and
//!   `point` is `PointEval`, once per point (the reference).
//! - `simd/<sin|cos|exp|ln|atan>/<vector|std>`: 65,536 arguments in
//!   `[-10, 10)`, `simd_math`'s slice functions against `std` per lane.
//!
//! These replace the ignored timing tests that frep-core kept before
//! (`batch_bench`, `interval_bench`); the interval figures are in the
//! `core` bench.

use criterion::{Criterion, Throughput};
use frep_core::eval::batch::{BatchEval, GradRegs};
use frep_core::eval::grad::{Grad, GradEval};
use frep_core::eval::simd_math as sm;
use frep_core::{Inputs, Model, PointEval, Tape};
use std::hint::black_box;
use std::time::Duration;

/// Grid points per axis (32,768 points).
const GRID: usize = 32;
/// Arguments per math-function call.
const MATH_N: usize = 1 << 16;

/// An anchor model: its name, tape and grid points.
struct Case {
    name: String,
    tape: Tape,
    points: [Vec<f64>; 3],
}

/// Cell centres of a `GRID³` grid over `b` (`x0, y0, z0, x1, y1, z1`).
fn grid(b: [f64; 6]) -> [Vec<f64>; 3] {
    let mut p: [Vec<f64>; 3] = Default::default();
    let at = |a: usize, i: usize| b[a] + (i as f64 + 0.5) * (b[a + 3] - b[a]) / GRID as f64;
    for k in 0..GRID {
        for j in 0..GRID {
            for i in 0..GRID {
                p[0].push(at(0, i));
                p[1].push(at(1, j));
                p[2].push(at(2, k));
            }
        }
    }
    p
}

/// The anchor models M1–M4 of `examples/`, those with a bounds line.
fn cases() -> Vec<Case> {
    frep_bench::example_sources("")
        .into_iter()
        .filter(|(file, _)| frep_bench::anchor_of(file).is_some())
        .filter_map(|(file, src)| {
            let bounds = frep_bench::bounds_line(&src)?;
            let tape = Model::compile(&src)
                .expect("an anchor model compiles")
                .tape();
            let name = file.trim_end_matches(".hf").to_string();
            Some(Case {
                name,
                tape,
                points: grid(bounds),
            })
        })
        .collect()
}

fn bench_evaluators(c: &mut Criterion, cases: &[Case]) {
    let inputs = Inputs::default();
    for case in cases {
        let [xs, ys, zs] = &case.points;
        let n = xs.len();
        let mut group = c.benchmark_group(format!("evaluators/{}", case.name));
        group.throughput(Throughput::Elements(n as u64));
        let mut batch = BatchEval::new(&case.tape);
        let mut out = vec![0.0; n];
        let mut gout = vec![Grad::default(); n];
        group.bench_function("batch", |b| {
            b.iter(|| {
                batch.eval(xs, ys, zs, &inputs, &mut out);
                black_box(out[n / 2])
            })
        });
        let mut regs = GradRegs::default();
        group.bench_function("batch-grad", |b| {
            b.iter(|| {
                batch.eval_grad(xs, ys, zs, &inputs, &mut regs, &mut gout);
                black_box(gout[n / 2])
            })
        });
        let mut grad = GradEval::new(&case.tape);
        group.bench_function("grad", |b| {
            b.iter(|| {
                grad.eval_batch(xs, ys, zs, &inputs, &mut gout);
                black_box(gout[n / 2])
            })
        });
        let mut point = PointEval::new(case.tape.clone());
        group.bench_function("point", |b| {
            b.iter(|| {
                let mut acc = 0.0;
                for i in 0..n {
                    acc += point.eval(xs[i], ys[i], zs[i], &inputs).unwrap_or(0.0);
                }
                black_box(acc)
            })
        });
        group.finish();
    }
}

fn bench_math(c: &mut Criterion) {
    let xs: Vec<f64> = (0..MATH_N)
        .map(|i| (i as f64 * 0.618_033_988_7) % 20.0 - 10.0)
        .collect();
    let mut out = vec![0.0; MATH_N];
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
    for (name, vector, std_fn) in rows {
        let mut group = c.benchmark_group(format!("simd/{name}"));
        group.throughput(Throughput::Elements(MATH_N as u64));
        group.bench_function("vector", |b| {
            b.iter(|| {
                vector(black_box(&xs), &mut out);
                black_box(out[0])
            })
        });
        group.bench_function("std", |b| {
            b.iter(|| {
                sm::map(black_box(&xs), &mut out, std_fn);
                black_box(out[0])
            })
        });
        group.finish();
    }
}

fn main() {
    let mut c = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2))
        .configure_from_args();
    bench_evaluators(&mut c, &cases());
    bench_math(&mut c);
    c.final_summary();
}
