//! Every resource limit of the artefact service, explicit and configurable.

use std::path::PathBuf;

/// Limits on one compile (the source is untrusted).
#[derive(Clone, Debug, PartialEq)]
pub struct CompileLimits {
    /// Largest source, bytes.
    pub max_source_bytes: usize,
    /// Largest expression graph, nodes.
    pub max_nodes: usize,
    /// Statements executed and calls inlined at compile time (a time bound).
    pub max_steps: usize,
    /// Loop iterations executed at compile time.
    pub max_iterations: usize,
    /// Largest `a[]` accepted in a request's parameter values.
    pub max_params: usize,
}

impl Default for CompileLimits {
    fn default() -> Self {
        CompileLimits {
            max_source_bytes: 1 << 20,
            max_nodes: 1_000_000,
            max_steps: 20_000_000,
            max_iterations: 1_000_000,
            max_params: 256,
        }
    }
}

/// Limits on what one artefact request may ask for.
#[derive(Clone, Debug, PartialEq)]
pub struct ArtefactLimits {
    /// Largest image (or view of a view set), pixels.
    pub max_image_pixels: u64,
    /// Largest image side, pixels.
    pub max_image_side: u32,
    /// Most views in a view set (views per ring × rings).
    pub max_views: u32,
    /// Largest sprite sheet, pixels in all.
    pub max_sheet_pixels: u64,
    /// Deepest octree of a viewer mesh.
    pub max_mesh_depth: u8,
    /// Deepest octree of an export.
    pub max_export_depth: u8,
    /// Most triangles of a mesh or an export.
    pub max_triangles: usize,
    /// Most samples per axis of a slices volume.
    pub max_volume_grid: u32,
    /// Most parameter values in a request.
    pub max_params: usize,
}

impl Default for ArtefactLimits {
    fn default() -> Self {
        ArtefactLimits {
            max_image_pixels: 2048 * 2048,
            max_image_side: 4096,
            max_views: 144,
            max_sheet_pixels: 16_384 * 16_384,
            max_mesh_depth: 9,
            max_export_depth: 10,
            max_triangles: 20_000_000,
            max_volume_grid: 256,
            max_params: 256,
        }
    }
}

/// The artefact service's configuration ([`crate::Artefacts::new`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ArtefactConfig {
    /// Folder of the disk cache (created if missing).
    pub cache_dir: PathBuf,
    /// Total size of the cached files, bytes; least recently used files go
    /// first when it is exceeded.
    pub cache_max_bytes: u64,
    /// Jobs computed at once (each uses the rayon pool inside).
    pub workers: usize,
    /// Jobs waiting for a worker at most; more get [`crate::ArtefactError::Busy`].
    pub queue_max: usize,
    /// Recipes (key → model, parameters, settings) remembered for `GET`,
    /// least recently registered forgotten first.
    pub max_recipes: usize,
    /// Request limits.
    pub limits: ArtefactLimits,
    /// Bytes of spare image buffers the workers share
    /// ([`frep_render::ImagePool`]); `0` keeps none.
    pub image_pool_bytes: usize,
}

impl ArtefactConfig {
    /// A configuration with default limits, caching in `cache_dir`.
    pub fn new(cache_dir: impl Into<PathBuf>) -> ArtefactConfig {
        ArtefactConfig {
            cache_dir: cache_dir.into(),
            cache_max_bytes: 1 << 30,
            workers: 2,
            queue_max: 64,
            max_recipes: 10_000,
            limits: ArtefactLimits::default(),
            image_pool_bytes: frep_render::image::DEFAULT_REUSE,
        }
    }
}
