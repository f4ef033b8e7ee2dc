//! Frustum subdivision: the boxes of a tile's frustum evaluated with
//! intervals, the tape shortened per box, boxes split front to back down to
//! leaves, a leaf's slab narrowed.

use frep_core::eval::interval::{Choice, Interval};
use frep_core::simplify::SimplifyMode;

use crate::camera::Aabb;

use super::rays::{clip_box, Corners};
use super::scratch::{choices_hash, tape_hash, Evals, NODE_BYTES};
use super::tile::TileCtx;
use super::LEAF;

/// A pixel rectangle `[x0, x1) × [y0, y1)` in tile-local pixels.
#[derive(Clone, Copy)]
pub(super) struct Rect {
    pub(super) x0: u32,
    pub(super) y0: u32,
    pub(super) x1: u32,
    pub(super) y1: u32,
}

impl Rect {
    fn size(&self) -> u32 {
        (self.x1 - self.x0).max(self.y1 - self.y0)
    }

    fn quadrants(&self) -> impl Iterator<Item = Rect> {
        let xm = self.x0 + (self.x1 - self.x0).div_ceil(2);
        let ym = self.y0 + (self.y1 - self.y0).div_ceil(2);
        let r = *self;
        [
            (r.x0, r.y0, xm, ym),
            (xm, r.y0, r.x1, ym),
            (r.x0, ym, xm, r.y1),
            (xm, ym, r.x1, r.y1),
        ]
        .into_iter()
        .filter(|q| q.0 < q.2 && q.1 < q.3)
        .map(|(x0, y0, x1, y1)| Rect { x0, y0, x1, y1 })
    }
}

pub(super) fn iv(lo: f64, hi: f64) -> Interval {
    Interval::new(lo, hi)
}

impl<'a> TileCtx<'a> {
    /// The depth range of the unresolved live rays of `rect` within
    /// `[za, zb]`, if any.
    fn active_range(&self, rect: Rect, za: f64, zb: f64) -> Option<(f64, f64)> {
        // Branch-free (and so vectorised, four rays at a time): a ray
        // outside `[za, zb]` (resolved and dead ones included: `[+∞, −∞]`)
        // contributes `+∞` to the minimum and `−∞` to the maximum. Depths
        // are never NaN.
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut l, mut h) = ([f64::INFINITY; 4], [f64::NEG_INFINITY; 4]);
        for y in rect.y0..rect.y1 {
            let row = (y * self.tw) as usize;
            let (a, b) = (row + rect.x0 as usize, row + rect.x1 as usize);
            let (z0s, z1s) = (&self.sc.z0s[a..b], &self.sc.z1s[a..b]);
            let mut c0 = z0s.chunks_exact(4);
            let mut c1 = z1s.chunks_exact(4);
            for (c0, c1) in (&mut c0).zip(&mut c1) {
                for k in 0..4 {
                    let (z0, z1) = (c0[k], c1[k]);
                    let inside = z1 >= za && z0 <= zb;
                    let a = if z0 > za { z0 } else { za };
                    let b = if z1 < zb { z1 } else { zb };
                    let a = if inside { a } else { f64::INFINITY };
                    let b = if inside { b } else { f64::NEG_INFINITY };
                    l[k] = if a < l[k] { a } else { l[k] };
                    h[k] = if b > h[k] { b } else { h[k] };
                }
            }
            for (&z0, &z1) in c0.remainder().iter().zip(c1.remainder()) {
                if z1 >= za && z0 <= zb {
                    lo = lo.min(z0.max(za));
                    hi = hi.max(z1.min(zb));
                }
            }
        }
        for k in 0..4 {
            lo = lo.min(l[k]);
            hi = hi.max(h[k]);
        }
        (lo <= hi).then_some((lo, hi))
    }

    /// Whether a live ray of `rect` is unresolved.
    fn any_unresolved(&self, rect: Rect) -> bool {
        (rect.y0..rect.y1).any(|y| {
            let row = (y * self.tw) as usize;
            let z0s = &self.sc.z0s[row + rect.x0 as usize..row + rect.x1 as usize];
            z0s.iter().any(|&z0| z0 != f64::INFINITY)
        })
    }

    /// The evaluator of the tape `e` shortened for the box it was last
    /// evaluated over (`e` itself when that does not shorten it).
    fn shorten(&mut self, e: usize) -> usize {
        let sc = &mut *self.sc;
        let ev = &sc.evals[e];
        if ev.tape.len() <= 4 || !ev.mask.can_shorten() {
            return e;
        }
        let mut choices = std::mem::take(&mut sc.choices);
        ev.mask.key(&ev.interval, &mut choices);
        let h = choices_hash(e, &choices);
        if let Some(bucket) = sc.children.get(&h) {
            for (p, key, child) in bucket {
                if *p as usize == e && key[..] == choices[..] {
                    let child = *child as usize;
                    sc.choices = choices;
                    return child;
                }
            }
        }
        let key: Box<[Choice]> = choices[..].into();
        ev.mask.expand(&key, &mut choices);
        let (t, st) = sc
            .simplifier
            .simplify(&ev.tape, &choices, SimplifyMode::Sign);
        sc.choices = choices;
        let child = if st.after < st.before {
            let th = tape_hash(&t);
            let same = sc
                .by_tape
                .get(&th)
                .and_then(|b| b.iter().copied().find(|&c| sc.evals[c as usize].tape == t));
            match same {
                Some(c) => c as usize,
                None => {
                    self.stats.simplified += 1;
                    sc.bytes += t.len() * NODE_BYTES;
                    sc.evals.push(Evals::new(t));
                    let c = sc.evals.len() - 1;
                    sc.by_tape.entry(th).or_default().push(c as u32);
                    c
                }
            }
        } else {
            e
        };
        sc.children
            .entry(h)
            .or_default()
            .push((e as u32, key, child as u32));
        child
    }

    /// The corner rays of `rect`'s frustum, for [`Corners::aabb`].
    pub(super) fn corners(&self, rect: Rect) -> Corners {
        let (x0, y0) = (self.tile.x0, self.tile.y0);
        Corners::of(
            &self.rm,
            x0 + rect.x0,
            y0 + rect.y0,
            x0 + rect.x1,
            y0 + rect.y1,
        )
    }

    /// The node of `rect`'s frustum between depths `za` and `zb`, on
    /// evaluator `e`.
    /// - `held`: the [`Scratch::epoch`] at which `rect` was last seen to
    ///   hold an unresolved ray (by its parent, for a depth half). While no
    ///   ray was resolved since, a view whose rays all share one depth range
    ///   needs no pass over the rays.
    /// - `exact`: whether [`TileCtx::exact`] may settle the node. It may not
    ///   below a node where it left rays unsure.
    ///
    /// [`Scratch::epoch`]: crate::raycast::scratch::Scratch::epoch
    #[allow(clippy::too_many_arguments)]
    pub(super) fn node(
        &mut self,
        e: usize,
        rect: Rect,
        k: &Corners,
        za: f64,
        zb: f64,
        held: Option<u64>,
        exact: bool,
    ) {
        if self.caster.cancelled() {
            return;
        }
        let range = match self.uniform {
            Some((z0, z1)) => {
                // Every live ray's range is `[z0, z1]`: the range is the
                // slab's part within it, if an unresolved ray is left.
                let (lo, hi) = (za.max(z0), zb.min(z1));
                let held = held == Some(self.sc.epoch);
                let r = (lo <= hi && (held || self.any_unresolved(rect))).then_some((lo, hi));
                debug_assert_eq!(r, self.active_range(rect, za, zb), "uniform depth range");
                r
            }
            None => self.active_range(rect, za, zb),
        };
        let Some((za, zb)) = range else {
            return;
        };
        let held = Some(self.sc.epoch);
        let Some(b) = clip_box(&k.aabb(za, zb), &self.caster.bounds) else {
            return;
        };
        let v = self.eval_box(e, &b);
        if v.is_outside() {
            return;
        }
        if v.is_positive() {
            self.fill(e, rect, za, zb);
            return;
        }
        // Shorten the tape for this box when that helps (the first box
        // shortened is the tile's: kept for checks of whole rays).
        let e = self.shorten(e);
        self.top.get_or_insert(e);
        if !(exact && self.caster.exact && self.sc.evals[e].exact.is_some()) {
            self.split(e, rect, k, za, zb, held, exact);
            return;
        }
        if rect.size() > LEAF && !self.sc.evals[e].affine {
            // Rectangles of leaf size over the whole slab. The interval
            // evaluations of the quadrants drop the rays far from the
            // surface (beside a wall) before any is sampled. A plane's rays
            // take no samples: all of the rectangle at once.
            for q in rect.quadrants() {
                let kq = self.corners(q);
                self.node(e, q, &kq, za, zb, None, exact);
            }
            return;
        }
        if self.exact(e, rect, za, zb) {
            return;
        }
        // Some rays were left unsure: a crossing that did not check out, or
        // a graze. Those alone are searched the usual way. The others are
        // set aside meanwhile, as their slab has no crossing.
        let mut hidden = std::mem::take(&mut self.sc.hidden);
        hidden.clear();
        let sc = &mut *self.sc;
        for &i in &sc.settled {
            hidden.push((i, sc.z0s[i], sc.z1s[i]));
            sc.z0s[i] = f64::INFINITY;
            sc.z1s[i] = f64::NEG_INFINITY;
        }
        sc.epoch += 1;
        self.split(e, rect, k, za, zb, None, false);
        for &(i, z0, z1) in &hidden {
            (self.sc.z0s[i], self.sc.z1s[i]) = (z0, z1);
        }
        self.sc.epoch += 1;
        self.sc.hidden = hidden;
    }

    /// The rest of [`TileCtx::node`] (its box neither outside nor inside
    /// throughout, `e` shortened for it): split it, or sample it as a leaf.
    #[allow(clippy::too_many_arguments)]
    fn split(
        &mut self,
        e: usize,
        rect: Rect,
        k: &Corners,
        za: f64,
        zb: f64,
        held: Option<u64>,
        exact: bool,
    ) {
        let s = rect.size();
        let cell = s as f64 * self.footprint(za).max(1e-300);
        if zb - za > 2.0 * cell {
            // Interval bisection along the frustum.
            let zm = 0.5 * (za + zb);
            self.node(e, rect, k, za, zm, held, exact);
            self.node(e, rect, k, zm, zb, held, exact);
        } else if s > LEAF {
            let zm = 0.5 * (za + zb);
            for q in rect.quadrants() {
                let kq = self.corners(q);
                self.node(e, q, &kq, za, zm, None, exact);
                self.node(e, q, &kq, zm, zb, None, exact);
            }
        } else if zb - za > self.caster.leaf_depth_px * self.footprint(za) {
            // Thin the leaf's slab further: interval evaluations on short
            // tapes are cheaper than sampling every ray of the leaf.
            let zm = 0.5 * (za + zb);
            self.node(e, rect, k, za, zm, held, exact);
            self.node(e, rect, k, zm, zb, held, exact);
        } else if let Some((za, zb)) = self.narrow(e, rect, k, za, zb) {
            self.leaf(e, rect, za, zb);
        }
    }

    /// The field of evaluator `e` over box `b` (counted).
    pub(super) fn eval_box(&mut self, e: usize, b: &Aabb) -> Interval {
        self.stats.interval_evals += 1;
        self.sc.evals[e].interval.eval(
            iv(b.min[0], b.max[0]),
            iv(b.min[1], b.max[1]),
            iv(b.min[2], b.max[2]),
            &self.caster.inputs,
        )
    }

    /// The part of a leaf's slab `[za, zb]` that may hold the surface.
    /// 1. The slab is cut into sub-slabs about [`ModelCaster::narrow_px`]
    ///    pixel footprints deep, each evaluated over the leaf's frustum.
    /// 2. The outside ones in front of the first that is not, and behind
    ///    the last, are dropped: nothing can cross there.
    /// 3. A sub-slab inside throughout ends the search. The span ends where
    ///    it starts, since the sub-slab's box holds its near face and the
    ///    last sample of every ray is inside.
    /// 4. It ends at `zb` instead where a ray of `rect` enters the model box
    ///    behind that sub-slab. That ray's segment must be sampled.
    ///
    /// `None`: all outside.
    ///
    /// [`ModelCaster::narrow_px`]: crate::raycast::caster::ModelCaster::narrow_px
    fn narrow(
        &mut self,
        e: usize,
        rect: Rect,
        k: &Corners,
        za: f64,
        zb: f64,
    ) -> Option<(f64, f64)> {
        let q = self.caster.narrow_px * self.footprint(za);
        if q.is_nan() || q <= 0.0 {
            return Some((za, zb));
        }
        let m = (((zb - za) / q).round() as usize).min(16);
        if m < 2 {
            return Some((za, zb));
        }
        let d = (zb - za) / m as f64;
        let at = |j: usize| if j == m { zb } else { za + d * j as f64 };
        let (mut first, mut end) = (None, zb);
        for j in 0..m {
            let Some(b) = clip_box(&k.aabb(at(j), at(j + 1)), &self.caster.bounds) else {
                continue;
            };
            let v = self.eval_box(e, &b);
            if v.is_outside() {
                continue;
            }
            first.get_or_insert(j);
            end = at(j + 1);
            if v.is_positive() {
                // Every ray through this sub-slab is inside where it
                // enters it: nothing behind that is needed, unless a ray
                // enters the model box only behind that depth.
                end = at(j);
                if self.enters_after(rect, end, zb) {
                    end = zb;
                }
                break;
            }
        }
        first.map(|f| (at(f), end))
    }

    /// Whether an unresolved live ray of `rect` starts (enters the model
    /// box) in `(z, zb]`.
    fn enters_after(&self, rect: Rect, z: f64, zb: f64) -> bool {
        (rect.y0..rect.y1).any(|y| {
            let row = (y * self.tw) as usize;
            let z0s = &self.sc.z0s[row + rect.x0 as usize..row + rect.x1 as usize];
            z0s.iter().any(|&z0| z0 > z && z0 <= zb)
        })
    }

    /// The box inside the solid throughout: rays still searching hit it
    /// where they enter it (after any feature pending in front of it).
    pub(super) fn fill(&mut self, e: usize, rect: Rect, za: f64, zb: f64) {
        // Pending rises not joined by this box are searched first; a rise
        // that runs into it goes on (the field is inside right after).
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let i = (y * self.tw + x) as usize;
                let r = self.sc.rays[i];
                let t = self.sc.tails[i];
                if !t.pending || !r.live || self.sc.resolved(i) || r.z1 < za || r.z0 > zb {
                    continue;
                }
                self.sc.tails[i].pending = false;
                if t.z_last != za.max(r.z0) {
                    self.sc.tail_list.push((i, t));
                }
            }
        }
        self.search_tails();
        let mut hit_rays = std::mem::take(&mut self.sc.hit_rays);
        hit_rays.clear();
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let i = (y * self.tw + x) as usize;
                let r = self.sc.rays[i];
                if !r.live || self.sc.resolved(i) || r.z1 < za || r.z0 > zb {
                    continue;
                }
                let z = za.max(r.z0);
                let hit = self.make_hit(i, z, z <= r.z0);
                self.set_hit(i, hit);
                hit_rays.push(i);
            }
        }
        self.flush_normals(e);
        self.colors(&hit_rays);
        self.sc.hit_rays = hit_rays;
    }
}
