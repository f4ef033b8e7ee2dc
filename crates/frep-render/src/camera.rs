//! Cameras: a turntable orbit that frames a bounding box, primary rays through
//! pixel centres, and the frustum of a pixel rectangle (for tile pruning).
//!
//! Conventions:
//! - World **z is up**.
//! - At yaw 0 and pitch 0 the eye sits on the −y side of the box and looks
//!   along +y. +x is to the right of the image and +z up.
//! - Yaw turns the eye counter-clockwise around z, seen from above. Yaw 90°
//!   puts the eye on +x, looking along −x, with +y to the right.
//! - Pitch raises the eye above the xy plane. Pitch 90° looks straight down.
//! - Pixel `(px, py)` has its centre at `(px + 0.5, py + 0.5)` in image
//!   coordinates. x grows to the right and y grows **down** the image.
//! - The field of view (perspective) and the extent (orthographic) apply to
//!   the *shorter* side of the image. So the framed box fits whatever the
//!   aspect ratio.

use serde::{Deserialize, Serialize};

/// An axis-aligned box in world coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// The minimum corner.
    pub min: [f64; 3],
    /// The maximum corner.
    pub max: [f64; 3],
}

impl Aabb {
    /// A box from its two corners (each coordinate is sorted).
    pub fn new(a: [f64; 3], b: [f64; 3]) -> Aabb {
        Aabb {
            min: [a[0].min(b[0]), a[1].min(b[1]), a[2].min(b[2])],
            max: [a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])],
        }
    }

    /// The centre of the box.
    pub fn center(&self) -> [f64; 3] {
        [
            0.5 * (self.min[0] + self.max[0]),
            0.5 * (self.min[1] + self.max[1]),
            0.5 * (self.min[2] + self.max[2]),
        ]
    }

    /// The radius of the bounding sphere (half the diagonal).
    pub fn radius(&self) -> f64 {
        0.5 * length(sub(self.max, self.min))
    }

    /// The size of the box along each axis.
    pub fn size(&self) -> [f64; 3] {
        sub(self.max, self.min)
    }

    /// The smallest box holding both boxes.
    pub fn union(&self, o: &Aabb) -> Aabb {
        Aabb {
            min: std::array::from_fn(|k| self.min[k].min(o.min[k])),
            max: std::array::from_fn(|k| self.max[k].max(o.max[k])),
        }
    }
}

/// A ray: `origin + t * dir`, with `dir` of unit length (so `t` is a distance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: [f64; 3],
    /// The unit direction.
    pub dir: [f64; 3],
}

impl Ray {
    /// The distances along the ray at which it enters and leaves `bounds`, if
    /// it meets the box ahead of its origin (`t0` is clamped to 0).
    pub fn clip(&self, bounds: &Aabb) -> Option<(f64, f64)> {
        self.clip_inv(bounds, self.dir.map(|d| 1.0 / d))
    }

    /// [`Ray::clip`] with `inv = 1 / dir` (per component) given, for callers
    /// clipping many rays of one direction.
    #[inline]
    pub fn clip_inv(&self, bounds: &Aabb, inv: [f64; 3]) -> Option<(f64, f64)> {
        let mut t0 = 0.0f64;
        let mut t1 = f64::INFINITY;
        for k in 0..3 {
            let inv = inv[k];
            let mut a = (bounds.min[k] - self.origin[k]) * inv;
            let mut b = (bounds.max[k] - self.origin[k]) * inv;
            if a > b {
                std::mem::swap(&mut a, &mut b);
            }
            // NaN (origin on a slab face with dir 0) leaves the range unchanged.
            if a > t0 {
                t0 = a;
            }
            if b < t1 {
                t1 = b;
            }
        }
        (t0 <= t1).then_some((t0, t1))
    }

    /// The point at distance `t` along the ray.
    pub fn at(&self, t: f64) -> [f64; 3] {
        add(self.origin, scale(self.dir, t))
    }
}

/// The projection of a camera.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Projection {
    /// Perspective, with the full field of view across the shorter image side.
    Perspective {
        /// Field of view in degrees across the shorter side of the image.
        fov_deg: f64,
    },
    /// Orthographic (parallel rays).
    Orthographic {
        /// Half the world extent seen across the shorter side of the image.
        half_extent: f64,
    },
}

/// A camera: eye, target, orthonormal frame and projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The eye position (for orthographic cameras: the centre of the plane
    /// the rays start from).
    pub eye: [f64; 3],
    /// The point looked at.
    pub target: [f64; 3],
    /// Unit vector pointing up in the image.
    pub up: [f64; 3],
    /// Unit vector pointing right in the image.
    pub right: [f64; 3],
    /// Unit viewing direction (from eye to target).
    pub forward: [f64; 3],
    /// The projection.
    pub projection: Projection,
}

/// The four corner rays of a pixel rectangle: the rays of every pixel inside
/// lie in the frustum they span.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frustum {
    /// Corner rays in the order top-left, top-right, bottom-left, bottom-right
    /// (through the rectangle's outer pixel *edges*, not centres).
    pub corners: [Ray; 4],
    /// The camera's unit viewing direction (depth is measured along it).
    pub forward: [f64; 3],
}

impl Frustum {
    /// The axis-aligned box enclosing the part of the frustum between the
    /// depths `z0 <= z1`, measured along the camera's viewing direction from
    /// the ray origins. The region is the convex hull of the 8 corner points
    /// at those depths, so this box is conservative.
    pub fn aabb_between_depths(&self, z0: f64, z1: f64) -> Aabb {
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for r in &self.corners {
            let c = dot(r.dir, self.forward).max(1e-12);
            for z in [z0, z1] {
                let p = r.at(z / c);
                for k in 0..3 {
                    min[k] = min[k].min(p[k]);
                    max[k] = max[k].max(p[k]);
                }
            }
        }
        Aabb { min, max }
    }
}

impl Camera {
    /// A camera at `eye` looking at `target`, with `up_hint` roughly up
    /// (it must not be parallel to the viewing direction).
    pub fn look_at(
        eye: [f64; 3],
        target: [f64; 3],
        up_hint: [f64; 3],
        projection: Projection,
    ) -> Camera {
        let forward = normalize(sub(target, eye));
        let right = normalize(cross(forward, up_hint));
        let up = cross(right, forward);
        Camera {
            eye,
            target,
            up,
            right,
            forward,
            projection,
        }
    }

    /// A turntable orbit around the centre of `bounds` at `yaw_deg`,
    /// `pitch_deg`, framing the box: the box's bounding sphere exactly fills
    /// the shorter side of the image.
    ///
    /// `fov_deg`: `Some(fov)` for a perspective camera with that field of
    /// view, `None` for an orthographic one.
    pub fn orbit(bounds: &Aabb, yaw_deg: f64, pitch_deg: f64, fov_deg: Option<f64>) -> Camera {
        let target = bounds.center();
        let r = bounds.radius().max(1e-12);
        let (yaw, pitch) = (yaw_deg.to_radians(), pitch_deg.to_radians());
        // Unit vector from target to eye; the right vector comes from yaw alone,
        // so looking straight down (pitch ±90°) is well defined.
        let back = [
            pitch.cos() * yaw.sin(),
            -pitch.cos() * yaw.cos(),
            pitch.sin(),
        ];
        let right = [yaw.cos(), yaw.sin(), 0.0];
        let forward = scale(back, -1.0);
        let up = normalize(cross(right, forward));
        let (distance, projection) = match fov_deg {
            Some(fov) => {
                let half = (0.5 * fov.clamp(1e-3, 179.0)).to_radians();
                (r / half.sin(), Projection::Perspective { fov_deg: fov })
            }
            None => (2.0 * r, Projection::Orthographic { half_extent: r }),
        };
        Camera {
            eye: add(target, scale(back, distance)),
            target,
            up,
            right,
            forward,
            projection,
        }
    }

    /// The ray through the centre of pixel `(px, py)` of a `width`×`height`
    /// image (y down).
    pub fn ray(&self, px: u32, py: u32, width: u32, height: u32) -> Ray {
        self.ray_at(px as f64 + 0.5, py as f64 + 0.5, width, height)
    }

    /// The ray through the continuous image point `(x, y)` (pixel units,
    /// `(0, 0)` the top-left corner of the image, y down).
    pub fn ray_at(&self, x: f64, y: f64, width: u32, height: u32) -> Ray {
        self.rays(width, height).ray_at(x, y)
    }

    /// The rays of a `width`×`height` image, for callers that make many.
    /// The per-image constants (the field of view's tangent, the scale) are
    /// computed once. The rays are [`Camera::ray_at`]'s, bit for bit.
    pub fn rays(&self, width: u32, height: u32) -> RayMaker {
        let s = 0.5 * width.min(height).max(1) as f64;
        let (k, footprint) = match self.projection {
            Projection::Perspective { fov_deg } => {
                let k = (0.5 * fov_deg).to_radians().tan();
                (k, k / s)
            }
            Projection::Orthographic { half_extent } => (half_extent, half_extent / s),
        };
        RayMaker {
            cam: *self,
            hw: 0.5 * width as f64,
            hh: 0.5 * height as f64,
            s,
            k,
            footprint,
        }
    }

    /// The frustum of the pixel rectangle `[x0, x1) × [y0, y1)` (pixel indices,
    /// y down): its corner rays pass through the outer pixel edges, so every
    /// pixel-centre ray of the rectangle lies inside.
    pub fn tile_frustum(
        &self,
        x0: u32,
        y0: u32,
        x1: u32,
        y1: u32,
        width: u32,
        height: u32,
    ) -> Frustum {
        self.rays(width, height).frustum(x0, y0, x1, y1)
    }

    /// The world size of one pixel at distance `t` from the eye (for
    /// perspective; constant for orthographic), in a `width`×`height` image.
    /// Useful as the precision a hit must be found to.
    pub fn pixel_footprint(&self, t: f64, width: u32, height: u32) -> f64 {
        let s = 0.5 * width.min(height).max(1) as f64;
        match self.projection {
            Projection::Perspective { fov_deg } => t.abs() * (0.5 * fov_deg).to_radians().tan() / s,
            Projection::Orthographic { half_extent } => half_extent / s,
        }
    }
}

/// The rays of one image size of a [`Camera`] (see [`Camera::rays`]).
#[derive(Clone, Copy, Debug)]
pub struct RayMaker {
    cam: Camera,
    hw: f64,
    hh: f64,
    s: f64,
    /// tan(fov/2) (perspective) or the half extent (orthographic).
    k: f64,
    /// The pixel footprint per unit distance (perspective) or the constant
    /// footprint (orthographic).
    footprint: f64,
}

impl RayMaker {
    /// [`Camera::ray_at`].
    #[inline]
    pub fn ray_at(&self, x: f64, y: f64) -> Ray {
        let c = &self.cam;
        let u = (x - self.hw) / self.s;
        let v = (self.hh - y) / self.s;
        match c.projection {
            Projection::Perspective { .. } => {
                let d = add(
                    c.forward,
                    add(scale(c.right, u * self.k), scale(c.up, v * self.k)),
                );
                Ray {
                    origin: c.eye,
                    dir: normalize(d),
                }
            }
            Projection::Orthographic { .. } => Ray {
                origin: add(
                    c.eye,
                    add(scale(c.right, u * self.k), scale(c.up, v * self.k)),
                ),
                dir: c.forward,
            },
        }
    }

    /// [`Camera::ray`].
    #[inline]
    pub fn ray(&self, px: u32, py: u32) -> Ray {
        self.ray_at(px as f64 + 0.5, py as f64 + 0.5)
    }

    /// The rays through the centres of the `L` pixels from `(x0, py)` along
    /// row `py`, as lanes (`origin[k][j]`, `dir[k][j]`). They are the rays
    /// of [`RayMaker::ray`], bit for bit. The row's terms are computed once,
    /// and the lanes in one pass that the compiler turns into vector code.
    /// Pixels past the image's edge get the rays their coordinates give;
    /// callers ignore them.
    // (The lane passes index several arrays at once.)
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    pub fn row_lanes<const L: usize>(
        &self,
        x0: u32,
        py: u32,
        origin: &mut [[f64; L]; 3],
        dir: &mut [[f64; L]; 3],
    ) {
        let c = &self.cam;
        let v = (self.hh - (py as f64 + 0.5)) / self.s;
        let row = scale(c.up, v * self.k);
        let mut off = [[0.0f64; L]; 3];
        for j in 0..L {
            let u = (f64::from(x0) + j as f64 + 0.5 - self.hw) / self.s;
            for k in 0..3 {
                off[k][j] = c.right[k] * (u * self.k) + row[k];
            }
        }
        match c.projection {
            Projection::Perspective { .. } => {
                for j in 0..L {
                    let a = [
                        c.forward[0] + off[0][j],
                        c.forward[1] + off[1][j],
                        c.forward[2] + off[2][j],
                    ];
                    // `normalize`, as a select.
                    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
                    let r = 1.0 / l;
                    let ok = l > 0.0 && l.is_finite();
                    for k in 0..3 {
                        origin[k][j] = c.eye[k];
                        dir[k][j] = if ok { a[k] * r } else { a[k] };
                    }
                }
            }
            Projection::Orthographic { .. } => {
                for j in 0..L {
                    for k in 0..3 {
                        origin[k][j] = c.eye[k] + off[k][j];
                        dir[k][j] = c.forward[k];
                    }
                }
            }
        }
    }

    /// The per-column terms of an orthographic view's origins for columns
    /// `x0..x0 + out.len()` (see [`RayMaker::ortho_row_origins`]). Every row
    /// shares them, so they are worked out once per tile, not per row. Each
    /// costs a division.
    pub fn ortho_columns(&self, x0: u32, out: &mut [f64]) {
        for (j, uk) in out.iter_mut().enumerate() {
            *uk = (f64::from(x0) + j as f64 + 0.5 - self.hw) / self.s * self.k;
        }
    }

    /// The origins of the `L` rays of columns `uk` along row `py` of an
    /// orthographic view, as lanes (`origin[k][j]`). `uk` holds their terms
    /// from [`RayMaker::ortho_columns`]. The origins are
    /// [`RayMaker::row_lanes`]', bit for bit. The directions are left out:
    /// every ray's is the camera's axis. Only for orthographic views.
    // (The lane passes index several arrays at once.)
    #[allow(clippy::needless_range_loop)]
    #[inline(always)]
    pub fn ortho_row_origins<const L: usize>(
        &self,
        uk: &[f64; L],
        py: u32,
        origin: [&mut [f64; L]; 3],
    ) {
        debug_assert!(matches!(
            self.cam.projection,
            Projection::Orthographic { .. }
        ));
        let c = &self.cam;
        let v = (self.hh - (py as f64 + 0.5)) / self.s;
        let row = scale(c.up, v * self.k);
        for (k, o) in origin.into_iter().enumerate() {
            for j in 0..L {
                o[j] = c.eye[k] + (c.right[k] * uk[j] + row[k]);
            }
        }
    }

    /// [`Camera::pixel_footprint`].
    #[inline]
    pub fn pixel_footprint(&self, t: f64) -> f64 {
        match self.cam.projection {
            Projection::Perspective { .. } => t.abs() * self.footprint,
            Projection::Orthographic { .. } => self.footprint,
        }
    }

    /// [`Camera::tile_frustum`].
    pub fn frustum(&self, x0: u32, y0: u32, x1: u32, y1: u32) -> Frustum {
        let (x0, y0, x1, y1) = (x0 as f64, y0 as f64, x1 as f64, y1 as f64);
        Frustum {
            corners: [
                self.ray_at(x0, y0),
                self.ray_at(x1, y0),
                self.ray_at(x0, y1),
                self.ray_at(x1, y1),
            ],
            forward: self.cam.forward,
        }
    }
}

pub(crate) fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(crate) fn length(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
pub(crate) fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = length(a);
    if l > 0.0 && l.is_finite() {
        scale(a, 1.0 / l)
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_box() -> Aabb {
        Aabb::new([-1.0; 3], [1.0; 3])
    }

    fn close(a: [f64; 3], b: [f64; 3], eps: f64) -> bool {
        length(sub(a, b)) < eps
    }

    /// Distance from point `p` to the line of `ray`.
    fn dist_to_ray(ray: &Ray, p: [f64; 3]) -> f64 {
        let d = sub(p, ray.origin);
        length(sub(d, scale(ray.dir, dot(d, ray.dir))))
    }

    #[test]
    fn centre_ray_hits_box_centre() {
        let b = Aabb::new([1.0, 2.0, 3.0], [2.0, 5.0, 4.0]);
        for fov in [Some(40.0), None] {
            for (yaw, pitch) in [(0.0, 0.0), (37.0, 20.0), (200.0, -60.0), (10.0, 90.0)] {
                let cam = Camera::orbit(&b, yaw, pitch, fov);
                // Even sizes: the image centre is a pixel corner.
                let r = cam.ray_at(64.0, 48.0, 128, 96);
                assert!(dist_to_ray(&r, b.center()) < 1e-9, "{yaw} {pitch} {fov:?}");
                assert!(close(r.dir, cam.forward, 1e-12));
                // Odd size: the centre pixel's ray.
                let r = cam.ray(50, 50, 101, 101);
                assert!(dist_to_ray(&r, b.center()) < 1e-9);
            }
        }
    }

    /// `row_lanes` gives `ray`'s rays bit for bit, in both projections, at
    /// odd and even sizes, past the image's right edge too.
    #[test]
    fn row_lanes_match_ray() {
        let b = Aabb::new([-1.0, 0.5, -2.0], [3.0, 1.5, 0.0]);
        for fov in [Some(35.0), None] {
            for (w, h) in [(7, 5), (64, 48)] {
                let rm = Camera::orbit(&b, 130.0, -35.0, fov).rays(w, h);
                for py in 0..h {
                    for x0 in (0..w).step_by(8) {
                        let mut o = [[0.0; 8]; 3];
                        let mut d = [[0.0; 8]; 3];
                        rm.row_lanes(x0, py, &mut o, &mut d);
                        for j in 0..8 {
                            let r = rm.ray(x0 + j as u32, py);
                            for k in 0..3 {
                                assert_eq!(o[k][j].to_bits(), r.origin[k].to_bits());
                                assert_eq!(d[k][j].to_bits(), r.dir[k].to_bits());
                            }
                        }
                    }
                }
            }
        }
    }

    /// `ortho_row_origins` gives `ray`'s origins bit for bit, at odd and
    /// even sizes, past the image's right edge too.
    #[test]
    #[allow(clippy::needless_range_loop)]
    fn ortho_row_origins_match_ray() {
        let b = Aabb::new([-1.0, 0.5, -2.0], [3.0, 1.5, 0.0]);
        for (yaw, pitch) in [(130.0, -35.0), (0.0, 90.0)] {
            for (w, h) in [(7, 5), (64, 48)] {
                let rm = Camera::orbit(&b, yaw, pitch, None).rays(w, h);
                for py in 0..h {
                    for x0 in (0..w).step_by(8) {
                        let (mut o, mut uk) = ([[0.0; 8]; 3], [0.0; 8]);
                        rm.ortho_columns(x0, &mut uk);
                        rm.ortho_row_origins(&uk, py, o.each_mut());
                        for j in 0..8 {
                            let r = rm.ray(x0 + j as u32, py);
                            for k in 0..3 {
                                assert_eq!(o[k][j].to_bits(), r.origin[k].to_bits());
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn frame_is_orthonormal() {
        for (yaw, pitch) in [(0.0, 0.0), (123.0, 45.0), (-30.0, 90.0), (0.0, -90.0)] {
            let c = Camera::orbit(&unit_box(), yaw, pitch, Some(30.0));
            for v in [c.up, c.right, c.forward] {
                assert!((length(v) - 1.0).abs() < 1e-12);
            }
            assert!(dot(c.up, c.right).abs() < 1e-12);
            assert!(dot(c.up, c.forward).abs() < 1e-12);
            assert!(dot(c.right, c.forward).abs() < 1e-12);
            // Right-handed: right × forward = up.
            assert!(close(cross(c.right, c.forward), c.up, 1e-12));
        }
    }

    #[test]
    fn yaw_turns_the_view() {
        let c0 = Camera::orbit(&unit_box(), 0.0, 0.0, Some(30.0));
        assert!(close(c0.forward, [0.0, 1.0, 0.0], 1e-12));
        assert!(close(c0.right, [1.0, 0.0, 0.0], 1e-12));
        assert!(close(c0.up, [0.0, 0.0, 1.0], 1e-12));
        let c90 = Camera::orbit(&unit_box(), 90.0, 0.0, Some(30.0));
        assert!(close(c90.forward, [-1.0, 0.0, 0.0], 1e-12));
        assert!(close(c90.right, [0.0, 1.0, 0.0], 1e-12));
        assert!(close(c90.up, [0.0, 0.0, 1.0], 1e-12));
        let top = Camera::orbit(&unit_box(), 0.0, 90.0, None);
        assert!(close(top.forward, [0.0, 0.0, -1.0], 1e-12));
        assert!(close(top.up, [0.0, 1.0, 0.0], 1e-12));
        // Image right in pixels is world right: a ray right of centre leans to +x.
        let r = c0.ray(100, 50, 101, 101);
        assert!(r.dir[0] > 0.0);
        // Image down (y grows) is world down.
        let r = c0.ray(50, 100, 101, 101);
        assert!(r.dir[2] < 0.0);
    }

    #[test]
    fn ortho_rays_are_parallel() {
        let cam = Camera::orbit(&unit_box(), 30.0, 25.0, None);
        let a = cam.ray(0, 0, 64, 32);
        let b = cam.ray(63, 31, 64, 32);
        assert!(close(a.dir, b.dir, 1e-15));
        assert!(!close(a.origin, b.origin, 1e-3));
        // Origins lie in one plane perpendicular to the view.
        assert!((dot(sub(a.origin, b.origin), cam.forward)).abs() < 1e-12);
        // The eye plane is outside the box's bounding sphere.
        assert!(length(sub(cam.eye, cam.target)) > unit_box().radius());
    }

    #[test]
    fn bounding_sphere_fills_the_view() {
        let b = unit_box();
        let r = b.radius();
        for fov in [Some(20.0), Some(60.0), None] {
            let cam = Camera::orbit(&b, 15.0, 10.0, fov);
            // The ray at the middle of the left edge of a square image is
            // tangent to the bounding sphere.
            let ray = cam.ray_at(0.0, 50.0, 100, 100);
            assert!((dist_to_ray(&ray, b.center()) - r).abs() < 1e-9, "{fov:?}");
            // For a wide image the limit is the shorter (vertical) side.
            let ray = cam.ray_at(100.0, 0.0, 200, 100);
            assert!((dist_to_ray(&ray, b.center()) - r).abs() < 1e-9);
        }
    }

    #[test]
    fn footprint_matches_neighbouring_rays() {
        for fov in [Some(45.0), None] {
            let cam = Camera::orbit(&unit_box(), 0.0, 0.0, fov);
            let (w, h) = (200, 100);
            let a = cam.ray_at(100.0, 50.0, w, h);
            let b = cam.ray_at(101.0, 50.0, w, h);
            let t = length(sub(cam.target, cam.eye));
            let d = length(sub(a.at(t), b.at(t)));
            let fp = cam.pixel_footprint(t, w, h);
            assert!((d - fp).abs() / fp < 1e-3, "{d} {fp}");
        }
    }

    #[test]
    fn tile_frustum_contains_its_pixels() {
        let b = unit_box();
        for fov in [Some(50.0), None] {
            let cam = Camera::orbit(&b, 33.0, 21.0, fov);
            let (w, h) = (64, 48);
            let f = cam.tile_frustum(16, 8, 32, 24, w, h);
            let tl = cam.ray_at(16.0, 8.0, w, h);
            assert_eq!(f.corners[0], tl);
            let (z0, z1) = (1.0, 5.0);
            let bx = f.aabb_between_depths(z0, z1);
            for py in 8..24 {
                for px in 16..32 {
                    let r = cam.ray(px, py, w, h);
                    let c = dot(r.dir, cam.forward);
                    for z in [z0, 2.0, 3.7, z1] {
                        let p = r.at(z / c);
                        assert!(
                            (0..3).all(|k| p[k] >= bx.min[k] - 1e-9 && p[k] <= bx.max[k] + 1e-9)
                        );
                    }
                }
            }
            // A pixel outside the tile leaves the box somewhere.
            let r = cam.ray(0, 47, w, h);
            let p = r.at(z1 / dot(r.dir, cam.forward));
            assert!((0..3).any(|k| p[k] < bx.min[k] || p[k] > bx.max[k]));
        }
    }

    #[test]
    fn clip_ray_to_box() {
        let b = unit_box();
        let r = Ray {
            origin: [0.0, -5.0, 0.0],
            dir: [0.0, 1.0, 0.0],
        };
        let (t0, t1) = r.clip(&b).unwrap();
        assert!((t0 - 4.0).abs() < 1e-12 && (t1 - 6.0).abs() < 1e-12);
        let miss = Ray {
            origin: [0.0, -5.0, 2.0],
            dir: [0.0, 1.0, 0.0],
        };
        assert!(miss.clip(&b).is_none());
        let behind = Ray {
            origin: [0.0, 5.0, 0.0],
            dir: [0.0, 1.0, 0.0],
        };
        assert!(behind.clip(&b).is_none());
    }
}
