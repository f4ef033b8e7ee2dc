//! A quick render timer for profiling the ray caster:
//! `render_time [filter] [size] [view] [threads] [reps]`. The view is one of:
//! - `top`: the render benchmark's orthographic top-down view, over
//!   `[-1, 1]³` for M1–M4 and the cube of the model's box otherwise;
//! - `turn`: the perspective turntable of the model's own box.
//!
//! Prints the minimum time per example, and the caster's counters with
//! `FREP_BENCH_STATS=1`. The caster's knobs and the tile size can be set for
//! experiments: `FREP_STEP_PX`,
//! `FREP_LEAF_DEPTH_PX`, `FREP_NARROW_PX`, `FREP_PRUNE_AFTER`, `FREP_FALLBACK_DEPTH`,
//! `FREP_TILE`.

use frep_bench::alloc::{peak_during, Counting};
use frep_bench::{example_box, example_sources, top_cube, top_view, Args};
use std::time::{Duration, Instant};

use frep_core::Model;
use frep_render::{render_with, CancelToken, ImagePool, ModelCaster, RenderSettings};

#[global_allocator]
static ALLOC: Counting = Counting;

fn main() {
    let args = Args::from_env();
    let filter = args.get(0, "");
    let size: u32 = args.num(1, "512");
    let view = args.get(2, "turn");
    let threads: usize = args.num(3, "2");
    let reps: usize = args.num(4, "5");
    let pool = Args::pool(threads);
    for (file, src) in example_sources(&filter) {
        let model = Model::compile(&src).expect("compiles");
        let (bounds, cam) = if view == "top" {
            let (cam, b) = top_view(top_cube(&file, &src));
            (b, cam)
        } else {
            let b = example_box(&src);
            let s = RenderSettings {
                bounds: b,
                ..Default::default()
            };
            (b, s.camera())
        };
        let mut s = RenderSettings {
            size: (size, size),
            bounds,
            ..Default::default()
        };
        if let Some(t) = std::env::var("FREP_TILE").ok().and_then(|v| v.parse().ok()) {
            s.tile_size = t;
        }
        let mut best = Duration::MAX;
        let mut stats = None;
        let mut peak = 0usize;
        let (cancel, images) = (CancelToken::new(), ImagePool::default());
        for _ in 0..reps {
            let mut caster = ModelCaster::new(&model, Default::default(), bounds);
            let knob = |k: &str| std::env::var(k).ok().and_then(|v| v.parse::<f64>().ok());
            if let Some(v) = knob("FREP_STEP_PX") {
                caster.step_px = v;
            }
            if let Some(v) = knob("FREP_LEAF_DEPTH_PX") {
                caster.leaf_depth_px = v;
            }
            if let Some(v) = knob("FREP_NARROW_PX") {
                caster.narrow_px = v;
            }
            if let Some(v) = knob("FREP_PRUNE_AFTER") {
                caster.prune_after = v as u32;
            }
            if let Some(v) = knob("FREP_FALLBACK_DEPTH") {
                caster.fallback_depth = v as u32;
            }
            let t = Instant::now();
            let (img, p) = peak_during(|| {
                pool.install(|| render_with(&caster, &s, &cam, &cancel, &images).unwrap())
            });
            best = best.min(t.elapsed());
            // (The first run's image bytes are new, so that the most is
            // the peak beyond them; later runs reuse them.)
            peak = peak.max(p.saturating_sub(img.rgba.len()));
            images.recycle(std::hint::black_box(img));
            stats = Some(caster.stats());
        }
        print!(
            "{file:<24} {size}² {view} {threads}t {:8.2} ms {:6.2} MiB",
            best.as_secs_f64() * 1e3,
            peak as f64 / (1u64 << 20) as f64
        );
        if std::env::var_os("FREP_BENCH_STATS").is_some() {
            print!("  {:?}", stats.unwrap());
        }
        println!();
    }
}
