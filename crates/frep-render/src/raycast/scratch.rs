//! The per-thread scratch of the caster ([`Scratch`]). It holds the
//! evaluators of the root tape and of every shortened tape met so far
//! ([`Evals`]), bounded in size. It also holds the buffers of a tile's rays,
//! samples, searches and brackets.

use frep_core::eval::batch::{BatchEval, GradRegs, Trig, LANES};
use frep_core::eval::grad::Grad;
use frep_core::eval::interval::{Choice, IntervalEval};
use frep_core::eval::Inputs;
use frep_core::hash::{FastHasher, FastMap};
use frep_core::simplify::{ChoiceMask, Simplifier, SimplifyMode};
use frep_core::Tape;

use super::csg::{Lanes, Solved, Work};
use super::leaf::Sampling;
use super::poly::{Quadric, RayPoly};
use super::rays::RayInfo;
use super::refine::Bracket;
use super::search::Tail;

/// The evaluators of one (possibly shortened) tape.
pub(super) struct Evals {
    pub(super) tape: Tape,
    /// What of the interval choices simplifying can read: the keys of the
    /// cache of shortened tapes, and whether [`SimplifyMode::Sign`] can ever
    /// shorten the tape ([`ChoiceMask::can_shorten`]).
    pub(super) mask: ChoiceMask,
    pub(super) interval: IntervalEval,
    batch: Option<BatchEval>,
    /// Set where the field along every ray is a polynomial of degree at
    /// most 2, up to a map that keeps its sign. Three samples then give it
    /// (see [`TileCtx::exact`]).
    /// - `Some(0.0)` where the field is a polynomial of degree 2 in the
    ///   point ([`Tape::polynomial_degree`]).
    /// - `Some(k)` where it is `k − sqrt(p)` with `p` one
    ///   ([`Tape::root_gap`]). Samples `f` map to `f·(2k − f) = k² − p`.
    ///
    /// Also `Some(0.0)` where the field is affine in the point (degree 1,
    /// `affine`): its values along each ray then come from [`Evals::plane`]
    /// without samples.
    ///
    /// [`TileCtx::exact`]: crate::raycast::tile::TileCtx::exact
    pub(super) exact: Option<f64>,
    /// Whether the field is affine in the point (a plane).
    pub(super) affine: bool,
    /// For an affine field, `[c, gx, gy, gz]` with `f(p) = c + g·p`, once
    /// computed (the value and gradient at one point): `None` until then,
    /// `Some(None)` where those were not finite.
    pub(super) plane: Option<Option<[f64; 4]>>,
    /// For a field of degree 2 or a root gap (`exact`, not `affine`), the
    /// quadric with its sign ([`Quadric`]), once computed: `None` until
    /// then, `Some(None)` where it could not be (values not finite, or not
    /// those of a quadric: [`TileCtx::quadric`]).
    ///
    /// [`TileCtx::quadric`]: crate::raycast::tile::TileCtx::quadric
    pub(super) quadric: Option<Option<Quadric>>,
}

impl Evals {
    pub(super) fn new(tape: Tape) -> Evals {
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
pub(super) const NODE_BYTES: usize = 160;

/// (parent evaluator, the key of its interval choices ([`ChoiceMask::key`]),
/// child evaluator).
type ChildEntry = (u32, Box<[Choice]>, u32);

/// Per-thread state of the caster, reused from tile to tile: the evaluators
/// of the root tape and of every shortened tape met so far, and the buffers
/// of a tile. The evaluators are keyed by the interval choices that
/// produced them, so a tape is never simplified or compiled twice.
pub(super) struct Scratch {
    /// `evals[0]` is the root tape's.
    pub(super) evals: Vec<Evals>,
    /// The arrays of the closed form on set expressions
    /// ([`TileCtx::closed_form`], [`ModelCaster::closed_form_tile`]), once
    /// used.
    ///
    /// [`TileCtx::closed_form`]: crate::raycast::tile::TileCtx::closed_form
    /// [`ModelCaster::closed_form_tile`]: crate::raycast::caster::ModelCaster::closed_form_tile
    pub(super) closed_form: Option<Box<(Lanes, Work, Solved)>>,
    /// The closed form's per-column terms of an orthographic tile's ray
    /// origins ([`RayMaker::ortho_columns`]).
    ///
    /// [`RayMaker::ortho_columns`]: crate::camera::RayMaker::ortho_columns
    pub(super) columns: Vec<f64>,
    /// Hash of (parent, choices) → (parent, choices, child): the child is
    /// the parent itself where simplifying does not shorten the tape.
    pub(super) children: FastMap<u64, Vec<ChildEntry>>,
    /// Hash of a shortened tape → the evaluators holding it (different
    /// boxes often shorten to the same tape).
    pub(super) by_tape: FastMap<u64, Vec<u32>>,
    /// Estimated bytes of `evals`.
    pub(super) bytes: usize,
    /// The key of the box being shortened, then its choices (see
    /// [`TileCtx::shorten`]).
    ///
    /// [`TileCtx::shorten`]: crate::raycast::tile::TileCtx::shorten
    pub(super) choices: Vec<Choice>,
    /// [`TileCtx::shorten`]'s buffers for simplifying (as long as the root
    /// tape at most).
    ///
    /// [`TileCtx::shorten`]: crate::raycast::tile::TileCtx::shorten
    pub(super) simplifier: Simplifier,
    pub(super) attr: Option<BatchEval>,
    /// The attribute tape's interval evaluator, for colours constant over
    /// a tile's hits ([`TileCtx::colors`]).
    ///
    /// [`TileCtx::colors`]: crate::raycast::tile::TileCtx::colors
    pub(super) attr_iv: Option<IntervalEval>,
    pub(super) rays: Vec<RayInfo>,
    /// Per ray, its depth range `[z0s, z1s]` while it is live and
    /// unresolved, else `[+∞, −∞]`.
    pub(super) z0s: Vec<f64>,
    pub(super) z1s: Vec<f64>,
    /// Bumped whenever rays are taken out of the depth ranges (see
    /// [`TileCtx::node`]'s `held`).
    ///
    /// [`TileCtx::node`]: crate::raycast::tile::TileCtx::node
    pub(super) epoch: u64,
    /// Rays whose hit still needs its normal (see [`TileCtx::flush_normals`]).
    ///
    /// [`TileCtx::flush_normals`]: crate::raycast::tile::TileCtx::flush_normals
    pub(super) need_normal: Vec<usize>,
    pub(super) tails: Vec<Tail>,
    /// Per ray: leaf slabs sampled without a crossing since its last
    /// check fell due, and the checks that fell due (see
    /// [`ModelCaster::prune_after`]).
    ///
    /// [`ModelCaster::prune_after`]: crate::raycast::caster::ModelCaster::prune_after
    pub(super) misses: Vec<(u16, u8)>,
    /// Rays due for that check: (ray, depth it starts at).
    pub(super) prune: Vec<(usize, f64)>,
    /// Those checks made so far by this thread, and those that found the
    /// rest of the ray outside (their success rate weighs the next ones).
    pub(super) prune_tried: u32,
    pub(super) prune_hit: u32,
    /// Points to evaluate: the first `np` of `xs`, `ys`, `zs` (the
    /// buffers only grow), and their values in the first `np` of `vals`.
    pub(super) xs: Vec<f64>,
    pub(super) ys: Vec<f64>,
    pub(super) zs: Vec<f64>,
    pub(super) np: usize,
    pub(super) vals: Vec<f64>,
    /// Values and gradients at the first `np` points (see
    /// [`Scratch::eval_grads`]).
    pub(super) grads: Vec<Grad>,
    /// Inverse gradient lengths ([`TileCtx::polish`]).
    ///
    /// [`TileCtx::polish`]: crate::raycast::tile::TileCtx::polish
    pub(super) inv_len: Vec<f64>,
    /// Working registers of [`BatchEval::eval_grad`] (for every tape).
    grad_regs: GradRegs,
    /// Per ray of the current leaf: (tile ray index, lo depth, hi depth).
    pub(super) leaf_rays: Vec<(usize, f64, f64)>,
    /// The rays [`TileCtx::exact`] found no crossing on, and their depth
    /// ranges while they are set aside (see [`TileCtx::node`]).
    ///
    /// [`TileCtx::exact`]: crate::raycast::tile::TileCtx::exact
    /// [`TileCtx::node`]: crate::raycast::tile::TileCtx::node
    pub(super) settled: Vec<usize>,
    pub(super) hidden: Vec<(usize, f64, f64)>,
    /// [`TileCtx::exact`]'s rays to sample.
    ///
    /// [`TileCtx::exact`]: crate::raycast::tile::TileCtx::exact
    pub(super) fresh: Vec<(usize, f64, f64)>,
    /// Per ray of the tile, its polynomial on the last exact evaluator it
    /// was sampled on (entries of earlier tiles are stale by their tag).
    pub(super) polys: Vec<RayPoly>,
    /// Counts the tiles this scratch cast.
    pub(super) tile_gen: u64,
    pub(super) brackets: Vec<Bracket>,
    /// Rays whose first sample is inside: (ray, depth, at the model box
    /// entry).
    pub(super) direct: Vec<(usize, f64, bool)>,
    pub(super) searches: Vec<Search>,
    /// Which of `searches` [`TileCtx::check_searches`] keeps; empty
    /// between uses.
    ///
    /// [`TileCtx::check_searches`]: crate::raycast::tile::TileCtx::check_searches
    pub(super) search_keep: Vec<bool>,
    /// Tails to search (see [`TileCtx::search_tails`]).
    ///
    /// [`TileCtx::search_tails`]: crate::raycast::tile::TileCtx::search_tails
    pub(super) tail_list: Vec<(usize, Tail)>,
    pub(super) hit_rays: Vec<usize>,
    pub(super) fracs: Vec<f64>,
    /// Crossings found but not refined yet and direct hits not recorded
    /// yet, one group per evaluator (see [`TileCtx::finish`]). The tile's
    /// are the first `groups`. The others are kept, empty, for their
    /// buffers' capacity.
    ///
    /// [`TileCtx::finish`]: crate::raycast::tile::TileCtx::finish
    pub(super) deferred: Vec<Deferred>,
    pub(super) groups: usize,
    /// Buffers lent in place of `brackets`, `direct`, `searches` and
    /// `need_normal` while [`TileCtx::search_tails`] sets those aside, kept
    /// (empty) for their capacity: no allocation per search.
    ///
    /// [`TileCtx::search_tails`]: crate::raycast::tile::TileCtx::search_tails
    pub(super) spare_brackets: Vec<Bracket>,
    pub(super) spare_direct: Vec<(usize, f64, bool)>,
    pub(super) spare_searches: Vec<Search>,
    pub(super) spare_need: Vec<usize>,
    /// Pending tails a leaf searches before its own samples (see
    /// [`TileCtx::leaf`]); empty between uses.
    ///
    /// [`TileCtx::leaf`]: crate::raycast::tile::TileCtx::leaf
    pub(super) resolve_first: Vec<(usize, Tail)>,
    /// [`TileCtx::refine`]'s brackets still too wide, and their trial depths.
    ///
    /// [`TileCtx::refine`]: crate::raycast::tile::TileCtx::refine
    pub(super) refine_active: Vec<usize>,
    pub(super) refine_trials: Vec<(f64, f64, usize)>,
    /// The caster's [`ModelCaster::trig`], for the batch evaluators (set
    /// at each use).
    ///
    /// [`ModelCaster::trig`]: crate::raycast::caster::ModelCaster::trig
    pub(super) trig: Trig,
}

/// A thin-feature search: (ray, lo depth, hi depth, f at lo, finest cell
/// length).
pub(super) type Search = (usize, f64, f64, f64, f64);

/// The crossings and direct hits of one evaluator waiting for the end of
/// the tile ([`TileCtx::finish`], [`TileCtx::flush_deferred`]).
///
/// [`TileCtx::finish`]: crate::raycast::tile::TileCtx::finish
/// [`TileCtx::flush_deferred`]: crate::raycast::tile::TileCtx::flush_deferred
#[derive(Default)]
pub(super) struct Deferred {
    pub(super) e: u32,
    pub(super) brackets: Vec<Bracket>,
    /// (ray, depth, at the model box entry), as [`Scratch::direct`].
    pub(super) direct: Vec<(usize, f64, bool)>,
}

/// Moves all of `from` to the end of `to`, leaving `from` empty: the
/// buffers are swapped (nothing copied) where `to` is empty.
pub(super) fn move_all<T>(from: &mut Vec<T>, to: &mut Vec<T>) {
    if to.is_empty() {
        std::mem::swap(from, to);
    } else {
        to.append(from);
    }
}

/// Sets `slot`'s buffer aside and lends it `spare`'s (empty) meanwhile.
pub(super) fn set_aside<T>(slot: &mut Vec<T>, spare: &mut Vec<T>) -> Vec<T> {
    std::mem::replace(slot, std::mem::take(spare))
}

/// Puts `kept` back in `slot`; the lent buffer, emptied, becomes the spare
/// again (its capacity kept).
pub(super) fn put_back<T>(slot: &mut Vec<T>, kept: Vec<T>, spare: &mut Vec<T>) {
    let mut lent = std::mem::replace(slot, kept);
    lent.clear();
    *spare = lent;
}

impl Scratch {
    pub(super) fn new(tape: &Tape) -> Scratch {
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
    pub(super) fn trim(&mut self) {
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
    pub(super) fn eval_points(&mut self, e: usize, inputs: &Inputs) {
        self.eval_points_on(e, None, inputs);
    }

    /// [`Scratch::eval_points`]; with `lines = Some((axis, len, grid))`,
    /// for leaf points on lines along `axis`, `len` per ray
    /// ([`BatchEval::eval_lines`]; see [`Scratch::sampling`]).
    pub(super) fn eval_points_on(
        &mut self,
        e: usize,
        lines: Option<(usize, usize, bool)>,
        inputs: &Inputs,
    ) {
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

    /// How the leaf points just written can be evaluated, where the rays run
    /// along coordinate axis `axis` (`leaf_rays`, with `len` depths each).
    /// - As lines where each ray's other two coordinates are the same bits
    ///   at its first and last depth. They are then the same at every
    ///   depth: the points are `origin + 0·t` there, and the depths are
    ///   monotone.
    /// - As a grid where, moreover, every ray has the first one's bits along
    ///   the axis: the same depths, origins and steps there.
    /// - Else point by point.
    ///
    /// Checks [`TileCtx::lines`] in debug builds.
    ///
    /// [`TileCtx::lines`]: crate::raycast::tile::TileCtx::lines
    pub(super) fn sampling(
        &self,
        axis: usize,
        leaf_rays: &[(usize, f64, f64)],
        len: usize,
    ) -> Sampling {
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
    pub(super) fn resolved(&self, i: usize) -> bool {
        self.z0s[i] == f64::INFINITY
    }

    /// Evaluates output 0 of evaluator `e` and its gradient at the
    /// buffered points into `grads`.
    pub(super) fn eval_grads(&mut self, e: usize, inputs: &Inputs) {
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
    pub(super) fn resolve(&mut self, i: usize) {
        self.z0s[i] = f64::INFINITY;
        self.z1s[i] = f64::NEG_INFINITY;
        self.epoch += 1;
    }

    pub(super) fn clear_points(&mut self) {
        self.np = 0;
    }

    pub(super) fn push_point(&mut self, p: [f64; 3]) {
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
    pub(super) fn set_points(&mut self, n: usize) {
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
pub(super) fn tape_hash(t: &Tape) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = FastHasher::default();
    t.hash(&mut h);
    h.finish()
}

pub(super) fn choices_hash(parent: usize, choices: &[Choice]) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ parent as u64;
    for c in choices {
        let v = c.exact as u64 | (c.sign as u64) << 8 | (c.decided as u64) << 16;
        h = (h ^ v).wrapping_mul(0x0100_0000_01b3);
        h ^= h >> 29;
    }
    h
}
