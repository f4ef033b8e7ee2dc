//! Meshing, side by side with fidget 0.5: time, triangles, Hausdorff error and peak memory
//! per model and depth, printed as a table (no criterion: one table is what we compare).
//!
//! Run: `scripts/bench-mesh.sh` (= `cargo bench -p frep-bench --features anchors --bench
//! mesh`). `FREP_BENCH_REPS` (default 3) sets the repetitions; the minimum time is kept.
//! `FREP_BENCH_DEPTHS` (default `6,7,8`) the depths. fidget meshes M1–M4 (the anchors) with
//! its faster evaluator per model (JIT, but the VM for M3, whose trigonometry the JIT calls
//! lane by lane; see shared/notes/rendering-and-meshing.md); the examples are ours only.
//! Both use rayon's global pool (all cores of the machine).
//!
//! "wt+simpl": watertight, then meshopt's error-bounded simplification with a bound of half
//! fidget's measured error (M1–M4), else 0.1 cell: the triangle count at about equal error.
//!
//! Hausdorff: the largest `|f| / |∇f|` (first-order distance to the surface) over the
//! vertices and triangle centroids, leaving out points within one cell of the box faces (our
//! caps lie on the box, fidget leaves the mesh open there). Memory: the peak of live heap
//! bytes during the run (a counting global allocator), per output triangle.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use frep_core::eval::grad::GradEval;
use frep_core::{Inputs, Model};
use frep_mesh::{polygonize, CancelToken, Mesh, MeshSettings, Method, Progress, Resolution};

struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards to the system allocator, only counting bytes.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            if new_size > layout.size() {
                let now = LIVE.fetch_add(new_size - layout.size(), Ordering::Relaxed) + new_size
                    - layout.size();
                PEAK.fetch_max(now, Ordering::Relaxed);
            } else {
                LIVE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
            }
        }
        p
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Runs `f` `reps` times: (min seconds, peak extra heap bytes of the first run, result).
fn measure<R>(reps: usize, mut f: impl FnMut() -> R) -> (f64, usize, R) {
    let mut best = f64::INFINITY;
    let mut peak = 0;
    let mut out = None;
    for r in 0..reps.max(1) {
        let base = LIVE.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        let t = Instant::now();
        let v = f();
        best = best.min(t.elapsed().as_secs_f64());
        if r == 0 {
            peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
        }
        out = Some(v);
    }
    (best, peak, out.expect("ran once"))
}

struct Case {
    name: String,
    model: Model,
    bounds: [f64; 6],
    fidget: Option<(fidget::context::Tree, bool)>,
}

fn bounds_line(src: &str) -> [f64; 6] {
    src.lines()
        .find_map(|l| l.strip_prefix("-- bounds:"))
        .map(|b| {
            let v: Vec<f64> = b
                .split(',')
                .map(|t| t.trim().parse().expect("number"))
                .collect();
            [v[0], v[1], v[2], v[3], v[4], v[5]]
        })
        .unwrap_or([-1.0, -1.0, -1.0, 1.0, 1.0, 1.0])
}

fn hausdorff(model: &Model, bounds: [f64; 6], cell: f64, positions: &Mesh) -> f64 {
    let tape = model.tape();
    let mut ge = GradEval::new(&tape);
    let inputs = Inputs::default();
    let near_box =
        |p: [f64; 3]| (0..3).any(|k| p[k] < bounds[k] + cell || p[k] > bounds[k + 3] - cell);
    let ge = std::cell::RefCell::new(&mut ge);
    positions.max_distance_to(|p| {
        if near_box(p) {
            return 0.0;
        }
        let g = ge.borrow_mut().eval(p[0], p[1], p[2], &inputs);
        let len = (g.dx * g.dx + g.dy * g.dy + g.dz * g.dz).sqrt();
        if len > 0.0 {
            g.v.abs() / len
        } else {
            0.0
        }
    })
}

fn fidget_mesh(tree: &fidget::context::Tree, jit: bool, depth: u8) -> Mesh {
    let settings = fidget::mesh::Settings {
        depth,
        ..Default::default()
    };
    let m = if jit {
        let shape = fidget::jit::JitShape::from(tree.clone())
            .try_into()
            .expect("shape");
        fidget::mesh::Octree::build(&shape, &settings)
            .expect("octree")
            .walk_dual()
    } else {
        let shape = fidget::vm::VmShape::from(tree.clone())
            .try_into()
            .expect("shape");
        fidget::mesh::Octree::build(&shape, &settings)
            .expect("octree")
            .walk_dual()
    };
    Mesh {
        positions: m.vertices.iter().map(|v| [v.x, v.y, v.z]).collect(),
        triangles: m
            .triangles
            .iter()
            .map(|t| [t.x as u32, t.y as u32, t.z as u32])
            .collect(),
        ..Default::default()
    }
}

fn main() {
    let reps: usize = std::env::var("FREP_BENCH_REPS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(3);
    let depths: Vec<u8> = std::env::var("FREP_BENCH_DEPTHS")
        .unwrap_or_else(|_| "6,7,8".into())
        .split(',')
        .filter_map(|d| d.trim().parse().ok())
        .collect();
    let only: Option<String> = std::env::var("FREP_BENCH_MODELS").ok();
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut names: Vec<_> = std::fs::read_dir(&root)
        .expect("examples")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "hf"))
        .collect();
    names.sort();
    let anchors = frep_bench::anchors::all();
    let mut cases = Vec::new();
    for p in names {
        let src = std::fs::read_to_string(&p).expect("read");
        let stem = p
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("?")
            .to_string();
        let fidget = ["m1", "m2", "m3", "m4"]
            .iter()
            .position(|m| stem.starts_with(m))
            .map(|i| (anchors[i].tree.clone(), i != 2));
        let name = match &fidget {
            Some(_) => format!("{} {}", stem[..2].to_uppercase(), &stem[3..]),
            None => stem,
        };
        if only.as_ref().is_some_and(|o| !name.contains(o.as_str())) {
            continue;
        }
        cases.push(Case {
            name,
            model: Model::compile(&src).expect("compiles"),
            bounds: bounds_line(&src),
            fidget,
        });
    }
    cases.sort_by_key(|c| (c.fidget.is_none(), c.name.clone()));
    println!(
        "threads: {}, reps: {reps} (min time), times in ms, tris in thousands, H = Hausdorff / cell, mem = peak heap bytes / triangle",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    println!(
        "| model | d | ours wt ms | tris k | H | B/tri | wt+simpl ms | tris k | H | ours dc ms | tris k | H | uniform mc ms | fidget ms | tris k | H | B/tri | fidget/ours |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for c in &cases {
        let mut prev: Option<f64> = None;
        for &d in &depths {
            let ext = (0..3)
                .map(|k| c.bounds[k + 3] - c.bounds[k])
                .fold(0.0f64, f64::max);
            let cell = ext / (1u64 << d) as f64;
            let settings = |method, simplify| MeshSettings {
                bounds: c.bounds,
                resolution: Resolution::Depth(d),
                method,
                simplify,
                ..Default::default()
            };
            let run = |s: &MeshSettings| {
                polygonize(&c.model, s, &Progress::new(), &CancelToken::new()).expect("mesh")
            };
            let wt_s = settings(Method::Watertight, None);
            let (t_wt, mem_wt, m_wt) = measure(reps, || run(&wt_s));
            let h_wt = hausdorff(&c.model, c.bounds, cell, &m_wt) / cell;
            let dc_s = settings(Method::DualContouring, None);
            let (t_dc, _, m_dc) = measure(reps, || run(&dc_s));
            let h_dc = hausdorff(&c.model, c.bounds, cell, &m_dc) / cell;
            let mc = if d <= 7 {
                let mc_s = settings(Method::MarchingCubes, None);
                format!("{:.0}", measure(1, || run(&mc_s)).0 * 1e3)
            } else {
                "–".into()
            };
            let mut fid_h = None;
            let fid = match &c.fidget {
                Some((tree, jit)) => {
                    let r = if d >= 8 { 1 } else { reps };
                    let (t, mem, m) = measure(r, || fidget_mesh(tree, *jit, d));
                    let h = hausdorff(&c.model, c.bounds, cell, &m) / cell;
                    fid_h = Some(h);
                    format!(
                        "{:.0} ({}) | {:.0} | {:.2} | {:.0} | {:.1}×",
                        t * 1e3,
                        if *jit { "jit" } else { "vm" },
                        m.triangles.len() as f64 / 1e3,
                        h,
                        mem as f64 / m.triangles.len().max(1) as f64,
                        t / t_wt
                    )
                }
                None => "– | – | – | – | –".into(),
            };
            // Simplified towards fidget's error (meshopt's bound is about half the measured
            // distance), else to a tenth of a cell.
            let target = fid_h.map_or(0.1, |h| (0.5 * h).max(0.02));
            let si_s = settings(Method::Watertight, Some(target));
            let (t_si, _, m_si) = measure(reps, || run(&si_s));
            let h_si = hausdorff(&c.model, c.bounds, cell, &m_si) / cell;
            let growth = prev.map_or(String::new(), |p| format!(" (×{:.1})", t_wt / p));
            prev = Some(t_wt);
            println!(
                "| {} | {d} | {:.0}{growth} | {:.0} | {:.2} | {:.0} | {:.0} | {:.0} | {:.2} | {:.0} | {:.0} | {:.2} | {mc} | {fid} |",
                c.name,
                t_wt * 1e3,
                m_wt.triangles.len() as f64 / 1e3,
                h_wt,
                mem_wt as f64 / m_wt.triangles.len().max(1) as f64,
                t_si * 1e3,
                m_si.triangles.len() as f64 / 1e3,
                h_si,
                t_dc * 1e3,
                m_dc.triangles.len() as f64 / 1e3,
                h_dc,
            );
        }
    }
}
