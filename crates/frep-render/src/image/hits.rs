//! What the ray caster produces: one [`Hit`] per ray, and per image a
//! [`HitBuffer`].

use crate::camera::Camera;

use super::DepthImage;

/// One ray hit: where the ray met the surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Distance along the (unit) ray from its origin.
    pub t: f64,
    /// The world position of the hit.
    pub position: [f64; 3],
    /// The surface normal pointing *out* of the solid (for HyperFun's
    /// positive-inside fields, `−∇f / |∇f|`). Need not be normalized; a zero
    /// or non-finite normal is shaded as facing the viewer.
    pub normal: [f64; 3],
    /// The attribute colour at the hit (sRGB components in `[0, 1]`), if the
    /// model has one; `None` uses the default material.
    pub color: Option<[f32; 3]>,
}

/// Per pixel, what the ray caster found: a hit or nothing, plus an optional
/// ambient-occlusion factor. Also remembers the camera it was cast with, for
/// view-relative lighting.
#[derive(Clone, Debug)]
pub struct HitBuffer {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The camera the rays came from.
    pub camera: Camera,
    /// `width * height` entries, row-major from the top-left.
    pub hits: Vec<Option<Hit>>,
    /// Optional per-pixel ambient occlusion: 1 = fully open, 0 = fully
    /// occluded (`width * height` entries when present).
    pub ao: Option<Vec<f32>>,
}

impl HitBuffer {
    /// An empty buffer (no hits).
    pub fn new(camera: Camera, width: u32, height: u32) -> HitBuffer {
        HitBuffer {
            width,
            height,
            camera,
            hits: vec![None; width as usize * height as usize],
            ao: None,
        }
    }

    /// The hit at pixel `(x, y)`.
    pub fn get(&self, x: u32, y: u32) -> Option<&Hit> {
        self.hits[y as usize * self.width as usize + x as usize].as_ref()
    }

    /// Sets the hit at pixel `(x, y)`.
    pub fn set(&mut self, x: u32, y: u32, hit: Option<Hit>) {
        self.hits[y as usize * self.width as usize + x as usize] = hit;
    }

    /// The number of pixels with a hit.
    pub fn hit_count(&self) -> usize {
        self.hits.iter().filter(|h| h.is_some()).count()
    }

    /// The depth image (hit distances) of this buffer.
    pub fn depth(&self) -> DepthImage {
        DepthImage {
            width: self.width,
            height: self.height,
            depth: self
                .hits
                .iter()
                .map(|h| h.map_or(f32::INFINITY, |h| h.t as f32))
                .collect(),
        }
    }
}
