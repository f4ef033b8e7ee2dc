//! Meshes: the polygonizer at `2^depth` cells along the box's longest side,
//! written by frep-mesh's exporter. It runs watertight marching cubes on the
//! pruned octree, with colours from the attributes. These are the calls
//! `frep mesh` makes. The viewer's mesh is the quantized, meshopt-compressed
//! glb three.js loads with `MeshoptDecoder`.

use frep_core::Inputs;
use frep_mesh::{export, polygonize, Format, Limits, MeshSettings, Method, Resolution};

use super::{Cancel, JobProgress};
use crate::compiled::Compiled;
use crate::config::ArtefactLimits;
use crate::error::ArtefactError;

/// Polygonizes `compiled` at `depth` and writes it in `format`.
pub fn mesh(
    compiled: &Compiled,
    inputs: Inputs,
    depth: u8,
    format: Format,
    limits: &ArtefactLimits,
    cancel: &Cancel,
    progress: &JobProgress,
) -> Result<Vec<u8>, ArtefactError> {
    let settings = MeshSettings {
        bounds: compiled.bounds(),
        resolution: Resolution::Depth(depth),
        method: Method::Watertight,
        colors: true,
        inputs,
        limits: Limits {
            max_depth: limits.max_mesh_depth.max(limits.max_export_depth),
            max_triangles: limits.max_triangles,
        },
        ..Default::default()
    };
    let mesh = polygonize(compiled.model(), &settings, progress.mesh(), cancel.token())?;
    cancel.check()?;
    export::to_bytes(&mesh, format).map_err(|e| ArtefactError::Mesh(e.to_string()))
}
