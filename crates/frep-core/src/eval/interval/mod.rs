//! Interval evaluation of a [`Tape`](crate::graph::Tape) over an
//! axis-aligned box, with the per-node [`Choice`]s that
//! [`simplify`](crate::simplify::simplify) uses to shorten the tape inside
//! that box.
//!
//! ## What an [`Interval`] means
//! An interval bounds the values that the *bulk* evaluators compute at every
//! point of the box: f64, runtime errors mapped to NaN, `Check` guards
//! ignored. Every non-NaN value lies in `[lo, hi]` (infinities included).
//! `nan` is set when some point may give NaN. An interval with `lo > hi` has
//! no non-NaN value: with `nan` set it is "always NaN" ([`Interval::NAN`]),
//! without it "no value at all" ([`Interval::EMPTY`], only seen for
//! unreachable cases).
//!
//! The bounds are those of the *computed* floating-point values, not of the
//! real-number functions:
//! - correctly rounded operations (`+ - * /`, `sqrt`, `floor`, ...) are
//!   monotone after rounding, so their corner values are exact bounds;
//! - library functions (`sin`, `exp`, `atan2`, ...) are widened by a few
//!   ulps;
//! - composite formulas (R-functions, blends, powers) are widened by a
//!   bound on their rounding error.
//!
//! ## Rules
//! * `min`/`max`, R-union and R-intersection are monotone non-decreasing in
//!   both arguments. R-difference `a \ b` is increasing in `a` and
//!   decreasing in `b`. Their bounds come from the corners, which is what
//!   makes R-function models prunable.
//! * `sin`/`cos` find the extrema inside the interval; `tan` is monotone
//!   between poles (a pole inside gives `[-inf, inf]` and NaN); checked
//!   operations set `nan` where their error region meets the interval.
//! * Comparisons and `and`/`or`/`not` give `[0, 0]`, `[1, 1]` when decided,
//!   else `[0, 1]`; a NaN operand counts as false, as in the bulk evaluators.
//! * `select` takes the branch(es) its condition may choose.

mod arith;
mod binary;
mod choice;
mod eval;
mod fast;
mod functions;

pub use arith::{next_down, next_up, Interval};
pub(crate) use choice::can_choose;
pub use choice::{Choice, Decided, Pick};
pub use eval::IntervalEval;

#[cfg(test)]
mod tests;
