//! A quick meshing timer for profiling the polygonizer:
//! `mesh_time [filter] [depth] [method] [threads] [reps]`, method `wt`, `dc` or `mc`.
//! Meshes every example whose file name contains `filter`, in the box of its `-- bounds:`
//! line. Prints the minimum time and the triangle count. For instruction counts, run it under
//! `valgrind --tool=callgrind` with 1 thread and 1 rep.

use std::time::{Duration, Instant};

use frep_bench::{bounds_line, example_sources, Args};
use frep_core::Model;
use frep_mesh::{polygonize, CancelToken, MeshSettings, Method, Progress, Resolution};

fn main() {
    let args = Args::from_env();
    let filter = args.get(0, "");
    let depth: u8 = args.num(1, "6");
    let method = match args.get(2, "wt").as_str() {
        "dc" => Method::DualContouring,
        "mc" => Method::MarchingCubes,
        _ => Method::Watertight,
    };
    let threads: usize = args.num(3, "2");
    let reps: usize = args.num(4, "5");
    let pool = Args::pool(threads);
    for (file, src) in example_sources(&filter) {
        let model = Model::compile(&src).expect("compiles");
        let Some(bounds) = bounds_line(&src) else {
            println!("{file:<24} no bounds line, skipped");
            continue;
        };
        let s = MeshSettings {
            bounds,
            resolution: Resolution::Depth(depth),
            method,
            ..Default::default()
        };
        let mut best = Duration::MAX;
        let mut tris = 0;
        for _ in 0..reps.max(1) {
            let t = Instant::now();
            let m = pool
                .install(|| polygonize(&model, &s, &Progress::new(), &CancelToken::new()))
                .expect("mesh");
            best = best.min(t.elapsed());
            tris = m.triangles.len();
        }
        println!(
            "{file:<24} d{depth} {method:?} {threads}t {:8.2} ms {tris} triangles",
            best.as_secs_f64() * 1e3
        );
    }
}
