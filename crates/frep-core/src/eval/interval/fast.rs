//! The register file and the evaluator's fast paths.
//!
//! The fast paths take nonempty, finite bounds. There no infinity meets a
//! zero or an opposite infinity, and no bound becomes NaN. So each gives
//! exactly what the general rule gives; every other case goes to the
//! general rule.
//!
//! Each path reads its arguments and writes its result in the registers.
//! The general rules are out-of-line calls that do the same. A result
//! merged from both paths would go through the stack and be loaded back in
//! a width that the store cannot forward.

use super::{arith::*, binary::*, functions::*};
use crate::ops::{self, BinaryOp, EPS};

/// Nonempty with finite bounds.
#[inline(always)]
fn finite1(a: Interval) -> bool {
    let w = a.hi - a.lo;
    (0.0..f64::INFINITY).contains(&w)
}

/// Both nonempty with finite bounds (or a conservative no).
#[inline(always)]
fn finite2(a: Interval, b: Interval) -> bool {
    let (wa, wb) = (a.hi - a.lo, b.hi - b.lo);
    (wa >= 0.0) & (wb >= 0.0) & (wa + wb < f64::INFINITY)
}

/// Out-of-line general rules: `v[out] = f(v[a], ..)`. They take indices,
/// not intervals, so that the fast path keeps its arguments in registers.
macro_rules! slow {
    ($name:ident, $f:expr, $($a:ident),+) => {
        #[cold]
        #[inline(never)]
        fn $name(v: &mut Regs, out: usize, $($a: u32),+) {
            v.set(out, $f($(v.get($a)),+));
        }
    };
}

slow!(add_slow, add, a, b);
slow!(sub_slow, sub, a, b);
slow!(mul_slow, mul, a, b);
slow!(sqr_slow, sqr, a);
slow!(neg_slow, neg, a);
slow!(sqrt_slow, sqrt_iv, a);
slow!(powi2_slow, |a| powi_iv(a, 2), a);
slow!(min_slow, min_iv, a, b);
slow!(max_slow, max_iv, a, b);
slow!(runion_slow, |a, b| rfun(BinaryOp::RUnion, a, b), a, b);
slow!(rinter_slow, |a, b| rfun(BinaryOp::RInter, a, b), a, b);
slow!(rdiff_slow, |a, b| rfun(BinaryOp::RDiff, a, b), a, b);

#[inline(always)]
pub(super) fn add_at(v: &mut Regs, out: usize, i: u32, j: u32) {
    let (a, b) = (v.get(i), v.get(j));
    if finite2(a, b) {
        v.set(
            out,
            Interval {
                lo: a.lo + b.lo,
                hi: a.hi + b.hi,
                nan: a.nan | b.nan,
            },
        );
    } else {
        add_slow(v, out, i, j);
    }
}

#[inline(always)]
pub(super) fn sub_at(v: &mut Regs, out: usize, i: u32, j: u32) {
    let (a, b) = (v.get(i), v.get(j));
    if finite2(a, b) {
        v.set(
            out,
            Interval {
                lo: a.lo - b.hi,
                hi: a.hi - b.lo,
                nan: a.nan | b.nan,
            },
        );
    } else {
        sub_slow(v, out, i, j);
    }
}

#[inline(always)]
pub(super) fn mul_at(v: &mut Regs, out: usize, i: u32, j: u32) {
    let (a, b) = (v.get(i), v.get(j));
    if finite2(a, b) {
        let c = [a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi];
        v.set(
            out,
            Interval {
                lo: c.iter().copied().fold(f64::INFINITY, f64::min),
                hi: c.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                nan: a.nan | b.nan,
            },
        );
    } else {
        mul_slow(v, out, i, j);
    }
}

#[inline(always)]
pub(super) fn sqr_at(v: &mut Regs, out: usize, i: u32) {
    let a = v.get(i);
    if finite1(a) {
        let (l, h) = (a.lo * a.lo, a.hi * a.hi);
        let (lo, hi) = if a.lo >= 0.0 {
            (l, h)
        } else if a.hi <= 0.0 {
            (h, l)
        } else {
            (0.0, l.max(h))
        };
        v.set(out, Interval { lo, hi, nan: a.nan });
    } else {
        sqr_slow(v, out, i);
    }
}

#[inline(always)]
pub(super) fn neg_at(v: &mut Regs, out: usize, i: u32) {
    let a = v.get(i);
    if finite1(a) {
        v.set(
            out,
            Interval {
                lo: -a.hi,
                hi: -a.lo,
                nan: a.nan,
            },
        );
    } else {
        neg_slow(v, out, i);
    }
}

#[inline(always)]
pub(super) fn sqrt_at(v: &mut Regs, out: usize, i: u32) {
    let a = v.get(i);
    if finite1(a) & (a.lo >= 0.0) {
        v.set(
            out,
            Interval {
                lo: a.lo.max(0.0).sqrt(),
                hi: a.hi.sqrt(),
                nan: a.nan,
            },
        );
    } else {
        sqrt_slow(v, out, i);
    }
}

/// `b ^ 2` away from the zero gap `(-EPS, EPS)`, where the rule is the
/// square's.
#[inline(always)]
pub(super) fn powi2_at(v: &mut Regs, out: usize, i: u32) {
    let b = v.get(i);
    let (l, h) = (b.lo * b.lo, b.hi * b.hi);
    if finite1(b) & (b.lo >= EPS) {
        v.set(
            out,
            Interval {
                lo: l,
                hi: h,
                nan: b.nan,
            },
        );
    } else if finite1(b) & (b.hi <= -EPS) {
        v.set(
            out,
            Interval {
                lo: h,
                hi: l,
                nan: b.nan,
            },
        );
    } else {
        powi2_slow(v, out, i);
    }
}

#[inline(always)]
pub(super) fn min_at(v: &mut Regs, out: usize, i: u32, j: u32) {
    let (a, b) = (v.get(i), v.get(j));
    if !(a.nan | b.nan) & (a.lo <= a.hi) & (b.lo <= b.hi) {
        v.set(
            out,
            Interval {
                lo: a.lo.min(b.lo),
                hi: a.hi.min(b.hi),
                nan: false,
            },
        );
    } else {
        min_slow(v, out, i, j);
    }
}

#[inline(always)]
pub(super) fn max_at(v: &mut Regs, out: usize, i: u32, j: u32) {
    let (a, b) = (v.get(i), v.get(j));
    if !(a.nan | b.nan) & (a.lo <= a.hi) & (b.lo <= b.hi) {
        v.set(
            out,
            Interval {
                lo: a.lo.max(b.lo),
                hi: a.hi.max(b.hi),
                nan: false,
            },
        );
    } else {
        max_slow(v, out, i, j);
    }
}

/// The R-functions on moderate arguments (see [`rfun`]).
#[inline(always)]
pub(super) fn rfun_at(v: &mut Regs, out: usize, op: BinaryOp, i: u32, j: u32) {
    let (a, b) = (v.get(i), v.get(j));
    let m = a.lo.abs().max(a.hi.abs()) + b.lo.abs().max(b.hi.abs());
    if finite2(a, b) & (m <= SQUARE_SAFE) {
        let w = 8.0 * f64::EPSILON * m + 1e-160;
        let (lo, hi) = match op {
            BinaryOp::RUnion => (ops::r_union(a.lo, b.lo), ops::r_union(a.hi, b.hi)),
            BinaryOp::RInter => (ops::r_inter(a.lo, b.lo), ops::r_inter(a.hi, b.hi)),
            _ => (ops::r_diff(a.lo, b.hi), ops::r_diff(a.hi, b.lo)),
        };
        v.set(
            out,
            Interval {
                lo: next_down(lo - w),
                hi: next_up(hi + w),
                nan: a.nan | b.nan,
            },
        );
    } else {
        match op {
            BinaryOp::RUnion => runion_slow(v, out, i, j),
            BinaryOp::RInter => rinter_slow(v, out, i, j),
            _ => rdiff_slow(v, out, i, j),
        }
    }
}

/// The nodes' intervals, one array per field: reads and writes of single
/// fields never meet a wider access to the same bytes (which the store
/// buffer cannot forward).
#[derive(Clone, Debug, Default)]
pub(super) struct Regs {
    /// One interval per node (one bounds check per access).
    pub(super) r: Vec<Interval>,
}

impl Regs {
    #[inline(always)]
    pub(super) fn get(&self, i: u32) -> Interval {
        self.r[i as usize]
    }

    #[inline(always)]
    pub(super) fn set(&mut self, i: usize, r: Interval) {
        self.r[i] = r;
    }
}
