//! Rays solved in closed form on models that are set operations over
//! quadrics ([`Csg`]).
//!
//! A model such as `hfSphere(x, c, 1) & x[3]` is a tree of R-functions
//! (`&`, `|`, `\`, `min`, `max`, negation) over simple fields. Each leaf
//! field is one of:
//! - a polynomial of degree at most 2 in the point: a sphere, cylinder,
//!   ellipsoid, cone or plane;
//! - a root gap `k − sqrt(p)` of one (a sphere written as a distance). It
//!   has the sign of `k² − p` where it is defined (`p ≥ 0`). Elsewhere it
//!   is NaN, outside, and so is the model.
//!
//! The algorithm:
//! 1. Each R-function keeps the sign of the set operation it stands for:
//!    `a & b ≥ 0` exactly where `a ≥ 0` and `b ≥ 0`, up to rounding. So the
//!    solid is that set expression over the leaves' solids.
//! 2. Along a ray, each leaf is a polynomial of degree 2 in the depth, with
//!    at most two crossings.
//! 3. A ray's first hit is the first of those crossings (or its entry into
//!    the model box) after which the expression holds. There is no interval
//!    evaluation, no sampling and no search.
//! 4. The tile's rays are solved in blocks of [`BLOCK`]. Every step is a
//!    loop over the block, which vectorises. The set expression is
//!    evaluated on bit masks of the whole block at once.
//! 5. The entry is not checked where the caller has shown that the model is
//!    outside there, by intervals over the box faces the rays enter by.
//!
//! Every result is checked the way the exact slabs of the general caster
//! are. Each leaf's value at each crossing that counts must be clear of
//! rounding: `1e-9` of the polynomial's scale over the ray. No leaf may
//! graze the ray. A ray that fails a check is left to the general caster:
//! two leaves crossing the ray at one point (an edge seen exactly), a
//! tangent ray, or values not finite.

use frep_core::eval::batch::{BatchEval, GradRegs};
use frep_core::eval::grad::Grad;
use frep_core::eval::Inputs;
use frep_core::graph::{Node, NodeId};
use frep_core::ops::{BinaryOp, UnaryOp};
use frep_core::Tape;

use super::poly::Quadric;
use crate::camera::Aabb;

/// Rays per block: one bit each in the masks of the set expression.
pub(super) const BLOCK: usize = 64;

/// The most leaves a [`Csg`] takes: a ray's work grows with their square
/// (every crossing is checked against every leaf).
pub(super) const MAX_LEAVES: usize = 8;

/// The deepest nesting of a set expression's operations, and half the
/// most steps it may take ([`Csg::of`]).
const MAX_OPS: usize = 64;

/// The deepest evaluation stack of a set expression ([`Csg::holds`];
/// checked by [`stack_depth`] when one is built).
const STACK: usize = MAX_OPS + 2;

/// The number of values a set expression leaves on the stack. `None` unless
/// every step finds its operands and the stack stays within [`STACK`].
fn stack_depth(prog: &[Step]) -> Option<usize> {
    let mut top = 0usize;
    for s in prog {
        top = match s {
            Step::Leaf(_) => top + 1,
            Step::Not => top.checked_sub(1)? + 1,
            Step::And | Step::Or => top.checked_sub(2)? + 1,
        };
        if top > STACK {
            return None;
        }
    }
    Some(top)
}

/// `leaf` of a [`Solved`] lane whose hit is its entry into the model box.
pub(super) const ENTRY: u64 = u64::MAX;

/// A model as a set expression over quadrics (see the module docs).
#[derive(Clone, Debug)]
pub(super) struct Csg {
    leaves: Vec<Quadric>,
    /// The set expression in postfix order.
    prog: Vec<Step>,
    /// The crossings that may start the solid along a ray: (leaf, whether
    /// it is the one into the leaf's solid). R-functions, `min` and `max`
    /// are monotone. So a leaf under no negation, or an even number, can
    /// only start the solid where the ray enters it. A leaf under an odd
    /// number can only start it where the ray leaves it.
    cands: Vec<(usize, bool)>,
    /// Per leaf, its form: [`PLANE`] (`A = 0`), [`DIAGONAL`] (an axis-aligned
    /// quadric: `A` diagonal) or [`FULL`].
    shape: Vec<u8>,
}

/// A leaf of degree at most 1 ([`Csg::shape`]).
const PLANE: u8 = 0;
/// A leaf whose `A` is diagonal ([`Csg::shape`]).
const DIAGONAL: u8 = 1;
/// Any other leaf ([`Csg::shape`]).
const FULL: u8 = 2;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Step {
    /// The solid of a leaf: its field `≥ 0`.
    Leaf(u8),
    /// The complement of the last value.
    Not,
    /// The intersection of the last two values.
    And,
    /// The union of the last two values.
    Or,
}

/// A block of rays `o + d·z` over depths `[z0, z1]` (a lane with
/// `z0 > z1` is idle).
pub(super) struct Lanes {
    pub o: [[f64; BLOCK]; 3],
    pub d: [[f64; BLOCK]; 3],
    pub z0: [f64; BLOCK],
    pub z1: [f64; BLOCK],
    /// `Some(d)` where every lane's direction is `d` (an orthographic
    /// view). The leaves' terms of the direction alone are then worked out
    /// once, not per lane.
    pub dir: Option<[f64; 3]>,
}

impl Lanes {
    /// Lane `k`'s direction: `dir` where every lane's is that (`FIXED`),
    /// else its own. With `FIXED` it is the same for every `k`, so loops
    /// can hoist what depends on it alone.
    #[inline(always)]
    fn dir_at<const FIXED: bool>(&self, k: usize, dir: [f64; 3]) -> [f64; 3] {
        if FIXED {
            dir
        } else {
            [self.d[0][k], self.d[1][k], self.d[2][k]]
        }
    }
}

impl Default for Lanes {
    fn default() -> Lanes {
        Lanes {
            o: [[0.0; BLOCK]; 3],
            d: [[0.0; BLOCK]; 3],
            z0: [f64::INFINITY; BLOCK],
            z1: [f64::NEG_INFINITY; BLOCK],
            dir: None,
        }
    }
}

/// What [`Csg::solve`] found for a block of rays, per lane.
pub(super) struct Solved {
    /// Whether the lane's outcome stands (else the general caster's).
    pub sure: u64,
    /// Whether the lane's ray is live (`z0 ≤ z1`; among the first `n`).
    pub live: u64,
    /// Whether the lane has a hit (`z < +∞`).
    pub hit: u64,
    /// Whether the lane's hit is its entry into the model box.
    pub entry: u64,
    /// The hit's depth (`+∞`: the ray misses).
    pub z: [f64; BLOCK],
    /// The leaf crossed at the hit, or [`ENTRY`].
    pub leaf: [u64; BLOCK],
    /// The hit's position `o + d·z`.
    pub p: [[f64; BLOCK]; 3],
    /// The outward normal at a leaf's hit, facing the ray: the leaf's
    /// gradient, of any length. Shading normalises it; here that would cost
    /// a square root and a division per lane. Any value in a lane whose hit
    /// is on no leaf.
    pub n: [[f64; BLOCK]; 3],
}

impl Default for Solved {
    fn default() -> Solved {
        Solved {
            sure: 0,
            live: 0,
            entry: 0,
            hit: 0,
            z: [f64::INFINITY; BLOCK],
            leaf: [ENTRY; BLOCK],
            p: [[0.0; BLOCK]; 3],
            n: [[0.0; BLOCK]; 3],
        }
    }
}

impl Csg {
    /// The set expression of output 0 of `tape` with these parameter
    /// values, where it is one; `None` otherwise. It is R-functions, `min`,
    /// `max` and negations over at most [`MAX_LEAVES`] leaves. A leaf is
    /// one of:
    /// - a field of degree at most 2 in the point, whose values agree with
    ///   its quadric (by `1e-9` of its scale) at the corners and the centre
    ///   of `bounds`;
    /// - a root gap `k − sqrt(p)` of one. It makes two leaves: `k² − p`,
    ///   and `p`, which must be `≥ 0` for the whole expression to hold.
    pub(super) fn of(tape: &Tape, inputs: &Inputs, bounds: &Aabb) -> Option<Csg> {
        let out = *tape.outputs.first()?;
        let mut b = Builder {
            tape,
            prog: Vec::new(),
            leaf_ids: Vec::new(),
            polarity: Vec::new(),
        };
        b.walk(out, 0, false)?;
        // Each leaf's quadric. A root gap `k − sqrt(p)` is `k² − p` (its
        // sign). Where `p < 0` its value is NaN, outside, and so is the
        // whole expression's. So the solid is also within `p ≥ 0`, a leaf
        // of its own joined to the expression by `&`.
        let mut leaves = Vec::with_capacity(b.leaf_ids.len());
        let mut defined = Vec::new();
        for &id in &b.leaf_ids {
            let (q, p) = leaf_quadric(tape, id, inputs, bounds)?;
            leaves.push(q);
            defined.extend(p);
        }
        for p in defined {
            b.prog.push(Step::Leaf(leaves.len() as u8));
            b.prog.push(Step::And);
            b.polarity.push((true, false));
            leaves.push(p);
        }
        if leaves.len() > MAX_LEAVES || stack_depth(&b.prog) != Some(1) {
            return None;
        }
        let mut cands = Vec::new();
        for (j, &(pos, neg)) in b.polarity.iter().enumerate() {
            if pos {
                cands.push((j, true));
            }
            if neg {
                cands.push((j, false));
            }
        }
        let shape = leaves
            .iter()
            .map(|q: &Quadric| {
                let off = [
                    q.a[0][1], q.a[0][2], q.a[1][2], q.a[1][0], q.a[2][0], q.a[2][1],
                ];
                let diag = [q.a[0][0], q.a[1][1], q.a[2][2]];
                match (
                    off.iter().all(|&v| v == 0.0),
                    diag.iter().all(|&v| v == 0.0),
                ) {
                    (true, true) => PLANE,
                    (true, false) => DIAGONAL,
                    _ => FULL,
                }
            })
            .collect();
        Some(Csg {
            leaves,
            prog: b.prog,
            cands,
            shape,
        })
    }

    /// The number of leaves.
    #[cfg(test)]
    pub(super) fn leaves(&self) -> usize {
        self.leaves.len()
    }

    /// The set expression over the leaves' bit masks `m` (bit `k` of
    /// `m[j]`: leaf `j` holds lane `k`): the lanes the solid holds.
    /// `stack`: its evaluation stack. The caller keeps it, so it is not
    /// cleared at every call; every entry is written before it is read.
    #[inline]
    fn holds(&self, m: &[u64; MAX_LEAVES], stack: &mut [u64; STACK]) -> u64 {
        let mut top = 0;
        for s in &self.prog {
            match *s {
                Step::Leaf(j) => {
                    stack[top] = m[j as usize];
                    top += 1;
                }
                Step::Not => stack[top - 1] = !stack[top - 1],
                Step::And => {
                    top -= 1;
                    stack[top - 1] &= stack[top];
                }
                Step::Or => {
                    top -= 1;
                    stack[top - 1] |= stack[top];
                }
            }
        }
        stack[0]
    }

    /// Solves the first `n` lanes of `l` (see the module docs), with `w`
    /// for its working arrays. `entry`: whether to check the rays' entry
    /// into the box as a hit. Callers skip that where they know the model
    /// is outside the solid wherever these rays enter it.
    // (The lane passes index several arrays at once.)
    #[allow(clippy::needless_range_loop)]
    pub(super) fn solve(&self, l: &Lanes, n: usize, w: &mut Work, s: &mut Solved, entry: bool) {
        const B: usize = BLOCK;
        let nl = self.leaves.len();
        // Per leaf, the polynomial along each ray `α z² + β z + γ`, the
        // rounding allowance, and the crossings (NaN where none).
        for ((q, &shape), lr) in self.leaves.iter().zip(&self.shape).zip(w.leaf.iter_mut()) {
            match (shape, l.dir) {
                (PLANE, None) => lr.solve::<PLANE, false>(q, l, [0.0; 3]),
                (DIAGONAL, None) => lr.solve::<DIAGONAL, false>(q, l, [0.0; 3]),
                (_, None) => lr.solve::<FULL, false>(q, l, [0.0; 3]),
                (PLANE, Some(d)) => lr.solve::<PLANE, true>(q, l, d),
                (DIAGONAL, Some(d)) => lr.solve::<DIAGONAL, true>(q, l, d),
                (_, Some(d)) => lr.solve::<FULL, true>(q, l, d),
            }
        }
        let Work {
            leaf: leaves,
            stack,
        } = w;
        let leaves = &leaves[..nl];
        let Solved {
            z: best,
            leaf,
            n: nrm,
            p: pos,
            ..
        } = s;
        // (Written by the first candidate that some lane may take, or
        // below where none is.)
        let mut fresh = true;
        let mut bad = 0u64;
        let mut live = 0u64;
        for k in 0..n {
            live |= u64::from(l.z0[k] <= l.z1[k]) << k;
        }
        // Candidates: the entry (`z0`; unless `entry` is off), then the
        // crossings that may start the solid. After each, the leaves' signs
        // give whether the solid holds the ray there.
        for cand in usize::from(!entry)..=self.cands.len() {
            let (own, enter) = match cand {
                0 => (None, false),
                c => {
                    let (j, enter) = self.cands[c - 1];
                    (Some(j), enter)
                }
            };
            let at = match own {
                None => &l.z0,
                Some(j) if enter => &leaves[j].enter,
                Some(j) => &leaves[j].leave,
            };
            let mut valid = 0u64;
            for k in 0..B {
                let z = at[k];
                let ok = if own.is_none() {
                    true
                } else {
                    z > l.z0[k] && z <= l.z1[k]
                };
                valid |= u64::from(ok) << k;
            }
            valid &= live;
            if valid == 0 {
                continue;
            }
            let mut m = [0u64; MAX_LEAVES];
            let mut unclear = 0u64;
            for (j, mj) in m.iter_mut().enumerate().take(nl) {
                let LeafRay { a, b, c, tol, .. } = &leaves[j];
                let mut bits = 0u64;
                let mut near = 0u64;
                if own == Some(j) {
                    // Just after its own crossing a leaf is inside where
                    // the ray enters it.
                    bits = if enter { !0 } else { 0 };
                } else {
                    for k in 0..B {
                        let z = at[k];
                        let v = (a[k] * z + b[k]) * z + c[k];
                        bits |= u64::from(v >= 0.0) << k;
                        // (NaN is unclear too.)
                        near |= u64::from((v.abs() <= tol[k]) | v.is_nan()) << k;
                    }
                }
                *mj = bits;
                unclear |= near;
            }
            bad |= valid & unclear;
            let inside = self.holds(&m, stack) & valid;
            let own = own.map_or(ENTRY, |j| j as u64);
            if fresh {
                // The first: nothing to keep (a select of constants, where
                // one of the array's own values compiles to a masked
                // store, slow).
                for k in 0..B {
                    let take = ((inside >> k) & 1 != 0) & (at[k] < f64::INFINITY);
                    best[k] = if take { at[k] } else { f64::INFINITY };
                    leaf[k] = if take { own } else { ENTRY };
                }
                fresh = false;
                continue;
            }
            for k in 0..B {
                let take = ((inside >> k) & 1 != 0) & (at[k] < best[k]);
                best[k] = if take { at[k] } else { best[k] };
                leaf[k] = if take { own } else { leaf[k] };
            }
        }
        if fresh {
            *best = [f64::INFINITY; B];
            *leaf = [ENTRY; B];
        }
        let mut grazing = 0u64;
        for lr in leaves {
            for (k, &g) in lr.graze.iter().enumerate() {
                grazing |= u64::from(g) << k;
            }
        }
        // The positions, and the normals: each leaf's gradient at its hits,
        // facing the ray.
        for a in 0..3 {
            for k in 0..B {
                pos[a][k] = l.o[a][k] + l.d[a][k] * best[k];
            }
        }
        let mut finite = 0u64;
        let mut first = true;
        for (j, q) in self.leaves.iter().enumerate() {
            // (Only the leaves some lane hits.)
            if !leaf[..n].contains(&(j as u64)) {
                continue;
            }
            // The first such leaf writes every lane: a plain store, where a
            // select compiles to a slow masked store. Lanes it does not hit
            // are the later leaves' to write, or have no leaf normal.
            finite |= if first {
                leaf_normals::<true>(q, j, l, pos, leaf, nrm)
            } else {
                leaf_normals::<false>(q, j, l, pos, leaf, nrm)
            };
            first = false;
        }
        let entry = {
            let mut e = 0u64;
            for (k, &lf) in leaf.iter().enumerate() {
                e |= u64::from(lf == ENTRY) << k;
            }
            e
        };
        let hit = {
            let mut h = 0u64;
            for (k, &z) in best.iter().enumerate() {
                h |= u64::from(z < f64::INFINITY) << k;
            }
            h
        };
        // A leaf's hit needs a normal; an entry hit's comes from the box.
        let normal_ok = !hit | entry | finite;
        s.sure = live & !bad & !grazing & normal_ok;
        s.live = live;
        s.hit = hit;
        s.entry = hit & entry;
    }
}

/// The normals of leaf `j` (quadric `q`) at the hits on it, written into
/// `nrm`. The lanes of `l` whose hit is on it come from `leaf`, their
/// positions from `pos`. The normal is its gradient, facing the ray. With
/// `ALL` every lane is written, else those lanes only.
/// Returns the lanes whose hit is on it with a usable gradient.
// (The lane passes index several arrays at once.)
#[allow(clippy::needless_range_loop)]
#[inline(always)]
fn leaf_normals<const ALL: bool>(
    q: &Quadric,
    j: usize,
    l: &Lanes,
    pos: &[[f64; BLOCK]; 3],
    leaf: &[u64; BLOCK],
    nrm: &mut [[f64; BLOCK]; 3],
) -> u64 {
    let [[a00, a01, a02], [_, a11, a12], [_, _, a22]] = q.a;
    let (g0, p0) = (q.g, q.p0);
    let mut finite = 0u64;
    for k in 0..BLOCK {
        // `Quadric::grad`, written out.
        let u = [pos[0][k] - p0[0], pos[1][k] - p0[1], pos[2][k] - p0[2]];
        let g = [
            g0[0] + 2.0 * (a00 * u[0] + a01 * u[1] + a02 * u[2]),
            g0[1] + 2.0 * (a01 * u[0] + a11 * u[1] + a12 * u[2]),
            g0[2] + 2.0 * (a02 * u[0] + a12 * u[1] + a22 * u[2]),
        ];
        let slope = g[0] * l.d[0][k] + g[1] * l.d[1][k] + g[2] * l.d[2][k];
        let len2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
        let f = -slope.signum();
        let mine = leaf[k] == j as u64;
        for a in 0..3 {
            nrm[a][k] = if ALL | mine { g[a] * f } else { nrm[a][k] };
        }
        let ok = (len2 > f64::MIN_POSITIVE) & (len2 < f64::MAX);
        finite |= u64::from(mine & ok) << k;
    }
    finite
}

/// The working arrays of [`Csg::solve`], and the set expression's
/// evaluation stack ([`Csg::holds`]). They are kept from block to block:
/// every lane of the leaves in use is written before it is read.
pub(super) struct Work {
    leaf: [LeafRay; MAX_LEAVES],
    stack: [u64; STACK],
}

impl Default for Work {
    fn default() -> Work {
        Work {
            leaf: Default::default(),
            stack: [0; STACK],
        }
    }
}

/// One leaf along a block of rays:
/// - its polynomial `a z² + b z + c` and rounding allowance `tol`;
/// - its crossing into its solid (`enter`, where the slope is positive) and
///   out of it (`leave`), NaN or infinite where there is none;
/// - whether it grazes the ray.
struct LeafRay {
    a: [f64; BLOCK],
    b: [f64; BLOCK],
    c: [f64; BLOCK],
    tol: [f64; BLOCK],
    enter: [f64; BLOCK],
    leave: [f64; BLOCK],
    graze: [bool; BLOCK],
}

impl Default for LeafRay {
    fn default() -> LeafRay {
        LeafRay {
            a: [0.0; BLOCK],
            b: [0.0; BLOCK],
            c: [0.0; BLOCK],
            tol: [0.0; BLOCK],
            enter: [0.0; BLOCK],
            leave: [0.0; BLOCK],
            graze: [false; BLOCK],
        }
    }
}

impl LeafRay {
    /// Quadric `q` along the rays of `l` (every lane; the idle ones give
    /// harmless values). It is not inlined, so its arguments are known not
    /// to overlap and the loop vectorises without run-time checks.
    /// `KIND`: the form of `q` ([`Csg::shape`]), its zero terms left out.
    /// `FIXED`: every lane's direction is `dir`, read instead of `l.d`. The
    /// terms of the direction alone are then the same in every lane, and
    /// the compiler takes them out of the loop (the same bits).
    #[inline(never)]
    fn solve<const KIND: u8, const FIXED: bool>(&mut self, q: &Quadric, l: &Lanes, dir: [f64; 3]) {
        // `q(p0 + u) = c + g·u + uᵀAu` with `u = o − p0 + d·z`, its terms
        // written out (so that the loop vectorises).
        let [g0, g1, g2] = q.g;
        let [[a00, a01, a02], [_, a11, a12], [_, _, a22]] = q.a;
        let (c0, p0) = (q.c, q.p0);
        if KIND == PLANE {
            // (Outside the loop: two stores, not a call.)
            self.graze = [false; BLOCK];
            for k in 0..BLOCK {
                let (u0, u1, u2) = (l.o[0][k] - p0[0], l.o[1][k] - p0[1], l.o[2][k] - p0[2]);
                let [d0, d1, d2] = l.dir_at::<FIXED>(k, dir);
                let (z0, z1) = (l.z0[k], l.z1[k]);
                let b = g0 * d0 + g1 * d1 + g2 * d2;
                let c = c0 + (g0 * u0 + g1 * u1 + g2 * u2);
                let zm = z0.abs().max(z1.abs());
                let t = 1e-9 * (b.abs() * zm + c.abs());
                // Its one root, into the solid where the slope `b` is
                // positive (the bits of the quadratic's form below). (By a
                // reciprocal: in orthographic views `b` is the same in
                // every lane, and the division leaves the loop.)
                let r = -c * (1.0 / b);
                self.enter[k] = if b > 0.0 { r } else { f64::NAN };
                self.leave[k] = if b < 0.0 { r } else { f64::NAN };
                (self.a[k], self.b[k], self.c[k]) = (0.0, b, c);
                self.tol[k] = t;
            }
            return;
        }
        let full = KIND == FULL;
        for k in 0..BLOCK {
            let (u0, u1, u2) = (l.o[0][k] - p0[0], l.o[1][k] - p0[1], l.o[2][k] - p0[2]);
            let [d0, d1, d2] = l.dir_at::<FIXED>(k, dir);
            let (z0, z1) = (l.z0[k], l.z1[k]);
            // `A·d` and `A·u` (`A` diagonal unless `full`).
            let (ad0, ad1, ad2, au0, au1, au2) = if full {
                (
                    a00 * d0 + a01 * d1 + a02 * d2,
                    a01 * d0 + a11 * d1 + a12 * d2,
                    a02 * d0 + a12 * d1 + a22 * d2,
                    a00 * u0 + a01 * u1 + a02 * u2,
                    a01 * u0 + a11 * u1 + a12 * u2,
                    a02 * u0 + a12 * u1 + a22 * u2,
                )
            } else {
                (a00 * d0, a11 * d1, a22 * d2, a00 * u0, a11 * u1, a22 * u2)
            };
            let a = d0 * ad0 + d1 * ad1 + d2 * ad2;
            let b = 2.0 * (u0 * ad0 + u1 * ad1 + u2 * ad2) + (g0 * d0 + g1 * d1 + g2 * d2);
            let c = c0 + (g0 * u0 + g1 * u1 + g2 * u2) + (u0 * au0 + u1 * au1 + u2 * au2);
            let zm = z0.abs().max(z1.abs());
            let t = 1e-9 * (a.abs() * zm * zm + b.abs() * zm + c.abs());
            let disc = b * b - 4.0 * a * c;
            // The roots `(−b ± √disc) / 2a`, where the slope `2az + b` is
            // `±√disc`, in the stable form: `h / a` and `c / h` with
            // `h = −(b + sign(b)·√disc) / 2`. For `b ≥ 0` the first is the
            // one out of the solid; `a = 0` (a plane) gives its one root as
            // `c / h` and ±∞ or NaN for the other. (`h / a` by a
            // reciprocal: in orthographic views `a` is the same in every
            // lane, and its division leaves the loop.)
            let sq = disc.max(0.0).sqrt();
            let h = -0.5 * (b + sq.copysign(b));
            let (r1, r2) = (h * (1.0 / a), c / h);
            let (enter, leave) = if b >= 0.0 { (r2, r1) } else { (r1, r2) };
            let real = disc >= 0.0;
            self.enter[k] = if real { enter } else { f64::NAN };
            self.leave[k] = if real { leave } else { f64::NAN };
            // A ray that grazes the leaf: its vertex (where the slope
            // changes sign) in range with a value (`−disc / 4a`) within
            // rounding of 0.
            let (s0, s1) = (2.0 * a * z0 + b, 2.0 * a * z1 + b);
            self.graze[k] = (a != 0.0) & (s0 * s1 <= 0.0) & (disc.abs() <= 4.0 * a.abs() * t);
            (self.a[k], self.b[k], self.c[k]) = (a, b, c);
            self.tol[k] = t;
        }
    }
}

/// Walks the set expression from the output down (see [`Csg::of`]).
struct Builder<'t> {
    tape: &'t Tape,
    prog: Vec<Step>,
    leaf_ids: Vec<NodeId>,
    /// Per leaf, whether it occurs under an even number of negations, and
    /// under an odd number.
    polarity: Vec<(bool, bool)>,
}

impl Builder<'_> {
    /// Appends node `id`'s set expression; `neg`: whether it is under an
    /// odd number of negations.
    fn walk(&mut self, id: NodeId, depth: usize, neg: bool) -> Option<()> {
        if depth > MAX_OPS || self.prog.len() > 2 * MAX_OPS {
            return None;
        }
        let node = self.tape.nodes[id.index()];
        let op = match node {
            Node::Binary(BinaryOp::RInter | BinaryOp::Min, a, b) => Some((a, b, Step::And, false)),
            Node::Binary(BinaryOp::RUnion | BinaryOp::Max, a, b) => Some((a, b, Step::Or, false)),
            // `a \ b` is `a & −b`.
            Node::Binary(BinaryOp::RDiff, a, b) => Some((a, b, Step::And, true)),
            _ => None,
        };
        if let Some((a, b, step, not_b)) = op {
            self.walk(a, depth + 1, neg)?;
            self.walk(b, depth + 1, neg != not_b)?;
            if not_b {
                self.prog.push(Step::Not);
            }
            self.prog.push(step);
            return Some(());
        }
        match node {
            Node::Unary(UnaryOp::Neg, a) => {
                self.walk(a, depth + 1, !neg)?;
                self.prog.push(Step::Not);
            }
            Node::Check(_, v) => self.walk(v, depth + 1, neg)?,
            _ => {
                let j = match self.leaf_ids.iter().position(|&l| l == id) {
                    Some(j) => j,
                    None if self.leaf_ids.len() < MAX_LEAVES => {
                        self.leaf_ids.push(id);
                        self.polarity.push((false, false));
                        self.leaf_ids.len() - 1
                    }
                    None => return None,
                };
                let p = &mut self.polarity[j];
                if neg {
                    p.1 = true;
                } else {
                    p.0 = true;
                }
                self.prog.push(Step::Leaf(j as u8));
            }
        }
        (self.prog.len() <= 2 * MAX_OPS).then_some(())
    }
}

/// Node `id` of `tape` as a quadric with the field's sign:
/// - a polynomial of degree at most 2 in the point gives that polynomial;
/// - a root gap `k − sqrt(p)` ([`Tape::root_gap`]) gives `k² − p` and,
///   second, `p`.
///
/// `None` where it is neither. Also `None` where the polynomial does not
/// agree with its quadric at the corners and centre of `bounds` (see
/// [`Csg::of`]).
fn leaf_quadric(
    tape: &Tape,
    id: NodeId,
    inputs: &Inputs,
    bounds: &Aabb,
) -> Option<(Quadric, Option<Quadric>)> {
    let sub = Tape::from_nodes(&tape.nodes, &[id]);
    if let Some(k) = sub.root_gap() {
        let Node::Binary(_, _, r) = tape.nodes[id.index()] else {
            return None;
        };
        let Node::Unary(_, p) = tape.nodes[r.index()] else {
            return None;
        };
        let p = polynomial_quadric(tape, p, inputs, bounds)?;
        let gap = Quadric {
            p0: p.p0,
            c: k * k - p.c,
            g: p.g.map(|v| -v),
            a: p.a.map(|row| row.map(|v| -v)),
        };
        return Some((gap, Some(p)));
    }
    Some((polynomial_quadric(tape, id, inputs, bounds)?, None))
}

/// Node `id` of `tape` as a quadric, where it is a polynomial of degree at
/// most 2 in the point that agrees with the quadric at the corners and
/// centre of `bounds`.
fn polynomial_quadric(tape: &Tape, id: NodeId, inputs: &Inputs, bounds: &Aabb) -> Option<Quadric> {
    let sub = Tape::from_nodes(&tape.nodes, &[id]);
    let degree = sub.polynomial_degree().filter(|&d| d <= 2)?;
    let (p0, h) = (bounds.center(), Quadric::fit_step(bounds));
    if !(h > 0.0 && h.is_finite()) {
        return None;
    }
    // The value and gradient at the fit's points, then the values at the
    // box's corners and `p0` again.
    let fit = Quadric::fit_points(p0, h);
    let pts: [[f64; 3]; 13] = std::array::from_fn(|j| match j {
        0..=3 => fit[j],
        4..=11 => std::array::from_fn(|k| {
            if (j - 4) >> k & 1 == 0 {
                bounds.min[k]
            } else {
                bounds.max[k]
            }
        }),
        _ => p0,
    });
    let mut gs = [Grad::default(); 13];
    BatchEval::new(&sub).eval_grad(
        &pts.map(|p| p[0]),
        &pts.map(|p| p[1]),
        &pts.map(|p| p[2]),
        inputs,
        &mut GradRegs::default(),
        &mut gs,
    );
    let qs: [(f64, [f64; 3]); 4] =
        std::array::from_fn(|j| (gs[j].v, [gs[j].dx, gs[j].dy, gs[j].dz]));
    let mut quad = Quadric::fit(p0, h, &qs);
    // (The terms a lower degree has not: exactly 0, not rounding.)
    if degree < 2 {
        quad.a = [[0.0; 3]; 3];
    }
    if degree == 0 {
        quad.g = [0.0; 3];
    }
    let Quadric { c, g, a, .. } = quad;
    let finite = [c]
        .iter()
        .chain(&g)
        .chain(a.iter().flatten())
        .all(|v| v.is_finite());
    if !finite {
        return None;
    }
    // The values at the box's corners and centre, against the quadric's.
    let agree = (4..13).all(|j| {
        let v = gs[j].v;
        let (want, scale) = quad.value_and_scale(pts[j]);
        v.is_finite() && (v - want).abs() <= 1e-9 * scale.max(v.abs())
    });
    agree.then_some(quad)
}

#[cfg(test)]
mod tests {
    use super::*;
    use frep_core::Model;

    fn csg(body: &str) -> Option<Csg> {
        let model = Model::compile(&format!("my_model(x[3], a[1]) {{ {body} }}")).unwrap();
        Csg::of(
            &model.tape(),
            &Inputs::default(),
            &Aabb::new([-1.0; 3], [1.0; 3]),
        )
    }

    /// R-functions, `min`, `max`, negations and `\` over fields of degree
    /// at most 2 are taken. So are the crossings that may start the solid:
    /// into a leaf under no negation, out of one under one. Blends, other
    /// functions of the point, degrees above 2 and more than
    /// [`MAX_LEAVES`] leaves are not.
    #[test]
    fn takes_set_expressions_over_quadrics() {
        let semi = csg("array c[3]; c = [0, 0, 0]; my_model = hfSphere(x, c, 1) & x[3];").unwrap();
        assert_eq!(semi.leaves(), 2);
        assert_eq!(semi.cands, [(0, true), (1, true)]);
        let diff = csg("my_model = (1 - x[1]^2 - x[2]^2) \\ (0.5 - x[1]^2 - x[3]^2);").unwrap();
        assert_eq!(diff.cands, [(0, true), (1, false)]);
        let both =
            csg("f = 0.5 - x[1]^2 - x[2]^2 - x[3]^2; my_model = max(f, -f & x[3]);").unwrap();
        assert_eq!(both.leaves(), 2);
        assert_eq!(both.cands, [(0, true), (0, false), (1, true)]);
        let planes = csg("my_model = min(min(1 - x[1], x[1] + 1), -x[3]);").unwrap();
        assert_eq!(planes.leaves(), 3);
        // A root gap `k − sqrt(p)`: `k² − p`, and `p ≥ 0` (where its value
        // is defined) joined to the whole expression.
        let gap = csg("my_model = (0.8 - sqrt(x[1]^2 + x[2]^2 + x[3]^2)) | (x[3] - 0.9);").unwrap();
        assert_eq!(gap.leaves(), 3);
        assert_eq!(gap.cands, [(0, true), (1, true), (2, true)]);
        assert_eq!(*gap.prog.last().unwrap(), Step::And);
        let (k2, p) = (&gap.leaves[0], &gap.leaves[2]);
        assert!((k2.c - (0.64 - p.c)).abs() < 1e-15 && k2.a[0][0] == -p.a[0][0]);
        for body in [
            "my_model = hfBlendInt(0.5 - x[1]^2 - x[2]^2 - x[3]^2, x[3], 0.1, 1, 1);",
            "my_model = (0.5 - x[1]^2 - x[2]^2 - x[3]^2) & sin(x[1]);",
            "my_model = 0.5 - x[1]^2 - x[2]^2 - x[3]^3;",
            "my_model = 0.5 - sqrt(x[1]^2 + x[2]^3);",
        ] {
            assert!(csg(body).is_none(), "{body}");
        }
        let spheres = |n: usize| {
            let terms: Vec<String> = (0..n)
                .map(|k| {
                    format!(
                        "(0.01 - (x[1] - {})^2 - x[2]^2 - x[3]^2)",
                        k as f64 * 0.2 - 0.8
                    )
                })
                .collect();
            format!("my_model = {};", terms.join(" | "))
        };
        assert_eq!(csg(&spheres(MAX_LEAVES)).unwrap().leaves(), MAX_LEAVES);
        assert!(csg(&spheres(MAX_LEAVES + 1)).is_none());
        // Deep expressions: a chain `a & (b & (a & ...))` of 60 operations
        // is taken (its stack checked), one past the depth limit is not.
        let chain = |n: usize| {
            let mut e = String::from("(0.5 - x[1]^2 - x[2]^2 - x[3]^2)");
            for k in 0..n {
                let leaf = ["(x[3] + 0.9)", "(0.5 - x[1]^2 - x[2]^2 - x[3]^2)"][k % 2];
                e = format!("({leaf} & {e})");
            }
            format!("my_model = {e};")
        };
        let deep = csg(&chain(60)).unwrap();
        assert_eq!(stack_depth(&deep.prog), Some(1));
        let mut l = Lanes::default();
        (l.o[2][0], l.d[2][0], l.z0[0], l.z1[0]) = (2.0, -1.0, 0.0, 4.0);
        let mut s = Solved::default();
        deep.solve(&l, 1, &mut Work::default(), &mut s, true);
        assert_eq!((s.sure, s.z[0]), (1, 2.0 - 0.5f64.sqrt()));
        assert!(csg(&chain(MAX_OPS + 1)).is_none());
    }

    /// Rays straight down (depth `z` at height `2 − z`) onto the unit
    /// sphere cut flat at height 0.5. They meet the flat face, the sphere
    /// below it, and nothing beside the sphere. One starts inside (its
    /// entry is the hit). Two are unsure: one tangent to the sphere, and
    /// one that starts on the flat face.
    #[test]
    fn solves_a_cut_sphere() {
        let c = csg("my_model = (1 - x[1]^2 - x[2]^2 - x[3]^2) & (0.5 - x[3]);").unwrap();
        let mut l = Lanes::default();
        let rays: [(f64, f64); 6] = [
            (0.0, 0.0),
            (0.95, 0.0),
            (1.2, 0.0),
            (0.0, 1.8),
            (1.0, 0.0),
            (0.0, 1.5),
        ];
        for (k, &(x, z0)) in rays.iter().enumerate() {
            for a in 0..3 {
                l.o[a][k] = [x, 0.0, 2.0][a];
                l.d[a][k] = [0.0, 0.0, -1.0][a];
            }
            (l.z0[k], l.z1[k]) = (z0, 4.0);
        }
        let mut s = Solved::default();
        c.solve(&l, rays.len(), &mut Work::default(), &mut s, true);
        assert_eq!(s.sure, 0b1111, "{:b}", s.sure);
        // (The compiler orders a commutative operation's operands: the
        // leaves' order is the tape's.)
        let sphere = c.leaves.iter().position(|q| q.a[0][0] != 0.0).unwrap() as u64;
        // (The normals are the leaves' gradients: compared as directions.)
        let n = |k: usize| {
            let v = [s.n[0][k], s.n[1][k], s.n[2][k]];
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            v.map(|c| c / l)
        };
        // The flat face at height 0.5.
        assert_eq!((s.z[0], s.leaf[0]), (1.5, 1 - sphere));
        assert_eq!(n(0).map(f64::abs), [0.0, 0.0, 1.0]);
        assert!(n(0)[2] > 0.0);
        // The sphere at height √(1 − 0.95²), its normal radial.
        let h = (1.0f64 - 0.95 * 0.95).sqrt();
        assert!((s.z[1] - (2.0 - h)).abs() < 1e-14, "{}", s.z[1]);
        assert_eq!(s.leaf[1], sphere);
        let want = [0.95, 0.0, h];
        assert!(
            (0..3).all(|a| (n(1)[a] - want[a]).abs() < 1e-14),
            "{:?}",
            n(1)
        );
        assert_eq!(s.z[2], f64::INFINITY);
        assert_eq!((s.z[3], s.leaf[3]), (1.8, ENTRY));
    }

    /// A root gap whose `p` is negative, its value NaN, in part of space:
    /// the solid ends where `p` turns negative. Along `y` through the
    /// origin, `0.6 − sqrt(x² − y² + 0.2)` is defined for `|y| ≤ √0.2`,
    /// and positive there. So the ray from `y = −2` enters at `y = −√0.2`,
    /// where `p` crosses 0, with the normal facing it.
    #[test]
    fn a_root_gap_ends_where_it_is_undefined() {
        let c = csg(
            "my_model = (0.6 - sqrt(x[1]^2 - x[2]^2 + 0.2)) & (0.8 - x[1]^2 - x[2]^2 - x[3]^2);",
        )
        .unwrap();
        assert_eq!(c.leaves(), 3);
        let mut l = Lanes::default();
        (l.o[1][0], l.d[1][0], l.z0[0], l.z1[0]) = (-2.0, 1.0, 0.0, 4.0);
        let mut s = Solved::default();
        c.solve(&l, 1, &mut Work::default(), &mut s, true);
        assert_eq!(s.sure, 1);
        assert!((s.z[0] - (2.0 - 0.2f64.sqrt())).abs() < 1e-14, "{}", s.z[0]);
        assert_eq!(s.leaf[0], 2);
        // (The normal is the leaf's gradient, `2y` along `y`.)
        let n = [s.n[0][0], s.n[1][0], s.n[2][0]];
        assert_eq!((n[0], n[2]), (0.0, 0.0));
        assert!((n[1] + 2.0 * 0.2f64.sqrt()).abs() < 1e-14, "{n:?}");
    }
}
