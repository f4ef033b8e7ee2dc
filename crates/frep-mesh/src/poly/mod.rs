//! The polygonizer: closed, outward-oriented meshes of a model's solid `f ≥ 0` in a box.
//!
//! ## Lattice
//! - The box is cut into cubic-ish cells, `2^depth` along its longest side.
//! - The field is sampled at cell **centres**.
//! - One virtual layer of samples lies *on* the box faces and counts as outside. So where the
//!   solid reaches the box, the surface closes on the box faces: cap vertices lie exactly on
//!   the faces.
//! - NaN counts as outside. A sample is inside iff `f ≥ 0`.
//!
//! ## Octree and bricks
//! 1. An octree over the cells descends from the whole box.
//! 2. Each node's box is evaluated with interval arithmetic on the node's tape. The box is
//!    grown by one cell, so that it covers the edges to its neighbours' samples.
//! 3. A node strictly inside (`f > 0`) or outside (`f < 0` or NaN) is pruned.
//! 4. Otherwise the tape is shortened for the node ([`SimplifyMode::Sign`]), keeping the sign
//!    of `f` and its gradient on the surface. The node's children are visited in parallel
//!    (rayon).
//! 5. Nodes of `BRICK³` cells are evaluated in batches ([`BatchEval`]) on their own tape.
//!
//! Every lattice sample thus has one canonical sign: its brick's, or its pruned node's.
//!
//! ## Extraction
//! Marching-cubes cubes join 8 neighbouring samples.
//! - A cube is handled by exactly one brick, in parallel. That is the first evaluated brick
//!   among its corners' bricks, else the first inside brick on the box boundary.
//! - Crossing edges get a vertex. For a virtual end it lies on the box face.
//! - Otherwise `Watertight` and `DualContouring` find it by Illinois regula falsi on the edge,
//!   with the brick's tape. `MarchingCubes` interpolates the samples linearly.
//! - The cases come from one face rule ([`table`]). So cubes that share a face agree, and the
//!   mesh is closed.
//!
//! The methods:
//! - [`Method::Watertight`]: the marching-cubes polygons, vertices shared by edge.
//! - [`Method::DualContouring`]: one vertex per polygon (component) per cube, and one quad per
//!   crossing edge.
//!   - The vertex is placed by a QEF of its crossings and gradient normals (sharp features).
//!   - The mesh is the dual of the marching-cubes mesh, hence a closed 2-manifold as well.
//!   - A polygon that crosses one cube face twice (walls about a cell thick) is first split in
//!     two by a chord ([`table::DualCase`]). Otherwise two such polygons of neighbouring cubes
//!     would share two segments, and their vertices a doubled (non-manifold) edge.
//!   - The edges at a chord's ends get a fan around their crossing instead of a quad.
//!   - The QEF minimizer may leave its cube by one cell. A union's groove less than a cell
//!     deep runs through cubes whose samples all lie on one side, next to the cubes that see
//!     both sheets.
//!   - Then a few Newton steps move the vertex onto the surface. A vertex on a crease does
//!     not move.
//!
//!   **Adaptive** ([`MeshSettings::adaptive`]): within each brick, blocks of 2×2×2, then
//!   4×4×4, 8×8×8 cubes collapse to one vertex, bottom-up. A block collapses when:
//!   - its sub-blocks did;
//!   - it is topologically one cube (Ju et al. 2002): one polygon, no ambiguous face, and the
//!     signs in the middle of its edges and faces and at its centre those of one of their
//!     corners;
//!   - the vertex of the merged QEF lies within the threshold of every crossing's tangent
//!     plane.
//!
//!   The quads are still made per cube edge on the finest lattice. The vertex keys of a
//!   collapsed block's cubes map to its one vertex. So the quads inside the block vanish, and
//!   those across its faces become triangles. The mesh is still the closed 2-manifold dual of
//!   the (now adaptive) cells.
//! - [`Method::MarchingCubes`]: the classic baseline. Uniform grid, no pruning, no
//!   simplification, linear interpolation, normals from the triangles.
//!
//! ## Code
//! - `settings`: what to mesh, errors, progress, cancellation.
//! - `grid`: the lattice and its signs.
//! - `octree`: interval pruning, brick evaluation.
//! - `crossings`: roots on edges, snapping vertices.
//! - `extract`: marching-cubes polygons and dual-contouring quads per brick.
//! - `adaptive`: collapsed blocks.
//! - `merge`: bricks joined into one mesh.
//! - `simplify`: meshopt.
//! - This file: the constants, the context and the driver ([`polygonize`]).
//!
//! [`SimplifyMode::Sign`]: frep_core::simplify::SimplifyMode::Sign
//! [`BatchEval`]: frep_core::eval::batch::BatchEval

pub mod bounds;
pub mod error;
mod qef;
pub mod table;

mod adaptive;
mod crossings;
mod extract;
mod grid;
mod merge;
mod octree;
mod settings;
#[cfg(feature = "export")]
mod simplify;

pub use settings::{CancelToken, Limits, MeshError, MeshSettings, Method, Progress, Resolution};
#[cfg(feature = "export")]
pub use simplify::{simplify_mesh, simplify_verified};

use std::sync::atomic::Ordering;
use std::sync::Arc;

use frep_core::eval::interval::IntervalEval;
use frep_core::eval::Inputs;
use frep_core::hash::FastMap;
use frep_core::Model;

use crate::Mesh;

use grid::{Grid, Lattice, INSIDE, OUTSIDE};
use merge::{merge_dual, merge_marching};
use octree::{Class, Leaf};

/// Side of the finest bricks evaluated in one batch (in cells), at most.
const BRICK: i32 = 16;

/// Largest number of bricks per axis (the brick map is dense).
const MAX_BRICKS: i32 = 128;

/// Vertices stay this fraction of an edge away from its ends (no coincident vertices).
const EDGE_MARGIN: f64 = 0.01;

/// Regula falsi steps on each crossing edge, at most.
const ROOT_STEPS: usize = 12;

/// A crossing is found when its estimate moves by less than this fraction of the edge.
const ROOT_TOL: f64 = 1e-4;

/// How far (in cells) a dual-contouring vertex may leave its cube (its QEF's box).
const DC_SLACK: f64 = 1.0;

/// Newton steps that move a dual-contouring vertex onto the surface.
const SNAP_STEPS: usize = 3;

/// Crossing normals are central differences over this fraction of a cell either side.
const NORMAL_STEP: f64 = 1e-3;

struct Ctx<'a> {
    grid: Grid,
    method: Method,
    inputs: &'a Inputs,
    progress: &'a Progress,
    cancel: &'a CancelToken,
    /// Number of colour channels to evaluate (0: none).
    colors: usize,
    /// [`MeshSettings::adaptive`].
    adaptive: Option<f64>,
}

#[cfg(feature = "parallel")]
fn par_map<T: Sync, R: Send>(v: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    use rayon::prelude::*;
    v.par_iter().map(f).collect()
}

#[cfg(not(feature = "parallel"))]
fn par_map<T: Sync, R: Send>(v: &[T], f: impl Fn(&T) -> R + Sync + Send) -> Vec<R> {
    v.iter().map(f).collect()
}

#[cfg(feature = "parallel")]
fn par_each<T: Send>(v: &mut [T], f: impl Fn(&mut T) + Sync + Send) {
    use rayon::prelude::*;
    v.par_iter_mut().for_each(f)
}

#[cfg(not(feature = "parallel"))]
fn par_each<T: Send>(v: &mut [T], f: impl Fn(&mut T) + Sync + Send) {
    v.iter_mut().for_each(f)
}

/// Maps by integer key ([`FastHasher`]).
///
/// [`FastHasher`]: frep_core::hash::FastHasher
type KeyMap<V> = FastMap<u64, V>;

/// Polygonizes `model`'s solid in `settings.bounds` (see the module docs).
pub fn polygonize(
    model: &Model,
    settings: &MeshSettings,
    progress: &Progress,
    cancel: &CancelToken,
) -> Result<Mesh, MeshError> {
    #[cfg(feature = "parallel")]
    if let Some(t) = settings.threads {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(t.max(1))
            .build()
            .map_err(|_| MeshError::Unsupported("cannot start the thread pool"))?;
        return pool.install(|| run(model, settings, progress, cancel));
    }
    run(model, settings, progress, cancel)
}

fn run(
    model: &Model,
    settings: &MeshSettings,
    progress: &Progress,
    cancel: &CancelToken,
) -> Result<Mesh, MeshError> {
    if settings.simplify.is_some() && !cfg!(feature = "export") {
        return Err(MeshError::Unsupported(
            "simplification needs the export feature (meshopt)",
        ));
    }
    let grid = Grid::new(settings)?;
    let colors = if settings.colors && model.has_attributes {
        model.s_dim.min(3)
    } else {
        0
    };
    let tape = Arc::new(if colors > 0 {
        model.tape_with_attributes()
    } else {
        model.tape()
    });
    let ctx = Ctx {
        grid: grid.clone(),
        method: settings.method,
        inputs: &settings.inputs,
        progress,
        cancel,
        colors,
        adaptive: settings.adaptive,
    };
    let nb = grid.nb as usize;
    let total = (nb * nb * nb) as u64;
    progress.done.store(0, Ordering::Relaxed);
    progress.estimated.store(2 * total, Ordering::Relaxed);

    // Phase 1: the octree.
    let mut ev = (settings.method != Method::MarchingCubes).then(|| IntervalEval::new(&tape));
    let leaves = match ctx.classify(&mut ev, &tape, [0; 3], grid.size) {
        Class::Go(t) => ctx.descend(t, [0; 3], grid.size)?,
        c => {
            progress.add(total);
            vec![Leaf::Pruned {
                origin: [0; 3],
                size: grid.size,
                inside: matches!(c, Class::Inside),
            }]
        }
    };
    let lat = lattice(&grid, leaves);

    // Phase 2: extraction by the generating bricks.
    let gen = generating_bricks(&lat);
    progress
        .estimated
        .store(total + gen.len() as u64, Ordering::Relaxed);
    progress.done.store(total, Ordering::Relaxed);
    let outs = par_map(&gen, |&(id, eval)| {
        let r = ctx.extract(&lat, id, eval);
        progress.add(1);
        r
    });
    drop(lat);
    let mut outs = outs.into_iter().collect::<Result<Vec<_>, _>>()?;
    ctx.check()?;

    // Phase 3: merge.
    let ntri: usize = outs
        .iter()
        .map(|o| o.tris.len() + o.triangles.len() + 2 * o.quads.len())
        .sum();
    if ntri > settings.limits.max_triangles {
        return Err(MeshError::TooManyTriangles(settings.limits.max_triangles));
    }
    let mut mesh = Mesh::default();
    mesh.triangles.reserve(ntri);
    let with_colors = colors > 0;
    if settings.method != Method::DualContouring {
        merge_marching(&mut outs, &mut mesh, with_colors);
    }
    merge_dual(outs, &mut mesh, with_colors);
    fill_normals(&mut mesh, settings.method);
    #[cfg(feature = "export")]
    if let Some(frac) = settings.simplify {
        let cell = grid.h.iter().fold(0.0f64, |a, &b| a.max(b));
        simplify_verified(
            &mut mesh,
            (frac * cell) as f32,
            settings.method == Method::Watertight,
        );
    }
    progress.done.store(progress.estimated(), Ordering::Relaxed);
    Ok(mesh)
}

/// The brick map of the octree's `leaves`: pruned inside nodes mark their bricks inside,
/// evaluated bricks are numbered in order.
fn lattice(grid: &Grid, leaves: Vec<Leaf>) -> Lattice<'_> {
    let nb = grid.nb as usize;
    let mut lat = Lattice {
        grid,
        map: vec![OUTSIDE; nb * nb * nb],
        bricks: Vec::new(),
    };
    for leaf in leaves {
        match leaf {
            Leaf::Pruned {
                origin,
                size,
                inside,
            } => {
                if !inside {
                    continue;
                }
                let s = size / grid.brick;
                let b0 = origin.map(|c| (c / grid.brick) as usize);
                for k in 0..s as usize {
                    for j in 0..s as usize {
                        for i in 0..s as usize {
                            lat.map[b0[0] + i + nb * (b0[1] + j + nb * (b0[2] + k))] = INSIDE;
                        }
                    }
                }
            }
            Leaf::Brick(b) => {
                let id = grid.brick_id(b.origin);
                lat.map[id] = 2 + lat.bricks.len() as u32;
                lat.bricks.push(b);
            }
        }
    }
    lat
}

/// The bricks that extract cubes, as `(brick id, evaluated brick)`: every evaluated brick,
/// and the inside bricks on the box boundary (their caps).
fn generating_bricks(lat: &Lattice) -> Vec<(usize, Option<usize>)> {
    let mut gen = Vec::new();
    for (id, &m) in lat.map.iter().enumerate() {
        match m {
            OUTSIDE => {}
            INSIDE => {
                if lat.grid.is_boundary_brick(id) {
                    gen.push((id, None));
                }
            }
            k => gen.push((id, Some((k - 2) as usize))),
        }
    }
    gen
}

/// Normals from the triangles: all of them for marching cubes, else only where the
/// vertex has none (a zero normal).
fn fill_normals(mesh: &mut Mesh, method: Method) {
    if method == Method::MarchingCubes {
        mesh.compute_normals();
    } else if mesh.normals.contains(&[0.0; 3]) {
        let given = std::mem::take(&mut mesh.normals);
        mesh.compute_normals();
        for (n, g) in mesh.normals.iter_mut().zip(given) {
            if g != [0.0; 3] {
                *n = g;
            }
        }
    }
}
