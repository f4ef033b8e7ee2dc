//! Render times of frep's ray caster (`frep_render::render`) on M1–M4 and
//! every example, at 512² and 1024², with 2 threads and 1 thread. Also the
//! peak heap beyond the image.
//!
//! With the `anchors` feature, fidget 0.5's 3D renderer (VM and JIT,
//! heightmap + normals) is timed in the same run. It renders M1–M4 from the
//! hand-written anchor trees, the other examples from `to_fidget`'s
//! translation of the same tape.
//!
//! Views:
//! - `top`: orthographic, looking down −z over `[-1, 1]³` (M1–M4) or over the
//!   cube of the example's box (longest side, around its centre). The square
//!   fills the image. This is what fidget's voxel render does natively, with
//!   depth = image width voxels. For an example, its tree is mapped from
//!   `[-1, 1]³` onto the cube. Ours renders the same view through an
//!   equivalent `Camera`, so the two columns compare like with like.
//! - `turn`: our usual turntable view (perspective, fov 30°, yaw 30°, pitch
//!   20°, framing the model box); ours only.
//!
//! `FREP_BENCH_STATS=1` also prints the caster's work counters per row.
//!
//! Timing:
//! - Each time is the minimum of at least `FREP_BENCH_REPS` runs (default 3;
//!   runs over 5 s are not repeated).
//! - Runs are repeated further until they took `FREP_BENCH_MIN_MS` in all
//!   (default 1000), ours and fidget's alike. So a fast render is sampled for
//!   as long as a slow one. That matters on a noisy machine: a short 2-thread
//!   render has fewer chances to run with both cores free.
//! - Our 2-thread top view and fidget's renders of the same row are measured
//!   in turns of about 50 ms each (`time_min_together`), not one after the
//!   other. A noisy stretch of the run then falls to both sides of the ratio
//!   alike.
//! - fidget's interpreter on M4 and on the examples is skipped unless
//!   `FREP_BENCH_SLOW=1`. On R-functions it takes minutes, per the notes.
//!
//! Run: `scripts/bench-render.sh` (or `cargo bench -p frep-bench --features
//! anchors --bench render`).

use frep_bench::alloc::{peak_during, Counting};
use std::time::{Duration, Instant};

use frep_core::Model;
use frep_render::{
    render_camera, render_with, Camera, CancelToken, ImagePool, ModelCaster, RenderSettings,
};

#[global_allocator]
static ALLOC: Counting = Counting;

fn reps() -> usize {
    std::env::var("FREP_BENCH_REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3)
        .max(1)
}

/// The least total time of the runs of one measurement, in ms.
fn min_ms() -> u64 {
    std::env::var("FREP_BENCH_MIN_MS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1000)
}

/// The minimum time of at least `reps()` runs and as many more as fit in
/// `min_ms()` in all (one run if it takes over 5 s).
fn time_min<F: FnMut()>(mut f: F) -> Duration {
    time_min_together(&mut [&mut f])[0]
}

/// How long each measurement of [`time_min_together`] runs at a turn
/// before the next one's turn.
const SLICE: Duration = Duration::from_millis(50);

/// [`time_min`] of several measurements at once, taken in turns of about
/// [`SLICE`] each (one run at least). Each is then sampled across the same
/// stretch of time. On a noisy machine the quiet moments fall to all of them
/// alike, and their ratio does not depend on which came first.
/// A measurement stops after `reps()` runs once its runs took `min_ms()`
/// in all, or after one run over 5 s; the others go on.
fn time_min_together(fs: &mut [&mut dyn FnMut()]) -> Vec<Duration> {
    let (reps, budget) = (reps(), Duration::from_millis(min_ms()));
    let mut best = vec![Duration::MAX; fs.len()];
    let mut runs = vec![0usize; fs.len()];
    let mut spent = vec![Duration::ZERO; fs.len()];
    let mut done = vec![false; fs.len()];
    while done.iter().any(|d| !d) {
        for (k, f) in fs.iter_mut().enumerate() {
            let turn = Instant::now();
            while !done[k] && turn.elapsed() < SLICE {
                let t = Instant::now();
                f();
                let d = t.elapsed();
                best[k] = best[k].min(d);
                runs[k] += 1;
                spent[k] += d;
                done[k] = d > Duration::from_secs(5) || (runs[k] >= reps && spent[k] >= budget);
            }
        }
    }
    best
}

use frep_bench::Args;

struct Row {
    name: String,
    size: u32,
    top: [Duration; 2],
    turn: [Duration; 2],
    peak_mib: f64,
    fidget: [Option<Duration>; 2],
}

fn ms(d: Duration) -> String {
    format!("{:.1}", d.as_secs_f64() * 1e3)
}

#[cfg(feature = "anchors")]
mod peer {
    use super::*;
    use fidget::jit::JitShape;
    use fidget::raster::voxel::{render, EvalConfig, RenderConfig};
    use fidget::render::{CancelToken, ThreadPool, VoxelSize};
    use fidget::shape::{BoundShape, Shape};

    fn run<F: fidget::eval::Function + fidget::render::RenderHints>(
        shape: Shape<F>,
        n: u32,
        threads: &ThreadPool,
    ) -> usize {
        let bound: BoundShape<F, f32> = shape.try_into().expect("no variables");
        let cfg = RenderConfig::from_size(VoxelSize::new(n, n, n));
        let eval = EvalConfig {
            tile_sizes: None,
            threads: Some(threads),
            cancel: CancelToken::new(),
        };
        let img = render(bound, &cfg, &eval).expect("not cancelled");
        img.iter().filter(|p| p.depth > 0).count()
    }

    /// fidget's tree for an example: the anchor tree for M1–M4 (`anchor` =
    /// 0..4), else `to_fidget`'s translation mapped onto the top view's cube.
    /// `None` where the model has an op fidget lacks.
    pub fn tree(
        model: &Model,
        anchor: Option<usize>,
        cube: ([f64; 3], f64),
    ) -> Option<fidget::context::Tree> {
        match anchor {
            Some(i) => Some(frep_bench::anchors::all().swap_remove(i).tree),
            None => frep_bench::to_fidget::tape_to_tree(&model.tape())
                .ok()
                .map(|t| frep_bench::to_fidget::in_cube(&t, cube)),
        }
    }

    /// fidget's JIT and VM render times of `tree` at `n`², 2 threads (the VM
    /// only with `vm`), measured in turns with `ours` (whose time comes
    /// first).
    pub fn times_beside(
        tree: &fidget::context::Tree,
        n: u32,
        vm: bool,
        ours: &mut dyn FnMut(),
    ) -> (Duration, [Option<Duration>; 2]) {
        let threads = ThreadPool::Custom(Args::pool(2));
        let mut jit = || {
            std::hint::black_box(run(JitShape::from(tree.clone()), n, &threads));
        };
        let mut interp = || {
            std::hint::black_box(run(fidget::vm::VmShape::from(tree.clone()), n, &threads));
        };
        if vm {
            let t = time_min_together(&mut [ours, &mut jit, &mut interp]);
            (t[0], [Some(t[1]), Some(t[2])])
        } else {
            let t = time_min_together(&mut [ours, &mut jit]);
            (t[0], [Some(t[1]), None])
        }
    }

    /// Pixels fidget sees as covered (for a sanity check against ours).
    pub fn coverage(tree: &fidget::context::Tree, n: u32) -> usize {
        run(
            JitShape::from(tree.clone()),
            n,
            &ThreadPool::Custom(Args::pool(2)),
        )
    }
}

fn main() {
    // `cargo bench` passes `--bench`; a name filter may follow.
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with("--"));
    let (p1, p2) = (Args::pool(1), Args::pool(2));
    // One image pool for all renders, as a server's worker pool owns one.
    let (cancel, images) = (CancelToken::new(), ImagePool::default());
    let mut rows = Vec::new();
    for (file, src) in frep_bench::example_sources(filter.as_deref().unwrap_or("")) {
        let model = Model::compile(&src).expect("example compiles");
        let bounds = frep_bench::example_box(&src);
        let anchor = frep_bench::anchor_of(&file);
        let cube = frep_bench::top_cube(&file, &src);
        #[cfg(feature = "anchors")]
        let peer_tree = peer::tree(&model, anchor, cube);
        // Sanity check that both sides see the same view: covered pixels at 256².
        #[cfg(feature = "anchors")]
        if let Some(t) = &peer_tree {
            let (cam, top_box) = frep_bench::top_view(cube);
            let caster = ModelCaster::new(&model, Default::default(), top_box);
            let ours =
                p2.install(|| frep_render::cast_tiled(&caster, &cam, 256, 256, 32).hit_count());
            eprintln!(
                "{file}: covered pixels at 256² top, ours {ours}, fidget {}",
                peer::coverage(t, 256)
            );
        }
        for size in [512u32, 1024] {
            let turn = RenderSettings {
                size: (size, size),
                bounds,
                ..Default::default()
            };
            let cam = turn.camera();
            // One render of ours, and its time (`time_min`).
            let render = |pool: &rayon::ThreadPool, s: &RenderSettings, c: &Camera| {
                let img = pool.install(|| render_camera(&model, s, c, &cancel, &images).unwrap());
                images.recycle(std::hint::black_box(img));
            };
            let run = |pool: &rayon::ThreadPool, s: &RenderSettings, c: &Camera| {
                time_min(|| render(pool, s, c))
            };
            let turn_t = [run(&p2, &turn, &cam), run(&p1, &turn, &cam)];
            if std::env::var_os("FREP_BENCH_STATS").is_some() {
                let caster = ModelCaster::new(&model, Default::default(), bounds);
                let t = Instant::now();
                p2.install(|| render_with(&caster, &turn, &cam, &cancel, &images).unwrap());
                eprintln!(
                    "{file} {size}² turn: {:?} {:?}",
                    t.elapsed(),
                    caster.stats()
                );
                let (top_cam, top_box) = frep_bench::top_view(cube);
                let top = RenderSettings {
                    size: (size, size),
                    bounds: top_box,
                    ..Default::default()
                };
                let caster = ModelCaster::new(&model, Default::default(), top.bounds);
                let t = Instant::now();
                p2.install(|| render_with(&caster, &top, &top_cam, &cancel, &images).unwrap());
                eprintln!("{file} {size}² top: {:?} {:?}", t.elapsed(), caster.stats());
            }
            // Peak heap of one 2-thread render, beyond the image (whose
            // bytes are new then: a pool that keeps nothing).
            let fresh = ImagePool::new(0);
            let (img, peak) = peak_during(|| {
                p2.install(|| render_camera(&model, &turn, &cam, &cancel, &fresh).unwrap())
            });
            let peak_mib = (peak as f64 - img.rgba.len() as f64) / (1u64 << 20) as f64;
            drop(img);
            let (c, top_box) = frep_bench::top_view(cube);
            let s = RenderSettings {
                size: (size, size),
                bounds: top_box,
                ..Default::default()
            };
            // fidget's VM takes minutes on R-function models (M4, the examples).
            let slow = std::env::var_os("FREP_BENCH_SLOW").is_some();
            let with_vm = slow || matches!(anchor, Some(0..=2));
            // Ours on 2 threads in turns with the peers (`time_min_together`).
            let mut ours = || render(&p2, &s, &c);
            #[cfg(feature = "anchors")]
            let (top2, fidget) = match &peer_tree {
                Some(t) => peer::times_beside(t, size, with_vm, &mut ours),
                None => (time_min(&mut ours), [None, None]),
            };
            #[cfg(not(feature = "anchors"))]
            let (top2, fidget) = {
                let _ = with_vm;
                (time_min(&mut ours), [None, None])
            };
            let top = [top2, run(&p1, &s, &c)];
            let row = Row {
                name: file.trim_end_matches(".hf").to_string(),
                size,
                top,
                turn: turn_t,
                peak_mib,
                fidget,
            };
            print_row(&row);
            rows.push(row);
        }
    }
    let _ = rows;
}

fn print_row(r: &Row) {
    static HEADER: std::sync::Once = std::sync::Once::new();
    HEADER.call_once(|| {
        println!(
            "| model | size | ours top 2t | ours top 1t | fidget JIT top 2t | fidget VM top 2t | ours/best peer | ours turn 2t | ours turn 1t | 40 ms (512² turn 2t) | peak MiB beyond image |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|");
    });
    let opt = |d: Option<Duration>| d.map_or("–".to_string(), ms);
    let best = match r.fidget {
        [Some(a), Some(b)] => Some(a.min(b)),
        [Some(a), None] | [None, Some(a)] => Some(a),
        _ => None,
    };
    let ratio = best.map_or("–".into(), |b| {
        format!("{:.3}", r.top[0].as_secs_f64() / b.as_secs_f64())
    });
    let target = if r.size == 512 {
        if r.turn[0] <= Duration::from_millis(40) {
            "yes"
        } else {
            "no"
        }
    } else {
        ""
    };
    println!(
        "| {} | {}² | {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
        r.name,
        r.size,
        ms(r.top[0]),
        ms(r.top[1]),
        opt(r.fidget[0]),
        opt(r.fidget[1]),
        ratio,
        ms(r.turn[0]),
        ms(r.turn[1]),
        target,
        r.peak_mib
    );
}
