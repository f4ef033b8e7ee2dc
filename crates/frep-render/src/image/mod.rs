//! Images, hit buffers (what the ray caster produces) and shading.
//!
//! The image type is here; the reuse of its bytes is in `pool`, the hit
//! buffer in `hits`, shading in `shade`, the sRGB encoding in `srgb`.

mod hits;
mod pool;
mod shade;
mod srgb;

pub use hits::{Hit, HitBuffer};
pub use pool::{ImagePool, DEFAULT_REUSE, REUSE_MIN};
pub(crate) use shade::{fill_background, ShadeIn};
pub use shade::{shade, Light, Lighting, Shader, SPAN};
pub use srgb::{linear_to_srgb, srgb_to_linear};

/// An 8-bit sRGB image with alpha, rows top to bottom.
///
/// Renders take its bytes from an [`ImagePool`]; hand it back with
/// [`ImagePool::recycle`] once encoded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes, RGBA, row-major from the top-left.
    pub rgba: Vec<u8>,
}

impl Image {
    /// The image's bytes ([`Image::rgba`]).
    pub fn into_rgba(self) -> Vec<u8> {
        self.rgba
    }

    /// An image filled with one colour.
    pub fn filled(width: u32, height: u32, rgba: [u8; 4]) -> Image {
        let n = width as usize * height as usize;
        let mut data = Vec::with_capacity(n * 4);
        for _ in 0..n {
            data.extend_from_slice(&rgba);
        }
        Image {
            width,
            height,
            rgba: data,
        }
    }

    /// The pixel at `(x, y)`.
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = (y as usize * self.width as usize + x as usize) * 4;
        [
            self.rgba[i],
            self.rgba[i + 1],
            self.rgba[i + 2],
            self.rgba[i + 3],
        ]
    }

    /// Sets the pixel at `(x, y)`.
    pub fn set_pixel(&mut self, x: u32, y: u32, rgba: [u8; 4]) {
        let i = (y as usize * self.width as usize + x as usize) * 4;
        self.rgba[i..i + 4].copy_from_slice(&rgba);
    }

    /// Copies `src` into this image with its top-left corner at `(x, y)`
    /// (clipped to this image).
    pub fn blit(&mut self, src: &Image, x: u32, y: u32) {
        let w = src.width.min(self.width.saturating_sub(x)) as usize;
        let h = src.height.min(self.height.saturating_sub(y));
        for row in 0..h {
            let s = row as usize * src.width as usize * 4;
            let d = ((y + row) as usize * self.width as usize + x as usize) * 4;
            self.rgba[d..d + w * 4].copy_from_slice(&src.rgba[s..s + w * 4]);
        }
    }

    /// Whether every pixel is fully opaque.
    pub fn is_opaque(&self) -> bool {
        self.rgba.chunks_exact(4).all(|p| p[3] == 255)
    }

    /// The RGB bytes (alpha dropped).
    pub fn to_rgb(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.rgba.len() / 4 * 3);
        for p in self.rgba.chunks_exact(4) {
            out.extend_from_slice(&p[..3]);
        }
        out
    }
}

/// Hit distances per pixel; `+∞` where the ray hit nothing.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height` distances, row-major from the top-left.
    pub depth: Vec<f32>,
}

impl DepthImage {
    /// A grey-scale view: near is white, far is dark, no hit is black.
    pub fn to_image(&self) -> Image {
        let finite = self.depth.iter().copied().filter(|d| d.is_finite());
        let (lo, hi) = finite.fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), d| {
            (a.min(d), b.max(d))
        });
        let span = (hi - lo).max(1e-20);
        let mut img = Image::filled(self.width, self.height, [0, 0, 0, 255]);
        for (i, d) in self.depth.iter().enumerate() {
            if d.is_finite() {
                let g = (255.0 - 200.0 * (d - lo) / span).round() as u8;
                img.rgba[i * 4..i * 4 + 3].copy_from_slice(&[g, g, g]);
            }
        }
        img
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Aabb, Camera};
    use crate::synthetic::sphere_hits;

    #[test]
    fn depth_image() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 0.0, 0.0, None);
        let hits = sphere_hits(&cam, 16, 16, [0.0; 3], 0.8, None);
        let d = hits.depth();
        assert!(d.depth[0].is_infinite());
        assert!(d.depth[8 * 16 + 8].is_finite());
        let img = d.to_image();
        assert_eq!(img.pixel(0, 0), [0, 0, 0, 255]);
        assert!(img.pixel(8, 8)[0] > 200);
    }

    #[test]
    fn blit_clips() {
        let mut a = Image::filled(4, 4, [0, 0, 0, 255]);
        let b = Image::filled(3, 3, [9, 9, 9, 255]);
        a.blit(&b, 2, 2);
        assert_eq!(a.pixel(3, 3), [9, 9, 9, 255]);
        assert_eq!(a.pixel(1, 1), [0, 0, 0, 255]);
    }
}
