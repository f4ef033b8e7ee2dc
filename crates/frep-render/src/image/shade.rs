//! Shading: lights ([`Lighting`]), the shader of a hit buffer
//! ([`shade`], [`Shader`]), shaded in passes of [`SPAN`] pixels.

use crate::camera::{add, dot, normalize, scale, Camera, Projection};

use super::hits::{Hit, HitBuffer};
use super::srgb::{srgb_table, srgb_to_linear, to_byte, SrgbTable};
use super::Image;

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

/// `x.powi(n)` for every lane, all lanes at once. It takes the same
/// square-and-multiply sequence as the `powi` intrinsic's runtime routine,
/// so the bits are the same. The routine is an out-of-line call per value.
#[inline]
fn powi_lanes(mut x: [f32; SPAN], mut n: u32) -> [f32; SPAN] {
    let mut r = [1.0f32; SPAN];
    loop {
        if n & 1 == 1 {
            for j in 0..SPAN {
                r[j] *= x[j];
            }
        }
        n /= 2;
        if n == 0 {
            return r;
        }
        for v in x.iter_mut() {
            *v *= *v;
        }
    }
}

/// Shades a hit buffer with:
/// - key + fill + rim lights fixed to the camera;
/// - hemisphere ambient (sky above, ground below, world z up);
/// - an optional per-pixel ambient-occlusion factor;
/// - attribute colours where present, the default material otherwise;
/// - a vertical background gradient where rays missed;
/// - sRGB encoding.
///
/// Surfaces seen from behind are lit as if facing the viewer (e.g. where
/// the bounding box cuts the solid open).
pub fn shade(hits: &HitBuffer, lighting: &Lighting) -> Image {
    let (w, h) = (hits.width, hits.height);
    let shader = Shader::new(&hits.camera, lighting, w, h);
    let mut img = Image::filled(w, h, [0, 0, 0, 255]);
    let w = w as usize;
    for y in 0..h {
        let row = y as usize * w..(y as usize + 1) * w;
        let ao = hits.ao.as_ref().map(|a| &a[row.clone()]);
        let rgba = &mut img.rgba[row.start * 4..row.end * 4];
        shader.span(y, &hits.hits[row], ao, rgba);
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
    pub(super) height: u32,
    /// The lights' directions in the world (rounded to `f32`, as the
    /// shading reads them: once here, not per pass).
    key: [f32; 3],
    fill: [f32; 3],
    rim: [f32; 3],
    base: [f32; 3],
    /// Orthographic views: the direction back to the eye and the key
    /// light's half vector, the same for every pixel (in `f32`).
    ortho: Option<([f32; 3], [f32; 3])>,
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
        let f32s = |v: [f64; 3]| v.map(|c| c as f32);
        Shader {
            camera: *camera,
            lighting: lighting.clone(),
            height,
            key: f32s(key),
            fill: f32s(to_world(lighting.fill.dir)),
            rim: f32s(to_world(lighting.rim.dir)),
            base: lighting.base_color.map(srgb_to_linear),
            ortho: ortho.map(|(v, hv)| (f32s(v), f32s(hv))),
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
    /// and ambient-occlusion factor (`None`: fully open): what
    /// [`Shader::span`] gives that pixel.
    pub fn pixel(&self, x: u32, y: u32, hit: Option<&Hit>, ao: Option<f32>) -> [u8; 3] {
        // The pixel column does not matter (yet): the view direction comes
        // from the hit.
        let _ = x;
        let mut rgba = [0u8; 4];
        let ao = ao.map(|a| [a]);
        self.span(y, &[hit.copied()], ao.as_ref().map(|a| &a[..]), &mut rgba);
        [rgba[0], rgba[1], rgba[2]]
    }

    /// The background colour of row `y` (the vertical gradient).
    pub(crate) fn background(&self, y: u32) -> [u8; 3] {
        let lighting = &self.lighting;
        let h = self.height;
        let s = if h > 1 {
            y as f32 / (h - 1) as f32
        } else {
            0.5
        };
        std::array::from_fn(|k| {
            to_byte(lighting.background_top[k] * (1.0 - s) + lighting.background_bottom[k] * s)
        })
    }

    /// Shades a run of pixels of row `y`: `hits[j]` (`None`: background)
    /// with ambient-occlusion factor `ao[j]` (`None`: fully open) gives the
    /// pixel `rgba[4j..4j + 4]`: its RGB bytes, alpha 255 (opaque).
    ///
    /// The pixels are shaded [`SPAN`] at a time, each step a loop over
    /// those pixels (vectorised). Every pixel gets the same bytes whatever
    /// its neighbours. [`Shader::pixel`] is this for one pixel.
    ///
    /// # Panics
    /// If `rgba` holds fewer than `4 · hits.len()` bytes, or `ao` is given
    /// with fewer entries than `hits`.
    pub fn span(&self, y: u32, hits: &[Option<Hit>], ao: Option<&[f32]>, rgba: &mut [u8]) {
        assert!(rgba.len() >= 4 * hits.len(), "Shader::span: rgba too short");
        if let Some(a) = ao {
            assert!(a.len() >= hits.len(), "Shader::span: ao too short");
        }
        let bg = self.background(y);
        for (c, hits) in hits.chunks(SPAN).enumerate() {
            let o = c * SPAN;
            let ao = ao.map(|a| &a[o..o + hits.len()]);
            self.chunk(bg, hits, ao, &mut rgba[4 * o..4 * (o + hits.len())]);
        }
    }

    /// [`Shader::span`] for at most [`SPAN`] pixels.
    fn chunk(&self, bg: [u8; 3], hits: &[Option<Hit>], ao: Option<&[f32]>, rgba: &mut [u8]) {
        let lighting = &self.lighting;
        let m = hits.len();
        debug_assert!(m <= SPAN);
        // Gather: per pixel, the hit's normal (raw), position, albedo and
        // occlusion, structure of arrays. Misses get harmless values (they
        // are not written).
        let mut lanes = ShadeLanes {
            n: [[0.0f64; SPAN]; 3],
            p: [[0.0f64; SPAN]; 3],
            albedo: [[0.0f32; SPAN]; 3],
            aof: [1.0f32; SPAN],
        };
        let ShadeLanes { n, p, albedo, aof } = &mut lanes;
        // Bit `j`: pixel `j` hit.
        let mut hit = 0u32;
        // Positions only matter to perspective views.
        let persp = self.needs_positions();
        let mut last = ([f32::NAN; 3], [0.0f32; 3]);
        for (j, h) in hits.iter().enumerate() {
            let Some(h) = h else { continue };
            hit |= 1 << j;
            for (n, v) in n.iter_mut().zip(h.normal) {
                n[j] = v;
            }
            if persp {
                for (p, v) in p.iter_mut().zip(h.position) {
                    p[j] = v;
                }
            }
            // Neighbouring hits mostly share a colour: its linear values
            // once per run of it (powf is a tenth of a hit's shading).
            let a = match h.color {
                None => self.base,
                Some(c) if c == last.0 => last.1,
                Some(c) => {
                    last = (c, c.map(srgb_to_linear));
                    last.1
                }
            };
            for k in 0..3 {
                albedo[k][j] = a[k];
            }
            if let Some(ao) = ao {
                aof[j] = 1.0 - lighting.ao_strength * (1.0 - ao[j].clamp(0.0, 1.0));
            }
        }
        if hit == 0 {
            fill_background(bg, rgba);
            return;
        }
        self.shade_lanes(bg, lanes.view(), hit, rgba);
    }

    /// Whether shading reads the hits' positions ([`ShadeLanes::p`]): in
    /// perspective views only.
    pub(crate) fn needs_positions(&self) -> bool {
        self.ortho.is_none()
    }

    /// Shades up to [`SPAN`] pixels given as arrays, for the pixels `rgba`
    /// holds. Pixel `j` is a hit where bit `j` of `hit` is set, else the
    /// background `bg`. With `lanes`' values at `j`, it gives the pixel
    /// `rgba[4j..4j + 4]` (alpha 255). This is what [`Shader::span`] does
    /// once it has gathered its hits.
    // Long on purpose: passes over stack arrays of `SPAN` lanes that vectorise. Split, each
    // step would take and return several of those arrays.
    // Kept whole; no split was measured.
    pub(crate) fn shade_lanes(&self, bg: [u8; 3], lanes: ShadeIn, hit: u32, rgba: &mut [u8]) {
        let lighting = &self.lighting;
        let cam = &self.camera;
        let ShadeIn { n, p, material } = lanes;
        let f32s = |v: [f64; 3]| v.map(|c| c as f32);
        let (key, fill, rim) = (self.key, self.fill, self.rim);
        // The normals scaled by a power of two (exact) so that their
        // largest component is about 1, then rounded to `f32`. Normals of
        // any finite size keep their direction. This is a pass of its own,
        // since the `f32` passes have twice the lanes.
        let mut nf = [[0.0f32; SPAN]; 3];
        for j in 0..SPAN {
            let g = [n[0][j], n[1][j], n[2][j]];
            let m = g[0].abs().max(g[1].abs()).max(g[2].abs());
            let e = (m.to_bits() >> 52) as i64;
            let s = f64::from_bits(((2046 - e).clamp(1, 2046) as u64) << 52);
            for k in 0..3 {
                nf[k][j] = (g[k] * s) as f32;
            }
        }
        // The direction back along each pixel's ray and the key light's
        // half vector. They are the same for every pixel of an orthographic
        // view, which then needs no arrays of them.
        let lights = (key, fill, rim);
        let [hemi, kd, fd, rd, sx] = match self.ortho {
            Some((v, hv)) => light_terms(&nf, lights, |_| (v, hv)),
            None => {
                let mut view = [[0.0f32; SPAN]; 3];
                let mut half = [[0.0f32; SPAN]; 3];
                let (eye, back) = (cam.eye, scale(cam.forward, -1.0));
                for j in 0..SPAN {
                    let v = normalize3([eye[0] - p[0][j], eye[1] - p[1][j], eye[2] - p[2][j]]);
                    let ok = v.iter().all(|c| c.is_finite()) && dot(v, v) > 0.5;
                    let v = f32s(if ok { v } else { back });
                    let hv = unit3_f32([key[0] + v[0], key[1] + v[1], key[2] + v[2]]);
                    for k in 0..3 {
                        view[k][j] = v[k];
                        half[k][j] = hv[k];
                    }
                }
                light_terms(&nf, lights, |j| {
                    (
                        [view[0][j], view[1][j], view[2][j]],
                        [half[0][j], half[1][j], half[2][j]],
                    )
                })
            }
        };
        // Blinn–Phong: whole exponents (the default 40) by multiplication.
        let mut spec = match self.whole_shininess {
            Some(e) => powi_lanes(sx, e),
            None => sx.map(|x| x.powf(lighting.shininess)),
        };
        for j in 0..SPAN {
            spec[j] = if kd[j] > 0.0 {
                lighting.specular * spec[j]
            } else {
                0.0
            };
        }
        let mut lin = [[0.0f32; SPAN]; 3];
        for (k, lin) in lin.iter_mut().enumerate() {
            let (sky, ground) = (lighting.sky[k], lighting.ground[k]);
            let (kc, fc, rc) = (
                lighting.key.color[k],
                lighting.fill.color[k],
                lighting.rim.color[k],
            );
            let terms = ([sky, ground, kc, fc, rc], [&hemi, &kd, &fd, &rd, &spec]);
            match material {
                // (The default material, open: the same values, its
                // constants folded.)
                None => light_channel(lin, terms, |_| self.base[k], |_| 1.0),
                Some((albedo, aof)) => light_channel(lin, terms, |j| albedo[k][j], |j| aof[j]),
            }
        }
        // The bytes of every lane first (no branch per pixel), then the
        // pixels that hit.
        let mut bytes = [[0u8; SPAN]; 3];
        for (b, lin) in bytes.iter_mut().zip(&lin) {
            if lighting.srgb {
                for j in 0..SPAN {
                    b[j] = self.srgb.byte(lin[j]);
                }
            } else {
                for j in 0..SPAN {
                    b[j] = to_byte(lin[j].clamp(0.0, 1.0));
                }
            }
        }
        // Whole pixels (alpha 255), as words: a select and a store per
        // eight pixels, not a branch and a three-byte copy per pixel.
        let back = u32::from_le_bytes([bg[0], bg[1], bg[2], 255]);
        let mut px = [0u32; SPAN];
        for j in 0..SPAN {
            let [r, g, b] = [bytes[0][j], bytes[1][j], bytes[2][j]].map(u32::from);
            let v = r | g << 8 | b << 16 | 0xff00_0000;
            px[j] = if (hit >> j) & 1 != 0 { v } else { back };
        }
        // (The same loop twice: over a whole pass its length is known, and
        // it becomes vector stores.)
        match <&mut [u8; 4 * SPAN]>::try_from(&mut *rgba) {
            Ok(all) => {
                for (o, p) in all.chunks_exact_mut(4).zip(&px) {
                    o.copy_from_slice(&p.to_le_bytes());
                }
            }
            Err(_) => {
                for (o, p) in rgba.chunks_exact_mut(4).zip(&px) {
                    o.copy_from_slice(&p.to_le_bytes());
                }
            }
        }
    }
}

/// Fills the pixels `rgba` holds with the background colour `bg`, opaque.
pub(crate) fn fill_background(bg: [u8; 3], rgba: &mut [u8]) {
    for px in rgba.chunks_exact_mut(4) {
        px.copy_from_slice(&[bg[0], bg[1], bg[2], 255]);
    }
}

/// Pixels per pass of [`Shader::span`].
pub const SPAN: usize = 32;

/// What [`Shader::shade_lanes`] shades, per pixel of a pass:
/// - the hit's normal, of any length;
/// - its position, read in perspective views only;
/// - its linear albedo;
/// - its ambient-occlusion factor (1: open).
#[derive(Clone, Debug)]
pub(crate) struct ShadeLanes {
    pub n: [[f64; SPAN]; 3],
    pub p: [[f64; SPAN]; 3],
    pub albedo: [[f32; SPAN]; 3],
    pub aof: [f32; SPAN],
}

impl ShadeLanes {
    /// The lanes as [`Shader::shade_lanes`] reads them.
    pub(crate) fn view(&self) -> ShadeIn<'_> {
        ShadeIn {
            n: self.n.each_ref(),
            p: self.p.each_ref(),
            material: Some((&self.albedo, &self.aof)),
        }
    }
}

/// What [`Shader::shade_lanes`] reads ([`ShadeLanes`]' fields), by
/// reference: normals and positions may be read where they lie (the
/// closed form's solved arrays), not copied first.
#[derive(Clone, Copy)]
pub(crate) struct ShadeIn<'a> {
    pub n: [&'a [f64; SPAN]; 3],
    pub p: [&'a [f64; SPAN]; 3],
    /// The albedo and ambient-occlusion factor per lane; `None`: the
    /// shader's default material, fully open, in every lane.
    pub material: Option<(&'a [[f32; SPAN]; 3], &'a [f32; SPAN])>,
}

/// The light terms per lane of normals `nf`. The normals may have any
/// length; unusable ones give way to the view direction. `vh(j)` gives the
/// direction back to the eye and the key light's half vector at lane `j`.
/// The result is the unit normal facing the viewer, and from it:
/// - the hemisphere blend;
/// - the key, fill and rim lights' diffuse terms;
/// - the key light's specular base.
#[inline(always)]
fn light_terms(
    nf: &[[f32; SPAN]; 3],
    (key, fill, rim): ([f32; 3], [f32; 3], [f32; 3]),
    vh: impl Fn(usize) -> ([f32; 3], [f32; 3]),
) -> [[f32; SPAN]; 5] {
    // (Five arrays, not one of five: one that large is cleared by a call
    // first.)
    let (mut hemi, mut kd, mut fd, mut rd, mut sx) = (
        [0.0f32; SPAN],
        [0.0f32; SPAN],
        [0.0f32; SPAN],
        [0.0f32; SPAN],
        [0.0f32; SPAN],
    );
    for j in 0..SPAN {
        let g = [nf[0][j], nf[1][j], nf[2][j]];
        let l2 = dot_f32(g, g);
        let ok = (l2 > 0.0) & (l2 < f32::INFINITY);
        let inv = 1.0 / l2.sqrt();
        let (v, half) = vh(j);
        let nn = if ok {
            [g[0] * inv, g[1] * inv, g[2] * inv]
        } else {
            v
        };
        let flip = if dot_f32(nn, v) < 0.0 { -1.0 } else { 1.0 };
        let nn = [nn[0] * flip, nn[1] * flip, nn[2] * flip];
        hemi[j] = 0.5 + 0.5 * nn[2];
        kd[j] = dot_f32(nn, key).max(0.0);
        fd[j] = dot_f32(nn, fill).max(0.0);
        rd[j] = dot_f32(nn, rim).max(0.0);
        sx[j] = dot_f32(nn, half).max(0.0);
    }
    [hemi, kd, fd, rd, sx]
}

/// One colour channel's linear value per lane. It comes from the channel's
/// colours `[sky, ground, key, fill, rim]` and the lanes' light terms
/// `[hemisphere blend, key, fill, rim, specular]`, weighed by lane `j`'s
/// albedo and ambient-occlusion factor.
#[inline(always)]
fn light_channel(
    lin: &mut [f32; SPAN],
    ([sky, ground, kc, fc, rc], [hemi, kd, fd, rd, spec]): ([f32; 5], [&[f32; SPAN]; 5]),
    albedo: impl Fn(usize) -> f32,
    aof: impl Fn(usize) -> f32,
) {
    for j in 0..SPAN {
        let ao = aof(j);
        let amb = (sky * hemi[j] + ground * (1.0 - hemi[j])) * ao;
        let diffuse = kc * kd[j] + fc * fd[j] + rc * rd[j];
        lin[j] = albedo(j) * (amb + diffuse * (0.35 + 0.65 * ao)) + spec[j] * kc * ao;
    }
}

#[inline(always)]
fn dot_f32(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a` scaled to unit length (`a` itself where that has none), in `f32`.
#[inline(always)]
fn unit3_f32(a: [f32; 3]) -> [f32; 3] {
    let l = dot_f32(a, a).sqrt();
    let ok = (l > 0.0) & (l < f32::INFINITY);
    let inv = 1.0 / l;
    if ok {
        [a[0] * inv, a[1] * inv, a[2] * inv]
    } else {
        a
    }
}

/// `normalize` with its test written branch-free (so loops over pixels
/// vectorise); the same values.
#[inline(always)]
fn normalize3(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    let ok = l > 0.0 && l.is_finite();
    let inv = 1.0 / l;
    let s = scale(a, inv);
    if ok {
        s
    } else {
        a
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
    fn powi_matches_std() {
        for n in [0u32, 1, 2, 3, 7, 40, 41, 1024] {
            for i in (0..=1000).step_by(SPAN) {
                let x: [f32; SPAN] = std::array::from_fn(|j| (i + j) as f32 / 1000.0);
                let p = powi_lanes(x, n);
                for j in 0..SPAN {
                    assert_eq!(
                        p[j].to_bits(),
                        x[j].powi(n as i32).to_bits(),
                        "{}^{n}",
                        x[j]
                    );
                }
            }
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

    /// A normal's length does not matter, from subnormal sizes to the
    /// largest finite ones. Scaled by a power of two, the image is that of
    /// the unit normals, byte for byte. Subnormal components hold fewer
    /// bits of the direction, so they are within one level. Infinite
    /// normals are unusable, lit as facing the viewer.
    #[test]
    fn normals_of_any_size_shade_alike() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        let cam = Camera::orbit(&b, 30.0, 20.0, Some(35.0));
        let hits = sphere_hits(&cam, 24, 24, [0.1, 0.0, 0.0], 0.8, None);
        let with = |f: &dyn Fn([f64; 3]) -> [f64; 3]| {
            let mut h = hits.clone();
            for h in h.hits.iter_mut().flatten() {
                h.normal = f(h.normal);
            }
            shade(&h, &Lighting::default()).into_rgba()
        };
        let unit = with(&|n| n);
        let most = |a: &[u8], b: &[u8]| a.iter().zip(b).map(|(x, y)| x.abs_diff(*y)).max();
        // 2^e exactly (`powi` may compute 1 / 2^1060 = 1 / ∞ for it).
        let pow2 = |e: i32| match e {
            ..-1022 => f64::from_bits(1 << (e + 1074)),
            _ => f64::from_bits(((e + 1023) as u64) << 52),
        };
        for e in [-1060, -1000, -140, 1, 100, 1023] {
            let s = pow2(e);
            let img = with(&|n| n.map(|c| c * s));
            let within = if e < -1020 { 1 } else { 0 };
            assert!(most(&img, &unit) <= Some(within), "2^{e}");
        }
        let bad = with(&|_| [f64::NAN; 3]);
        assert_ne!(bad, unit);
        assert_eq!(with(&|_| [f64::INFINITY, 0.0, 1.0]), bad);
        assert_eq!(with(&|_| [0.0; 3]), bad);
    }

    /// A row shaded in one call gives every pixel the bytes it gets alone,
    /// whatever its neighbours in the pass. The row mixes hits, misses,
    /// colours, occlusion, unusable and back-facing normals, in both
    /// projections.
    #[test]
    fn span_matches_pixel() {
        let b = Aabb::new([-1.0; 3], [1.0; 3]);
        for ortho in [false, true] {
            let mut cam = Camera::orbit(&b, 30.0, 20.0, Some(35.0));
            if ortho {
                cam = Camera::orbit(&b, 30.0, 20.0, None);
            }
            let hits = sphere_hits(&cam, 80, 3, [0.1, 0.0, 0.0], 0.8, None);
            let mut row: Vec<Option<Hit>> = hits.hits[80..160].to_vec();
            for (j, h) in row.iter_mut().enumerate() {
                let Some(h) = h else { continue };
                match j % 5 {
                    1 => h.color = Some([0.9, 0.2, 0.1]),
                    2 => h.normal = [f64::NAN; 3],
                    3 => h.normal = scale(h.normal, -3.0),
                    4 => h.normal = [0.0; 3],
                    _ => {}
                }
            }
            let ao: Vec<f32> = (0..80).map(|j| (j % 7) as f32 / 6.0).collect();
            let shader = Shader::new(&cam, &Lighting::default(), 80, 3);
            for a in [None, Some(&ao[..])] {
                let mut rgba = vec![0u8; 80 * 4];
                shader.span(1, &row, a, &mut rgba);
                for (j, h) in row.iter().enumerate() {
                    let one = shader.pixel(j as u32, 1, h.as_ref(), a.map(|a| a[j]));
                    assert_eq!(rgba[4 * j..4 * j + 3], one, "pixel {j}, ortho {ortho}");
                    // (Whole pixels: `rgba` started transparent.)
                    assert_eq!(rgba[4 * j + 3], 255, "pixel {j}, ortho {ortho}");
                }
            }
        }
    }
}
