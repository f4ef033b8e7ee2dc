//! Evaluators of a [`Tape`](crate::Tape).
//!
//! Every evaluator reads the point from `Node::X(0..3)` (x, y, z) and the
//! other inputs from [`Inputs`]: the parameters `a[]` (`Node::Param(i)`) and,
//! for models that declare `x[4]` or more, the extra coordinate slots
//! (`Node::X(i)` with `i >= 3`). Missing values read as 0, the reference
//! host's default.

pub mod batch;
pub mod grad;
pub mod simd_math;

/// Values of a model's inputs other than the point.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Inputs {
    /// `a[1..]`; missing ones are 0.
    pub params: Vec<f64>,
    /// `x[4..]` for models that declare more than three coordinates.
    pub extra_x: Vec<f64>,
}

impl Inputs {
    /// Inputs with these parameters and no extra coordinates.
    pub fn with_params(params: &[f64]) -> Self {
        Inputs {
            params: params.to_vec(),
            extra_x: Vec::new(),
        }
    }

    /// `a[i + 1]` (0 when not given).
    #[inline]
    pub fn param(&self, i: u32) -> f64 {
        self.params.get(i as usize).copied().unwrap_or(0.0)
    }

    /// `x[i + 1]` for `i >= 3` (0 when not given).
    #[inline]
    pub fn extra_x(&self, i: u32) -> f64 {
        (i as usize)
            .checked_sub(3)
            .and_then(|k| self.extra_x.get(k).copied())
            .unwrap_or(0.0)
    }
}

pub mod interval;
pub mod point;
pub mod reference;
pub use point::PointEval;

#[cfg(test)]
pub(crate) mod testutil;
