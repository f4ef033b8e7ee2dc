//! Still images: the ray caster's `render_camera` through the shared camera
//! ([`crate::camera::camera`]), then the encoder; the same two calls as
//! `frep render`. A section plane ([`section_of`]) cuts the model open.

use frep_core::Inputs;
use frep_render::{encode, render_camera, ImagePool, RenderSettings, Section};
use frep_wire::{CameraView, ImageEncoding, SectionPlane};

use super::{limit, Cancel};
use crate::camera::camera;
use crate::compiled::Compiled;
use crate::config::ArtefactLimits;
use crate::error::ArtefactError;
use crate::key::image_format;

/// Refuses an empty image or one over the limits.
pub fn check_size(width: u32, height: u32, limits: &ArtefactLimits) -> Result<(), ArtefactError> {
    if width == 0 || height == 0 {
        return Err(ArtefactError::BadRequest(format!(
            "image size {width}x{height} is empty"
        )));
    }
    limit(
        "image side",
        limits.max_image_side.into(),
        width.max(height).into(),
    )?;
    limit(
        "image pixels",
        limits.max_image_pixels,
        width as u64 * height as u64,
    )
}

/// Refuses a section plane the ray caster cannot use (a zero or
/// non-finite normal, a non-finite offset).
pub fn check_section(section: Option<&SectionPlane>) -> Result<(), ArtefactError> {
    match section.map(|s| section_of(s).normalized()) {
        Some(Err(e)) => Err(ArtefactError::BadRequest(e.to_string())),
        _ => Ok(()),
    }
}

/// The ray caster's section plane of a wire one (the same convention:
/// the solid is kept where `normal · p <= offset`).
pub fn section_of(s: &SectionPlane) -> Section {
    Section {
        normal: s.normal,
        offset: s.offset,
    }
}

/// The render settings of an image of `compiled` (its box, these inputs).
pub fn settings(
    compiled: &Compiled,
    inputs: Inputs,
    width: u32,
    height: u32,
    quality: u8,
    section: Option<&SectionPlane>,
) -> RenderSettings {
    RenderSettings {
        size: (width, height),
        bounds: compiled.aabb(),
        quality: quality.clamp(1, 100),
        inputs,
        section: section.map(section_of),
        ..Default::default()
    }
}

/// Renders and encodes one image; its bytes come from `pool` and go back
/// to it once encoded.
#[allow(clippy::too_many_arguments)]
pub fn image(
    compiled: &Compiled,
    inputs: Inputs,
    view: &CameraView,
    width: u32,
    height: u32,
    format: ImageEncoding,
    quality: u8,
    section: Option<&SectionPlane>,
    cancel: &Cancel,
    pool: &ImagePool,
) -> Result<Vec<u8>, ArtefactError> {
    let s = settings(compiled, inputs, width, height, quality, section);
    let cam = camera(view, &s.bounds);
    let img = render_camera(compiled.model(), &s, &cam, cancel.token(), pool)?;
    let bytes = encode(&img, image_format(format), s.quality);
    pool.recycle(img);
    Ok(bytes?)
}
