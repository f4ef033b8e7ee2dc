//! Anchor figures: fidget's bulk (float slice) and interval evaluation of the
//! benchmark models M1–M4, with its interpreter (VM) and its JIT.
//!
//! Run: `cargo bench -p frep-bench --features anchors --bench fidget_eval`.
//! Ids read `fidget_eval/<what>/<backend>/<model>`:
//! - `float_slice_1M`: 100³ = 1,000,000 points (cell centres of a grid over
//!   `[-1, 1]³`), evaluated in slices of [`SLICE`] points;
//! - `interval_4096`: the 16³ = 4096 cells of the same box, one interval
//!   evaluation each (no tape simplification).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use fidget::eval::{Function, MathFunction};
use fidget::shape::{EzShape, Shape};
use fidget::types::Interval;
use frep_bench::{anchors, grid_boxes, grid_points};
use std::hint::black_box;
use std::time::Duration;

/// Points per bulk call. fidget's own renderers use small slices; 4096 keeps
/// the per-call overhead negligible while staying in cache.
const SLICE: usize = 4096;

fn float_slice<F: Function + MathFunction>(c: &mut Criterion, backend: &str) {
    let [xs, ys, zs] = grid_points(100);
    let mut group = c.benchmark_group("fidget_eval/float_slice_1M");
    group.throughput(Throughput::Elements(xs.len() as u64));
    for model in anchors::all() {
        let shape = Shape::<F>::from(model.tree);
        let tape = shape.ez_float_slice_tape();
        let mut eval = Shape::<F>::new_float_slice_eval();
        group.bench_function(BenchmarkId::new(backend, model.name), |b| {
            b.iter(|| {
                let mut sum = 0.0f32;
                for ((x, y), z) in xs.chunks(SLICE).zip(ys.chunks(SLICE)).zip(zs.chunks(SLICE)) {
                    let out = eval.eval(&tape, x, y, z).expect("float slice evaluation");
                    sum += out[0];
                }
                black_box(sum)
            })
        });
    }
    group.finish();
}

fn interval<F: Function + MathFunction>(c: &mut Criterion, backend: &str) {
    let boxes = grid_boxes(16);
    let mut group = c.benchmark_group("fidget_eval/interval_4096");
    group.throughput(Throughput::Elements(boxes.len() as u64));
    for model in anchors::all() {
        let shape = Shape::<F>::from(model.tree);
        let tape = shape.ez_interval_tape();
        let mut eval = Shape::<F>::new_interval_eval();
        group.bench_function(BenchmarkId::new(backend, model.name), |b| {
            b.iter(|| {
                let mut ambiguous = 0usize;
                for [x, y, z] in &boxes {
                    let (v, _trace) = eval
                        .eval(
                            &tape,
                            Interval::new(x[0], x[1]),
                            Interval::new(y[0], y[1]),
                            Interval::new(z[0], z[1]),
                        )
                        .expect("interval evaluation");
                    ambiguous += usize::from(v.lower() <= 0.0 && v.upper() >= 0.0);
                }
                black_box(ambiguous)
            })
        });
    }
    group.finish();
}

fn benches(c: &mut Criterion) {
    float_slice::<fidget::vm::VmFunction>(c, "vm");
    float_slice::<fidget::jit::JitFunction>(c, "jit");
    interval::<fidget::vm::VmFunction>(c, "vm");
    interval::<fidget::jit::JitFunction>(c, "jit");
}

criterion_group! {
    name = fidget_eval;
    // Few samples: these are anchor figures to compare against, not a
    // regression gate, and M4 in the VM takes a while per iteration.
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = benches
}
criterion_main!(fidget_eval);
