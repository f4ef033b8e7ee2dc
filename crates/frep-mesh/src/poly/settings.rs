//! What to polygonize and how ([`MeshSettings`], [`Method`], [`Resolution`],
//! [`Limits`]), its errors ([`MeshError`]) and progress ([`Progress`]).
//! Cancellation is frep-core's [`CancelToken`], re-exported here.

use std::sync::atomic::{AtomicU64, Ordering};

use frep_core::eval::Inputs;
pub use frep_core::CancelToken;

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
    /// Adaptive dual contouring: blocks of 2×2×2, 4×4×4, … cubes (up to a brick) get one
    /// vertex. A block qualifies when its collapse is topologically safe and its merged QEF's
    /// vertex lies within this fraction of the cell size of every crossing's tangent plane.
    /// Flat regions get bigger polygons; the mesh stays a closed 2-manifold.
    /// [`Method::DualContouring`] only (ignored by the other methods); `None`: off.
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
    pub(super) done: AtomicU64,
    pub(super) estimated: AtomicU64,
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

    pub(super) fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }
}
