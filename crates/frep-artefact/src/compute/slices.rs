//! Slices: the field sampled at voxel centres of an `n³` grid over the
//! model box.
//! - Sampling is frep-render's `sample_grid`, as `frep slices` does it. The
//!   rows of a slice are evaluated as lines along x.
//! - Values map to bytes `128 + 127 · f / scale`, clamped to 1..=255, and 0
//!   where the model failed.
//! - The scale is frep-render's automatic one: a band of 4 voxels each side
//!   of the surface.
//! - The body is the raw volume, x fastest, then y, then z. It is a WebGL2
//!   `R8` 3D texture as is.

use std::sync::atomic::{AtomicUsize, Ordering};

use frep_core::eval::batch::BatchEval;
use frep_core::Inputs;
use frep_render::sample_grid;
use frep_render::slices::grid_bytes;
use frep_wire::VolumeLayout;

use super::{Cancel, JobProgress};
use crate::compiled::Compiled;
use crate::error::ArtefactError;

/// Band half-width of the byte mapping, in voxels (frep-render's default).
const BAND_VOXELS: f32 = 4.0;

/// The volume's bytes and their mapping.
pub fn volume(
    compiled: &Compiled,
    inputs: &Inputs,
    n: u32,
    cancel: &Cancel,
    progress: &JobProgress,
) -> Result<(Vec<u8>, VolumeLayout), ArtefactError> {
    let n = n.max(1) as usize;
    let bounds = compiled.aabb();
    let tape = compiled.model().tape();
    let done = AtomicUsize::new(0);
    let grid = sample_grid(&bounds, [n; 3], cancel.token(), |xs, ys, zs, out| {
        BatchEval::new(&tape).eval_lines(0, n, true, xs, ys, zs, inputs, out);
        let k = done.fetch_add(1, Ordering::Relaxed) + 1;
        progress.set(0.95 * k as f64 / n as f64);
    })?;
    let scale = grid.auto_scale(BAND_VOXELS);
    let layout = VolumeLayout {
        dims: [n as u32; 3],
        bounds: compiled.bounds(),
        scale: scale as f64,
    };
    Ok((grid_bytes(&grid, scale), layout))
}
