//! Images, hit buffers (what the ray caster produces) and shading.
//!
//! The image type and the reuse of its bytes are here; the hit buffer is in
//! `hits`, shading in `shade`, the sRGB encoding in `srgb`.

mod hits;
mod shade;
mod srgb;

pub use hits::{Hit, HitBuffer};
pub(crate) use shade::{fill_background, ShadeIn};
pub use shade::{shade, Light, Lighting, Shader, SPAN};
pub use srgb::{linear_to_srgb, srgb_to_linear};

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// An 8-bit sRGB image with alpha, rows top to bottom.
///
/// A dropped image's bytes (from [`REUSE_MIN`] up) are kept for the next
/// render's image ([`set_image_reuse`]). Memory the process already has is
/// written without page faults. Fresh memory from the system takes one per
/// 4 KiB page on its first write. Measured here: a 1024² render on 2
/// threads took 10.1 ms in fresh memory, 7.7 ms in memory reused.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width * height * 4` bytes, RGBA, row-major from the top-left.
    pub rgba: Vec<u8>,
}

impl Drop for Image {
    fn drop(&mut self) {
        keep_for_reuse(std::mem::take(&mut self.rgba));
    }
}

/// The least capacity of an image's bytes kept for reuse (smaller ones
/// cost little to allocate afresh).
pub const REUSE_MIN: usize = 256 << 10;

/// The most images' bytes kept for reuse at once.
const REUSE_COUNT: usize = 4;

/// The most bytes kept for reuse ([`set_image_reuse`]).
static REUSE_LIMIT: AtomicUsize = AtomicUsize::new(64 << 20);

/// Dropped images' bytes, for the next renders' images.
static SPARE: Mutex<Spare> = Mutex::new(Spare(Vec::new()));

/// Sets the most bytes that dropped images may keep for the next renders'
/// images (at most four of them, each of [`REUSE_MIN`] bytes or more; 64 MiB
/// by default). `0` turns reuse off and frees what is kept.
pub fn set_image_reuse(max_bytes: usize) {
    REUSE_LIMIT.store(max_bytes, Ordering::Relaxed);
    spare().trim(max_bytes);
}

/// The most bytes dropped images may keep ([`set_image_reuse`]).
pub fn image_reuse() -> usize {
    REUSE_LIMIT.load(Ordering::Relaxed)
}

fn spare() -> std::sync::MutexGuard<'static, Spare> {
    SPARE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Keeps `bytes` for reuse, where the limits allow.
fn keep_for_reuse(bytes: Vec<u8>) {
    if bytes.capacity() >= REUSE_MIN {
        spare().keep(bytes, REUSE_LIMIT.load(Ordering::Relaxed));
    }
}

/// `len` zero bytes for an image: kept ones where some fit
/// ([`Spare::take`]), else new ones. (Cleared although the renders write
/// every pixel: a pixel that some path left out would otherwise show
/// another render's image, maybe another user's model. Leaving them was
/// 2-3 % faster on 2 threads at 512², in the twenty-fourth bench run.)
pub(crate) fn image_bytes(len: usize) -> Vec<u8> {
    let found = spare().take(len);
    match found {
        Some(mut v) => {
            v.clear();
            v.resize(len, 0);
            v
        }
        None => vec![0; len],
    }
}

/// Buffers kept for reuse.
struct Spare(Vec<Vec<u8>>);

impl Spare {
    /// The bytes (capacities) kept.
    fn bytes(&self) -> usize {
        self.0.iter().map(Vec::capacity).sum()
    }

    /// Keeps `v` where that stays within [`REUSE_COUNT`] buffers and
    /// `limit` bytes.
    fn keep(&mut self, v: Vec<u8>, limit: usize) {
        if self.0.len() < REUSE_COUNT && self.bytes() + v.capacity() <= limit {
            self.0.push(v);
        }
    }

    /// The smallest buffer kept that holds `len` bytes and is no more than
    /// four times that (a larger one would stay tied up in a small image).
    pub(super) fn take(&mut self, len: usize) -> Option<Vec<u8>> {
        let fits = |v: &&Vec<u8>| (len..=len.saturating_mul(4)).contains(&v.capacity());
        let best = (self.0.iter().enumerate())
            .filter(|(_, v)| fits(v))
            .min_by_key(|(_, v)| v.capacity())
            .map(|(i, _)| i)?;
        Some(self.0.swap_remove(best))
    }

    /// Frees buffers until at most `limit` bytes are kept.
    fn trim(&mut self, limit: usize) {
        while self.bytes() > limit {
            self.0.pop();
        }
    }
}

impl Image {
    /// The image's bytes ([`Image::rgba`]), taken from it (not kept for
    /// reuse then: see [`set_image_reuse`]).
    pub fn into_rgba(mut self) -> Vec<u8> {
        std::mem::take(&mut self.rgba)
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

    /// Kept buffers stay within the count and byte limits. A request gets
    /// the smallest that holds it and is at most four times its size (the
    /// same allocation), else none. Trimming frees down to a limit.
    #[test]
    fn spare_buffers_fit_and_stay_within_limits() {
        let mut s = Spare(Vec::new());
        let mb = 1 << 20;
        for cap in [4 * mb, mb, 2 * mb] {
            s.keep(Vec::with_capacity(cap), 8 * mb);
        }
        // Over the byte limit (7 MiB kept): not kept.
        s.keep(Vec::with_capacity(2 * mb), 8 * mb);
        assert_eq!(s.bytes(), 7 * mb);
        let two = s.0[2].as_ptr();
        let v = s.take(mb + 1).unwrap();
        assert_eq!((v.capacity(), v.as_ptr()), (2 * mb, two));
        // Only the 4 MiB one is left to hold 1 MiB + 1; 3 KiB would tie it
        // up: none.
        assert!(s.take(3 << 10).is_none());
        assert!(s.take(5 * mb).is_none());
        // At most four buffers.
        for _ in 0..4 {
            s.keep(Vec::with_capacity(mb), 64 * mb);
        }
        assert_eq!(s.0.len(), REUSE_COUNT);
        s.trim(5 * mb);
        assert!(s.bytes() <= 5 * mb, "{}", s.bytes());
        s.trim(0);
        assert_eq!(s.bytes(), 0);
    }

    /// Renders whose image takes the bytes of one dropped before (another
    /// view's, other sizes) equal renders into new memory.
    #[test]
    fn images_in_reused_bytes_equal_fresh_ones() {
        use crate::raycast::{render_camera, RenderSettings};
        let model = frep_core::Model::compile(
            "my_model(x[3], a[1]) { array c[3]; c = [0, 0, 0]; my_model = hfSphere(x, c, 0.8) & x[3]; }",
        )
        .unwrap();
        let render = |yaw: f64, size: u32| {
            let s = RenderSettings {
                size: (size, size),
                bounds: Aabb::new([-1.0; 3], [1.0; 3]),
                yaw,
                ..Default::default()
            };
            render_camera(&model, &s, &s.camera(), None).unwrap()
        };
        // (Two views of one size: each takes the other's kept bytes.)
        let views = [(30.0, 300), (75.0, 256), (120.0, 256)];
        let fresh: Vec<Image> = views
            .iter()
            .map(|&(yaw, n)| {
                let img = render(yaw, n);
                // (A copy: its bytes are new, never reused.)
                img.clone()
            })
            .collect();
        for _ in 0..3 {
            for (k, &(yaw, n)) in views.iter().enumerate().rev() {
                let img = render(yaw, n);
                assert_eq!(img, fresh[k], "yaw {yaw}");
            }
        }
    }

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
