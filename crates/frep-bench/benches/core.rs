//! frep's kernel figures, and fidget's on the same models in the same run.
//!
//! Run: `scripts/bench-core.sh` (= `cargo bench -p frep-bench --features
//! anchors --bench core`). Without `--features anchors` only frep's figures
//! are measured. Criterion ids:
//! - `compile/<model>`: `Model::compile` and `Model::tape` of each example
//!   and of each file of the shared HyperFun corpus (when present);
//! - `batch/<model>/<frep|fidget-vm|fidget-jit>`: 100³ = 1,000,000 points
//!   (cell centres of a grid over the model's `-- bounds:` box), in slices of
//!   [`SLICE`] points; frep in `f64`, fidget in `f32`;
//! - `interval/<model>/<frep|fidget-vm|fidget-jit>`: the 16³ = 4096 cells of
//!   the same box, one interval evaluation each (no tape simplification).
//!
//! fidget evaluates the examples translated by `frep_bench::to_fidget`
//! (negated, R-functions expanded). Models it cannot express are skipped
//! with a note. After criterion, a plain table repeats the figures from a
//! quick loop of its own (the minimum of several repeats). It adds the
//! ratios frep / fidget: above 1, frep is faster.
//!
//! Environment: `FREP_HYPERFUN_CORPUS` (the corpus folder),
//! `FREP_BENCH_CRITERION=0` (table only), `FREP_BENCH_TABLE=0` (criterion only).

use criterion::{BenchmarkId, Criterion, Throughput};
use frep_core::eval::batch::BatchEval;
use frep_core::eval::interval::{Interval, IntervalEval};
use frep_core::{Inputs, Model, Tape};
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Points per bulk call, for frep and fidget alike: large enough that the
/// per-call overhead is negligible, small enough to stay in cache.
const SLICE: usize = 4096;
/// Grid points per axis for batch evaluation (1M points).
const GRID: usize = 100;
/// Cells per axis for interval evaluation (4096 boxes).
const CELLS: usize = 16;

/// A model file: its name, source and, for examples, its box.
struct Source {
    name: String,
    src: String,
    /// `x0, y0, z0, x1, y1, z1` from the `-- bounds:` line (examples only).
    bounds: Option<[f64; 6]>,
}

fn hf_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "hf"))
        .collect();
    files.sort();
    files
}

fn read_sources(dir: &Path) -> Vec<Source> {
    hf_files(dir)
        .into_iter()
        .filter_map(|p| {
            let src = std::fs::read_to_string(&p).ok()?;
            let name = p.file_stem()?.to_string_lossy().into_owned();
            let bounds = frep_bench::bounds_line(&src);
            Some(Source { name, src, bounds })
        })
        .collect()
}

/// The shared corpus: `$FREP_HYPERFUN_CORPUS`, else `shared/hyperfun/corpus`
/// beside the workspace (or one level further up, for a worktree).
fn corpus_dir() -> Option<PathBuf> {
    if let Some(dir) = std::env::var_os("FREP_HYPERFUN_CORPUS") {
        return Some(PathBuf::from(dir));
    }
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    [
        "../../../shared/hyperfun/corpus",
        "../../../../shared/hyperfun/corpus",
    ]
    .iter()
    .map(|rel| manifest.join(rel))
    .find(|p| p.is_dir())
}

/// A model that compiles, with its evaluation inputs.
struct Case {
    name: String,
    tape: Tape,
    /// Grid points over the box, `f64` (frep) and `f32` (fidget).
    points: [Vec<f64>; 3],
    #[cfg_attr(not(feature = "anchors"), allow(dead_code))]
    points32: [Vec<f32>; 3],
    /// The cells of the box, per axis `[lo, hi]`.
    boxes: Vec<[[f64; 2]; 3]>,
    /// fidget's translation, or why there is none.
    #[cfg(feature = "anchors")]
    tree: Result<fidget::context::Tree, String>,
}

fn grid(bounds: [f64; 6]) -> ([Vec<f64>; 3], Vec<[[f64; 2]; 3]>) {
    let lo = [bounds[0], bounds[1], bounds[2]];
    let hi = [bounds[3], bounds[4], bounds[5]];
    let coord =
        |axis: usize, i: usize, n: usize| lo[axis] + (hi[axis] - lo[axis]) * (i as f64 / n as f64);
    let mut pts: [Vec<f64>; 3] = Default::default();
    for k in 0..GRID {
        for j in 0..GRID {
            for i in 0..GRID {
                for (axis, idx) in [i, j, k].into_iter().enumerate() {
                    // Cell centres; rounded to f32 so that both kernels see
                    // exactly the same points.
                    let c = coord(axis, 2 * idx + 1, 2 * GRID);
                    pts[axis].push(f64::from(c as f32));
                }
            }
        }
    }
    let mut boxes = Vec::with_capacity(CELLS.pow(3));
    for k in 0..CELLS {
        for j in 0..CELLS {
            for i in 0..CELLS {
                let span = |axis: usize, idx: usize| {
                    [
                        f64::from(coord(axis, idx, CELLS) as f32),
                        f64::from(coord(axis, idx + 1, CELLS) as f32),
                    ]
                };
                boxes.push([span(0, i), span(1, j), span(2, k)]);
            }
        }
    }
    (pts, boxes)
}

fn cases(examples: &[Source]) -> Vec<Case> {
    let mut out = Vec::new();
    for s in examples {
        let Some(bounds) = s.bounds else {
            println!("note: {} has no `-- bounds:` line; not evaluated", s.name);
            continue;
        };
        let model = match Model::compile(&s.src) {
            Ok(m) => m,
            Err(d) => {
                println!("note: {} does not compile: {}", s.name, d.message);
                continue;
            }
        };
        let tape = model.tape();
        let (points, boxes) = grid(bounds);
        let points32 = points
            .clone()
            .map(|axis| axis.into_iter().map(|v| v as f32).collect());
        #[cfg(feature = "anchors")]
        let tree = frep_bench::to_fidget::tape_to_tree(&tape).map_err(|e| e.to_string());
        #[cfg(feature = "anchors")]
        if let Err(e) = &tree {
            println!("note: {}: no fidget translation ({e}); frep only", s.name);
        }
        out.push(Case {
            name: s.name.clone(),
            tape,
            points,
            points32,
            boxes,
            #[cfg(feature = "anchors")]
            tree,
        });
    }
    out
}

// ----- one pass of each measurement ------------------------------------------

fn frep_batch(eval: &mut BatchEval, [xs, ys, zs]: &[Vec<f64>; 3], out: &mut [f64]) -> f64 {
    let inputs = Inputs::default();
    let mut sum = 0.0;
    for (((x, y), z), o) in xs
        .chunks(SLICE)
        .zip(ys.chunks(SLICE))
        .zip(zs.chunks(SLICE))
        .zip(out.chunks_mut(SLICE))
    {
        eval.eval(x, y, z, &inputs, o);
        sum += o[0];
    }
    sum
}

fn frep_interval(eval: &mut IntervalEval, boxes: &[[[f64; 2]; 3]]) -> usize {
    let inputs = Inputs::default();
    let mut ambiguous = 0;
    for [x, y, z] in boxes {
        let v = eval.eval(
            Interval::new(x[0], x[1]),
            Interval::new(y[0], y[1]),
            Interval::new(z[0], z[1]),
            &inputs,
        );
        ambiguous += usize::from(v.contains(0.0));
    }
    ambiguous
}

#[cfg(feature = "anchors")]
mod fid {
    //! fidget's side: the same passes, generic over its VM and JIT.
    use super::SLICE;
    use fidget::context::Tree;
    use fidget::eval::{BulkEvaluator, Function, MathFunction, TracingEvaluator};
    use fidget::shape::{EzShape, Shape, ShapeBulkEval, ShapeTape, ShapeTracingEval};
    use fidget::types::Interval;

    /// A fidget shape ready for both evaluations.
    pub struct Fidget<F: Function + MathFunction + Clone> {
        slice_tape: ShapeTape<<F::FloatSliceEval as BulkEvaluator>::Tape>,
        slice_eval: ShapeBulkEval<F::FloatSliceEval>,
        interval_tape: ShapeTape<<F::IntervalEval as TracingEvaluator>::Tape>,
        interval_eval: ShapeTracingEval<F::IntervalEval>,
    }

    impl<F: Function + MathFunction + Clone> Fidget<F> {
        pub fn new(tree: &Tree) -> Self {
            let shape = Shape::<F>::from(tree.clone());
            Fidget {
                slice_tape: shape.ez_float_slice_tape(),
                slice_eval: Shape::<F>::new_float_slice_eval(),
                interval_tape: shape.ez_interval_tape(),
                interval_eval: Shape::<F>::new_interval_eval(),
            }
        }

        pub fn batch(&mut self, [xs, ys, zs]: &[Vec<f32>; 3]) -> f32 {
            let mut sum = 0.0;
            for ((x, y), z) in xs.chunks(SLICE).zip(ys.chunks(SLICE)).zip(zs.chunks(SLICE)) {
                let out = self
                    .slice_eval
                    .eval(&self.slice_tape, x, y, z)
                    .expect("fidget float slice evaluation");
                sum += out[0];
            }
            sum
        }

        pub fn interval(&mut self, boxes: &[[[f64; 2]; 3]]) -> usize {
            let mut ambiguous = 0;
            let iv = |r: [f64; 2]| Interval::new(r[0] as f32, r[1] as f32);
            for &[x, y, z] in boxes {
                let (v, _trace) = self
                    .interval_eval
                    .eval(&self.interval_tape, iv(x), iv(y), iv(z))
                    .expect("fidget interval evaluation");
                ambiguous += usize::from(v.lower() <= 0.0 && v.upper() >= 0.0);
            }
            ambiguous
        }
    }
}

// ----- criterion ---------------------------------------------------------------

fn bench_compile(c: &mut Criterion, sources: &[Source]) {
    let mut group = c.benchmark_group("compile");
    for s in sources {
        if let Err(d) = Model::compile(&s.src) {
            println!("note: {} does not compile: {}", s.name, d.message);
            continue;
        }
        group.bench_function(&s.name, |b| {
            b.iter(|| Model::compile(black_box(&s.src)).expect("compiles").tape())
        });
    }
    group.finish();
}

fn bench_eval(c: &mut Criterion, cases: &[Case]) {
    for case in cases {
        let mut group = c.benchmark_group(format!("batch/{}", case.name));
        group.throughput(Throughput::Elements(case.points[0].len() as u64));
        let mut eval = BatchEval::new(&case.tape);
        let mut out = vec![0.0; case.points[0].len()];
        group.bench_function("frep", |b| {
            b.iter(|| black_box(frep_batch(&mut eval, &case.points, &mut out)))
        });
        #[cfg(feature = "anchors")]
        if let Ok(tree) = &case.tree {
            let mut vm = fid::Fidget::<fidget::vm::VmFunction>::new(tree);
            group.bench_function("fidget-vm", |b| {
                b.iter(|| black_box(vm.batch(&case.points32)))
            });
            let mut jit = fid::Fidget::<fidget::jit::JitFunction>::new(tree);
            group.bench_function("fidget-jit", |b| {
                b.iter(|| black_box(jit.batch(&case.points32)))
            });
        }
        group.finish();

        let mut group = c.benchmark_group(format!("interval/{}", case.name));
        group.throughput(Throughput::Elements(case.boxes.len() as u64));
        let mut eval = IntervalEval::new(&case.tape);
        group.bench_function(BenchmarkId::from_parameter("frep"), |b| {
            b.iter(|| black_box(frep_interval(&mut eval, &case.boxes)))
        });
        #[cfg(feature = "anchors")]
        if let Ok(tree) = &case.tree {
            let mut vm = fid::Fidget::<fidget::vm::VmFunction>::new(tree);
            group.bench_function("fidget-vm", |b| {
                b.iter(|| black_box(vm.interval(&case.boxes)))
            });
            let mut jit = fid::Fidget::<fidget::jit::JitFunction>::new(tree);
            group.bench_function("fidget-jit", |b| {
                b.iter(|| black_box(jit.interval(&case.boxes)))
            });
        }
        group.finish();
    }
}

// ----- the plain table -------------------------------------------------------------

/// The fastest of several runs of `f` (at least 3, until 0.4 s or 20 runs).
fn best_of(mut f: impl FnMut()) -> Duration {
    best_of_each(&mut [&mut f])[0]
}

/// The fastest run of each of `fs`, run in interleaved rounds: at least 3,
/// until 0.4 s per function or 20 rounds. A load change on the machine then
/// affects all of them alike, and their ratios stay meaningful.
fn best_of_each(fs: &mut [&mut dyn FnMut()]) -> Vec<Duration> {
    fs.iter_mut().for_each(|f| f()); // warm-up
    let budget = Duration::from_millis(400) * fs.len() as u32;
    let start = Instant::now();
    let mut best = vec![Duration::MAX; fs.len()];
    let mut rounds = 0;
    while rounds < 3 || (rounds < 20 && start.elapsed() < budget) {
        for (f, b) in fs.iter_mut().zip(&mut best) {
            let t = Instant::now();
            f();
            *b = (*b).min(t.elapsed());
        }
        rounds += 1;
    }
    best
}

/// Millions of items per second.
fn rate(items: usize, t: Duration) -> f64 {
    items as f64 / t.as_secs_f64() / 1e6
}

fn fmt_opt(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".to_string(), |v| format!("{v:.digits$}"))
}

/// Evaluation figures of one model: frep, then fidget VM and JIT (if any).
struct Rates {
    frep: f64,
    vm: Option<f64>,
    jit: Option<f64>,
}

impl Rates {
    fn frep_only(frep: f64) -> Rates {
        Rates {
            frep,
            vm: None,
            jit: None,
        }
    }

    fn row(&self, name: &str, ops: usize) -> String {
        let ratio = |f: Option<f64>| f.map(|f| self.frep / f);
        format!(
            "{name:<22} {ops:>6} {:>10.2} {:>10} {:>10} {:>8} {:>8}",
            self.frep,
            fmt_opt(self.vm, 2),
            fmt_opt(self.jit, 2),
            fmt_opt(ratio(self.vm), 2),
            fmt_opt(ratio(self.jit), 2),
        )
    }
}

fn table(sources: &[Source], cases: &[Case]) {
    println!();
    println!("== compile (Model::compile + tape), min of repeats ==");
    println!("{:<68} {:>6} {:>10}", "model", "nodes", "µs");
    for s in sources {
        let Ok(model) = Model::compile(&s.src) else {
            continue;
        };
        let t = best_of(|| {
            black_box(Model::compile(black_box(&s.src)).expect("compiles").tape());
        });
        let nodes = model.tape().len();
        println!("{:<68} {nodes:>6} {:>10.1}", s.name, t.as_secs_f64() * 1e6);
    }

    let header = |what: &str, unit: &str| {
        println!();
        println!(
            "== {what}, {unit}/s (min of repeats); ratio = frep / fidget, > 1: frep faster =="
        );
        println!(
            "{:<22} {:>6} {:>10} {:>10} {:>10} {:>8} {:>8}",
            "model", "nodes", "frep", "fidget-vm", "fidget-jit", "/vm", "/jit"
        );
    };
    let mut batch = Vec::new();
    let mut interval = Vec::new();
    for case in cases {
        let (n, nb) = (case.points[0].len(), case.boxes.len());
        let mut eval = BatchEval::new(&case.tape);
        let mut out = vec![0.0; n];
        let mut ieval = IntervalEval::new(&case.tape);
        let mut frep_b = || {
            black_box(frep_batch(&mut eval, &case.points, &mut out));
        };
        let mut frep_i = || {
            black_box(frep_interval(&mut ieval, &case.boxes));
        };
        let (b, i);
        #[cfg(feature = "anchors")]
        {
            if let Ok(tree) = &case.tree {
                let mut vm = fid::Fidget::<fidget::vm::VmFunction>::new(tree);
                let mut jit = fid::Fidget::<fidget::jit::JitFunction>::new(tree);
                let t = best_of_each(&mut [
                    &mut frep_b,
                    &mut || {
                        black_box(vm.batch(&case.points32));
                    },
                    &mut || {
                        black_box(jit.batch(&case.points32));
                    },
                ]);
                b = Rates {
                    frep: rate(n, t[0]),
                    vm: Some(rate(n, t[1])),
                    jit: Some(rate(n, t[2])),
                };
                let t = best_of_each(&mut [
                    &mut frep_i,
                    &mut || {
                        black_box(vm.interval(&case.boxes));
                    },
                    &mut || {
                        black_box(jit.interval(&case.boxes));
                    },
                ]);
                i = Rates {
                    frep: rate(nb, t[0]),
                    vm: Some(rate(nb, t[1])),
                    jit: Some(rate(nb, t[2])),
                };
            } else {
                b = Rates::frep_only(rate(n, best_of(&mut frep_b)));
                i = Rates::frep_only(rate(nb, best_of(&mut frep_i)));
            }
        }
        #[cfg(not(feature = "anchors"))]
        {
            b = Rates::frep_only(rate(n, best_of(&mut frep_b)));
            i = Rates::frep_only(rate(nb, best_of(&mut frep_i)));
        }
        batch.push(b.row(&case.name, case.tape.len()));
        interval.push(i.row(&case.name, case.tape.len()));
    }
    header("batch, 1M points", "Mpoints");
    batch.iter().for_each(|r| println!("{r}"));
    header("interval, 4096 boxes", "Mboxes");
    interval.iter().for_each(|r| println!("{r}"));
    if cfg!(not(feature = "anchors")) {
        println!("(fidget columns: run with --features anchors)");
    }
}

fn main() {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let examples = read_sources(&manifest.join("../../examples"));
    let mut sources: Vec<Source> = examples
        .iter()
        .map(|s| Source {
            name: s.name.clone(),
            src: s.src.clone(),
            bounds: s.bounds,
        })
        .collect();
    match corpus_dir() {
        Some(dir) => sources.extend(read_sources(&dir).into_iter().map(|mut s| {
            s.name = format!("corpus/{}", s.name);
            s.bounds = None;
            s
        })),
        None => println!(
            "note: the shared HyperFun corpus is absent; compile figures of the examples only"
        ),
    }
    let cases = cases(&examples);

    let flag = |var: &str| std::env::var(var).map_or(true, |v| v != "0");
    // `cargo test --benches` runs this binary without `--bench`: one quick
    // pass of each criterion benchmark, no table.
    let bench_mode = std::env::args().any(|a| a == "--bench");
    if flag("FREP_BENCH_CRITERION") || !bench_mode {
        let mut c = Criterion::default()
            .sample_size(10)
            .warm_up_time(Duration::from_millis(500))
            .measurement_time(Duration::from_secs(2))
            .configure_from_args();
        bench_compile(&mut c, &sources);
        bench_eval(&mut c, &cases);
        c.final_summary();
    }
    if bench_mode && flag("FREP_BENCH_TABLE") {
        table(&sources, &cases);
    }
}
