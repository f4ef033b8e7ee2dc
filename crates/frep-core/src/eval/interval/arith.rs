//! [`Interval`] and its arithmetic: outward rounding, `+ - * /` and squares.
//!
//! - Correctly rounded operations are monotone, so corner values are exact
//!   bounds.
//! - Library functions are widened by [`LIBM_ULPS`] ulps with [`up`] and
//!   [`down`], which step the bits of the double.

use crate::ops::EPS;

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

pub(super) fn down(mut x: f64, ulps: u32) -> f64 {
    if bit_steps(x) {
        let (b, n) = (x.to_bits(), u64::from(ulps));
        return f64::from_bits(if x > 0.0 { b - n } else { b + n });
    }
    for _ in 0..ulps {
        x = next_down(x);
    }
    x
}

pub(super) fn up(mut x: f64, ulps: u32) -> f64 {
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
pub(super) const LIBM_ULPS: u32 = 4;

/// Magnitude above which squares inside R-functions may overflow.
pub(super) const SQUARE_SAFE: f64 = 1e150;

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
    pub(super) fn has(&self, v: f64) -> bool {
        self.lo <= v && v <= self.hi
    }

    /// Whether an infinite value is possible.
    pub(super) fn has_inf(&self) -> bool {
        !self.is_empty() && (self.lo == f64::NEG_INFINITY || self.hi == f64::INFINITY)
    }

    /// Whether some value may count as true (`|v| >= 1e-6`).
    pub(super) fn may_truthy(&self) -> bool {
        !self.is_empty() && (self.lo <= -EPS || self.hi >= EPS)
    }

    /// Whether some value may count as false (`|v| < 1e-6` or NaN).
    pub(super) fn may_falsy(&self) -> bool {
        self.nan || (!self.is_empty() && self.lo < EPS && self.hi > -EPS)
    }

    /// Non-NaN and finite, with a magnitude that R-functions square safely.
    pub(super) fn tame(&self) -> bool {
        !self.nan && !self.is_empty() && self.lo >= -SQUARE_SAFE && self.hi <= SQUARE_SAFE
    }
}

/// `[lo, hi]` with the flag; NaN bounds become infinite and set the flag.
pub(super) fn make(lo: f64, hi: f64, nan: bool) -> Interval {
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

pub(super) fn none(nan: bool) -> Interval {
    Interval {
        nan,
        ..Interval::EMPTY
    }
}

pub(super) fn bool_iv(may_true: bool, may_false: bool) -> Interval {
    match (may_true, may_false) {
        (true, true) => Interval::new(0.0, 1.0),
        (true, false) => Interval::point(1.0),
        (false, true) => Interval::point(0.0),
        (false, false) => Interval::EMPTY,
    }
}

/// Hull of corner values; any NaN corner gives everything.
pub(super) fn corners(c: [f64; 4], nan: bool) -> Interval {
    if c.iter().any(|v| v.is_nan()) {
        return Interval::ENTIRE;
    }
    let lo = c.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    make(lo, hi, nan)
}

pub(super) fn widen(iv: Interval, ulps: u32) -> Interval {
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
pub(super) fn widen_rel(iv: Interval, rel: f64) -> Interval {
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

pub(super) fn neg(a: Interval) -> Interval {
    if a.is_empty() {
        return a;
    }
    make(-a.hi, -a.lo, a.nan)
}

pub(super) fn add(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let inf = f64::INFINITY;
    let nan = a.nan || b.nan || (a.hi == inf && b.lo == -inf) || (a.lo == -inf && b.hi == inf);
    make(a.lo + b.lo, a.hi + b.hi, nan)
}

pub(super) fn sub(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let inf = f64::INFINITY;
    let nan = a.nan || b.nan || (a.hi == inf && b.hi == inf) || (a.lo == -inf && b.lo == -inf);
    make(a.lo - b.hi, a.hi - b.lo, nan)
}

pub(super) fn mul(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let nan = a.nan || b.nan || (a.has(0.0) && b.has_inf()) || (b.has(0.0) && a.has_inf());
    corners([a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi], nan)
}

pub(super) fn sqr(a: Interval) -> Interval {
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

pub(super) fn div_checked(a: Interval, b: Interval) -> Interval {
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

pub(super) fn div_ieee(a: Interval, b: Interval) -> Interval {
    if a.is_empty() || b.is_empty() {
        return none(a.nan || b.nan);
    }
    let nan = a.nan || b.nan || (a.has_inf() && b.has_inf());
    if b.has(0.0) {
        return make(f64::NEG_INFINITY, f64::INFINITY, nan || a.has(0.0));
    }
    div_part(a, b.lo, b.hi, nan)
}
