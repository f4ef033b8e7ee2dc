//! Interval evaluation of a [`Tape`] over an axis-aligned box, with the
//! per-node [`Choice`]s that [`simplify`](crate::simplify::simplify) uses to
//! shorten the tape inside that box.
//!
//! ## What an [`Interval`] means
//! An interval bounds the values that the *bulk* evaluators compute (f64,
//! runtime errors mapped to NaN, `Check` guards ignored) at every point of the
//! box: every non-NaN value lies in `[lo, hi]` (infinities included), and
//! `nan` is set when some point may give NaN. An interval with `lo > hi` has
//! no non-NaN value: with `nan` set it is "always NaN" ([`Interval::NAN`]),
//! without it "no value at all" ([`Interval::EMPTY`], only seen for
//! unreachable cases).
//!
//! The bounds are those of the *computed* floating-point values, not of the
//! real-number functions: correctly rounded operations (`+ - * /`, `sqrt`,
//! `floor`, ...) are monotone after rounding, so their corner values are exact
//! bounds; library functions (`sin`, `exp`, `atan2`, ...) are widened by a
//! few ulps; composite formulas (R-functions, blends, powers) by a bound on
//! their rounding error.
//!
//! ## Rules
//! * `min`/`max`, R-union and R-intersection are monotone non-decreasing in
//!   both arguments, R-difference `a \ b` is increasing in `a` and decreasing
//!   in `b`: their bounds come from the corners (this is what makes R-function
//!   models prunable, see the notes on rendering and meshing).
//! * `sin`/`cos` find the extrema inside the interval; `tan` is monotone
//!   between poles (a pole inside gives `[-inf, inf]` and NaN); checked
//!   operations set `nan` where their error region meets the interval.
//! * Comparisons and `and`/`or`/`not` give `[0, 0]`, `[1, 1]` when decided,
//!   else `[0, 1]`; a NaN operand counts as false, as in the bulk evaluators.
//! * `select` takes the branch(es) its condition may choose.

use super::{simd_math, Inputs};
use crate::graph::{Node, NodeId, Tape};
use crate::ops::{self, BinaryOp, BlendOp, UnaryOp, EPS};
use std::collections::HashMap;
use std::f64::consts::{FRAC_PI_2, PI};
use std::sync::{Mutex, OnceLock, PoisonError};

/// The least double above `x` (`x` itself for `+inf` and NaN).
#[inline]
pub fn next_up(x: f64) -> f64 {
    if !(x < f64::INFINITY) {
        return x;
    }
    // Up is one more in the bits of a positive number, one less in those
    // of a negative one; both zeros step to the least positive double.
    let b = if x == 0.0 { 0 } else { x.to_bits() as i64 };
    f64::from_bits(b.wrapping_add(1 | (b >> 63)) as u64)
}

/// The greatest double below `x` (`x` itself for `-inf` and NaN).
#[inline]
pub fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// Whether `ulps` steps from `x` are plain steps of its bits: a normal
/// number, away from zero and the infinities.
#[inline(always)]
fn bit_steps(x: f64) -> bool {
    (f64::MIN_POSITIVE..=1e300).contains(&x.abs())
}

fn down(mut x: f64, ulps: u32) -> f64 {
    if bit_steps(x) {
        let (b, n) = (x.to_bits(), u64::from(ulps));
        return f64::from_bits(if x > 0.0 { b - n } else { b + n });
    }
    for _ in 0..ulps {
        x = next_down(x);
    }
    x
}

fn up(mut x: f64, ulps: u32) -> f64 {
    if bit_steps(x) {
        let (b, n) = (x.to_bits(), u64::from(ulps));
        return f64::from_bits(if x > 0.0 { b + n } else { b - n });
    }
    for _ in 0..ulps {
        x = next_up(x);
    }
    x
}

/// Widening (in ulps) of results of the C math library's functions, and of
/// `simd_math`'s sin and cos (within 1 ulp of `std`'s).
const LIBM_ULPS: u32 = 4;

/// Magnitude above which squares inside R-functions may overflow.
const SQUARE_SAFE: f64 = 1e150;

/// Bounds on the values an expression takes over a box (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// Lower bound of the non-NaN values (may be `-inf`).
    pub lo: f64,
    /// Upper bound of the non-NaN values (may be `+inf`).
    pub hi: f64,
    /// Whether some point of the box may give NaN.
    pub nan: bool,
}

impl Interval {
    /// Every value, NaN included.
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
        nan: true,
    };
    /// Always NaN (no non-NaN value).
    pub const NAN: Interval = Interval {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
        nan: true,
    };
    /// No value at all (an unreachable case).
    pub const EMPTY: Interval = Interval {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
        nan: false,
    };

    /// `[lo, hi]` without NaN. NaN bounds widen to infinities and set `nan`.
    pub fn new(lo: f64, hi: f64) -> Interval {
        make(lo, hi, false)
    }

    /// The single value `v` (NaN gives [`Interval::NAN`]).
    pub fn point(v: f64) -> Interval {
        if v.is_nan() {
            Interval::NAN
        } else {
            Interval {
                lo: v,
                hi: v,
                nan: false,
            }
        }
    }

    /// The same bounds, with `nan` also set when `nan` is.
    pub fn with_nan(self, nan: bool) -> Interval {
        Interval {
            nan: self.nan || nan,
            ..self
        }
    }

    /// Whether no non-NaN value is possible.
    pub fn is_empty(&self) -> bool {
        !(self.lo <= self.hi)
    }

    /// Whether `v` is a possible value (NaN: whether `nan` is set).
    pub fn contains(&self, v: f64) -> bool {
        if v.is_nan() {
            self.nan
        } else {
            self.lo <= v && v <= self.hi
        }
    }

    /// Strictly positive everywhere, never NaN: inside the solid throughout.
    pub fn is_positive(&self) -> bool {
        !self.nan && self.lo > 0.0
    }

    /// Strictly negative everywhere, never NaN.
    pub fn is_negative(&self) -> bool {
        !self.nan && self.hi < 0.0
    }

    /// Negative or NaN everywhere: outside the solid throughout (NaN counts
    /// as outside).
    pub fn is_outside(&self) -> bool {
        self.hi < 0.0 || self.is_empty()
    }

    /// `hi - lo` (0 for an empty interval).
    pub fn width(&self) -> f64 {
        if self.is_empty() {
            0.0
        } else {
            self.hi - self.lo
        }
    }

    /// The midpoint (NaN for an empty interval).
    pub fn mid(&self) -> f64 {
        if self.is_empty() {
            f64::NAN
        } else if self.lo.is_finite() && self.hi.is_finite() {
            self.lo + 0.5 * (self.hi - self.lo)
        } else {
            0.5 * (self.lo + self.hi)
        }
    }

    /// The smallest interval holding both.
    pub fn hull(self, o: Interval) -> Interval {
        Interval {
            lo: self.lo.min(o.lo),
            hi: self.hi.max(o.hi),
            nan: self.nan || o.nan,
        }
    }

    /// Whether the non-NaN part contains `v`.
    fn has(&self, v: f64) -> bool {
        self.lo <= v && v <= self.hi
    }

    /// Whether an infinite value is possible.
    fn has_inf(&self) -> bool {
        !self.is_empty() && (self.lo == f64::NEG_INFINITY || self.hi == f64::INFINITY)
    }

    /// Whether some value may count as true (`|v| >= 1e-6`).
    fn may_truthy(&self) -> bool {
        !self.is_empty() && (self.lo <= -EPS || self.hi >= EPS)
    }

    /// Whether some value may count as false (`|v| < 1e-6` or NaN).
    fn may_falsy(&self) -> bool {
        self.nan || (!self.is_empty() && self.lo < EPS && self.hi > -EPS)
    }

    /// Non-NaN and finite, with a magnitude that R-functions square safely.
    fn tame(&self) -> bool {
        !self.nan && !self.is_empty() && self.lo >= -SQUARE_SAFE && self.hi <= SQUARE_SAFE
    }
}

/// `[lo, hi]` with the flag; NaN bounds become infinite and set the flag.
fn make(lo: f64, hi: f64, nan: bool) -> Interval {
    let mut iv = Interval { lo, hi, nan };
    if lo.is_nan() {
        iv.lo = f64::NEG_INFINITY;
        iv.nan = true;
    }
    if hi.is_nan() {
        iv.hi = f64::INFINITY;
        iv.nan = true;
    }
    iv
}

fn none(nan: bool) -> Interval {
    Interval {
        nan,
        ..Interval::EMPTY
    }
}

fn bool_iv(may_true: bool, may_false: bool) -> Interval {
    match (may_true, may_false) {
        (true, true) => Interval::new(0.0, 1.0),
        (true, false) => Interval::point(1.0),
        (false, true) => Interval::point(0.0),
        (false, false) => Interval::EMPTY,
    }
}

/// Hull of corner values; any NaN corner gives everything.
fn corners(c: [f64; 4], nan: bool) -> Interval {
    if c.iter().any(|v| v.is_nan()) {
        return Interval::ENTIRE;
    }
    let lo = c.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    make(lo, hi, nan)
}

fn widen(iv: Interval, ulps: u32) -> Interval {
    if iv.is_empty() {
        return iv;
    }
    Interval {
        lo: down(iv.lo, ulps),
        hi: up(iv.hi, ulps),
        nan: iv.nan,
    }
}

/// Widens by a relative error `rel` (and one ulp).
fn widen_rel(iv: Interval, rel: f64) -> Interval {
    if iv.is_empty() {
        return iv;
    }
    if !(rel < 0.5) {
        let lo = if iv.lo >= 0.0 { 0.0 } else { f64::NEG_INFINITY };
        let hi = if iv.hi <= 0.0 { 0.0 } else { f64::INFINITY };
        return make(lo, hi, iv.nan);
    }
    let lo = if iv.lo >= 0.0 {
        iv.lo * (1.0 - rel)
    } else {
        iv.lo * (1.0 + rel)
    };
    let hi = if iv.hi >= 0.0 {
        iv.hi * (1.0 + rel)
    } else {
        iv.hi * (1.0 - rel)
    };
    make(next_down(lo), next_up(hi), iv.nan)
}

fn neg(a: Interval) -> Interval {
    if a.is_empty() {
        return a;
    }
    make(-a.hi, -a.lo, a.nan)
}

fn add(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let inf = f64::INFINITY;
    let nan = a.nan || b.nan || (a.hi == inf && b.lo == -inf) || (a.lo == -inf && b.hi == inf);
    make(a.lo + b.lo, a.hi + b.hi, nan)
}

fn sub(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let inf = f64::INFINITY;
    let nan = a.nan || b.nan || (a.hi == inf && b.hi == inf) || (a.lo == -inf && b.lo == -inf);
    make(a.lo - b.hi, a.hi - b.lo, nan)
}

fn mul(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let nan = a.nan || b.nan || (a.has(0.0) && b.has_inf()) || (b.has(0.0) && a.has_inf());
    corners([a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi], nan)
}

fn sqr(a: Interval) -> Interval {
    if a.is_empty() {
        return a;
    }
    let (l, h) = (a.lo * a.lo, a.hi * a.hi);
    if a.lo >= 0.0 {
        make(l, h, a.nan)
    } else if a.hi <= 0.0 {
        make(h, l, a.nan)
    } else {
        make(0.0, l.max(h), a.nan)
    }
}

/// `a / [blo, bhi]` for a divisor interval without 0.
fn div_part(a: Interval, blo: f64, bhi: f64, nan: bool) -> Interval {
    corners([a.lo / blo, a.lo / bhi, a.hi / blo, a.hi / bhi], nan)
}

fn div_checked(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let nan = a.nan || b.nan || (b.lo < EPS && b.hi > -EPS);
    let mut r = none(nan);
    if b.lo <= -EPS {
        r = r.hull(div_part(a, b.lo, b.hi.min(-EPS), false));
    }
    if b.hi >= EPS {
        r = r.hull(div_part(a, b.lo.max(EPS), b.hi, false));
    }
    r
}

fn div_ieee(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let nan = a.nan || b.nan || (a.has_inf() && b.has_inf());
    if b.has(0.0) {
        return make(f64::NEG_INFINITY, f64::INFINITY, nan || a.has(0.0));
    }
    div_part(a, b.lo, b.hi, nan)
}

/// Whether `[lo - m, hi + m]` holds a point `off + k * period`.
fn hits(a: Interval, off: f64, period: f64) -> bool {
    let m = extreme_margin(a);
    let n0 = ((a.lo - off) / period).floor();
    (-1..=2).any(|k| {
        let c = off + (n0 + f64::from(k)) * period;
        c >= a.lo - m && c <= a.hi + m
    })
}

fn sin_cos(a: Interval, is_cos: bool) -> Interval {
    let (s, c) = sin_cos_pair(a);
    if is_cos {
        c
    } else {
        s
    }
}

/// `(sin a, cos a)`, from one reduction of each end.
fn sin_cos_pair(a: Interval) -> (Interval, Interval) {
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
fn extreme_margin(a: Interval) -> f64 {
    1e-9 * (1.0 + a.lo.abs().max(a.hi.abs()))
}

/// Which of the points `j·π/2` lie in `[lo − m, hi + m]`, by `j mod 4`:
/// `[cos max, sin max, cos min, sin min]`, from the reductions of the ends
/// (`lo ≈ k₀·π/2 + r₀`, `hi ≈ k₁·π/2 + r₁`): no division.
fn quarter_extremes(t: &simd_math::TrigEnds, m: f64) -> [bool; 4] {
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

fn tan(a: Interval) -> Interval {
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

fn sqrt_iv(a: Interval) -> Interval {
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

fn not_iv(a: Interval) -> Interval {
    // not(v) = 1 where v is falsy (NaN included), 0 where truthy.
    bool_iv(a.may_falsy(), a.may_truthy())
}

fn unary(op: UnaryOp, a: Interval) -> Interval {
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

fn min_iv(a: Interval, b: Interval) -> Interval {
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

fn max_iv(a: Interval, b: Interval) -> Interval {
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
fn rfun(op: BinaryOp, a: Interval, b: Interval) -> Interval {
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

fn blend_iv(op: BlendOp, [f1, f2, a0, a1, a2]: [Interval; 5]) -> Interval {
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
fn powi_iv(b: Interval, n: i32) -> Interval {
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

fn binary(op: BinaryOp, a: Interval, b: Interval, same: bool) -> Interval {
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

/// Which argument a node reduces to inside the box.
///
/// For `min`, `max`, `and`, `or`: `Left` is the first argument, `Right` the
/// second; for `select`: `Left` is the then-branch, `Right` the else-branch;
/// for the R-functions (sign sense only): the argument that keeps the sign;
/// for `Check(g, v)`: always `Right` (`v`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Pick {
    /// Not decided: keep the node.
    #[default]
    Both,
    /// The node reduces to its first value argument.
    Left,
    /// The node reduces to its second value argument.
    Right,
    /// The node is the constant 0 throughout (boolean operations).
    False,
    /// The node is the constant 1 throughout (boolean operations).
    True,
}

/// The sign of a node over the box, when decided.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Decided {
    /// Both signs, zero or NaN are possible.
    #[default]
    No,
    /// Strictly positive, never NaN, and at most 1e150 (so that a parent
    /// R-function cannot overflow when the node is replaced by 1).
    Positive,
    /// Strictly negative, never NaN, and at least -1e150.
    Negative,
}

/// What the interval evaluation learned about one node, for both
/// simplification modes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Choice {
    /// The reduction that keeps the value bit for bit.
    pub exact: Pick,
    /// The reduction that keeps the sign (and NaN-ness) when the node is
    /// used only for its sign; at least as strong as `exact`.
    pub sign: Pick,
    /// The node's sign over the box.
    pub decided: Decided,
}

/// Whether a node's values are exactly 0.0 or 1.0.
pub(crate) fn is_bool_node(n: &Node) -> bool {
    matches!(
        n,
        Node::Unary(UnaryOp::Not, _)
            | Node::Binary(
                BinaryOp::Lt
                    | BinaryOp::Gt
                    | BinaryOp::Le
                    | BinaryOp::Ge
                    | BinaryOp::Eq
                    | BinaryOp::Ne
                    | BinaryOp::And
                    | BinaryOp::Or,
                _,
                _
            )
    )
}

fn all_truthy(a: Interval) -> bool {
    !a.nan && !a.is_empty() && (a.lo >= EPS || a.hi <= -EPS)
}

// ----- fast paths ----------------------------------------------------------
//
// The evaluator's common operations on nonempty, finite bounds: there no
// infinity meets a zero or an opposite infinity and no bound becomes NaN,
// so each gives exactly what the general rule gives; every other case goes
// to the general rule. Each reads its arguments and writes its result in
// `v` itself, and the general rules are out-of-line calls that do the same:
// a result merged from both paths would go through the stack, and be loaded
// back in a width that the store cannot forward.

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
fn add_at(v: &mut Regs, out: usize, i: u32, j: u32) {
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
fn sub_at(v: &mut Regs, out: usize, i: u32, j: u32) {
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
fn mul_at(v: &mut Regs, out: usize, i: u32, j: u32) {
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
fn sqr_at(v: &mut Regs, out: usize, i: u32) {
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
fn neg_at(v: &mut Regs, out: usize, i: u32) {
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
fn sqrt_at(v: &mut Regs, out: usize, i: u32) {
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
fn powi2_at(v: &mut Regs, out: usize, i: u32) {
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
fn min_at(v: &mut Regs, out: usize, i: u32, j: u32) {
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
fn max_at(v: &mut Regs, out: usize, i: u32, j: u32) {
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
fn rfun_at(v: &mut Regs, out: usize, op: BinaryOp, i: u32, j: u32) {
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

/// One operation of the lowered tape, its arguments as node indices. The
/// common operations have variants of their own; leaves are not here
/// (constants are stored once, inputs set at the start of each evaluation).
#[derive(Clone, Copy, Debug)]
enum Op {
    Add(u32, u32),
    Sub(u32, u32),
    Mul(u32, u32),
    /// `a * a`.
    Sqr(u32),
    Neg(u32),
    /// `Sqrt` and `SqrtF` (the same interval rule).
    Sqrt(u32),
    /// `PowI(a, 2)`.
    PowI2(u32),
    Min(u32, u32),
    Max(u32, u32),
    RUnion(u32, u32),
    RInter(u32, u32),
    RDiff(u32, u32),
    Unary(UnaryOp, u32),
    /// Any other binary operation; the flag tells whether both arguments
    /// are the same node.
    Binary(BinaryOp, u32, u32, bool),
    PowI(u32, i32),
    Select(u32, u32, u32),
    /// A blend; its arguments are `blends[i]`.
    Blend(BlendOp, u32),
    /// `Check(_, v)`: the value of `v`.
    Copy(u32),
    /// `sin a` into the first node and `cos a` into the second: the two
    /// nodes of one argument, computed together at the first of them (the
    /// second emits nothing).
    SinCos(u32, u32, u32),
}

/// The bit of input `x[k]` in a mask of inputs: `x`, `y` and `z` one each,
/// every other input (extra coordinates, parameters) the fourth.
fn input_bit(k: u32) -> u8 {
    if k < 3 {
        1 << k
    } else {
        OTHER_INPUTS
    }
}

/// The bit of every input but `x`, `y` and `z` (see [`input_bit`]).
const OTHER_INPUTS: u8 = 1 << 3;

/// Every input's bit.
const ALL_INPUTS: u8 = 0b1111;

/// An operation and the node it computes.
#[derive(Clone, Copy, Debug)]
struct Instr {
    op: Op,
    out: u32,
}

/// The nodes' intervals, one array per field: reads and writes of single
/// fields never meet a wider access to the same bytes (which the store
/// buffer cannot forward).
#[derive(Clone, Debug, Default)]
struct Regs {
    /// One interval per node (one bounds check per access).
    r: Vec<Interval>,
}

impl Regs {
    #[inline(always)]
    fn get(&self, i: u32) -> Interval {
        self.r[i as usize]
    }

    #[inline(always)]
    fn set(&mut self, i: usize, r: Interval) {
        self.r[i] = r;
    }
}

/// Interval evaluator of one tape, reusable across boxes.
///
/// [`new`](IntervalEval::new) lowers the tape once into a flat list of
/// operations. The per-node intervals and [`Choice`]s are assembled when
/// [`intervals`](IntervalEval::intervals) or
/// [`choices`](IntervalEval::choices) is first called after an evaluation.
#[derive(Debug)]
pub struct IntervalEval {
    tape: Tape,
    code: Vec<Instr>,
    /// The input leaves (`X`, `Param`), set at the start of each evaluation.
    leaves: Vec<(u32, Node)>,
    blends: Vec<[u32; 5]>,
    regs: Regs,
    /// Per operation of `code`, the inputs it depends on ([`input_bit`]).
    deps: Vec<u8>,
    /// Per set of changed inputs (a mask of [`input_bit`]s, neither empty
    /// nor all), the operations of `code` that depend on one of them, built
    /// when first needed. Every node has a register of its own, so the
    /// others still hold their values from the last evaluation.
    partial: Vec<Option<Box<[Instr]>>>,
    /// Whether an evaluation has set every register.
    primed: bool,
    /// The intervals of the last evaluation, once asked for.
    values: OnceLock<Vec<Interval>>,
    /// The choices of the last evaluation, once asked for.
    choices: OnceLock<Vec<Choice>>,
    /// Buffers for the next intervals and choices.
    spare: Mutex<(Vec<Interval>, Vec<Choice>)>,
}

impl Clone for IntervalEval {
    fn clone(&self) -> Self {
        IntervalEval {
            tape: self.tape.clone(),
            code: self.code.clone(),
            leaves: self.leaves.clone(),
            blends: self.blends.clone(),
            regs: self.regs.clone(),
            deps: self.deps.clone(),
            partial: self.partial.clone(),
            primed: self.primed,
            values: self.values.clone(),
            choices: self.choices.clone(),
            spare: Mutex::default(),
        }
    }
}

impl IntervalEval {
    /// An evaluator for `tape`.
    pub fn new(tape: &Tape) -> Self {
        let n = tape.len();
        let mut regs = Regs {
            r: vec![Interval::EMPTY; n],
        };
        let mut code = Vec::with_capacity(n);
        let mut leaves = Vec::with_capacity(4);
        let mut blends = Vec::new();
        let ix = |id: NodeId| id.index() as u32;
        // `sin a` and `cos a` of one argument: both computed at the first.
        let mut trig: HashMap<u32, [Option<u32>; 2]> = HashMap::new();
        for (i, node) in tape.nodes.iter().enumerate() {
            if let Node::Unary(op @ (UnaryOp::Sin | UnaryOp::Cos), a) = *node {
                trig.entry(ix(a)).or_default()[usize::from(op == UnaryOp::Cos)] = Some(i as u32);
            }
        }
        let mut paired = HashMap::new();
        for [s, c] in trig.into_values() {
            if let (Some(s), Some(c)) = (s, c) {
                paired.insert(s.min(c), Some((s, c)));
                paired.insert(s.max(c), None);
            }
        }
        for (i, node) in tape.nodes.iter().enumerate() {
            if let Some(&pair) = paired.get(&(i as u32)) {
                if let (Some((s, c)), Node::Unary(_, a)) = (pair, *node) {
                    code.push(Instr {
                        op: Op::SinCos(ix(a), s, c),
                        out: i as u32,
                    });
                }
                continue;
            }
            let op = match *node {
                Node::Const(bits) => {
                    regs.set(i, Interval::point(f64::from_bits(bits)));
                    continue;
                }
                Node::Error(_) => {
                    regs.set(i, Interval::NAN);
                    continue;
                }
                Node::X(_) | Node::Param(_) => {
                    leaves.push((i as u32, *node));
                    continue;
                }
                Node::Unary(op, a) => match op {
                    UnaryOp::Neg => Op::Neg(ix(a)),
                    UnaryOp::Sqrt | UnaryOp::SqrtF => Op::Sqrt(ix(a)),
                    _ => Op::Unary(op, ix(a)),
                },
                Node::PowI(a, 2) => Op::PowI2(ix(a)),
                Node::PowI(a, n) => Op::PowI(ix(a), n),
                Node::Binary(op, a, b) => {
                    let (a, b) = (ix(a), ix(b));
                    match op {
                        BinaryOp::Add => Op::Add(a, b),
                        BinaryOp::Sub => Op::Sub(a, b),
                        BinaryOp::Mul if a == b => Op::Sqr(a),
                        BinaryOp::Mul => Op::Mul(a, b),
                        BinaryOp::Min => Op::Min(a, b),
                        BinaryOp::Max => Op::Max(a, b),
                        BinaryOp::RUnion => Op::RUnion(a, b),
                        BinaryOp::RInter => Op::RInter(a, b),
                        BinaryOp::RDiff => Op::RDiff(a, b),
                        _ => Op::Binary(op, a, b, a == b),
                    }
                }
                Node::Select(c, t, e) => Op::Select(ix(c), ix(t), ix(e)),
                Node::Blend(op, args) => {
                    blends.push(args.map(ix));
                    Op::Blend(op, (blends.len() - 1) as u32)
                }
                Node::Check(_, v) => Op::Copy(ix(v)),
            };
            code.push(Instr { op, out: i as u32 });
        }
        // Which inputs each node depends on.
        let mut node_deps = vec![0u8; n];
        for (i, node) in tape.nodes.iter().enumerate() {
            node_deps[i] = match *node {
                Node::X(k) => input_bit(k),
                Node::Param(_) => OTHER_INPUTS,
                _ => node.children().fold(0, |m, c| m | node_deps[c.index()]),
            };
        }
        let deps = code
            .iter()
            .map(|ins| match ins.op {
                // The pair's argument (`out` is one of the two results).
                Op::SinCos(a, _, _) => node_deps[a as usize],
                _ => node_deps[ins.out as usize],
            })
            .collect();
        IntervalEval {
            tape: tape.clone(),
            code,
            leaves,
            blends,
            regs,
            deps,
            partial: vec![None; ALL_INPUTS as usize],
            primed: false,
            values: OnceLock::new(),
            choices: OnceLock::new(),
            spare: Mutex::default(),
        }
    }

    /// The tape evaluated.
    pub fn tape(&self) -> &Tape {
        &self.tape
    }

    /// Evaluates every node over the box `x × y × z` and returns output 0's
    /// interval ([`Interval::NAN`] for a tape without outputs).
    pub fn eval(&mut self, x: Interval, y: Interval, z: Interval, inputs: &Inputs) -> Interval {
        self.run(x, y, z, inputs);
        self.tape
            .outputs
            .first()
            .map_or(Interval::NAN, |o| self.regs.get(o.index() as u32))
    }

    /// Evaluates every node and returns every output's interval.
    pub fn eval_outputs(
        &mut self,
        x: Interval,
        y: Interval,
        z: Interval,
        inputs: &Inputs,
    ) -> Vec<Interval> {
        self.run(x, y, z, inputs);
        self.tape
            .outputs
            .iter()
            .map(|o| self.regs.get(o.index() as u32))
            .collect()
    }

    /// Each node's interval from the last evaluation.
    pub fn intervals(&self) -> &[Interval] {
        self.values.get_or_init(|| {
            let mut v = std::mem::take(&mut self.spare().0);
            v.clear();
            v.extend((0..self.tape.len() as u32).map(|i| self.regs.get(i)));
            v
        })
    }

    /// Each node's [`Choice`] from the last evaluation (for
    /// [`simplify`](crate::simplify::simplify)).
    pub fn choices(&self) -> &[Choice] {
        self.choices.get_or_init(|| {
            let values = self.intervals();
            let mut c = std::mem::take(&mut self.spare().1);
            c.clear();
            let nodes = &self.tape.nodes;
            c.extend((0..nodes.len()).map(|i| choice_of(nodes, |k| values[k], i)));
            c
        })
    }

    /// Node `i`'s [`Choice`] from the last evaluation, as
    /// [`choices`](IntervalEval::choices)`()[i]` (computed alone).
    ///
    /// # Panics
    /// If `i` is not a node of the tape.
    pub fn choice(&self, i: usize) -> Choice {
        choice_of(&self.tape.nodes, |k| self.regs.get(k as u32), i)
    }

    /// Node `i`'s [`Choice::decided`] from the last evaluation: all of its
    /// [`choice`](IntervalEval::choice) for a node that cannot choose (an
    /// arithmetic operation: its picks are [`Pick::Both`]).
    ///
    /// # Panics
    /// If `i` is not a node of the tape.
    pub fn decided(&self, i: usize) -> Decided {
        decided_of(self.regs.get(i as u32))
    }

    fn spare(&self) -> std::sync::MutexGuard<'_, (Vec<Interval>, Vec<Choice>)> {
        self.spare.lock().unwrap_or_else(PoisonError::into_inner)
    }

    fn run(&mut self, x: Interval, y: Interval, z: Interval, inputs: &Inputs) {
        let spare = self.spare.get_mut().unwrap_or_else(PoisonError::into_inner);
        if let Some(v) = self.values.take() {
            spare.0 = v;
        }
        if let Some(c) = self.choices.take() {
            spare.1 = c;
        }
        let v = &mut self.regs;
        // The inputs that differ from the last evaluation's (bit for bit).
        let mut changed = 0u8;
        for &(i, node) in &self.leaves {
            let (r, bit) = match node {
                Node::X(0) => (x, input_bit(0)),
                Node::X(1) => (y, input_bit(1)),
                Node::X(2) => (z, input_bit(2)),
                Node::X(k) => (Interval::point(inputs.extra_x(k)), OTHER_INPUTS),
                Node::Param(k) => (Interval::point(inputs.param(k)), OTHER_INPUTS),
                _ => unreachable!("not an input leaf"),
            };
            let old = v.get(i);
            if (old.lo.to_bits(), old.hi.to_bits(), old.nan)
                != (r.lo.to_bits(), r.hi.to_bits(), r.nan)
            {
                changed |= bit;
            }
            v.set(i as usize, r);
        }
        // Only the operations that depend on a changed input run; the
        // others' registers hold what they would compute.
        let code: &[Instr] = if !self.primed || changed == ALL_INPUTS {
            self.primed = true;
            &self.code
        } else if changed == 0 {
            &[]
        } else {
            let (code, deps) = (&self.code, &self.deps);
            self.partial[changed as usize].get_or_insert_with(|| {
                code.iter()
                    .zip(deps)
                    .filter(|&(_, &d)| d & changed != 0)
                    .map(|(ins, _)| *ins)
                    .collect()
            })
        };
        for ins in code {
            let out = ins.out as usize;
            let g = |i: u32| v.get(i);
            match ins.op {
                Op::Add(a, b) => add_at(v, out, a, b),
                Op::Sub(a, b) => sub_at(v, out, a, b),
                Op::Mul(a, b) => mul_at(v, out, a, b),
                Op::Sqr(a) => sqr_at(v, out, a),
                Op::Neg(a) => neg_at(v, out, a),
                Op::Sqrt(a) => sqrt_at(v, out, a),
                Op::PowI2(a) => powi2_at(v, out, a),
                Op::Min(a, b) => min_at(v, out, a, b),
                Op::Max(a, b) => max_at(v, out, a, b),
                Op::RUnion(a, b) => rfun_at(v, out, BinaryOp::RUnion, a, b),
                Op::RInter(a, b) => rfun_at(v, out, BinaryOp::RInter, a, b),
                Op::RDiff(a, b) => rfun_at(v, out, BinaryOp::RDiff, a, b),
                Op::Unary(op, a) => v.set(out, unary(op, g(a))),
                Op::Binary(op, a, b, same) => v.set(out, binary(op, g(a), g(b), same)),
                Op::PowI(a, n) => v.set(out, powi_iv(g(a), n)),
                Op::Select(c, t, e) => v.set(out, select_iv(g(c), g(t), g(e))),
                Op::Blend(op, k) => v.set(out, blend_iv(op, self.blends[k as usize].map(g))),
                Op::Copy(a) => v.set(out, g(a)),
                Op::SinCos(a, s, c) => {
                    let (si, co) = sin_cos_pair(g(a));
                    v.set(s as usize, si);
                    v.set(c as usize, co);
                }
            }
        }
    }
}

/// `select(c, t, e)`: the branches `c` may choose.
fn select_iv(c: Interval, t: Interval, e: Interval) -> Interval {
    let mut r = none(false);
    if c.may_truthy() {
        r = r.hull(t);
    }
    if c.may_falsy() {
        r = r.hull(e);
    }
    r
}

/// Whether [`choice_of`] can give node `n` an `exact` pick other than
/// [`Pick::Both`]: the nodes that pick an argument or a branch (`min`,
/// `max`, the R-functions, `select`, `Check`) and the booleans (a constant
/// once decided). Kept beside [`choice_of`] and [`binary_picks`], which it
/// must follow.
pub(crate) fn can_choose(n: &Node) -> bool {
    is_bool_node(n)
        || matches!(
            n,
            Node::Binary(
                BinaryOp::Min
                    | BinaryOp::Max
                    | BinaryOp::RUnion
                    | BinaryOp::RInter
                    | BinaryOp::RDiff,
                ..
            ) | Node::Select(..)
                | Node::Check(..)
        )
}

/// The [`Choice`] of node `i`, from the intervals of an evaluation
/// (`v(k)`: node `k`'s).
#[inline]
fn choice_of(nodes: &[Node], v: impl Fn(usize) -> Interval, i: usize) -> Choice {
    let node = &nodes[i];
    let r = v(i);
    let g = |id: NodeId| v(id.index());
    let mut exact = Pick::Both;
    let mut sign = Pick::Both;
    match *node {
        Node::Binary(op, a, b) => {
            (exact, sign) = binary_picks(op, g(a), g(b), nodes, a, b);
        }
        Node::Select(c, _, _) => {
            let ic = g(c);
            if !ic.may_falsy() {
                exact = Pick::Left;
            } else if !ic.may_truthy() {
                exact = Pick::Right;
            }
        }
        Node::Check(..) => exact = Pick::Right,
        _ => {}
    }
    if sign == Pick::Both {
        sign = exact;
    }
    let decided = decided_of(r);
    if is_bool_node(node) && !r.nan && r.lo == r.hi {
        exact = if r.lo == 0.0 { Pick::False } else { Pick::True };
        sign = exact;
    }
    Choice {
        exact,
        sign,
        decided,
    }
}

/// The [`Choice::decided`] of a node of interval `r`.
#[inline]
fn decided_of(r: Interval) -> Decided {
    // Only moderate values may become ±1: a huge or infinite one
    // overflows the squares of an R-function parent.
    if r.is_positive() && r.tame() {
        Decided::Positive
    } else if r.is_negative() && r.tame() {
        Decided::Negative
    } else {
        Decided::No
    }
}

/// The exact and sign picks of a binary node.
fn binary_picks(
    op: BinaryOp,
    a: Interval,
    b: Interval,
    nodes: &[Node],
    ia: NodeId,
    ib: NodeId,
) -> (Pick, Pick) {
    let ne = !a.is_empty() && !b.is_empty();
    let clean = !a.nan && !b.nan && ne;
    let mut exact = Pick::Both;
    let mut sign = Pick::Both;
    match op {
        BinaryOp::Min => {
            if clean && a.hi < b.lo {
                exact = Pick::Left;
            } else if !ne || a.lo >= b.hi {
                exact = Pick::Right;
            } else if a.tame() && b.tame() && b.lo > 0.0 {
                sign = Pick::Left;
            } else if a.tame() && b.tame() && a.lo > 0.0 {
                sign = Pick::Right;
            }
        }
        BinaryOp::Max => {
            if clean && a.lo > b.hi {
                exact = Pick::Left;
            } else if !ne || a.hi <= b.lo {
                exact = Pick::Right;
            } else if a.tame() && b.tame() && b.hi < 0.0 {
                sign = Pick::Left;
            } else if a.tame() && b.tame() && a.hi < 0.0 {
                sign = Pick::Right;
            }
        }
        BinaryOp::RUnion | BinaryOp::RInter | BinaryOp::RDiff => {
            // sign(a | b) = sign(max(a, b)), sign(a & b) = sign(min(a, b)),
            // sign(a \ b) = sign(min(a, -b)) in exact arithmetic; where the
            // dropped argument has a fixed sign, the other one decides, and at
            // its zero the gradient is its own (see the simplify module).
            let (ta, tb) = (a.tame(), b.tame());
            // The kept argument may be NaN, but not too large (its square).
            let a_ok = a.lo.abs().max(a.hi.abs()) <= SQUARE_SAFE;
            let b_ok = b.lo.abs().max(b.hi.abs()) <= SQUARE_SAFE;
            match op {
                BinaryOp::RUnion if tb && a_ok && b.hi < 0.0 => sign = Pick::Left,
                BinaryOp::RUnion if ta && b_ok && a.hi < 0.0 => sign = Pick::Right,
                BinaryOp::RInter if tb && a_ok && b.lo > 0.0 => sign = Pick::Left,
                BinaryOp::RInter if ta && b_ok && a.lo > 0.0 => sign = Pick::Right,
                BinaryOp::RDiff if tb && a_ok && b.hi < 0.0 => sign = Pick::Left,
                _ => {}
            }
        }
        BinaryOp::And => {
            if all_truthy(a) && is_bool_node(&nodes[ib.index()]) {
                exact = Pick::Right;
            } else if all_truthy(b) && is_bool_node(&nodes[ia.index()]) {
                exact = Pick::Left;
            }
        }
        BinaryOp::Or => {
            if !a.may_truthy() && is_bool_node(&nodes[ib.index()]) {
                exact = Pick::Right;
            } else if !b.may_truthy() && is_bool_node(&nodes[ia.index()]) {
                exact = Pick::Left;
            }
        }
        _ => {}
    }
    (exact, sign)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::testutil::*;
    use crate::graph::Graph;
    use proptest::prelude::*;

    fn iv(lo: f64, hi: f64) -> Interval {
        Interval::new(lo, hi)
    }

    fn ivs(lo: [f64; 3], hi: [f64; 3]) -> [Interval; 3] {
        [iv(lo[0], hi[0]), iv(lo[1], hi[1]), iv(lo[2], hi[2])]
    }

    /// Every node's point value lies in its interval.
    fn check_contains(tape: &Tape, lo: [f64; 3], hi: [f64; 3], pts: &[[f64; 3]], inputs: &Inputs) {
        let mut ev = IntervalEval::new(tape);
        let [x, y, z] = ivs(lo, hi);
        ev.eval(x, y, z, inputs);
        for &t in pts {
            let p = at(lo, hi, t);
            let vals = eval_point_all(tape, p, inputs);
            for (i, &v) in vals.iter().enumerate() {
                let r = ev.intervals()[i];
                assert!(
                    r.contains(v),
                    "node {i} {:?} = {v:e} at {p:?} outside {r:?}; args {:?}",
                    tape.nodes[i],
                    tape.nodes[i]
                        .children()
                        .map(|c| (vals[c.index()], ev.intervals()[c.index()]))
                        .collect::<Vec<_>>()
                );
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]
        #[test]
        fn intervals_contain_point_values(
            ins in instrs(24),
            (c, h) in boxes(),
            pts in fracs(8),
            a0 in constant(),
        ) {
            let mut g = Graph::new();
            let out = build_random(&mut g, &ins);
            let tape = g.tape(&[out]);
            let (lo, hi) = corners_of(c, h);
            check_contains(&tape, lo, hi, &pts, &Inputs::with_params(&[a0]));
        }

        #[test]
        fn reevaluation_equals_a_fresh_evaluation(
            ins in instrs(24),
            seq in prop::collection::vec((boxes(), 0u8..16, constant()), 2..8),
        ) {
            // Boxes in a row, each keeping some of the last one's inputs
            // (bits of `keep`: x, y, z, the parameter): only the operations
            // of the changed ones run again, and every node's interval and
            // choice must be what a fresh evaluator gives.
            let mut g = Graph::new();
            let out = build_random(&mut g, &ins);
            let tape = g.tape(&[out]);
            let mut ev = IntervalEval::new(&tape);
            let (mut b, mut a0) = (ivs([0.0; 3], [0.0; 3]), 0.0);
            for (k, ((c, h), keep, p)) in seq.into_iter().enumerate() {
                let (lo, hi) = corners_of(c, h);
                let nb = ivs(lo, hi);
                for j in 0..3 {
                    if k == 0 || keep & (1 << j) == 0 {
                        b[j] = nb[j];
                    }
                }
                if k == 0 || keep & 8 == 0 {
                    a0 = p;
                }
                let inputs = Inputs::with_params(&[a0]);
                ev.eval(b[0], b[1], b[2], &inputs);
                let mut fresh = IntervalEval::new(&tape);
                fresh.eval(b[0], b[1], b[2], &inputs);
                let bits = |v: &[Interval]| -> Vec<(u64, u64, bool)> {
                    v.iter().map(|i| (i.lo.to_bits(), i.hi.to_bits(), i.nan)).collect()
                };
                prop_assert_eq!(bits(ev.intervals()), bits(fresh.intervals()), "box {}", k);
                prop_assert_eq!(ev.choices(), fresh.choices(), "box {}", k);
                // Node by node, as the whole list gives them.
                for (i, c) in fresh.choices().iter().enumerate() {
                    prop_assert_eq!(ev.choice(i), *c, "node {} of box {}", i, k);
                    prop_assert_eq!(ev.decided(i), c.decided, "node {} of box {}", i, k);
                }
            }
        }

        #[test]
        fn extremes_from_the_reduction_equal_those_by_division(
            lo in -2000.0..2000.0f64,
            w in prop_oneof![
                2 => 0.0..1e-6f64,
                4 => 0.0..2.0f64,
                4 => 1.0..7.0f64,
            ],
            near in any::<bool>(),
            k in -1000i32..1000,
            d in -1e-6..1e-6f64,
        ) {
            // Either end may sit next to a multiple of π/2.
            let lo = if near { f64::from(k) * FRAC_PI_2 + d } else { lo };
            for a in [iv(lo, lo + w), iv(lo - w, lo)] {
                let t = simd_math::sin_cos_ends(a.lo, a.hi).unwrap();
                let m = extreme_margin(a);
                let want = [0.0, FRAC_PI_2, PI, -FRAC_PI_2].map(|off| hits(a, off, 2.0 * PI));
                prop_assert_eq!(quarter_extremes(&t, m), want, "{:?}", a);
                let (s, c) = simd_math::sin_cos(a.lo);
                prop_assert_eq!((t.sin[0], t.cos[0]), (s, c));
            }
        }

        #[test]
        fn unary_and_binary_ops_on_random_intervals(
            a in (constant(), 0.0..4.0f64),
            b in (constant(), 0.0..4.0f64),
            ts in prop::collection::vec((0.0..1.0f64, 0.0..1.0f64), 6),
            n in -5i32..6,
        ) {
            // Each op alone over a box of its two arguments (x and y).
            let mut g = Graph::new();
            let (x, y) = (g.x(0), g.x(1));
            let mut outs = vec![];
            for op in UnaryOp::ALL {
                outs.push(g.unary(op, x));
            }
            for op in BinaryOp::ALL {
                outs.push(g.binary(op, x, y));
            }
            outs.push(g.pow_int(x, n));
            outs.push(g.binary(BinaryOp::Mul, x, x));
            let tape = g.tape(&outs);
            let lo = [a.0, b.0, 0.0];
            let hi = [a.0 + a.1, b.0 + b.1, 0.0];
            let pts: Vec<[f64; 3]> = ts.iter().map(|&(s, t)| [s, t, 0.0])
                .chain([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]])
                .collect();
            check_contains(&tape, lo, hi, &pts, &Inputs::default());
        }
    }

    #[test]
    fn next_up_down() {
        assert_eq!(next_up(0.0), f64::from_bits(1));
        assert_eq!(next_up(-0.0), f64::from_bits(1));
        assert_eq!(next_down(0.0), -f64::from_bits(1));
        assert_eq!(next_up(1.0), 1.0 + f64::EPSILON);
        assert_eq!(next_down(1.0), 1.0 - f64::EPSILON / 2.0);
        assert_eq!(next_up(f64::INFINITY), f64::INFINITY);
        assert_eq!(next_up(f64::NEG_INFINITY), f64::MIN);
        assert_eq!(next_down(f64::INFINITY), f64::MAX);
    }

    #[test]
    fn lazy_intervals_and_choices_follow_the_last_evaluation() {
        let mut g = Graph::new();
        let f = m4(&mut g, 4);
        let tape = g.tape(&[f]);
        let boxes = [
            ivs([0.8, -1.0, 0.8], [1.0, -0.8, 1.0]),
            ivs([-1.0; 3], [1.0; 3]),
            ivs([0.84, -0.01, -0.81], [0.86, 0.01, -0.79]),
        ];
        let mut ev = IntervalEval::new(&tape);
        let mut copy = ev.clone();
        for (k, b) in boxes.iter().enumerate() {
            let r = ev.eval(b[0], b[1], b[2], &Inputs::default());
            copy.eval(b[0], b[1], b[2], &Inputs::default());
            if k == 1 {
                // This box's results stay unread.
                continue;
            }
            let mut fresh = IntervalEval::new(&tape);
            fresh.eval(b[0], b[1], b[2], &Inputs::default());
            assert_eq!(ev.intervals()[tape.outputs[0].index()], r);
            assert_eq!(ev.intervals(), fresh.intervals());
            assert_eq!(ev.choices(), fresh.choices());
            assert_eq!(copy.choices(), fresh.choices());
            // A clone keeps the results read so far.
            assert_eq!(ev.clone().intervals(), fresh.intervals());
            assert_eq!(ev.clone().choices(), fresh.choices());
        }
    }

    #[test]
    fn sin_and_cos_of_one_argument_together() {
        // sin(3x)·cos(3x) + cos(y)·cos(sin 3x) + sin(y) + sin(sin 3x) − sin z:
        // pairs at 3x, y and sin 3x (cos first at y), sin z alone.
        let mut g = Graph::new();
        let (x, y, z) = (g.x(0), g.x(1), g.x(2));
        let three = g.constant(3.0);
        let a = g.binary(BinaryOp::Mul, x, three);
        let cy = g.unary(UnaryOp::Cos, y);
        let sa = g.unary(UnaryOp::Sin, a);
        let ca = g.unary(UnaryOp::Cos, a);
        let sy = g.unary(UnaryOp::Sin, y);
        let sz = g.unary(UnaryOp::Sin, z);
        let css = g.unary(UnaryOp::Cos, sa);
        let sss = g.unary(UnaryOp::Sin, sa);
        let t1 = g.binary(BinaryOp::Mul, sa, ca);
        let t2 = g.binary(BinaryOp::Mul, cy, css);
        let t3 = g.binary(BinaryOp::Add, sy, sss);
        let t4 = g.binary(BinaryOp::Sub, t3, sz);
        let s1 = g.binary(BinaryOp::Add, t1, t2);
        let out = g.binary(BinaryOp::Add, s1, t4);
        let tape = g.tape(&[out]);
        let ev = IntervalEval::new(&tape);
        let pairs = ev
            .code
            .iter()
            .filter(|i| matches!(i.op, Op::SinCos(..)))
            .count();
        let singles = ev
            .code
            .iter()
            .filter(|i| matches!(i.op, Op::Unary(..)))
            .count();
        assert_eq!((pairs, singles), (3, 1));
        // Each node's interval is the one the op gives alone, over boxes
        // around extremes, wide, huge, unbounded and NaN-carrying.
        let mut ev = ev;
        let h = std::f64::consts::FRAC_PI_2;
        for b in [
            ivs([0.1, 0.2, 0.3], [0.2, 0.4, 0.5]),
            ivs(
                [h / 3.0 - 1e-9, h - 1e-9, -h],
                [h / 3.0 + 1e-9, h + 1e-9, h],
            ),
            ivs([-1.0, 3.0, 2.0], [1.0, 3.2, 9.0]),
            ivs([-10.0, -7.0, 0.0], [10.0, -6.9, 1e-300]),
            ivs([1e8, 1e12, 5.0], [1e8 + 0.5, 1e12 + 1.0, 5.0]),
            ivs([0.0, f64::NEG_INFINITY, 1.0], [f64::INFINITY, 0.0, 1.0]),
        ] {
            ev.eval(b[0], b[1], b[2], &Inputs::default());
            let v = ev.intervals();
            for (i, node) in tape.nodes.iter().enumerate() {
                if let Node::Unary(op, a) = *node {
                    assert_eq!(v[i], unary(op, v[a.index()]), "node {i} over {b:?}");
                }
            }
            let lo = [b[0].lo, b[1].lo, b[2].lo];
            let hi = [b[0].hi, b[1].hi, b[2].hi];
            if lo.iter().chain(&hi).all(|c| c.is_finite()) {
                let pts: Vec<[f64; 3]> = (0..=4)
                    .map(|k| [k as f64 / 4.0, 1.0 - k as f64 / 4.0, 0.5])
                    .collect();
                check_contains(&tape, lo, hi, &pts, &Inputs::default());
            }
        }
    }

    #[test]
    fn ulp_steps() {
        // The bit shortcut of `up`/`down` agrees with single steps.
        let tiny = f64::from_bits(1);
        for x in [
            0.0,
            -0.0,
            tiny,
            -tiny,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            1.0,
            -1.0,
            0.3,
            -2.5e-300,
            1e300,
            -1e300,
            1.1e300,
            f64::MAX,
            -f64::MAX,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ] {
            for n in 0..6 {
                let (mut d, mut u) = (x, x);
                for _ in 0..n {
                    d = next_down(d);
                    u = next_up(u);
                }
                assert_eq!(down(x, n).to_bits(), d.to_bits(), "down({x:e}, {n})");
                assert_eq!(up(x, n).to_bits(), u.to_bits(), "up({x:e}, {n})");
            }
        }
    }

    #[test]
    fn rules() {
        // sin finds its extrema; a monotone piece stays tight.
        let s = unary(UnaryOp::Sin, iv(0.0, 2.0));
        assert_eq!(s.hi, 1.0);
        assert!(s.lo <= 0.0 && s.lo > -1e-300);
        let s = unary(UnaryOp::Sin, iv(-0.5, 0.5));
        assert!((s.hi - 0.5f64.sin()).abs() < 1e-15 && !s.nan);
        let c = unary(UnaryOp::Cos, iv(3.0, 3.5));
        assert_eq!(c.lo, -1.0);
        assert!(!unary(UnaryOp::Sin, iv(0.0, f64::INFINITY)).is_empty());
        assert!(unary(UnaryOp::Sin, iv(0.0, f64::INFINITY)).nan);
        // Checked sqrt/log/div set nan on their error regions only.
        assert!(unary(UnaryOp::Sqrt, iv(-1.0, 4.0)).nan);
        assert_eq!(unary(UnaryOp::Sqrt, iv(1.0, 4.0)), iv(1.0, 2.0));
        assert!(unary(UnaryOp::Log, iv(0.0, 1.0)).nan);
        let d = binary(BinaryOp::Div, iv(1.0, 2.0), iv(-1.0, 2.0), false);
        assert!(d.nan && d.lo == -2e6 && d.hi == 2e6);
        let d = binary(BinaryOp::Div, iv(1.0, 2.0), iv(1.0, 2.0), false);
        assert_eq!(d, iv(0.5, 2.0));
        let d = binary(BinaryOp::DivF, iv(1.0, 2.0), iv(-1.0, 2.0), false);
        assert!(!d.nan && d.lo == f64::NEG_INFINITY && d.hi == f64::INFINITY);
        // tan: pole inside.
        assert_eq!(unary(UnaryOp::Tan, iv(1.0, 2.0)), Interval::ENTIRE);
        assert!(!unary(UnaryOp::Tan, iv(-1.0, 1.0)).nan);
        // Integer powers.
        assert_eq!(powi_iv(iv(-2.0, 3.0), 2), iv(0.0, 9.0));
        assert_eq!(powi_iv(iv(-2.0, 3.0), 3), iv(-8.0, 27.0));
        let p = powi_iv(iv(-2.0, 3.0), -1);
        assert!(p.nan && p.lo == -1e6 && p.hi == 1e6);
        assert_eq!(powi_iv(iv(2.0, 4.0), -2), iv(1.0 / 16.0, 0.25));
        assert!(!powi_iv(iv(-2.0, 3.0), 2).nan);
        // Comparisons and logic.
        let lt = binary(BinaryOp::Lt, iv(0.0, 1.0), iv(2.0, 3.0), false);
        assert_eq!(lt, Interval::point(1.0));
        let lt = binary(BinaryOp::Lt, iv(0.0, 2.5), iv(2.0, 3.0), false);
        assert_eq!(lt, iv(0.0, 1.0));
        assert_eq!(not_iv(Interval::NAN), Interval::point(1.0));
        // R-functions: the notes' example (a, b in [1, 2]).
        let r = rfun(BinaryOp::RInter, iv(1.0, 2.0), iv(1.0, 2.0));
        assert!((r.lo - (2.0 - 2f64.sqrt())).abs() < 1e-14);
        assert!((r.hi - (4.0 - 8f64.sqrt())).abs() < 1e-14);
        let r = rfun(BinaryOp::RDiff, iv(1.0, 2.0), iv(1.0, 2.0));
        assert!((r.lo - ops::r_diff(1.0, 2.0)).abs() < 1e-14);
        assert!((r.hi - ops::r_diff(2.0, 1.0)).abs() < 1e-14);
        // min with a NaN first argument returns the second.
        let m = min_iv(Interval::NAN, iv(1.0, 2.0));
        assert_eq!(m, iv(1.0, 2.0));
    }

    fn sample_range(tape: &Tape, lo: [f64; 3], hi: [f64; 3], n: usize) -> (f64, f64) {
        let mut r = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..=n {
            for j in 0..=n {
                for k in 0..=n {
                    let t = [i, j, k].map(|v| v as f64 / n as f64);
                    let v = eval_point(tape, at(lo, hi, t), &Inputs::default());
                    r = (r.0.min(v), r.1.max(v));
                }
            }
        }
        r
    }

    #[test]
    fn m4_decided_far_and_tight_near_the_surface() {
        let mut g = Graph::new();
        let f = m4(&mut g, 10);
        let tape = g.tape(&[f]);
        let mut ev = IntervalEval::new(&tape);
        // Far from every sphere.
        let r = ev.eval(
            iv(0.8, 1.0),
            iv(-1.0, -0.8),
            iv(0.8, 1.0),
            &Inputs::default(),
        );
        assert!(r.is_negative(), "{r:?}");
        // The whole box: undecided.
        let r = ev.eval(
            iv(-1.0, 1.0),
            iv(-1.0, 1.0),
            iv(-1.0, 1.0),
            &Inputs::default(),
        );
        assert!(!r.is_negative() && !r.is_positive());
        // A small box on the surface of sphere 0 at (0.85, 0, -0.8).
        for (c, h) in [
            ([0.85, 0.0, -0.8], 0.01),
            ([0.6, 0.0, -0.55], 0.02),
            ([0.3, 0.4, 0.0], 0.05),
        ] {
            let lo = c.map(|v| v - h);
            let hi = c.map(|v| v + h);
            let [x, y, z] = ivs(lo, hi);
            let r = ev.eval(x, y, z, &Inputs::default());
            let (slo, shi) = sample_range(&tape, lo, hi, 8);
            assert!(r.lo <= slo && shi <= r.hi);
            let ratio = r.width() / (shi - slo);
            assert!(
                ratio < 2.0,
                "box at {c:?}: {r:?} vs sampled [{slo}, {shi}], ratio {ratio}"
            );
        }
    }
}
