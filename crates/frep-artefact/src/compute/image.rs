//! Still images: the ray caster's `render_camera` through the shared camera
//! ([`crate::camera::camera`]), then the encoder; the same two calls as
//! `frep render`.

use frep_core::Inputs;
use frep_render::{encode, render_camera, RenderSettings};
use frep_wire::{CameraView, ImageEncoding};

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

/// The render settings of an image of `compiled` (its box, these inputs).
pub fn settings(
    compiled: &Compiled,
    inputs: Inputs,
    width: u32,
    height: u32,
    quality: u8,
) -> RenderSettings {
    RenderSettings {
        size: (width, height),
        bounds: compiled.aabb(),
        quality: quality.clamp(1, 100),
        inputs,
        ..Default::default()
    }
}

/// Renders and encodes one image.
#[allow(clippy::too_many_arguments)]
pub fn image(
    compiled: &Compiled,
    inputs: Inputs,
    view: &CameraView,
    width: u32,
    height: u32,
    format: ImageEncoding,
    quality: u8,
    cancel: &Cancel,
) -> Result<Vec<u8>, ArtefactError> {
    let s = settings(compiled, inputs, width, height, quality);
    let cam = camera(view, &s.bounds);
    let img = render_camera(compiled.model(), &s, &cam, Some(cancel.flag()))?;
    Ok(encode(&img, image_format(format), s.quality)?)
}
