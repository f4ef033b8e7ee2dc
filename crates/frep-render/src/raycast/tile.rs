//! One tile's cast ([`TileCtx`]): its state and the order of its steps.

use crate::camera::{Camera, RayMaker};
use crate::image::Hit;
use crate::tiles::Tile;

use super::caster::{CastStats, ModelCaster};
use super::frustum::Rect;
use super::poly::RayPoly;
use super::rays::set_up_rays;
use super::scratch::{move_all, Scratch};
use super::search::Tail;

pub(super) struct TileCtx<'a> {
    pub(super) caster: &'a ModelCaster,
    pub(super) rm: RayMaker,
    pub(super) tile: &'a Tile,
    pub(super) out: &'a mut [Option<Hit>],
    pub(super) sc: &'a mut Scratch,
    pub(super) tw: u32,
    /// The evaluator of the tape shortened for the whole tile's box (valid
    /// for every ray of the tile over its whole depth range), once the root
    /// node has shortened it.
    pub(super) top: Option<usize>,
    /// The depth range every live ray of the tile shares, where they all
    /// share one (an orthographic view whose rays enter and leave the
    /// model box through faces square to them).
    pub(super) uniform: Option<(f64, f64)>,
    /// Whether a hit was recorded.
    pub(super) any_hit: bool,
    /// The coordinate axis every ray runs along, and whether their origins
    /// agree along it. Set where all rays run along one axis (an
    /// orthographic view straight along it) and share one depth range from
    /// 0 on.
    /// - A ray's other two coordinates are then the same bits at every
    ///   depth (`o + 0·t`, `t >= 0`).
    /// - Where the origins agree, so are the axis coordinates of every ray
    ///   of a leaf, since their depths are the same.
    ///
    /// A leaf's samples are then evaluated as lines, or as a grid
    /// ([`BatchEval::eval_lines`]).
    ///
    /// [`BatchEval::eval_lines`]: frep_core::eval::batch::BatchEval::eval_lines
    pub(super) lines: Option<(usize, bool)>,
    pub(super) stats: CastStats,
}

impl<'a> TileCtx<'a> {
    pub(super) fn new(
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

    pub(super) fn footprint(&self, z: f64) -> f64 {
        self.rm.pixel_footprint(z)
    }

    pub(super) fn run(&mut self) {
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

    /// Refines and records the deferred crossings and direct hits of the
    /// tile, one group per evaluator. Refinement steps, normals and colours
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

    /// Records ray `i`'s hit.
    pub(super) fn set_hit(&mut self, i: usize, h: Hit) {
        self.out[i] = Some(h);
        self.any_hit = true;
        self.sc.resolve(i);
    }
}
