//! Native throughput of the bindings, to set beside the WebAssembly
//! module's (`web/tests/unit/wasm-throughput.test.ts` prints those):
//! batch evaluations per second at 262,144 points and the time of one
//! depth-7 mesh, per example. Single-threaded like the module: run with
//! `RAYON_NUM_THREADS=1 cargo run --release -p frep-wasm --example throughput`.

use std::time::Instant;

use frep_wasm::{Kernel, MeshRequest};

const MODELS: &[&str] = &["sphere", "m2_spheres100", "m3_gyroid", "m4_rblend10"];
const POINTS: usize = 262_144;

/// The same xorshift32 points as web/src/wasm/host.ts's `benchPoints`.
fn points(b: [f64; 6], n: usize) -> Vec<f64> {
    let mut s: u32 = 0x9e37_79b9;
    let mut xyz = vec![0.0; 3 * n];
    for a in 0..3 {
        for i in 0..n {
            s ^= s << 13;
            s ^= s >> 17;
            s ^= s << 5;
            xyz[a * n + i] = b[a] + (b[a + 3] - b[a]) * (f64::from(s) / 4_294_967_296.0);
        }
    }
    xyz
}

fn main() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples");
    let mut kernel = Kernel::new();
    for name in MODELS {
        let src = std::fs::read_to_string(format!("{root}/{name}.hf")).expect("example");
        let c = kernel.compile(&src, &Default::default());
        let b = c.bounds.expect("box");
        let xyz = points(b, POINTS);
        let mut out = Vec::new();
        // One warm-up, then the best of five.
        let mut best = f64::INFINITY;
        for _ in 0..6 {
            let t = Instant::now();
            kernel
                .eval_points(c.handle, &xyz, &[], &mut out)
                .expect("eval");
            best = best.min(t.elapsed().as_secs_f64());
        }
        let req = MeshRequest {
            bounds: b,
            depth: 7,
            method: None,
            params: Vec::new(),
            colors: None,
            max_triangles: None,
            max_depth: None,
        };
        let mut mesh_best = f64::INFINITY;
        for _ in 0..3 {
            let t = Instant::now();
            kernel.polygonize(c.handle, &req).expect("mesh");
            mesh_best = mesh_best.min(t.elapsed().as_secs_f64());
        }
        println!(
            "{name}: {:.1} M evals/s, depth-7 mesh {:.1} ms",
            POINTS as f64 / best / 1e6,
            mesh_best * 1e3
        );
    }
}
