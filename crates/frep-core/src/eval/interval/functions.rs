//! Interval bounds of the unary functions: trigonometry, roots, logs,
//! exponentials and the rest of [`UnaryOp`].
//!
//! - `sin`/`cos` look for extrema inside the interval.
//! - `tan` is monotone between poles; a pole inside gives every value.
//! - Monotone functions take their ends, widened where libm rounds.

use super::arith::*;
use crate::eval::simd_math;
use crate::ops::{self, UnaryOp, EPS};
use std::f64::consts::{FRAC_PI_2, PI};

/// Whether `[lo - m, hi + m]` holds a point `off + k * period`.
pub(super) fn hits(a: Interval, off: f64, period: f64) -> bool {
    let m = extreme_margin(a);
    let n0 = ((a.lo - off) / period).floor();
    (-1..=2).any(|k| {
        let c = off + (n0 + f64::from(k)) * period;
        c >= a.lo - m && c <= a.hi + m
    })
}

pub(super) fn sin_cos(a: Interval, is_cos: bool) -> Interval {
    let (s, c) = sin_cos_pair(a);
    if is_cos {
        c
    } else {
        s
    }
}

/// `(sin a, cos a)`, from one reduction of each end.
pub(super) fn sin_cos_pair(a: Interval) -> (Interval, Interval) {
    let Some(nan) = trig_guard(a) else {
        let w = trig_whole(a);
        return (w, w);
    };
    // The batch evaluator's branch-free sin/cos (< 1 ulp from `std`, so
    // within the LIBM_ULPS widening; cheaper than libm's calls).
    let Some(t) = simd_math::sin_cos_ends(a.lo, a.hi) else {
        // Ends beyond the fast reduction's range: `std`, and the extremes
        // found by division.
        let (sl, cl) = simd_math::sin_cos(a.lo);
        let (sh, ch) = simd_math::sin_cos(a.hi);
        let [cmax, smax, cmin, smin] =
            [0.0, FRAC_PI_2, PI, -FRAC_PI_2].map(|off| hits(a, off, 2.0 * PI));
        return (
            trig_part(nan, sl, sh, smax, smin),
            trig_part(nan, cl, ch, cmax, cmin),
        );
    };
    let [cmax, smax, cmin, smin] = quarter_extremes(&t, extreme_margin(a));
    (
        trig_part(nan, t.sin[0], t.sin[1], smax, smin),
        trig_part(nan, t.cos[0], t.cos[1], cmax, cmin),
    )
}

/// How far outside an interval an extreme of sin/cos still counts as in
/// it (rounding of the ends and of the reduction).
pub(super) fn extreme_margin(a: Interval) -> f64 {
    1e-9 * (1.0 + a.lo.abs().max(a.hi.abs()))
}

/// Which of the points `j·π/2` lie in `[lo − m, hi + m]`, by `j mod 4`:
/// `[cos max, sin max, cos min, sin min]`, from the reductions of the ends
/// (`lo ≈ k₀·π/2 + r₀`, `hi ≈ k₁·π/2 + r₁`): no division.
pub(super) fn quarter_extremes(t: &simd_math::TrigEnds, m: f64) -> [bool; 4] {
    // The first j with j·π/2 ≥ lo − m: k₀ when r₀ ≤ m (|r| ≲ π/4, so k₀ − 1
    // never is), else k₀ + 1; the last with j·π/2 ≤ hi + m likewise.
    let first = t.k[0] + if t.r[0] <= m { 0.0 } else { 1.0 };
    let last = t.k[1] - if t.r[1] >= -m { 0.0 } else { 1.0 };
    let mut f = [false; 4];
    if last - first >= 3.0 {
        return [true; 4];
    }
    let mut j = first;
    while j <= last {
        // Whole numbers below 2^21: exact as integers.
        f[(j as i64).rem_euclid(4) as usize] = true;
        j += 1.0;
    }
    f
}

/// The NaN flag of `sin a` / `cos a` where its ends are worth evaluating;
/// `None` where [`trig_whole`] is the answer (empty, unbounded, a whole
/// period or more, or too large to reduce).
fn trig_guard(a: Interval) -> Option<bool> {
    let mag = a.lo.abs().max(a.hi.abs());
    if a.is_empty() || a.has_inf() || a.hi - a.lo >= 2.0 * PI || mag > 1e9 {
        None
    } else {
        Some(a.nan)
    }
}

/// `sin a` / `cos a` where [`trig_guard`] gives up: empty stays empty,
/// otherwise `[-1, 1]` (NaN possible where `a` holds an infinity).
fn trig_whole(a: Interval) -> Interval {
    if a.is_empty() {
        a
    } else {
        make(-1.0, 1.0, a.nan || a.has_inf())
    }
}

/// A sine-like function over an interval from its values `fl`, `fh` at
/// the ends, and whether the interval holds a maximum / a minimum.
fn trig_part(nan: bool, fl: f64, fh: f64, has_max: bool, has_min: bool) -> Interval {
    if has_max && has_min {
        // Both extremes inside: the ends do not matter.
        return make(-1.0, 1.0, nan);
    }
    let mut lo = down(fl.min(fh), LIBM_ULPS);
    let mut hi = up(fl.max(fh), LIBM_ULPS);
    if has_max {
        hi = 1.0;
    }
    if has_min {
        lo = -1.0;
    }
    make(lo.max(-1.0), hi.min(1.0), nan)
}

pub(super) fn tan(a: Interval) -> Interval {
    if a.is_empty() {
        return a;
    }
    let mag = a.lo.abs().max(a.hi.abs());
    if a.has_inf() || a.hi - a.lo >= PI || mag > 1e9 || hits(a, FRAC_PI_2, PI) {
        return Interval::ENTIRE;
    }
    let nan = a.nan || a.lo.cos().abs() < 2.0 * EPS || a.hi.cos().abs() < 2.0 * EPS;
    widen(make(a.lo.tan(), a.hi.tan(), nan), LIBM_ULPS)
}

/// A non-decreasing library function applied to the endpoints, widened.
fn mono(a: Interval, f: fn(f64) -> f64) -> Interval {
    if a.is_empty() {
        return a;
    }
    widen(make(f(a.lo), f(a.hi), a.nan), LIBM_ULPS)
}

/// A non-decreasing, correctly rounded or exact function of the endpoints.
fn mono_exact(a: Interval, f: fn(f64) -> f64) -> Interval {
    if a.is_empty() {
        return a;
    }
    make(f(a.lo), f(a.hi), a.nan)
}

fn log_iv(a: Interval, f: fn(f64) -> f64) -> Interval {
    if a.is_empty() {
        return a;
    }
    let nan = a.nan || a.lo <= 0.0;
    if !(a.hi > 0.0) {
        return none(nan);
    }
    let lo = if a.lo > 0.0 { a.lo } else { f64::from_bits(1) };
    widen(make(f(lo), f(a.hi), nan), LIBM_ULPS)
}

pub(super) fn sqrt_iv(a: Interval) -> Interval {
    if a.is_empty() {
        return a;
    }
    let nan = a.nan || a.lo < 0.0;
    if a.hi < 0.0 {
        return none(nan);
    }
    make(a.lo.max(0.0).sqrt(), a.hi.sqrt(), nan)
}

fn asin_acos(a: Interval, is_acos: bool) -> Interval {
    if a.is_empty() {
        return a;
    }
    let nan = a.nan || a.lo < -1.0 || a.hi > 1.0;
    let (lo, hi) = (a.lo.max(-1.0), a.hi.min(1.0));
    if lo > hi {
        return none(nan);
    }
    let r = if is_acos {
        make(hi.acos(), lo.acos(), nan)
    } else {
        make(lo.asin(), hi.asin(), nan)
    };
    widen(r, LIBM_ULPS)
}

fn abs_iv(a: Interval) -> Interval {
    if a.is_empty() {
        return a;
    }
    if a.lo >= 0.0 {
        make(a.lo.abs(), a.hi, a.nan)
    } else if a.hi <= 0.0 {
        make(-a.hi, -a.lo, a.nan)
    } else {
        make(0.0, (-a.lo).max(a.hi), a.nan)
    }
}

fn cosh_iv(a: Interval) -> Interval {
    if a.is_empty() {
        return a;
    }
    let (cl, ch) = (a.lo.cosh(), a.hi.cosh());
    let lo = if a.has(0.0) { 1.0 } else { cl.min(ch) };
    widen(make(lo, cl.max(ch), a.nan), LIBM_ULPS)
}

fn exp_iv(a: Interval) -> Interval {
    let r = mono(a, f64::exp);
    if r.is_empty() {
        r
    } else {
        make(r.lo.max(0.0), r.hi, r.nan)
    }
}

fn frac_iv(a: Interval) -> Interval {
    if a.is_empty() {
        return a;
    }
    let nan = a.nan || a.has_inf();
    let (tl, th) = (a.lo.trunc(), a.hi.trunc());
    if a.lo.is_finite() && a.hi.is_finite() && tl == th {
        make(a.lo - tl, a.hi - th, nan)
    } else {
        let lo = if a.lo >= 0.0 { 0.0 } else { -1.0 };
        let hi = if a.hi <= 0.0 { 0.0 } else { 1.0 };
        make(lo, hi, nan)
    }
}

pub(super) fn not_iv(a: Interval) -> Interval {
    // not(v) = 1 where v is falsy (NaN included), 0 where truthy.
    bool_iv(a.may_falsy(), a.may_truthy())
}

pub(super) fn unary(op: UnaryOp, a: Interval) -> Interval {
    match op {
        UnaryOp::Neg => neg(a),
        UnaryOp::Abs => abs_iv(a),
        UnaryOp::Sqrt | UnaryOp::SqrtF => sqrt_iv(a),
        UnaryOp::Exp => exp_iv(a),
        UnaryOp::Log => log_iv(a, f64::ln),
        UnaryOp::Logd => log_iv(a, f64::log10),
        UnaryOp::Sin => sin_cos(a, false),
        UnaryOp::Cos => sin_cos(a, true),
        UnaryOp::Tan => tan(a),
        UnaryOp::Asin => asin_acos(a, false),
        UnaryOp::Acos => asin_acos(a, true),
        UnaryOp::Atan => {
            let r = mono(a, f64::atan);
            let m = up(FRAC_PI_2, 1);
            if r.is_empty() {
                r
            } else {
                make(r.lo.max(-m), r.hi.min(m), r.nan)
            }
        }
        UnaryOp::Sinh => mono(a, f64::sinh),
        UnaryOp::Cosh => cosh_iv(a),
        UnaryOp::Tanh => {
            let r = mono(a, f64::tanh);
            if r.is_empty() {
                r
            } else {
                make(r.lo.max(-1.0), r.hi.min(1.0), r.nan)
            }
        }
        UnaryOp::Ceil => mono_exact(a, f64::ceil),
        UnaryOp::Floor => mono_exact(a, f64::floor),
        UnaryOp::Trunc => mono_exact(a, f64::trunc),
        UnaryOp::RoundHalfUp => mono_exact(a, ops::round_half_up),
        UnaryOp::Frac => frac_iv(a),
        UnaryOp::Not => not_iv(a),
    }
}
