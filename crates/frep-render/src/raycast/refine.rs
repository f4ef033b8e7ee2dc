//! Refinement of bracketed crossings: the false-position polish, then
//! secant steps (Illinois rule).

use crate::image::Hit;

use super::normals::{len2, unit, NORMAL_LEN2};
use super::scratch::{move_all, Deferred};
use super::tile::TileCtx;
use super::{POLISH_PX, REFINE, REFINE_PX};

/// A bracketed crossing: `f(lo) < 0` (or NaN), `f(hi) >= 0`.
#[derive(Clone, Copy)]
pub(super) struct Bracket {
    pub(super) ray: usize,
    pub(super) lo: f64,
    pub(super) hi: f64,
    pub(super) f_lo: f64,
    pub(super) f_hi: f64,
    /// Which end the last refinement step kept (−1 lo, 1 hi, 0 none), for
    /// the Illinois rule.
    pub(super) kept: i8,
}

impl Bracket {
    /// Where the secant (false position) crosses zero, as a fraction of the
    /// bracket from `lo`, where the values allow one (finite, `f_lo < 0`,
    /// rising).
    fn secant(&self) -> Option<f64> {
        let (fl, fh) = (self.f_lo, self.f_hi);
        (fl.is_finite() && fh.is_finite() && fl < 0.0 && fh > fl).then(|| -fl / (fh - fl))
    }

    /// The next trial depth: the secant point kept away from the ends, or
    /// the midpoint where the values do not allow one.
    fn trial(&self) -> f64 {
        let w = self.hi - self.lo;
        match self.secant() {
            Some(s) => self.lo + w * s.clamp(1.0 / 16.0, 15.0 / 16.0),
            None => self.lo + 0.5 * w,
        }
    }
}

impl<'a> TileCtx<'a> {
    /// Resolves the rays of the buffered brackets and direct hits
    /// (evaluator `e`): they are searched no further, and their hits are
    /// refined and recorded at the end of the tile
    /// ([`TileCtx::flush_deferred`]).
    pub(super) fn finish(&mut self, e: usize) {
        let sc = &mut *self.sc;
        let rays = sc.brackets.iter().map(|b| b.ray);
        for i in rays.chain(sc.direct.iter().map(|d| d.0)) {
            sc.z0s[i] = f64::INFINITY;
            sc.z1s[i] = f64::NEG_INFINITY;
        }
        sc.epoch += 1;
        if sc.brackets.is_empty() && sc.direct.is_empty() {
            return;
        }
        // The evaluator's group of the tile (a few per tile: a short scan).
        let e = e as u32;
        let g = match sc.deferred[..sc.groups].iter().position(|d| d.e == e) {
            Some(g) => g,
            None => {
                if sc.groups == sc.deferred.len() {
                    sc.deferred.push(Deferred::default());
                }
                sc.deferred[sc.groups].e = e;
                sc.groups += 1;
                sc.groups - 1
            }
        };
        let d = &mut sc.deferred[g];
        move_all(&mut sc.brackets, &mut d.brackets);
        move_all(&mut sc.direct, &mut d.direct);
    }

    /// Resolves the buffered brackets (evaluator `e`: at their
    /// false-position points where the field is close to linear, else
    /// refined), records their hits and the buffered direct hits, and their
    /// colours.
    pub(super) fn record(&mut self, e: usize) {
        let mut hit_rays = std::mem::take(&mut self.sc.hit_rays);
        hit_rays.clear();
        self.polish(e, &mut hit_rays);
        self.refine(e);
        let brackets = std::mem::take(&mut self.sc.brackets);
        let direct = std::mem::take(&mut self.sc.direct);
        for b in &brackets {
            let z = b.secant().map_or(b.hi, |s| b.lo + (b.hi - b.lo) * s);
            let h = self.make_hit(b.ray, z.clamp(b.lo, b.hi), false);
            self.set_hit(b.ray, h);
            hit_rays.push(b.ray);
        }
        for &(i, z, at_entry) in &direct {
            let h = self.make_hit(i, z, at_entry);
            self.set_hit(i, h);
            hit_rays.push(i);
        }
        self.flush_normals(e);
        self.colors(&hit_rays);
        self.sc.brackets = brackets;
        self.sc.brackets.clear();
        self.sc.direct = direct;
        self.sc.direct.clear();
        self.sc.hit_rays = hit_rays;
    }

    /// Resolves the buffered brackets (evaluator `e`) where the field is
    /// close to linear.
    /// 1. The value and gradient at each bracket's false-position point come
    ///    in one batch of [`BatchEval::eval_grad`]. The normal needs the
    ///    gradient anyway.
    /// 2. That point is the hit, and the gradient there its normal, where
    ///    two things hold. One Newton step along the ray from there would
    ///    move at most [`POLISH_PX`] footprints and stay in the bracket. The
    ///    slope along the ray is within a factor of two of the bracket's
    ///    secant slope, so no kink or bend lies inside.
    /// 3. Those hits are recorded into `hit_rays`.
    /// 4. The brackets left are narrowed to the side of that point that
    ///    holds the crossing, then refined ([`TileCtx::refine`]).
    ///
    /// [`BatchEval::eval_grad`]: frep_core::eval::batch::BatchEval::eval_grad
    fn polish(&mut self, e: usize, hit_rays: &mut Vec<usize>) {
        let sc = &mut *self.sc;
        let nb = sc.brackets.len();
        if nb == 0 {
            return;
        }
        let mut cs = std::mem::take(&mut sc.fracs);
        cs.clear();
        sc.set_points(nb);
        for (j, b) in sc.brackets.iter().enumerate() {
            let w = b.hi - b.lo;
            let c = b
                .secant()
                .map_or(b.lo + 0.5 * w, |s| b.lo + w * s.clamp(0.0, 1.0));
            cs.push(c);
            [sc.xs[j], sc.ys[j], sc.zs[j]] = sc.rays[b.ray].at_depth(c);
        }
        self.stats.grad_evals += nb as u64;
        sc.eval_grads(e, &self.caster.inputs);
        let mut brackets = std::mem::take(&mut self.sc.brackets);
        let grads = std::mem::take(&mut self.sc.grads);
        // Inverse gradient lengths first, in a loop of their own: square
        // roots and divisions that do not wait on each other.
        let mut inv = std::mem::take(&mut self.sc.inv_len);
        inv.clear();
        inv.extend(grads[..nb].iter().map(|g| 1.0 / len2(g).sqrt()));
        let mut kept = 0;
        for j in 0..nb {
            let b = brackets[j];
            let (g, c) = (grads[j], cs[j]);
            let r = self.sc.rays[b.ray];
            // The slope along the ray (per unit depth), and the bracket's.
            let s = g.dx * r.dz[0] + g.dy * r.dz[1] + g.dz * r.dz[2];
            let m = (b.f_hi - b.f_lo) / (b.hi - b.lo);
            let d = -g.v / s;
            let tol = POLISH_PX * self.footprint(b.lo);
            let linear = s > 0.0 && m >= 0.5 * s && m <= 2.0 * s;
            let normal = if !(linear && d.abs() <= tol && c + d >= b.lo && c + d <= b.hi) {
                None
            } else if NORMAL_LEN2.contains(&len2(&g)) {
                // What `unit` gives, its division done above.
                let k = inv[j];
                Some([-g.dx * k, -g.dy * k, -g.dz * k])
            } else {
                unit([-g.dx, -g.dy, -g.dz])
            };
            match normal {
                Some(normal) => {
                    let h = Hit {
                        t: c / r.c,
                        position: r.at_depth(c),
                        normal,
                        color: None,
                    };
                    self.set_hit(b.ray, h);
                    hit_rays.push(b.ray);
                }
                None => {
                    // Refined from the side of `c` that holds the crossing.
                    let mut b = b;
                    if g.v >= 0.0 {
                        (b.hi, b.f_hi) = (c, g.v);
                    } else {
                        (b.lo, b.f_lo) = (c, g.v);
                    }
                    brackets[kept] = b;
                    kept += 1;
                }
            }
        }
        brackets.truncate(kept);
        self.sc.brackets = brackets;
        self.sc.grads = grads;
        self.sc.fracs = cs;
        self.sc.inv_len = inv;
    }

    /// Refines the buffered brackets at once (one batch per step) until
    /// each is at most [`REFINE_PX`] pixel footprints wide (at most
    /// [`REFINE`] steps). Each step tries the false-position point `c` (the
    /// Illinois rule, kept off the ends) as a pair `c ± tol·0.45`. Where
    /// the crossing lies between the two, the bracket is done. For a smooth
    /// field that nearly always happens after one step. Otherwise the side
    /// that holds the first crossing is kept. A bracket too narrow for a
    /// pair gets `c` alone.
    fn refine(&mut self, e: usize) {
        if self.sc.brackets.is_empty() {
            return;
        }
        let mut tol = std::mem::take(&mut self.sc.fracs);
        tol.clear();
        for b in &self.sc.brackets {
            tol.push(REFINE_PX * self.footprint(b.lo));
        }
        let mut active = std::mem::take(&mut self.sc.refine_active);
        let mut trials = std::mem::take(&mut self.sc.refine_trials);
        let sc = &mut *self.sc;
        // Only brackets still too wide (a narrowed one never widens).
        active.clear();
        active.extend((0..sc.brackets.len()).filter(|&j| {
            let b = &sc.brackets[j];
            b.hi - b.lo > tol[j]
        }));
        for _ in 0..REFINE {
            if active.is_empty() {
                break;
            }
            // Per active bracket its trial depths (a pair, or one depth
            // twice: evaluated once, read twice), written straight into
            // the point buffers.
            trials.clear();
            sc.set_points(2 * active.len());
            let mut np = 0;
            for &j in &active {
                let b = &sc.brackets[j];
                let c = b.trial();
                let h = 0.45 * tol[j];
                let (a, d) = if c - h > b.lo && c + h < b.hi {
                    (c - h, c + h)
                } else {
                    (c, c)
                };
                let r = &sc.rays[b.ray];
                [sc.xs[np], sc.ys[np], sc.zs[np]] = r.at_depth(a);
                trials.push((a, d, np));
                if a == d {
                    np += 1;
                } else {
                    [sc.xs[np + 1], sc.ys[np + 1], sc.zs[np + 1]] = r.at_depth(d);
                    np += 2;
                }
            }
            sc.np = np;
            self.stats.point_evals += np as u64;
            sc.eval_points(e, &self.caster.inputs);
            // Each bracket narrowed; those still too wide stay active.
            let mut kept = 0;
            for t in 0..active.len() {
                let j = active[t];
                let (a, d, o) = trials[t];
                let b = &mut sc.brackets[j];
                let fa = sc.vals[o];
                let fd = if a == d { fa } else { sc.vals[o + 1] };
                if fa >= 0.0 {
                    // The first crossing is in front of the pair.
                    b.hi = a;
                    b.f_hi = fa;
                    if b.kept == -1 {
                        b.f_lo *= 0.5;
                    }
                    b.kept = -1;
                } else if fd >= 0.0 {
                    // Between the two: the bracket is the pair.
                    (b.lo, b.f_lo, b.hi, b.f_hi, b.kept) = (a, fa, d, fd, 0);
                } else {
                    b.lo = d;
                    b.f_lo = fd;
                    if b.kept == 1 {
                        b.f_hi *= 0.5;
                    }
                    b.kept = 1;
                }
                if b.hi - b.lo > tol[j] {
                    active[kept] = j;
                    kept += 1;
                }
            }
            active.truncate(kept);
        }
        self.sc.fracs = tol;
        self.sc.refine_active = active;
        self.sc.refine_trials = trials;
    }
}
