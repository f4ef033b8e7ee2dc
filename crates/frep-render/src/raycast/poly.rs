//! The field along one ray as a polynomial in the depth ([`RayPoly`]) and
//! its first root ([`Root`]); the quadric of a shortened tape of degree 2
//! ([`Quadric`]).

use crate::camera::{dot, sub, Aabb};
use crate::image::Hit;

use super::normals::unit;
use super::rays::RayInfo;

/// A polynomial of degree 2 in the point, about a point `p0`:
/// `q(p0 + u) = c + g·u + uᵀ·A·u` (`a` symmetric).
/// - For a field of degree 2 it is the field.
/// - For a root gap `k − sqrt(p)` it is `k² − p`. That has the field's
///   sign and, on the surface, the direction of its gradient
///   (`∇q = 2(k − f)·∇f`).
///
/// Along a ray `p = o + dz·z` it is a polynomial of degree 2 in the depth,
/// so no samples are needed ([`TileCtx::exact`]).
///
/// [`TileCtx::exact`]: crate::raycast::tile::TileCtx::exact
#[derive(Clone, Copy, Debug)]
pub(super) struct Quadric {
    pub(super) p0: [f64; 3],
    pub(super) c: f64,
    pub(super) g: [f64; 3],
    pub(super) a: [[f64; 3]; 3],
}

impl Quadric {
    /// `(α, β, γ)` with `q(o + dz·z) = α z² + β z + γ` along ray `r`.
    #[inline]
    fn along(&self, r: &RayInfo) -> (f64, f64, f64) {
        self.along_ray(r.origin, r.dz)
    }

    /// [`Quadric::along`] for the ray `origin + dz·z`.
    #[inline(always)]
    pub(super) fn along_ray(&self, origin: [f64; 3], dz: [f64; 3]) -> (f64, f64, f64) {
        let w = sub(origin, self.p0);
        let a = &self.a;
        let ad = [dot(a[0], dz), dot(a[1], dz), dot(a[2], dz)];
        let aw = [dot(a[0], w), dot(a[1], w), dot(a[2], w)];
        (
            dot(dz, ad),
            2.0 * dot(w, ad) + dot(self.g, dz),
            self.c + dot(self.g, w) + dot(w, aw),
        )
    }

    /// The hit of ray `r` at depth `z`, on the quadric's surface: its
    /// normal the quadric's (`None` where that has no direction).
    #[inline]
    pub(super) fn hit(&self, r: &RayInfo, z: f64) -> Option<Hit> {
        let position = r.at_depth(z);
        let g = self.grad(position);
        let normal = unit([-g[0], -g[1], -g[2]])?;
        Some(Hit {
            t: z / r.c,
            position,
            normal,
            color: None,
        })
    }

    /// The step of a fit over the model box `b` ([`Quadric::fit`]): a
    /// quarter of its longest side.
    pub(super) fn fit_step(b: &Aabb) -> f64 {
        0.25 * (0..3).map(|a| b.max[a] - b.min[a]).fold(0.0, f64::max)
    }

    /// The points a quadric is fitted at ([`Quadric::fit`]): `p0`, and `h`
    /// from it along each axis.
    pub(super) fn fit_points(p0: [f64; 3], h: f64) -> [[f64; 3]; 4] {
        std::array::from_fn(|j| {
            let mut p = p0;
            if j > 0 {
                p[j - 1] += h;
            }
            p
        })
    }

    /// The quadric about `p0` with the values and gradients `qs` at its
    /// [`Quadric::fit_points`]. It takes the value and gradient at `p0`.
    /// `A` comes from the differences of the gradients, symmetrised. A
    /// quadric's gradient is affine, so that is exact but for rounding.
    pub(super) fn fit(p0: [f64; 3], h: f64, qs: &[(f64, [f64; 3]); 4]) -> Quadric {
        let (c, g) = qs[0];
        let mut a = [[0.0; 3]; 3];
        for (i, row) in a.iter_mut().enumerate() {
            for (j, v) in row.iter_mut().enumerate() {
                let dij = qs[j + 1].1[i] - g[i];
                let dji = qs[i + 1].1[j] - g[j];
                *v = (dij + dji) / (4.0 * h);
            }
        }
        Quadric { p0, c, g, a }
    }

    /// `q(p)`, and the sum of its terms' sizes there (for a rounding
    /// allowance).
    pub(super) fn value_and_scale(&self, p: [f64; 3]) -> (f64, f64) {
        let u = sub(p, self.p0);
        let a = &self.a;
        let (lin, quad) = (
            dot(self.g, u),
            dot(u, [dot(a[0], u), dot(a[1], u), dot(a[2], u)]),
        );
        (self.c + lin + quad, self.c.abs() + lin.abs() + quad.abs())
    }

    /// `∇q` at `p`.
    #[inline]
    pub(super) fn grad(&self, p: [f64; 3]) -> [f64; 3] {
        let u = sub(p, self.p0);
        let a = &self.a;
        [
            self.g[0] + 2.0 * dot(a[0], u),
            self.g[1] + 2.0 * dot(a[1], u),
            self.g[2] + 2.0 * dot(a[2], u),
        ]
    }
}

/// Where a polynomial along a ray first reaches `f ≥ 0` (see
/// [`RayPoly::first_root`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Root {
    /// At this depth.
    At(f64),
    /// Nowhere in the range: it stays below `0` by more than rounding.
    None,
    /// Within rounding of `0` without a clear crossing (a graze), or
    /// below `0` at the start by no more than rounding.
    Unsure,
}

/// The field along one ray on one evaluator whose tape is a polynomial of
/// degree at most 2 in the point ([`Tape::polynomial_degree`]). Along the
/// ray it is then a polynomial of degree at most 2 in the depth:
/// `q(s) = a s² + b s + c`. `s = (z − lo) / w` is the fraction of the slab
/// it was sampled over. It holds for the whole ray, not only that slab, so
/// a later slab of the ray on the same evaluator needs no samples.
///
/// Where the tape is `k − sqrt(p)` instead ([`Tape::root_gap`]), `q` is
/// that of `f·(2k − f) = k² − p`, which has the field's sign
/// ([`RayPoly::field`] maps its values back).
///
/// [`Tape::polynomial_degree`]: frep_core::Tape::polynomial_degree
/// [`Tape::root_gap`]: frep_core::Tape::root_gap
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct RayPoly {
    /// The tile's [`Scratch::tile_gen`] (high 32 bits) and the evaluator
    /// plus 1 (0: none yet).
    ///
    /// [`Scratch::tile_gen`]: crate::raycast::scratch::Scratch::tile_gen
    pub(super) tag: u64,
    pub(super) lo: f64,
    pub(super) w: f64,
    pub(super) a: f64,
    pub(super) b: f64,
    pub(super) c: f64,
    /// The largest magnitude sampled: the scale of rounding errors.
    pub(super) scale: f64,
    /// The root gap `k` (`0`: `q` is the field's own polynomial).
    pub(super) k: f64,
}

impl RayPoly {
    /// The polynomial through the values `[f0, fm, f1]` (finite) at `lo`,
    /// the middle and `hi`: the field's, or where the root gap `k` is
    /// positive those of `f·(2k − f)` ([`RayPoly::map`]).
    pub(super) fn fit(tag: u64, lo: f64, hi: f64, [f0, fm, f1]: [f64; 3], k: f64) -> RayPoly {
        RayPoly {
            tag,
            lo,
            w: hi - lo,
            a: 2.0 * (f1 - 2.0 * fm + f0),
            b: 4.0 * fm - 3.0 * f0 - f1,
            c: f0,
            scale: f0.abs().max(fm.abs()).max(f1.abs()),
            k,
        }
    }

    /// The polynomial of ray `r` on the quadric `quad` (its own, not
    /// fitted to samples), in the fraction of the slab `[lo, hi]`.
    #[inline]
    pub(super) fn of_quadric(
        tag: u64,
        lo: f64,
        hi: f64,
        quad: &Quadric,
        r: &RayInfo,
        k: f64,
    ) -> RayPoly {
        let [a, b, c, scale] = RayPoly::coefficients(lo, hi, quad.along(r));
        RayPoly {
            tag,
            lo,
            w: hi - lo,
            a,
            b,
            c,
            scale,
            k,
        }
    }

    /// [`RayPoly::of_quadric`]'s `a`, `b`, `c` and scale, from the ray's
    /// `(α, β, γ)` ([`Quadric::along`]).
    #[inline(always)]
    pub(super) fn coefficients(lo: f64, hi: f64, (al, be, ga): (f64, f64, f64)) -> [f64; 4] {
        let w = hi - lo;
        let (a, b, c) = (
            al * w * w,
            (2.0 * al * lo + be) * w,
            (al * lo + be) * lo + ga,
        );
        let (qm, q1) = (0.25 * a + 0.5 * b + c, a + b + c);
        [a, b, c, c.abs().max(qm.abs()).max(q1.abs())]
    }

    /// The polynomial's value for the field's value `f`: `f` itself, or
    /// for a root gap `k` `f·(2k − f)`.
    pub(super) fn map(f: f64, k: f64) -> f64 {
        if k > 0.0 {
            f * (2.0 * k - f)
        } else {
            f
        }
    }

    /// The field's value for the polynomial's value `q`: `q` itself, or
    /// for a root gap `k` the `f ≤ k` with `f·(2k − f) = q`, which is
    /// `q / (k + sqrt(k² − q))` (without cancellation near the surface).
    pub(super) fn field(&self, q: f64) -> f64 {
        let k = self.k;
        if k > 0.0 {
            q / (k + (k * k - q).max(0.0).sqrt())
        } else {
            q
        }
    }

    fn at_s(&self, s: f64) -> f64 {
        (self.a * s + self.b) * s + self.c
    }

    fn s_of(&self, z: f64) -> f64 {
        if self.w > 0.0 {
            (z - self.lo) / self.w
        } else {
            0.0
        }
    }

    /// The value at depth `z`.
    pub(super) fn at(&self, z: f64) -> f64 {
        self.at_s(self.s_of(z))
    }

    /// The rounding error of values at fractions within `[s0, s1]`, taken
    /// as `1e-9` of the samples' scale, growing with the square of the
    /// distance from the sampled slab.
    fn tol_s(&self, s0: f64, s1: f64) -> f64 {
        1e-9 * self.scale * s0.abs().max(s1.abs()).max(1.0).powi(2)
    }

    /// [`RayPoly::tol_s`] between depths `za` and `zb`.
    pub(super) fn tol(&self, za: f64, zb: f64) -> f64 {
        self.tol_s(self.s_of(za), self.s_of(zb))
    }

    /// Whether the polynomial, fitted over its own slab, is finite and
    /// clearly outside at the slab's start: below `−1e-9` of its scale,
    /// the rounding allowance there ([`TileCtx::take_fresh`]'s case).
    ///
    /// [`TileCtx::take_fresh`]: crate::raycast::tile::TileCtx::take_fresh
    #[inline]
    pub(super) fn fresh_outside(&self) -> bool {
        let finite = [self.a, self.b, self.c, self.scale]
            .iter()
            .all(|v| v.is_finite());
        finite && self.w > 0.0 && self.c < -1e-9 * self.scale
    }

    /// Whether the field is clearly defined at the slab's start. It always
    /// is, but for a root gap `k − sqrt(p)`. Its polynomial `q = k² − p`
    /// holds no trace of where `p < 0`, where the field is NaN, outside.
    /// So a root gap is clearly defined only where `q` is below `k²` by more
    /// than rounding. Before a crossing from `q < 0`, `p > k²`: only a slab
    /// that starts inside needs this.
    pub(super) fn defined_at_start(&self) -> bool {
        let k2 = self.k * self.k;
        self.k <= 0.0 || self.c < k2 - 1e-9 * self.scale.max(k2)
    }

    /// The smallest fraction past `s0` where `q = 0` (`∞` where none).
    #[inline]
    pub(super) fn first_s(&self, s0: f64) -> f64 {
        let (a, b, c) = (self.a, self.b, self.c);
        let mut first = f64::INFINITY;
        if a == 0.0 {
            if b > 0.0 {
                first = -c / b;
            }
        } else {
            let disc = b * b - 4.0 * a * c;
            if disc >= 0.0 {
                // Both roots without cancellation: q/a and c/q.
                let q = -0.5 * (b + disc.sqrt().copysign(b));
                for r in [q / a, c / q] {
                    if r > s0 && r < first {
                        first = r;
                    }
                }
            }
        }
        first
    }

    /// The first depth in `(za, zb]` where `q ≥ 0`, given `q(za) < 0` by
    /// more than rounding ([`RayPoly::tol`]; else [`Root::Unsure`]).
    pub(super) fn first_root(&self, za: f64, zb: f64) -> Root {
        let valid = self.w > 0.0 && za <= zb;
        if !valid {
            return Root::Unsure;
        }
        let (s0, s1) = (self.s_of(za), self.s_of(zb));
        let tol = self.tol_s(s0, s1);
        let q0 = self.at_s(s0);
        if q0 >= -tol || q0.is_nan() {
            return Root::Unsure;
        }
        self.root_from(s0, s1, q0, tol, za, zb)
    }

    /// [`RayPoly::first_root`] past its checks: `s0` and `s1` the
    /// fractions of `za` and `zb`, `q0` the value at `s0` (below `−tol`).
    #[inline]
    pub(super) fn root_from(&self, s0: f64, s1: f64, q0: f64, tol: f64, za: f64, zb: f64) -> Root {
        let (a, b) = (self.a, self.b);
        let first = self.first_s(s0);
        if first <= s1 {
            return Root::At((self.lo + self.w * first).clamp(za, zb));
        }
        // No root in the range: its largest value there, against rounding.
        let mut top = q0.max(self.at_s(s1));
        if a < 0.0 {
            let s = -b / (2.0 * a);
            if s > s0 && s < s1 {
                top = top.max(self.at_s(s));
            }
        }
        if top < -tol {
            Root::None
        } else {
            Root::Unsure
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The polynomial through `f` sampled at `lo`, the middle and `hi`.
    fn fit(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> RayPoly {
        RayPoly::fit(1, lo, hi, [f(lo), f(0.5 * (lo + hi)), f(hi)], 0.0)
    }

    fn at(r: Root) -> f64 {
        match r {
            Root::At(z) => z,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn first_root_of_a_quadratic() {
        // Enters at 2, leaves at 3: the first crossing, inside the slab.
        let q = |z: f64| -(z - 2.0) * (z - 3.0);
        let p = fit(q, 1.0, 4.0);
        assert!((at(p.first_root(1.0, 4.0)) - 2.0).abs() < 1e-12);
        // Both roots between the samples (all three outside): still found.
        let p = fit(q, 0.0, 5.0);
        assert!(q(0.0) < 0.0 && q(2.5) > 0.0 && q(5.0) < 0.0);
        let p0 = fit(q, -1.0, 0.9);
        assert!(q(-1.0) < 0.0 && q(-0.05) < 0.0 && q(0.9) < 0.0);
        assert!((at(p.first_root(0.0, 5.0)) - 2.0).abs() < 1e-12);
        // From a slab in front of them, for a later slab: no samples.
        assert_eq!(p0.first_root(-1.0, 0.9), Root::None);
        assert!((at(p0.first_root(0.9, 2.5)) - 2.0).abs() < 1e-9);
        assert_eq!(p0.first_root(3.5, 9.0), Root::None);
        // Linear (a plane) and constant (beside a wall) along the ray.
        let p = fit(|z| z - 1.25, 0.0, 2.0);
        assert!((at(p.first_root(0.0, 2.0)) - 1.25).abs() < 1e-12);
        assert_eq!(p.first_root(0.0, 1.0), Root::None);
        let p = fit(|_| -0.5, 0.0, 2.0);
        assert_eq!(p.first_root(0.0, 100.0), Root::None);
    }

    #[test]
    fn root_gaps_in_closed_form() {
        // M1's sphere `0.8 − sqrt(x² + y² + z²)` along the z axis from
        // z = 2 down: `0.8 − |2 − t|`, inside for t in [1.2, 2.8]. Not a
        // polynomial in t (a kink at t = 2), but `k² − (2 − t)²` is.
        let k = 0.8;
        let f = |t: f64| k - (2.0 - t).abs();
        let q = |t: f64| RayPoly::map(f(t), k);
        let p = RayPoly::fit(1, 0.0, 1.0, [q(0.0), q(0.5), q(1.0)], k);
        assert_eq!(p.first_root(0.0, 1.0), Root::None);
        assert!((at(p.first_root(1.0, 4.0)) - 1.2).abs() < 1e-12);
        // The polynomial's values map back to the field's.
        for t in [0.0, 0.7, 1.2, 1.5, 2.0, 2.6] {
            assert!((p.field(p.at(t)) - f(t)).abs() < 1e-12, "{t}");
        }
        // Fitted on the far side of the kink, it still gives the entry.
        let p = RayPoly::fit(1, 2.5, 4.0, [q(2.5), q(3.25), q(4.0)], k);
        assert!((at(p.first_root(0.0, 4.0)) - 1.2).abs() < 1e-12);
        // Without the map, the kinked samples fit a wrong polynomial.
        let q = RayPoly::fit(1, 0.0, 4.0, [f(0.0), f(2.0), f(4.0)], 0.0);
        assert!(matches!(q.first_root(0.0, 4.0), Root::At(z) if (z - 1.2).abs() > 0.1));
    }

    #[test]
    fn grazes_are_unsure() {
        // Touching 0 at 2 without crossing, and within rounding of it.
        for top in [0.0, -1e-13] {
            let p = fit(|z: f64| top - (z - 2.0) * (z - 2.0), 1.0, 3.0);
            assert_eq!(p.first_root(1.0, 1.5), Root::None, "{top}");
            assert!(matches!(p.first_root(1.0, 3.0), Root::Unsure | Root::At(_)));
            if top < 0.0 {
                assert_eq!(p.first_root(1.0, 3.0), Root::Unsure);
            }
        }
        // Starting at 0 (not clearly outside), or an empty slab.
        let p = fit(|z| z, 0.0, 1.0);
        assert_eq!(p.first_root(0.0, 1.0), Root::Unsure);
        let p = RayPoly::fit(1, 1.0, 1.0, [-1.0, -1.0, -1.0], 0.0);
        assert_eq!(p.first_root(1.0, 1.0), Root::Unsure);
    }
}
