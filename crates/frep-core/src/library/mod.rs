//! The FRep library of HyperFun (`hfSphere`, `hfBlendUni`, `hfRotate3DZ`, ...)
//! as graph builders.
//!
//! Each [`LibFn`] builds the nodes computing one call from the argument
//! nodes, porting the C reference library (`hflibrary_lib/*.c`) formula by
//! formula, with the C code's floating-point operation order so that constant
//! folding and the evaluators give the reference's bits. Library arithmetic
//! is IEEE (`DivF`, `SqrtF`, `PowF`): the C library never raises HyperFun
//! runtime errors.
//!
//! Conventions of the port:
//! * conditions the C code tests on values (sentinels for ~0 axes, `d < 0`
//!   in `hfBlock`, the taper's `|scale| < 1e-6`, the metaball's pieces, the
//!   arc's `theta > 180`) become [`Graph::select`] nodes over comparison
//!   nodes, which fold away when the values are constants;
//! * the sentinel `-1111111111111.0` for a point array without exactly 3
//!   items is decided at build time (array sizes are static);
//! * arrays shorter than the C code reads (a centre with fewer than 3 items,
//!   blobby arrays shorter than `x0`, ...) are a [`LibError`]: the C code
//!   would read outside the array;
//! * a zero-length `hfConvLine`/`hfConvCurve` segment, where the C code calls
//!   `error()`, is a [`LibError`] when the end points are constants and gives
//!   NaN otherwise; `hfConvMesh` needs constant triangle indices;
//! * transformations and attribute setters write their results into the
//!   [`LibArg::Array`] they modify and return the constant 1;
//! * `hfConvArc` writes `angle[n] + 1e-6` and the clamped `theta[n]` back
//!   into its array arguments on every call, as the C code does.
//!
//! The convolution closed forms were checked against quadrature of the
//! Cauchy kernel `1 / (1 + S²r²)²` (see the tests). Each convolution file
//! says what its closed form integrates.
//!
//! ## Coverage of the reference function table (`int_global.c`)
//! Implemented: every entry of SPEC §4.1–4.3 (`hfSphere`, `hfEllipsoid`,
//! `hfTorusX/Y/Z`, `hfEllCylX/Y/Z`, `hfCylinderX/Y/Z`, `hfBlock`,
//! `hfBlobby`, `hfMetaball`, `hfSoft`, `hfScale3D`, `hfShift3D`,
//! `hfRotate3DX/Y/Z`, `hfBlendUni`, `hfBlendInt`, `hfTwistX/Y/Z`,
//! `hfStretch3D`, `hfTaperX/Y/Z`, `hfConvPoint`, `hfConvLine`, `hfConvArc`,
//! `hfConvTriangle`, `hfConvLineR`, `hfConvCurve`, `hfConvMesh`, `hfNoiseG`,
//! `hfSuperell`, `hfConeX/Y/Z`, `hfEllConeX/Y/Z`, `hfSpaceMapCubic`,
//! `hfSpaceMapExp`), the attribute setters `hfA_SetColor` and
//! `hfA_SetAttributes`, and the distance primitives `hfDConeX/Y/Z`,
//! `hfDCylinder`, `hfDTorusX/Y/Z`.
//!
//! Not implemented (table entries): `hfBezierVolume`, `hfR` (R-package
//! only), `hfDEllipsoid` (Newton iteration), the SARDF operations `hfDUni`,
//! `hfDInt`, `hfDSub`, `hfDBlendUni`, `hfDBlendInt`, `hfSawtooth`, and the
//! attribute functions `hfA_Wave`, `hfA_CheckerBoard`, `hfA_Union`,
//! `hfA_Crackles`, `hfA_Circles`, `hfA_NoiseG`, `hfA_NoiseP`,
//! `hfA_Turbulence` (RNG / noise tables), `hfA_Lerp`, `hfA_Cerp`,
//! `hfA_Clamp`, `hfA_Floor`, `hfA_Pulse`, `hfA_LookUpTable`,
//! `hfA_SmoothLookUpTable`, `hfA_Step`, `hfA_SmoothStep`, `hfA_Modulo`,
//! `hfA_Spline`, `hfA_RGBToHSV`, `hfA_HSVToRGB`. (`hfCubicBSpline` and
//! `hfVoxel` are commented out of the table.)

mod attributes;
mod blends;
mod build;
mod conv_arc;
mod conv_triangle;
mod convolution;
mod distance;
mod primitives;
mod table;
mod transformations;

use crate::graph::{Graph, NodeId};

/// Kind of a library function parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParamKind {
    /// A real number.
    Scalar,
    /// An array (passed by reference in the reference interpreter).
    Array,
}

/// An argument as the compiler passes it. Arrays are passed by value: the
/// function may modify the Vec (transformations do) and the compiler writes
/// the items back into the caller's array after the call.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum LibArg {
    /// A scalar argument's node.
    Scalar(NodeId),
    /// An array argument's items.
    Array(Vec<NodeId>),
}

pub use crate::error::LibError;

/// One library function.
#[derive(Debug)]
pub struct LibFn {
    /// The lower-case name, e.g. `"hfsphere"`.
    pub name: &'static str,
    /// The name as the reference documentation spells it, e.g. `"hfSphere"`
    /// (HyperFun ignores case; editors show and complete this one).
    pub display: &'static str,
    /// The kinds of the parameters, in call order.
    pub params: &'static [ParamKind],
    /// The parameters' names as the reference documentation gives them, in
    /// call order (as many as `params`).
    pub param_names: &'static [&'static str],
    /// What it computes, in one sentence (for editors' help).
    pub doc: &'static str,
    /// Builds the call's value from its arguments.
    pub build: fn(&mut Graph, &mut [LibArg]) -> Result<NodeId, LibError>,
}

/// Looks a library function up by its lower-case name (ASCII case is
/// ignored).
pub fn lookup(name: &str) -> Option<&'static LibFn> {
    table::ALL
        .iter()
        .find(|f| f.name.eq_ignore_ascii_case(name))
}

/// All library functions (for exhaustiveness tests).
pub fn all() -> &'static [LibFn] {
    table::ALL
}

/// What the C primitives return when the point array has not 3 items.
pub const SENTINEL: f64 = -1111111111111.0;

#[cfg(test)]
use primitives::other_axes;
#[cfg(test)]
mod tests;
