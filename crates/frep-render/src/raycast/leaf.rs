//! Leaf sampling: a leaf's rays sampled in one batch across its slab and
//! their first sign change bracketed; the whole-ray checks of rays along
//! walls.

use super::frustum::Rect;
use super::rays::clip_box;
use super::refine::Bracket;
use super::search::Tail;
use super::tile::TileCtx;
use super::INTERVAL_COST;

/// How a leaf's sample points can be evaluated (see [`Scratch::sampling`]).
///
/// [`Scratch::sampling`]: crate::raycast::scratch::Scratch::sampling
#[derive(Clone, Copy, PartialEq, PartialOrd)]
pub(super) enum Sampling {
    /// Point by point.
    Points,
    /// As lines along the view's axis ([`BatchEval::eval_lines`]).
    ///
    /// [`BatchEval::eval_lines`]: frep_core::eval::batch::BatchEval::eval_lines
    Lines,
    /// As lines with the same depths on every ray.
    Grid,
}

/// NaN (outside) as −∞, for comparing samples.
#[inline]
fn ord(v: f64) -> f64 {
    if v.is_nan() {
        f64::NEG_INFINITY
    } else {
        v
    }
}

/// Whether `c` is a local maximum between `left` and `right` (all through
/// [`ord`]), not −∞.
#[inline]
fn local_max(left: f64, c: f64, right: f64) -> bool {
    c > f64::NEG_INFINITY && c >= left && c >= right && (c > left || c > right)
}

impl<'a> TileCtx<'a> {
    /// The cost of a whole-ray check (one interval evaluation of the
    /// tile's tape, by tape lengths; see [`ModelCaster::prune_after`]), and
    /// the chance that one succeeds, from this thread's checks so far.
    ///
    /// [`ModelCaster::prune_after`]: crate::raycast::caster::ModelCaster::prune_after
    pub(super) fn whole_ray_check(&self) -> (f64, f64) {
        let sc = &*self.sc;
        let cost = INTERVAL_COST * sc.evals[self.top.unwrap_or(0)].tape.len() as f64;
        let odds = (sc.prune_hit as f64 + 1.0) / (sc.prune_tried as f64 + 2.0);
        (cost, odds)
    }

    /// The live unresolved rays of `rect` that reach the slab `[za, zb]`
    /// (a resolved or dead ray's range is `[+∞, −∞]`), as (ray, its part of
    /// the slab). Pending segments in front of the slab, not followed by it,
    /// are searched first (with `all_tails`, those it follows on from too),
    /// and the rays they resolve left out. The buffer is
    /// [`Scratch::leaf_rays`]'s: the caller puts it back.
    ///
    /// [`Scratch::leaf_rays`]: crate::raycast::scratch::Scratch::leaf_rays
    pub(super) fn gather(
        &mut self,
        rect: Rect,
        za: f64,
        zb: f64,
        all_tails: bool,
    ) -> Vec<(usize, f64, f64)> {
        let mut rays = std::mem::take(&mut self.sc.leaf_rays);
        rays.clear();
        for y in rect.y0..rect.y1 {
            let row = (y * self.tw) as usize;
            for i in row + rect.x0 as usize..row + rect.x1 as usize {
                let sc = &mut *self.sc;
                let (z0, z1) = (sc.z0s[i], sc.z1s[i]);
                if z1 < za || z0 > zb {
                    continue;
                }
                let t = &mut sc.tails[i];
                if t.pending && (all_tails || t.z_last != za.max(z0)) {
                    t.pending = false;
                    let t = *t;
                    sc.tail_list.push((i, t));
                }
                rays.push((i, za.max(z0), zb.min(z1)));
            }
        }
        if !self.sc.tail_list.is_empty() {
            self.search_tails();
            let sc = &*self.sc;
            rays.retain(|&(i, _, _)| sc.z0s[i] <= zb);
        }
        rays
    }

    /// Samples each of `rays` (ray, lo, hi) at the `n + 1` depths
    /// `lo + (hi − lo)·k/n`, all in one batch on evaluator `e` (as lines
    /// where the view allows): ray `j`'s values are `vals[j·(n+1)..]`, its
    /// fractions `fracs`.
    pub(super) fn sample(&mut self, e: usize, rays: &[(usize, f64, f64)], n: usize) {
        let sc = &mut *self.sc;
        sc.fracs.clear();
        sc.fracs.extend((0..n + 1).map(|k| k as f64 / n as f64));
        let total = rays.len() * (n + 1);
        sc.set_points(total);
        {
            let fr = &sc.fracs[..];
            let xs = sc.xs[..total].chunks_exact_mut(n + 1);
            let ys = sc.ys[..total].chunks_exact_mut(n + 1);
            let zs = sc.zs[..total].chunks_exact_mut(n + 1);
            for (((&(i, lo, hi), xs), ys), zs) in rays.iter().zip(xs).zip(ys).zip(zs) {
                let r = &sc.rays[i];
                let d = hi - lo;
                let m = fr.len();
                let (xs, ys, zs) = (&mut xs[..m], &mut ys[..m], &mut zs[..m]);
                let ([ox, oy, oz], [dx, dy, dz]) = (r.origin, r.dz);
                for k in 0..m {
                    let t = lo + d * fr[k];
                    xs[k] = ox + dx * t;
                    ys[k] = oy + dy * t;
                    zs[k] = oz + dz * t;
                }
            }
        }
        self.stats.point_evals += total as u64;
        match self.lines {
            Some((axis, grid)) => {
                debug_assert!(
                    sc.sampling(axis, rays, n + 1)
                        >= if grid {
                            Sampling::Grid
                        } else {
                            Sampling::Lines
                        },
                    "leaf points on lines"
                );
                self.stats.line_points += total as u64;
                sc.eval_points_on(e, Some((axis, n + 1, grid)), &self.caster.inputs);
            }
            None => sc.eval_points(e, &self.caster.inputs),
        }
    }

    // Long on purpose: one pass over the leaf's rays, hot per ray. Each ray's steps (pending
    // rise, first inside sample, local maximum, pruning) read and write the same scratch and
    // tail; kept together, as the algorithm reads.
    // Kept whole; no split was measured.
    pub(super) fn leaf(&mut self, e: usize, rect: Rect, za: f64, zb: f64) {
        let step = self.caster.step_px.max(1e-3) * self.footprint(za).max(1e-300);
        let n = (((zb - za) / step).ceil() as usize).clamp(1, 4096);
        let min_len = self.min_len(step, za);
        let leaf_rays = self.gather(rect, za, zb, false);
        if leaf_rays.is_empty() {
            self.sc.leaf_rays = leaf_rays;
            return;
        }
        // Sample every ray at n + 1 depths, all rays in one batch.
        self.sample(e, &leaf_rays, n);
        let sc = &mut *self.sc;
        let vals = std::mem::take(&mut sc.vals);
        let prune_after = self.caster.prune_after;
        // Relative costs of sampling a ray over one more leaf slab and of
        // one interval evaluation of the tile's tape, by tape lengths.
        let slab = self.caster.leaf_depth_px * self.footprint(za).max(1e-300);
        let sample_cost = (n + 1) as f64 * self.sc.evals[e].tape.len() as f64;
        // Weighed by the chance that a check succeeds, so far.
        let (check_cost, odds) = self.whole_ray_check();
        let sample_cost = sample_cost * odds;
        let mut resolve_first = std::mem::take(&mut self.sc.resolve_first);
        for (j, &(i, lo, hi)) in leaf_rays.iter().enumerate() {
            let v = &vals[j * (n + 1)..(j + 1) * (n + 1)];
            let sc = &mut *self.sc;
            let fr = &sc.fracs;
            let z = |k: usize| lo + (hi - lo) * fr[k];
            let t = sc.tails[i];
            let contiguous = t.valid && t.z_last == lo;
            // A rise pending at the end of the previous slab: it goes on
            // (no thin feature can hide at that maximum) or it is searched.
            if t.pending {
                if contiguous && n >= 1 && ord(v[1]) > ord(v[0]) && v[0] < 0.0 {
                    sc.tails[i].pending = false;
                } else {
                    // Searched below, before this slab's result is used.
                    resolve_first.push((i, t));
                    sc.tails[i].pending = false;
                }
            }
            match v.iter().position(|&f| f >= 0.0) {
                Some(0) => sc.direct.push((i, lo, lo <= sc.rays[i].z0)),
                Some(k) => sc.brackets.push(Bracket {
                    ray: i,
                    lo: z(k - 1),
                    hi: z(k),
                    f_lo: v[k - 1],
                    f_hi: v[k],
                    kept: 0,
                }),
                None => {
                    // No sample inside: a feature thinner than a step can
                    // only hide around a local maximum of the samples (NaN
                    // counting as −∞); search there. The left neighbour of
                    // the first sample is the previous slab's, when it
                    // joins on; a rise to the last sample is left pending.
                    let left0 = if contiguous {
                        ord(t.f_prev)
                    } else {
                        f64::NEG_INFINITY
                    };
                    let mut pending = false;
                    let (mut left, mut c) = (left0, ord(v[0]));
                    #[allow(clippy::needless_range_loop)]
                    for k in 0..n + 1 {
                        let right = if k < n {
                            ord(v[k + 1])
                        } else {
                            f64::NEG_INFINITY
                        };
                        if local_max(left, c, right) {
                            if k == n && n > 0 && hi < sc.rays[i].z1 {
                                pending = true;
                            } else {
                                let a = k.saturating_sub(1);
                                sc.searches
                                    .push((i, z(a), z((k + 1).min(n)), v[a], min_len));
                            }
                            break;
                        }
                        (left, c) = (c, right);
                    }
                    sc.tails[i] = Tail {
                        valid: true,
                        pending: false,
                        ev: e as u32,
                        z_prev: z(n.saturating_sub(1)),
                        f_prev: v[n.saturating_sub(1)],
                        z_last: hi,
                    };
                    // Set after any search of the previous tail below.
                    if pending {
                        sc.tails[i].pending = true;
                    }
                    if prune_after > 0 {
                        let m = &mut sc.misses[i];
                        m.0 = m.0.saturating_add(1);
                        if u32::from(m.0) >= prune_after.saturating_mul(1 << m.1.min(12)) {
                            *m = (0, m.1.saturating_add(1));
                            // From the pending segment on, if any.
                            let from = if pending { z(n.saturating_sub(1)) } else { hi };
                            // Worth it where the slabs left could cost more
                            // samples than the check.
                            let slabs = (sc.rays[i].z1 - from) / slab;
                            if slabs * sample_cost > check_cost {
                                sc.prune.push((i, from));
                            }
                        }
                    }
                }
            }
        }
        self.sc.vals = vals;
        // Pending segments of the previous slabs come first: a hit there
        // replaces anything this slab found behind it.
        let resolve = !resolve_first.is_empty();
        self.sc.tail_list.append(&mut resolve_first);
        self.sc.resolve_first = resolve_first;
        if resolve {
            self.search_tails();
            let sc = &mut *self.sc;
            let z0s = &sc.z0s;
            let open = |i: usize| z0s[i] != f64::INFINITY;
            sc.brackets.retain(|b| open(b.ray));
            sc.direct.retain(|d| open(d.0));
            sc.searches.retain(|s| open(s.0));
        }
        self.run_searches(e);
        self.finish(e);
        self.prune_rays();
        self.sc.leaf_rays = leaf_rays;
    }

    /// Checks the rays due (see [`ModelCaster::prune_after`]). Each gets one
    /// interval evaluation of the tile's tape over the rest of its depth
    /// range, the box of that segment. A ray that is outside there is a
    /// miss, searched no further, its pending segment included.
    ///
    /// [`ModelCaster::prune_after`]: crate::raycast::caster::ModelCaster::prune_after
    pub(super) fn prune_rays(&mut self) {
        let mut prune = std::mem::take(&mut self.sc.prune);
        for &(i, from) in &prune {
            let r = self.sc.rays[i];
            if self.sc.resolved(i) || from >= r.z1 {
                continue;
            }
            let Some(b) = clip_box(&r.segment_box(from, r.z1), &self.caster.bounds) else {
                continue;
            };
            self.sc.prune_tried = self.sc.prune_tried.saturating_add(1);
            if self.eval_box(self.top.unwrap_or(0), &b).is_outside() {
                self.sc.prune_hit = self.sc.prune_hit.saturating_add(1);
                self.sc.resolve(i);
                self.sc.tails[i].pending = false;
            }
        }
        prune.clear();
        self.sc.prune = prune;
    }
}
