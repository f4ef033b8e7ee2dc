//! Rays, set up for the caster:
//! - a tile's rays in lanes ([`set_up_rays`]): origins, directions, depth
//!   scales and their clip to the model box;
//! - one ray ([`RayInfo`]);
//! - a rectangle's corner rays ([`Corners`]).

use crate::camera::{dot, sub, Aabb, Camera, Projection, RayMaker};
use crate::tiles::Tile;

use super::csg::{Lanes, BLOCK};
use super::scratch::Scratch;

/// One pixel's ray, with its depth range inside the model box (depth = the
/// distance along the camera's viewing direction, `z = t · c`).
#[derive(Clone, Copy, Default)]
pub(super) struct RayInfo {
    pub(super) origin: [f64; 3],
    pub(super) dir: [f64; 3],
    /// `dir / c`: the point at depth `z` is `origin + dz · z`.
    pub(super) dz: [f64; 3],
    /// `dir · forward`.
    pub(super) c: f64,
    pub(super) z0: f64,
    pub(super) z1: f64,
    pub(super) live: bool,
}

impl RayInfo {
    #[inline]
    pub(super) fn at_depth(&self, z: f64) -> [f64; 3] {
        [
            self.origin[0] + self.dz[0] * z,
            self.origin[1] + self.dz[1] * z,
            self.origin[2] + self.dz[2] * z,
        ]
    }

    /// The axis-aligned box of the ray's segment between depths `a` and
    /// `b`.
    pub(super) fn segment_box(&self, a: f64, b: f64) -> Aabb {
        let (pa, pb) = (self.at_depth(a), self.at_depth(b));
        Aabb {
            min: std::array::from_fn(|k| pa[k].min(pb[k])),
            max: std::array::from_fn(|k| pa[k].max(pb[k])),
        }
    }
}

/// The corner rays of a pixel rectangle's frustum, through its outer pixel
/// edges. Each is a point and its direction per unit depth, so the
/// frustum's boxes between depths take no division. The depth-bisection
/// children of a node share them.
pub(super) struct Corners {
    pub(super) origin: [[f64; 3]; 4],
    pub(super) dz: [[f64; 3]; 4],
}

impl Corners {
    /// The corner rays of the frustum of the image pixels
    /// `[x0, x1) × [y0, y1)`.
    pub(super) fn of(rm: &RayMaker, x0: u32, y0: u32, x1: u32, y1: u32) -> Corners {
        let fr = rm.frustum(x0, y0, x1, y1);
        let mut k = Corners {
            origin: [[0.0; 3]; 4],
            dz: [[0.0; 3]; 4],
        };
        for (j, r) in fr.corners.iter().enumerate() {
            let c = dot(r.dir, fr.forward).max(1e-12);
            k.origin[j] = r.origin;
            k.dz[j] = [r.dir[0] / c, r.dir[1] / c, r.dir[2] / c];
        }
        k
    }

    /// The axis-aligned box of the frustum between depths `z0` and `z1`
    /// (what [`Frustum::aabb_between_depths`](crate::camera::Frustum::aabb_between_depths) gives).
    pub(super) fn aabb(&self, z0: f64, z1: f64) -> Aabb {
        let mut min = [f64::INFINITY; 3];
        let mut max = [f64::NEG_INFINITY; 3];
        for j in 0..4 {
            for z in [z0, z1] {
                for a in 0..3 {
                    let p = self.origin[j][a] + self.dz[j][a] * z;
                    min[a] = min[a].min(p);
                    max[a] = max[a].max(p);
                }
            }
        }
        Aabb { min, max }
    }
}

/// A ray direction's `c = dir · forward` (at least 1e-12), `dz = dir / c`
/// and `1 / dir` (per component).
pub(super) fn per_dir(d: [f64; 3], forward: [f64; 3]) -> (f64, [f64; 3], [f64; 3]) {
    let c = dot(d, forward).max(1e-12);
    (c, [d[0] / c, d[1] / c, d[2] / c], d.map(|v| 1.0 / v))
}

/// The outward normal of the face of box `b` that `p` lies on, if it does
/// (a hit where the solid is cut open by the box).
pub(super) fn entry_face(b: &Aabb, p: &[f64; 3]) -> Option<[f64; 3]> {
    let mut best = (f64::INFINITY, [0.0; 3]);
    for k in 0..3 {
        let size = (b.max[k] - b.min[k]).abs().max(1e-300);
        for (face, sign) in [(b.min[k], -1.0), (b.max[k], 1.0)] {
            let d = (p[k] - face).abs() / size;
            if d < best.0 {
                let mut n = [0.0; 3];
                n[k] = sign;
                best = (d, n);
            }
        }
    }
    (best.0 < 1e-6).then_some(best.1)
}

/// How many rays of a row [`set_up_rays`] computes in one pass.
pub(super) const SETUP_LANES: usize = 16;

/// Sizes `sc.rays`, `sc.z0s` and `sc.z1s` for the tile and fills them with
/// its rays (`rm`, of `cam`), row by row. Each ray gets its [`per_dir`]
/// terms and its depth range inside `bounds`
/// ([`Ray::clip_inv`](crate::camera::Ray::clip_inv)). [`SETUP_LANES`] rays
/// are set up at a time, in passes over arrays that the compiler turns into
/// vector code. The bits are those of one ray at a time. In an orthographic
/// view, returns the [`per_dir`] terms all rays share (the camera axis's).
pub(super) fn set_up_rays(
    bounds: &Aabb,
    cam: &Camera,
    rm: RayMaker,
    tile: &Tile,
    sc: &mut Scratch,
) -> Option<(f64, [f64; 3], [f64; 3])> {
    const L: usize = SETUP_LANES;
    let forward = cam.forward;
    // Once for all rays of an orthographic view (their direction is the
    // camera's axis).
    let fixed = matches!(cam.projection, Projection::Orthographic { .. })
        .then(|| per_dir(forward, forward));
    let n = (tile.w() * tile.h()) as usize;
    sc.rays.resize(n, RayInfo::default());
    sc.z0s.resize(n, 0.0);
    sc.z1s.resize(n, 0.0);
    let (rays, z0s, z1s) = (&mut sc.rays[..n], &mut sc.z0s[..n], &mut sc.z1s[..n]);
    let mut k = 0;
    let mut r = RayLanes::default();
    for py in tile.y0..tile.y1 {
        let mut x = tile.x0;
        while x < tile.x1 {
            let n = ((tile.x1 - x) as usize).min(L);
            ray_lanes(bounds, forward, fixed, &rm, (x, py), &mut r);
            let RayLanes {
                o,
                d,
                dz,
                c,
                z0,
                z1,
            } = &r;
            for j in 0..n {
                let live = z0[j] <= z1[j];
                let (rz0, rz1) = if live { (z0[j], z1[j]) } else { (0.0, 0.0) };
                rays[k] = RayInfo {
                    origin: [o[0][j], o[1][j], o[2][j]],
                    dir: [d[0][j], d[1][j], d[2][j]],
                    dz: [dz[0][j], dz[1][j], dz[2][j]],
                    c: c[j],
                    z0: rz0,
                    z1: rz1,
                    live,
                };
                (z0s[k], z1s[k]) = (z0[j], z1[j]);
                k += 1;
            }
            x += n as u32;
        }
    }
    debug_assert_eq!(k, n, "every ray of the tile set up");
    fixed
}

/// The first `m` rays of `r` into lanes `k..k + m` of `lanes` (origins,
/// directions scaled to depth, depth ranges): a row's last rays, where
/// fewer than [`SETUP_LANES`] are left.
#[cold]
#[inline(never)]
pub(super) fn put_ray_lanes(lanes: &mut Lanes, r: &RayLanes, k: usize, m: usize) {
    for a in 0..3 {
        lanes.o[a][k..k + m].copy_from_slice(&r.o[a][..m]);
        lanes.d[a][k..k + m].copy_from_slice(&r.dz[a][..m]);
    }
    lanes.z0[k..k + m].copy_from_slice(&r.z0[..m]);
    lanes.z1[k..k + m].copy_from_slice(&r.z1[..m]);
}

/// [`SETUP_LANES`] rays of a row ([`ray_lanes`]): origins, directions, the
/// [`per_dir`] terms, and the depths `z0 ≤ z1` of the ray's part in the
/// model box (`[+∞, −∞]` where it misses the box).
#[derive(Default)]
pub(super) struct RayLanes {
    pub(super) o: [[f64; SETUP_LANES]; 3],
    pub(super) d: [[f64; SETUP_LANES]; 3],
    pub(super) dz: [[f64; SETUP_LANES]; 3],
    pub(super) c: [f64; SETUP_LANES],
    pub(super) z0: [f64; SETUP_LANES],
    pub(super) z1: [f64; SETUP_LANES],
}

/// What [`set_up_rays`] sets up, for the rays of pixels `x..x + SETUP_LANES`
/// of row `py`, clipped to `bounds`. `rm` is of a camera looking along
/// `forward`. `fixed`: the [`per_dir`] terms all rays share, in an
/// orthographic view. The work is done in passes over arrays, which
/// vectorise, and written into `out` in place, with no copy of the arrays.
#[inline(always)]
pub(super) fn ray_lanes(
    bounds: &Aabb,
    forward: [f64; 3],
    fixed: Option<(f64, [f64; 3], [f64; 3])>,
    rm: &RayMaker,
    (x, py): (u32, u32),
    out: &mut RayLanes,
) {
    const L: usize = SETUP_LANES;
    let RayLanes {
        o,
        d,
        dz,
        c,
        z0,
        z1,
    } = out;
    rm.row_lanes(x, py, o, d);
    let mut inv = [[0.0f64; L]; 3];
    match fixed {
        Some((fc, fdz, finv)) => {
            *c = [fc; L];
            for a in 0..3 {
                dz[a] = [fdz[a]; L];
                inv[a] = [finv[a]; L];
            }
        }
        None => {
            // `per_dir` written out: called per lane it gives the
            // same bits, but the pass no longer vectorises (+5 M
            // instructions on a 512² turntable, measured).
            for j in 0..L {
                let cj =
                    (d[0][j] * forward[0] + d[1][j] * forward[1] + d[2][j] * forward[2]).max(1e-12);
                c[j] = cj;
                for a in 0..3 {
                    dz[a][j] = d[a][j] / cj;
                    inv[a][j] = 1.0 / d[a][j];
                }
            }
        }
    }
    clip_lanes(bounds, o.each_ref(), |a, j| inv[a][j], |j| c[j], (z0, z1));
}

/// The depths `z0 ≤ z1` of the part inside `bounds` of `L` rays, or
/// `[+∞, −∞]` where a ray misses it. The rays start at origins `o`, with
/// reciprocal directions `inv(axis, lane)` and depth scales `c(lane)`. This
/// is [`Ray::clip_inv`](crate::camera::Ray::clip_inv) with selects, the
/// depths `t·c`. [`ray_lanes`] and [`ortho_lanes`] share this one body, so
/// their bits are the same.
// (The lane passes index several arrays at once.)
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn clip_lanes<const L: usize>(
    bounds: &Aabb,
    o: [&[f64; L]; 3],
    inv: impl Fn(usize, usize) -> f64,
    c: impl Fn(usize) -> f64,
    (z0, z1): (&mut [f64; L], &mut [f64; L]),
) {
    let mut t0 = [0.0f64; L];
    let mut t1 = [f64::INFINITY; L];
    for a in 0..3 {
        for j in 0..L {
            let p = (bounds.min[a] - o[a][j]) * inv(a, j);
            let q = (bounds.max[a] - o[a][j]) * inv(a, j);
            let swap = p > q;
            let (lo, hi) = (if swap { q } else { p }, if swap { p } else { q });
            t0[j] = if lo > t0[j] { lo } else { t0[j] };
            t1[j] = if hi < t1[j] { hi } else { t1[j] };
        }
    }
    for j in 0..L {
        let live = t0[j] <= t1[j];
        z0[j] = if live { t0[j] * c(j) } else { f64::INFINITY };
        z1[j] = if live {
            t1[j] * c(j)
        } else {
            f64::NEG_INFINITY
        };
    }
}

/// [`ray_lanes`] in an orthographic view, for the rays of the pixels of
/// columns `uk` ([`RayMaker::ortho_columns`]) of row `py`. `c` and `inv`
/// are the [`per_dir`] terms of the camera's axis, which every ray shares.
/// Their origins and depth ranges go straight into lanes
/// `k..k + SETUP_LANES` of `lanes`, with the same bits. The directions are
/// the caller's, written once.
#[inline(always)]
pub(super) fn ortho_lanes(
    bounds: &Aabb,
    (c, inv): (f64, [f64; 3]),
    rm: &RayMaker,
    (uk, py): (&[f64; SETUP_LANES], u32),
    lanes: &mut Lanes,
    k: usize,
) {
    const L: usize = SETUP_LANES;
    fn lane(v: &mut [f64; BLOCK], k: usize) -> &mut [f64; L] {
        (&mut v[k..k + L]).try_into().expect("SETUP_LANES lanes")
    }
    let [o0, o1, o2] = &mut lanes.o;
    rm.ortho_row_origins(uk, py, [lane(o0, k), lane(o1, k), lane(o2, k)]);
    let o = [&*lane(o0, k), &*lane(o1, k), &*lane(o2, k)];
    let z = (lane(&mut lanes.z0, k), lane(&mut lanes.z1, k));
    clip_lanes(bounds, o, |a, _| inv[a], |_| c, z);
}

/// The least and greatest depth of the corners of box `b`, which bound its
/// points'. Depth is the distance along the viewing direction from the eye;
/// orthographic rays start on the eye's plane.
pub(super) fn depth_range(b: &Aabb, camera: &Camera) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for j in 0..8 {
        let p = std::array::from_fn(|a| {
            if (j >> a) & 1 == 0 {
                b.min[a]
            } else {
                b.max[a]
            }
        });
        let z = dot(sub(p, camera.eye), camera.forward);
        lo = lo.min(z);
        hi = hi.max(z);
    }
    (lo, hi)
}

pub(super) fn clip_box(b: &Aabb, bounds: &Aabb) -> Option<Aabb> {
    let mut min = [0.0; 3];
    let mut max = [0.0; 3];
    for k in 0..3 {
        min[k] = b.min[k].max(bounds.min[k]);
        max[k] = b.max[k].min(bounds.max[k]);
        if min[k] > max[k] || min[k].is_nan() || max[k].is_nan() {
            return None;
        }
    }
    Some(Aabb { min, max })
}

#[cfg(test)]
mod tests {
    use super::*;
    use frep_core::Model;

    /// `set_up_rays` gives each ray of a tile what `RayMaker::ray`,
    /// `per_dir` and `Ray::clip_inv` give it one at a time, bit for bit.
    /// Checked in perspective and orthographic views, oblique and straight
    /// along an axis. The latter have directions with zero components and
    /// origins on the box's faces, whose slab tests meet `0 · ∞`. Also in
    /// tiles narrower than a lane pass or cut off by the image's edge, and
    /// with rays that miss the box.
    #[test]
    fn set_up_rays_match_one_ray_at_a_time() {
        let b = Aabb::new([-1.0, -0.5, -2.0], [1.0, 0.5, 0.0]);
        let tape = Model::compile("my_model(x[3], a[1]) { my_model = 1 - x[1]*x[1]; }")
            .unwrap()
            .tape()
            .clone();
        let mut sc = Scratch::new(&tape);
        let axis = Camera {
            eye: [0.0, 0.25, 5.0],
            target: [0.0, 0.25, 0.0],
            forward: [0.0, 0.0, -1.0],
            right: [1.0, 0.0, 0.0],
            up: [0.0, 1.0, 0.0],
            projection: Projection::Orthographic { half_extent: 1.0 },
        };
        let cams = [
            Camera::orbit(&b, 30.0, 20.0, Some(30.0)),
            Camera::orbit(&b, 200.0, -60.0, Some(60.0)),
            Camera::orbit(&b, 35.0, 25.0, None),
            axis,
        ];
        for (c, cam) in cams.into_iter().enumerate() {
            let (w, h) = (21, 19);
            let rm = cam.rays(w, h);
            // Straight along the axis: the box's x faces through the
            // origins of columns 3 and 17, whose slab tests give `0 · ∞`.
            let b = if c == 3 {
                let (lo, hi) = (rm.ray(3, 0).origin[0], rm.ray(17, 0).origin[0]);
                Aabb::new([lo, b.min[1], b.min[2]], [hi, b.max[1], b.max[2]])
            } else {
                b
            };
            let tile = |x0, y0, x1, y1| Tile {
                x0,
                y0,
                x1,
                y1,
                width: w,
                height: h,
            };
            for tile in [tile(0, 0, 21, 19), tile(5, 3, 10, 7), tile(16, 11, 21, 19)] {
                let n = (tile.w() * tile.h()) as usize;
                let fixed = set_up_rays(&b, &cam, rm, &tile, &mut sc);
                let ortho = matches!(cam.projection, Projection::Orthographic { .. });
                assert_eq!(fixed.is_some(), ortho);
                let mut k = 0;
                let mut misses = 0;
                for py in tile.y0..tile.y1 {
                    for px in tile.x0..tile.x1 {
                        let r = rm.ray(px, py);
                        let (c, dz, inv) = per_dir(r.dir, cam.forward);
                        let got = &sc.rays[k];
                        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                        assert_eq!(bits(&got.origin), bits(&r.origin));
                        assert_eq!(bits(&got.dir), bits(&r.dir));
                        assert_eq!(bits(&got.dz), bits(&dz));
                        assert_eq!(got.c.to_bits(), c.to_bits());
                        match r.clip_inv(&b, inv) {
                            Some((t0, t1)) => {
                                assert!(got.live);
                                assert_eq!(got.z0.to_bits(), (t0 * c).to_bits());
                                assert_eq!(got.z1.to_bits(), (t1 * c).to_bits());
                                assert_eq!((sc.z0s[k], sc.z1s[k]), (got.z0, got.z1));
                            }
                            None => {
                                assert!(!got.live);
                                assert_eq!(sc.z0s[k], f64::INFINITY);
                                assert_eq!(sc.z1s[k], f64::NEG_INFINITY);
                                misses += 1;
                            }
                        }
                        k += 1;
                    }
                }
                assert_eq!(k, n);
                if tile.x1 - tile.x0 == w {
                    assert!(misses > 0 && misses < n, "{misses} of {n} rays miss");
                }
            }
        }
    }
}
