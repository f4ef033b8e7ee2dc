//! Interval bounds of the binary operations and the blends.
//!
//! - `min`, `max`, R-union and R-intersection grow with both arguments;
//!   R-difference grows with the first and falls with the second. Their
//!   bounds come from the corners.
//! - Powers split by the sign of the base and the kind of exponent.
//! - Comparisons give `[0, 0]` or `[1, 1]` when decided, else `[0, 1]`.

use super::arith::*;
use crate::ops::{self, BinaryOp, BlendOp, EPS};
use std::f64::consts::PI;

pub(super) fn min_iv(a: Interval, b: Interval) -> Interval {
    // min(a, b) = if a < b { a } else { b }: NaN a gives b, NaN b gives NaN.
    let mut r = none(b.nan);
    if !a.is_empty() && !b.is_empty() {
        r = r.hull(Interval::new(a.lo.min(b.lo), a.hi.min(b.hi)));
    }
    if a.nan && !b.is_empty() {
        r = r.hull(Interval::new(b.lo, b.hi));
    }
    r
}

pub(super) fn max_iv(a: Interval, b: Interval) -> Interval {
    let mut r = none(b.nan);
    if !a.is_empty() && !b.is_empty() {
        r = r.hull(Interval::new(a.lo.max(b.lo), a.hi.max(b.hi)));
    }
    if a.nan && !b.is_empty() {
        r = r.hull(Interval::new(b.lo, b.hi));
    }
    r
}

/// The R-functions: monotone, bounds from the corners, widened by their
/// rounding error (about 5 eps (|a| + |b|), plus underflow of the squares).
pub(super) fn rfun(op: BinaryOp, a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let nan = a.nan || b.nan;
    let m = a.lo.abs().max(a.hi.abs()) + b.lo.abs().max(b.hi.abs());
    if !(m <= SQUARE_SAFE) {
        return Interval::ENTIRE;
    }
    let w = 8.0 * f64::EPSILON * m + 1e-160;
    let (lo, hi) = match op {
        BinaryOp::RUnion => (ops::r_union(a.lo, b.lo), ops::r_union(a.hi, b.hi)),
        BinaryOp::RInter => (ops::r_inter(a.lo, b.lo), ops::r_inter(a.hi, b.hi)),
        _ => (ops::r_diff(a.lo, b.hi), ops::r_diff(a.hi, b.lo)),
    };
    make(next_down(lo - w), next_up(hi + w), nan)
}

pub(super) fn blend_iv(op: BlendOp, [f1, f2, a0, a1, a2]: [Interval; 5]) -> Interval {
    let r = rfun(
        match op {
            BlendOp::Union => BinaryOp::RUnion,
            BlendOp::Inter => BinaryOp::RInter,
        },
        f1,
        f2,
    );
    let t1 = div_ieee(f1, a1);
    let t2 = div_ieee(f2, a2);
    let q = add(add(Interval::point(1.0), sqr(t1)), sqr(t2));
    add(r, div_ieee(a0, q))
}

fn atan2_iv(y: Interval, x: Interval) -> Interval {
    if y.is_empty() || x.is_empty() {
        return none(y.nan || x.nan);
    }
    let nan = y.nan || x.nan;
    // Away from the cut (x < 0, y = 0) and the origin, atan2 is monotone in
    // each argument: its extrema are at the corners.
    if x.lo > 0.0 || y.lo > 0.0 || y.hi < 0.0 {
        let c = [
            y.lo.atan2(x.lo),
            y.lo.atan2(x.hi),
            y.hi.atan2(x.lo),
            y.hi.atan2(x.hi),
        ];
        widen(corners(c, nan), LIBM_ULPS)
    } else {
        widen(make(-PI, PI, nan), LIBM_ULPS)
    }
}

fn mod_iv(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let r = ops::round_half_up;
    let ra = Interval::new(r(a.lo), r(a.hi));
    let rb = Interval::new(r(b.lo), r(b.hi));
    let nan = a.nan || b.nan || ra.has_inf() || rb.has(0.0);
    if rb.lo == rb.hi && rb.lo != 0.0 && rb.lo.is_finite() && ra.lo.abs().max(ra.hi.abs()) < 1e15 {
        let d = rb.lo.abs();
        let same = |p: f64, q: f64| (p.abs() / d).floor() == (q.abs() / d).floor();
        if (ra.lo >= 0.0 || ra.hi <= 0.0) && same(ra.lo, ra.hi) {
            return make(ra.lo % d, ra.hi % d, nan);
        }
    }
    let m = ra
        .lo
        .abs()
        .max(ra.hi.abs())
        .min(rb.lo.abs().max(rb.hi.abs()));
    let lo = if ra.lo >= 0.0 { 0.0 } else { -m };
    let hi = if ra.hi <= 0.0 { 0.0 } else { m };
    make(lo, hi, nan)
}

/// Bounds of `b^e` for `b > 0` over the box, computed either as
/// `exp(e ln b)` or by repeated multiplication: `b^e` is monotone in each
/// argument, so the corners bound it; widened by the relative rounding error.
fn pow_pos(b: Interval, e: Interval) -> Interval {
    let c = [
        b.lo.powf(e.lo),
        b.lo.powf(e.hi),
        b.hi.powf(e.lo),
        b.hi.powf(e.hi),
    ];
    let t = [b.lo, b.hi]
        .iter()
        .flat_map(|&bb| [e.lo, e.hi].map(|ee| (ee * bb.ln()).abs()))
        .fold(0.0, f64::max);
    let n = e.lo.abs().max(e.hi.abs());
    widen_rel(corners(c, false), 8.0 * f64::EPSILON * (t + n + 4.0))
}

/// HyperFun's checked `b ^ e` ([`ops::hf_pow`]).
fn hf_pow_iv(b: Interval, e: Interval) -> Interval {
    if e.lo == e.hi && !e.nan && e.lo.is_finite() {
        let ev = e.lo;
        if ev - ev.floor() < EPS {
            let n = ops::round_half_up(ev.abs());
            if n <= f64::from(i32::MAX) {
                let n = n as i32;
                return powi_iv(b, if ev < 0.0 { -n } else { n });
            }
        }
    }
    let mut r = none(false);
    let mut nan = false;
    let may_small = !b.is_empty() && b.lo < EPS && b.hi > -EPS;
    if b.nan {
        // Not small; an exponent in [0, EPS) is the integer 0: 1.
        nan = true;
        if !e.is_empty() && e.lo < EPS && e.hi >= 0.0 {
            r = r.hull(Interval::point(1.0));
        }
    }
    if e.nan {
        nan = true;
        if may_small {
            r = r.hull(Interval::point(0.0));
        }
    }
    if b.is_empty() || e.is_empty() {
        return r.with_nan(nan);
    }
    if may_small {
        if e.lo <= EPS {
            nan = true;
        }
        if e.hi > EPS {
            r = r.hull(Interval::point(0.0));
        }
    }
    // Integer-like exponents lie within EPS above the integer they use.
    let ext = Interval::new(e.lo - EPS, e.hi);
    let nonint = e.lo != e.hi || !(e.lo - e.lo.floor() < EPS);
    if b.lo <= -EPS {
        if nonint {
            nan = true;
        }
        let mag = pow_pos(Interval::new(b.hi.min(-EPS).abs(), b.lo.abs()), ext);
        if !mag.is_empty() {
            r = r.hull(make(-mag.hi, mag.hi, mag.nan));
        }
    }
    if b.hi >= EPS {
        r = r.hull(pow_pos(Interval::new(b.lo.max(EPS), b.hi), ext));
        // exp(inf * ln 1) is NaN.
        nan |= e.has_inf();
    }
    r.with_nan(nan)
}

/// `b ^ n` for a constant integer `n` ([`ops::pow_int`]): exact bounds from
/// the monotone repeated product on each side of the zero gap.
pub(super) fn powi_iv(b: Interval, n: i32) -> Interval {
    let m = n.unsigned_abs();
    let ulps = if f64::from(m) > ops::POW_LOOP_MAX {
        LIBM_ULPS
    } else {
        0
    };
    let pr = |v: f64| ops::pow_repeated(v, f64::from(m), false);
    let mut r = none(b.nan && n != 0);
    if b.nan && n == 0 {
        r = r.hull(Interval::point(1.0));
    }
    if b.is_empty() {
        return r;
    }
    if b.lo < EPS && b.hi > -EPS {
        if n >= 1 {
            r = r.hull(Interval::point(0.0));
        } else {
            r = r.with_nan(true);
        }
    }
    let invert = |lo: f64, hi: f64| {
        if n < 0 {
            (1.0 / hi, 1.0 / lo)
        } else {
            (lo, hi)
        }
    };
    if b.hi >= EPS {
        let (lo, hi) = invert(pr(b.lo.max(EPS)), pr(b.hi));
        r = r.hull(widen(make(lo, hi, false), ulps));
    }
    if b.lo <= -EPS {
        let (ml, mh) = (pr(b.hi.min(-EPS).abs()), pr(b.lo.abs()));
        let (lo, hi) = if m.is_multiple_of(2) {
            (ml, mh)
        } else {
            (-mh, -ml)
        };
        let (lo, hi) = invert(lo, hi);
        r = r.hull(widen(make(lo, hi, false), ulps));
    }
    r
}

/// C's `pow`.
fn powf_iv(b: Interval, e: Interval) -> Interval {
    let mut r = none(b.nan || e.nan);
    if b.nan && e.has(0.0) {
        r = r.hull(Interval::point(1.0));
    }
    if e.nan && b.has(1.0) {
        r = r.hull(Interval::point(1.0));
    }
    if b.is_empty() || e.is_empty() {
        return r;
    }
    if b.lo > 0.0 {
        let c = [
            b.lo.powf(e.lo),
            b.lo.powf(e.hi),
            b.hi.powf(e.lo),
            b.hi.powf(e.hi),
        ];
        return r.hull(widen(corners(c, false), LIBM_ULPS));
    }
    let e_int = e.lo == e.hi && e.lo.is_finite() && e.lo.fract() == 0.0;
    let nan = b.lo < 0.0 && !e_int;
    let ml = if b.has(0.0) {
        0.0
    } else {
        b.lo.abs().min(b.hi.abs())
    };
    let mh = b.lo.abs().max(b.hi.abs());
    let c = [ml.powf(e.lo), ml.powf(e.hi), mh.powf(e.lo), mh.powf(e.hi)];
    let mag = widen(corners(c, false), LIBM_ULPS);
    r.hull(make(-mag.hi, mag.hi, nan || mag.nan))
}

fn compare(op: BinaryOp, a: Interval, b: Interval) -> Interval {
    let ne = !a.is_empty() && !b.is_empty();
    let an = a.nan || b.nan;
    let (t, f) = match op {
        BinaryOp::Lt => (ne && a.lo < b.hi, an || (ne && a.hi >= b.lo)),
        BinaryOp::Gt => (ne && a.hi > b.lo, an || (ne && a.lo <= b.hi)),
        BinaryOp::Le => (ne && a.lo <= b.hi, an || (ne && a.hi > b.lo)),
        BinaryOp::Ge => (ne && a.hi >= b.lo, an || (ne && a.lo < b.hi)),
        BinaryOp::Eq | BinaryOp::Ne => {
            let d = sub(a, b);
            let de = !d.is_empty();
            let close = de && d.lo < EPS && d.hi > -EPS;
            let far = de && (d.lo <= -EPS || d.hi >= EPS);
            if op == BinaryOp::Eq {
                (close, far || d.nan)
            } else {
                (far, close || d.nan)
            }
        }
        BinaryOp::And => (
            a.may_truthy() && b.may_truthy(),
            a.may_falsy() || b.may_falsy(),
        ),
        BinaryOp::Or => (
            a.may_truthy() || b.may_truthy(),
            a.may_falsy() && b.may_falsy(),
        ),
        _ => unreachable!("not a comparison"),
    };
    bool_iv(t, f)
}

pub(super) fn binary(op: BinaryOp, a: Interval, b: Interval, same: bool) -> Interval {
    match op {
        BinaryOp::Add => add(a, b),
        BinaryOp::Sub => sub(a, b),
        BinaryOp::Mul if same => sqr(a),
        BinaryOp::Mul => mul(a, b),
        BinaryOp::Div => div_checked(a, b),
        BinaryOp::DivF => div_ieee(a, b),
        BinaryOp::Pow => hf_pow_iv(a, b),
        BinaryOp::PowF => powf_iv(a, b),
        BinaryOp::Min => min_iv(a, b),
        BinaryOp::Max => max_iv(a, b),
        BinaryOp::Atan2 => atan2_iv(a, b),
        BinaryOp::Mod => mod_iv(a, b),
        BinaryOp::RUnion | BinaryOp::RInter | BinaryOp::RDiff => rfun(op, a, b),
        BinaryOp::Lt
        | BinaryOp::Gt
        | BinaryOp::Le
        | BinaryOp::Ge
        | BinaryOp::Eq
        | BinaryOp::Ne
        | BinaryOp::And
        | BinaryOp::Or => compare(op, a, b),
    }
}
