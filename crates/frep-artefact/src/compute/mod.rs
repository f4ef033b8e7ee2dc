//! Computing one artefact, synchronously on the caller's thread. The
//! kernels spread the work over rayon inside. Each kernel is called exactly
//! as the command line calls it, so the server's time is the CLI's plus the
//! cache.
//!
//! Every computation takes a [`Cancel`] and a [`JobProgress`] it reports
//! into. The kernels check the cancel: the ray caster before each tile, the
//! polygonizer per octree node, the sampler per slice.

pub mod export;
pub mod image;
pub mod mesh;
pub mod shader;
pub mod slices;
pub mod viewset;

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use frep_core::CancelToken;
use frep_render::ImagePool;
use frep_wire::{ArtefactSpec, VolumeLayout};

use crate::compiled::Compiled;
use crate::config::ArtefactLimits;
use crate::error::ArtefactError;
use crate::key::media_type;

/// Cancels a computation from another thread: the kernels' one
/// [`CancelToken`], plus [`Cancel::check`] for this crate's errors.
#[derive(Clone, Debug, Default)]
pub struct Cancel {
    token: CancelToken,
}

impl Cancel {
    /// A token not yet cancelled.
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Asks the computation to stop.
    pub fn cancel(&self) {
        self.token.cancel();
    }

    /// Whether [`Cancel::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.token.is_cancelled()
    }

    /// The token the kernels poll.
    pub fn token(&self) -> &CancelToken {
        &self.token
    }

    /// `Err(Cancelled)` once cancelled.
    pub fn check(&self) -> Result<(), ArtefactError> {
        if self.is_cancelled() {
            Err(ArtefactError::Cancelled)
        } else {
            Ok(())
        }
    }
}

/// Progress of one computation, readable from any thread: a fraction set by
/// the computation, or the polygonizer's own counter while it runs.
#[derive(Debug, Default)]
pub struct JobProgress {
    fraction: AtomicU64,
    meshing: AtomicBool,
    mesh: frep_mesh::Progress,
}

impl JobProgress {
    /// Nothing done yet.
    pub fn new() -> JobProgress {
        JobProgress::default()
    }

    /// Done so far, in `[0, 1]`.
    pub fn fraction(&self) -> f64 {
        if self.meshing.load(Ordering::Relaxed) {
            self.mesh.fraction()
        } else {
            f64::from_bits(self.fraction.load(Ordering::Relaxed))
        }
    }

    /// Sets the fraction done (clamped to `[0, 1]`).
    pub fn set(&self, f: f64) {
        let f = if f.is_finite() {
            f.clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.fraction.store(f.to_bits(), Ordering::Relaxed);
    }

    /// The polygonizer's counter; from now on [`JobProgress::fraction`]
    /// reads it.
    pub fn mesh(&self) -> &frep_mesh::Progress {
        self.meshing.store(true, Ordering::Relaxed);
        &self.mesh
    }
}

/// A computed artefact.
#[derive(Clone, Debug, PartialEq)]
pub struct Output {
    /// The body.
    pub bytes: Vec<u8>,
    /// Its media type.
    pub media_type: &'static str,
    /// For slices: the mapping of the bytes.
    pub volume: Option<VolumeLayout>,
}

impl Output {
    fn new(bytes: Vec<u8>, spec: &ArtefactSpec) -> Output {
        Output {
            bytes,
            media_type: media_type(spec),
            volume: None,
        }
    }
}

/// Refuses a spec that asks for more than `limits` allow, or for nothing.
pub fn check_limits(spec: &ArtefactSpec, limits: &ArtefactLimits) -> Result<(), ArtefactError> {
    match spec {
        ArtefactSpec::Image {
            width,
            height,
            quality,
            section,
            ..
        } => {
            image::check_size(*width, *height, limits)?;
            image::check_section(section.as_ref())?;
            check_quality(*quality)
        }
        ArtefactSpec::ViewSet {
            views,
            elevations,
            width,
            height,
            quality,
            section,
            ..
        }
        | ArtefactSpec::ViewSetIndex {
            views,
            elevations,
            width,
            height,
            quality,
            section,
            ..
        } => {
            viewset::check(*views, elevations, *width, *height, limits)?;
            image::check_section(section.as_ref())?;
            check_quality(*quality)
        }
        ArtefactSpec::Mesh { depth } => {
            limit("mesh depth", limits.max_mesh_depth.into(), (*depth).into())
        }
        ArtefactSpec::Export { depth, .. } => limit(
            "export depth",
            limits.max_export_depth.into(),
            (*depth).into(),
        ),
        ArtefactSpec::Slices { grid } => {
            if *grid == 0 {
                return Err(ArtefactError::BadRequest("a grid of 0 samples".into()));
            }
            limit("volume grid", limits.max_volume_grid.into(), (*grid).into())
        }
        ArtefactSpec::Shader => Ok(()),
    }
}

fn check_quality(q: u8) -> Result<(), ArtefactError> {
    if (1..=100).contains(&q) {
        Ok(())
    } else {
        Err(ArtefactError::BadRequest(format!(
            "quality {q} is outside 1..=100"
        )))
    }
}

/// `Err(Limit)` when `got > limit`.
pub(crate) fn limit(name: &'static str, limit: u64, got: u64) -> Result<(), ArtefactError> {
    if got > limit {
        Err(ArtefactError::Limit { name, limit, got })
    } else {
        Ok(())
    }
}

/// Computes `spec` for `compiled` at parameter values `params` (defaults
/// filled in), after checking `limits`. Images take their bytes from
/// `pool` and give them back once encoded.
pub fn compute(
    compiled: &Compiled,
    params: &[f64],
    spec: &ArtefactSpec,
    limits: &ArtefactLimits,
    cancel: &Cancel,
    progress: &JobProgress,
    pool: &ImagePool,
) -> Result<Output, ArtefactError> {
    check_limits(spec, limits)?;
    cancel.check()?;
    let inputs = compiled.inputs(params);
    let out = match spec {
        ArtefactSpec::Image {
            camera,
            width,
            height,
            format,
            quality,
            section,
        } => Output::new(
            image::image(
                compiled,
                inputs,
                camera,
                *width,
                *height,
                *format,
                *quality,
                section.as_ref(),
                cancel,
                pool,
            )?,
            spec,
        ),
        ArtefactSpec::ViewSet {
            views,
            elevations,
            width,
            height,
            format,
            quality,
            fov,
            section,
        } => {
            let set = viewset::ViewSetSpec {
                views: *views,
                elevations: elevations.clone(),
                width: *width,
                height: *height,
                format: *format,
                quality: *quality,
                fov: *fov,
                section: *section,
            };
            Output::new(
                viewset::sheet(compiled, inputs, &set, cancel, progress, pool)?,
                spec,
            )
        }
        ArtefactSpec::ViewSetIndex {
            views,
            elevations,
            width,
            height,
            ..
        } => {
            let layout = viewset::layout(*views, elevations, *width, *height);
            Output::new(json(&layout)?, spec)
        }
        ArtefactSpec::Mesh { depth } => Output::new(
            mesh::mesh(
                compiled,
                inputs,
                *depth,
                frep_mesh::Format::GlbMeshopt,
                limits,
                cancel,
                progress,
            )?,
            spec,
        ),
        ArtefactSpec::Export { format, depth } => Output::new(
            export::export(compiled, inputs, *format, *depth, limits, cancel, progress)?,
            spec,
        ),
        ArtefactSpec::Slices { grid } => {
            let (bytes, layout) = slices::volume(compiled, &inputs, *grid, cancel, progress)?;
            Output {
                volume: Some(layout),
                ..Output::new(bytes, spec)
            }
        }
        ArtefactSpec::Shader => Output::new(json(&shader::shader(compiled, &inputs))?, spec),
    };
    progress.set(1.0);
    Ok(out)
}

fn json<T: serde::Serialize>(v: &T) -> Result<Vec<u8>, ArtefactError> {
    serde_json::to_vec(v).map_err(|e| ArtefactError::Render(e.to_string()))
}
