//! Slabs whose shortened tape is a plane or a quadric: every ray's crossing
//! solved in closed form ([`TileCtx::exact`]).

use crate::camera::dot;
use crate::image::Hit;

use super::frustum::Rect;
use super::normals::{unit, NORMAL_LEN2};
use super::poly::{Quadric, RayPoly, Root};
use super::search::Tail;
use super::tile::TileCtx;
use super::{EXACT_BRACKET_PX, QUAD_BLOCK};

impl<'a> TileCtx<'a> {
    /// Settles the slab `[za, zb]` of `rect`'s rays on evaluator `e`. Along
    /// every ray, `e`'s field is a polynomial of degree at most 2, up to a
    /// map that keeps its sign ([`Evals::exact`]).
    /// 1. Each ray's polynomial comes from the quadric's coefficients
    ///    ([`TileCtx::quadric`]). For a plane it comes from its values, and
    ///    the rays that clearly cross it are hits at once
    ///    ([`TileCtx::plane_hits`]). Where neither is to be had, it comes
    ///    from samples at the slab's ends and middle.
    /// 2. Its first crossing (`f ≥ 0`) is found in closed form
    ///    ([`RayPoly::first_root`]) and checked. It is the hit where the
    ///    polynomial is outside [`EXACT_BRACKET_PX`] footprints before it
    ///    and inside as many after.
    /// 3. A ray inside at its first sample is a direct hit.
    /// 4. A ray whose polynomial stays clearly outside over the slab has no
    ///    crossing there. It goes on behind, its tail set as a sampled
    ///    slab's.
    ///
    /// Returns whether every ray was settled so. If not, the rays with no
    /// crossing are in [`Scratch::settled`], and the others are left
    /// unresolved. Those are a crossing that did not check out, a ray
    /// grazing the surface, or a value not finite.
    ///
    /// [`Evals::exact`]: crate::raycast::scratch::Evals::exact
    /// [`Scratch::settled`]: crate::raycast::scratch::Scratch::settled
    pub(super) fn exact(&mut self, e: usize, rect: Rect, za: f64, zb: f64) -> bool {
        self.sc.settled.clear();
        let rays = self.gather(rect, za, zb, true);
        if rays.is_empty() {
            self.sc.leaf_rays = rays;
            return true;
        }
        let tag = (self.sc.tile_gen << 32) | (e as u64 + 1);
        let mut fresh = std::mem::take(&mut self.sc.fresh);
        fresh.clear();
        let mut sure = true;
        // Rays whose polynomial on this evaluator is known from an earlier
        // slab: no samples.
        for &(i, lo, hi) in &rays {
            let p = self.sc.polys[i];
            if p.tag != tag || !self.settle(&p, e, i, lo, hi) {
                fresh.push((i, lo, hi));
            }
        }
        if !fresh.is_empty() {
            let (i, lo, _) = fresh[0];
            let p0 = self.sc.rays[i].at_depth(lo);
            let (affine, k) = (
                self.sc.evals[e].affine,
                self.sc.evals[e].exact.unwrap_or(0.0),
            );
            let quad = if affine {
                None
            } else {
                let h = Quadric::fit_step(&self.caster.bounds);
                self.quadric(e, p0, h)
            };
            if let Some(quad) = quad {
                // Each ray's polynomial from the quadric: no samples.
                if self.caster.quadric_blocks && self.caster.attr_tape.is_none() {
                    for chunk in fresh.chunks(QUAD_BLOCK) {
                        sure &= self.quadric_block(&quad, tag, k, e, chunk);
                    }
                } else {
                    for &(i, lo, hi) in &fresh {
                        let p = RayPoly::of_quadric(tag, lo, hi, &quad, &self.sc.rays[i], k);
                        sure &= match self.take_fresh(&p, e, i, lo, hi) {
                            Some(settled) => settled,
                            None => self.take_poly(p, e, i, lo, hi),
                        };
                    }
                }
            } else {
                match if affine { self.plane(e, p0) } else { None } {
                    Some(pl) => {
                        self.plane_hits(&pl, &mut fresh);
                        self.plane_values(&pl, &fresh);
                    }
                    None => self.sample(e, &fresh, 2),
                }
                let vals = std::mem::take(&mut self.sc.vals);
                for (j, &(i, lo, hi)) in fresh.iter().enumerate() {
                    let v = [vals[3 * j], vals[3 * j + 1], vals[3 * j + 2]];
                    let q = v.map(|f| RayPoly::map(f, k));
                    let p = RayPoly::fit(tag, lo, hi, q, k);
                    sure &= match self.take_fresh(&p, e, i, lo, hi) {
                        Some(settled) => settled,
                        None => self.take_poly(p, e, i, lo, hi),
                    };
                }
                self.sc.vals = vals;
            }
        }
        self.sc.fresh = fresh;
        self.finish(e);
        self.prune_rays();
        self.sc.leaf_rays = rays;
        sure
    }

    /// Ray `i`'s fresh polynomial `p` over its part `[lo, hi]` of an exact
    /// slab on evaluator `e`.
    /// - Inside at `lo` is a direct hit there, where the field is defined
    ///   there ([`RayPoly::defined_at_start`]). Else the ray is unsure.
    /// - Values not finite leave the ray unsure (`false`).
    /// - Otherwise `p` is kept for the ray's later slabs, and
    ///   [`TileCtx::settle`] takes it.
    fn take_poly(&mut self, p: RayPoly, e: usize, i: usize, lo: f64, hi: f64) -> bool {
        if p.c >= 0.0 {
            if !p.defined_at_start() {
                return false;
            }
            self.sc.direct.push((i, lo, lo <= self.sc.rays[i].z0));
            return true;
        }
        if ![p.a, p.b, p.c, p.scale].iter().all(|v| v.is_finite()) {
            return false;
        }
        self.sc.polys[i] = p;
        self.settle(&p, e, i, lo, hi)
    }

    /// Ray `i`'s part `[lo, hi]` of an exact slab on evaluator `e`, by its
    /// polynomial `p` ([`TileCtx::exact`]).
    /// - A crossing is the hit where the polynomial's values
    ///   [`EXACT_BRACKET_PX`] footprints either side of it are both clear of
    ///   rounding.
    /// - The hit is recorded at once with the quadric's normal where `e` has
    ///   one ([`Evals::quadric`]) and no colour is due. Else it is recorded
    ///   as a direct hit, its normal by the gradient there.
    /// - No crossing puts the ray in [`Scratch::settled`] and sets its tail
    ///   as a sampled slab would.
    /// - The polynomial may have no crossing on the rest of the ray either.
    ///   The ray is then due for the whole-ray check of
    ///   [`ModelCaster::prune_after`], if the slabs left would likely cost
    ///   more.
    ///
    /// `false`: unsure (nothing recorded).
    ///
    /// [`Evals::quadric`]: crate::raycast::scratch::Evals::quadric
    /// [`Scratch::settled`]: crate::raycast::scratch::Scratch::settled
    /// [`ModelCaster::prune_after`]: crate::raycast::caster::ModelCaster::prune_after
    fn settle(&mut self, p: &RayPoly, e: usize, i: usize, lo: f64, hi: f64) -> bool {
        let settled = self.settle_by(p, e, i, lo, hi);
        self.stats.exact_rays += u64::from(settled);
        settled
    }

    /// Evaluator `e`'s plane ([`Evals::plane`]; its field affine), from the
    /// value and gradient at `p0` the first time.
    ///
    /// [`Evals::plane`]: crate::raycast::scratch::Evals::plane
    #[inline(never)]
    fn plane(&mut self, e: usize, p0: [f64; 3]) -> Option<[f64; 4]> {
        if let Some(p) = self.sc.evals[e].plane {
            return p;
        }
        let sc = &mut *self.sc;
        sc.set_points(1);
        [sc.xs[0], sc.ys[0], sc.zs[0]] = p0;
        sc.eval_grads(e, &self.caster.inputs);
        self.stats.grad_evals += 1;
        let g = sc.grads[0];
        let c = g.v - (g.dx * p0[0] + g.dy * p0[1] + g.dz * p0[2]);
        let p = [c, g.dx, g.dy, g.dz];
        let p = p.iter().all(|v| v.is_finite()).then_some(p);
        sc.evals[e].plane = Some(p);
        p
    }

    /// Evaluator `e`'s quadric ([`Evals::quadric`]): its field of degree 2,
    /// or a root gap. The first time, it comes from the values and
    /// gradients at `p0` and at `h` from it along each axis. A quadric's
    /// gradient is affine, so its differences give `A` exactly but for
    /// rounding. `None` where those are not finite, or where the values
    /// there differ from the quadric by more than `1e-9` of their scale.
    ///
    /// [`Evals::quadric`]: crate::raycast::scratch::Evals::quadric
    #[inline(never)]
    fn quadric(&mut self, e: usize, p0: [f64; 3], h: f64) -> Option<Quadric> {
        if let Some(q) = self.sc.evals[e].quadric {
            return q;
        }
        let k = self.sc.evals[e].exact.unwrap_or(0.0);
        let sc = &mut *self.sc;
        sc.set_points(4);
        for (j, p) in Quadric::fit_points(p0, h).into_iter().enumerate() {
            [sc.xs[j], sc.ys[j], sc.zs[j]] = p;
        }
        sc.eval_grads(e, &self.caster.inputs);
        self.stats.grad_evals += 4;
        // Values and gradients of q: the field's, or for a root gap `k`
        // those of f·(2k − f).
        let qs: [(f64, [f64; 3]); 4] = std::array::from_fn(|j| {
            let g = sc.grads[j];
            let grad = [g.dx, g.dy, g.dz];
            if k > 0.0 {
                let s = 2.0 * (k - g.v);
                (g.v * (2.0 * k - g.v), grad.map(|d| s * d))
            } else {
                (g.v, grad)
            }
        });
        let quad = Quadric::fit(p0, h, &qs);
        let Quadric { c, g, a, .. } = quad;
        let finite = qs
            .iter()
            .all(|(v, g)| v.is_finite() && g.iter().all(|d| d.is_finite()));
        // The values at the other points, against the quadric's.
        let agree = (1..4).all(|j| {
            let (v, _) = qs[j];
            let want = c + g[j - 1] * h + a[j - 1][j - 1] * h * h;
            let scale = c.abs().max(v.abs()).max(g[j - 1].abs() * h);
            (v - want).abs() <= 1e-9 * scale
        });
        let quad = (finite && agree).then_some(quad);
        sc.evals[e].quadric = Some(quad);
        quad
    }

    /// For an affine field `pl` ([`Evals::plane`]), records at once the hits
    /// of the rays of `rays` (ray, lo, hi) that cross it clearly in their
    /// slab. Clearly means outside at `lo` and inside at `hi`, each by more
    /// than rounding. The hit is at the crossing, with the plane's normal,
    /// found without evaluating the tape. Sampling and [`TileCtx::polish`]
    /// find the same hit and normal there. The other rays are left in
    /// `rays`. For a model with attribute colours that is all of them:
    /// their hits are recorded with their colours.
    ///
    /// [`Evals::plane`]: crate::raycast::scratch::Evals::plane
    #[inline(never)]
    fn plane_hits(&mut self, pl: &[f64; 4], rays: &mut Vec<(usize, f64, f64)>) {
        let g = [pl[1], pl[2], pl[3]];
        let Some(normal) = unit([-g[0], -g[1], -g[2]]) else {
            return;
        };
        if self.caster.attr_tape.is_some() {
            return;
        }
        let mut kept = 0;
        for j in 0..rays.len() {
            let (i, lo, hi) = rays[j];
            let r = self.sc.rays[i];
            let a = pl[0] + dot(g, r.origin);
            let b = dot(g, r.dz);
            let (f0, f1) = (a + b * lo, a + b * hi);
            let tol = 1e-9 * f0.abs().max(f1.abs());
            if f0 < -tol && f1 > tol {
                let z = (lo + (hi - lo) * (-f0 / (f1 - f0))).clamp(lo, hi);
                let h = Hit {
                    t: z / r.c,
                    position: r.at_depth(z),
                    normal,
                    color: None,
                };
                self.set_hit(i, h);
                self.stats.exact_rays += 1;
            } else {
                rays[kept] = rays[j];
                kept += 1;
            }
        }
        rays.truncate(kept);
    }

    /// What [`TileCtx::sample`] with `n = 2` gives `rays`, for an affine
    /// field `pl` ([`Evals::plane`]): its values at each ray's `lo`, middle
    /// and `hi`, in `vals`, computed without evaluating the tape.
    ///
    /// [`Evals::plane`]: crate::raycast::scratch::Evals::plane
    #[inline(never)]
    fn plane_values(&mut self, pl: &[f64; 4], rays: &[(usize, f64, f64)]) {
        let sc = &mut *self.sc;
        if sc.vals.len() < 3 * rays.len() {
            sc.vals.resize(3 * rays.len(), 0.0);
        }
        let g = [pl[1], pl[2], pl[3]];
        for (&(i, lo, hi), v) in rays.iter().zip(sc.vals.chunks_exact_mut(3)) {
            let r = &sc.rays[i];
            // Along the ray, f = a + b·z.
            let a = pl[0] + dot(g, r.origin);
            let b = dot(g, r.dz);
            v[0] = a + b * lo;
            v[1] = a + b * (0.5 * (lo + hi));
            v[2] = a + b * hi;
        }
    }

    /// Whether the crossing at depth `z` of the ray polynomial `p`, over the
    /// slab `[lo, hi]`, is clear. Clear means outside [`EXACT_BRACKET_PX`]
    /// footprints before it and inside as many after, within the slab, each
    /// by more than rounding.
    #[inline]
    fn clear_at(&self, p: &RayPoly, z: f64, lo: f64, hi: f64) -> bool {
        let d = EXACT_BRACKET_PX * self.rm.pixel_footprint(z);
        let (a, b) = ((z - d).max(lo), (z + d).min(hi));
        let (fa, fb) = (p.at(a), p.at(b));
        let tol = p.tol(a, b);
        fa < -tol && fb > tol
    }

    /// [`TileCtx::take_poly`] for a ray's fresh polynomial `p` over its
    /// slab `[lo, hi]`, in the common case: `p` finite and clearly outside
    /// at `lo`. It does not re-derive what that case gives. `p` was fitted
    /// over this very slab, so the slab's fractions are `0` and `1`
    /// exactly. The value at `lo` is `p.c`, and the rounding allowance is
    /// `1e-9` of `p`'s scale ([`RayPoly::first_root`] finds the same). The
    /// outcome is the same, bit for bit. `None` where the case is not this
    /// one, for `take_poly` to handle.
    #[inline]
    fn take_fresh(&mut self, p: &RayPoly, e: usize, i: usize, lo: f64, hi: f64) -> Option<bool> {
        if !p.fresh_outside() {
            return None;
        }
        self.sc.polys[i] = *p;
        let root = p.root_from(0.0, 1.0, p.c, 1e-9 * p.scale, lo, hi);
        let settled = self.settle_root(p, root, e, i, lo, hi);
        self.stats.exact_rays += u64::from(settled);
        Some(settled)
    }

    /// [`TileCtx::exact`]'s fresh rays `rays` (ray, lo, hi; at most
    /// [`QUAD_BLOCK`]) on evaluator `e`, whose quadric `quad` is known, for
    /// a model with no colours ([`ModelCaster::quadric_blocks`]). It does
    /// what [`RayPoly::of_quadric`] and [`TileCtx::take_poly`] do for each.
    /// - The common case is a clear crossing in the slab, recorded with the
    ///   quadric's normal. It is worked out for all rays at once, in one
    ///   pass over arrays that vectorises, with the same values bit for bit.
    /// - Every other ray is taken as before ([`TileCtx::take_fresh`] or
    ///   `take_poly`), in the rays' order.
    ///
    /// Returns whether every ray was settled.
    ///
    /// [`ModelCaster::quadric_blocks`]: crate::raycast::caster::ModelCaster::quadric_blocks
    // Long on purpose: its passes share a dozen stack arrays of `QUAD_BLOCK` lanes and
    // vectorise over them. Split, each step would take them all.
    // Kept whole; no split was measured.
    #[inline(never)]
    fn quadric_block(
        &mut self,
        quad: &Quadric,
        tag: u64,
        k: f64,
        e: usize,
        rays: &[(usize, f64, f64)],
    ) -> bool {
        const B: usize = QUAD_BLOCK;
        let n = rays.len();
        assert!(n <= B, "quadric_block: too many rays");
        // The rays, as arrays.
        let mut o = [[0.0f64; B]; 3];
        let mut dz = [[0.0f64; B]; 3];
        let (mut rc, mut lo, mut hi) = ([1.0f64; B], [0.0f64; B], [0.0f64; B]);
        for (j, &(i, l, h)) in rays.iter().enumerate() {
            let r = &self.sc.rays[i];
            for a in 0..3 {
                o[a][j] = r.origin[a];
                dz[a][j] = r.dz[a];
            }
            (rc[j], lo[j], hi[j]) = (r.c, l, h);
        }
        let mut pa = [0.0f64; B];
        let mut pb = [0.0f64; B];
        let mut pc = [0.0f64; B];
        let mut ps = [0.0f64; B];
        let mut zs = [0.0f64; B];
        let mut pos = [[0.0f64; B]; 3];
        let mut nrm = [[0.0f64; B]; 3];
        let mut ok = [false; B];
        // Whole vectors (the lanes past `n` hold harmless zeros).
        for j in 0..n.next_multiple_of(4).min(B) {
            // `RayPoly::of_quadric`.
            let d = [dz[0][j], dz[1][j], dz[2][j]];
            let oj = [o[0][j], o[1][j], o[2][j]];
            let (l, h) = (lo[j], hi[j]);
            let wd = h - l;
            let [a, b, c, scale] = RayPoly::coefficients(l, h, quad.along_ray(oj, d));
            (pa[j], pb[j], pc[j], ps[j]) = (a, b, c, scale);
            let p = RayPoly {
                tag,
                lo: l,
                w: wd,
                a,
                b,
                c,
                scale,
                k,
            };
            // `take_fresh`'s case, then `RayPoly::root_from`'s crossing and
            // `TileCtx::clear_at`.
            let fresh = p.fresh_outside();
            let first = p.first_s(0.0);
            let mut z = l + wd * first;
            // (`f64::clamp`, which would panic on the idle lanes' NaNs.)
            if z < l {
                z = l;
            }
            if z > h {
                z = h;
            }
            let clear = self.clear_at(&p, z, l, h);
            // `Quadric::hit`: the position and the normal, `unit`'s common
            // case.
            let at = [oj[0] + d[0] * z, oj[1] + d[1] * z, oj[2] + d[2] * z];
            let gr = quad.grad(at);
            let nn = [-gr[0], -gr[1], -gr[2]];
            let l2 = dot(nn, nn);
            let kk = 1.0 / l2.sqrt();
            for a in 0..3 {
                pos[a][j] = at[a];
                nrm[a][j] = nn[a] * kk;
            }
            zs[j] = z;
            ok[j] = fresh && first <= 1.0 && clear && NORMAL_LEN2.contains(&l2);
        }
        let mut sure = true;
        for (j, &(i, l, h)) in rays.iter().enumerate() {
            if ok[j] {
                // (A hit ray's polynomial is not kept: it is searched no
                // further.)
                let hit = Hit {
                    t: zs[j] / rc[j],
                    position: [pos[0][j], pos[1][j], pos[2][j]],
                    normal: [nrm[0][j], nrm[1][j], nrm[2][j]],
                    color: None,
                };
                self.set_hit(i, hit);
                self.stats.exact_rays += 1;
            } else {
                let p = RayPoly {
                    tag,
                    lo: l,
                    w: h - l,
                    a: pa[j],
                    b: pb[j],
                    c: pc[j],
                    scale: ps[j],
                    k,
                };
                sure &= match self.take_fresh(&p, e, i, l, h) {
                    Some(settled) => settled,
                    None => self.take_poly(p, e, i, l, h),
                };
            }
        }
        sure
    }

    /// [`TileCtx::settle`] without the count.
    fn settle_by(&mut self, p: &RayPoly, e: usize, i: usize, lo: f64, hi: f64) -> bool {
        self.settle_root(p, p.first_root(lo, hi), e, i, lo, hi)
    }

    /// [`TileCtx::settle_by`] with the first root of `p` (its
    /// [`RayPoly::first_root`]) found.
    #[inline]
    fn settle_root(
        &mut self,
        p: &RayPoly,
        root: Root,
        e: usize,
        i: usize,
        lo: f64,
        hi: f64,
    ) -> bool {
        match root {
            Root::At(z) => {
                if !self.clear_at(p, z, lo, hi) {
                    return false;
                }
                // The hit: its normal the quadric's where that is known
                // (and no colour is due), else by the gradient there (as a
                // direct hit's).
                let quad = self.sc.evals[e].quadric.as_ref().and_then(Option::as_ref);
                if let Some(quad) = quad.filter(|_| self.caster.attr_tape.is_none()) {
                    if let Some(h) = quad.hit(&self.sc.rays[i], z) {
                        self.set_hit(i, h);
                        return true;
                    }
                }
                self.sc.direct.push((i, z, false));
                true
            }
            Root::None => {
                let zm = 0.5 * (lo + hi);
                let (check, odds) = self.whole_ray_check();
                let sc = &mut *self.sc;
                sc.tails[i] = Tail {
                    valid: true,
                    pending: false,
                    ev: e as u32,
                    z_prev: zm,
                    f_prev: p.field(p.at(zm)),
                    z_last: hi,
                };
                sc.settled.push(i);
                let z1 = sc.rays[i].z1;
                if self.caster.prune_after > 0 && hi < z1 && hi > lo {
                    // Slabs like this one left, each a visit of about a
                    // sampled ray's cost, against one interval evaluation
                    // of the tile's tape, weighed by the checks' success.
                    let slabs = (z1 - hi) / (hi - lo);
                    let visit = 3.0 * sc.evals[e].tape.len() as f64;
                    if slabs * visit * odds > check && p.first_root(hi, z1) == Root::None {
                        sc.prune.push((i, hi));
                    }
                }
                true
            }
            Root::Unsure => false,
        }
    }
}
