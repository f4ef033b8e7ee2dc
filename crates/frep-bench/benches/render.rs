//! Render times of frep's ray caster (`frep_render::render`) on M1–M4 and
//! every example, at 512² and 1024², with 2 threads and 1 thread, the peak
//! heap beyond the image, and — with the `anchors` feature — fidget 0.5's 3D
//! renderer (VM and JIT, heightmap + normals) on M1–M4 in the same run.
//!
//! Views:
//! - `top`: orthographic, looking down −z over `[-1, 1]³`, the square filling
//!   the image. This is what fidget's voxel render does natively (depth =
//!   image width voxels); ours renders the same view through an equivalent
//!   `Camera`, so the two columns compare like with like.
//! - `turn`: our usual turntable view (perspective, fov 30°, yaw 30°, pitch
//!   20°, framing the model box); ours only.
//!
//! `FREP_BENCH_STATS=1` also prints the caster's work counters per row.
//!
//! Each time is the minimum of `FREP_BENCH_REPS` runs (default 3; runs over
//! 5 s are not repeated). fidget's interpreter on M4 (minutes, per the notes)
//! is skipped unless `FREP_BENCH_SLOW=1`.
//!
//! Run: `scripts/bench-render.sh` (or `cargo bench -p frep-bench --features
//! anchors --bench render`).

use frep_bench::alloc::{peak_during, Counting};
use std::time::{Duration, Instant};

use frep_core::Model;
use frep_render::camera::Projection;
use frep_render::{render_camera, render_with, Aabb, Camera, ModelCaster, RenderSettings};

#[global_allocator]
static ALLOC: Counting = Counting;

fn reps() -> usize {
    std::env::var("FREP_BENCH_REPS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(3)
        .max(1)
}

/// The minimum time of up to `reps()` runs (one if it takes over 5 s).
fn time_min<F: FnMut()>(mut f: F) -> Duration {
    let mut best = Duration::MAX;
    for _ in 0..reps() {
        let t = Instant::now();
        f();
        let d = t.elapsed();
        best = best.min(d);
        if d > Duration::from_secs(5) {
            break;
        }
    }
    best
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

fn bounds_of(src: &str) -> Aabb {
    src.lines()
        .find_map(|l| l.trim().strip_prefix("-- bounds:"))
        .map(|b| {
            let v: Vec<f64> = b.split(',').map(|s| s.trim().parse().unwrap()).collect();
            Aabb::new([v[0], v[1], v[2]], [v[3], v[4], v[5]])
        })
        .unwrap_or(Aabb::new([-10.0; 3], [10.0; 3]))
}

/// fidget's native 3D view: orthographic, looking down −z, `[-1, 1]²` filling
/// the image.
fn top_camera() -> Camera {
    Camera::look_at(
        [0.0, 0.0, 3.0],
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        Projection::Orthographic { half_extent: 1.0 },
    )
}

struct Row {
    name: String,
    size: u32,
    top: Option<[Duration; 2]>,
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

    /// fidget's JIT and VM render times of model `i` (0..4) at `n`², 2 threads.
    pub fn times(i: usize, n: u32) -> [Option<Duration>; 2] {
        let tree = || frep_bench::anchors::all().swap_remove(i).tree;
        let threads = ThreadPool::Custom(pool(2));
        let jit = time_min(|| {
            std::hint::black_box(run(JitShape::from(tree()), n, &threads));
        });
        let slow = std::env::var_os("FREP_BENCH_SLOW").is_some();
        let vm = (i != 3 || slow).then(|| {
            time_min(|| {
                std::hint::black_box(run(fidget::vm::VmShape::from(tree()), n, &threads));
            })
        });
        [Some(jit), vm]
    }

    /// Pixels fidget sees as covered (for a sanity check against ours).
    pub fn coverage(i: usize, n: u32) -> usize {
        let tree = frep_bench::anchors::all().swap_remove(i).tree;
        run(JitShape::from(tree), n, &ThreadPool::Custom(pool(2)))
    }
}

fn main() {
    // `cargo bench` passes `--bench`; a name filter may follow.
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with("--"));
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples");
    let mut files: Vec<String> = std::fs::read_dir(dir)
        .expect("examples folder")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".hf"))
        .collect();
    files.sort();
    let (p1, p2) = (pool(1), pool(2));
    let mut rows = Vec::new();
    for file in &files {
        if filter.as_ref().is_some_and(|f| !file.contains(f.as_str())) {
            continue;
        }
        let src = std::fs::read_to_string(format!("{dir}/{file}")).expect("model source");
        let model = Model::compile(&src).expect("example compiles");
        let bounds = bounds_of(&src);
        let anchor = ["m1_", "m2_", "m3_", "m4_"]
            .iter()
            .position(|p| file.starts_with(p));
        for size in [512u32, 1024] {
            let turn = RenderSettings {
                size: (size, size),
                bounds,
                ..Default::default()
            };
            let cam = turn.camera();
            let run = |pool: &rayon::ThreadPool, s: &RenderSettings, c: &Camera| {
                time_min(|| {
                    pool.install(|| {
                        std::hint::black_box(render_camera(&model, s, c, None).unwrap())
                    });
                })
            };
            let turn_t = [run(&p2, &turn, &cam), run(&p1, &turn, &cam)];
            if std::env::var_os("FREP_BENCH_STATS").is_some() {
                let caster = ModelCaster::new(&model, Default::default(), bounds);
                let t = Instant::now();
                p2.install(|| render_with(&caster, &turn, &cam, None).unwrap());
                eprintln!(
                    "{file} {size}² turn: {:?} {:?}",
                    t.elapsed(),
                    caster.stats()
                );
                let top = RenderSettings {
                    size: (size, size),
                    bounds: Aabb::new([-1.0; 3], [1.0; 3]),
                    ..Default::default()
                };
                let caster = ModelCaster::new(&model, Default::default(), top.bounds);
                let t = Instant::now();
                p2.install(|| render_with(&caster, &top, &top_camera(), None).unwrap());
                eprintln!("{file} {size}² top: {:?} {:?}", t.elapsed(), caster.stats());
            }
            // Peak heap of one 2-thread render, beyond the image.
            let (img, peak) =
                peak_during(|| p2.install(|| render_camera(&model, &turn, &cam, None).unwrap()));
            let peak_mib = (peak as f64 - img.rgba.len() as f64) / (1u64 << 20) as f64;
            drop(img);
            let (top, fidget) = match anchor {
                Some(i) => {
                    let s = RenderSettings {
                        size: (size, size),
                        bounds: Aabb::new([-1.0; 3], [1.0; 3]),
                        ..Default::default()
                    };
                    let c = top_camera();
                    let t = [run(&p2, &s, &c), run(&p1, &s, &c)];
                    #[cfg(feature = "anchors")]
                    let f = peer::times(i, size);
                    #[cfg(not(feature = "anchors"))]
                    let f = {
                        let _ = i;
                        [None, None]
                    };
                    (Some(t), f)
                }
                None => (None, [None, None]),
            };
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
    #[cfg(feature = "anchors")]
    for i in 0..4 {
        if filter.is_none() {
            eprintln!(
                "fidget covered pixels M{} 256²: {}",
                i + 1,
                peer::coverage(i, 256)
            );
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
    let ratio = match (r.top, best) {
        (Some(t), Some(b)) => format!("{:.3}", t[0].as_secs_f64() / b.as_secs_f64()),
        _ => "–".into(),
    };
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
        opt(r.top.map(|t| t[0])),
        opt(r.top.map(|t| t[1])),
        opt(r.fidget[0]),
        opt(r.fidget[1]),
        ratio,
        ms(r.turn[0]),
        ms(r.turn[1]),
        target,
        r.peak_mib
    );
}
