//! The FRep ray caster: a [`TileCaster`] for a compiled HyperFun [`Model`].
//!
//! HyperFun fields are not distance fields, so the caster never steps by the
//! field value. Per tile of the image:
//!
//! 1. **Frustum pruning.** The tile's rays are clipped to the model box; the
//!    part of the tile frustum between two depths is enclosed in an
//!    axis-aligned box ([`Frustum::aabb_between_depths`](crate::camera::Frustum::aabb_between_depths)) and the field is
//!    evaluated over it with interval arithmetic. A box that is outside
//!    (negative or NaN throughout) is skipped; a box that is inside throughout
//!    ends every ray still searching there; otherwise the tape is shortened
//!    for the box ([`SimplifyMode::Sign`]) and the box is split, front to
//!    back: first along the depth (interval bisection along the frustum)
//!    until a depth slab is about as deep as the rectangle is wide in pixel
//!    footprints, then into four sub-rectangles and two depth halves, down
//!    to leaves of [`LEAF`]×[`LEAF`] pixels.
//! 2. **Leaves.** Every unresolved ray of a leaf is sampled at steps of
//!    [`ModelCaster::step_px`] pixel footprints across the slab, all rays of
//!    the leaf in one batch ([`BatchEval`], vectorised across rays). The
//!    first sign change (`f >= 0` inside, NaN outside) is refined by
//!    bisection (again batched across rays) and a final secant step. A ray
//!    whose samples show no crossing although the leaf is ambiguous gets an
//!    interval bisection along its own segment, down to a fraction of a
//!    pixel, so features thinner than a step are not lost.
//! 3. **Shading inputs.** Normals are `−∇f/|∇f|` by forward-mode automatic
//!    differentiation ([`GradEval`]) on the leaf's shortened tape; where the
//!    gradient vanishes (e.g. `(r² − |p|²)³` on its surface) central
//!    differences at the pixel footprint are used, and failing those the
//!    direction back to the eye. Where the solid is cut by the model box the
//!    normal is the box face's. Attribute colours come from `s[1..3]` when
//!    the model declares `s[]`.
//!
//! Evaluators are built per tile and per shortened tape, never per pixel;
//! a tile holds its hits and a few batches of sample coordinates.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;

use frep_core::eval::batch::BatchEval;
use frep_core::eval::grad::GradEval;
use frep_core::eval::interval::{Interval, IntervalEval};
use frep_core::eval::Inputs;
use frep_core::simplify::{simplify_with_stats, SimplifyMode};
use frep_core::{Model, Tape};
use rayon::prelude::*;

use crate::camera::{dot, Aabb, Camera};
use crate::image::{Hit, HitBuffer, Image, Lighting, Shader};
use crate::tiles::{cast_tiled, tiles, Tile, TileCaster};

/// Leaves of the tile subdivision are at most this many pixels wide.
pub const LEAF: u32 = 8;

/// Bisection steps that refine a bracketed crossing (then one secant step):
/// the bracket shrinks to `1/2^REFINE` of a sampling step.
const REFINE: usize = 8;

/// The largest image the renderer accepts: 16 384 pixels a side and 64
/// megapixels in all.
pub const MAX_SIDE: u32 = 16_384;
/// See [`MAX_SIDE`].
pub const MAX_PIXELS: u64 = 64 << 20;

/// Counters of the work a caster did (for pruning regression checks).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CastStats {
    /// Interval evaluations (frustum boxes and ray segments).
    pub interval_evals: u64,
    /// Point evaluations (samples, refinement, finite differences).
    pub point_evals: u64,
    /// Gradient evaluations (normals).
    pub grad_evals: u64,
    /// Tape simplifications that shortened the tape.
    pub simplified: u64,
}

#[derive(Default)]
struct AtomicStats {
    interval_evals: AtomicU64,
    point_evals: AtomicU64,
    grad_evals: AtomicU64,
    simplified: AtomicU64,
}

/// A [`TileCaster`] for a compiled model (see the module docs).
pub struct ModelCaster {
    tape: Tape,
    attr_tape: Option<Tape>,
    inputs: Inputs,
    bounds: Aabb,
    cancel: Option<Arc<AtomicBool>>,
    /// Sampling step along rays in leaves, in pixel footprints (default 1).
    pub step_px: f64,
    /// Depth of the per-ray interval bisection below one sampling step for
    /// rays whose samples miss in an ambiguous leaf (default 3: 1/8 step).
    pub fallback_depth: u32,
    /// Leaves are sampled once their depth slab is at most this many pixel
    /// footprints deep (deeper ones are split by interval bisection first).
    pub leaf_depth_px: f64,
    stats: AtomicStats,
}

impl ModelCaster {
    /// A caster of `model` with these parameter values, clipped to `bounds`.
    pub fn new(model: &Model, inputs: Inputs, bounds: Aabb) -> ModelCaster {
        ModelCaster {
            tape: model.tape(),
            attr_tape: (model.has_attributes && model.s_dim >= 3)
                .then(|| model.tape_with_attributes()),
            inputs,
            bounds,
            cancel: None,
            step_px: 1.0,
            fallback_depth: 3,
            leaf_depth_px: 16.0,
            stats: AtomicStats::default(),
        }
    }

    /// A caster of a bare tape (output 0 is the field, positive inside).
    pub fn from_tape(tape: Tape, inputs: Inputs, bounds: Aabb) -> ModelCaster {
        ModelCaster {
            tape,
            attr_tape: None,
            inputs,
            bounds,
            cancel: None,
            step_px: 1.0,
            fallback_depth: 3,
            leaf_depth_px: 16.0,
            stats: AtomicStats::default(),
        }
    }

    /// Checks `flag` before each tile and each frustum box; once it is set
    /// the remaining tiles are left empty.
    pub fn with_cancel(mut self, flag: Arc<AtomicBool>) -> ModelCaster {
        self.cancel = Some(flag);
        self
    }

    /// The model box rays are clipped to.
    pub fn bounds(&self) -> &Aabb {
        &self.bounds
    }

    /// The work done so far.
    pub fn stats(&self) -> CastStats {
        CastStats {
            interval_evals: self.stats.interval_evals.load(Ordering::Relaxed),
            point_evals: self.stats.point_evals.load(Ordering::Relaxed),
            grad_evals: self.stats.grad_evals.load(Ordering::Relaxed),
            simplified: self.stats.simplified.load(Ordering::Relaxed),
        }
    }

    fn cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

impl TileCaster for ModelCaster {
    fn cast_tile(&self, camera: &Camera, tile: &Tile, out: &mut [Option<Hit>]) {
        if self.cancelled() {
            return;
        }
        let mut ctx = TileCtx::new(self, camera, tile, out);
        ctx.run();
        let s = &self.stats;
        s.interval_evals
            .fetch_add(ctx.stats.interval_evals, Ordering::Relaxed);
        s.point_evals
            .fetch_add(ctx.stats.point_evals, Ordering::Relaxed);
        s.grad_evals
            .fetch_add(ctx.stats.grad_evals, Ordering::Relaxed);
        s.simplified
            .fetch_add(ctx.stats.simplified, Ordering::Relaxed);
    }
}

/// The evaluators of one (possibly shortened) tape.
struct Evals {
    tape: Tape,
    interval: IntervalEval,
    batch: Option<BatchEval>,
    grad: Option<GradEval>,
}

impl Evals {
    fn new(tape: Tape) -> Evals {
        Evals {
            interval: IntervalEval::new(&tape),
            tape,
            batch: None,
            grad: None,
        }
    }

    fn batch(&mut self) -> &mut BatchEval {
        let tape = &self.tape;
        self.batch.get_or_insert_with(|| BatchEval::new(tape))
    }

    fn grad(&mut self) -> &mut GradEval {
        let tape = &self.tape;
        self.grad.get_or_insert_with(|| GradEval::new(tape))
    }
}

/// One pixel's ray, with its depth range inside the model box (depth = the
/// distance along the camera's viewing direction, `z = t · c`).
#[derive(Clone, Copy)]
struct RayInfo {
    origin: [f64; 3],
    dir: [f64; 3],
    /// `dir · forward`.
    c: f64,
    z0: f64,
    z1: f64,
    live: bool,
}

impl RayInfo {
    fn at_depth(&self, z: f64) -> [f64; 3] {
        let t = z / self.c;
        [
            self.origin[0] + self.dir[0] * t,
            self.origin[1] + self.dir[1] * t,
            self.origin[2] + self.dir[2] * t,
        ]
    }
}

/// A pixel rectangle `[x0, x1) × [y0, y1)` in tile-local pixels.
#[derive(Clone, Copy)]
struct Rect {
    x0: u32,
    y0: u32,
    x1: u32,
    y1: u32,
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

/// A bracketed crossing: `f(lo) < 0` (or NaN), `f(hi) >= 0`.
struct Bracket {
    ray: usize,
    lo: f64,
    hi: f64,
    f_lo: f64,
    f_hi: f64,
}

struct TileCtx<'a> {
    caster: &'a ModelCaster,
    cam: &'a Camera,
    tile: &'a Tile,
    out: &'a mut [Option<Hit>],
    rays: Vec<RayInfo>,
    tw: u32,
    stats: CastStats,
    xs: Vec<f64>,
    ys: Vec<f64>,
    zs: Vec<f64>,
    vals: Vec<f64>,
    /// Per ray of the current leaf: (tile ray index, lo depth, hi depth).
    leaf_rays: Vec<(usize, f64, f64)>,
    brackets: Vec<Bracket>,
    attr: Option<BatchEval>,
}

fn clip_box(b: &Aabb, bounds: &Aabb) -> Option<Aabb> {
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

fn iv(lo: f64, hi: f64) -> Interval {
    Interval::new(lo, hi)
}

impl<'a> TileCtx<'a> {
    fn new(
        caster: &'a ModelCaster,
        cam: &'a Camera,
        tile: &'a Tile,
        out: &'a mut [Option<Hit>],
    ) -> TileCtx<'a> {
        let mut rays = Vec::with_capacity((tile.w() * tile.h()) as usize);
        for py in tile.y0..tile.y1 {
            for px in tile.x0..tile.x1 {
                let r = cam.ray(px, py, tile.width, tile.height);
                let c = dot(r.dir, cam.forward).max(1e-12);
                let (z0, z1, live) = match r.clip(&caster.bounds) {
                    Some((t0, t1)) => (t0 * c, t1 * c, true),
                    None => (0.0, 0.0, false),
                };
                rays.push(RayInfo {
                    origin: r.origin,
                    dir: r.dir,
                    c,
                    z0,
                    z1,
                    live,
                });
            }
        }
        TileCtx {
            caster,
            cam,
            tile,
            out,
            rays,
            tw: tile.w(),
            stats: CastStats::default(),
            xs: Vec::new(),
            ys: Vec::new(),
            zs: Vec::new(),
            vals: Vec::new(),
            leaf_rays: Vec::new(),
            brackets: Vec::new(),
            attr: None,
        }
    }

    fn footprint(&self, z: f64) -> f64 {
        self.cam
            .pixel_footprint(z, self.tile.width, self.tile.height)
    }

    fn run(&mut self) {
        let (mut zmin, mut zmax) = (f64::INFINITY, f64::NEG_INFINITY);
        for r in self.rays.iter().filter(|r| r.live) {
            zmin = zmin.min(r.z0);
            zmax = zmax.max(r.z1);
        }
        if zmin > zmax || zmin.is_nan() || zmax.is_nan() {
            return;
        }
        let rect = Rect {
            x0: 0,
            y0: 0,
            x1: self.tile.w(),
            y1: self.tile.h(),
        };
        let mut root = Evals::new(self.caster.tape.clone());
        self.node(&mut root, rect, zmin, zmax);
    }

    /// The depth range of the unresolved live rays of `rect` within
    /// `[za, zb]`, if any.
    fn active_range(&self, rect: Rect, za: f64, zb: f64) -> Option<(f64, f64)> {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let i = (y * self.tw + x) as usize;
                let r = &self.rays[i];
                if !r.live || self.out[i].is_some() || r.z1 < za || r.z0 > zb {
                    continue;
                }
                lo = lo.min(r.z0.max(za));
                hi = hi.max(r.z1.min(zb));
            }
        }
        (lo <= hi).then_some((lo, hi))
    }

    fn node(&mut self, ev: &mut Evals, rect: Rect, za: f64, zb: f64) {
        if self.caster.cancelled() {
            return;
        }
        let Some((za, zb)) = self.active_range(rect, za, zb) else {
            return;
        };
        let fr = self.cam.tile_frustum(
            self.tile.x0 + rect.x0,
            self.tile.y0 + rect.y0,
            self.tile.x0 + rect.x1,
            self.tile.y0 + rect.y1,
            self.tile.width,
            self.tile.height,
        );
        let Some(b) = clip_box(&fr.aabb_between_depths(za, zb), &self.caster.bounds) else {
            return;
        };
        self.stats.interval_evals += 1;
        let v = ev.interval.eval(
            iv(b.min[0], b.max[0]),
            iv(b.min[1], b.max[1]),
            iv(b.min[2], b.max[2]),
            &self.caster.inputs,
        );
        if v.is_outside() {
            return;
        }
        if v.is_positive() {
            self.fill(ev, rect, za, zb);
            return;
        }
        // Shorten the tape for this box when that helps.
        let mut child = None;
        if ev.tape.len() > 4 {
            let (t, st) = simplify_with_stats(&ev.tape, ev.interval.choices(), SimplifyMode::Sign);
            if st.after < st.before {
                self.stats.simplified += 1;
                child = Some(Evals::new(t));
            }
        }
        let ev: &mut Evals = match &mut child {
            Some(c) => c,
            None => ev,
        };
        let s = rect.size();
        let cell = s as f64 * self.footprint(za).max(1e-300);
        if zb - za > 2.0 * cell {
            // Interval bisection along the frustum.
            let zm = 0.5 * (za + zb);
            self.node(ev, rect, za, zm);
            self.node(ev, rect, zm, zb);
        } else if s > LEAF {
            let zm = 0.5 * (za + zb);
            for q in rect.quadrants() {
                self.node(ev, q, za, zm);
                self.node(ev, q, zm, zb);
            }
        } else if zb - za > self.caster.leaf_depth_px * self.footprint(za) {
            // Thin the leaf's slab further: interval evaluations on short
            // tapes are cheaper than sampling every ray of the leaf.
            let zm = 0.5 * (za + zb);
            self.node(ev, rect, za, zm);
            self.node(ev, rect, zm, zb);
        } else {
            self.leaf(ev, rect, za, zb);
        }
    }

    /// The box inside the solid throughout: rays still searching hit it
    /// where they enter it.
    fn fill(&mut self, ev: &mut Evals, rect: Rect, za: f64, zb: f64) {
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let i = (y * self.tw + x) as usize;
                let r = self.rays[i];
                if !r.live || self.out[i].is_some() || r.z1 < za || r.z0 > zb {
                    continue;
                }
                let z = za.max(r.z0);
                let hit = self.make_hit(ev, i, z, z <= r.z0);
                self.out[i] = Some(hit);
            }
        }
    }

    fn make_hit(&mut self, ev: &mut Evals, i: usize, z: f64, at_entry: bool) -> Hit {
        let r = self.rays[i];
        let p = r.at_depth(z);
        let face = if at_entry && z > 0.0 {
            self.entry_face(&p)
        } else {
            None
        };
        let normal = match face {
            Some(n) => n,
            None => self.normal(ev, &r, p, z),
        };
        Hit {
            t: z / r.c,
            position: p,
            normal,
            color: None,
        }
    }

    /// The outward normal of the model box face `p` lies on, if it does and
    /// the field is inside there (the solid is cut open by the box).
    fn entry_face(&self, p: &[f64; 3]) -> Option<[f64; 3]> {
        let b = &self.caster.bounds;
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

    fn normal(&mut self, ev: &mut Evals, r: &RayInfo, p: [f64; 3], z: f64) -> [f64; 3] {
        self.stats.grad_evals += 1;
        let g = ev.grad().eval(p[0], p[1], p[2], &self.caster.inputs);
        let n = [-g.dx, -g.dy, -g.dz];
        if let Some(n) = unit(n) {
            return n;
        }
        // Zero or non-finite gradient: central differences at the footprint.
        let h = self.footprint(z).max(1e-9 * (1.0 + z.abs()));
        for scale in [0.5, 2.0, 8.0] {
            let d = h * scale;
            self.xs.clear();
            self.ys.clear();
            self.zs.clear();
            for k in 0..3 {
                for s in [d, -d] {
                    let mut q = p;
                    q[k] += s;
                    self.xs.push(q[0]);
                    self.ys.push(q[1]);
                    self.zs.push(q[2]);
                }
            }
            self.vals.clear();
            self.vals.resize(6, 0.0);
            self.stats.point_evals += 6;
            ev.batch().eval(
                &self.xs,
                &self.ys,
                &self.zs,
                &self.caster.inputs,
                &mut self.vals,
            );
            let v = &self.vals;
            let n = [-(v[0] - v[1]), -(v[2] - v[3]), -(v[4] - v[5])];
            if let Some(n) = unit(n) {
                return n;
            }
        }
        [-r.dir[0], -r.dir[1], -r.dir[2]]
    }

    fn leaf(&mut self, ev: &mut Evals, rect: Rect, za: f64, zb: f64) {
        let step = self.caster.step_px.max(1e-3) * self.footprint(za).max(1e-300);
        let n = (((zb - za) / step).ceil() as usize).clamp(1, 4096);
        self.leaf_rays.clear();
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                let i = (y * self.tw + x) as usize;
                let r = &self.rays[i];
                if !r.live || self.out[i].is_some() || r.z1 < za || r.z0 > zb {
                    continue;
                }
                self.leaf_rays.push((i, za.max(r.z0), zb.min(r.z1)));
            }
        }
        if self.leaf_rays.is_empty() {
            return;
        }
        // Sample every ray at n + 1 depths, all rays in one batch.
        self.xs.clear();
        self.ys.clear();
        self.zs.clear();
        for &(i, lo, hi) in &self.leaf_rays {
            let r = &self.rays[i];
            for k in 0..=n {
                let z = lo + (hi - lo) * (k as f64 / n as f64);
                let p = r.at_depth(z);
                self.xs.push(p[0]);
                self.ys.push(p[1]);
                self.zs.push(p[2]);
            }
        }
        self.vals.clear();
        self.vals.resize(self.xs.len(), 0.0);
        self.stats.point_evals += self.xs.len() as u64;
        ev.batch().eval(
            &self.xs,
            &self.ys,
            &self.zs,
            &self.caster.inputs,
            &mut self.vals,
        );
        self.brackets.clear();
        let leaf_rays = std::mem::take(&mut self.leaf_rays);
        let mut direct: Vec<(usize, f64, bool)> = Vec::new();
        let mut missed: Vec<(usize, f64, f64)> = Vec::new();
        for (j, &(i, lo, hi)) in leaf_rays.iter().enumerate() {
            let v = &self.vals[j * (n + 1)..(j + 1) * (n + 1)];
            let z = |k: usize| lo + (hi - lo) * (k as f64 / n as f64);
            match v.iter().position(|&f| f >= 0.0) {
                Some(0) => direct.push((i, lo, lo <= self.rays[i].z0)),
                Some(k) => self.brackets.push(Bracket {
                    ray: i,
                    lo: z(k - 1),
                    hi: z(k),
                    f_lo: v[k - 1],
                    f_hi: v[k],
                }),
                None => {
                    // No sample inside: a feature thinner than a step can
                    // only hide around a local maximum of the samples
                    // (NaN counting as -inf); search there.
                    let g = |k: usize| {
                        if v[k].is_nan() {
                            f64::NEG_INFINITY
                        } else {
                            v[k]
                        }
                    };
                    for k in 0..=n {
                        let left = if k > 0 { g(k - 1) } else { f64::NEG_INFINITY };
                        let right = if k < n { g(k + 1) } else { f64::NEG_INFINITY };
                        let c = g(k);
                        if c > f64::NEG_INFINITY
                            && c >= left
                            && c >= right
                            && (c > left || c > right)
                        {
                            missed.push((i, z(k.saturating_sub(1)), z((k + 1).min(n))));
                            break;
                        }
                    }
                }
            }
        }
        // Rays whose samples saw no crossing: interval bisection along the
        // ray, down to a fraction of a step.
        let min_len = step / (1u64 << self.caster.fallback_depth.min(20)) as f64;
        for &(i, lo, hi) in &missed {
            if let Some((a, b)) = self.ray_search(ev, i, lo, hi, min_len) {
                let r = self.rays[i];
                let pa = r.at_depth(a);
                let pb = r.at_depth(b);
                let fa = self.point(ev, pa);
                let fb = self.point(ev, pb);
                if fa >= 0.0 {
                    direct.push((i, a, a <= r.z0));
                } else {
                    self.brackets.push(Bracket {
                        ray: i,
                        lo: a,
                        hi: b,
                        f_lo: fa,
                        f_hi: fb.max(0.0),
                    });
                }
            }
        }
        self.refine(ev);
        let brackets = std::mem::take(&mut self.brackets);
        let mut hit_rays = Vec::with_capacity(brackets.len() + direct.len());
        for b in &brackets {
            let z = if b.f_lo.is_finite() && b.f_hi.is_finite() && b.f_lo < 0.0 && b.f_hi > b.f_lo {
                b.lo + (b.hi - b.lo) * (-b.f_lo / (b.f_hi - b.f_lo))
            } else {
                b.hi
            };
            let h = self.make_hit(ev, b.ray, z.clamp(b.lo, b.hi), false);
            self.out[b.ray] = Some(h);
            hit_rays.push(b.ray);
        }
        for &(i, z, at_entry) in &direct {
            let h = self.make_hit(ev, i, z, at_entry);
            self.out[i] = Some(h);
            hit_rays.push(i);
        }
        self.brackets = brackets;
        self.leaf_rays = leaf_rays;
        self.colors(&hit_rays);
    }

    fn point(&mut self, ev: &mut Evals, p: [f64; 3]) -> f64 {
        let mut out = [0.0];
        self.stats.point_evals += 1;
        ev.batch()
            .eval(&[p[0]], &[p[1]], &[p[2]], &self.caster.inputs, &mut out);
        out[0]
    }

    /// Interval bisection along ray `i` over depths `[a, b]`, front to back:
    /// the first sub-segment no longer than `min_len` that may hold the
    /// surface and whose midpoint (or end) is inside.
    fn ray_search(
        &mut self,
        ev: &mut Evals,
        i: usize,
        a: f64,
        b: f64,
        min_len: f64,
    ) -> Option<(f64, f64)> {
        let r = self.rays[i];
        let pa = r.at_depth(a);
        let pb = r.at_depth(b);
        self.stats.interval_evals += 1;
        let v = ev.interval.eval(
            iv(pa[0].min(pb[0]), pa[0].max(pb[0])),
            iv(pa[1].min(pb[1]), pa[1].max(pb[1])),
            iv(pa[2].min(pb[2]), pa[2].max(pb[2])),
            &self.caster.inputs,
        );
        if v.is_outside() {
            return None;
        }
        if v.is_positive() {
            return Some((a, a));
        }
        let m = 0.5 * (a + b);
        if b - a <= min_len {
            let fm = self.point(ev, r.at_depth(m));
            return (fm >= 0.0).then_some((a, m));
        }
        self.ray_search(ev, i, a, m, min_len)
            .or_else(|| self.ray_search(ev, i, m, b, min_len))
    }

    /// Bisection of every bracket at once (one batch per step).
    fn refine(&mut self, ev: &mut Evals) {
        if self.brackets.is_empty() {
            return;
        }
        for _ in 0..REFINE {
            self.xs.clear();
            self.ys.clear();
            self.zs.clear();
            for b in &self.brackets {
                let p = self.rays[b.ray].at_depth(0.5 * (b.lo + b.hi));
                self.xs.push(p[0]);
                self.ys.push(p[1]);
                self.zs.push(p[2]);
            }
            self.vals.clear();
            self.vals.resize(self.xs.len(), 0.0);
            self.stats.point_evals += self.xs.len() as u64;
            ev.batch().eval(
                &self.xs,
                &self.ys,
                &self.zs,
                &self.caster.inputs,
                &mut self.vals,
            );
            for (b, &f) in self.brackets.iter_mut().zip(&self.vals) {
                let m = 0.5 * (b.lo + b.hi);
                if f >= 0.0 {
                    b.hi = m;
                    b.f_hi = f;
                } else {
                    b.lo = m;
                    b.f_lo = f;
                }
            }
        }
    }

    /// Attribute colours (`s[1..3]` as sRGB in `[0, 1]`) at the given hits.
    fn colors(&mut self, hit_rays: &[usize]) {
        let Some(attr_tape) = &self.caster.attr_tape else {
            return;
        };
        if hit_rays.is_empty() {
            return;
        }
        let eval = self.attr.get_or_insert_with(|| BatchEval::new(attr_tape));
        self.xs.clear();
        self.ys.clear();
        self.zs.clear();
        for &i in hit_rays {
            let p = self.out[i].as_ref().map_or([0.0; 3], |h| h.position);
            self.xs.push(p[0]);
            self.ys.push(p[1]);
            self.zs.push(p[2]);
        }
        let mut outs = vec![Vec::new(); attr_tape.outputs.len()];
        self.stats.point_evals += hit_rays.len() as u64;
        eval.eval_outputs(&self.xs, &self.ys, &self.zs, &self.caster.inputs, &mut outs);
        if outs.len() < 4 {
            return;
        }
        for (j, &i) in hit_rays.iter().enumerate() {
            let c = [outs[1][j], outs[2][j], outs[3][j]];
            if let Some(h) = &mut self.out[i] {
                if c.iter().all(|v| v.is_finite()) {
                    h.color = Some(c.map(|v| v.clamp(0.0, 1.0) as f32));
                }
            }
        }
    }
}

fn unit(n: [f64; 3]) -> Option<[f64; 3]> {
    let l = dot(n, n).sqrt();
    if l > 0.0 && l.is_finite() {
        let u = [n[0] / l, n[1] / l, n[2] / l];
        u.iter().all(|v| v.is_finite()).then_some(u)
    } else if n.iter().all(|v| v.is_finite()) && n.iter().any(|&v| v != 0.0) {
        // Tiny components whose squares underflow: rescale first.
        let m = n.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        unit([n[0] / m, n[1] / m, n[2] / m])
    } else {
        None
    }
}

/// What to render.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    /// Image size in pixels `(width, height)`.
    pub size: (u32, u32),
    /// Turntable yaw in degrees (see [`Camera::orbit`]).
    pub yaw: f64,
    /// Turntable pitch in degrees.
    pub pitch: f64,
    /// Field of view in degrees (perspective); `None`: orthographic.
    pub fov: Option<f64>,
    /// The model box: rays are clipped to it and the camera frames it.
    pub bounds: Aabb,
    /// Encoder quality 1–100 for JPEG and WebP (not used by the caster).
    pub quality: u8,
    /// Compute ambient occlusion (a few field samples along each normal).
    pub ao: bool,
    /// Parameter values `a[]` and extra coordinates.
    pub inputs: Inputs,
    /// Tile size in pixels (tiles run in parallel).
    pub tile_size: u32,
    /// The lights.
    pub lighting: Lighting,
}

impl Default for RenderSettings {
    fn default() -> Self {
        RenderSettings {
            size: (512, 512),
            yaw: 30.0,
            pitch: 20.0,
            fov: Some(30.0),
            bounds: Aabb::new([-10.0; 3], [10.0; 3]),
            quality: 85,
            ao: false,
            inputs: Inputs::default(),
            tile_size: 32,
            lighting: Lighting::default(),
        }
    }
}

impl RenderSettings {
    /// The camera these settings describe.
    pub fn camera(&self) -> Camera {
        Camera::orbit(&self.bounds, self.yaw, self.pitch, self.fov)
    }
}

/// Why a render produced no image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum RenderError {
    /// The cancel flag was set.
    Cancelled,
    /// The size is zero or above [`MAX_SIDE`] / [`MAX_PIXELS`].
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
    },
}

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RenderError::Cancelled => write!(f, "render cancelled"),
            RenderError::BadSize { width, height } => write!(
                f,
                "image size {width}x{height} is outside 1..={MAX_SIDE} a side, {MAX_PIXELS} pixels in all"
            ),
        }
    }
}

impl std::error::Error for RenderError {}

fn check_size(width: u32, height: u32) -> Result<(), RenderError> {
    if width == 0
        || height == 0
        || width > MAX_SIDE
        || height > MAX_SIDE
        || width as u64 * height as u64 > MAX_PIXELS
    {
        return Err(RenderError::BadSize { width, height });
    }
    Ok(())
}

fn is_cancelled(cancel: Option<&Arc<AtomicBool>>) -> bool {
    cancel.is_some_and(|c| c.load(Ordering::Relaxed))
}

fn make_caster(
    model: &Model,
    settings: &RenderSettings,
    cancel: Option<&Arc<AtomicBool>>,
) -> ModelCaster {
    let caster = ModelCaster::new(model, settings.inputs.clone(), settings.bounds);
    match cancel {
        Some(c) => caster.with_cancel(c.clone()),
        None => caster,
    }
}

/// Casts the rays of `settings` and returns every hit (with ambient
/// occlusion when `settings.ao`).
pub fn render_hits(
    model: &Model,
    settings: &RenderSettings,
    cancel: Option<&Arc<AtomicBool>>,
) -> Result<HitBuffer, RenderError> {
    let (w, h) = settings.size;
    check_size(w, h)?;
    let caster = make_caster(model, settings, cancel);
    let cam = settings.camera();
    let mut hits = cast_tiled(&caster, &cam, w, h, settings.tile_size.max(1));
    if is_cancelled(cancel) {
        return Err(RenderError::Cancelled);
    }
    if settings.ao {
        let mut ev = BatchEval::new(&caster.tape);
        let mut ao = vec![1.0; hits.hits.len()];
        ambient_occlusion(&mut ev, &caster, &hits.hits, &mut ao);
        hits.ao = Some(ao);
    }
    Ok(hits)
}

/// Renders a shaded image of `model` as `settings` describe. Tiles are cast
/// and shaded in parallel and only the image is kept whole (no full hit
/// buffer). `cancel`, when set during the render, makes it stop early with
/// [`RenderError::Cancelled`].
pub fn render(
    model: &Model,
    settings: &RenderSettings,
    cancel: Option<&Arc<AtomicBool>>,
) -> Result<Image, RenderError> {
    render_camera(model, settings, &settings.camera(), cancel)
}

/// [`render`] through any camera (e.g. one view of a view set, or a
/// benchmark's fixed view); `settings.yaw`, `pitch` and `fov` are ignored.
pub fn render_camera(
    model: &Model,
    settings: &RenderSettings,
    camera: &Camera,
    cancel: Option<&Arc<AtomicBool>>,
) -> Result<Image, RenderError> {
    let caster = make_caster(model, settings, cancel);
    render_with(&caster, settings, camera, cancel)
}

/// [`render_camera`] with a prepared caster (whose [`CastStats`] then count
/// this render).
pub fn render_with(
    caster: &ModelCaster,
    settings: &RenderSettings,
    camera: &Camera,
    cancel: Option<&Arc<AtomicBool>>,
) -> Result<Image, RenderError> {
    let (w, h) = settings.size;
    check_size(w, h)?;
    let shader = Shader::new(camera, &settings.lighting, w, h);
    let ts = tiles(w, h, settings.tile_size.max(1));
    let shaded: Vec<(Tile, Vec<u8>)> = ts
        .into_par_iter()
        .map_init(
            || None::<BatchEval>,
            |ao_eval, t| {
                let n = (t.w() * t.h()) as usize;
                let mut hits = vec![None; n];
                caster.cast_tile(camera, &t, &mut hits);
                let mut ao = Vec::new();
                if settings.ao {
                    ao.resize(n, 1.0);
                    let ev = ao_eval.get_or_insert_with(|| BatchEval::new(&caster.tape));
                    ambient_occlusion(ev, caster, &hits, &mut ao);
                }
                let mut rgba = vec![255u8; n * 4];
                let mut i = 0;
                for y in t.y0..t.y1 {
                    for x in t.x0..t.x1 {
                        let a = ao.get(i).copied();
                        let rgb = shader.pixel(x, y, hits[i].as_ref(), a);
                        rgba[i * 4..i * 4 + 3].copy_from_slice(&rgb);
                        i += 1;
                    }
                }
                (t, rgba)
            },
        )
        .collect();
    if is_cancelled(cancel) {
        return Err(RenderError::Cancelled);
    }
    let mut img = Image {
        width: w,
        height: h,
        rgba: vec![0; w as usize * h as usize * 4],
    };
    for (t, rgba) in shaded {
        let tw = t.w() as usize * 4;
        for row in 0..t.h() as usize {
            let d = ((t.y0 as usize + row) * w as usize + t.x0 as usize) * 4;
            img.rgba[d..d + tw].copy_from_slice(&rgba[row * tw..(row + 1) * tw]);
        }
    }
    Ok(img)
}

/// Ambient occlusion: the fraction of a few points along each normal (at
/// 1, 2, 4 and 8 % of the model box's radius) that lie outside the solid,
/// weighted towards the near ones.
fn ambient_occlusion(
    ev: &mut BatchEval,
    caster: &ModelCaster,
    hits: &[Option<Hit>],
    ao: &mut [f32],
) {
    const DIST: [f64; 4] = [0.01, 0.02, 0.04, 0.08];
    const WEIGHT: [f32; 4] = [0.4, 0.3, 0.2, 0.1];
    let r = caster.bounds.radius();
    let (mut xs, mut ys, mut zs) = (Vec::new(), Vec::new(), Vec::new());
    let mut idx = Vec::new();
    for (i, h) in hits.iter().enumerate() {
        let Some(h) = h else { continue };
        let n = unit(h.normal).unwrap_or([0.0; 3]);
        for d in DIST {
            xs.push(h.position[0] + n[0] * d * r);
            ys.push(h.position[1] + n[1] * d * r);
            zs.push(h.position[2] + n[2] * d * r);
        }
        idx.push(i);
    }
    if idx.is_empty() {
        return;
    }
    let mut vals = vec![0.0; xs.len()];
    ev.eval(&xs, &ys, &zs, &caster.inputs, &mut vals);
    caster
        .stats
        .point_evals
        .fetch_add(xs.len() as u64, Ordering::Relaxed);
    for (j, &i) in idx.iter().enumerate() {
        let mut occ = 0.0;
        for k in 0..4 {
            if vals[j * 4 + k] >= 0.0 {
                occ += WEIGHT[k];
            }
        }
        ao[i] = 1.0 - occ;
    }
}
