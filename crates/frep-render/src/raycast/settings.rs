//! What to render ([`RenderSettings`]), the largest image it may ask for
//! ([`RenderLimits`]) and why a render fails ([`RenderError`]).

use frep_core::eval::Inputs;

use crate::camera::{Aabb, Camera};
use crate::image::Lighting;

use super::section::Section;
use super::{MAX_PIXELS, MAX_SIDE};

/// What to render.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image size in pixels `(width, height)`.
    pub size: (u32, u32),
    /// Turntable yaw in degrees (see [`Camera::orbit`]).
    pub yaw: f64,
    /// Turntable pitch in degrees.
    pub pitch: f64,
    /// Field of view in degrees (perspective); `None`: orthographic.
    pub fov: Option<f64>,
    /// The model box: rays are clipped to it and the camera frames it.
    pub bounds: Aabb,
    /// Encoder quality 1–100 for JPEG and WebP (not used by the caster).
    pub quality: u8,
    /// Compute ambient occlusion (a few field samples along each normal).
    pub ao: bool,
    /// Parameter values `a[]` and extra coordinates.
    pub inputs: Inputs,
    /// Tile size in pixels (tiles run in parallel).
    pub tile_size: u32,
    /// The lights.
    pub lighting: Lighting,
    /// A section plane cutting the solid open (`None`: the whole model).
    pub section: Option<Section>,
    /// The largest image accepted.
    pub limits: RenderLimits,
}

/// The largest image a render accepts; bigger sizes fail with
/// [`RenderError::BadSize`]. The defaults are [`MAX_SIDE`] and
/// [`MAX_PIXELS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderLimits {
    /// Largest width or height, pixels.
    pub max_side: u32,
    /// Largest width × height.
    pub max_pixels: u64,
}

impl Default for RenderLimits {
    fn default() -> Self {
        RenderLimits {
            max_side: MAX_SIDE,
            max_pixels: MAX_PIXELS,
        }
    }
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            size: (512, 512),
            yaw: 30.0,
            pitch: 20.0,
            fov: Some(30.0),
            bounds: Aabb::new([-10.0; 3], [10.0; 3]),
            quality: 85,
            ao: false,
            inputs: Inputs::default(),
            tile_size: 32,
            lighting: Lighting::default(),
            section: None,
            limits: RenderLimits::default(),
        }
    }
}

impl RenderSettings {
    /// The camera these settings describe.
    pub fn camera(&self) -> Camera {
        Camera::orbit(&self.bounds, self.yaw, self.pitch, self.fov)
    }
}

/// Why a render produced no image.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RenderError {
    /// The [`CancelToken`](frep_core::CancelToken) was cancelled.
    #[error("render cancelled")]
    Cancelled,
    /// The size is zero or above the [`RenderLimits`].
    #[error(
        "image size {width}x{height} is outside 1..={} a side, {} pixels in all",
        limits.max_side,
        limits.max_pixels
    )]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// The limits it broke.
        limits: RenderLimits,
    },
    /// The section plane is not a plane (see [`SectionError`]).
    ///
    /// [`SectionError`]: super::SectionError
    #[error("{0}")]
    BadSection(String),
}

pub(super) fn check_size(
    (width, height): (u32, u32),
    limits: RenderLimits,
) -> Result<(), RenderError> {
    if width == 0
        || height == 0
        || width > limits.max_side
        || height > limits.max_side
        || width as u64 * height as u64 > limits.max_pixels
    {
        return Err(RenderError::BadSize {
            width,
            height,
            limits,
        });
    }
    Ok(())
}
