//! The section (clipping) plane ([`Section`]). The part of the solid with
//! `normal · p > offset` is cut away, showing its inside. The studio's
//! `SectionPlane` and its client ray caster use the same convention.
//!
//! The caster clips by casting a different field, `min(offset − n·p, f)`:
//! a set intersection with the kept half-space. It is built into the
//! model's graph once per render ([`sectioned_tape`]).
//! - Every path of the caster then handles the plane as any other part of
//!   the model: interval pruning, shortened tapes, quadrics and set
//!   expressions in closed form, the box cut.
//! - A ray starts where it enters the kept half-space.
//! - Where the solid is cut, its hit lies on the plane, with the plane's
//!   normal. The gradient of `offset − n·p` is `−n`.
//! - The cut face keeps the model's attribute colour there. A model without
//!   colours shows it in [`SECTION_CAP`] (the studio's `sectionCap`), as
//!   the client modes do. [`Section::is_on_cap`] tells a cut-face hit.

use frep_core::ops::BinaryOp;
use frep_core::{Model, Tape};

use crate::image::Hit;

/// The cut face's colour for a model without attribute colours (sRGB in
/// `[0, 1]`; the studio's `SCENE.sectionCap`).
pub const SECTION_CAP: [f32; 3] = [0.85, 0.45, 0.3];

/// A section plane: the solid is kept where `normal · p <= offset`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    /// The plane's normal, pointing into the part cut away (world
    /// coordinates; any non-zero length, see [`Section::normalized`]).
    pub normal: [f64; 3],
    /// The plane's offset along the normal, world units (for a unit normal).
    pub offset: f64,
}

/// Why a [`Section`] cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "section plane: the normal must be finite and non-zero and the offset finite \
     (normal {normal:?}, offset {offset})"
)]
pub struct SectionError {
    /// The normal given.
    pub normal: [f64; 3],
    /// The offset given.
    pub offset: f64,
}

impl Section {
    /// The same plane with a unit normal (the offset scaled with it), or an
    /// error where the normal is zero or either is not finite.
    pub fn normalized(&self) -> Result<Section, SectionError> {
        let err = || SectionError {
            normal: self.normal,
            offset: self.offset,
        };
        let len = self.normal.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !len.is_finite() || len <= 0.0 || !self.offset.is_finite() {
            return Err(err());
        }
        let normal = self.normal.map(|v| v / len);
        let offset = self.offset / len;
        if !offset.is_finite() {
            return Err(err());
        }
        Ok(Section { normal, offset })
    }

    /// `offset − normal · p`: positive on the kept side.
    pub fn signed(&self, p: [f64; 3]) -> f64 {
        self.offset - (self.normal[0] * p[0] + self.normal[1] * p[1] + self.normal[2] * p[2])
    }

    /// Whether `hit` lies on the cut face of this (normalized) section:
    /// within `tol` of the plane with a normal along the plane's.
    pub fn is_on_cap(&self, hit: &Hit, tol: f64) -> bool {
        if self.signed(hit.position).abs() > tol {
            return false;
        }
        let n = hit.normal;
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        let along = n[0] * self.normal[0] + n[1] * self.normal[1] + n[2] * self.normal[2];
        // Within about 0.1° of the plane's normal.
        len > 0.0 && along >= len * (1.0 - 1e-6)
    }
}

/// The tape of `model`'s value cut by `section` (a normalized plane):
/// `min(offset − n·p, f)`. The plane's value comes first so that where `f`
/// is NaN (an error: outside) the result is NaN too (`min(a, b)` is
/// `a < b ? a : b`). Zero components of the normal add no term.
pub fn sectioned_tape(model: &Model, section: &Section) -> Tape {
    let mut g = model.graph.clone();
    let mut dot = None;
    for (k, &c) in section.normal.iter().enumerate() {
        if c == 0.0 {
            continue;
        }
        let x = g.x(k as u32);
        let cn = g.constant(c);
        let term = g.binary(BinaryOp::Mul, cn, x);
        dot = Some(match dot {
            Some(d) => g.binary(BinaryOp::Add, d, term),
            None => term,
        });
    }
    let off = g.constant(section.offset);
    let plane = match dot {
        Some(d) => g.binary(BinaryOp::Sub, off, d),
        // (A normalized section has a non-zero component.)
        None => off,
    };
    let v = g.binary(BinaryOp::Min, plane, model.value);
    g.tape(&[v])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normalized_rejects_bad_planes() {
        let bad = [
            Section {
                normal: [0.0; 3],
                offset: 0.0,
            },
            Section {
                normal: [f64::NAN, 0.0, 1.0],
                offset: 0.0,
            },
            Section {
                normal: [0.0, 0.0, 1.0],
                offset: f64::INFINITY,
            },
        ];
        for s in bad {
            assert!(s.normalized().is_err(), "{s:?}");
        }
        let s = Section {
            normal: [0.0, 0.0, 2.0],
            offset: 1.0,
        }
        .normalized()
        .unwrap();
        assert_eq!(s.normal, [0.0, 0.0, 1.0]);
        assert_eq!(s.offset, 0.5);
    }

    /// The sectioned field is inside exactly where the model is and the
    /// point is on the kept side; NaN (an error) stays NaN.
    #[test]
    fn sectioned_field_is_the_intersection() {
        let m = Model::compile(
            "m(x[3], a[1]) { m = min(1 - x[1]*x[1] - x[2]*x[2] - x[3]*x[3], sqrt(x[1] + 2) - 0.5); }",
        )
        .unwrap();
        let s = Section {
            normal: [0.3, -0.2, 0.9],
            offset: 0.1,
        }
        .normalized()
        .unwrap();
        let cut = sectioned_tape(&m, &s);
        let mut full = frep_core::eval::batch::BatchEval::new(&m.tape());
        let mut ev = frep_core::eval::batch::BatchEval::new(&cut);
        let pts: Vec<[f64; 3]> = (0..400)
            .map(|i| {
                let f = |k: u32| ((i * 37 + k * 11) % 97) as f64 / 97.0 * 6.0 - 3.0;
                [f(0), f(1), f(2)]
            })
            .collect();
        let xs: Vec<f64> = pts.iter().map(|p| p[0]).collect();
        let ys: Vec<f64> = pts.iter().map(|p| p[1]).collect();
        let zs: Vec<f64> = pts.iter().map(|p| p[2]).collect();
        let inputs = frep_core::eval::Inputs::default();
        let (mut a, mut b) = (vec![0.0; 400], vec![0.0; 400]);
        full.eval(&xs, &ys, &zs, &inputs, &mut a);
        ev.eval(&xs, &ys, &zs, &inputs, &mut b);
        let mut nan = 0;
        for (j, p) in pts.iter().enumerate() {
            if a[j].is_nan() {
                assert!(b[j].is_nan(), "{p:?}");
                nan += 1;
                continue;
            }
            assert_eq!(b[j] >= 0.0, a[j] >= 0.0 && s.signed(*p) >= 0.0, "{p:?}");
        }
        assert!(nan > 0, "some points outside sqrt's domain");
    }
}
