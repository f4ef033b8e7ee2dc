//! The caster of one model ([`ModelCaster`]). It holds:
//! - its settings and statistics;
//! - the pool of per-thread scratch;
//! - the interval checks of a tile's box;
//! - the tile entry point ([`TileCaster`]).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use frep_core::eval::batch::Trig;
use frep_core::eval::Inputs;
use frep_core::{CancelToken, Model, Tape};

use crate::camera::{Aabb, Camera, Projection, RayMaker};
use crate::image::Hit;
use crate::tiles::{Tile, TileCaster};

use super::csg::Csg;
use super::frustum::iv;
use super::rays::{clip_box, depth_range, Corners};
use super::scratch::Scratch;
use super::section::{sectioned_tape, Section, SectionError, SECTION_CAP};
use super::tile::TileCtx;

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
    /// Rays' slabs settled in closed form (see [`ModelCaster::exact`]).
    /// A slab is settled with a hit bracketed or no crossing, from samples
    /// or from the ray's polynomial of an earlier slab. Also counted: rays
    /// solved whole on a set expression over quadrics ([`ModelCaster::csg`]).
    pub exact_rays: u64,
}

#[derive(Default)]
pub(super) struct AtomicStats {
    pub(super) interval_evals: AtomicU64,
    pub(super) point_evals: AtomicU64,
    pub(super) grad_evals: AtomicU64,
    pub(super) simplified: AtomicU64,
    pub(super) empty_tiles: AtomicU64,
    pub(super) line_points: AtomicU64,
    pub(super) exact_rays: AtomicU64,
}

/// A [`TileCaster`] for a compiled model (see the module docs).
pub struct ModelCaster {
    pub(super) tape: Tape,
    pub(super) attr_tape: Option<Tape>,
    pub(super) inputs: Inputs,
    pub(super) bounds: Aabb,
    /// The section plane the tape is cut by (normalized), if any.
    pub(super) section: Option<Section>,
    cancel: CancelToken,
    /// Sampling step along rays in leaves, in pixel footprints (default 2;
    /// thinner features are found by the thin-feature search).
    pub step_px: f64,
    /// A ray whose samples miss in an ambiguous leaf gets a thin-feature
    /// search. It samples cells of `1/2^fallback_depth` of a step or of a
    /// pixel footprint, whichever is smaller (default 3: 1/8).
    pub fallback_depth: u32,
    /// Leaves are sampled once their depth slab is at most this many pixel
    /// footprints deep (deeper ones are split by interval bisection first).
    pub leaf_depth_px: f64,
    /// A leaf's slab is narrowed to the part that may hold the surface by
    /// interval evaluations over sub-slabs about this many pixel footprints
    /// deep (0: not narrowed).
    pub narrow_px: f64,
    /// A ray sampled in this many leaf slabs without a crossing may have
    /// the rest of its depth range checked with one interval evaluation, of
    /// the tape shortened for its tile. The check is made where it is likely
    /// to cost less than sampling on. Where the rest is outside, the ray is
    /// searched no further. The next check waits twice as many slabs. 0:
    /// never checked.
    pub prune_after: u32,
    /// Whether the leaves of an orthographic view straight along a
    /// coordinate axis are evaluated as lines ([`BatchEval::eval_lines`]).
    /// Expensive functions of the other two coordinates are then computed
    /// once per ray, those of the axis one once per depth, with the same
    /// values. Default on; off for comparisons.
    ///
    /// [`BatchEval::eval_lines`]: frep_core::eval::batch::BatchEval::eval_lines
    pub lines: bool,
    /// Whether quadric slabs are solved in closed form (see the module
    /// docs). In such a slab of a frustum, the (shortened) tape is a
    /// polynomial of degree 2 in the point. Each ray's crossing is then
    /// solved from 3 samples and checked by the value and gradient there,
    /// not sampled and searched. Default on; off for comparisons.
    pub exact: bool,
    /// Whether the rays of such a slab on a quadric are solved in blocks of
    /// up to a leaf's, for a model with no colours
    /// (`TileCtx::quadric_block`). The common case then takes a pass over
    /// arrays that vectorises, not one ray at a time. The hits are the
    /// same, bit for bit, for about 30 % fewer instructions on a sphere's
    /// top view. Default on; off for comparisons.
    pub quadric_blocks: bool,
    /// Whether each tile's rays are first solved in closed form
    /// (`raycast::csg`), for a model with no colours that is a set
    /// expression over quadrics: spheres, cylinders, planes, and so on.
    /// Such a model is R-functions, `min`, `max` and negations over at most
    /// 8 fields of degree at most 2 in the point, or over root gaps
    /// `k − sqrt(p)` of one. Every leaf's crossings are found and the
    /// expression checked after each. The rays that fail a check are cast
    /// the usual way. Default on; off for comparisons.
    pub csg: bool,
    /// The model's set expression, where it is one ([`ModelCaster::csg`]).
    pub(super) csg_tree: Option<Csg>,
    /// How the batch evaluators of samples, refinement and normals compute
    /// `sin` and `cos`. Default [`Trig::Fast`]: within about `2e-14` of
    /// the value, not an ulp. A sign test at a sample, a hit refined to a
    /// fraction of a footprint and a normal for shading need no more. The
    /// gyroid's frame then takes about a tenth less time. [`Trig::Exact`]
    /// is for comparisons. Interval evaluations stay exact.
    pub trig: Trig,
    pub(super) stats: AtomicStats,
    /// Per-thread evaluators and buffers, reused from tile to tile, each
    /// with the rayon thread that last used it. That thread takes it again,
    /// since its caches are warm in that core's. Another thread takes it
    /// only when none of its own is free.
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

    /// A caster of `model` cut by `section` (see [`Section`]). The field
    /// cast is the model's intersected with the kept half-space. The cut
    /// face of a model without colours gets [`SECTION_CAP`]. `None`:
    /// [`ModelCaster::new`]. An error where the plane is not one.
    pub fn sectioned(
        model: &Model,
        inputs: Inputs,
        bounds: Aabb,
        section: Option<&Section>,
    ) -> Result<ModelCaster, SectionError> {
        let Some(section) = section else {
            return Ok(ModelCaster::new(model, inputs, bounds));
        };
        let section = section.normalized()?;
        Ok(ModelCaster {
            attr_tape: model
                .attribute_tape()
                .filter(|t| model.s_dim >= 3 && t.outputs.len() >= 3),
            section: Some(section),
            ..ModelCaster::from_tape(sectioned_tape(model, &section), inputs, bounds)
        })
    }

    /// The section plane the model is cut by (normalized), if any.
    pub fn section(&self) -> Option<&Section> {
        self.section.as_ref()
    }

    /// A caster of a bare tape (output 0 is the field, positive inside).
    pub fn from_tape(tape: Tape, inputs: Inputs, bounds: Aabb) -> ModelCaster {
        let csg_tree = Csg::of(&tape, &inputs, &bounds);
        ModelCaster {
            tape,
            attr_tape: None,
            inputs,
            bounds,
            section: None,
            cancel: CancelToken::new(),
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

    /// Checks `cancel` before each tile and each frustum box; once it is
    /// cancelled the remaining tiles are left empty.
    pub fn with_cancel(mut self, cancel: CancelToken) -> ModelCaster {
        self.cancel = cancel;
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

    /// The tile's box ([`ModelCaster::tile_box`]). `None` where the tile's
    /// whole frustum within the model box's depth range misses the box, or
    /// is outside by one interval evaluation of the root tape. None of its
    /// rays is then set up. The box holds every box the tile's root
    /// node would evaluate, so nothing that node would find is skipped.
    pub(super) fn live_tile_box(
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

    /// Whether a ray of the tile may be inside the solid where it enters
    /// the box. The tile's rays inside the model box lie in `bx`
    /// ([`ModelCaster::tile_box`]).
    /// - `false` where the model is outside throughout the part of `bx` on
    ///   each face that such rays can enter by. Those are the faces whose
    ///   plane has the eye on its outer side (in an orthographic view, the
    ///   rays' start).
    /// - `true` where rays may start inside the box: its nearest corner is
    ///   not in front of the eye.
    ///
    /// Each face's check is counted in `stats`.
    pub(super) fn may_hold_at_entry(
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

    pub(super) fn cancelled(&self) -> bool {
        self.cancel.is_cancelled()
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
    pub(super) fn cast_tile_hits(
        &self,
        camera: &Camera,
        tile: &Tile,
        out: &mut [Option<Hit>],
    ) -> bool {
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
        if any_hit {
            self.color_caps(camera, tile, out);
        }
        // The tile's own check.
        stats.interval_evals += 1;
        self.put_scratch(scratch);
        self.add_stats(&stats);
        any_hit
    }

    /// Gives the cut face's hits that have no attribute colour
    /// [`SECTION_CAP`] (hits within a pixel footprint of the plane, with
    /// its normal).
    fn color_caps(&self, camera: &Camera, tile: &Tile, out: &mut [Option<Hit>]) {
        let Some(s) = &self.section else { return };
        for h in out.iter_mut().flatten() {
            let tol = camera.pixel_footprint(h.t, tile.width, tile.height);
            // (A colour not defined there shows the cap's, as on the client.)
            let no_color = match h.color {
                None => true,
                Some(c) => c.iter().any(|v| v.is_nan()),
            };
            if no_color && s.is_on_cap(h, tol.max(1e-12)) {
                h.color = Some(SECTION_CAP);
            }
        }
    }

    /// A [`Scratch`] from the pool (the one this thread last used where it
    /// is free), or a new one.
    pub(super) fn take_scratch(&self) -> Box<Scratch> {
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
    pub(super) fn put_scratch(&self, scratch: Box<Scratch>) {
        if let Ok(mut p) = self.pool.lock() {
            p.push((rayon::current_thread_index(), scratch));
        }
    }

    /// Adds a tile's counts to the caster's.
    pub(super) fn add_stats(&self, stats: &CastStats) {
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
}
