//! Images, hit buffers (what the ray caster produces) and shading.

use crate::camera::{add, dot, normalize, scale, sub, Camera, Projection};

/// An 8-bit sRGB image with alpha, rows top to bottom.
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

/// A directional light, given relative to the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Direction *towards* the light in camera coordinates: x right, y up,
    /// z towards the viewer. Need not be normalized.
    pub dir: [f64; 3],
    /// Linear RGB intensity.
    pub color: [f32; 3],
}

/// How to shade a hit buffer. Colours are linear RGB unless noted.
#[derive(Clone, Debug, PartialEq)]
pub struct Lighting {
    /// The main light (upper left, in front).
    pub key: Light,
    /// The fill light (softer, from the other side).
    pub fill: Light,
    /// A rim/back light that outlines silhouettes (may be black).
    pub rim: Light,
    /// Hemisphere ambient: colour from straight above (world +z).
    pub sky: [f32; 3],
    /// Hemisphere ambient: colour from straight below.
    pub ground: [f32; 3],
    /// The surface colour without attributes (sRGB in `[0, 1]`).
    pub base_color: [f32; 3],
    /// Specular (Blinn–Phong) strength of the key light.
    pub specular: f32,
    /// Blinn–Phong exponent.
    pub shininess: f32,
    /// How much the per-pixel ambient occlusion darkens (0 = ignore it).
    pub ao_strength: f32,
    /// Background colour at the top of the image (sRGB in `[0, 1]`).
    pub background_top: [f32; 3],
    /// Background colour at the bottom of the image (sRGB in `[0, 1]`).
    pub background_bottom: [f32; 3],
    /// Encode the output as sRGB (true) or write linear values (false).
    pub srgb: bool,
}

impl Default for Lighting {
    fn default() -> Self {
        Lighting {
            key: Light {
                dir: [-0.5, 0.7, 0.6],
                color: [0.85, 0.82, 0.78],
            },
            fill: Light {
                dir: [0.7, 0.1, 0.5],
                color: [0.22, 0.25, 0.3],
            },
            rim: Light {
                dir: [0.2, 0.4, -1.0],
                color: [0.15, 0.15, 0.15],
            },
            sky: [0.22, 0.24, 0.28],
            ground: [0.08, 0.07, 0.06],
            base_color: [0.72, 0.74, 0.78],
            specular: 0.25,
            shininess: 40.0,
            ao_strength: 1.0,
            background_top: [0.26, 0.29, 0.34],
            background_bottom: [0.09, 0.10, 0.12],
            srgb: true,
        }
    }
}

/// sRGB component in `[0, 1]` to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Linear component to sRGB in `[0, 1]` (clamped).
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        c * 12.92
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// `x.powi(n)` by the same square-and-multiply sequence as the `powi`
/// intrinsic's runtime routine, inline (the routine is an out-of-line call).
#[inline]
fn powi(mut x: f32, mut n: u32) -> f32 {
    let mut r = 1.0f32;
    loop {
        if n & 1 == 1 {
            r *= x;
        }
        n /= 2;
        if n == 0 {
            return r;
        }
        x *= x;
    }
}

fn to_byte(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0 + 0.5) as u8
}

/// Cells of [`srgb_byte`]'s index over `[0, 1]`.
const SRGB_CELLS: usize = 4096;

/// `to_byte(linear_to_srgb(c))` without a `powf`: the byte is the number of
/// thresholds at or below `c`, where threshold `b - 1` is the smallest `c`
/// whose byte is at least `b` (found once by bisection over the `f32`s, so
/// the result is the same byte, bit for bit, for every finite `c`). An index
/// gives the count at the start of `c`'s cell of `1/SRGB_CELLS` (exact: the
/// scaling is by a power of two), and the thresholds inside the cell, at
/// most a few, are counted one by one.
#[cfg_attr(not(test), allow(dead_code))]
fn srgb_byte(c: f32) -> u8 {
    srgb_table().byte(c)
}

/// The thresholds and index of [`srgb_byte`].
#[derive(Debug)]
struct SrgbTable {
    t: [f32; 255],
    idx: Vec<u8>,
}

fn srgb_table() -> &'static SrgbTable {
    static T: std::sync::OnceLock<SrgbTable> = std::sync::OnceLock::new();
    T.get_or_init(|| {
        let byte = |bits: u32| to_byte(linear_to_srgb(f32::from_bits(bits)));
        let t: [f32; 255] = std::array::from_fn(|i| {
            let want = i as u8 + 1;
            // Non-negative f32s are ordered like their bit patterns.
            let (mut lo, mut hi) = (0u32, 1.0f32.to_bits());
            while lo < hi {
                let mid = lo + (hi - lo) / 2;
                if byte(mid) >= want {
                    hi = mid;
                } else {
                    lo = mid + 1;
                }
            }
            f32::from_bits(lo)
        });
        let idx = (0..=SRGB_CELLS)
            .map(|q| {
                let x = q as f32 / SRGB_CELLS as f32;
                t.partition_point(|&v| v <= x) as u8
            })
            .collect();
        SrgbTable { t, idx }
    })
}

impl SrgbTable {
    /// [`srgb_byte`].
    #[inline]
    fn byte(&self, c: f32) -> u8 {
        let tab = self;
        if c.is_nan() {
            return to_byte(linear_to_srgb(c));
        }
        if c < 0.0 {
            return tab.t.partition_point(|&x| x <= c) as u8;
        }
        if c >= 1.0 {
            return 255;
        }
        let mut b = tab.idx[(c * SRGB_CELLS as f32) as usize] as usize;
        while b < 255 && tab.t[b] <= c {
            b += 1;
        }
        b as u8
    }
}

/// Shades a hit buffer: key + fill + rim lights fixed to the camera,
/// hemisphere ambient (sky above, ground below, world z up), an optional
/// per-pixel ambient-occlusion factor, attribute colours where present (the
/// default material otherwise), a vertical background gradient where rays
/// missed, and sRGB encoding. Surfaces seen from behind (e.g. where the
/// bounding box cuts the solid open) are lit as if facing the viewer.
pub fn shade(hits: &HitBuffer, lighting: &Lighting) -> Image {
    let (w, h) = (hits.width, hits.height);
    let shader = Shader::new(&hits.camera, lighting, w, h);
    let mut img = Image::filled(w, h, [0, 0, 0, 255]);
    for y in 0..h {
        for x in 0..w {
            let i = y as usize * w as usize + x as usize;
            let ao = hits.ao.as_ref().map(|a| a[i]);
            let rgb = shader.pixel(x, y, hits.hits[i].as_ref(), ao);
            img.rgba[i * 4..i * 4 + 3].copy_from_slice(&rgb);
        }
    }
    img
}

/// The per-pixel part of [`shade`], for callers that shade tile by tile
/// (without holding a whole [`HitBuffer`]): [`Shader::pixel`] gives exactly
/// the colour [`shade`] gives that pixel.
#[derive(Clone, Debug)]
pub struct Shader {
    camera: Camera,
    lighting: Lighting,
    height: u32,
    key: [f64; 3],
    fill: [f64; 3],
    rim: [f64; 3],
    base: [f32; 3],
    /// Orthographic views: the direction back to the eye and the key
    /// light's half vector, the same for every pixel.
    ortho: Option<([f64; 3], [f64; 3])>,
    /// The shininess, when a whole number in `[0, 1024]`.
    whole_shininess: Option<u32>,
    srgb: &'static SrgbTable,
}

impl Shader {
    /// A shader for a `width`×`height` image seen by `camera`.
    pub fn new(camera: &Camera, lighting: &Lighting, width: u32, height: u32) -> Shader {
        let _ = width;
        let cam = camera;
        let to_world = |d: [f64; 3]| {
            normalize(add(
                add(scale(cam.right, d[0]), scale(cam.up, d[1])),
                scale(cam.forward, -d[2]),
            ))
        };
        let key = to_world(lighting.key.dir);
        let ortho = match cam.projection {
            Projection::Perspective { .. } => None,
            Projection::Orthographic { .. } => {
                let view = Shader::view_or_back(cam, scale(cam.forward, -1.0));
                Some((view, normalize(add(key, view))))
            }
        };
        let e = lighting.shininess;
        Shader {
            camera: *camera,
            lighting: lighting.clone(),
            height,
            key,
            fill: to_world(lighting.fill.dir),
            rim: to_world(lighting.rim.dir),
            base: lighting.base_color.map(srgb_to_linear),
            ortho,
            whole_shininess: (e.fract() == 0.0 && (0.0..=1024.0).contains(&e)).then_some(e as u32),
            srgb: srgb_table(),
        }
    }

    /// `view` where it is a usable direction, else straight back along the
    /// camera's axis.
    #[inline]
    fn view_or_back(cam: &Camera, view: [f64; 3]) -> [f64; 3] {
        if view.iter().all(|v| v.is_finite()) && dot(view, view) > 0.5 {
            view
        } else {
            scale(cam.forward, -1.0)
        }
    }

    /// The RGB bytes of pixel `(x, y)` with this hit (`None`: background)
    /// and ambient-occlusion factor (`None`: fully open).
    pub fn pixel(&self, x: u32, y: u32, hit: Option<&Hit>, ao: Option<f32>) -> [u8; 3] {
        let lighting = &self.lighting;
        let cam = &self.camera;
        // The pixel column does not matter (yet): the view direction comes
        // from the hit.
        let _ = x;
        let h = self.height;
        let encode = |c: f32| {
            if lighting.srgb {
                self.srgb.byte(c)
            } else {
                to_byte(c.clamp(0.0, 1.0))
            }
        };
        let Some(hit) = hit else {
            let s = if h > 1 {
                y as f32 / (h - 1) as f32
            } else {
                0.5
            };
            return std::array::from_fn(|k| {
                to_byte(lighting.background_top[k] * (1.0 - s) + lighting.background_bottom[k] * s)
            });
        };
        let (key, fill, rim) = (self.key, self.fill, self.rim);
        // The direction back along the pixel's ray (`cam.ray(x, y).origin`
        // is the eye, or for orthographic views a point straight back).
        let (view, half) = match self.ortho {
            Some(vh) => vh,
            None => {
                let view = Shader::view_or_back(cam, normalize(sub(cam.eye, hit.position)));
                (view, normalize(add(key, view)))
            }
        };
        let mut n = normalize(hit.normal);
        if !(n.iter().all(|v| v.is_finite()) && dot(n, n) > 0.5) {
            n = view;
        }
        if dot(n, view) < 0.0 {
            n = scale(n, -1.0);
        }
        let albedo = hit.color.map_or(self.base, |c| c.map(srgb_to_linear));
        let ao = ao.map_or(1.0, |a| {
            1.0 - lighting.ao_strength * (1.0 - a.clamp(0.0, 1.0))
        });
        let hemi = 0.5 + 0.5 * n[2] as f32;
        let kd = dot(n, key).max(0.0) as f32;
        let fd = dot(n, fill).max(0.0) as f32;
        let rd = dot(n, rim).max(0.0) as f32;
        let spec = if kd > 0.0 {
            let x = dot(n, half).max(0.0) as f32;
            // Whole exponents (the default 40) by multiplication, no powf.
            let p = match self.whole_shininess {
                Some(e) => powi(x, e),
                None => x.powf(lighting.shininess),
            };
            lighting.specular * p
        } else {
            0.0
        };
        std::array::from_fn(|k| {
            let amb = (lighting.sky[k] * hemi + lighting.ground[k] * (1.0 - hemi)) * ao;
            let diffuse = lighting.key.color[k] * kd
                + lighting.fill.color[k] * fd
                + lighting.rim.color[k] * rd;
            let c = albedo[k] * (amb + diffuse * (0.35 + 0.65 * ao))
                + spec * lighting.key.color[k] * ao;
            encode(c)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Aabb;
    use crate::synthetic::sphere_hits;

    fn lum(p: [u8; 4]) -> u32 {
        p[0] as u32 + p[1] as u32 + p[2] as u32
    }

    #[test]
    fn srgb_byte_table_matches_powf() {
        for i in 0..=200_000u32 {
            let c = i as f32 / 100_000.0 - 0.5;
            assert_eq!(srgb_byte(c), to_byte(linear_to_srgb(c)), "{c}");
        }
        for bits in (0..0x3f80_0000u32).step_by(997) {
            let c = f32::from_bits(bits);
            assert_eq!(srgb_byte(c), to_byte(linear_to_srgb(c)), "{c}");
        }
        assert_eq!(srgb_byte(f32::NAN), to_byte(linear_to_srgb(f32::NAN)));
        assert_eq!(srgb_byte(f32::INFINITY), 255);
        assert_eq!(srgb_byte(f32::NEG_INFINITY), 0);
    }

    #[test]
    fn powi_matches_std() {
        for n in [0u32, 1, 2, 3, 7, 40, 41, 1024] {
            for i in 0..=1000 {
                let x = i as f32 / 1000.0;
                assert_eq!(powi(x, n).to_bits(), x.powi(n as i32).to_bits(), "{x}^{n}");
            }
        }
    }

    #[test]
    fn srgb_round_trip() {
        for i in 0..=255u32 {
            let c = i as f32 / 255.0;
            assert_eq!(to_byte(linear_to_srgb(srgb_to_linear(c))), i as u8);
        }
    }

    #[test]
    fn shaded_sphere_reads_as_a_sphere() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 0.0, 0.0, Some(35.0));
        let hits = sphere_hits(&cam, 64, 64, [0.0; 3], 0.8, None);
        let img = shade(&hits, &Lighting::default());
        assert_eq!(img.rgba.len(), 64 * 64 * 4);
        assert!(img.is_opaque());
        // Background corners are the gradient: top lighter than bottom.
        assert!(lum(img.pixel(0, 0)) > lum(img.pixel(0, 63)));
        // The key light is upper left: that side is brighter than lower right.
        assert!(lum(img.pixel(22, 22)) > lum(img.pixel(44, 44)));
        // The sphere differs from the background.
        assert_ne!(img.pixel(32, 32), img.pixel(0, 32));
        // Attribute colours are used: a red sphere is red.
        let red = sphere_hits(&cam, 64, 64, [0.0; 3], 0.8, Some([1.0, 0.0, 0.0]));
        let p = shade(&red, &Lighting::default()).pixel(30, 30);
        assert!(
            p[0] as u32 > 2 * p[1].max(p[2]) as u32 && p[0] > 100,
            "{p:?}"
        );
    }

    #[test]
    fn ambient_occlusion_darkens() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 0.0, 0.0, Some(35.0));
        let mut hits = sphere_hits(&cam, 32, 32, [0.0; 3], 0.8, None);
        let open = shade(&hits, &Lighting::default());
        hits.ao = Some(vec![0.2; 32 * 32]);
        let closed = shade(&hits, &Lighting::default());
        assert!(lum(closed.pixel(16, 16)) < lum(open.pixel(16, 16)));
        assert_eq!(closed.pixel(0, 0), open.pixel(0, 0));
    }

    #[test]
    fn back_faces_and_bad_normals_are_lit() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 0.0, 0.0, Some(35.0));
        let mut hits = sphere_hits(&cam, 16, 16, [0.0; 3], 0.8, None);
        let front = shade(&hits, &Lighting::default()).pixel(8, 8);
        for h in hits.hits.iter_mut().flatten() {
            h.normal = scale(h.normal, -1.0);
        }
        assert_eq!(shade(&hits, &Lighting::default()).pixel(8, 8), front);
        for h in hits.hits.iter_mut().flatten() {
            h.normal = [f64::NAN; 3];
        }
        let p = shade(&hits, &Lighting::default()).pixel(8, 8);
        assert!(lum(p) > 100);
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
