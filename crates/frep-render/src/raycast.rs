//! The FRep ray caster: a [`TileCaster`] for a compiled HyperFun [`Model`].
//!
//! HyperFun fields are not distance fields, so the caster never steps by the
//! field value. Per tile of the image:
//!
//! 0. **Empty tiles.** The tile's whole frustum over the model box's depth
//!    range is evaluated once with interval arithmetic; where that box is
//!    outside, none of the tile's rays is set up (where the model covers
//!    part of the image, that was most of the cost of the misses).
//!    **Set expressions over quadrics.** Where the model is R-functions,
//!    `min`, `max` and negations over fields of degree at most 2 in the
//!    point or root gaps of one ([`ModelCaster::csg`]), every ray is then solved in closed form
//!    (`csg`): its first hit is the first leaf crossing after which the set
//!    expression holds. Only the rays that fail its checks go on to the
//!    steps below.
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
//!    to leaves of [`LEAF`]×[`LEAF`] pixels. A leaf's slab is narrowed to
//!    the part that may hold the surface by interval evaluations over
//!    sub-slabs [`ModelCaster::narrow_px`] footprints deep (no node
//!    bookkeeping per sub-slab: one leaf is sampled over the span from the
//!    first to the last sub-slab that is not outside, or to the start of
//!    the first sub-slab inside throughout, where every ray is inside; not
//!    where a ray of the leaf enters the model box behind that depth).
//! 2. **Leaves.** Every unresolved ray of a leaf is sampled at steps of
//!    [`ModelCaster::step_px`] pixel footprints across the slab, all rays of
//!    the leaf in one batch ([`BatchEval`], vectorised across rays, with
//!    `sin` and `cos` to about `2e-14` of the value, not an ulp:
//!    [`ModelCaster::trig`]; in an
//!    orthographic view straight along an axis, as lines:
//!    [`BatchEval::eval_lines`], the transcendental functions of the other
//!    two coordinates once per ray and of the axis one once per depth). The
//!    first sign change (`f >= 0` inside, NaN outside) is bracketed; the
//!    ray is then resolved (searched no further), and its bracket waits
//!    for the end of the tile, where all brackets of one shortened tape are
//!    resolved together (batches of up to a tile's rays, not a leaf's).
//!    First the value and gradient at each bracket's false-position point
//!    (the gradient is the normal's): where one Newton step from there
//!    would move at most 1/64 of a footprint and the slope along the ray
//!    agrees with the bracket's secant slope (no kink or bend inside), that
//!    point is the hit. The other brackets are refined to 1/16 of a
//!    footprint, then one secant step: each step evaluates a pair of depths
//!    just either side of the false-position point (Illinois rule), which
//!    for a smooth field nearly always closes the bracket at once.
//!    **Quadrics in closed form.** Where the tape shortened for a box is
//!    a polynomial of degree 2 in the point ([`Tape::polynomial_degree`]:
//!    a sphere, a cylinder, a cone or an ellipsoid alone in the box), the
//!    field along every ray is a polynomial of degree at most 2 in the
//!    depth: the box is split into leaf-sized rectangles over its whole
//!    slab (the quadrants' interval evaluations drop the rays far from the
//!    surface), and each ray's first crossing is solved in closed form;
//!    where the polynomial is clearly outside 1/8 of a footprint before it
//!    and inside 1/8 after, it is the hit. The same holds for a tape
//!    `k − sqrt(p)` with `p` such a polynomial ([`Tape::root_gap`]: its
//!    values `f` map to `f·(2k − f) = k² − p`, of the same sign). The
//!    quadric's coefficients come from the values and gradients at four
//!    points, once per shortened tape; each ray's polynomial
//!    then comes from them and the hit's normal from the quadric's
//!    gradient: no samples and no gradient evaluation per ray (for a model
//!    with no colours, a leaf's rays at once: the common case, a clear
//!    crossing, in one pass over arrays that vectorises,
//!    [`ModelCaster::quadric_blocks`]; for a model
//!    with attribute colours the normals are evaluated with the colours;
//!    where the four points give no quadric, a value not finite there,
//!    each ray is sampled at its slab's ends and middle instead). The
//!    polynomial holds for the whole ray on that tape, so a later slab of
//!    the ray on the same tape needs nothing new; where it has no crossing
//!    on the rest of the ray either, the whole-ray check of step 4 is made
//!    at once where likely to pay. A ray the closed form leaves unsure (a
//!    graze within rounding of the surface, a value not finite) is sampled
//!    as above. Planes (degree 1) likewise: the plane's coefficients come
//!    from one value and gradient, the box's whole rectangle is taken at
//!    once, and each ray that clearly crosses the plane in its slab gets
//!    its hit there with the plane's normal.
//! 3. **Thin features.** A ray whose samples show no crossing although the
//!    leaf is ambiguous can only hide a feature thinner than a step around a
//!    local maximum of its samples; that segment is checked with one
//!    interval evaluation (a leaf's segments over their hull first, then
//!    over each half of a hull not outside: `TileCtx::check_searches`)
//!    and, if it may hold the surface, sampled at the
//!    midpoints of cells of 1/2^[`ModelCaster::fallback_depth`] of a step or
//!    footprint, whichever is smaller (the cells an interval bisection would
//!    end with), batched. A maximum at the *end* of a slab is not searched at
//!    once: the ray remembers its last samples, and when its next slab
//!    follows on and the field keeps rising, there is nothing to search;
//!    otherwise (a gap, a fall, an inside box with a gap, the end of the
//!    tile) the segment is searched first, with the evaluator it was
//!    sampled with, before anything behind it is used.
//! 4. **Rays along walls.** A ray sampled in
//!    [`ModelCaster::prune_after`] leaf slabs without a crossing (down the
//!    bore of a tube seen along its axis, beside a wall parallel to it:
//!    every frustum box there holds the wall) has the rest of its depth
//!    range checked with one interval evaluation over that segment's box,
//!    on the tape shortened for the tile; where it is outside, the ray is a
//!    miss and is searched no further. The check is made where the slabs
//!    left, weighed by the share of checks that succeeded so far, would
//!    cost more to sample than the check (tape lengths as the measure).
//! 5. **Shading inputs.** Normals are `−∇f/|∇f|`, the gradient by
//!    forward-mode automatic differentiation over the batch evaluator's
//!    program ([`BatchEval::eval_grad`]), all hits of a tile and tape in one
//!    batch on that shortened tape (the one that found the hit at a
//!    false-position point, or right after refinement; the shortened tape
//!    keeps the gradient at the surface); where the gradient vanishes
//!    or is not finite (`(r² − |p|²)³` on its surface), central differences
//!    at ½, 2 and 8 pixel footprints, and failing those the direction back
//!    to the eye. Where the solid is cut by the
//!    model box the normal is the box face's. Attribute colours come from
//!    `s[1..3]` when the model declares `s[]`, evaluated on the attributes'
//!    own tape ([`Model::attribute_tape`]), once for all of a group's hits
//!    where an interval evaluation over their box gives each a single value.
//!
//! Tiles are cast by one worker per thread ([`for_each_dynamic`]), each
//! taking the tiles of its own contiguous share one at a time and then the
//! last tile of the largest share left. Evaluators are never built per
//! pixel: each worker thread keeps (from
//! tile to tile, in a pool of the caster, which hands a thread back its
//! own) the root tape's evaluators and
//! those of every shortened tape met so far, keyed by the interval choices
//! that produced them (a tape is simplified and compiled once, and boxes that
//! shorten to the same tape share it), bounded to a few MiB. Rays, frustum
//! corners and pixel footprints use per-image constants ([`RayMaker`]).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use frep_core::eval::batch::{BatchEval, GradRegs, Trig, LANES};
use frep_core::eval::grad::Grad;
use frep_core::eval::interval::{Choice, Interval, IntervalEval};
use frep_core::eval::Inputs;
use frep_core::hash::{FastHasher, FastMap};
use frep_core::simplify::{ChoiceMask, Simplifier, SimplifyMode};
use frep_core::{Model, Tape};

use crate::camera::{dot, sub, Aabb, Camera, Projection, RayMaker};
use crate::image::{fill_background, Hit, HitBuffer, Image, Lighting, ShadeIn, Shader, SPAN};
use crate::tiles::{cast_tiled, for_each_dynamic, tile_rows, tiles, Tile, TileCaster};

mod csg;
use csg::{Csg, Lanes, Solved, Work, BLOCK, ENTRY};

/// An interval evaluation costs about this many point evaluations (in a
/// batch) of the same tape: the weight of a whole-ray check against the
/// samples it may save ([`ModelCaster::prune_after`]). Tuned on the
/// turntable views: 8 rather than 4 saves 1.6 % of android_robot's frame
/// and 1 % of sake_pot's, the other views within 0.3 %.
const INTERVAL_COST: f64 = 8.0;

/// Leaves of the tile subdivision are at most this many pixels wide.
pub const LEAF: u32 = 8;

/// At most this many bisection steps refine a bracketed crossing (then one
/// secant step)...
const REFINE: usize = 8;
/// ...until the bracket is at most this many pixel footprints wide.
const REFINE_PX: f64 = 1.0 / 16.0;
/// A bracket's false-position point is the hit without refinement where a
/// Newton step from it would move at most this many footprints (see
/// [`TileCtx::polish`]).
const POLISH_PX: f64 = 1.0 / 64.0;

/// [`TileCtx::exact`] takes a crossing it computed as the hit where its
/// polynomial is clearly outside this many pixel footprints before it and
/// inside as many after.
const EXACT_BRACKET_PX: f64 = 1.0 / 8.0;

/// Rays per pass of [`TileCtx::quadric_block`] (a leaf's).
const QUAD_BLOCK: usize = (LEAF * LEAF) as usize;

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
    /// Shortened tapes built (each distinct one once per worker thread:
    /// evaluators are cached from tile to tile).
    pub simplified: u64,
    /// Tiles found outside by one interval evaluation before any of their
    /// rays was set up (see the module docs).
    pub empty_tiles: u64,
    /// Of the point evaluations, those made as lines along a coordinate
    /// axis (see [`ModelCaster::lines`]).
    pub line_points: u64,
    /// Rays' slabs settled in closed form (see [`ModelCaster::exact`]):
    /// a hit bracketed or no crossing, from samples or from the ray's
    /// polynomial of an earlier slab; and rays solved whole on a set
    /// expression over quadrics ([`ModelCaster::csg`]).
    pub exact_rays: u64,
}

#[derive(Default)]
struct AtomicStats {
    interval_evals: AtomicU64,
    point_evals: AtomicU64,
    grad_evals: AtomicU64,
    simplified: AtomicU64,
    empty_tiles: AtomicU64,
    line_points: AtomicU64,
    exact_rays: AtomicU64,
}

/// A [`TileCaster`] for a compiled model (see the module docs).
pub struct ModelCaster {
    tape: Tape,
    attr_tape: Option<Tape>,
    inputs: Inputs,
    bounds: Aabb,
    cancel: Option<Arc<AtomicBool>>,
    /// Sampling step along rays in leaves, in pixel footprints (default 2;
    /// thinner features are found by the thin-feature search).
    pub step_px: f64,
    /// Thin-feature searches of rays whose samples miss in an ambiguous
    /// leaf sample cells of `1/2^fallback_depth` of a step or of a pixel
    /// footprint, whichever is smaller (default 3: 1/8).
    pub fallback_depth: u32,
    /// Leaves are sampled once their depth slab is at most this many pixel
    /// footprints deep (deeper ones are split by interval bisection first).
    pub leaf_depth_px: f64,
    /// A leaf's slab is narrowed to the part that may hold the surface by
    /// interval evaluations over sub-slabs about this many pixel footprints
    /// deep (0: not narrowed).
    pub narrow_px: f64,
    /// A ray sampled in this many leaf slabs without a crossing has the
    /// rest of its depth range checked with one interval evaluation (of the
    /// tape shortened for its tile), where that is likely to cost less than
    /// sampling on, and is searched no further where that is outside; the
    /// next check waits twice as many slabs (0: never checked).
    pub prune_after: u32,
    /// Whether the leaves of an orthographic view straight along a
    /// coordinate axis are evaluated as lines ([`BatchEval::eval_lines`]:
    /// expensive functions of the other two coordinates once per ray, of
    /// the axis one once per depth; the same values). Default on; off for
    /// comparisons.
    pub lines: bool,
    /// Whether the slabs of a frustum where the (shortened) tape is a
    /// polynomial of degree 2 in the point (a quadric) have their rays'
    /// crossings solved in closed form from 3 samples each, and checked by
    /// the value and gradient there, not sampled and searched (see the
    /// module docs). Default on; off for comparisons.
    pub exact: bool,
    /// Whether the rays of such a slab on a quadric, for a model with no
    /// colours, are solved in blocks of up to a leaf's, the common case in
    /// a pass over arrays that vectorises
    /// (`TileCtx::quadric_block`), not one at a time: the same hits, bit
    /// for bit, for about 30 % fewer instructions on a sphere's top view.
    /// Default on; off for comparisons.
    pub quadric_blocks: bool,
    /// Whether, for a model with no colours that is a set expression over
    /// quadrics (R-functions, `min`, `max` and negations over at most 8
    /// fields of degree at most 2 in the point, or root gaps `k − sqrt(p)`
    /// of one: spheres, cylinders, planes, ...), each tile's rays are first
    /// solved in closed form, every leaf's
    /// crossings found and the expression checked after each
    /// (`raycast::csg`); the rays that fail a check are cast the usual way.
    /// Default on; off for comparisons.
    pub csg: bool,
    /// The model's set expression, where it is one ([`ModelCaster::csg`]).
    csg_tree: Option<Csg>,
    /// How the batch evaluators of samples, refinement and normals compute
    /// `sin` and `cos`. Default [`Trig::Fast`] (within about `2e-14` of
    /// the value, not an ulp: a sign test at a sample, a hit refined to a
    /// fraction of a footprint and a normal for shading need no more; the
    /// gyroid's frame costs about a tenth less time); [`Trig::Exact`] for
    /// comparisons. Interval evaluations stay exact.
    pub trig: Trig,
    stats: AtomicStats,
    /// Per-thread evaluators and buffers, reused from tile to tile, each
    /// with the rayon thread that last used it: that thread takes it
    /// again (its caches warm in that core's), another one only when none
    /// of its own is free.
    pool: Mutex<Vec<(Option<usize>, Box<Scratch>)>>,
}

impl ModelCaster {
    /// A caster of `model` with these parameter values, clipped to `bounds`.
    pub fn new(model: &Model, inputs: Inputs, bounds: Aabb) -> ModelCaster {
        ModelCaster {
            attr_tape: model
                .attribute_tape()
                .filter(|t| model.s_dim >= 3 && t.outputs.len() >= 3),
            ..ModelCaster::from_tape(model.tape(), inputs, bounds)
        }
    }

    /// A caster of a bare tape (output 0 is the field, positive inside).
    pub fn from_tape(tape: Tape, inputs: Inputs, bounds: Aabb) -> ModelCaster {
        let csg_tree = Csg::of(&tape, &inputs, &bounds);
        ModelCaster {
            tape,
            attr_tape: None,
            inputs,
            bounds,
            cancel: None,
            step_px: 2.0,
            fallback_depth: 3,
            leaf_depth_px: 16.0,
            narrow_px: 4.0,
            prune_after: 3,
            lines: true,
            exact: true,
            quadric_blocks: true,
            csg: true,
            csg_tree,
            trig: Trig::Fast,
            stats: AtomicStats::default(),
            pool: Mutex::new(Vec::new()),
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
            empty_tiles: self.stats.empty_tiles.load(Ordering::Relaxed),
            line_points: self.stats.line_points.load(Ordering::Relaxed),
            exact_rays: self.stats.exact_rays.load(Ordering::Relaxed),
        }
    }

    /// The tile's box ([`ModelCaster::tile_box`]), unless the tile's whole
    /// frustum within the model box's depth range is outside (one interval
    /// evaluation of the root tape) or misses the box: then `None`, and
    /// none of its rays is set up. The box holds every box the tile's root
    /// node would evaluate, so nothing that node would find is skipped.
    fn live_tile_box(
        &self,
        camera: &Camera,
        rm: &RayMaker,
        tile: &Tile,
        sc: &mut Scratch,
    ) -> Option<Aabb> {
        self.tile_box(camera, rm, tile)
            .filter(|bx| !self.outside_in(bx, sc))
    }

    /// A box holding the parts of `tile`'s rays (`rm`, of `camera`) inside
    /// the model box; `None` where they miss it.
    fn tile_box(&self, camera: &Camera, rm: &RayMaker, tile: &Tile) -> Option<Aabb> {
        let b = &self.bounds;
        let (lo, hi) = depth_range(b, camera);
        let lo = lo.max(0.0);
        if lo > hi || hi.is_nan() {
            return None;
        }
        let k = Corners::of(rm, tile.x0, tile.y0, tile.x1, tile.y1);
        clip_box(&k.aabb(lo, hi), b)
    }

    /// Whether the model is outside the solid throughout `bx` (by the
    /// interval evaluator of the whole tape).
    fn outside_in(&self, bx: &Aabb, sc: &mut Scratch) -> bool {
        sc.evals[0]
            .interval
            .eval(
                iv(bx.min[0], bx.max[0]),
                iv(bx.min[1], bx.max[1]),
                iv(bx.min[2], bx.max[2]),
                &self.inputs,
            )
            .is_outside()
    }

    /// Whether a ray of the tile whose rays inside the model box lie in
    /// `bx` ([`ModelCaster::tile_box`]) may be inside the solid where it
    /// enters the box: `false` where the model is outside throughout the
    /// part of `bx` on each face of the box that such rays can enter by
    /// (a face whose plane has the eye, or in an orthographic view the
    /// rays' start, on its outer side). `true` where rays may start inside
    /// the box (its nearest corner is not in front of the eye).
    /// (Each face's check is counted in `stats`.)
    fn may_hold_at_entry(
        &self,
        camera: &Camera,
        bx: &Aabb,
        sc: &mut Scratch,
        stats: &mut CastStats,
    ) -> bool {
        let b = &self.bounds;
        if depth_range(b, camera).0 <= 0.0 {
            return true;
        }
        let ortho = matches!(camera.projection, Projection::Orthographic { .. });
        for a in 0..3 {
            for (face, low) in [(b.min[a], true), (b.max[a], false)] {
                // Rays enter by the face at `b.min[a]` going up axis `a`.
                let enters = match (ortho, low) {
                    (true, true) => camera.forward[a] > 0.0,
                    (true, false) => camera.forward[a] < 0.0,
                    (false, true) => camera.eye[a] < face,
                    (false, false) => camera.eye[a] > face,
                };
                // (`bx` is within the model box: no ray of the tile enters
                // by a face it does not reach.)
                if !enters || face < bx.min[a] || face > bx.max[a] {
                    continue;
                }
                let mut f = *bx;
                (f.min[a], f.max[a]) = (face, face);
                stats.interval_evals += 1;
                if !self.outside_in(&f, sc) {
                    return true;
                }
            }
        }
        false
    }

    fn cancelled(&self) -> bool {
        self.cancel
            .as_ref()
            .is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

impl TileCaster for ModelCaster {
    fn cast_tile(&self, camera: &Camera, tile: &Tile, out: &mut [Option<Hit>]) {
        self.cast_tile_hits(camera, tile, out);
    }
}

impl ModelCaster {
    /// [`TileCaster::cast_tile`], telling whether any ray hit (`out` is
    /// not written where none did).
    fn cast_tile_hits(&self, camera: &Camera, tile: &Tile, out: &mut [Option<Hit>]) -> bool {
        if self.cancelled() {
            return false;
        }
        let mut scratch = self.take_scratch();
        // The rays of this image size, for the check and the tile's rays.
        let rm = camera.rays(tile.width, tile.height);
        let empty = self
            .live_tile_box(camera, &rm, tile, &mut scratch)
            .is_none();
        let (mut stats, any_hit) = if empty {
            let stats = CastStats {
                empty_tiles: 1,
                ..CastStats::default()
            };
            (stats, false)
        } else {
            let mut ctx = TileCtx::new(self, camera, rm, tile, out, &mut scratch);
            ctx.run();
            (ctx.stats, ctx.any_hit)
        };
        // The tile's own check.
        stats.interval_evals += 1;
        self.put_scratch(scratch);
        self.add_stats(&stats);
        any_hit
    }

    /// A [`Scratch`] from the pool (the one this thread last used where it
    /// is free), or a new one.
    fn take_scratch(&self) -> Box<Scratch> {
        let me = rayon::current_thread_index();
        let scratch = self.pool.lock().ok().and_then(|mut p| {
            let j = p
                .iter()
                .rposition(|(o, _)| *o == me)
                .or(p.len().checked_sub(1))?;
            Some(p.swap_remove(j).1)
        });
        let mut scratch = scratch.unwrap_or_else(|| Box::new(Scratch::new(&self.tape)));
        scratch.trim();
        scratch.trig = self.trig;
        scratch
    }

    /// Returns `scratch` to the pool.
    fn put_scratch(&self, scratch: Box<Scratch>) {
        if let Ok(mut p) = self.pool.lock() {
            p.push((rayon::current_thread_index(), scratch));
        }
    }

    /// Adds a tile's counts to the caster's.
    fn add_stats(&self, stats: &CastStats) {
        let s = &self.stats;
        s.interval_evals
            .fetch_add(stats.interval_evals, Ordering::Relaxed);
        s.point_evals
            .fetch_add(stats.point_evals, Ordering::Relaxed);
        s.grad_evals.fetch_add(stats.grad_evals, Ordering::Relaxed);
        s.simplified.fetch_add(stats.simplified, Ordering::Relaxed);
        s.empty_tiles
            .fetch_add(stats.empty_tiles, Ordering::Relaxed);
        s.line_points
            .fetch_add(stats.line_points, Ordering::Relaxed);
        s.exact_rays.fetch_add(stats.exact_rays, Ordering::Relaxed);
    }

    /// Casts and shades `tile` in closed form on the model's set expression
    /// ([`ModelCaster::csg`]) straight into its `rows` of RGBA bytes (no hit
    /// records), [`BLOCK`] rays at a time: for [`render_with`] where no
    /// colours and no ambient occlusion are due. Returns `false`, leaving
    /// the tile to the general caster (its rows then partly written), where
    /// a ray fails a check of [`Csg::solve`], is inside the solid at the
    /// eye, or the render was cancelled. The rays' entry into the model box
    /// is tried as a hit only where [`ModelCaster::may_hold_at_entry`]
    /// cannot rule it out.
    fn closed_form_tile(
        &self,
        csg: &Csg,
        camera: &Camera,
        shader: &Shader,
        tile: &Tile,
        rows: &mut [&mut [u8]],
    ) -> bool {
        if self.cancelled() {
            return false;
        }
        let mut sc = self.take_scratch();
        let mut stats = CastStats {
            interval_evals: 1,
            ..CastStats::default()
        };
        let done = self.closed_form_rows(csg, camera, shader, tile, rows, &mut sc, &mut stats);
        self.put_scratch(sc);
        self.add_stats(&stats);
        done
    }

    /// [`ModelCaster::closed_form_tile`] with a scratch.
    #[allow(clippy::too_many_arguments)]
    fn closed_form_rows(
        &self,
        csg: &Csg,
        camera: &Camera,
        shader: &Shader,
        tile: &Tile,
        rows: &mut [&mut [u8]],
        sc: &mut Scratch,
        stats: &mut CastStats,
    ) -> bool {
        const L: usize = SETUP_LANES;
        let rm = camera.rays(tile.width, tile.height);
        // (Every pixel below is written whole, alpha 255 included.)
        let Some(bx) = self.live_tile_box(camera, &rm, tile, sc) else {
            stats.empty_tiles += 1;
            for (row, y) in rows.iter_mut().zip(tile.y0..) {
                fill_background(shader.background(y), row);
            }
            return true;
        };
        // Whether any ray may hit where it enters the box (else that
        // candidate is not checked).
        let entry = self.may_hold_at_entry(camera, &bx, sc, stats);
        let forward = camera.forward;
        let fixed = matches!(camera.projection, Projection::Orthographic { .. })
            .then(|| per_dir(forward, forward));
        let mut cf = sc.closed_form.take().unwrap_or_default();
        // (Orthographic: the origins' per-column terms, which every row
        // shares, once per tile.)
        let cols = &mut sc.columns;
        if fixed.is_some() {
            cols.resize((tile.x1 - tile.x0) as usize, 0.0);
            rm.ortho_columns(tile.x0, cols);
        }
        let (lanes, work, solved) = &mut *cf;
        // (Every ray of an orthographic view has the camera's direction:
        // the direction arrays are written once here, not per ray.)
        lanes.dir = fixed.map(|(_, dz, _)| dz);
        if let Some((_, dz, _)) = fixed {
            for (d, v) in lanes.d.iter_mut().zip(dz) {
                *d = [v; BLOCK];
            }
        }
        // Normals and positions of a partial pass (a whole one is read
        // where the solver wrote it).
        let mut shade = ([[0.0; SPAN]; 3], [[0.0; SPAN]; 3]);
        // The block's runs of pixels: (row, first column, first lane,
        // length).
        let mut runs = [(0u32, 0u32, 0usize, 0usize); BLOCK];
        let r = &mut RayLanes::default();
        let (mut nruns, mut n) = (0, 0);
        let mut ok = true;
        'rows: for py in tile.y0..tile.y1 {
            let mut x = tile.x0;
            while x < tile.x1 {
                let len = ((tile.x1 - x) as usize).min(BLOCK);
                if n + len > BLOCK {
                    ok = self.closed_form_block(
                        (csg, entry),
                        tile,
                        shader,
                        rows,
                        (lanes, work, solved),
                        &runs[..nruns],
                        n,
                        &mut shade,
                        stats,
                    );
                    if !ok {
                        break 'rows;
                    }
                    (nruns, n) = (0, 0);
                }
                let mut j = 0;
                while j < len {
                    let (k, m) = (n + j, L.min(len - j));
                    if let (Some((c, _, inv)), true) = (fixed, m == L) {
                        // (Straight into the lanes: origins and depths.)
                        let c0 = (x - tile.x0) as usize + j;
                        let uk = cols[c0..c0 + L].try_into().expect("SETUP_LANES columns");
                        ortho_lanes(&self.bounds, (c, inv), &rm, (uk, py), lanes, k);
                        j += L;
                        continue;
                    }
                    ray_lanes(&self.bounds, forward, fixed, &rm, (x + j as u32, py), r);
                    if m == L {
                        // (A copy of known length: no call. The other
                        // case is a function of its own, so that the
                        // compiler does not merge the two into one copy
                        // of either length, a call.)
                        for a in 0..3 {
                            lanes.o[a][k..k + L].copy_from_slice(&r.o[a]);
                            lanes.d[a][k..k + L].copy_from_slice(&r.dz[a]);
                        }
                        lanes.z0[k..k + L].copy_from_slice(&r.z0);
                        lanes.z1[k..k + L].copy_from_slice(&r.z1);
                    } else {
                        put_ray_lanes(lanes, r, k, m);
                    }
                    j += L;
                }
                runs[nruns] = (py, x, n, len);
                nruns += 1;
                n += len;
                x += len as u32;
            }
        }
        if ok && n > 0 {
            ok = self.closed_form_block(
                (csg, entry),
                tile,
                shader,
                rows,
                (lanes, work, solved),
                &runs[..nruns],
                n,
                &mut shade,
                stats,
            );
        }
        sc.closed_form = Some(cf);
        ok
    }

    /// Solves the `n` rays of a block of [`ModelCaster::closed_form_rows`]
    /// and shades its `runs` of pixels; `false` where a ray is unsure.
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn closed_form_block(
        &self,
        (csg, entry): (&Csg, bool),
        tile: &Tile,
        shader: &Shader,
        rows: &mut [&mut [u8]],
        (lanes, work, solved): (&mut Lanes, &mut Work, &mut Solved),
        runs: &[(u32, u32, usize, usize)],
        n: usize,
        (sn, sp): &mut ([[f64; SPAN]; 3], [[f64; SPAN]; 3]),
        stats: &mut CastStats,
    ) -> bool {
        csg.solve(lanes, n, work, solved, entry);
        let live = solved.live;
        if live & !solved.sure != 0 {
            return false;
        }
        stats.exact_rays += u64::from(live.count_ones());
        // Hits at the entry into the box: the box face's normal.
        let mut entries = solved.entry;
        while entries != 0 {
            let k = entries.trailing_zeros() as usize;
            entries &= entries - 1;
            let p = [solved.p[0][k], solved.p[1][k], solved.p[2][k]];
            match (solved.z[k] > 0.0)
                .then(|| entry_face(&self.bounds, &p))
                .flatten()
            {
                Some(f) => (0..3).for_each(|a| solved.n[a][k] = f[a]),
                None => return false,
            }
        }
        // Positions are read in perspective views only.
        let persp = shader.needs_positions();
        for &(py, x, first, len) in runs {
            let row = &mut rows[(py - tile.y0) as usize];
            let bg = shader.background(py);
            let mut c = 0;
            while c < len {
                let (m, k) = ((len - c).min(SPAN), first + c);
                let o = 4 * (x - tile.x0) as usize + 4 * c;
                let hit = ((solved.hit >> k) & (u64::MAX >> (64 - m))) as u32;
                if hit == 0 {
                    fill_background(bg, &mut row[o..o + 4 * m]);
                    c += m;
                    continue;
                }
                let span = (m == SPAN).then(|| (span_at(&solved.n, k), span_at(&solved.p, k)));
                let (n, p) = match span {
                    // A whole pass: read where the solver wrote (no copy).
                    Some((Some(n), Some(p))) => (n, p),
                    _ => {
                        for a in 0..3 {
                            sn[a][..m].copy_from_slice(&solved.n[a][k..k + m]);
                            if persp {
                                sp[a][..m].copy_from_slice(&solved.p[a][k..k + m]);
                            }
                        }
                        (sn.each_ref(), sp.each_ref())
                    }
                };
                // (The default material, fully open: no colours, no
                // occlusion here.)
                let lanes = ShadeIn {
                    n,
                    p,
                    material: None,
                };
                shader.shade_lanes(bg, lanes, hit, &mut row[o..o + 4 * m]);
                c += m;
            }
        }
        true
    }
}

/// Lanes `k..k + SPAN` of three arrays of a block, where they lie within
/// it.
fn span_at(v: &[[f64; BLOCK]; 3], k: usize) -> Option<[&[f64; SPAN]; 3]> {
    let [a, b, c] = v.each_ref().map(|v| v[k..].first_chunk::<SPAN>());
    Some([a?, b?, c?])
}

/// The evaluators of one (possibly shortened) tape.
struct Evals {
    tape: Tape,
    /// What of the interval choices simplifying can read: the keys of the
    /// cache of shortened tapes, and whether [`SimplifyMode::Sign`] can ever
    /// shorten the tape ([`ChoiceMask::can_shorten`]).
    mask: ChoiceMask,
    interval: IntervalEval,
    batch: Option<BatchEval>,
    /// Where the field along every ray is a polynomial of degree at most 2,
    /// up to a map that keeps its sign, so that three samples give it (see
    /// [`TileCtx::exact`]): `Some(0.0)` where the field is a polynomial of
    /// degree 2 in the point ([`Tape::polynomial_degree`]), `Some(k)` where
    /// it is `k − sqrt(p)` with `p` one ([`Tape::root_gap`]; samples `f` map
    /// to `f·(2k − f) = k² − p`).
    ///
    /// Also `Some(0.0)` where the field is affine in the point (degree 1,
    /// `affine`): its values along each ray then come from [`Evals::plane`]
    /// without samples.
    exact: Option<f64>,
    /// Whether the field is affine in the point (a plane).
    affine: bool,
    /// For an affine field, `[c, gx, gy, gz]` with `f(p) = c + g·p`, once
    /// computed (the value and gradient at one point): `None` until then,
    /// `Some(None)` where those were not finite.
    plane: Option<Option<[f64; 4]>>,
    /// For a field of degree 2 or a root gap (`exact`, not `affine`), the
    /// quadric with its sign ([`Quadric`]), once computed: `None` until
    /// then, `Some(None)` where it could not be (values not finite, or not
    /// those of a quadric: [`TileCtx::quadric`]).
    quadric: Option<Option<Quadric>>,
}

/// A polynomial of degree 2 in the point, about a point `p0`:
/// `q(p0 + u) = c + g·u + uᵀ·A·u` (`a` symmetric). For a field of degree 2
/// it is the field; for a root gap `k − sqrt(p)` it is `k² − p`, which has
/// the field's sign and, on the surface, the direction of its gradient
/// (`∇q = 2(k − f)·∇f`). Along a ray `p = o + dz·z` it is a polynomial of
/// degree 2 in the depth: no samples are needed ([`TileCtx::exact`]).
#[derive(Clone, Copy, Debug)]
struct Quadric {
    p0: [f64; 3],
    c: f64,
    g: [f64; 3],
    a: [[f64; 3]; 3],
}

impl Quadric {
    /// `(α, β, γ)` with `q(o + dz·z) = α z² + β z + γ` along ray `r`.
    #[inline]
    fn along(&self, r: &RayInfo) -> (f64, f64, f64) {
        self.along_ray(r.origin, r.dz)
    }

    /// [`Quadric::along`] for the ray `origin + dz·z`.
    #[inline(always)]
    fn along_ray(&self, origin: [f64; 3], dz: [f64; 3]) -> (f64, f64, f64) {
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
    fn hit(&self, r: &RayInfo, z: f64) -> Option<Hit> {
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
    fn fit_step(b: &Aabb) -> f64 {
        0.25 * (0..3).map(|a| b.max[a] - b.min[a]).fold(0.0, f64::max)
    }

    /// The points a quadric is fitted at ([`Quadric::fit`]): `p0`, and `h`
    /// from it along each axis.
    fn fit_points(p0: [f64; 3], h: f64) -> [[f64; 3]; 4] {
        std::array::from_fn(|j| {
            let mut p = p0;
            if j > 0 {
                p[j - 1] += h;
            }
            p
        })
    }

    /// The quadric about `p0` with the values and gradients `qs` at its
    /// [`Quadric::fit_points`]: the value and gradient at `p0`, and `A`
    /// from the differences of the gradients (a quadric's gradient is
    /// affine: exact but for rounding), symmetrised.
    fn fit(p0: [f64; 3], h: f64, qs: &[(f64, [f64; 3]); 4]) -> Quadric {
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
    fn value_and_scale(&self, p: [f64; 3]) -> (f64, f64) {
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
    fn grad(&self, p: [f64; 3]) -> [f64; 3] {
        let u = sub(p, self.p0);
        let a = &self.a;
        [
            self.g[0] + 2.0 * dot(a[0], u),
            self.g[1] + 2.0 * dot(a[1], u),
            self.g[2] + 2.0 * dot(a[2], u),
        ]
    }
}

impl Evals {
    fn new(tape: Tape) -> Evals {
        let degree = tape.polynomial_degree();
        Evals {
            interval: IntervalEval::new(&tape),
            mask: ChoiceMask::new(&tape, SimplifyMode::Sign),
            exact: match degree {
                Some(1 | 2) => Some(0.0),
                _ => tape.root_gap(),
            },
            affine: degree == Some(1),
            plane: None,
            quadric: None,
            tape,
            batch: None,
        }
    }

    fn batch(&mut self) -> &mut BatchEval {
        let tape = &self.tape;
        self.batch.get_or_insert_with(|| BatchEval::new(tape))
    }
}

/// Above about this many bytes of evaluators held by one [`Scratch`], its
/// cache of shortened tapes is cleared (between tiles) to bound memory.
const CACHE_BYTES: usize = 6 << 20;
/// Bytes per tape node of a cached [`Evals`] (the tape, the interval
/// evaluator's values and choices, the batch evaluator's maps, the gradient
/// evaluator's values), roughly.
const NODE_BYTES: usize = 160;

/// (parent evaluator, the key of its interval choices ([`ChoiceMask::key`]),
/// child evaluator).
type ChildEntry = (u32, Box<[Choice]>, u32);

/// Per-thread state of the caster, reused from tile to tile: the evaluators
/// of the root tape and of every shortened tape met so far (keyed by the
/// interval choices that produced them, so a tape is never simplified or
/// compiled twice), and the buffers of a tile.
struct Scratch {
    /// `evals[0]` is the root tape's.
    evals: Vec<Evals>,
    /// The arrays of the closed form on set expressions
    /// ([`TileCtx::closed_form`], [`ModelCaster::closed_form_tile`]), once
    /// used.
    closed_form: Option<Box<(Lanes, Work, Solved)>>,
    /// The closed form's per-column terms of an orthographic tile's ray
    /// origins ([`RayMaker::ortho_columns`]).
    columns: Vec<f64>,
    /// Hash of (parent, choices) → (parent, choices, child): the child is
    /// the parent itself where simplifying does not shorten the tape.
    children: FastMap<u64, Vec<ChildEntry>>,
    /// Hash of a shortened tape → the evaluators holding it (different
    /// boxes often shorten to the same tape).
    by_tape: FastMap<u64, Vec<u32>>,
    /// Estimated bytes of `evals`.
    bytes: usize,
    /// The key of the box being shortened, then its choices (see
    /// [`TileCtx::shorten`]).
    choices: Vec<Choice>,
    /// [`TileCtx::shorten`]'s buffers for simplifying (as long as the root
    /// tape at most).
    simplifier: Simplifier,
    attr: Option<BatchEval>,
    /// The attribute tape's interval evaluator, for colours constant over
    /// a tile's hits ([`TileCtx::colors`]).
    attr_iv: Option<IntervalEval>,
    rays: Vec<RayInfo>,
    /// Per ray, its depth range `[z0s, z1s]` while it is live and
    /// unresolved, else `[+∞, −∞]`.
    z0s: Vec<f64>,
    z1s: Vec<f64>,
    /// Bumped whenever rays are taken out of the depth ranges (see
    /// [`TileCtx::node`]'s `held`).
    epoch: u64,
    /// Rays whose hit still needs its normal (see [`TileCtx::flush_normals`]).
    need_normal: Vec<usize>,
    tails: Vec<Tail>,
    /// Per ray: leaf slabs sampled without a crossing since its last
    /// check fell due, and the checks that fell due (see
    /// [`ModelCaster::prune_after`]).
    misses: Vec<(u16, u8)>,
    /// Rays due for that check: (ray, depth it starts at).
    prune: Vec<(usize, f64)>,
    /// Those checks made so far by this thread, and those that found the
    /// rest of the ray outside (their success rate weighs the next ones).
    prune_tried: u32,
    prune_hit: u32,
    /// Points to evaluate: the first `np` of `xs`, `ys`, `zs` (the
    /// buffers only grow), and their values in the first `np` of `vals`.
    xs: Vec<f64>,
    ys: Vec<f64>,
    zs: Vec<f64>,
    np: usize,
    vals: Vec<f64>,
    /// Values and gradients at the first `np` points (see
    /// [`Scratch::eval_grads`]).
    grads: Vec<Grad>,
    /// Inverse gradient lengths ([`TileCtx::polish`]).
    inv_len: Vec<f64>,
    /// Working registers of [`BatchEval::eval_grad`] (for every tape).
    grad_regs: GradRegs,
    /// Per ray of the current leaf: (tile ray index, lo depth, hi depth).
    leaf_rays: Vec<(usize, f64, f64)>,
    /// The rays [`TileCtx::exact`] found no crossing on, and their depth
    /// ranges while they are set aside (see [`TileCtx::node`]).
    settled: Vec<usize>,
    hidden: Vec<(usize, f64, f64)>,
    /// [`TileCtx::exact`]'s rays to sample.
    fresh: Vec<(usize, f64, f64)>,
    /// Per ray of the tile, its polynomial on the last exact evaluator it
    /// was sampled on (entries of earlier tiles are stale by their tag).
    polys: Vec<RayPoly>,
    /// Counts the tiles this scratch cast.
    tile_gen: u64,
    brackets: Vec<Bracket>,
    /// Rays whose first sample is inside: (ray, depth, at the model box
    /// entry).
    direct: Vec<(usize, f64, bool)>,
    searches: Vec<Search>,
    /// Which of `searches` [`TileCtx::check_searches`] keeps; empty
    /// between uses.
    search_keep: Vec<bool>,
    /// Tails to search (see [`TileCtx::search_tails`]).
    tail_list: Vec<(usize, Tail)>,
    hit_rays: Vec<usize>,
    fracs: Vec<f64>,
    /// Crossings found but not refined yet and direct hits not recorded
    /// yet, one group per evaluator (see [`TileCtx::finish`]): the tile's
    /// are the first `groups`; the others are kept (empty) for their
    /// buffers' capacity.
    deferred: Vec<Deferred>,
    groups: usize,
    /// Buffers lent in place of `brackets`, `direct`, `searches` and
    /// `need_normal` while [`TileCtx::search_tails`] sets those aside, kept
    /// (empty) for their capacity: no allocation per search.
    spare_brackets: Vec<Bracket>,
    spare_direct: Vec<(usize, f64, bool)>,
    spare_searches: Vec<Search>,
    spare_need: Vec<usize>,
    /// Pending tails a leaf searches before its own samples (see
    /// [`TileCtx::leaf`]); empty between uses.
    resolve_first: Vec<(usize, Tail)>,
    /// [`TileCtx::refine`]'s brackets still too wide, and their trial depths.
    refine_active: Vec<usize>,
    refine_trials: Vec<(f64, f64, usize)>,
    /// The caster's [`ModelCaster::trig`], for the batch evaluators (set
    /// at each use).
    trig: Trig,
}

/// A thin-feature search: (ray, lo depth, hi depth, f at lo, finest cell
/// length).
type Search = (usize, f64, f64, f64, f64);

/// The crossings and direct hits of one evaluator waiting for the end of
/// the tile ([`TileCtx::finish`], [`TileCtx::flush_deferred`]).
#[derive(Default)]
struct Deferred {
    e: u32,
    brackets: Vec<Bracket>,
    /// (ray, depth, at the model box entry), as [`Scratch::direct`].
    direct: Vec<(usize, f64, bool)>,
}

/// Moves all of `from` to the end of `to`, leaving `from` empty: the
/// buffers are swapped (nothing copied) where `to` is empty.
fn move_all<T>(from: &mut Vec<T>, to: &mut Vec<T>) {
    if to.is_empty() {
        std::mem::swap(from, to);
    } else {
        to.append(from);
    }
}

/// Sets `slot`'s buffer aside and lends it `spare`'s (empty) meanwhile.
fn set_aside<T>(slot: &mut Vec<T>, spare: &mut Vec<T>) -> Vec<T> {
    std::mem::replace(slot, std::mem::take(spare))
}

/// Puts `kept` back in `slot`; the lent buffer, emptied, becomes the spare
/// again (its capacity kept).
fn put_back<T>(slot: &mut Vec<T>, kept: Vec<T>, spare: &mut Vec<T>) {
    let mut lent = std::mem::replace(slot, kept);
    lent.clear();
    *spare = lent;
}

impl Scratch {
    fn new(tape: &Tape) -> Scratch {
        Scratch {
            evals: vec![Evals::new(tape.clone())],
            closed_form: None,
            columns: Vec::new(),
            children: FastMap::default(),
            by_tape: FastMap::default(),
            bytes: tape.len() * NODE_BYTES,
            choices: Vec::new(),
            simplifier: Simplifier::default(),
            attr: None,
            attr_iv: None,
            rays: Vec::new(),
            z0s: Vec::new(),
            z1s: Vec::new(),
            epoch: 0,
            need_normal: Vec::new(),
            tails: Vec::new(),
            misses: Vec::new(),
            prune: Vec::new(),
            prune_tried: 0,
            prune_hit: 0,
            xs: Vec::new(),
            ys: Vec::new(),
            zs: Vec::new(),
            np: 0,
            vals: Vec::new(),
            grads: Vec::new(),
            inv_len: Vec::new(),
            grad_regs: GradRegs::default(),
            leaf_rays: Vec::new(),
            settled: Vec::new(),
            hidden: Vec::new(),
            fresh: Vec::new(),
            polys: Vec::new(),
            tile_gen: 0,
            brackets: Vec::new(),
            direct: Vec::new(),
            searches: Vec::new(),
            tail_list: Vec::new(),
            hit_rays: Vec::new(),
            fracs: Vec::new(),
            deferred: Vec::new(),
            groups: 0,
            spare_brackets: Vec::new(),
            spare_direct: Vec::new(),
            spare_searches: Vec::new(),
            spare_need: Vec::new(),
            resolve_first: Vec::new(),
            search_keep: Vec::new(),
            refine_active: Vec::new(),
            refine_trials: Vec::new(),
            trig: Trig::Exact,
        }
    }

    /// Drops the shortened tapes' evaluators when they hold too much.
    fn trim(&mut self) {
        if self.bytes > CACHE_BYTES {
            self.evals.truncate(1);
            self.children.clear();
            self.by_tape.clear();
            self.bytes = self.evals[0].tape.len() * NODE_BYTES
                + self.evals[0].batch.as_mut().map_or(0, batch_bytes);
        }
    }

    /// Evaluates output 0 of evaluator `e` at the buffered points into
    /// `vals`.
    fn eval_points(&mut self, e: usize, inputs: &Inputs) {
        self.eval_points_on(e, None, inputs);
    }

    /// [`Scratch::eval_points`]; with `lines = Some((axis, len, grid))`,
    /// for leaf points on lines along `axis`, `len` per ray
    /// ([`BatchEval::eval_lines`]; see [`Scratch::sampling`]).
    fn eval_points_on(&mut self, e: usize, lines: Option<(usize, usize, bool)>, inputs: &Inputs) {
        let n = self.np;
        if self.vals.len() < n {
            self.vals.resize(n, 0.0);
        }
        let b = counted_batch(&mut self.evals, &mut self.bytes, e, self.trig);
        let (xs, ys, zs) = (&self.xs[..n], &self.ys[..n], &self.zs[..n]);
        let out = &mut self.vals[..n];
        match lines {
            Some((axis, len, grid)) => b.eval_lines(axis, len, grid, xs, ys, zs, inputs, out),
            None => b.eval(xs, ys, zs, inputs, out),
        }
    }

    /// How the leaf points just written (`leaf_rays` with `len` depths
    /// each) can be evaluated, where the rays run along coordinate axis
    /// `axis`: as lines where each ray's other two coordinates are the same
    /// bits at its first and last depth (so at all: the points are
    /// `origin + 0·t` there, and the depths are monotone), as a grid where
    /// moreover every ray has the first one's bits along the axis (the same
    /// depths, origins and steps there), else point by point. Checks
    /// [`TileCtx::lines`] in debug builds.
    fn sampling(&self, axis: usize, leaf_rays: &[(usize, f64, f64)], len: usize) -> Sampling {
        let (b, c) = match axis {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        let cs = [&self.xs, &self.ys, &self.zs];
        let same = |k: usize, i: usize, j: usize| cs[k][i].to_bits() == cs[k][j].to_bits();
        let lines = (0..leaf_rays.len()).all(|r| {
            let (i, j) = (r * len, r * len + len - 1);
            same(b, i, j) && same(c, i, j)
        });
        if !lines {
            return Sampling::Points;
        }
        let key = |&(i, lo, hi): &(usize, f64, f64)| {
            let r = &self.rays[i];
            [lo, hi, r.origin[axis], r.dz[axis]].map(f64::to_bits)
        };
        let first = leaf_rays.first().map(key);
        if leaf_rays.iter().all(|l| Some(key(l)) == first) {
            Sampling::Grid
        } else {
            Sampling::Lines
        }
    }

    /// Whether ray `i` is resolved (its hit found, perhaps not recorded
    /// yet) or dead.
    fn resolved(&self, i: usize) -> bool {
        self.z0s[i] == f64::INFINITY
    }

    /// Evaluates output 0 of evaluator `e` and its gradient at the
    /// buffered points into `grads`.
    fn eval_grads(&mut self, e: usize, inputs: &Inputs) {
        let n = self.np;
        if self.grads.len() < n {
            self.grads.resize(n, Grad::default());
        }
        counted_batch(&mut self.evals, &mut self.bytes, e, self.trig).eval_grad(
            &self.xs[..n],
            &self.ys[..n],
            &self.zs[..n],
            inputs,
            &mut self.grad_regs,
            &mut self.grads[..n],
        );
    }

    /// Takes ray `i` out of the depth ranges searched.
    fn resolve(&mut self, i: usize) {
        self.z0s[i] = f64::INFINITY;
        self.z1s[i] = f64::NEG_INFINITY;
        self.epoch += 1;
    }

    fn clear_points(&mut self) {
        self.np = 0;
    }

    fn push_point(&mut self, p: [f64; 3]) {
        if self.np < self.xs.len() {
            self.xs[self.np] = p[0];
            self.ys[self.np] = p[1];
            self.zs[self.np] = p[2];
        } else {
            self.xs.push(p[0]);
            self.ys.push(p[1]);
            self.zs.push(p[2]);
        }
        self.np += 1;
    }

    /// Makes room for `n` points (the buffers only grow: no clearing per
    /// batch), to be written by index.
    fn set_points(&mut self, n: usize) {
        if self.xs.len() < n {
            self.xs.resize(n, 0.0);
            self.ys.resize(n, 0.0);
            self.zs.resize(n, 0.0);
        }
        self.np = n;
    }
}

/// Evaluator `e`'s batch evaluator, its bytes added to `bytes` when it is
/// built here, set to compute `sin` and `cos` as `trig` says.
fn counted_batch<'e>(
    evals: &'e mut [Evals],
    bytes: &mut usize,
    e: usize,
    trig: Trig,
) -> &'e mut BatchEval {
    let ev = &mut evals[e];
    if ev.batch.is_none() {
        *bytes += batch_bytes(ev.batch());
    }
    let b = ev.batch();
    b.set_trig(trig);
    b
}

/// The bytes of a batch evaluator's registers and instructions, roughly.
fn batch_bytes(b: &mut BatchEval) -> usize {
    let (instrs, regs) = b.program_size();
    regs * LANES * 8 + instrs * 16
}

/// The key of a shortened tape in [`Scratch::by_tape`]: with
/// [`FastHasher`], not SipHash, which made hashing a fifth of the
/// shortening's cost.
fn tape_hash(t: &Tape) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = FastHasher::default();
    t.hash(&mut h);
    h.finish()
}

fn choices_hash(parent: usize, choices: &[Choice]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ parent as u64;
    for c in choices {
        let v = c.exact as u64 | (c.sign as u64) << 8 | (c.decided as u64) << 16;
        h = (h ^ v).wrapping_mul(0x0100_0000_01b3);
        h ^= h >> 29;
    }
    h
}

/// One pixel's ray, with its depth range inside the model box (depth = the
/// distance along the camera's viewing direction, `z = t · c`).
#[derive(Clone, Copy, Default)]
struct RayInfo {
    origin: [f64; 3],
    dir: [f64; 3],
    /// `dir / c`: the point at depth `z` is `origin + dz · z`.
    dz: [f64; 3],
    /// `dir · forward`.
    c: f64,
    z0: f64,
    z1: f64,
    live: bool,
}

impl RayInfo {
    #[inline]
    fn at_depth(&self, z: f64) -> [f64; 3] {
        [
            self.origin[0] + self.dz[0] * z,
            self.origin[1] + self.dz[1] * z,
            self.origin[2] + self.dz[2] * z,
        ]
    }

    /// The axis-aligned box of the ray's segment between depths `a` and
    /// `b`.
    fn segment_box(&self, a: f64, b: f64) -> Aabb {
        let (pa, pb) = (self.at_depth(a), self.at_depth(b));
        Aabb {
            min: std::array::from_fn(|k| pa[k].min(pb[k])),
            max: std::array::from_fn(|k| pa[k].max(pb[k])),
        }
    }
}

/// The corner rays of a pixel rectangle's frustum (through its outer pixel
/// edges), each as a point and its direction per unit depth, so that the
/// frustum's boxes between depths take no division (the depth-bisection
/// children of a node share them).
struct Corners {
    origin: [[f64; 3]; 4],
    dz: [[f64; 3]; 4],
}

impl Corners {
    /// The corner rays of the frustum of the image pixels
    /// `[x0, x1) × [y0, y1)`.
    fn of(rm: &RayMaker, x0: u32, y0: u32, x1: u32, y1: u32) -> Corners {
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
    fn aabb(&self, z0: f64, z1: f64) -> Aabb {
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

/// The last two samples of a ray's latest sampled slab without a crossing.
/// `pending`: the last sample is a local maximum so far (the field rises
/// towards the slab's end), so a feature thinner than a step may hide just
/// before it; the next contiguous slab tells whether the rise goes on, and
/// otherwise the segment is searched (before anything behind it is used).
#[derive(Clone, Copy, Default)]
struct Tail {
    valid: bool,
    pending: bool,
    ev: u32,
    z_prev: f64,
    f_prev: f64,
    z_last: f64,
}

/// How a leaf's sample points can be evaluated (see [`Scratch::sampling`]).
#[derive(Clone, Copy, PartialEq, PartialOrd)]
enum Sampling {
    /// Point by point.
    Points,
    /// As lines along the view's axis ([`BatchEval::eval_lines`]).
    Lines,
    /// As lines with the same depths on every ray.
    Grid,
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
#[derive(Clone, Copy)]
struct Bracket {
    ray: usize,
    lo: f64,
    hi: f64,
    f_lo: f64,
    f_hi: f64,
    /// Which end the last refinement step kept (−1 lo, 1 hi, 0 none), for
    /// the Illinois rule.
    kept: i8,
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

/// Where a polynomial along a ray first reaches `f ≥ 0` (see
/// [`RayPoly::first_root`]).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Root {
    /// At this depth.
    At(f64),
    /// Nowhere in the range: it stays below `0` by more than rounding.
    None,
    /// Within rounding of `0` without a clear crossing (a graze), or
    /// below `0` at the start by no more than rounding.
    Unsure,
}

/// The field along one ray on one evaluator whose tape is a polynomial of
/// degree at most 2 in the point ([`Tape::polynomial_degree`]), so along the
/// ray a polynomial of degree at most 2 in the depth:
/// `q(s) = a s² + b s + c` in the fraction `s = (z − lo) / w` of the slab
/// it was sampled over. It holds for the whole ray, not only that slab:
/// a later slab of the ray on the same evaluator needs no samples.
///
/// Where the tape is `k − sqrt(p)` instead ([`Tape::root_gap`]), `q` is
/// that of `f·(2k − f) = k² − p`, which has the field's sign
/// ([`RayPoly::field`] maps its values back).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct RayPoly {
    /// The tile's [`Scratch::tile_gen`] (high 32 bits) and the evaluator
    /// plus 1 (0: none yet).
    tag: u64,
    lo: f64,
    w: f64,
    a: f64,
    b: f64,
    c: f64,
    /// The largest magnitude sampled: the scale of rounding errors.
    scale: f64,
    /// The root gap `k` (`0`: `q` is the field's own polynomial).
    k: f64,
}

impl RayPoly {
    /// The polynomial through the values `[f0, fm, f1]` (finite) at `lo`,
    /// the middle and `hi`: the field's, or where the root gap `k` is
    /// positive those of `f·(2k − f)` ([`RayPoly::map`]).
    fn fit(tag: u64, lo: f64, hi: f64, [f0, fm, f1]: [f64; 3], k: f64) -> RayPoly {
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
    fn of_quadric(tag: u64, lo: f64, hi: f64, quad: &Quadric, r: &RayInfo, k: f64) -> RayPoly {
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
    fn coefficients(lo: f64, hi: f64, (al, be, ga): (f64, f64, f64)) -> [f64; 4] {
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
    fn map(f: f64, k: f64) -> f64 {
        if k > 0.0 {
            f * (2.0 * k - f)
        } else {
            f
        }
    }

    /// The field's value for the polynomial's value `q`: `q` itself, or
    /// for a root gap `k` the `f ≤ k` with `f·(2k − f) = q`, which is
    /// `q / (k + sqrt(k² − q))` (without cancellation near the surface).
    fn field(&self, q: f64) -> f64 {
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
    fn at(&self, z: f64) -> f64 {
        self.at_s(self.s_of(z))
    }

    /// The rounding error of values at fractions within `[s0, s1]`, taken
    /// as `1e-9` of the samples' scale, growing with the square of the
    /// distance from the sampled slab.
    fn tol_s(&self, s0: f64, s1: f64) -> f64 {
        1e-9 * self.scale * s0.abs().max(s1.abs()).max(1.0).powi(2)
    }

    /// [`RayPoly::tol_s`] between depths `za` and `zb`.
    fn tol(&self, za: f64, zb: f64) -> f64 {
        self.tol_s(self.s_of(za), self.s_of(zb))
    }

    /// Whether the polynomial, fitted over its own slab, is finite and
    /// clearly outside at the slab's start: below `−1e-9` of its scale,
    /// the rounding allowance there ([`TileCtx::take_fresh`]'s case).
    #[inline]
    fn fresh_outside(&self) -> bool {
        let finite = [self.a, self.b, self.c, self.scale]
            .iter()
            .all(|v| v.is_finite());
        finite && self.w > 0.0 && self.c < -1e-9 * self.scale
    }

    /// Whether the field is clearly defined at the slab's start: always,
    /// but for a root gap `k − sqrt(p)`, whose polynomial `q = k² − p`
    /// holds no trace of where `p < 0` (the field NaN, outside), only
    /// where `q` is below `k²` by more than rounding. (Before a crossing
    /// from `q < 0`, `p > k²`: only a slab that starts inside needs this.)
    fn defined_at_start(&self) -> bool {
        let k2 = self.k * self.k;
        self.k <= 0.0 || self.c < k2 - 1e-9 * self.scale.max(k2)
    }

    /// The smallest fraction past `s0` where `q = 0` (`∞` where none).
    #[inline]
    fn first_s(&self, s0: f64) -> f64 {
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
    fn first_root(&self, za: f64, zb: f64) -> Root {
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
    fn root_from(&self, s0: f64, s1: f64, q0: f64, tol: f64, za: f64, zb: f64) -> Root {
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

struct TileCtx<'a> {
    caster: &'a ModelCaster,
    rm: RayMaker,
    tile: &'a Tile,
    out: &'a mut [Option<Hit>],
    sc: &'a mut Scratch,
    tw: u32,
    /// The evaluator of the tape shortened for the whole tile's box (valid
    /// for every ray of the tile over its whole depth range), once the root
    /// node has shortened it.
    top: Option<usize>,
    /// The depth range every live ray of the tile shares, where they all
    /// share one (an orthographic view whose rays enter and leave the
    /// model box through faces square to them).
    uniform: Option<(f64, f64)>,
    /// Whether a hit was recorded.
    any_hit: bool,
    /// The coordinate axis every ray runs along, where they all do (an
    /// orthographic view straight along an axis) and share one depth range
    /// from 0 on, and whether their origins agree along it: a ray's other
    /// two coordinates are then the same bits at every depth (`o + 0·t`,
    /// `t >= 0`), and where the origins agree so are the axis coordinates of
    /// every ray of a leaf (their depths are the same): its samples are
    /// evaluated as lines, or a grid ([`BatchEval::eval_lines`]).
    lines: Option<(usize, bool)>,
    stats: CastStats,
}

/// A ray direction's `c = dir · forward` (at least 1e-12), `dz = dir / c`
/// and `1 / dir` (per component).
fn per_dir(d: [f64; 3], forward: [f64; 3]) -> (f64, [f64; 3], [f64; 3]) {
    let c = dot(d, forward).max(1e-12);
    (c, [d[0] / c, d[1] / c, d[2] / c], d.map(|v| 1.0 / v))
}

/// The outward normal of the face of box `b` that `p` lies on, if it does
/// (a hit where the solid is cut open by the box).
fn entry_face(b: &Aabb, p: &[f64; 3]) -> Option<[f64; 3]> {
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
const SETUP_LANES: usize = 16;

/// Sizes `sc.rays`, `sc.z0s` and `sc.z1s` for the tile and fills them with
/// its rays (`rm`, of `cam`), row by row: each ray's [`per_dir`] terms and
/// its depth range inside `bounds` ([`Ray::clip_inv`](crate::camera::Ray::clip_inv)), for
/// [`SETUP_LANES`] rays at a time in passes over arrays, which the compiler
/// turns into vector code. The same bits as one ray at a time. Returns the
/// [`per_dir`] terms all rays share (those of the camera's axis) in an
/// orthographic view.
fn set_up_rays(
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
fn put_ray_lanes(lanes: &mut Lanes, r: &RayLanes, k: usize, m: usize) {
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
struct RayLanes {
    o: [[f64; SETUP_LANES]; 3],
    d: [[f64; SETUP_LANES]; 3],
    dz: [[f64; SETUP_LANES]; 3],
    c: [f64; SETUP_LANES],
    z0: [f64; SETUP_LANES],
    z1: [f64; SETUP_LANES],
}

/// The rays of pixels `x..x + SETUP_LANES` of row `py` (`rm`, of a camera
/// looking along `forward`; `fixed`: the [`per_dir`] terms all rays share,
/// in an orthographic view) clipped to `bounds`, in passes over arrays
/// (which vectorise), into `out` (written in place: no copy of the
/// arrays): what [`set_up_rays`] sets up.
#[inline(always)]
fn ray_lanes(
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

/// The depths `z0 ≤ z1` of the part inside `bounds` of the `L` rays from
/// origins `o` with reciprocal directions `inv(axis, lane)` and depth
/// scales `c(lane)` (`[+∞, −∞]` where a ray misses it):
/// [`Ray::clip_inv`](crate::camera::Ray::clip_inv) with selects, the
/// depths `t·c`. (One body for [`ray_lanes`] and [`ortho_lanes`]: the same
/// bits.)
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

/// [`ray_lanes`] in an orthographic view (`c` and `inv`: the [`per_dir`]
/// terms of the camera's axis, which every ray shares) for the rays of
/// the pixels of columns `uk` ([`RayMaker::ortho_columns`]) of row `py`,
/// written straight into lanes
/// `k..k + SETUP_LANES` of `lanes`: their origins and depth ranges, the
/// same bits (the directions are the caller's, written once).
#[inline(always)]
fn ortho_lanes(
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

/// The least and greatest depth (distance along the viewing direction
/// from the eye; orthographic rays start on the eye's plane) of the
/// corners of box `b`, which bound its points'.
fn depth_range(b: &Aabb, camera: &Camera) -> (f64, f64) {
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
        rm: RayMaker,
        tile: &'a Tile,
        out: &'a mut [Option<Hit>],
        sc: &'a mut Scratch,
    ) -> TileCtx<'a> {
        let fixed = set_up_rays(&caster.bounds, cam, rm, tile, sc);
        let mut live = sc.rays.iter().filter(|r| r.live);
        let uniform = live.next().map(|r| (r.z0, r.z1)).filter(|&(z0, z1)| {
            live.all(|r| r.z0.to_bits() == z0.to_bits() && r.z1.to_bits() == z1.to_bits())
        });
        let axis = fixed.and_then(|(_, dz, _)| match dz.map(|v| v == 0.0) {
            [false, true, true] => Some(0),
            [true, false, true] => Some(1),
            [true, true, false] => Some(2),
            _ => None,
        });
        let lines = match (axis, uniform) {
            (Some(a), Some((z0, _))) if z0 >= 0.0 && caster.lines => {
                let mut live = sc.rays.iter().filter(|r| r.live);
                let o = live.next().map(|r| r.origin[a].to_bits());
                Some((a, live.all(|r| Some(r.origin[a].to_bits()) == o)))
            }
            _ => None,
        };
        debug_assert_eq!(sc.groups, 0, "the last tile's hits flushed");
        sc.tails.clear();
        sc.tails.resize(sc.rays.len(), Tail::default());
        sc.misses.clear();
        sc.misses.resize(sc.rays.len(), (0, 0));
        if sc.polys.len() < sc.rays.len() {
            sc.polys.resize(sc.rays.len(), RayPoly::default());
        }
        sc.tile_gen += 1;
        if sc.tile_gen > u64::from(u32::MAX) {
            sc.tile_gen = 1;
            sc.polys.fill(RayPoly::default());
        }
        TileCtx {
            caster,
            rm,
            tile,
            out,
            sc,
            tw: tile.w(),
            top: None,
            uniform,
            any_hit: false,
            lines,
            stats: CastStats::default(),
        }
    }

    fn footprint(&self, z: f64) -> f64 {
        self.rm.pixel_footprint(z)
    }

    fn run(&mut self) {
        if let Some(csg) = self.caster.csg_tree.as_ref() {
            if self.caster.csg && self.caster.attr_tape.is_none() {
                self.closed_form(csg);
            }
        }
        // The depth range of the live rays (a dead ray's is `[+∞, −∞]`).
        let zmin = self.sc.z0s.iter().fold(f64::INFINITY, |m, &z| m.min(z));
        let zmax = self.sc.z1s.iter().fold(f64::NEG_INFINITY, |m, &z| m.max(z));
        if zmin > zmax || zmin.is_nan() || zmax.is_nan() {
            return;
        }
        let rect = Rect {
            x0: 0,
            y0: 0,
            x1: self.tile.w(),
            y1: self.tile.h(),
        };
        let k = self.corners(rect);
        self.node(0, rect, &k, zmin, zmax, None, true);
        // Rays whose last samples rose to the end of their last slab.
        for i in 0..self.sc.rays.len() {
            if self.sc.tails[i].pending && !self.sc.resolved(i) {
                let t = self.sc.tails[i];
                self.sc.tails[i].pending = false;
                self.sc.tail_list.push((i, t));
            }
        }
        self.search_tails();
        self.flush_deferred();
    }

    /// Solves the tile's live rays in closed form on the model's set
    /// expression ([`ModelCaster::csg`]), [`BLOCK`] at a time: the hits and
    /// misses that check out are final, the other rays are left as they
    /// were.
    fn closed_form(&mut self, csg: &Csg) {
        let mut cf = self.sc.closed_form.take().unwrap_or_default();
        let (lanes, work, solved) = &mut *cf;
        // (Each lane's own direction: the arrays may come from a view
        // whose rays shared one.)
        lanes.dir = None;
        let mut idx = [0usize; BLOCK];
        let mut n = 0;
        for i in 0..self.sc.rays.len() {
            let (z0, z1) = (self.sc.z0s[i], self.sc.z1s[i]);
            if z0 > z1 {
                continue;
            }
            let r = &self.sc.rays[i];
            for a in 0..3 {
                lanes.o[a][n] = r.origin[a];
                lanes.d[a][n] = r.dz[a];
            }
            (lanes.z0[n], lanes.z1[n]) = (z0, z1);
            idx[n] = i;
            n += 1;
            if n == BLOCK {
                csg.solve(lanes, n, work, solved, true);
                self.take_solved(solved, &idx[..n]);
                n = 0;
            }
        }
        if n > 0 {
            csg.solve(lanes, n, work, solved, true);
            self.take_solved(solved, &idx[..n]);
        }
        self.sc.closed_form = Some(cf);
    }

    /// Records the sure outcomes of [`Csg::solve`] for rays `idx`.
    fn take_solved(&mut self, s: &Solved, idx: &[usize]) {
        for (k, &i) in idx.iter().enumerate() {
            if (s.sure >> k) & 1 == 0 {
                continue;
            }
            let z = s.z[k];
            if z == f64::INFINITY {
                self.sc.resolve(i);
                self.stats.exact_rays += 1;
                continue;
            }
            let r = &self.sc.rays[i];
            let position = [s.p[0][k], s.p[1][k], s.p[2][k]];
            let normal = if s.leaf[k] == ENTRY {
                // Inside where it enters the box: the box's face, as a
                // direct hit there gets (none at the eye: left alone).
                match (z > 0.0).then(|| self.entry_face(&position)).flatten() {
                    Some(n) => n,
                    None => continue,
                }
            } else {
                [s.n[0][k], s.n[1][k], s.n[2][k]]
            };
            let hit = Hit {
                t: z / r.c,
                position,
                normal,
                color: None,
            };
            self.set_hit(i, hit);
            self.stats.exact_rays += 1;
        }
    }

    /// Refines and records the deferred crossings and direct hits of the
    /// tile, one group per evaluator: refinement steps, normals and colours
    /// then run in batches of up to the whole tile instead of a leaf.
    fn flush_deferred(&mut self) {
        let n = std::mem::take(&mut self.sc.groups);
        // In the order of the evaluators, each group's hits moved into
        // `brackets` and `direct` (empty here, and again after `record`).
        debug_assert!(
            self.sc.brackets.is_empty() && self.sc.direct.is_empty(),
            "every leaf finished"
        );
        self.sc.deferred[..n].sort_unstable_by_key(|d| d.e);
        for g in 0..n {
            let sc = &mut *self.sc;
            let d = &mut sc.deferred[g];
            move_all(&mut d.brackets, &mut sc.brackets);
            move_all(&mut d.direct, &mut sc.direct);
            let e = d.e as usize;
            self.record(e);
        }
    }

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

    /// Records ray `i`'s hit.
    fn set_hit(&mut self, i: usize, h: Hit) {
        self.out[i] = Some(h);
        self.any_hit = true;
        self.sc.resolve(i);
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
    fn corners(&self, rect: Rect) -> Corners {
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
    /// evaluator `e`. `held`: the [`Scratch::epoch`] at which `rect` was
    /// last seen to hold an unresolved ray (by its parent, for a depth
    /// half): while no ray was resolved since, a view whose rays all share
    /// one depth range needs no pass over the rays. `exact`: whether
    /// [`TileCtx::exact`] may settle the node (not below a node where it
    /// left rays unsure).
    #[allow(clippy::too_many_arguments)]
    fn node(
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
            // Rectangles of leaf size over the whole slab: the interval
            // evaluations of the quadrants drop the rays far from the
            // surface (beside a wall) before any is sampled. (A plane's
            // rays take no samples: all of the rectangle at once.)
            for q in rect.quadrants() {
                let kq = self.corners(q);
                self.node(e, q, &kq, za, zb, None, exact);
            }
            return;
        }
        if self.exact(e, rect, za, zb) {
            return;
        }
        // Some rays were left unsure (a crossing that did not check out, a
        // graze): those alone are searched the usual way, the others set
        // aside meanwhile (their slab has no crossing).
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

    /// Settles the slab `[za, zb]` of `rect`'s rays on evaluator `e`, whose
    /// field along every ray is a polynomial of degree at most 2, up to a
    /// map that keeps its sign ([`Evals::exact`]): each ray's polynomial
    /// comes from the quadric's coefficients ([`TileCtx::quadric`]; for a
    /// plane from its values, and the rays that clearly cross it are hits
    /// at once: [`TileCtx::plane_hits`]), or where those are not to be had
    /// from samples at its slab's ends and middle, and its first
    /// crossing (`f ≥ 0`) is found in closed form
    /// ([`RayPoly::first_root`]) and checked: where the polynomial is
    /// outside [`EXACT_BRACKET_PX`] footprints before it and inside as many
    /// after, it is the hit. A ray inside at its first sample is a direct
    /// hit; one whose polynomial stays clearly outside over the slab has no
    /// crossing there (it goes on behind, its tail set as a sampled slab's).
    /// Returns whether every ray was settled so; if not, the rays with no
    /// crossing are in [`Scratch::settled`] and the others (a crossing that
    /// did not check out, a ray grazing the surface, a value not finite)
    /// are left unresolved.
    fn exact(&mut self, e: usize, rect: Rect, za: f64, zb: f64) -> bool {
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
    /// slab on evaluator `e`: inside at `lo` is a direct hit there (where
    /// the field is defined there: [`RayPoly::defined_at_start`]; else the
    /// ray is unsure); values not finite leave the ray unsure (`false`);
    /// otherwise `p` is kept
    /// for the ray's later slabs and [`TileCtx::settle`] takes it.
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
    /// polynomial `p` ([`TileCtx::exact`]). A crossing is the hit where the
    /// polynomial's values [`EXACT_BRACKET_PX`] footprints either side of
    /// it are both clear of rounding: recorded at once with the quadric's
    /// normal where `e` has one ([`Evals::quadric`]) and no colour is due,
    /// else as a direct hit (its normal by the gradient there). No
    /// crossing puts the ray in
    /// [`Scratch::settled`] and sets its tail as a sampled slab would; where
    /// the polynomial has no crossing on the rest of the ray either, the
    /// ray is due for the whole-ray check of [`ModelCaster::prune_after`]
    /// if the slabs left would likely cost more. `false`: unsure (nothing
    /// recorded).
    fn settle(&mut self, p: &RayPoly, e: usize, i: usize, lo: f64, hi: f64) -> bool {
        let settled = self.settle_by(p, e, i, lo, hi);
        self.stats.exact_rays += u64::from(settled);
        settled
    }

    /// Evaluator `e`'s plane ([`Evals::plane`]; its field affine), from the
    /// value and gradient at `p0` the first time.
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

    /// Evaluator `e`'s quadric ([`Evals::quadric`]; its field of degree 2
    /// or a root gap), the first time from the values and gradients at
    /// `p0` and at `h` from it along each axis (a quadric's gradient is
    /// affine: its differences give `A` exactly but for rounding). `None`
    /// where those are not finite or the values there do not agree with
    /// the quadric (by more than `1e-9` of their scale).
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
    /// slab (outside at `lo` and inside at `hi`, each by more than
    /// rounding): at the crossing, with the plane's normal (the hit and
    /// normal sampling and [`TileCtx::polish`] find there), without
    /// evaluating the tape.
    /// The other rays are left in `rays` (all of them for a model with
    /// attribute colours, whose hits are recorded with their colours).
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

    /// Whether the crossing at depth `z` of the ray polynomial `p` (over
    /// the slab `[lo, hi]`) is clear: outside [`EXACT_BRACKET_PX`]
    /// footprints before it and inside as many after (within the slab),
    /// each by more than rounding.
    #[inline]
    fn clear_at(&self, p: &RayPoly, z: f64, lo: f64, hi: f64) -> bool {
        let d = EXACT_BRACKET_PX * self.rm.pixel_footprint(z);
        let (a, b) = ((z - d).max(lo), (z + d).min(hi));
        let (fa, fb) = (p.at(a), p.at(b));
        let tol = p.tol(a, b);
        fa < -tol && fb > tol
    }

    /// [`TileCtx::take_poly`] for a ray's fresh polynomial `p` over its
    /// slab `[lo, hi]`, where `p` is finite and clearly outside at `lo`
    /// (the common case), without re-deriving what that gives:
    /// `p` was fitted over this very slab, so the slab's fractions are `0`
    /// and `1` exactly, the value at `lo` is `p.c` and the rounding
    /// allowance `1e-9` of `p`'s scale ([`RayPoly::first_root`] finds the
    /// same). The same outcome, bit for bit; `None` where the case is not
    /// this one (for `take_poly`).
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
    /// a model with no colours ([`ModelCaster::quadric_blocks`]): what
    /// [`RayPoly::of_quadric`] and [`TileCtx::take_poly`] do for each, with
    /// the common case — a clear crossing in the slab, recorded with the
    /// quadric's normal — worked out for all rays at once in one
    /// pass over arrays (which vectorises), the same values
    /// bit for bit; every other ray is taken as before
    /// ([`TileCtx::take_fresh`] or `take_poly`), in the rays' order.
    /// Returns whether every ray was settled.
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

    /// The cost of a whole-ray check (one interval evaluation of the
    /// tile's tape, by tape lengths; see [`ModelCaster::prune_after`]), and
    /// the chance that one succeeds, from this thread's checks so far.
    fn whole_ray_check(&self) -> (f64, f64) {
        let sc = &*self.sc;
        let cost = INTERVAL_COST * sc.evals[self.top.unwrap_or(0)].tape.len() as f64;
        let odds = (sc.prune_hit as f64 + 1.0) / (sc.prune_tried as f64 + 2.0);
        (cost, odds)
    }

    /// The field of evaluator `e` over box `b` (counted).
    fn eval_box(&mut self, e: usize, b: &Aabb) -> Interval {
        self.stats.interval_evals += 1;
        self.sc.evals[e].interval.eval(
            iv(b.min[0], b.max[0]),
            iv(b.min[1], b.max[1]),
            iv(b.min[2], b.max[2]),
            &self.caster.inputs,
        )
    }

    /// The part of a leaf's slab `[za, zb]` that may hold the surface: the
    /// slab is cut into sub-slabs about [`ModelCaster::narrow_px`] pixel
    /// footprints deep, each evaluated over the leaf's frustum, and the
    /// outside ones in front of the first that is not and behind the last
    /// are dropped (nothing can cross there). A sub-slab inside throughout
    /// ends the search: the span ends where it starts (the last sample of
    /// every ray is inside: the sub-slab's box holds its near face), or at
    /// `zb` where a ray of `rect` enters the model box behind that (its
    /// segment must be sampled).
    /// `None`: all outside.
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
    fn fill(&mut self, e: usize, rect: Rect, za: f64, zb: f64) {
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

    /// The hit of ray `i` at depth `z`; its normal is the model box face's
    /// where the solid is cut open there, else left for
    /// [`TileCtx::flush_normals`].
    fn make_hit(&mut self, i: usize, z: f64, at_entry: bool) -> Hit {
        let r = self.sc.rays[i];
        let p = r.at_depth(z);
        let face = if at_entry && z > 0.0 {
            self.entry_face(&p)
        } else {
            None
        };
        let normal = match face {
            Some(n) => n,
            None => {
                self.sc.need_normal.push(i);
                [f64::NAN; 3]
            }
        };
        Hit {
            t: z / r.c,
            position: p,
            normal,
            color: None,
        }
    }

    /// Normals of the hits made since the last call: the gradient by
    /// forward-mode automatic differentiation ([`BatchEval::eval_grad`]),
    /// all hits in one batch (evaluator `e`); where it vanishes or is not
    /// finite, [`TileCtx::normal`].
    fn flush_normals(&mut self, e: usize) {
        let sc = &mut *self.sc;
        if sc.need_normal.is_empty() {
            return;
        }
        let need = std::mem::take(&mut sc.need_normal);
        sc.set_points(need.len());
        let mut o = 0;
        for &i in &need {
            let Some(h) = &self.out[i] else { continue };
            [sc.xs[o], sc.ys[o], sc.zs[o]] = h.position;
            o += 1;
        }
        sc.np = o;
        self.stats.grad_evals += o as u64;
        sc.eval_grads(e, &self.caster.inputs);
        let grads = std::mem::take(&mut self.sc.grads);
        let mut j = 0;
        for &i in &need {
            let Some(h) = &self.out[i] else { continue };
            let g = grads[j];
            j += 1;
            let n = match unit([-g.dx, -g.dy, -g.dz]) {
                Some(n) => n,
                None => {
                    let (p, t) = (h.position, h.t);
                    let r = self.sc.rays[i];
                    self.normal(e, &r, p, t * r.c)
                }
            };
            if let Some(h) = &mut self.out[i] {
                h.normal = n;
            }
        }
        self.sc.grads = grads;
        self.sc.need_normal = need;
        self.sc.need_normal.clear();
    }

    /// [`entry_face`] of the model box.
    fn entry_face(&self, p: &[f64; 3]) -> Option<[f64; 3]> {
        entry_face(&self.caster.bounds, p)
    }

    /// The normal at `p` where the gradient vanishes or is not finite (a
    /// field like `(r² − |p|²)³` on its surface, a kink): central
    /// differences at half, 2 and 8 pixel footprints, the first that does
    /// not vanish; failing those, the direction back along the ray.
    fn normal(&mut self, e: usize, r: &RayInfo, p: [f64; 3], z: f64) -> [f64; 3] {
        let h = self.footprint(z).max(1e-9 * (1.0 + z.abs()));
        for scale in [0.5, 2.0, 8.0] {
            let d = h * scale;
            self.sc.clear_points();
            for k in 0..3 {
                for s in [d, -d] {
                    let mut q = p;
                    q[k] += s;
                    self.sc.push_point(q);
                }
            }
            self.stats.point_evals += 6;
            self.sc.eval_points(e, &self.caster.inputs);
            let v = &self.sc.vals;
            let n = [-(v[0] - v[1]), -(v[2] - v[3]), -(v[4] - v[5])];
            if let Some(n) = unit(n) {
                return n;
            }
        }
        [-r.dir[0], -r.dir[1], -r.dir[2]]
    }

    /// The finest depth resolution of thin-feature searches, for sampling
    /// steps of `step`.
    /// (A fraction of the sampling step or of the pixel footprint at depth
    /// `z`, whichever is smaller.)
    fn min_len(&self, step: f64, z: f64) -> f64 {
        step.min(self.footprint(z)) / (1u64 << self.caster.fallback_depth.min(20)) as f64
    }

    /// Searches the buffered `searches` (all with evaluator `e`) for a
    /// feature thinner than a step: each segment is sampled at the midpoints
    /// of its cells no longer than its `min_len` (the cells an interval
    /// bisection down to `min_len` would test), all in one batch; the first
    /// inside midpoint gives a bracket.
    fn run_searches(&mut self, e: usize) {
        if self.sc.searches.is_empty() {
            return;
        }
        // Interval evaluations over the segments first: most local maxima
        // of smooth fields are far from the surface.
        let searches = std::mem::take(&mut self.sc.searches);
        let mut keep = std::mem::take(&mut self.sc.search_keep);
        keep.clear();
        keep.resize(searches.len(), false);
        self.check_searches(e, &searches, &mut keep);
        let mut searches = searches;
        let mut kept = keep.iter();
        searches.retain(|_| kept.next().copied().unwrap_or(true));
        self.sc.search_keep = keep;
        self.sc.searches = searches;
        let sc = &mut *self.sc;
        if sc.searches.is_empty() {
            return;
        }
        sc.clear_points();
        let searches = std::mem::take(&mut sc.searches);
        for &(i, a, b, _, min_len) in &searches {
            let m = cells(b - a, min_len);
            let r = sc.rays[i];
            let w = (b - a) / m as f64;
            for j in 0..m {
                let p = r.at_depth(a + w * (j as f64 + 0.5));
                sc.push_point(p);
            }
        }
        sc.searches = searches;
        self.stats.point_evals += sc.np as u64;
        sc.eval_points(e, &self.caster.inputs);
        let mut off = 0;
        for &(i, a, b, fa, min_len) in &sc.searches {
            let m = cells(b - a, min_len);
            let w = (b - a) / m as f64;
            let v = &sc.vals[off..off + m];
            off += m;
            let (mut lo, mut f_lo) = (a, fa);
            for (j, &f) in v.iter().enumerate() {
                let z = a + w * (j as f64 + 0.5);
                if f >= 0.0 {
                    sc.brackets.push(Bracket {
                        ray: i,
                        lo,
                        hi: z,
                        f_lo,
                        f_hi: f,
                        kept: 0,
                    });
                    break;
                }
                (lo, f_lo) = (z, f);
            }
        }
        sc.searches.clear();
    }

    /// Sets `keep[j]` for each search `list[j]` (ray, from, to, …) whose
    /// segment's box is not outside on evaluator `e`: one interval
    /// evaluation over the hull of the segments' boxes, and only where that
    /// is not outside, the same for each half of the list, down to single
    /// segments (those evaluated as before). Neighbouring rays' searches
    /// are mostly outside together: on android_robot's turntable a third
    /// fewer evaluations, on M3's half.
    fn check_searches(&mut self, e: usize, list: &[Search], keep: &mut [bool]) {
        let Some((&(i, a, b, _, _), rest)) = list.split_first() else {
            return;
        };
        let rays = &self.sc.rays;
        let hull = rest
            .iter()
            .fold(rays[i].segment_box(a, b), |h, &(i, a, b, _, _)| {
                h.union(&rays[i].segment_box(a, b))
            });
        if self.eval_box(e, &hull).is_outside() {
            return;
        }
        if rest.is_empty() {
            keep[0] = true;
            return;
        }
        let mid = list.len() / 2;
        let (k0, k1) = keep.split_at_mut(mid);
        self.check_searches(e, &list[..mid], k0);
        self.check_searches(e, &list[mid..], k1);
    }

    /// Searches the segments of the buffered `tail_list` (rays and their
    /// pending tails), each with the evaluator it was sampled with, one
    /// batch per evaluator; hits are recorded. Empties the list (the
    /// callers clear the rays' pending flags).
    fn search_tails(&mut self) {
        let mut list = std::mem::take(&mut self.sc.tail_list);
        if list.is_empty() {
            self.sc.tail_list = list;
            return;
        }
        list.sort_by_key(|(_, t)| t.ev);
        let sc = &mut *self.sc;
        let brackets = set_aside(&mut sc.brackets, &mut sc.spare_brackets);
        let direct = set_aside(&mut sc.direct, &mut sc.spare_direct);
        let searches = set_aside(&mut sc.searches, &mut sc.spare_searches);
        // Hits of another box waiting for normals (from `fill`): not with
        // these tapes.
        let need = set_aside(&mut sc.need_normal, &mut sc.spare_need);
        let mut k = 0;
        while k < list.len() {
            let e = list[k].1.ev;
            while k < list.len() && list[k].1.ev == e {
                let (i, t) = list[k];
                let min_len = self.min_len(t.z_last - t.z_prev, t.z_prev);
                self.sc
                    .searches
                    .push((i, t.z_prev, t.z_last, t.f_prev, min_len));
                k += 1;
            }
            self.run_searches(e as usize);
            self.finish(e as usize);
        }
        let sc = &mut *self.sc;
        put_back(&mut sc.brackets, brackets, &mut sc.spare_brackets);
        put_back(&mut sc.direct, direct, &mut sc.spare_direct);
        put_back(&mut sc.searches, searches, &mut sc.spare_searches);
        put_back(&mut sc.need_normal, need, &mut sc.spare_need);
        list.clear();
        sc.tail_list = list;
    }

    /// Resolves the rays of the buffered brackets and direct hits
    /// (evaluator `e`): they are searched no further, and their hits are
    /// refined and recorded at the end of the tile
    /// ([`TileCtx::flush_deferred`]).
    fn finish(&mut self, e: usize) {
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
    fn record(&mut self, e: usize) {
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

    /// The live unresolved rays of `rect` that reach the slab `[za, zb]`
    /// (a resolved or dead ray's range is `[+∞, −∞]`), as (ray, its part of
    /// the slab). Pending segments in front of the slab, not followed by it,
    /// are searched first (with `all_tails`, those it follows on from too),
    /// and the rays they resolve left out. The buffer is
    /// [`Scratch::leaf_rays`]'s: the caller puts it back.
    fn gather(&mut self, rect: Rect, za: f64, zb: f64, all_tails: bool) -> Vec<(usize, f64, f64)> {
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
    fn sample(&mut self, e: usize, rays: &[(usize, f64, f64)], n: usize) {
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

    fn leaf(&mut self, e: usize, rect: Rect, za: f64, zb: f64) {
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

    /// Checks the rays due (see [`ModelCaster::prune_after`]): one interval
    /// evaluation of the tile's tape over the rest of each ray's depth range
    /// (the box of that segment); a ray that is outside there is searched
    /// no further (a miss), its pending segment included.
    fn prune_rays(&mut self) {
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

    /// Resolves the buffered brackets (evaluator `e`) where the field is
    /// close to linear: the value and gradient at each bracket's false
    /// position point (one batch of [`BatchEval::eval_grad`], which the
    /// normal needs anyway), and where one Newton step along the ray from
    /// there would move at most [`POLISH_PX`] footprints and stay in the
    /// bracket, and the slope along the ray is within a factor of two of
    /// the bracket's secant slope (no kink or bend inside it), the hit is
    /// that point and its normal the gradient's there (hits recorded into
    /// `hit_rays`). The brackets left, narrowed to the side of that point
    /// that holds the crossing, are refined ([`TileCtx::refine`]).
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
    /// Illinois rule, kept off the ends) as a pair `c ± tol·0.45`: where
    /// the crossing lies between the two (a smooth field, after one step
    /// nearly always) the bracket is done; otherwise the side that holds
    /// the first crossing is kept. A bracket too narrow for a pair gets
    /// `c` alone.
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

    /// Attribute colours (`s[1..3]` as sRGB in `[0, 1]`) at the given hits.
    fn colors(&mut self, hit_rays: &[usize]) {
        let Some(attr_tape) = &self.caster.attr_tape else {
            return;
        };
        if hit_rays.is_empty() {
            return;
        }
        let sc = &mut *self.sc;
        // Where the attributes are constant over the box of the hits (an
        // interval evaluation gives each a single value), that is every
        // hit's colour, without evaluating them point by point.
        let hull = hit_rays
            .iter()
            .filter_map(|&i| self.out[i].as_ref())
            .map(|h| Aabb::new(h.position, h.position))
            .reduce(|a, b| a.union(&b))
            .filter(|b| (0..3).all(|k| b.min[k] <= b.max[k]));
        if let Some(b) = hull {
            let ev = sc
                .attr_iv
                .get_or_insert_with(|| IntervalEval::new(attr_tape));
            let out = ev.eval_outputs(
                iv(b.min[0], b.max[0]),
                iv(b.min[1], b.max[1]),
                iv(b.min[2], b.max[2]),
                &self.caster.inputs,
            );
            self.stats.interval_evals += 1;
            let single = |r: &Interval| !r.nan && r.lo == r.hi && r.lo.is_finite();
            if out.len() >= 3 && out[..3].iter().all(single) {
                let c = [0, 1, 2].map(|k| out[k].lo.clamp(0.0, 1.0) as f32);
                for &i in hit_rays {
                    if let Some(h) = &mut self.out[i] {
                        h.color = Some(c);
                    }
                }
                return;
            }
        }
        sc.clear_points();
        for &i in hit_rays {
            let p = self.out[i].as_ref().map_or([0.0; 3], |h| h.position);
            sc.push_point(p);
        }
        let eval = sc.attr.get_or_insert_with(|| BatchEval::new(attr_tape));
        let mut outs = vec![Vec::new(); attr_tape.outputs.len()];
        self.stats.point_evals += hit_rays.len() as u64;
        let n = sc.np;
        eval.eval_outputs(
            &sc.xs[..n],
            &sc.ys[..n],
            &sc.zs[..n],
            &self.caster.inputs,
            &mut outs,
        );
        if outs.len() < 3 {
            return;
        }
        for (j, &i) in hit_rays.iter().enumerate() {
            let c = [outs[0][j], outs[1][j], outs[2][j]];
            if let Some(h) = &mut self.out[i] {
                if c.iter().all(|v| v.is_finite()) {
                    h.color = Some(c.map(|v| v.clamp(0.0, 1.0) as f32));
                }
            }
        }
    }
}

/// The number of cells (a power of two) an interval bisection of a segment
/// of length `len` down to `min_len` ends with.
fn cells(len: f64, min_len: f64) -> usize {
    let mut m = 1usize;
    let mut w = len;
    while w > min_len && m < 4096 {
        w *= 0.5;
        m *= 2;
    }
    m
}

/// The squared length of a gradient.
#[inline]
fn len2(g: &Grad) -> f64 {
    g.dx * g.dx + g.dy * g.dy + g.dz * g.dz
}

/// Squared lengths whose vector [`unit()`] scales by `1 / √l²`: normal finite
/// numbers (no component overflows or underflows in the sum).
const NORMAL_LEN2: std::ops::Range<f64> = f64::MIN_POSITIVE..f64::MAX;

fn unit(n: [f64; 3]) -> Option<[f64; 3]> {
    let l2 = dot(n, n);
    if NORMAL_LEN2.contains(&l2) {
        // The common case: one division (finite components, their squares
        // neither overflowing nor underflowing in sum).
        let k = 1.0 / l2.sqrt();
        return Some([n[0] * k, n[1] * k, n[2] * k]);
    }
    let l = l2.sqrt();
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
    let mut img = Image {
        width: w,
        height: h,
        rgba: crate::image::image_bytes(w as usize * h as usize * 4),
    };
    // Each tile is shaded straight into its rows of the image, or filled
    // with the background where no ray hit (nothing to shade). The hit
    // buffer is kept per worker, from tile to tile, and cleared only after
    // a tile with a hit (the caster writes nothing where no ray hits).
    let rows = tile_rows(&mut img.rgba, w as usize, 4, &ts);
    let work: Vec<_> = ts.into_iter().zip(rows).collect();
    // Models that are set expressions over quadrics: each tile solved and
    // shaded in closed form where every ray checks out.
    let closed_form = caster
        .csg_tree
        .as_ref()
        .filter(|_| caster.csg && caster.attr_tape.is_none() && !settings.ao);
    for_each_dynamic(
        work,
        || (None::<BatchEval>, Vec::<Option<Hit>>::new(), false),
        |(ao_eval, hits, dirty), (t, mut rows)| {
            if let Some(csg) = closed_form {
                if caster.closed_form_tile(csg, camera, &shader, &t, &mut rows) {
                    return;
                }
            }
            let n = (t.w() * t.h()) as usize;
            if *dirty || hits.len() != n {
                hits.clear();
                hits.resize(n, None);
            }
            *dirty = caster.cast_tile_hits(camera, &t, hits);
            if !*dirty {
                for (row, y) in rows.iter_mut().zip(t.y0..) {
                    fill_background(shader.background(y), row);
                }
                return;
            }
            let mut ao = Vec::new();
            if settings.ao {
                ao.resize(n, 1.0);
                let ev = ao_eval.get_or_insert_with(|| BatchEval::new(&caster.tape));
                ambient_occlusion(ev, caster, hits, &mut ao);
            }
            let tw = t.w() as usize;
            for ((r, row), y) in rows.iter_mut().enumerate().zip(t.y0..) {
                let span = r * tw..(r + 1) * tw;
                let a = (!ao.is_empty()).then(|| &ao[span.clone()]);
                shader.span(y, &hits[span], a, row);
            }
        },
    );
    if is_cancelled(cancel) {
        return Err(RenderError::Cancelled);
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

    /// `set_up_rays` gives each ray of a tile what `RayMaker::ray`,
    /// `per_dir` and `Ray::clip_inv` give it one at a time, bit for bit: in
    /// perspective and orthographic views, oblique and straight along an
    /// axis (directions with zero components, origins on the box's faces,
    /// whose slab tests meet `0 · ∞`), in tiles narrower than a lane pass
    /// and cut off by the image's edge, with rays that miss the box.
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
