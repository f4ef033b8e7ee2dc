//! Meshing, side by side with fidget 0.5: time, triangles, symmetric Hausdorff error and peak
//! memory per model and depth, printed as a table (no criterion: one table is what we compare).
//!
//! Run: `scripts/bench-mesh.sh` (= `cargo bench -p frep-bench --features anchors --bench
//! mesh`). Environment:
//! - `FREP_BENCH_REPS` (default 3): the repetitions; the minimum time is kept.
//! - `FREP_BENCH_DEPTHS` (default `6,7,8`): the depths.
//! - `FREP_BENCH_MODELS`: a name filter, a part of the row's name. `=name` is exactly that
//!   name: `=sphere` is the plain sphere alone.
//!
//! fidget meshes on the same box and at the same depth. The box is the cube of the model
//! box's longest side around its centre, so the cell size is the same.
//! - M1–M4 come from the hand-written anchor trees, on the JIT. M3 takes the VM, whose
//!   trigonometry the JIT calls lane by lane (see shared/notes/rendering-and-meshing.md).
//! - The examples come from `to_fidget`'s translation of the same tape (JIT).
//! - Both use rayon's global pool (all cores of the machine).
//!
//! H: [`SurfaceSamples`]' symmetric Hausdorff estimate in cells.
//! - Mesh points are projected onto the surface by Newton steps. The distance is lowered to
//!   the nearest sign change along a fan of 256 rays where that is nearer.
//! - Dense surface points (the lattice crossings at depth + 1) are measured to the nearest
//!   triangle.
//! - Points within one cell of the box faces are left out. Our caps lie on the box, and
//!   fidget leaves the mesh open there.
//!
//! "adaptive dc": dual contouring with `MeshSettings::adaptive` = 0.1 cell. Blocks of
//! 2×2×2, 4×4×4, … cubes collapse to one vertex where that keeps the topology and every
//! crossing's tangent plane within 0.1 cell of the vertex.
//!
//! "reduced": our smallest mesh at fidget's error, in model units. The candidates:
//! - watertight, dual contouring or adaptive dual contouring, at the row's depth `d` or at
//!   `d − 1`, `d − 2`. A coarser mesh whose error is below fidget's at `d` is as good a mesh
//!   at that error.
//! - Adaptive dual contouring takes the largest threshold of 0.8, 0.6, 0.4, 0.3, 0.2, 0.14,
//!   0.1, 0.07, 0.05 cell of its own depth that meets it, labelled `adc7/0.2`.
//! - Only where none of those meets it, the same at `d + 1`, up to depth 8. A finer mesh,
//!   adaptively reduced, can still have fewer triangles.
//! - Watertight and dual contouring also simplified with meshopt (labelled `dc6+s0.12`). The
//!   bound is the largest of 0.5, 0.25, 0.12, 0.06, 0.03, 0.015 cell of depth `d` whose
//!   measured H is at most fidget's H.
//! - A simplified mesh is verified (see `simplify_verified`): closed, manifold, oriented, the
//!   same components and genus, and for watertight free of self-intersections.
//!
//! Every candidate is measured with the row's samples, H in cells of the row's depth. Its
//! time is the meshing plus the simplification. Memory: the peak of live heap bytes during
//! the run (a counting global allocator), per output triangle.

use frep_bench::alloc::{peak_during, Counting};
use std::time::Instant;

use frep_core::{Inputs, Model};
use frep_mesh::poly::error::SurfaceSamples;
use frep_mesh::poly::simplify_verified;
use frep_mesh::{polygonize, CancelToken, Mesh, MeshSettings, Method, Progress, Resolution};

/// Thresholds of adaptive dual contouring tried for "reduced" (fractions of the cell), largest
/// first.
const ADAPTIVE: [f64; 9] = [0.8, 0.6, 0.4, 0.3, 0.2, 0.14, 0.1, 0.07, 0.05];
/// The threshold of the "adaptive dc" columns.
const ADAPTIVE_COLUMN: f64 = 0.1;

#[global_allocator]
static ALLOC: Counting = Counting;

/// Runs `f` `reps` times: (min seconds, peak extra heap bytes of the first run, result).
fn measure<R>(reps: usize, mut f: impl FnMut() -> R) -> (f64, usize, R) {
    let mut best = f64::INFINITY;
    let mut peak = 0;
    let mut out = None;
    for r in 0..reps.max(1) {
        let t = Instant::now();
        let (v, p) = peak_during(&mut f);
        best = best.min(t.elapsed().as_secs_f64());
        if r == 0 {
            peak = p;
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

/// fidget's mesh of `tree` in the cube of `bounds`' longest side around its centre.
fn fidget_mesh(tree: &fidget::context::Tree, jit: bool, depth: u8, bounds: [f64; 6]) -> Mesh {
    let settings = fidget::mesh::Settings {
        depth,
        ..Default::default()
    };
    let (c, half) = frep_bench::cube_of(bounds);
    let tree = frep_bench::to_fidget::in_cube(tree, (c, half));
    let tree = &tree;
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
        positions: m
            .vertices
            .iter()
            .map(|v| {
                [v.x, v.y, v.z]
                    .map(f64::from)
                    .iter()
                    .enumerate()
                    .map(|(k, &u)| (c[k] + half * u) as f32)
                    .collect::<Vec<_>>()
                    .try_into()
                    .expect("3")
            })
            .collect(),
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
    let anchors = frep_bench::anchors::all();
    let mut cases = Vec::new();
    for (file, src) in frep_bench::example_sources("") {
        let stem = file.trim_end_matches(".hf").to_string();
        let model = Model::compile(&src).expect("compiles");
        let anchor = frep_bench::anchor_of(&file);
        let fidget = match anchor {
            Some(i) => Some((anchors[i].tree.clone(), i != 2)),
            None => frep_bench::to_fidget::tape_to_tree(&model.tape())
                .ok()
                .map(|t| (t, true)),
        };
        let name = match anchor {
            Some(_) => format!("{} {}", stem[..2].to_uppercase(), &stem[3..]),
            None => stem,
        };
        let wanted = |o: &String| match o.strip_prefix('=') {
            Some(exact) => name == exact,
            None => name.contains(o.as_str()),
        };
        if only.as_ref().is_some_and(|o| !wanted(o)) {
            continue;
        }
        cases.push(Case {
            name,
            model,
            bounds: frep_bench::bounds_line(&src).unwrap_or([-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]),
            fidget,
        });
    }
    cases.sort_by_key(|c| (!c.name.starts_with('M'), c.name.clone()));
    println!(
        "threads: {}, reps: {reps} (min time), times in ms, tris in thousands, H = symmetric Hausdorff / cell, B/tri = peak heap bytes / triangle",
        std::thread::available_parallelism().map_or(1, |n| n.get())
    );
    println!(
        "| model | d | ours wt ms | tris k | H | B/tri | ours dc ms | tris k | H | adaptive dc ms | tris k | H | uniform mc ms | fidget ms | tris k | H | B/tri | reduced: ours | ms | tris k | H | fidget / ours time | reduced / fidget tris |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let inputs = Inputs::default();
    for c in &cases {
        for &d in &depths {
            let ext = (0..3)
                .map(|k| c.bounds[k + 3] - c.bounds[k])
                .fold(0.0f64, f64::max);
            let cell = ext / (1u64 << d) as f64;
            let samples = SurfaceSamples::new(&c.model, &inputs, c.bounds, d, cell);
            let h = |m: &Mesh| samples.error(m).hausdorff() / cell;
            let settings_at = |method, depth| MeshSettings {
                bounds: c.bounds,
                resolution: Resolution::Depth(depth),
                method,
                ..Default::default()
            };
            let settings = |method| settings_at(method, d);
            let run = |s: &MeshSettings| {
                polygonize(&c.model, s, &Progress::new(), &CancelToken::new()).expect("mesh")
            };
            let wt_s = settings(Method::Watertight);
            let (t_wt, mem_wt, m_wt) = measure(reps, || run(&wt_s));
            let h_wt = h(&m_wt);
            let dc_s = settings(Method::DualContouring);
            let (t_dc, _, m_dc) = measure(reps, || run(&dc_s));
            let h_dc = h(&m_dc);
            let adc_s = MeshSettings {
                adaptive: Some(ADAPTIVE_COLUMN),
                ..settings(Method::DualContouring)
            };
            let (t_adc, _, m_adc) = measure(reps, || run(&adc_s));
            let h_adc = h(&m_adc);
            let mc = if d <= 7 {
                let mc_s = settings(Method::MarchingCubes);
                format!("{:.0}", measure(1, || run(&mc_s)).0 * 1e3)
            } else {
                "–".into()
            };
            let ours_best = t_wt.min(t_dc);
            let mut fid = None;
            let fid_cols = match &c.fidget {
                Some((tree, jit)) => {
                    let r = if d >= 8 { 1 } else { reps };
                    let (t, mem, m) = measure(r, || fidget_mesh(tree, *jit, d, c.bounds));
                    let hf = h(&m);
                    fid = Some((t, m.triangles.len(), hf));
                    format!(
                        "{:.0} ({}) | {:.0} | {:.2} | {:.0}",
                        t * 1e3,
                        if *jit { "jit" } else { "vm" },
                        m.triangles.len() as f64 / 1e3,
                        hf,
                        mem as f64 / m.triangles.len().max(1) as f64,
                    )
                }
                None => "– | – | – | –".into(),
            };
            // The smallest of our meshes at fidget's error: wt or dc at this depth or one or
            // two coarser, unsimplified or simplified with a verified bound. Equal error is
            // about model units, not the depth. Every candidate is measured with this row's
            // samples, H in this row's cells.
            let target = fid.map_or(h_wt.max(h_dc), |f| f.2);
            let mut best: Option<(String, f64, usize, f64)> = None;
            let consider = |best: &mut Option<(String, f64, usize, f64)>,
                            label: String,
                            t: f64,
                            tris: usize,
                            hm: f64| {
                if hm <= target && best.as_ref().is_none_or(|b| tris < b.2) {
                    *best = Some((label, t, tris, hm));
                }
            };
            // Depths d, d − 1, d − 2. Then, only where none of those meets fidget's error,
            // d + 1 (at most 8): a finer mesh reduced adaptively can still have fewer
            // triangles.
            let mut levels: Vec<u8> = (d.saturating_sub(2).max(3)..=d).rev().collect();
            let mut li = 0;
            while li < levels.len() {
                let dl = levels[li];
                li += 1;
                let coarse = |method| -> (f64, Mesh) {
                    let (t, _, m) = measure(reps, || run(&settings_at(method, dl)));
                    (t, m)
                };
                // Adaptive dual contouring: the largest threshold that meets fidget's H.
                for tol in ADAPTIVE {
                    let (t, m) = if dl == d && tol == ADAPTIVE_COLUMN {
                        (t_adc, m_adc.clone())
                    } else {
                        let s = MeshSettings {
                            adaptive: Some(tol),
                            ..settings_at(Method::DualContouring, dl)
                        };
                        let (t, _, m) = measure(reps, || run(&s));
                        (t, m)
                    };
                    let hm = h(&m);
                    if hm <= target {
                        consider(
                            &mut best,
                            format!("adc{dl}/{tol}"),
                            t,
                            m.triangles.len(),
                            hm,
                        );
                        break;
                    }
                }
                let bases = if dl == d {
                    vec![
                        ("dc", t_dc, m_dc.clone(), h_dc),
                        ("wt", t_wt, m_wt.clone(), h_wt),
                    ]
                } else {
                    [("dc", Method::DualContouring), ("wt", Method::Watertight)]
                        .into_iter()
                        .map(|(l, method)| {
                            let (t, m) = coarse(method);
                            let hm = h(&m);
                            (l, t, m, hm)
                        })
                        .collect()
                };
                for (label, t_base, base, h_base) in bases {
                    let label = format!("{label}{dl}");
                    consider(
                        &mut best,
                        label.clone(),
                        t_base,
                        base.triangles.len(),
                        h_base,
                    );
                    for frac in [0.5, 0.25, 0.12, 0.06, 0.03, 0.015] {
                        let mut m = base.clone();
                        let t0 = Instant::now();
                        let kept = simplify_verified(
                            &mut m,
                            (frac * cell) as f32,
                            label.starts_with("wt"),
                        );
                        let ts = t0.elapsed().as_secs_f64();
                        let Some(e) = kept else { continue };
                        let hs = h(&m);
                        if hs <= target {
                            consider(
                                &mut best,
                                format!("{label}+s{:.2}", e as f64 / cell),
                                t_base + ts,
                                m.triangles.len(),
                                hs,
                            );
                            break;
                        }
                    }
                }
                if li == levels.len() && best.is_none() && d < 8 && dl != d + 1 {
                    levels.push(d + 1);
                }
            }
            let red = match (&best, fid) {
                (Some((l, t, n, hr)), f) => format!(
                    "{l} | {:.0} | {:.0} | {:.2} | {} | {}",
                    t * 1e3,
                    *n as f64 / 1e3,
                    hr,
                    f.map_or("–".into(), |f| format!("{:.1}×", f.0 / ours_best)),
                    f.map_or("–".into(), |f| format!(
                        "{:.2}",
                        *n as f64 / f.1.max(1) as f64
                    )),
                ),
                (None, f) => format!(
                    "none ≤ fidget's H | – | – | – | {} | –",
                    f.map_or("–".into(), |f| format!("{:.1}×", f.0 / ours_best)),
                ),
            };
            println!(
                "| {} | {d} | {:.0} | {:.0} | {:.2} | {:.0} | {:.0} | {:.0} | {:.2} | {:.0} | {:.0} | {:.2} | {mc} | {fid_cols} | {red} |",
                c.name,
                t_wt * 1e3,
                m_wt.triangles.len() as f64 / 1e3,
                h_wt,
                mem_wt as f64 / m_wt.triangles.len().max(1) as f64,
                t_dc * 1e3,
                m_dc.triangles.len() as f64 / 1e3,
                h_dc,
                t_adc * 1e3,
                m_adc.triangles.len() as f64 / 1e3,
                h_adc,
            );
        }
    }
}
