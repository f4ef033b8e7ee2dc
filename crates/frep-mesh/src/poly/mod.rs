//! The polygonizer: closed, outward-oriented meshes of a model's solid `f ≥ 0` in a box.
//!
//! ## Lattice
//! The box is cut into cubic-ish cells, `2^depth` along its longest side; the field is sampled
//! at cell **centres**. One virtual layer of samples lies *on* the box faces and counts as
//! outside, so that where the solid reaches the box the surface closes on the box faces (cap
//! vertices lie exactly on the faces). NaN counts as outside; a sample is inside iff `f ≥ 0`.
//!
//! ## Octree and bricks
//! An octree over the cells descends from the whole box; each node's box (grown by one cell,
//! so that it covers the edges to its neighbours' samples) is evaluated with interval
//! arithmetic on the node's tape. A node strictly inside (`f > 0`) or outside (`f < 0` or NaN)
//! is pruned; otherwise the tape is shortened for the node ([`SimplifyMode::Sign`]: the sign
//! of `f` and its gradient on the surface are kept) and its children are visited in parallel
//! (rayon). Nodes of `BRICK³` cells are evaluated in batches ([`BatchEval`]) on their own
//! tape. Every lattice sample thus has one canonical sign: its brick's, or its pruned node's.
//!
//! ## Extraction
//! Marching-cubes cubes join 8 neighbouring samples. A cube is handled by exactly one brick
//! (the first evaluated brick among its corners' bricks, else the first inside brick on the
//! box boundary), in parallel. Crossing edges get a vertex: on the box face for a virtual end,
//! otherwise found by Illinois regula falsi on the edge with the brick's tape (`Watertight`,
//! `DualContouring`) or by linear interpolation of the samples (`MarchingCubes`). The cases
//! come from one face rule ([`table`]), so cubes that share a face agree and the mesh is closed.
//! - [`Method::Watertight`]: the marching-cubes polygons, vertices shared by edge.
//! - [`Method::DualContouring`]: one vertex per polygon (component) per cube, placed by a QEF
//!   of its crossings and gradient normals (sharp features), one quad per crossing edge: the
//!   dual of the marching-cubes mesh, hence a closed 2-manifold as well. A polygon that
//!   crosses one cube face twice (walls about a cell thick) is first split in two by a chord
//!   ([`table::DualCase`]): otherwise two such polygons of neighbouring cubes would share two
//!   segments and their vertices a doubled (non-manifold) edge. The edges at a chord's ends
//!   get a fan around their crossing instead of a quad. The QEF minimizer may leave its cube
//!   by one cell (a union's groove less than a cell deep runs through cubes whose samples all
//!   lie on one side, next to the cubes that see both sheets), then a few Newton steps move the vertex
//!   onto the surface (a vertex on a crease does not move).
//!
//!   **Adaptive** ([`MeshSettings::adaptive`]): within each brick, blocks of 2×2×2, then
//!   4×4×4, 8×8×8 cubes collapse to one vertex, bottom-up, when their sub-blocks did, the
//!   block is topologically one cube (Ju et al. 2002: one polygon, no ambiguous face, the
//!   signs in the middle of its edges and faces and at its centre those of one of their
//!   corners) and the vertex of the merged QEF lies within the threshold of every crossing's
//!   tangent plane. The quads are still made per cube edge on the finest lattice, with the
//!   vertex keys of a collapsed block's cubes mapped to its one vertex: the quads inside the
//!   block vanish, those across its faces become triangles, so the mesh is still the closed
//!   2-manifold dual of the (now adaptive) cells.
//! - [`Method::MarchingCubes`]: the classic baseline: uniform grid, no pruning, no
//!   simplification, linear interpolation, normals from the triangles.

pub mod bounds;
pub mod error;
mod qef;
pub mod table;

use std::cell::Cell;
use std::collections::hash_map::Entry;
use std::hash::{Hash, Hasher};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;

use frep_core::eval::batch::BatchEval;
use frep_core::eval::grad::GradEval;
use frep_core::eval::interval::{Interval, IntervalEval};
use frep_core::eval::Inputs;
use frep_core::hash::{FastHasher, FastMap};
use frep_core::simplify::{simplify, SimplifyMode};
use frep_core::{Model, Tape};

use crate::Mesh;
use table::{cases, edge_between, edge_corners};

/// How the surface is extracted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Method {
    /// Dual contouring with QEF vertex placement (sharp features), a closed 2-manifold.
    DualContouring,
    /// Marching cubes on the pruned octree: closed, consistently oriented 2-manifold.
    #[default]
    Watertight,
    /// Classic marching cubes on a uniform grid (the baseline): no pruning, linear
    /// interpolation.
    MarchingCubes,
}

/// The size of the cells.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Resolution {
    /// `2^depth` cells along the longest side of the box.
    Depth(u8),
    /// Cells of (at most) this size.
    CellSize(f64),
}

/// Explicit limits on the work a request may ask for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Largest octree depth (`2^depth` cells along the longest side).
    pub max_depth: u8,
    /// Largest number of output triangles.
    pub max_triangles: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_depth: 12,
            max_triangles: 50_000_000,
        }
    }
}

/// What to polygonize and how.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshSettings {
    /// The box `x0, y0, z0, x1, y1, z1`.
    pub bounds: [f64; 6],
    /// Cell size.
    pub resolution: Resolution,
    /// Extraction method.
    pub method: Method,
    /// Error-bounded simplification after meshing, the bound as a fraction of the cell size
    /// (e.g. 0.1); needs the `export` feature (meshopt). `None`: off.
    pub simplify: Option<f64>,
    /// Adaptive dual contouring: blocks of 2×2×2, 4×4×4, … cubes (up to a brick) whose merged
    /// QEF's vertex lies within this fraction of the cell size of every crossing's tangent
    /// plane, and whose collapse is topologically safe, get one vertex (bigger polygons on flat
    /// regions; the mesh stays a closed 2-manifold). [`Method::DualContouring`] only (ignored
    /// by the other methods); `None`: off.
    pub adaptive: Option<f64>,
    /// Per-vertex colours from the attributes `s[1..3]` (when the model declares `s`).
    pub colors: bool,
    /// Parameters `a[]` and extra coordinates.
    pub inputs: Inputs,
    /// Limits.
    pub limits: Limits,
    /// Worker threads (`None`: rayon's global pool).
    pub threads: Option<usize>,
}

impl Default for MeshSettings {
    fn default() -> Self {
        MeshSettings {
            bounds: [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0],
            resolution: Resolution::Depth(6),
            method: Method::default(),
            simplify: None,
            adaptive: None,
            colors: true,
            inputs: Inputs::default(),
            limits: Limits::default(),
            threads: None,
        }
    }
}

/// Why polygonizing failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// The [`CancelToken`] was cancelled.
    #[error("cancelled")]
    Cancelled,
    /// The box is empty, inverted or not finite.
    #[error("invalid bounding box {0:?}")]
    InvalidBounds([f64; 6]),
    /// The resolution asks for more than [`Limits::max_depth`] (or is not positive).
    #[error("resolution needs depth {depth}, the limit is {max}")]
    TooDeep {
        /// Depth asked for.
        depth: u32,
        /// The limit.
        max: u8,
    },
    /// More triangles than [`Limits::max_triangles`].
    #[error("more than {0} triangles")]
    TooManyTriangles(usize),
    /// The settings ask for something this build cannot do.
    #[error("{0}")]
    Unsupported(&'static str),
}

/// Progress of a run, readable from another thread: `done` of `estimated` work units.
#[derive(Debug, Default)]
pub struct Progress {
    done: AtomicU64,
    estimated: AtomicU64,
}

impl Progress {
    /// A fresh counter.
    pub fn new() -> Self {
        Self::default()
    }

    /// Units done so far.
    pub fn done(&self) -> u64 {
        self.done.load(Ordering::Relaxed)
    }

    /// Current estimate of the total (grows or shrinks as the octree is explored).
    pub fn estimated(&self) -> u64 {
        self.estimated.load(Ordering::Relaxed)
    }

    /// `done / estimated` in `[0, 1]` (0 before the start).
    pub fn fraction(&self) -> f64 {
        let e = self.estimated();
        if e == 0 {
            0.0
        } else {
            (self.done() as f64 / e as f64).min(1.0)
        }
    }

    fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }
}

/// Cancels a run from another thread (clones share the flag).
#[derive(Clone, Debug, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    /// A token not yet cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the run to stop; it returns [`MeshError::Cancelled`] soon after.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether [`CancelToken::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

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

/// The point and bracket buffers of [`Ctx::crossings`], kept per thread between bricks.
#[derive(Default)]
struct CrossingBufs {
    xs: Vec<f64>,
    ys: Vec<f64>,
    zs: Vec<f64>,
    f: Vec<f64>,
    ts: Vec<f64>,
    last: Vec<f64>,
    active: Vec<usize>,
    /// Per edge: (t inside, f there, t outside, f there, side of the last move).
    st: Vec<(f64, f64, f64, f64, i8)>,
}

thread_local! {
    static CROSSING_BUFS: Cell<CrossingBufs> = Cell::new(CrossingBufs::default());
}

/// The per-brick buffers of [`Ctx::extract`], kept per thread between bricks.
#[derive(Default)]
struct ExtractBufs {
    /// Signs of the samples `o − 1 ..= o + b` around the brick.
    sign: Vec<bool>,
    /// Per row of `sign` along x: 0 all outside, 1 all inside, 2 mixed.
    rows: Vec<u8>,
    /// Per edge of the brick's samples (`3 × (b + 2)³`, by lower end and axis): its index in
    /// `edges`, `u32::MAX` before it is met (and again after the brick).
    edge_index: Vec<u32>,
    edges: Vec<EdgeRec>,
    edge_keys: Vec<u64>,
    /// Cubes with surface: (min corner, case, local edge indices).
    cubes: Vec<([i32; 3], usize, [u32; 12])>,
}

thread_local! {
    static EXTRACT_BUFS: Cell<ExtractBufs> = Cell::new(ExtractBufs::default());
}

/// Batch evaluators compiled on this thread, by tape: bricks mostly share a few shortened
/// tapes, and compiling one (a copy of the tape, its register program and registers) per
/// brick cost more than evaluating it.
#[derive(Default)]
struct BatchCache {
    /// (hash of the tape, its evaluator), most recently used last.
    evals: Vec<(u64, BatchEval)>,
}

/// At most this many evaluators are kept per thread.
const BATCH_CACHE: usize = 16;

thread_local! {
    static BATCH_EVALS: Cell<BatchCache> = Cell::new(BatchCache::default());
}

/// Runs `f` with this thread's batch evaluator of `tape` (compiled on first use).
fn with_batch<R>(tape: &Tape, f: impl FnOnce(&mut BatchEval) -> R) -> R {
    let mut cache = BATCH_EVALS.with(Cell::take);
    let mut hasher = FastHasher::default();
    tape.hash(&mut hasher);
    let h = hasher.finish();
    let evals = &mut cache.evals;
    match evals.iter().rposition(|(k, e)| *k == h && e.tape() == tape) {
        Some(i) => {
            let last = evals.len() - 1;
            evals.swap(i, last);
        }
        None => {
            if evals.len() >= BATCH_CACHE {
                evals.remove(0);
            }
            evals.push((h, BatchEval::new(tape)));
        }
    }
    let r = f(&mut evals.last_mut().expect("pushed above").1);
    BATCH_EVALS.with(|c| c.set(cache));
    r
}

/// `v` as `n` zeros, reusing its capacity.
fn zeroed(v: &mut Vec<f64>, n: usize) {
    v.clear();
    v.resize(n, 0.0);
}

/// The sampling lattice.
#[derive(Clone, Debug)]
struct Grid {
    lo: [f64; 3],
    hi: [f64; 3],
    /// Samples (cells) per axis.
    n: [i32; 3],
    /// Cell size per axis.
    h: [f64; 3],
    /// The octree covers `size³` cells.
    size: i32,
    /// Brick side in cells.
    brick: i32,
    /// Bricks per axis (`size / brick`).
    nb: i32,
}

impl Grid {
    fn new(s: &MeshSettings) -> Result<Grid, MeshError> {
        let b = s.bounds;
        let lo = [b[0], b[1], b[2]];
        let hi = [b[3], b[4], b[5]];
        if (0..3).any(|k| !(lo[k].is_finite() && hi[k].is_finite() && hi[k] > lo[k])) {
            return Err(MeshError::InvalidBounds(b));
        }
        let ext = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
        let cell = match s.resolution {
            Resolution::Depth(d) => {
                if d > s.limits.max_depth {
                    return Err(MeshError::TooDeep {
                        depth: d as u32,
                        max: s.limits.max_depth,
                    });
                }
                ext / (1u64 << d) as f64
            }
            Resolution::CellSize(c) => {
                if !(c > 0.0 && c.is_finite()) {
                    return Err(MeshError::TooDeep {
                        depth: u32::MAX,
                        max: s.limits.max_depth,
                    });
                }
                c
            }
        };
        let n = [0, 1, 2].map(|k| (((hi[k] - lo[k]) / cell) * (1.0 - 1e-12)).ceil().max(1.0));
        let nmax = n.iter().fold(1.0f64, |a, &b| a.max(b));
        let depth = nmax.log2().ceil().max(0.0) as u32;
        if depth > s.limits.max_depth as u32 {
            return Err(MeshError::TooDeep {
                depth,
                max: s.limits.max_depth,
            });
        }
        let n = n.map(|v| v as i32);
        let size = 1i32 << depth;
        let brick = BRICK.min(size).max(size / MAX_BRICKS);
        Ok(Grid {
            lo,
            hi,
            n,
            h: [0, 1, 2].map(|k| (hi[k] - lo[k]) / n[k] as f64),
            size,
            brick,
            nb: size / brick,
        })
    }

    /// Coordinate of sample `i` along axis `a`; `-1` and `n` are the box faces.
    #[inline]
    fn coord(&self, a: usize, i: i32) -> f64 {
        if i < 0 {
            self.lo[a]
        } else if i >= self.n[a] {
            self.hi[a]
        } else {
            self.lo[a] + (i as f64 + 0.5) * self.h[a]
        }
    }

    #[inline]
    fn point(&self, p: [i32; 3]) -> [f64; 3] {
        [
            self.coord(0, p[0]),
            self.coord(1, p[1]),
            self.coord(2, p[2]),
        ]
    }

    #[inline]
    fn is_virtual(&self, p: [i32; 3]) -> bool {
        (0..3).any(|a| p[a] < 0 || p[a] >= self.n[a])
    }

    /// The interval box of a node of `s³` cells at `o`, grown by one cell, clipped to the box.
    fn node_box(&self, o: [i32; 3], s: i32) -> [Interval; 3] {
        [0, 1, 2].map(|a| {
            let lo = self.lo[a] + (o[a] as f64 - 0.5) * self.h[a];
            let hi = self.lo[a] + ((o[a] + s) as f64 + 0.5) * self.h[a];
            Interval::new(lo.max(self.lo[a]), hi.min(self.hi[a]))
        })
    }

    #[inline]
    fn brick_id(&self, p: [i32; 3]) -> usize {
        let b = p.map(|c| (c / self.brick) as usize);
        let nb = self.nb as usize;
        b[0] + nb * (b[1] + nb * b[2])
    }

    fn is_boundary_brick(&self, id: usize) -> bool {
        let nb = self.nb as usize;
        let b = [id % nb, id / nb % nb, id / (nb * nb)];
        (0..3).any(|a| b[a] == 0 || (b[a] as i32 + 1) * self.brick >= self.n[a])
    }
}

const OFFS: [[i32; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [0, 1, 0],
    [1, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [0, 1, 1],
    [1, 1, 1],
];

fn add(p: [i32; 3], q: [i32; 3]) -> [i32; 3] {
    [p[0] + q[0], p[1] + q[1], p[2] + q[2]]
}

/// 20 bits per coordinate (shifted by one so that the virtual layer `-1` fits).
fn point_key(p: [i32; 3]) -> u64 {
    ((p[0] + 1) as u64) | ((p[1] + 1) as u64) << 20 | ((p[2] + 1) as u64) << 40
}

/// An evaluated brick.
struct Brick {
    origin: [i32; 3],
    tape: Arc<Tape>,
    /// Inside bits of its `brick³` samples.
    bits: Vec<u64>,
    /// Sample values (the uniform baseline only).
    values: Option<Vec<f32>>,
}

enum Leaf {
    Pruned {
        origin: [i32; 3],
        size: i32,
        inside: bool,
    },
    Brick(Brick),
}

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

/// Splits `v` into consecutive chunks of these lengths.
fn split_lens<T>(mut v: &mut [T], lens: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut out = Vec::new();
    for n in lens {
        let (a, b) = std::mem::take(&mut v).split_at_mut(n);
        out.push(a);
        v = b;
    }
    out
}

/// The merge of marching-cubes bricks (`tris` and `shared`): each brick's vertices in
/// order, a vertex on a shared edge only from the first brick that has it, then the
/// brick's triangles, renumbered. Only the shared vertices go through one hash map, in
/// brick order; numbering and copying run in parallel.
fn merge_marching(outs: &mut [BrickOut], mesh: &mut Mesh, with_colors: bool) {
    // Shared vertices met before: (this brick's vertex, earlier brick, its vertex), in the
    // order of this brick's vertices; `ends[b]` ends brick b's.
    let nshared: usize = outs.iter().map(|o| o.shared.len()).sum();
    let mut first: KeyMap<(u32, u32)> =
        KeyMap::with_capacity_and_hasher(nshared, Default::default());
    let mut dups: Vec<(u32, u32, u32)> = Vec::new();
    let mut ends = Vec::with_capacity(outs.len());
    for (b, o) in outs.iter().enumerate() {
        for &(v, key) in &o.shared {
            match first.entry(key) {
                Entry::Vacant(e) => {
                    e.insert((b as u32, v));
                }
                Entry::Occupied(e) => {
                    let (b0, v0) = *e.get();
                    dups.push((v, b0, v0));
                }
            }
        }
        ends.push(dups.len());
    }
    drop(first);
    let dup_range = |b: usize| if b == 0 { 0 } else { ends[b - 1] }..ends[b];
    // Each brick's kept vertices are numbered in order from its offset.
    let kept: Vec<usize> = (0..outs.len())
        .map(|b| outs[b].positions.len() - dup_range(b).len())
        .collect();
    let mut offsets = Vec::with_capacity(outs.len());
    let mut total = 0usize;
    for &k in &kept {
        offsets.push(total);
        total += k;
    }
    struct Job<'a> {
        out: &'a BrickOut,
        dups: &'a [(u32, u32, u32)],
        offset: u32,
        remap: Vec<u32>,
    }
    let mut jobs: Vec<Job> = outs
        .iter()
        .enumerate()
        .map(|(b, o)| Job {
            out: o,
            dups: &dups[dup_range(b)],
            offset: offsets[b] as u32,
            remap: Vec::new(),
        })
        .collect();
    par_each(&mut jobs, |j| {
        let n = j.out.positions.len();
        j.remap.reserve_exact(n);
        let (mut next, mut d) = (j.offset, 0);
        for v in 0..n as u32 {
            if j.dups.get(d).is_some_and(|x| x.0 == v) {
                j.remap.push(u32::MAX);
                d += 1;
            } else {
                j.remap.push(next);
                next += 1;
            }
        }
    });
    // The earlier bricks' numbers of the duplicates.
    let fixes: Vec<Vec<u32>> = par_map(&jobs, |j| {
        j.dups
            .iter()
            .map(|&(_, b0, v0)| jobs[b0 as usize].remap[v0 as usize])
            .collect()
    });
    for (j, f) in jobs.iter_mut().zip(fixes) {
        for (&(v, _, _), g) in j.dups.iter().zip(f) {
            j.remap[v as usize] = g;
        }
    }
    let base_v = mesh.positions.len();
    let base_t = mesh.triangles.len();
    let ntri: usize = outs.iter().map(|o| o.tris.len()).sum();
    mesh.positions.resize(base_v + total, [0.0; 3]);
    mesh.normals.resize(base_v + total, [0.0; 3]);
    if with_colors {
        mesh.colors.resize(base_v + total, [0.0; 3]);
    }
    mesh.triangles.resize(base_t + ntri, [0; 3]);
    let pos = split_lens(&mut mesh.positions[base_v..], kept.iter().copied());
    let nrm = split_lens(&mut mesh.normals[base_v..], kept.iter().copied());
    let mut col = if with_colors {
        split_lens(&mut mesh.colors[base_v..], kept.iter().copied())
    } else {
        Vec::new()
    };
    col.resize_with(outs.len(), Default::default);
    let tri = split_lens(
        &mut mesh.triangles[base_t..],
        outs.iter().map(|o| o.tris.len()),
    );
    let mut work: Vec<_> = jobs
        .iter()
        .zip(pos)
        .zip(nrm)
        .zip(col)
        .zip(tri)
        .map(|((((j, p), n), c), t)| (j, p, n, c, t))
        .collect();
    par_each(&mut work, |(j, p, n, c, t)| {
        let o = j.out;
        let mut k = 0;
        for (v, &g) in j.remap.iter().enumerate() {
            if g == j.offset + k as u32 {
                p[k] = o.positions[v];
                n[k] = o.normals[v];
                if !c.is_empty() {
                    c[k] = o.colors.get(v).copied().unwrap_or([0.0; 3]);
                }
                k += 1;
            }
        }
        for (dst, src) in t.iter_mut().zip(&o.tris) {
            *dst = src.map(|i| j.remap[i as usize]);
        }
    });
    drop(work);
    drop(jobs);
    for o in outs.iter_mut() {
        *o = BrickOut::default();
    }
}

/// Maps by integer key ([`FastHasher`]).
type KeyMap<V> = FastMap<u64, V>;

enum Class {
    Inside,
    Outside,
    Go(Arc<Tape>),
}

impl Ctx<'_> {
    fn check(&self) -> Result<(), MeshError> {
        if self.cancel.is_cancelled() {
            Err(MeshError::Cancelled)
        } else {
            Ok(())
        }
    }

    fn bricks_in(&self, s: i32) -> u64 {
        let k = (s / self.grid.brick).max(1) as u64;
        k * k * k
    }

    fn classify(
        &self,
        ev: &mut Option<IntervalEval>,
        tape: &Arc<Tape>,
        o: [i32; 3],
        s: i32,
    ) -> Class {
        if (0..3).any(|a| o[a] >= self.grid.n[a]) {
            return Class::Outside;
        }
        let Some(ev) = ev else {
            return Class::Go(tape.clone());
        };
        let [x, y, z] = self.grid.node_box(o, s);
        let iv = ev.eval(x, y, z, self.inputs);
        if iv.is_positive() {
            Class::Inside
        } else if iv.is_outside() {
            Class::Outside
        } else {
            let t = simplify(tape, ev.choices(), SimplifyMode::Sign);
            if t.len() < tape.len() {
                Class::Go(Arc::new(t))
            } else {
                Class::Go(tape.clone())
            }
        }
    }

    fn descend(&self, tape: Arc<Tape>, o: [i32; 3], s: i32) -> Result<Vec<Leaf>, MeshError> {
        self.check()?;
        if s <= self.grid.brick {
            return Ok(vec![Leaf::Brick(self.eval_brick(tape, o))]);
        }
        let half = s / 2;
        let mut ev = (self.method != Method::MarchingCubes).then(|| IntervalEval::new(&tape));
        let mut leaves = Vec::new();
        let mut todo = Vec::new();
        for off in OFFS {
            let co = [
                o[0] + off[0] * half,
                o[1] + off[1] * half,
                o[2] + off[2] * half,
            ];
            match self.classify(&mut ev, &tape, co, half) {
                Class::Go(t) => todo.push((t, co)),
                c => {
                    self.progress.add(self.bricks_in(half));
                    leaves.push(Leaf::Pruned {
                        origin: co,
                        size: half,
                        inside: matches!(c, Class::Inside),
                    });
                }
            }
        }
        for r in par_map(&todo, |(t, co)| self.descend(t.clone(), *co, half)) {
            leaves.extend(r?);
        }
        Ok(leaves)
    }

    fn eval_brick(&self, tape: Arc<Tape>, o: [i32; 3]) -> Brick {
        let g = &self.grid;
        let b = g.brick;
        let m = (b * b * b) as usize;
        // The crossing search's buffers of this thread (not in use while descending).
        let mut bufs = CROSSING_BUFS.with(Cell::take);
        let CrossingBufs { xs, ys, zs, f, .. } = &mut bufs;
        for v in [&mut *xs, &mut *ys, &mut *zs] {
            v.clear();
        }
        // The brick's coordinates along x, then the rows and layers from them.
        xs.extend((0..b).map(|i| g.coord(0, o[0] + i)));
        let bu = b as usize;
        for _ in 1..bu * bu {
            xs.extend_from_within(..bu);
        }
        for k in 0..b {
            let z = g.coord(2, o[2] + k);
            for j in 0..b {
                let y = g.coord(1, o[1] + j);
                ys.extend(std::iter::repeat_n(y, bu));
                zs.extend(std::iter::repeat_n(z, bu));
            }
        }
        zeroed(f, m);
        with_batch(&tape, |be| be.eval(xs, ys, zs, self.inputs, f));
        let out = &f[..];
        let mut bits = vec![0u64; m.div_ceil(64)];
        // Samples past the grid's last (the virtual layer) stay outside.
        let clipped = (0..3).any(|a| o[a] + b > g.n[a]);
        let mut l = 0;
        for k in 0..b {
            for j in 0..b {
                for i in 0..b {
                    let real = !clipped || !g.is_virtual([o[0] + i, o[1] + j, o[2] + k]);
                    if out[l] >= 0.0 && real {
                        bits[l / 64] |= 1 << (l % 64);
                    }
                    l += 1;
                }
            }
        }
        let values = (self.method == Method::MarchingCubes).then(|| {
            out.iter()
                .map(|&v| {
                    // Keep the sign through the narrowing.
                    let f = v as f32;
                    if f == 0.0 && v < 0.0 {
                        -f32::MIN_POSITIVE
                    } else {
                        f
                    }
                })
                .collect()
        });
        CROSSING_BUFS.with(|c| c.set(bufs));
        self.progress.add(1);
        Brick {
            origin: o,
            tape,
            bits,
            values,
        }
    }
}

/// Canonical signs of every sample: the brick map.
struct Lattice<'a> {
    grid: &'a Grid,
    /// Per brick: 0 outside, 1 inside, `2 + i` evaluated brick `i`.
    map: Vec<u32>,
    bricks: Vec<Brick>,
}

const OUTSIDE: u32 = 0;
const INSIDE: u32 = 1;

impl Lattice<'_> {
    #[inline]
    fn local(&self, p: [i32; 3]) -> usize {
        let b = self.grid.brick;
        let l = p.map(|c| c % b);
        (l[0] + b * (l[1] + b * l[2])) as usize
    }

    #[inline]
    fn inside(&self, p: [i32; 3]) -> bool {
        if self.grid.is_virtual(p) {
            return false;
        }
        match self.map[self.grid.brick_id(p)] {
            OUTSIDE => false,
            INSIDE => true,
            k => {
                let l = self.local(p);
                self.bricks[(k - 2) as usize].bits[l / 64] >> (l % 64) & 1 == 1
            }
        }
    }

    /// Sample value (uniform baseline: every real sample is in an evaluated brick).
    fn value(&self, p: [i32; 3]) -> f64 {
        match self.map[self.grid.brick_id(p)] {
            OUTSIDE => -1.0,
            INSIDE => 1.0,
            k => self.bricks[(k - 2) as usize]
                .values
                .as_ref()
                .map_or(0.0, |v| v[self.local(p)] as f64),
        }
    }

    fn case_at(&self, q: [i32; 3]) -> usize {
        let mut mask = 0;
        for (c, off) in OFFS.iter().enumerate() {
            if self.inside(add(q, *off)) {
                mask |= 1 << c;
            }
        }
        mask
    }

    /// The brick that handles cube `q`.
    fn owner(&self, q: [i32; 3]) -> Option<usize> {
        let mut first = None;
        for off in OFFS {
            let p = add(q, off);
            if self.grid.is_virtual(p) {
                continue;
            }
            let id = self.grid.brick_id(p);
            match self.map[id] {
                OUTSIDE => {}
                INSIDE => {
                    if first.is_none() && self.grid.is_boundary_brick(id) {
                        first = Some(id);
                    }
                }
                _ => return Some(id),
            }
        }
        first
    }
}

/// What one brick contributes.
#[derive(Default)]
struct BrickOut {
    /// Dual contouring: the vertices' keys (one per position).
    keys: Vec<u64>,
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    colors: Vec<[f32; 3]>,
    /// Marching cubes: triangles of this brick's vertex indices.
    tris: Vec<[u32; 3]>,
    /// Marching cubes: `(vertex index, key)` of the vertices on edges that cubes of other
    /// bricks may share, by increasing index (the others are this brick's alone).
    shared: Vec<(u32, u64)>,
    /// Dual contouring: triangles of vertex keys.
    triangles: Vec<[u64; 3]>,
    /// Dual contouring: quads of vertex keys, counter-clockwise from outside.
    quads: Vec<[u64; 4]>,
    /// Adaptive dual contouring: `(key, merged vertex's key)` of the vertices of collapsed
    /// blocks.
    aliases: Vec<(u64, u64)>,
}

struct EdgeRec {
    /// Lower end.
    p: [i32; 3],
    axis: usize,
    /// Whether the lower end is the inside one.
    inside_low: bool,
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if l > 0.0 && l.is_finite() {
        v.map(|c| c / l)
    } else {
        [0.0; 3]
    }
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}

impl Ctx<'_> {
    /// Finds the crossings of `edges` (positions and outward unit normals).
    fn crossings(
        &self,
        lat: &Lattice,
        brick: Option<&Brick>,
        edges: &[EdgeRec],
    ) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let g = &self.grid;
        let mut pos = vec![[0.0; 3]; edges.len()];
        let mut nrm = vec![[0.0; 3]; edges.len()];
        // Real edges to refine: (edge index, inside point, outside point).
        let mut todo: Vec<(usize, [f64; 3], [f64; 3])> = Vec::with_capacity(edges.len());
        for (i, e) in edges.iter().enumerate() {
            let mut hi = e.p;
            hi[e.axis] += 1;
            let (pin, pout) = if e.inside_low { (e.p, hi) } else { (hi, e.p) };
            if g.is_virtual(pout) {
                pos[i] = g.point(pout);
                let mut n = [0.0; 3];
                n[e.axis] = if e.inside_low { 1.0 } else { -1.0 };
                nrm[i] = n;
                continue;
            }
            let (a, b) = (g.point(pin), g.point(pout));
            if self.method == Method::MarchingCubes || brick.is_none() {
                let (fa, fb) = (lat.value(pin), lat.value(pout));
                let t = if fa >= 0.0 && fb < 0.0 {
                    fa / (fa - fb)
                } else {
                    0.5
                };
                let t = t.clamp(EDGE_MARGIN, 1.0 - EDGE_MARGIN);
                pos[i] = [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
            } else {
                todo.push((i, a, b));
            }
        }
        let Some(brick) = brick.filter(|_| !todo.is_empty()) else {
            return (pos, nrm);
        };
        with_batch(&brick.tape, |be| {
            self.crossings_with(brick, be, todo, pos, nrm)
        })
    }

    /// [`Ctx::crossings`] of the edges `todo` to refine, with the brick's evaluator.
    fn crossings_with(
        &self,
        brick: &Brick,
        be: &mut BatchEval,
        todo: Vec<(usize, [f64; 3], [f64; 3])>,
        mut pos: Vec<[f64; 3]>,
        mut nrm: Vec<[f64; 3]>,
    ) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let g = &self.grid;
        let n = todo.len();
        // This thread's buffers: no allocation per brick (the allocator's locks are shared).
        let mut bufs = CROSSING_BUFS.with(Cell::take);
        let CrossingBufs {
            xs,
            ys,
            zs,
            f,
            ts,
            last,
            active,
            st,
        } = &mut bufs;
        for v in [&mut *xs, &mut *ys, &mut *zs, &mut *f] {
            zeroed(v, 2 * n);
        }
        for (j, (_, a, b)) in todo.iter().enumerate() {
            (xs[j], ys[j], zs[j]) = (a[0], a[1], a[2]);
            (xs[n + j], ys[n + j], zs[n + j]) = (b[0], b[1], b[2]);
        }
        be.eval(xs, ys, zs, self.inputs, f);
        // Brackets: t0 inside (f0 ≥ 0), t1 outside; side of the last move for Illinois.
        st.clear();
        st.extend((0..n).map(|j| (0.0, f[j], 1.0, f[n + j], 0)));
        let next_t = |s: &(f64, f64, f64, f64, i8)| {
            let (t0, f0, t1, f1, _) = *s;
            if f0.is_finite() && f1.is_finite() && f0 >= 0.0 && f1 < 0.0 {
                let t = t0 + (t1 - t0) * f0 / (f0 - f1);
                if t > t0 && t < t1 {
                    return t;
                }
            }
            0.5 * (t0 + t1)
        };
        xs.truncate(n);
        ys.truncate(n);
        zs.truncate(n);
        f.truncate(n);
        zeroed(ts, n);
        // Edges still searched: an edge whose estimate moved by less than `ROOT_TOL` of the
        // edge (or that hit `f = 0`) is done and leaves the batch.
        active.clear();
        active.extend(0..n);
        last.clear();
        last.resize(n, f64::NAN);
        for _ in 0..ROOT_STEPS {
            let m = active.len();
            if m == 0 {
                break;
            }
            for (k, &j) in active.iter().enumerate() {
                let (a, b) = (todo[j].1, todo[j].2);
                let t = next_t(&st[j]);
                ts[k] = t;
                xs[k] = a[0] + t * (b[0] - a[0]);
                ys[k] = a[1] + t * (b[1] - a[1]);
                zs[k] = a[2] + t * (b[2] - a[2]);
            }
            be.eval(&xs[..m], &ys[..m], &zs[..m], self.inputs, &mut f[..m]);
            for (k, &j) in active.iter().enumerate() {
                let s = &mut st[j];
                if f[k] >= 0.0 {
                    *s = (ts[k], f[k], s.2, if s.4 == 1 { 0.5 * s.3 } else { s.3 }, 1);
                } else {
                    let f1 = if f[k].is_nan() { s.3 } else { f[k] };
                    *s = (s.0, if s.4 == -1 { 0.5 * s.1 } else { s.1 }, ts[k], f1, -1);
                }
            }
            let mut k = 0;
            active.retain(|&j| {
                let done = f[k] == 0.0 || (ts[k] - last[j]).abs() < ROOT_TOL;
                last[j] = ts[k];
                k += 1;
                !done
            });
        }
        for (j, (i, a, b)) in todo.iter().enumerate() {
            let t = next_t(&st[j]).clamp(EDGE_MARGIN, 1.0 - EDGE_MARGIN);
            pos[*i] = [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
        }
        // Normals: central differences at `NORMAL_STEP` of a cell, all crossings of the brick
        // in one batch (six points each); where they vanish or are not finite (a flat or
        // singular field there), forward-mode differentiation.
        let hs = g.h.map(|c| c * NORMAL_STEP);
        for v in [&mut *xs, &mut *ys, &mut *zs, &mut *f] {
            zeroed(v, 6 * n);
        }
        for (j, (i, _, _)) in todo.iter().enumerate() {
            let p = pos[*i];
            for o in 0..6 {
                let (ax, k) = (o / 2, 6 * j + o);
                let mut q = p;
                q[ax] += if o % 2 == 0 { hs[ax] } else { -hs[ax] };
                (xs[k], ys[k], zs[k]) = (q[0], q[1], q[2]);
            }
        }
        be.eval(xs, ys, zs, self.inputs, f);
        let mut ge: Option<GradEval> = None;
        for (j, (i, _, _)) in todo.iter().enumerate() {
            let v = &f[6 * j..6 * j + 6];
            let d = [0, 1, 2].map(|k| -(v[2 * k] - v[2 * k + 1]) / hs[k]);
            let mut nv = norm(d);
            if nv == [0.0; 3] {
                let p = pos[*i];
                let gr = ge.get_or_insert_with(|| GradEval::new(&brick.tape)).eval(
                    p[0],
                    p[1],
                    p[2],
                    self.inputs,
                );
                nv = norm([-gr.dx, -gr.dy, -gr.dz]);
            }
            nrm[*i] = nv;
        }
        CROSSING_BUFS.with(|c| c.set(bufs));
        (pos, nrm)
    }

    /// Moves a dual-contouring vertex onto the surface by Newton steps along the gradient,
    /// staying in the cube `[lo, hi]`: where the QEF minimizer had to be clamped (a crease that
    /// leaves the cube) or the tangent planes disagree (curvature), the vertex would
    /// otherwise sit off the surface. On a crease `f ≈ 0` already and nothing moves.
    fn snap(&self, ge: &mut GradEval, x: [f64; 3], lo: [f64; 3], hi: [f64; 3]) -> [f64; 3] {
        let mut x = x;
        for _ in 0..SNAP_STEPS {
            let g = ge.eval(x[0], x[1], x[2], self.inputs);
            let len2 = g.dx * g.dx + g.dy * g.dy + g.dz * g.dz;
            if !(len2 > 0.0 && len2.is_finite() && g.v.is_finite()) || g.v == 0.0 {
                break;
            }
            let s = g.v / len2;
            let y = [
                (x[0] - s * g.dx).clamp(lo[0], hi[0]),
                (x[1] - s * g.dy).clamp(lo[1], hi[1]),
                (x[2] - s * g.dz).clamp(lo[2], hi[2]),
            ];
            if y == x {
                break;
            }
            x = y;
        }
        x
    }

    /// Adaptive dual contouring ([`MeshSettings::adaptive`]): the blocks of 2×2×2, 4×4×4, …
    /// cubes of brick `o` that collapse to one vertex, as `cube's vertex key → (merged
    /// vertex's key, position, normal)`. Bottom-up (Ju et al. 2002, "Dual Contouring of Hermite
    /// Data", §4.2), a block of side `S` collapses when
    /// - its 8 sub-blocks are empty or collapsed (cubes: one polygon), and all its samples are
    ///   real (no cap);
    /// - as one cube (its 8 corner samples) it has one polygon and no ambiguous face;
    /// - its topology is the coarse cube's: the sample in the middle of each coarse edge has
    ///   the sign of one of the edge's ends, the one in the middle of each face the sign of
    ///   one of the face's corners, the centre the sign of one of the corners (the finer
    ///   samples were checked by the sub-blocks);
    /// - the vertex of the QEF of all its crossings, snapped onto the surface, lies within
    ///   `tol` cell of every crossing's tangent plane.
    #[allow(clippy::too_many_arguments)]
    fn collapse(
        &self,
        ge: &mut GradEval,
        o: [i32; 3],
        sign: &[bool],
        cubes: &[([i32; 3], usize, [u32; 12])],
        pos: &[[f64; 3]],
        nrm: &[[f64; 3]],
        tol: f64,
    ) -> KeyMap<(u64, [f64; 3], [f64; 3])> {
        /// A block: no surface, not collapsible, or collapsed (its cubes' vertex keys and
        /// crossings).
        #[derive(Clone)]
        enum Block {
            Empty,
            Blocked,
            Merged(Vec<u64>, Vec<u32>),
        }
        let g = &self.grid;
        let b = g.brick;
        let e = (b + 2) as usize;
        let at = |p: [i32; 3]| {
            sign[(p[0] - o[0] + 1) as usize
                + e * ((p[1] - o[1] + 1) as usize + e * (p[2] - o[2] + 1) as usize)]
        };
        let dual = table::dual_cases();
        let h = g.h.iter().fold(0.0f64, |a, &c| a.max(c));
        let idx = |k: [i32; 3], n: i32| (k[0] + n * (k[1] + n * k[2])) as usize;
        // Level 0: the cubes of the brick.
        let mut level = vec![Block::Empty; (b * b * b) as usize];
        for (q, mask, local) in cubes {
            let k = [0, 1, 2].map(|a| q[a] - o[a]);
            if k.iter().any(|&c| c < 0 || c >= b) {
                continue;
            }
            level[idx(k, b)] = match &dual[*mask].polygons[..] {
                [poly] => Block::Merged(
                    vec![point_key(*q) << 3],
                    poly.iter().map(|&ei| local[ei as usize]).collect(),
                ),
                _ => Block::Blocked,
            };
        }
        let mut out = KeyMap::default();
        let (mut pts, mut ns) = (Vec::new(), Vec::new());
        let mut side = 2;
        while side <= b {
            let n = b / side;
            let mut next = vec![Block::Empty; (n * n * n) as usize];
            for kz in 0..n {
                for ky in 0..n {
                    for kx in 0..n {
                        let k = [kx, ky, kz];
                        let q0 = [0, 1, 2].map(|a| o[a] + side * k[a]);
                        let subs: Vec<&Block> = OFFS
                            .iter()
                            .map(|off| &level[idx([0, 1, 2].map(|a| 2 * k[a] + off[a]), 2 * n)])
                            .collect();
                        let blocked = subs.iter().any(|s| matches!(s, Block::Blocked))
                            || (subs.iter().any(|s| matches!(s, Block::Merged(..)))
                                && !self.coarse_ok(&at, q0, side));
                        next[idx(k, n)] = if blocked {
                            Block::Blocked
                        } else {
                            let (mut members, mut edges) = (Vec::new(), Vec::new());
                            for s in subs {
                                if let Block::Merged(m, es) = s {
                                    members.extend_from_slice(m);
                                    edges.extend_from_slice(es);
                                }
                            }
                            edges.sort_unstable();
                            edges.dedup();
                            if members.is_empty() {
                                Block::Empty
                            } else if members.len() == 1 {
                                Block::Merged(members, edges)
                            } else {
                                pts.clear();
                                ns.clear();
                                let mut avg = [0.0; 3];
                                for &v in &edges {
                                    pts.push(pos[v as usize]);
                                    ns.push(nrm[v as usize]);
                                    for c in 0..3 {
                                        avg[c] += nrm[v as usize][c];
                                    }
                                }
                                let lo = [0, 1, 2].map(|a| g.coord(a, q0[a]) - DC_SLACK * g.h[a]);
                                let hi =
                                    [0, 1, 2].map(|a| g.coord(a, q0[a] + side) + DC_SLACK * g.h[a]);
                                let x = self.snap(ge, qef::solve(&pts, &ns, lo, hi), lo, hi);
                                let far = pts.iter().zip(&ns).any(|(p, nr)| {
                                    let d = (0..3).map(|c| nr[c] * (x[c] - p[c])).sum::<f64>();
                                    d.is_nan() || d.abs() > tol * h
                                });
                                if far {
                                    Block::Blocked
                                } else {
                                    let rep = members[0];
                                    for &m in &members {
                                        out.insert(m, (rep, x, norm(avg)));
                                    }
                                    Block::Merged(members, edges)
                                }
                            }
                        };
                    }
                }
            }
            level = next;
            side *= 2;
        }
        out
    }

    /// Whether the block of `side` cubes at `q0` is one coarse cube topologically (see
    /// [`Ctx::collapse`]): real samples, one polygon, no ambiguous face, the signs in the
    /// middle of its edges and faces and at its centre those of one of their corners.
    fn coarse_ok(&self, at: &impl Fn([i32; 3]) -> bool, q0: [i32; 3], side: i32) -> bool {
        let g = &self.grid;
        if (0..3).any(|a| q0[a] + side >= g.n[a]) {
            return false;
        }
        let half = side / 2;
        let corner = |c: usize| add(q0, OFFS[c].map(|v| side * v));
        let mut cm = 0usize;
        for c in 0..8 {
            cm |= (at(corner(c)) as usize) << c;
        }
        if cm == 0 || cm == 255 || cases()[cm].polygons() != 1 {
            return false;
        }
        for (c0, off0) in OFFS.iter().enumerate() {
            for a in 0..3 {
                let c1 = c0 | 1 << a;
                if c1 == c0 {
                    continue;
                }
                let (s0, s1) = (at(corner(c0)), at(corner(c1)));
                let mid = at(add(q0, add(*off0, OFFS[c1]).map(|v| half * v)));
                if s0 == s1 && mid != s0 {
                    return false;
                }
            }
        }
        for a in 0..3 {
            for sd in 0..2 {
                let cs: Vec<usize> = (0..8).filter(|c| (c >> a) & 1 == sd).collect();
                let mut centre = q0.map(|v| v + half);
                centre[a] = q0[a] + side * sd as i32;
                let sc = at(centre);
                if !cs.iter().any(|&c| at(corner(c)) == sc) {
                    return false;
                }
                // Two inside corners on a diagonal (their indices differ in two bits).
                let inside: Vec<usize> = cs.iter().copied().filter(|&c| at(corner(c))).collect();
                if let [i, j] = inside[..] {
                    if (i ^ j).count_ones() == 2 {
                        return false;
                    }
                }
            }
        }
        let sc = at(q0.map(|v| v + half));
        (0..8).any(|c| at(corner(c)) == sc)
    }

    fn colors_at(&self, brick: Option<&Brick>, pts: &[[f64; 3]]) -> Vec<[f32; 3]> {
        let Some(brick) = brick.filter(|_| self.colors > 0 && !pts.is_empty()) else {
            return Vec::new();
        };
        let xs: Vec<f64> = pts.iter().map(|p| p[0]).collect();
        let ys: Vec<f64> = pts.iter().map(|p| p[1]).collect();
        let zs: Vec<f64> = pts.iter().map(|p| p[2]).collect();
        let mut outs = vec![Vec::new(); brick.tape.outputs.len()];
        with_batch(&brick.tape, |be| {
            be.eval_outputs(&xs, &ys, &zs, self.inputs, &mut outs)
        });
        (0..pts.len())
            .map(|i| {
                [0, 1, 2].map(|c| {
                    let k = (c + 1).min(self.colors);
                    let v = outs[k][i] as f32;
                    if v.is_finite() {
                        v.clamp(0.0, 1.0)
                    } else {
                        0.0
                    }
                })
            })
            .collect()
    }

    /// Extracts the cubes owned by brick `id` (evaluated brick `eval`, if any).
    fn extract(
        &self,
        lat: &Lattice,
        id: usize,
        eval: Option<usize>,
    ) -> Result<BrickOut, MeshError> {
        // This thread's buffers: no allocation per brick for them.
        let mut bufs = EXTRACT_BUFS.with(Cell::take);
        let out = self.extract_with(lat, id, eval, &mut bufs);
        EXTRACT_BUFS.with(|c| c.set(bufs));
        out
    }

    /// [`Ctx::extract`] with the buffers given.
    fn extract_with(
        &self,
        lat: &Lattice,
        id: usize,
        eval: Option<usize>,
        bufs: &mut ExtractBufs,
    ) -> Result<BrickOut, MeshError> {
        self.check()?;
        let g = &self.grid;
        let b = g.brick;
        let nb = g.nb as usize;
        let o = [id % nb, id / nb % nb, id / (nb * nb)].map(|c| c as i32 * b);
        let brick = eval.map(|k| &lat.bricks[k]);
        // Signs of samples o-1 ..= o+b.
        let e = (b + 2) as usize;
        let ExtractBufs {
            sign,
            rows,
            edge_index,
            edges,
            edge_keys,
            cubes,
        } = bufs;
        sign.clear();
        sign.resize(e * e * e, false);
        // By the 27 bricks around (this one included): the layer below (−1), the brick's
        // own samples (0), the layer above (+1) along each axis.
        let span = |d: i32| match d {
            -1 => -1..=-1,
            0 => 0..=b - 1,
            _ => b..=b,
        };
        let bc = o.map(|c| c / b);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let nc = [bc[0] + dx, bc[1] + dy, bc[2] + dz];
                    if nc.iter().any(|&c| c < 0 || c >= g.nb) {
                        continue;
                    }
                    let nid = nc[0] as usize + nb * (nc[1] as usize + nb * nc[2] as usize);
                    let bits = match lat.map[nid] {
                        OUTSIDE => continue,
                        INSIDE => None,
                        k => Some(&lat.bricks[(k - 2) as usize].bits),
                    };
                    let d = [dx, dy, dz].map(|c| c * b);
                    for k in span(dz) {
                        for j in span(dy) {
                            for i in span(dx) {
                                let l = (i + 1) as usize
                                    + e * ((j + 1) as usize + e * (k + 1) as usize);
                                sign[l] = match bits {
                                    // Virtual samples are outside (not set in the bits).
                                    None => !g.is_virtual([o[0] + i, o[1] + j, o[2] + k]),
                                    Some(bits) => {
                                        let m =
                                            (i - d[0] + b * (j - d[1] + b * (k - d[2]))) as usize;
                                        bits[m / 64] >> (m % 64) & 1 == 1
                                    }
                                };
                            }
                        }
                    }
                }
            }
        }
        debug_assert!((0..e * e * e).all(|l| {
            let c = [l % e, l / e % e, l / (e * e)].map(|c| c as i32 - 1);
            sign[l] == lat.inside([o[0] + c[0], o[1] + c[1], o[2] + c[2]])
        }));
        let table = cases();
        let edge_slot = |p: [i32; 3], axis: usize| {
            let l = [0, 1, 2].map(|a| (p[a] - o[a] + 1) as usize);
            axis + 3 * (l[0] + e * (l[1] + e * l[2]))
        };
        // Every entry is `u32::MAX` between bricks (reset below).
        if edge_index.len() < 3 * e * e * e {
            edge_index.resize(3 * e * e * e, u32::MAX);
        }
        edges.clear();
        edge_keys.clear();
        cubes.clear();
        let upper = [0, 1, 2].map(|a| (b - 1).min(g.n[a] - 1 - o[a]));
        // Per row of samples along x: 0 all outside, 1 all inside, 2 mixed.
        rows.clear();
        rows.extend(sign.chunks_exact(e).map(|r| {
            if r.iter().all(|&v| v) {
                1u8
            } else if r.iter().all(|&v| !v) {
                0
            } else {
                2
            }
        }));
        for k in -1..=upper[2] {
            for j in -1..=upper[1] {
                // The four rows of this row of cubes; all alike and not mixed: no surface.
                let r = [(j, k), (j + 1, k), (j, k + 1), (j + 1, k + 1)]
                    .map(|(y, z)| (y + 1) as usize * e + (z + 1) as usize * e * e);
                let st = r.map(|l| rows[l / e]);
                if st[0] != 2 && st.iter().all(|&v| v == st[0]) {
                    continue;
                }
                // Corner bits of the cubes' x = i face: bits 0, 2, 4, 6 of the case.
                let face = |x: usize| {
                    sign[r[0] + x] as usize
                        | (sign[r[1] + x] as usize) << 2
                        | (sign[r[2] + x] as usize) << 4
                        | (sign[r[3] + x] as usize) << 6
                };
                let mut left = face(0);
                for i in -1..=upper[0] {
                    let q = [o[0] + i, o[1] + j, o[2] + k];
                    let right = face((i + 2) as usize);
                    let mask = left | right << 1;
                    left = right;
                    if mask == 0 || mask == 255 {
                        continue;
                    }
                    let border = [i, j, k].iter().any(|&c| c < 0 || c >= b - 1);
                    if border && lat.owner(q) != Some(id) {
                        continue;
                    }
                    let case = &table[mask];
                    let mut local = [u32::MAX; 12];
                    for (ei, comp) in case.component.iter().enumerate() {
                        if *comp == 255 {
                            continue;
                        }
                        let (c0, c1) = edge_corners(ei as u8);
                        let p = add(q, OFFS[c0]);
                        let axis = (c0 ^ c1).trailing_zeros() as usize;
                        let slot = &mut edge_index[edge_slot(p, axis)];
                        if *slot == u32::MAX {
                            *slot = edges.len() as u32;
                            edges.push(EdgeRec {
                                p,
                                axis,
                                inside_low: mask >> c0 & 1 == 1,
                            });
                            edge_keys.push(point_key(p) << 2 | axis as u64);
                        }
                        local[ei] = *slot;
                    }
                    cubes.push((q, mask, local));
                }
            }
        }
        for r in edges.iter() {
            edge_index[edge_slot(r.p, r.axis)] = u32::MAX;
        }
        let (pos, nrm) = self.crossings(lat, brick, edges);
        let mut out = BrickOut::default();
        if self.method != Method::DualContouring {
            out.colors = self.colors_at(brick, &pos);
            out.positions = pos.iter().map(|p| p.map(|c| c as f32)).collect();
            out.normals = nrm.iter().map(|p| p.map(|c| c as f32)).collect();
            // Most cases are one or two triangles (no regrowth in the common case).
            out.tris.reserve(2 * cubes.len());
            out.shared.reserve(edges.len());
            // An edge is this brick's alone when its four cubes are inner cubes of the
            // brick (every corner sample in it: only this brick makes them). Along the
            // edge its lower end is such a cube's lower corner, across it the lower end
            // is a cube's lower or upper corner.
            for (v, e) in edges.iter().enumerate() {
                let inner = (0..3).all(|a| {
                    let c = e.p[a] - o[a];
                    c >= i32::from(a != e.axis) && c <= b - 2
                });
                if !inner {
                    out.shared.push((v as u32, edge_keys[v]));
                }
            }
            for (_, mask, local) in cubes.iter() {
                let case = &table[*mask];
                for k in 0..case.polygons() {
                    let poly = case.polygon(k);
                    let key = |e: u8| local[e as usize];
                    let p = |e: u8| pos[local[e as usize] as usize];
                    let n = poly.len();
                    if n == 3 {
                        out.tris.push([key(poly[0]), key(poly[1]), key(poly[2])]);
                        continue;
                    }
                    // A fan whose diagonals avoid the cube's faces: a diagonal on a face
                    // would be a diagonal of the neighbouring cube too (a non-manifold edge).
                    let fan_ok = |apex: usize| {
                        (2..n - 1).all(|j| !table::share_face(poly[apex], poly[(apex + j) % n]))
                    };
                    let mut apexes: Vec<usize> = (0..n).filter(|&a| fan_ok(a)).collect();
                    if n == 4 && apexes.len() == 2 {
                        // The shorter diagonal.
                        if dist2(p(poly[1]), p(poly[3])) < dist2(p(poly[0]), p(poly[2])) {
                            apexes.swap(0, 1);
                        }
                    }
                    if let Some(&a) = apexes.first() {
                        for j in 1..n - 1 {
                            out.tris.push([
                                key(poly[a]),
                                key(poly[(a + j) % n]),
                                key(poly[(a + j + 1) % n]),
                            ]);
                        }
                        continue;
                    }
                    // No such fan: a centre vertex.
                    let mut c = [0.0; 3];
                    let mut nc = [0.0; 3];
                    for &e in poly {
                        let v = local[e as usize] as usize;
                        for d in 0..3 {
                            c[d] += pos[v][d] / n as f64;
                            nc[d] += nrm[v][d];
                        }
                    }
                    let ck = out.positions.len() as u32;
                    out.positions.push(c.map(|x| x as f32));
                    out.normals.push(norm(nc).map(|x| x as f32));
                    if !out.colors.is_empty() {
                        let col = out.colors[local[poly[0] as usize] as usize];
                        out.colors.push(col);
                    }
                    for j in 0..n {
                        out.tris.push([ck, key(poly[j]), key(poly[(j + 1) % n])]);
                    }
                }
            }
            return Ok(out);
        }
        // Dual contouring: one vertex per polygon (split where a polygon crosses a face
        // twice, see `DualCase`), one quad per crossing lower edge.
        let dual = table::dual_cases();
        let mut ge = brick.map(|b| GradEval::new(&b.tape));
        let mut pts = Vec::new();
        let mut ns = Vec::new();
        let mut dc_pos = Vec::new();
        let merged = match (self.adaptive, ge.as_mut()) {
            (Some(t), Some(ge)) => self.collapse(ge, o, sign, cubes, &pos, &nrm, t),
            _ => KeyMap::default(),
        };
        for (q, mask, local) in cubes.iter() {
            let case = &dual[*mask];
            let key = point_key(*q) << 3;
            if let Some(&(rep, x, n)) = merged.get(&key) {
                if rep == key {
                    dc_pos.push(x);
                    out.keys.push(key);
                    out.positions.push(x.map(|c| c as f32));
                    out.normals.push(n.map(|c| c as f32));
                } else {
                    out.aliases.push((key, rep));
                }
            }
            // Vertices may leave their cube by up to a cell: a crease (a groove of a union)
            // can run outside the cubes whose crossings see both of its sheets, through cubes
            // whose samples all lie inside (M2's necks: with half a cell, the groove was cut
            // off by 0.25 cell at depth 7).
            // Not on the box: cap vertices stay on its faces.
            let slack = if g.is_virtual(*q) || g.is_virtual(add(*q, [1, 1, 1])) {
                0.0
            } else {
                DC_SLACK
            };
            let lo = [0, 1, 2].map(|k| g.coord(k, q[k]) - slack * g.h[k]);
            let hi = [0, 1, 2].map(|k| g.coord(k, q[k] + 1) + slack * g.h[k]);
            for (k, poly) in case.polygons.iter().enumerate() {
                if merged.contains_key(&key) {
                    break;
                }
                pts.clear();
                ns.clear();
                let mut avg = [0.0; 3];
                for &ei in poly {
                    let v = local[ei as usize] as usize;
                    pts.push(pos[v]);
                    ns.push(nrm[v]);
                    for c in 0..3 {
                        avg[c] += nrm[v][c];
                    }
                }
                let mut x = qef::solve(&pts, &ns, lo, hi);
                if let Some(ge) = ge.as_mut() {
                    x = self.snap(ge, x, lo, hi);
                }
                dc_pos.push(x);
                out.keys.push(point_key(*q) << 3 | k as u64);
                out.positions.push(x.map(|c| c as f32));
                out.normals.push(norm(avg).map(|c| c as f32));
            }
            for axis in 0..3 {
                let c1 = 1usize << axis;
                let e0 = edge_between(0, c1) as usize;
                if case.at[e0][0] == 255 {
                    continue;
                }
                let (bx, cx) = ((axis + 1) % 3, (axis + 2) % 3);
                let mut eb = [0; 3];
                eb[bx] = 1;
                let mut ec = [0; 3];
                ec[cx] = 1;
                // The cubes around the edge in order; in each, the polygon holding the
                // segment on the face shared with the previous cube, then (when the edge
                // ends a chord there) the one on the face shared with the next.
                let mut ring: Vec<u64> = Vec::with_capacity(4);
                for (slot, d) in [[0, 0, 0], eb, add(eb, ec), ec].iter().enumerate() {
                    let qn = [q[0] - d[0], q[1] - d[1], q[2] - d[2]];
                    let m = if slot == 0 { *mask } else { lat.case_at(qn) };
                    let lo_c = (d[0] | d[1] << 1 | d[2] << 2) as usize;
                    let e = edge_between(lo_c, lo_c | c1);
                    let (prev_ax, next_ax) = if slot % 2 == 0 { (cx, bx) } else { (bx, cx) };
                    let ef = table::edge_faces(e);
                    let id = |ax: usize| {
                        let f = (2 * ax + d[ax] as usize) as u8;
                        let s = usize::from(ef[1] == f);
                        dual[m].at[e as usize][s] as u64
                    };
                    let (a, b) = (id(prev_ax), id(next_ax));
                    ring.push(point_key(qn) << 3 | a);
                    if b != a {
                        ring.push(point_key(qn) << 3 | b);
                    }
                }
                if mask & 1 == 0 {
                    ring.reverse();
                }
                if let [a, b, c, d] = ring[..] {
                    out.quads.push([a, b, c, d]);
                    continue;
                }
                // A chord ends here: a fan around the edge's crossing (a new vertex, so that
                // no new edge can duplicate an existing one).
                let v = local[e0] as usize;
                let ck = 1 << 63 | point_key(*q) << 2 | axis as u64;
                dc_pos.push(pos[v]);
                out.keys.push(ck);
                out.positions.push(pos[v].map(|c| c as f32));
                out.normals.push(nrm[v].map(|c| c as f32));
                for j in 0..ring.len() {
                    out.triangles
                        .push([ck, ring[j], ring[(j + 1) % ring.len()]]);
                }
            }
        }
        out.colors = self.colors_at(brick, &dc_pos);
        Ok(out)
    }
}

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
    let mut lat = Lattice {
        grid: &grid,
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
    // Phase 2: extraction by the generating bricks.
    let mut gen: Vec<(usize, Option<usize>)> = Vec::new();
    for (id, &m) in lat.map.iter().enumerate() {
        match m {
            OUTSIDE => {}
            INSIDE => {
                if grid.is_boundary_brick(id) {
                    gen.push((id, None));
                }
            }
            k => gen.push((id, Some((k - 2) as usize))),
        }
    }
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
    let push_vertex = |mesh: &mut Mesh, o: &BrickOut, v: usize| {
        mesh.positions.push(o.positions[v]);
        mesh.normals.push(o.normals[v]);
        if with_colors {
            mesh.colors
                .push(o.colors.get(v).copied().unwrap_or([0.0; 3]));
        }
        (mesh.positions.len() - 1) as u32
    };
    if settings.method != Method::DualContouring {
        merge_marching(&mut outs, &mut mesh, with_colors);
    }
    // Dual contouring: vertices by key.
    let nv: usize = outs.iter().map(|o| o.keys.len()).sum();
    let mut index: KeyMap<u32> = KeyMap::with_capacity_and_hasher(nv, Default::default());
    for o in &mut outs {
        for (v, &key) in o.keys.iter().enumerate() {
            if let Entry::Vacant(e) = index.entry(key) {
                e.insert(push_vertex(&mut mesh, o, v));
            }
        }
        o.keys = Vec::new();
        o.positions = Vec::new();
        o.normals = Vec::new();
        o.colors = Vec::new();
    }
    for o in &mut outs {
        for (key, rep) in std::mem::take(&mut o.aliases) {
            if let Some(&i) = index.get(&rep) {
                index.insert(key, i);
            }
        }
    }
    let look = |k: &u64| index.get(k).copied();
    for o in &outs {
        for t in &o.triangles {
            if let [Some(a), Some(b), Some(c)] = t.each_ref().map(look) {
                // Two ends merged by a collapsed block: the triangle is gone.
                if a != b && b != c && c != a {
                    mesh.triangles.push([a, b, c]);
                }
            }
        }
        for q in &o.quads {
            let [Some(a), Some(b), Some(c), Some(d)] = q.each_ref().map(look) else {
                continue;
            };
            if a == b || b == c || c == d || d == a || a == c || b == d {
                // Around an edge on a collapsed block's face one side is merged: a triangle;
                // inside the block it is gone.
                let mut v = vec![a, b, c, d];
                v.dedup();
                if v.len() > 1 && v[0] == v[v.len() - 1] {
                    v.pop();
                }
                if let [x, y, z] = v[..] {
                    if x != z {
                        mesh.triangles.push([x, y, z]);
                    }
                }
                continue;
            }
            let p = |i: u32| crate::mesh::to_f64(mesh.positions[i as usize]);
            let tri_n = |x: u32, y: u32, z: u32| {
                norm(crate::mesh::cross(
                    crate::mesh::sub(p(y), p(x)),
                    crate::mesh::sub(p(z), p(x)),
                ))
            };
            // The diagonal whose two triangles fold least; a zero-area triangle (its normal
            // is 0) makes a split fold most.
            let d1 = crate::mesh::dot(tri_n(a, b, c), tri_n(a, c, d));
            let d2 = crate::mesh::dot(tri_n(a, b, d), tri_n(b, c, d));
            let flat = |x: u32, y: u32, z: u32| tri_n(x, y, z) == [0.0; 3];
            let bad1 = flat(a, b, c) || flat(a, c, d);
            let bad2 = flat(a, b, d) || flat(b, c, d);
            if (d1 >= d2 && !bad1) || bad2 {
                mesh.triangles.push([a, b, c]);
                mesh.triangles.push([a, c, d]);
            } else {
                mesh.triangles.push([a, b, d]);
                mesh.triangles.push([b, c, d]);
            }
        }
    }
    drop(outs);
    drop(index);
    if settings.method == Method::MarchingCubes {
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

/// [`simplify_mesh`], then a check that the result keeps what the input had: closed,
/// 2-manifold, consistently oriented, no degenerate triangles, the same components and Euler
/// characteristic (genus), and, when `intersections`, no self-intersections. A result that
/// fails is dropped and the simplification retried with half the error (three tries); the
/// mesh stays unsimplified when every try fails. Returns the error bound that was kept.
#[cfg(feature = "export")]
pub fn simplify_verified(mesh: &mut Mesh, error: f32, intersections: bool) -> Option<f32> {
    let before = mesh.topology();
    if !(before.is_closed_manifold() && before.is_consistently_oriented()) {
        simplify_mesh(mesh, error);
        return Some(error);
    }
    let mut e = error;
    for _ in 0..3 {
        let mut m = mesh.clone();
        simplify_mesh(&mut m, e);
        let t = m.topology();
        let ok = t.is_closed_manifold()
            && t.is_consistently_oriented()
            && t.degenerate_triangles == 0
            && t.components == before.components
            && t.euler_characteristic() == before.euler_characteristic()
            && (!intersections || m.self_intersections(1) == 0);
        if ok {
            *mesh = m;
            return Some(e);
        }
        e *= 0.5;
    }
    None
}

/// Error-bounded edge-collapse simplification (meshopt), absolute error `error`.
#[cfg(feature = "export")]
pub fn simplify_mesh(mesh: &mut Mesh, error: f32) {
    if mesh.triangles.is_empty() {
        return;
    }
    let flat: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let bytes: Vec<u8> = mesh
        .positions
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
        .collect();
    let Ok(adapter) = meshopt::VertexDataAdapter::new(&bytes, 12, 0) else {
        return;
    };
    let out = meshopt::simplify(
        &flat,
        &adapter,
        0,
        error,
        meshopt::SimplifyOptions::LockBorder | meshopt::SimplifyOptions::ErrorAbsolute,
        None,
    );
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    let mut m = Mesh::default();
    for &i in &out {
        if remap[i as usize] == u32::MAX {
            remap[i as usize] = m.positions.len() as u32;
            m.positions.push(mesh.positions[i as usize]);
            if !mesh.normals.is_empty() {
                m.normals.push(mesh.normals[i as usize]);
            }
            if !mesh.colors.is_empty() {
                m.colors.push(mesh.colors[i as usize]);
            }
        }
    }
    m.triangles = out
        .chunks_exact(3)
        .map(|t| {
            [
                remap[t[0] as usize],
                remap[t[1] as usize],
                remap[t[2] as usize],
            ]
        })
        .collect();
    *mesh = m;
}
