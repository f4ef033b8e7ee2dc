//! Downloads: the mesh in STL (binary), OBJ, PLY (binary, with vertex
//! colours), glb (meshopt) or 3MF. The polygonizer runs as for the viewer's
//! mesh ([`super::mesh::mesh`]); only the writer differs.

use frep_core::Inputs;
use frep_wire::ExportFormat;

use super::{Cancel, JobProgress};
use crate::compiled::Compiled;
use crate::config::ArtefactLimits;
use crate::error::ArtefactError;
use crate::key::export_format;

/// Polygonizes `compiled` at `depth` and writes the file.
pub fn export(
    compiled: &Compiled,
    inputs: Inputs,
    format: ExportFormat,
    depth: u8,
    limits: &ArtefactLimits,
    cancel: &Cancel,
    progress: &JobProgress,
) -> Result<Vec<u8>, ArtefactError> {
    super::mesh::mesh(
        compiled,
        inputs,
        depth,
        export_format(format),
        limits,
        cancel,
        progress,
    )
}
