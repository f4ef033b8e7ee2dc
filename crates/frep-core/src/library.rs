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
//! `tan` and `atanh` inside `hfConvArc` have no IEEE graph operation; they
//! are built from the checked ones behind selects that keep them error-free
//! (`tan` as `sin/cos` where `|cos| < 1e-6`, a value within a few ulps of
//! libm's; `log` as NaN / `-inf` outside its domain, like C's).
//!
//! The convolution closed forms were checked against quadrature of the Cauchy
//! kernel `1 / (1 + S²r²)²` (see the tests): `hfConvLine`/`hfConvCurve`
//! integrate it along the segment's length, `hfConvArc` over the arc's
//! *angle* (not its length: `r` times smaller), and `hfConvTriangle` /
//! `hfConvMesh` give `S³` times its area integral. `hfConvArc` is singular
//! (NaN) where the point's local x coordinate is 0, as in C.
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

use std::fmt;

use crate::graph::{Graph, NodeId};
use crate::ops::{BinaryOp, BlendOp, UnaryOp, EPS};

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

/// A compile-time error in the arguments of a call (wrong array size etc.),
/// reported by the compiler at the span of argument `arg` (0-based).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LibError {
    /// The 0-based index of the offending argument.
    pub arg: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for LibError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "argument {}: {}", self.arg + 1, self.message)
    }
}

impl std::error::Error for LibError {}

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
    ALL.iter().find(|f| f.name.eq_ignore_ascii_case(name))
}

/// All library functions (for exhaustiveness tests).
pub fn all() -> &'static [LibFn] {
    ALL
}

/// What the C primitives return when the point array has not 3 items.
pub const SENTINEL: f64 = -1111111111111.0;

/// `-11111111111.0`: the distance cones' sentinel.
const SENTINEL_DCONE: f64 = -11111111111.0;
/// `-11111111111.1`: `hfDCylinder`'s sentinel.
const SENTINEL_DCYL: f64 = -11111111111.1;
/// `PI` of `hfConvArc.c` (deliberately the truncated value).
#[allow(clippy::approx_constant)]
const ARC_PI: f64 = 3.141592;

const S: ParamKind = ParamKind::Scalar;
const A: ParamKind = ParamKind::Array;

macro_rules! lib {
    ($name:literal, $display:literal, [$($k:ident $p:literal),*], $f:ident, $doc:literal) => {
        LibFn {
            name: $name,
            display: $display,
            params: &[$($k),*],
            param_names: &[$($p),*],
            doc: $doc,
            build: $f,
        }
    };
}

static ALL: &[LibFn] = &[
    lib!(
        "hfsphere",
        "hfSphere",
        [A "x", A "center", S "R"],
        hf_sphere,
        "Sphere of radius R around center: R² − |x − center|²."
    ),
    lib!(
        "hfellipsoid",
        "hfEllipsoid",
        [A "x", A "center", S "a", S "b", S "c"],
        hf_ellipsoid,
        "Ellipsoid with semi-axes a, b, c around center."
    ),
    lib!(
        "hftorusz",
        "hfTorusZ",
        [A "x", A "center", S "R", S "r0"],
        hf_torus_z,
        "Torus around an axis parallel to z: major radius R, minor radius r0."
    ),
    lib!(
        "hftorusx",
        "hfTorusX",
        [A "x", A "center", S "R", S "r0"],
        hf_torus_x,
        "Torus around an axis parallel to x: major radius R, minor radius r0."
    ),
    lib!(
        "hftorusy",
        "hfTorusY",
        [A "x", A "center", S "R", S "r0"],
        hf_torus_y,
        "Torus around an axis parallel to y: major radius R, minor radius r0."
    ),
    lib!(
        "hfellcylx",
        "hfEllCylX",
        [A "x", A "center", S "a", S "b"],
        hf_ell_cyl_x,
        "Infinite elliptic cylinder along x with semi-axes a, b."
    ),
    lib!(
        "hfellcyly",
        "hfEllCylY",
        [A "x", A "center", S "a", S "b"],
        hf_ell_cyl_y,
        "Infinite elliptic cylinder along y with semi-axes a, b."
    ),
    lib!(
        "hfellcylz",
        "hfEllCylZ",
        [A "x", A "center", S "a", S "b"],
        hf_ell_cyl_z,
        "Infinite elliptic cylinder along z with semi-axes a, b."
    ),
    lib!(
        "hfcylinderx",
        "hfCylinderX",
        [A "x", A "center", S "R"],
        hf_cylinder_x,
        "Infinite circular cylinder along x of radius R."
    ),
    lib!(
        "hfcylindery",
        "hfCylinderY",
        [A "x", A "center", S "R"],
        hf_cylinder_y,
        "Infinite circular cylinder along y of radius R."
    ),
    lib!(
        "hfcylinderz",
        "hfCylinderZ",
        [A "x", A "center", S "R"],
        hf_cylinder_z,
        "Infinite circular cylinder along z of radius R."
    ),
    lib!(
        "hfblock",
        "hfBlock",
        [A "x", A "vertex", S "dx", S "dy", S "dz"],
        hf_block,
        "Box with one corner at vertex and edges dx, dy, dz."
    ),
    lib!(
        "hfblobby",
        "hfBlobby",
        [A "x", A "x0", A "y0", A "z0", A "a", A "b", S "T"],
        hf_blobby,
        "Blobby model: Gaussian blobs at (x0[i], y0[i], z0[i]) with strengths a, widths b, threshold T."
    ),
    lib!(
        "hfmetaball",
        "hfMetaball",
        [A "x", A "x0", A "y0", A "z0", A "b", A "d", S "T"],
        hf_metaball,
        "Metaballs at (x0[i], y0[i], z0[i]) with weights b, radii d, threshold T."
    ),
    lib!(
        "hfsoft",
        "hfSoft",
        [A "x", A "x0", A "y0", A "z0", A "d", S "T"],
        hf_soft,
        "Soft objects at (x0[i], y0[i], z0[i]) with radii d, threshold T."
    ),
    lib!(
        "hfscale3d",
        "hfScale3D",
        [A "xt", S "sx", S "sy", S "sz"],
        hf_scale3d,
        "Scales the coordinates xt by sx, sy, sz (a space transformation)."
    ),
    lib!(
        "hfshift3d",
        "hfShift3D",
        [A "xt", S "dx", S "dy", S "dz"],
        hf_shift3d,
        "Moves the coordinates xt by dx, dy, dz (a space transformation)."
    ),
    lib!(
        "hfrotate3dz",
        "hfRotate3DZ",
        [A "xt", S "theta"],
        hf_rotate3d_z,
        "Rotates the coordinates xt around z by theta radians."
    ),
    lib!(
        "hfrotate3dy",
        "hfRotate3DY",
        [A "xt", S "theta"],
        hf_rotate3d_y,
        "Rotates the coordinates xt around y by theta radians."
    ),
    lib!(
        "hfrotate3dx",
        "hfRotate3DX",
        [A "xt", S "theta"],
        hf_rotate3d_x,
        "Rotates the coordinates xt around x by theta radians."
    ),
    lib!(
        "hfblenduni",
        "hfBlendUni",
        [S "f1", S "f2", S "a0", S "a1", S "a2"],
        hf_blend_uni,
        "Blending union of f1 and f2: displacement a0, shape a1, a2."
    ),
    lib!(
        "hfblendint",
        "hfBlendInt",
        [S "f1", S "f2", S "a0", S "a1", S "a2"],
        hf_blend_int,
        "Blending intersection of f1 and f2: displacement a0, shape a1, a2."
    ),
    lib!(
        "hftwistz",
        "hfTwistZ",
        [A "xt", S "z1", S "z2", S "theta1", S "theta2"],
        hf_twist_z,
        "Twists xt around z from angle theta1 at z1 to theta2 at z2."
    ),
    lib!(
        "hftwisty",
        "hfTwistY",
        [A "xt", S "y1", S "y2", S "theta1", S "theta2"],
        hf_twist_y,
        "Twists xt around y from angle theta1 at y1 to theta2 at y2."
    ),
    lib!(
        "hftwistx",
        "hfTwistX",
        [A "xt", S "x1", S "x2", S "theta1", S "theta2"],
        hf_twist_x,
        "Twists xt around x from angle theta1 at x1 to theta2 at x2."
    ),
    lib!(
        "hfstretch3d",
        "hfStretch3D",
        [A "xt", A "x0", S "sx", S "sy", S "sz"],
        hf_stretch3d,
        "Stretches xt about the point x0 by sx, sy, sz."
    ),
    lib!(
        "hftaperz",
        "hfTaperZ",
        [A "xt", S "z1", S "z2", S "s1", S "s2"],
        hf_taper_z,
        "Tapers xt along z: scale s1 at z1 to s2 at z2."
    ),
    lib!(
        "hftapery",
        "hfTaperY",
        [A "xt", S "y1", S "y2", S "s1", S "s2"],
        hf_taper_y,
        "Tapers xt along y: scale s1 at y1 to s2 at y2."
    ),
    lib!(
        "hftaperx",
        "hfTaperX",
        [A "xt", S "x1", S "x2", S "s1", S "s2"],
        hf_taper_x,
        "Tapers xt along x: scale s1 at x1 to s2 at x2."
    ),
    lib!(
        "hfconvpoint",
        "hfConvPoint",
        [A "x", A "vect", A "S", S "T"],
        hf_conv_point,
        "Convolution surface of points vect with kernel widths S and threshold T."
    ),
    lib!(
        "hfconvline",
        "hfConvLine",
        [A "x", A "begin", A "end", A "S", S "T"],
        hf_conv_line,
        "Convolution surface of segments begin[i]–end[i], widths S, threshold T."
    ),
    lib!(
        "hfconvarc",
        "hfConvArc",
        [A "x", A "center", A "radius", A "theta", A "axis", A "angle", A "S", S "T"],
        hf_conv_arc,
        "Convolution surface of arcs: centre, radius, arc angle theta, rotation axis and angle, widths S, threshold T."
    ),
    lib!(
        "hfconvtriangle",
        "hfConvTriangle",
        [A "x", A "vect", A "S", S "T"],
        hf_conv_triangle,
        "Convolution surface of triangles (9 numbers each in vect), widths S, threshold T."
    ),
    lib!(
        "hfconvliner",
        "hfConvLineR",
        [A "x", A "begin", A "end", S "R"],
        hf_conv_line_r,
        "Convolution surface of segments begin[i]–end[i] with radius R."
    ),
    lib!(
        "hfconvcurve",
        "hfConvCurve",
        [A "x", A "vect", A "S", S "T"],
        hf_conv_curve,
        "Convolution surface of the polyline through the points vect, widths S, threshold T."
    ),
    lib!(
        "hfconvmesh",
        "hfConvMesh",
        [A "x", A "vect", A "tri", A "S", S "T"],
        hf_conv_mesh,
        "Convolution surface of a triangle mesh: vertices vect, vertex indices tri, widths S, threshold T."
    ),
    lib!(
        "hfnoiseg",
        "hfNoiseG",
        [A "x", S "amp", S "freq", S "phase"],
        hf_noise_g,
        "Gaussian-like noise of amplitude amp, frequency freq and phase, added to a shape."
    ),
    lib!(
        "hfsuperell",
        "hfSuperell",
        [A "x", A "center", S "a", S "b", S "c", S "s1", S "s2"],
        hf_superell,
        "Superellipsoid with semi-axes a, b, c and shape exponents s1, s2."
    ),
    lib!(
        "hfconex",
        "hfConeX",
        [A "x", A "center", S "R"],
        hf_cone_x,
        "Infinite circular cone along x, apex at center, slope R."
    ),
    lib!(
        "hfconey",
        "hfConeY",
        [A "x", A "center", S "R"],
        hf_cone_y,
        "Infinite circular cone along y, apex at center, slope R."
    ),
    lib!(
        "hfconez",
        "hfConeZ",
        [A "x", A "center", S "R"],
        hf_cone_z,
        "Infinite circular cone along z, apex at center, slope R."
    ),
    lib!(
        "hfellconex",
        "hfEllConeX",
        [A "x", A "center", S "a", S "b"],
        hf_ell_cone_x,
        "Infinite elliptic cone along x, apex at center, slopes a, b."
    ),
    lib!(
        "hfellconey",
        "hfEllConeY",
        [A "x", A "center", S "a", S "b"],
        hf_ell_cone_y,
        "Infinite elliptic cone along y, apex at center, slopes a, b."
    ),
    lib!(
        "hfellconez",
        "hfEllConeZ",
        [A "x", A "center", S "a", S "b"],
        hf_ell_cone_z,
        "Infinite elliptic cone along z, apex at center, slopes a, b."
    ),
    lib!(
        "hfspacemapcubic",
        "hfSpaceMapCubic",
        [A "xt", A "source", A "target", A "b"],
        hf_space_map_cubic,
        "Space mapping moving the points source to target with cubic falloff b."
    ),
    lib!(
        "hfspacemapexp",
        "hfSpaceMapExp",
        [A "xt", A "source", A "target", A "b"],
        hf_space_map_exp,
        "Space mapping moving the points source to target with exponential falloff b."
    ),
    lib!(
        "hfa_setcolor",
        "hfA_SetColor",
        [S "f", A "s", S "r", S "g", S "b"],
        hfa_set_color,
        "Sets the colour attributes s[1..3] to r, g, b; returns 1."
    ),
    lib!(
        "hfa_setattributes",
        "hfA_SetAttributes",
        [S "f", A "s", A "s1"],
        hfa_set_attributes,
        "Copies the attributes s1 into s; returns 1."
    ),
    lib!(
        "hfdconex",
        "hfDConeX",
        [A "x", A "center", S "R"],
        hf_dcone_x,
        "Distance-based cone along x, apex at center, slope R."
    ),
    lib!(
        "hfdconey",
        "hfDConeY",
        [A "x", A "center", S "R"],
        hf_dcone_y,
        "Distance-based cone along y, apex at center, slope R."
    ),
    lib!(
        "hfdconez",
        "hfDConeZ",
        [A "x", A "center", S "R"],
        hf_dcone_z,
        "Distance-based cone along z, apex at center, slope R."
    ),
    lib!(
        "hfdcylinder",
        "hfDCylinder",
        [A "x", A "center", A "u", S "R"],
        hf_dcylinder,
        "Distance-based infinite cylinder through center along direction u, radius R."
    ),
    lib!(
        "hfdtorusx",
        "hfDTorusX",
        [A "x", A "center", S "R", S "r0"],
        hf_dtorus_x,
        "Distance-based torus around x: major radius R, minor radius r0."
    ),
    lib!(
        "hfdtorusy",
        "hfDTorusY",
        [A "x", A "center", S "R", S "r0"],
        hf_dtorus_y,
        "Distance-based torus around y: major radius R, minor radius r0."
    ),
    lib!(
        "hfdtorusz",
        "hfDTorusZ",
        [A "x", A "center", S "R", S "r0"],
        hf_dtorus_z,
        "Distance-based torus around z: major radius R, minor radius r0."
    ),
];

// ---------------------------------------------------------------------------
// Building blocks

/// Shorthands for IEEE graph arithmetic.
struct C<'g> {
    g: &'g mut Graph,
}

impl C<'_> {
    fn k(&mut self, v: f64) -> NodeId {
        self.g.constant(v)
    }
    fn bin(&mut self, op: BinaryOp, a: NodeId, b: NodeId) -> NodeId {
        self.g.binary(op, a, b)
    }
    fn add(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Add, a, b)
    }
    fn sub(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Sub, a, b)
    }
    fn mul(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Mul, a, b)
    }
    fn div(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::DivF, a, b)
    }
    fn pow(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::PowF, a, b)
    }
    /// `a * a`, as the C code's `SQ(a)` / `a*a`.
    fn sq(&mut self, a: NodeId) -> NodeId {
        self.mul(a, a)
    }
    /// `k + a` with a constant `k`.
    fn kadd(&mut self, k: f64, a: NodeId) -> NodeId {
        let k = self.k(k);
        self.add(k, a)
    }
    /// `k - a` with a constant `k`.
    fn ksub(&mut self, k: f64, a: NodeId) -> NodeId {
        let k = self.k(k);
        self.sub(k, a)
    }
    /// `k * a` with a constant `k`.
    fn kmul(&mut self, k: f64, a: NodeId) -> NodeId {
        let k = self.k(k);
        self.mul(k, a)
    }
    fn un(&mut self, op: UnaryOp, a: NodeId) -> NodeId {
        self.g.unary(op, a)
    }
    fn neg(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Neg, a)
    }
    fn abs(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Abs, a)
    }
    fn sqrt(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::SqrtF, a)
    }
    fn sin(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Sin, a)
    }
    fn cos(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Cos, a)
    }
    fn exp(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Exp, a)
    }
    fn atan(&mut self, a: NodeId) -> NodeId {
        self.un(UnaryOp::Atan, a)
    }
    /// C `log`: `ln` for positive arguments, `-inf` at 0, NaN below or NaN.
    fn log(&mut self, a: NodeId) -> NodeId {
        let z = self.k(0.0);
        let pos = self.bin(BinaryOp::Gt, a, z);
        let zero = self.bin(BinaryOp::Ge, a, z);
        let ln = self.un(UnaryOp::Log, a);
        let ninf = self.k(f64::NEG_INFINITY);
        let nan = self.k(f64::NAN);
        let rest = self.g.select(zero, ninf, nan);
        self.g.select(pos, ln, rest)
    }
    /// C `tan`: libm's where the checked `tan` accepts the argument, `sin/cos`
    /// where `|cos| < 1e-6`.
    fn tan(&mut self, a: NodeId) -> NodeId {
        let c = self.cos(a);
        let ac = self.abs(c);
        let eps = self.k(EPS);
        let ok = self.bin(BinaryOp::Ge, ac, eps);
        let t = self.un(UnaryOp::Tan, a);
        let s = self.sin(a);
        let q = self.div(s, c);
        self.g.select(ok, t, q)
    }
    /// `archyp.h`'s `atanh(z) = log((1+z)*sqrt(1/(1-(z*z))))`.
    fn atanh(&mut self, z: NodeId) -> NodeId {
        let opz = self.kadd(1.0, z);
        let zz = self.sq(z);
        let omz = self.ksub(1.0, zz);
        let one = self.k(1.0);
        let inv = self.div(one, omz);
        let r = self.sqrt(inv);
        let p = self.mul(opz, r);
        self.log(p)
    }
    fn lt(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Lt, a, b)
    }
    fn le(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Le, a, b)
    }
    fn gt(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Gt, a, b)
    }
    fn ge(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Ge, a, b)
    }
    fn or(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::Or, a, b)
    }
    fn and(&mut self, a: NodeId, b: NodeId) -> NodeId {
        self.bin(BinaryOp::And, a, b)
    }
    fn sel(&mut self, c: NodeId, t: NodeId, e: NodeId) -> NodeId {
        self.g.select(c, t, e)
    }
    /// `|a| < EPS`, as 1/0.
    fn tiny(&mut self, a: NodeId) -> NodeId {
        let aa = self.abs(a);
        let eps = self.k(EPS);
        self.lt(aa, eps)
    }
    /// `cond ? SENTINEL : f` for a list of conditions or'ed together.
    fn sentinel_if(&mut self, conds: &[NodeId], f: NodeId) -> NodeId {
        let mut c = conds[0];
        for &d in &conds[1..] {
            c = self.or(c, d);
        }
        let s = self.k(SENTINEL);
        self.sel(c, s, f)
    }
}

fn err(arg: usize, message: String) -> LibError {
    LibError { arg, message }
}

fn scalar(args: &[LibArg], i: usize) -> Result<NodeId, LibError> {
    match &args[i] {
        LibArg::Scalar(n) => Ok(*n),
        LibArg::Array(_) => Err(err(i, "expected a number, found an array".into())),
    }
}

fn array(args: &[LibArg], i: usize) -> Result<Vec<NodeId>, LibError> {
    match &args[i] {
        LibArg::Array(v) => Ok(v.clone()),
        LibArg::Scalar(_) => Err(err(i, "expected an array, found a number".into())),
    }
}

/// The array argument `i`, which must have at least `n` items.
fn array_min(
    args: &[LibArg],
    i: usize,
    n: usize,
    func: &str,
    what: &str,
) -> Result<Vec<NodeId>, LibError> {
    let v = array(args, i)?;
    if v.len() < n {
        return Err(err(
            i,
            format!(
                "{func}: array `{what}` has {} items, at least {n} are needed",
                v.len()
            ),
        ));
    }
    Ok(v)
}

fn set_array(args: &mut [LibArg], i: usize, v: Vec<NodeId>) {
    args[i] = LibArg::Array(v);
}

/// The point argument (0) if it has exactly 3 items.
fn point(args: &[LibArg]) -> Result<Option<[NodeId; 3]>, LibError> {
    let x = array(args, 0)?;
    Ok(if x.len() == 3 {
        Some([x[0], x[1], x[2]])
    } else {
        None
    })
}

/// `x - centre` of a centred primitive (`x` argument 0, centre argument 1),
/// or `None` when `x` has not 3 items (the sentinel case).
fn centred(args: &[LibArg], c: &mut C, func: &str) -> Result<Option<[NodeId; 3]>, LibError> {
    let centre = array_min(args, 1, 3, func, "center")?;
    let Some(x) = point(args)? else {
        return Ok(None);
    };
    Ok(Some([
        c.sub(x[0], centre[0]),
        c.sub(x[1], centre[1]),
        c.sub(x[2], centre[2]),
    ]))
}

macro_rules! centred_or_sentinel {
    ($args:expr, $c:expr, $func:expr) => {
        match centred($args, &mut $c, $func)? {
            Some(d) => d,
            None => return Ok($c.k(SENTINEL)),
        }
    };
}

// ---------------------------------------------------------------------------
// Primitives

fn hf_sphere(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let r = scalar(args, 2)?;
    let [xt, yt, zt] = centred_or_sentinel!(args, c, "hfSphere");
    let rr = c.sq(r);
    let x2 = c.sq(xt);
    let y2 = c.sq(yt);
    let z2 = c.sq(zt);
    let f = c.sub(rr, x2);
    let f = c.sub(f, y2);
    Ok(c.sub(f, z2))
}

fn hf_ellipsoid(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (a, b, cc) = (scalar(args, 2)?, scalar(args, 3)?, scalar(args, 4)?);
    let [dx, dy, dz] = centred_or_sentinel!(args, c, "hfEllipsoid");
    let xt = c.div(dx, a);
    let yt = c.div(dy, b);
    let zt = c.div(dz, cc);
    let f = one_minus_squares(&mut c, &[xt, yt, zt]);
    let conds = [c.tiny(a), c.tiny(b), c.tiny(cc)];
    Ok(c.sentinel_if(&conds, f))
}

/// `1. - t0*t0 - t1*t1 - ...`
fn one_minus_squares(c: &mut C, ts: &[NodeId]) -> NodeId {
    let mut f = c.k(1.0);
    for &t in ts {
        let t2 = c.sq(t);
        f = c.sub(f, t2);
    }
    f
}

/// `r0*r0 - u*u - v*v - w*w - R*R + 2*R*sqrt(s)` where `(u, v, w)` are the
/// squares in the C code's order and `s` the sqrt argument.
fn torus_tail(c: &mut C, r0: NodeId, big_r: NodeId, sq: [NodeId; 3], s: NodeId) -> NodeId {
    let mut f = c.sq(r0);
    for q in sq {
        f = c.sub(f, q);
    }
    let rr = c.sq(big_r);
    f = c.sub(f, rr);
    let two_r = c.kmul(2.0, big_r);
    let rt = c.sqrt(s);
    let t = c.mul(two_r, rt);
    c.add(f, t)
}

fn hf_torus_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (big_r, r0) = (scalar(args, 2)?, scalar(args, 3)?);
    let [xt, yt, zt] = centred_or_sentinel!(args, c, "hfTorusX");
    let z2 = c.sq(zt);
    let y2 = c.sq(yt);
    let x2 = c.sq(xt);
    let s = c.add(z2, y2);
    Ok(torus_tail(&mut c, r0, big_r, [x2, y2, z2], s))
}

fn hf_torus_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (big_r, r0) = (scalar(args, 2)?, scalar(args, 3)?);
    let [xt, yt, zt] = centred_or_sentinel!(args, c, "hfTorusY");
    let z2 = c.sq(zt);
    let x2 = c.sq(xt);
    let y2 = c.sq(yt);
    let s = c.add(z2, x2);
    Ok(torus_tail(&mut c, r0, big_r, [x2, y2, z2], s))
}

fn hf_torus_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (big_r, r0) = (scalar(args, 2)?, scalar(args, 3)?);
    let [xt, yt, zt] = centred_or_sentinel!(args, c, "hfTorusZ");
    let x2 = c.sq(xt);
    let y2 = c.sq(yt);
    let z2 = c.sq(zt);
    let s = c.add(x2, y2);
    Ok(torus_tail(&mut c, r0, big_r, [x2, y2, z2], s))
}

/// Elliptic cylinder along axis `skip`: `1 - (d_i/a)^2 - (d_j/b)^2`.
fn ell_cyl(g: &mut Graph, args: &[LibArg], skip: usize, func: &str) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (a, b) = (scalar(args, 2)?, scalar(args, 3)?);
    let Some(d) = centred(args, &mut c, func)? else {
        return Ok(c.k(SENTINEL));
    };
    let (i, j) = other_axes(skip);
    let u = c.div(d[i], a);
    let v = c.div(d[j], b);
    let f = one_minus_squares(&mut c, &[u, v]);
    let conds = [c.tiny(a), c.tiny(b)];
    Ok(c.sentinel_if(&conds, f))
}

fn other_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

fn hf_ell_cyl_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    ell_cyl(g, args, 0, "hfEllCylX")
}
fn hf_ell_cyl_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    ell_cyl(g, args, 1, "hfEllCylY")
}
fn hf_ell_cyl_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    ell_cyl(g, args, 2, "hfEllCylZ")
}

/// Circular cylinder along axis `skip`: `R*R - d_i^2 - d_j^2`.
fn cylinder(g: &mut Graph, args: &[LibArg], skip: usize, func: &str) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let r = scalar(args, 2)?;
    let Some(d) = centred(args, &mut c, func)? else {
        return Ok(c.k(SENTINEL));
    };
    let (i, j) = other_axes(skip);
    let rr = c.sq(r);
    let u = c.sq(d[i]);
    let v = c.sq(d[j]);
    let f = c.sub(rr, u);
    Ok(c.sub(f, v))
}

fn hf_cylinder_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cylinder(g, args, 0, "hfCylinderX")
}
fn hf_cylinder_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cylinder(g, args, 1, "hfCylinderY")
}
fn hf_cylinder_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cylinder(g, args, 2, "hfCylinderZ")
}

/// (Elliptic) cone along `axis`: `d_axis^2 - (d_i/a)^2 - (d_j/b)^2`, where
/// the circular cone passes `a = b = R` (argument 2 twice).
fn cone(
    g: &mut Graph,
    args: &[LibArg],
    axis: usize,
    elliptic: bool,
    func: &str,
) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let a = scalar(args, 2)?;
    let b = if elliptic { scalar(args, 3)? } else { a };
    let Some(d) = centred(args, &mut c, func)? else {
        return Ok(c.k(SENTINEL));
    };
    let (i, j) = other_axes(axis);
    let t = d[axis];
    let u = c.div(d[i], a);
    let v = c.div(d[j], b);
    let t2 = c.sq(t);
    let u2 = c.sq(u);
    let v2 = c.sq(v);
    let f = c.sub(t2, u2);
    Ok(c.sub(f, v2))
}

fn hf_cone_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cone(g, args, 0, false, "hfConeX")
}
fn hf_cone_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cone(g, args, 1, false, "hfConeY")
}
fn hf_cone_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cone(g, args, 2, false, "hfConeZ")
}
fn hf_ell_cone_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cone(g, args, 0, true, "hfEllConeX")
}
fn hf_ell_cone_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cone(g, args, 1, true, "hfEllConeY")
}
fn hf_ell_cone_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    cone(g, args, 2, true, "hfEllConeZ")
}

fn hf_block(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let ds = [scalar(args, 2)?, scalar(args, 3)?, scalar(args, 4)?];
    let v = array_min(args, 1, 3, "hfBlock", "vertex")?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    let mut t = [x[0]; 3];
    for k in 0..3 {
        let lo = c.sub(x[k], v[k]);
        let vd = c.add(v[k], ds[k]);
        let hi = c.sub(vd, x[k]);
        t[k] = c.mul(lo, hi);
    }
    let f = c.bin(BinaryOp::RInter, t[0], t[1]);
    let f = c.bin(BinaryOp::RInter, f, t[2]);
    let z = c.k(0.0);
    let conds = [c.lt(ds[0], z), c.lt(ds[1], z), c.lt(ds[2], z)];
    Ok(c.sentinel_if(&conds, f))
}

fn hf_superell(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (a, b, cc) = (scalar(args, 2)?, scalar(args, 3)?, scalar(args, 4)?);
    let (s1, s2) = (scalar(args, 5)?, scalar(args, 6)?);
    let [dx, dy, dz] = centred_or_sentinel!(args, c, "hfSuperell");
    let xt = c.div(dx, a);
    let yt = c.div(dy, b);
    let zt = c.div(dz, cc);
    let two = c.k(2.0);
    let p = c.div(two, s2);
    let ax = c.abs(xt);
    let xp = c.pow(ax, p);
    let ay = c.abs(yt);
    let yp = c.pow(ay, p);
    let az = c.abs(zt);
    let pz = c.div(two, s1);
    let zp = c.pow(az, pz);
    let sxy = c.add(xp, yp);
    let e = c.div(s2, s1);
    let xyp = c.pow(sxy, e);
    let f = c.ksub(1.0, xyp);
    let f = c.sub(f, zp);
    let conds = [c.tiny(a), c.tiny(b), c.tiny(cc), c.tiny(s1), c.tiny(s2)];
    Ok(c.sentinel_if(&conds, f))
}

/// The centre arrays `x0, y0, z0` (arguments 1..=3) of the blob primitives
/// and their count `N = size(x0)`, checking that `others` (argument index,
/// name) have at least `N` items too.
#[allow(clippy::type_complexity)]
fn blob_arrays(
    args: &[LibArg],
    func: &str,
    others: &[(usize, &str)],
) -> Result<(usize, [Vec<NodeId>; 3], Vec<Vec<NodeId>>), LibError> {
    let x0 = array(args, 1)?;
    let n = x0.len();
    let y0 = array_min(args, 2, n, func, "y0")?;
    let z0 = array_min(args, 3, n, func, "z0")?;
    let mut rest = Vec::new();
    for &(i, name) in others {
        rest.push(array_min(args, i, n, func, name)?);
    }
    Ok((n, [x0, y0, z0], rest))
}

/// `(x - x0[i], y - y0[i], z - z0[i])`
fn blob_d(c: &mut C, x: &[NodeId], ctr: &[Vec<NodeId>; 3], i: usize) -> [NodeId; 3] {
    [
        c.sub(x[0], ctr[0][i]),
        c.sub(x[1], ctr[1][i]),
        c.sub(x[2], ctr[2][i]),
    ]
}

/// `xt*xt + yt*yt + zt*zt`
fn norm2(c: &mut C, d: [NodeId; 3]) -> NodeId {
    let a = c.sq(d[0]);
    let b = c.sq(d[1]);
    let s = c.add(a, b);
    let z = c.sq(d[2]);
    c.add(s, z)
}

/// The point array of the blob primitives: only its first 3 items are read
/// (the C code does not check its size).
fn blob_point(args: &[LibArg], func: &str) -> Result<Vec<NodeId>, LibError> {
    array_min(args, 0, 3, func, "x")
}

fn hf_blobby(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 6)?;
    let (n, ctr, rest) = blob_arrays(args, "hfBlobby", &[(4, "a"), (5, "b")])?;
    if n == 0 {
        return Ok(c.k(SENTINEL));
    }
    let x = blob_point(args, "hfBlobby")?;
    let (a, b) = (&rest[0], &rest[1]);
    let mut f = c.k(0.0);
    for i in 0..n {
        let d = blob_d(&mut c, &x, &ctr, i);
        let r2 = norm2(&mut c, d);
        let na = c.neg(a[i]);
        let e = c.mul(na, r2);
        let e = c.exp(e);
        let term = c.mul(b[i], e);
        f = c.add(f, term);
    }
    Ok(c.sub(f, t))
}

fn hf_metaball(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 6)?;
    let (n, ctr, rest) = blob_arrays(args, "hfMetaball", &[(4, "b"), (5, "d")])?;
    if n == 0 {
        return Ok(c.k(SENTINEL));
    }
    let x = blob_point(args, "hfMetaball")?;
    let (b, d) = (&rest[0], &rest[1]);
    let mut mb = c.k(0.0);
    let zero = c.k(0.0);
    for i in 0..n {
        let dv = blob_d(&mut c, &x, &ctr, i);
        let r2 = norm2(&mut c, dv);
        let r = c.sqrt(r2);
        let rd = c.div(r, d[i]);
        let three = c.k(3.0);
        let d3 = c.div(d[i], three);
        // r <= d/3: mb + b*(1 - 3*rd*rd)
        let t3 = c.kmul(3.0, rd);
        let t3 = c.mul(t3, rd);
        let inner = c.ksub(1.0, t3);
        let near = c.mul(b[i], inner);
        let near = c.add(mb, near);
        // d/3 < r < d: mb + 1.5*b*(1-rd)*(1-rd)
        let om = c.ksub(1.0, rd);
        let far = c.kmul(1.5, b[i]);
        let far = c.mul(far, om);
        let far = c.mul(far, om);
        let far = c.add(mb, far);
        let in_d = c.lt(r, d[i]);
        let outer = c.sel(in_d, far, mb);
        let in_d3 = c.le(r, d3);
        let v = c.sel(in_d3, near, outer);
        let pos = c.gt(d[i], zero);
        mb = c.sel(pos, v, mb);
    }
    Ok(c.sub(mb, t))
}

fn hf_soft(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 5)?;
    let (n, ctr, rest) = blob_arrays(args, "hfSoft", &[(4, "d")])?;
    if n == 0 {
        return Ok(c.k(SENTINEL));
    }
    let x = blob_point(args, "hfSoft")?;
    let d = &rest[0];
    let mut soft = c.k(0.0);
    for (i, &di) in d.iter().enumerate().take(n) {
        let dv = blob_d(&mut c, &x, &ctr, i);
        let r2 = norm2(&mut c, dv);
        let r4 = c.sq(r2);
        let d2 = c.sq(di);
        let d4 = c.sq(d2);
        // soft + 1 - 22*r2/(9*d2) + 17*r4/(9*d4) - 4*r4*r2/(9*d4*d2)
        let v = c.kadd(1.0, soft);
        let v = {
            let nu = c.kmul(22.0, r2);
            let de = c.kmul(9.0, d2);
            let q = c.div(nu, de);
            c.sub(v, q)
        };
        let v = {
            let nu = c.kmul(17.0, r4);
            let de = c.kmul(9.0, d4);
            let q = c.div(nu, de);
            c.add(v, q)
        };
        let v = {
            let nu = c.kmul(4.0, r4);
            let nu = c.mul(nu, r2);
            let de = c.kmul(9.0, d4);
            let de = c.mul(de, d2);
            let q = c.div(nu, de);
            c.sub(v, q)
        };
        let r = c.sqrt(r2);
        let inside = c.le(r, di);
        soft = c.sel(inside, v, soft);
    }
    Ok(c.sub(soft, t))
}

// ---------------------------------------------------------------------------
// Convolution surfaces (Cauchy kernel 1 / (1 + S^2 r^2)^2)

fn hf_conv_point(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 3)?;
    let s = array(args, 2)?;
    let n = s.len();
    let v = array_min(args, 1, 3 * n, "hfConvPoint", "vect")?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    let mut f = c.k(0.0);
    for (k, &sk) in s.iter().enumerate() {
        let d = [
            c.sub(v[3 * k], x[0]),
            c.sub(v[3 * k + 1], x[1]),
            c.sub(v[3 * k + 2], x[2]),
        ];
        let r2 = norm2(&mut c, d);
        let s2 = c.sq(sk);
        let q = c.mul(s2, r2);
        let q = c.kadd(1.0, q);
        let q = c.sq(q);
        let one = c.k(1.0);
        let term = c.div(one, q);
        f = c.add(f, term);
    }
    Ok(c.sub(f, t))
}

/// The Cauchy line-segment kernel of `hfConvLine.c` for segment `b → e`
/// with width `s`, at point `x`, added to `f`.
fn conv_segment(
    c: &mut C,
    f: NodeId,
    x: [NodeId; 3],
    b: [NodeId; 3],
    e: [NodeId; 3],
    s: NodeId,
) -> NodeId {
    let del = [c.sub(e[0], b[0]), c.sub(e[1], b[1]), c.sub(e[2], b[2])];
    let l = norm2(c, del);
    let l = c.sqrt(l);
    let ax = [c.div(del[0], l), c.div(del[1], l), c.div(del[2], l)];
    let d = [c.sub(x[0], b[0]), c.sub(x[1], b[1]), c.sub(x[2], b[2])];
    let xx = {
        let p0 = c.mul(d[0], ax[0]);
        let p1 = c.mul(d[1], ax[1]);
        let p2 = c.mul(d[2], ax[2]);
        let s01 = c.add(p0, p1);
        c.add(s01, p2)
    };
    let ss = c.sq(s);
    let dd = norm2(c, d);
    let xx2 = c.sq(xx);
    let p = {
        let t = c.sub(dd, xx2);
        let t = c.mul(ss, t);
        let t = c.kadd(1.0, t);
        c.sqrt(t)
    };
    let q = {
        let ll = c.sq(l);
        let t = c.add(dd, ll);
        let tl = c.kmul(2.0, l);
        let tl = c.mul(tl, xx);
        let t = c.sub(t, tl);
        let t = c.mul(ss, t);
        let t = c.kadd(1.0, t);
        c.sqrt(t)
    };
    let pp = c.sq(p);
    let two_pp = {
        let t = c.kmul(2.0, p);
        c.mul(t, p)
    };
    // xx / (2*p*p*(p*p + S*S*xx*xx))
    let t1 = {
        let u = c.mul(ss, xx);
        let u = c.mul(u, xx);
        let u = c.add(pp, u);
        let de = c.mul(two_pp, u);
        c.div(xx, de)
    };
    // (l - xx) / (2*p*p*q*q)
    let lmx = c.sub(l, xx);
    let t2 = {
        let de = c.mul(two_pp, q);
        let de = c.mul(de, q);
        c.div(lmx, de)
    };
    // (atan(S*xx/p) + atan(S*(l - xx)/p)) / (2*S*p*p*p)
    let t3 = {
        let u = c.mul(s, xx);
        let u = c.div(u, p);
        let u = c.atan(u);
        let v = c.mul(s, lmx);
        let v = c.div(v, p);
        let v = c.atan(v);
        let nu = c.add(u, v);
        let de = c.kmul(2.0, s);
        let de = c.mul(de, p);
        let de = c.mul(de, p);
        let de = c.mul(de, p);
        c.div(nu, de)
    };
    let sum = c.add(t1, t2);
    let sum = c.add(sum, t3);
    c.add(f, sum)
}

/// A [`LibError`] when the segment `b → e` is constant and of length 0.
fn check_segment(
    c: &mut C,
    b: [NodeId; 3],
    e: [NodeId; 3],
    arg: usize,
    func: &str,
    n: usize,
) -> Result<(), LibError> {
    let del = [c.sub(e[0], b[0]), c.sub(e[1], b[1]), c.sub(e[2], b[2])];
    let l = norm2(c, del);
    let l = c.sqrt(l);
    if c.g.const_value(l) == Some(0.0) {
        return Err(err(
            arg,
            format!(
                "{func}: the tips of segment {} take the same coordinates",
                n + 1
            ),
        ));
    }
    Ok(())
}

fn triple(v: &[NodeId], at: usize) -> [NodeId; 3] {
    [v[at], v[at + 1], v[at + 2]]
}

fn hf_conv_line(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 4)?;
    let s = array(args, 3)?;
    let n = s.len();
    let end = array_min(args, 2, 3 * n, "hfConvLine", "end")?;
    let begin = array_min(args, 1, 3 * n, "hfConvLine", "begin")?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    let mut f = c.k(0.0);
    for (k, &sk) in s.iter().enumerate() {
        let (b, e) = (triple(&begin, 3 * k), triple(&end, 3 * k));
        check_segment(&mut c, b, e, 2, "hfConvLine", k)?;
        f = conv_segment(&mut c, f, x, b, e, sk);
    }
    Ok(c.sub(f, t))
}

fn hf_conv_curve(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 3)?;
    let s = array(args, 2)?;
    let n = s.len();
    let v = array_min(args, 1, 3 * (n + 1), "hfConvCurve", "vect")?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    let mut f = c.k(0.0);
    for (k, &sk) in s.iter().enumerate() {
        let (b, e) = (triple(&v, 3 * k), triple(&v, 3 * (k + 1)));
        check_segment(&mut c, b, e, 1, "hfConvCurve", k)?;
        f = conv_segment(&mut c, f, x, b, e, sk);
    }
    Ok(c.sub(f, t))
}

fn hf_conv_line_r(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let r = scalar(args, 3)?;
    let end = array(args, 2)?;
    let n = end.len() / 3;
    let begin = array_min(args, 1, 3 * n, "hfConvLineR", "begin")?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    // S = 1; if (R < 1) S = 1/R
    let one = c.k(1.0);
    let small = c.lt(r, one);
    let inv = c.div(one, r);
    let s = c.sel(small, inv, one);
    let ss = c.sq(s);
    let rr = c.sq(r);
    let mut f = c.k(0.0);
    let mut tt = c.k(0.0);
    for k in 0..n {
        let (b, e) = (triple(&begin, 3 * k), triple(&end, 3 * k));
        let del = [c.sub(e[0], b[0]), c.sub(e[1], b[1]), c.sub(e[2], b[2])];
        let l = norm2(&mut c, del);
        let l = c.sqrt(l);
        let ax = [c.div(del[0], l), c.div(del[1], l), c.div(del[2], l)];
        let d = [c.sub(x[0], b[0]), c.sub(x[1], b[1]), c.sub(x[2], b[2])];
        let ll = c.sq(l);
        // pT = sqrt(1 + SQ(S)*SQ(R)); qT2 = 1 + SQ(S)*(SQ(R) + SQ(l))
        let pt = c.mul(ss, rr);
        let pt = c.kadd(1.0, pt);
        let pt = c.sqrt(pt);
        let qt2 = c.add(rr, ll);
        let qt2 = c.mul(ss, qt2);
        let qt2 = c.kadd(1.0, qt2);
        // T = l / (2.0*SQ(pT)*qT2) + (atan(S*l/pT)) / (2.0*S*SQ(pT)*pT)
        let ptp = c.sq(pt);
        let de = c.kmul(2.0, ptp);
        let de = c.mul(de, qt2);
        let a1 = c.div(l, de);
        let u = c.mul(s, l);
        let u = c.div(u, pt);
        let u = c.atan(u);
        let de = c.kmul(2.0, s);
        let de = c.mul(de, ptp);
        let de = c.mul(de, pt);
        let a2 = c.div(u, de);
        tt = c.add(a1, a2);
        let xx = {
            let p0 = c.mul(d[0], ax[0]);
            let p1 = c.mul(d[1], ax[1]);
            let p2 = c.mul(d[2], ax[2]);
            let s01 = c.add(p0, p1);
            c.add(s01, p2)
        };
        let dd = norm2(&mut c, d);
        let xx2 = c.sq(xx);
        // p = sqrt(1 + SQ(S)*(SQ(dx) + SQ(dy) + SQ(dz) - SQ(xx)))
        let p = c.sub(dd, xx2);
        let p = c.mul(ss, p);
        let p = c.kadd(1.0, p);
        let p = c.sqrt(p);
        // q2 = 1 + SQ(S)*(SQ(dx) + SQ(dy) + SQ(dz) + SQ(l) - 2.0*l*xx)
        let q2 = c.add(dd, ll);
        let tl = c.kmul(2.0, l);
        let tl = c.mul(tl, xx);
        let q2 = c.sub(q2, tl);
        let q2 = c.mul(ss, q2);
        let q2 = c.kadd(1.0, q2);
        let two_pp = c.kmul(2.0, p);
        let two_pp = c.mul(two_pp, p);
        let pp = c.sq(p);
        let t1 = {
            let u = c.mul(s, s);
            let u = c.mul(u, xx);
            let u = c.mul(u, xx);
            let u = c.add(pp, u);
            let de = c.mul(two_pp, u);
            c.div(xx, de)
        };
        let lmx = c.sub(l, xx);
        let t2 = {
            let de = c.mul(two_pp, q2);
            c.div(lmx, de)
        };
        let t3 = {
            let u = c.mul(s, xx);
            let u = c.div(u, p);
            let u = c.atan(u);
            let v = c.mul(s, lmx);
            let v = c.div(v, p);
            let v = c.atan(v);
            let nu = c.add(u, v);
            let de = c.kmul(2.0, s);
            let de = c.mul(de, p);
            let de = c.mul(de, p);
            let de = c.mul(de, p);
            c.div(nu, de)
        };
        let ftmp = c.add(t1, t2);
        let ftmp = c.add(ftmp, t3);
        // if (f < 1) { f = f + f_tmp; if (f > 1) f = 1; }
        let sum = c.add(f, ftmp);
        let over = c.gt(sum, one);
        let clamped = c.sel(over, one, sum);
        let below = c.lt(f, one);
        f = c.sel(below, clamped, f);
    }
    Ok(c.sub(f, tt))
}

/// Rotation coefficients of `hfConvArc.c` for the unit axis `(i, j, k)` and
/// `c = cos`, `s = sin` of the angle: applied to `v` as the C code does.
fn arc_rotate(c: &mut C, ijk: [NodeId; 3], cs: NodeId, sn: NodeId, v: [NodeId; 3]) -> [NodeId; 3] {
    let [i, j, k] = ijk;
    let one_c = c.ksub(1.0, cs);
    let ii = c.mul(i, i);
    let jj = c.mul(j, j);
    let kk = c.mul(k, k);
    let ij = c.mul(i, j);
    let jk = c.mul(j, k);
    let ki = c.mul(k, i);
    let is = c.mul(i, sn);
    let js = c.mul(j, sn);
    let ks = c.mul(k, sn);
    // base + prod * one_c
    let lin = |c: &mut C, base: NodeId, prod: NodeId| {
        let po = c.mul(prod, one_c);
        c.add(base, po)
    };
    let nks = c.neg(ks);
    let nis = c.neg(is);
    let njs = c.neg(js);
    let m = [
        [lin(c, cs, ii), lin(c, nks, ij), lin(c, js, ki)],
        [lin(c, ks, ij), lin(c, cs, jj), lin(c, nis, jk)],
        [lin(c, njs, ki), lin(c, is, jk), lin(c, cs, kk)],
    ];
    let mut out = [v[0]; 3];
    for (r, row) in m.iter().enumerate() {
        let a = c.mul(row[0], v[0]);
        let b = c.mul(row[1], v[1]);
        let s = c.add(a, b);
        let d = c.mul(row[2], v[2]);
        out[r] = c.add(s, d);
    }
    out
}

/// `f1 + f2` of `hfConvArc.c`: the arc of radius `r` over `[0, th]` (radians)
/// in the local frame, at the local point `(nx, ny, nz)`.
fn arc_kernel(c: &mut C, r: NodeId, s: NodeId, n: [NodeId; 3], th: NodeId) -> NodeId {
    let [nx, ny, nz] = n;
    let ss = c.sq(s);
    let rr = c.sq(r);
    // a = 2.0*r*S*S
    let a = c.kmul(2.0, r);
    let a = c.mul(a, s);
    let a = c.mul(a, s);
    let d2 = norm2(c, n);
    // b = 1.0 + SQ(r)*SQ(S) + SQ(S)*d2
    let rs = c.mul(rr, ss);
    let b = c.kadd(1.0, rs);
    let sd = c.mul(ss, d2);
    let b = c.add(b, sd);
    // p2 = -QU(r)*QU(S) + 2.0*SQ(r)*SQ(S)*(SQ(S)*(d2 - 2.0*SQ(z)) - 1.0) - SQ(1.0 + SQ(S)*d2)
    let qr = c.mul(rr, rr);
    let qr = c.neg(qr);
    let qs = c.mul(ss, ss);
    let p2a = c.mul(qr, qs);
    let m = c.kmul(2.0, rr);
    let m = c.mul(m, ss);
    let zz = c.sq(nz);
    let z2 = c.kmul(2.0, zz);
    let u = c.sub(d2, z2);
    let u = c.mul(ss, u);
    let one = c.k(1.0);
    let u = c.sub(u, one);
    let p2b = c.mul(m, u);
    let p2 = c.add(p2a, p2b);
    let w = c.kadd(1.0, sd);
    let w = c.sq(w);
    let p2 = c.sub(p2, w);
    // p1 = (p2 < 0.0) ? sqrt(-p2) : sqrt(p2)
    let zero = c.k(0.0);
    let negp = c.lt(p2, zero);
    let mp2 = c.neg(p2);
    let sm = c.sqrt(mp2);
    let sp = c.sqrt(p2);
    let p1 = c.sel(negp, sm, sp);
    let p3 = c.mul(p1, p2);
    let sin_th = c.sin(th);
    let cos_th = c.cos(th);
    // f1 = (b*y) / (x*p2*(a*x-b)) + (a*(SQ(x) + SQ(y))*sin(th) - b*y) / (x*p2*(a*(x*cos(th) + y*sin(th)) - b))
    let by = c.mul(b, ny);
    let xp2 = c.mul(nx, p2);
    let ax = c.mul(a, nx);
    let axb = c.sub(ax, b);
    let de1 = c.mul(xp2, axb);
    let f1a = c.div(by, de1);
    let xx = c.sq(nx);
    let yy = c.sq(ny);
    let xy = c.add(xx, yy);
    let nu = c.mul(a, xy);
    let nu = c.mul(nu, sin_th);
    let nu = c.sub(nu, by);
    let xc = c.mul(nx, cos_th);
    let ys = c.mul(ny, sin_th);
    let de = c.add(xc, ys);
    let de = c.mul(a, de);
    let de = c.sub(de, b);
    let de = c.mul(xp2, de);
    let f1b = c.div(nu, de);
    let f1 = c.add(f1a, f1b);
    // tan(th/2.0)
    let two = c.k(2.0);
    let half = c.div(th, two);
    let tn = c.tan(half);
    let ay = c.mul(a, ny);
    let axb2 = c.add(ax, b);
    let axbt = c.mul(axb2, tn);
    let two_b = c.kmul(2.0, b);
    // p2 < 0: 2.0*b*(atan(-a*y/p1) + atan((a*y - (a*x + b)*tan(th/2.0)) / p1)) / p3
    let f2n = {
        let na = c.neg(a);
        let u = c.mul(na, ny);
        let u = c.div(u, p1);
        let u = c.atan(u);
        let v = c.sub(ay, axbt);
        let v = c.div(v, p1);
        let v = c.atan(v);
        let s = c.add(u, v);
        let s = c.mul(two_b, s);
        c.div(s, p3)
    };
    // else: 2.0*b*(atanh(a*y/p1) + atanh(((a*x + b)*tan(th/2.0) - a*y) / p1)) / p3
    let f2p = {
        let u = c.div(ay, p1);
        let u = c.atanh(u);
        let v = c.sub(axbt, ay);
        let v = c.div(v, p1);
        let v = c.atanh(v);
        let s = c.add(u, v);
        let s = c.mul(two_b, s);
        c.div(s, p3)
    };
    let f2 = c.sel(negp, f2n, f2p);
    c.add(f1, f2)
}

fn hf_conv_arc(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 7)?;
    let s = array(args, 6)?;
    let n = s.len();
    let mut angle = array_min(args, 5, n, "hfConvArc", "angle")?;
    let axis = array_min(args, 4, 3 * n, "hfConvArc", "axis")?;
    let mut theta = array_min(args, 3, n, "hfConvArc", "theta")?;
    let radius = array_min(args, 2, n, "hfConvArc", "radius")?;
    let center = array_min(args, 1, 3 * n, "hfConvArc", "center")?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    let pi = c.k(ARC_PI);
    let k180 = c.k(180.0);
    let rd = c.div(pi, k180);
    let eps = c.k(EPS);
    let mut f = c.k(0.0);
    for m in 0..n {
        let ctr = triple(&center, 3 * m);
        let r = radius[m];
        angle[m] = c.add(angle[m], eps);
        let mut ijk = [
            c.add(axis[3 * m], eps),
            c.add(axis[3 * m + 1], eps),
            c.add(axis[3 * m + 2], eps),
        ];
        let length = norm2(&mut c, ijk);
        let length = c.sqrt(length);
        let short = c.lt(length, eps);
        let length = c.sel(short, eps, length);
        for a in &mut ijk {
            *a = c.div(*a, length);
        }
        let nang = c.neg(angle[m]);
        let ang = c.mul(rd, nang);
        let cs = c.cos(ang);
        let sn = c.sin(ang);
        // if (theta > 360) theta = 360
        let k360 = c.k(360.0);
        let big = c.gt(theta[m], k360);
        theta[m] = c.sel(big, k360, theta[m]);
        let d = [
            c.sub(x[0], ctr[0]),
            c.sub(x[1], ctr[1]),
            c.sub(x[2], ctr[2]),
        ];
        // the part beyond PI
        let over = c.gt(theta[m], k180);
        if c.g.const_value(over) != Some(0.0) {
            let ot = c.sub(theta[m], k180);
            let over_th = c.mul(ot, rd);
            let temp = arc_rotate(&mut c, ijk, cs, sn, d);
            let zero = c.k(0.0);
            let onek = c.k(1.0);
            let m180 = c.k(-180.0);
            let oa = c.mul(rd, m180);
            let oc = c.cos(oa);
            let os = c.sin(oa);
            let ov = arc_rotate(&mut c, [zero, zero, onek], oc, os, temp);
            let part = arc_kernel(&mut c, r, s[m], ov, over_th);
            let fo = c.add(f, part);
            f = c.sel(over, fo, f);
            theta[m] = c.sel(over, k180, theta[m]);
        }
        let th = c.mul(theta[m], rd);
        let nv = arc_rotate(&mut c, ijk, cs, sn, d);
        let part = arc_kernel(&mut c, r, s[m], nv, th);
        f = c.add(f, part);
    }
    set_array(args, 5, angle);
    set_array(args, 3, theta);
    Ok(c.sub(f, t))
}

/// One triangle of `hfConvTriangle.c` / `hfConvMesh.c`, added to `f`.
fn conv_triangle(c: &mut C, f: NodeId, x: [NodeId; 3], tri: [[NodeId; 3]; 3], s: NodeId) -> NodeId {
    let [mut a1, mut a2, mut a3] = tri;
    let len = |c: &mut C, p: [NodeId; 3], q: [NodeId; 3]| {
        let d = [c.sub(p[0], q[0]), c.sub(p[1], q[1]), c.sub(p[2], q[2])];
        let n = norm2(c, d);
        c.sqrt(n)
    };
    let l0 = len(c, a2, a1);
    let l1 = len(c, a3, a2);
    let l2 = len(c, a1, a3);
    // Reorder so that the longest edge is a1-a2.
    let c1a = c.ge(l1, l2);
    let c1b = c.gt(l1, l0);
    let c1 = c.and(c1a, c1b);
    let c2a = c.ge(l2, l1);
    let c2b = c.gt(l2, l0);
    let c2 = c.and(c2a, c2b);
    let (o1, o2, o3) = (a1, a2, a3);
    for k in 0..3 {
        // case 1: (a1, a2, a3) = (a2, a3, a1); case 2: (a3, a1, a2)
        let e1 = c.sel(c2, o3[k], o1[k]);
        a1[k] = c.sel(c1, o2[k], e1);
        let e2 = c.sel(c2, o1[k], o2[k]);
        a2[k] = c.sel(c1, o3[k], e2);
        let e3 = c.sel(c2, o2[k], o3[k]);
        a3[k] = c.sel(c1, o1[k], e3);
    }
    let l0 = len(c, a2, a1);
    let a21 = [
        c.sub(a2[0], a1[0]),
        c.sub(a2[1], a1[1]),
        c.sub(a2[2], a1[2]),
    ];
    let a13 = [
        c.sub(a1[0], a3[0]),
        c.sub(a1[1], a3[1]),
        c.sub(a1[2], a3[2]),
    ];
    let dot = |c: &mut C, u: [NodeId; 3], v: [NodeId; 3]| {
        let p0 = c.mul(u[0], v[0]);
        let p1 = c.mul(u[1], v[1]);
        let s = c.add(p0, p1);
        let p2 = c.mul(u[2], v[2]);
        c.add(s, p2)
    };
    // t = -(a21 . a13) / SQ(len[0])
    let t = dot(c, a21, a13);
    let t = c.neg(t);
    let l02 = c.sq(l0);
    let t = c.div(t, l02);
    let mut bp = [x[0]; 3];
    for k in 0..3 {
        let ta = c.mul(t, a21[k]);
        bp[k] = c.add(a1[k], ta);
    }
    let d = [c.sub(x[0], bp[0]), c.sub(x[1], bp[1]), c.sub(x[2], bp[2])];
    let unit = |c: &mut C, p: [NodeId; 3]| {
        let u = [c.sub(p[0], bp[0]), c.sub(p[1], bp[1]), c.sub(p[2], bp[2])];
        let n = norm2(c, u);
        let l = c.sqrt(n);
        [c.div(u[0], l), c.div(u[1], l), c.div(u[2], l)]
    };
    let uv = unit(c, a2);
    let vv = unit(c, a3);
    let d2 = norm2(c, d);
    let u = dot(c, d, uv);
    let v = dot(c, d, vv);
    let h = len(c, a3, bp);
    let a1l = len(c, a1, bp);
    let a2l = len(c, a2, bp);
    let g = c.sub(v, h);
    // m = a2*g + u*h; k = u*h - a1*g
    let a2g = c.mul(a2l, g);
    let uh = c.mul(u, h);
    let m = c.add(a2g, uh);
    let a1g = c.mul(a1l, g);
    let kk = c.sub(uh, a1g);
    // C2 = 1.0/(SQ(S)) + d2 - SQ(u)
    let ss = c.sq(s);
    let one = c.k(1.0);
    let c2 = c.div(one, ss);
    let c2 = c.add(c2, d2);
    let uu = c.sq(u);
    let c2 = c.sub(c2, uu);
    let cc = c.sqrt(c2);
    let vv2 = c.sq(v);
    let q = c.sub(c2, vv2);
    // w = C2 - 2.0*v*h + SQ(h)
    let tv = c.kmul(2.0, v);
    let tvh = c.mul(tv, h);
    let w = c.sub(c2, tvh);
    let hh = c.sq(h);
    let w = c.add(w, hh);
    // A2 = SQ(a1)*w + SQ(h)*(q + SQ(u)) - 2.0*a1*h*u*g
    let quu = c.add(q, uu);
    let hq = c.mul(hh, quu);
    let a1a1 = c.sq(a1l);
    let aw = c.mul(a1a1, w);
    let aa2 = c.add(aw, hq);
    let z = c.kmul(2.0, a1l);
    let z = c.mul(z, h);
    let z = c.mul(z, u);
    let z = c.mul(z, g);
    let aa2 = c.sub(aa2, z);
    let aa = c.sqrt(aa2);
    // B2 = SQ(a2)*w + SQ(h)*(q + SQ(u)) + 2.0*a2*h*u*g
    let a2a2 = c.sq(a2l);
    let bw = c.mul(a2a2, w);
    let bb2 = c.add(bw, hq);
    let z = c.kmul(2.0, a2l);
    let z = c.mul(z, h);
    let z = c.mul(z, u);
    let z = c.mul(z, g);
    let bb2 = c.add(bb2, z);
    let bb = c.sqrt(bb2);
    let n1 = c.add(a1l, u);
    let n2 = c.sub(a2l, u);
    let vh = c.mul(v, h);
    let n3 = c.mul(a1l, n1);
    let n3 = c.add(n3, vh);
    let gh = c.mul(g, h);
    let na1 = c.neg(a1l);
    let n4 = c.mul(na1, u);
    let n4 = c.sub(n4, gh);
    let na2 = c.neg(a2l);
    let n5 = c.mul(na2, n2);
    let n5 = c.sub(n5, vh);
    let n6 = c.mul(na2, u);
    let n6 = c.add(n6, gh);
    let arc = |c: &mut C, coef: NodeId, p: NodeId, q: NodeId, den: NodeId| {
        let a = c.div(p, den);
        let a = c.atan(a);
        let b = c.div(q, den);
        let b = c.atan(b);
        let s = c.add(a, b);
        let s = c.mul(coef, s);
        c.div(s, den)
    };
    let arc1 = arc(c, kk, n3, n4, aa);
    let arc2 = arc(c, m, n5, n6, bb);
    let arc3 = arc(c, v, n1, n2, cc);
    let sum = c.add(arc1, arc2);
    let sum = c.add(sum, arc3);
    let de = c.kmul(2.0, q);
    let de = c.mul(de, s);
    let term = c.div(sum, de);
    c.add(f, term)
}

fn hf_conv_triangle(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 3)?;
    let s = array(args, 2)?;
    let n = s.len();
    let v = array_min(args, 1, 9 * n, "hfConvTriangle", "vect")?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    let mut f = c.k(0.0);
    for (k, &sk) in s.iter().enumerate() {
        let tri = [
            triple(&v, 9 * k),
            triple(&v, 9 * k + 3),
            triple(&v, 9 * k + 6),
        ];
        f = conv_triangle(&mut c, f, x, tri, sk);
    }
    Ok(c.sub(f, t))
}

fn hf_conv_mesh(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let t = scalar(args, 4)?;
    let s = array(args, 3)?;
    let n = s.len();
    let tri = array_min(args, 2, 3 * n, "hfConvMesh", "tri")?;
    let v = array(args, 1)?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    let mut f = c.k(0.0);
    for (k, &sk) in s.iter().enumerate() {
        let mut corners = [[x[0]; 3]; 3];
        for (j, corner) in corners.iter_mut().enumerate() {
            let Some(iv) = c.g.const_value(tri[3 * k + j]) else {
                return Err(err(
                    2,
                    "hfConvMesh: triangle vertex indices must be constants".into(),
                ));
            };
            // C: 3*((int)tri - 1), truncating toward zero.
            let idx = iv.trunc();
            if !(idx >= 1.0 && 3.0 * idx <= v.len() as f64) {
                return Err(err(
                    2,
                    format!(
                        "hfConvMesh: vertex index {iv} out of range 1..{}",
                        v.len() / 3
                    ),
                ));
            }
            *corner = triple(&v, 3 * (idx as usize - 1));
        }
        f = conv_triangle(&mut c, f, x, corners, sk);
    }
    Ok(c.sub(f, t))
}

fn hf_noise_g(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (a1, a2, phase) = (scalar(args, 1)?, scalar(args, 2)?, scalar(args, 3)?);
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL));
    };
    let a2v = [c.mul(a2, x[0]), c.mul(a2, x[1]), c.mul(a2, x[2])];
    let sv = [c.sin(a2v[0]), c.sin(a2v[1]), c.sin(a2v[2])];
    let k117 = c.k(1.17);
    let a1d = c.div(a1, k117);
    let k135 = c.k(1.35);
    // sx2 uses sz, sy2 uses sx, sz2 uses sy
    let partner = [sv[2], sv[0], sv[1]];
    let mut ser = [x[0]; 3];
    for k in 0..3 {
        let u = c.div(a2v[k], k135);
        let ps = c.mul(phase, partner[k]);
        let u = c.add(u, ps);
        let u = c.sin(u);
        let s2 = c.mul(a1d, u);
        let a1s = c.mul(a1, sv[k]);
        ser[k] = c.add(a1s, s2);
    }
    let ss = c.mul(ser[0], ser[1]);
    Ok(c.mul(ss, ser[2]))
}

// ---------------------------------------------------------------------------
// Operations

fn blend(g: &mut Graph, args: &[LibArg], op: BlendOp) -> Result<NodeId, LibError> {
    let mut v = [NodeId(0); 5];
    for (i, slot) in v.iter_mut().enumerate() {
        *slot = scalar(args, i)?;
    }
    Ok(g.blend(op, v))
}

fn hf_blend_uni(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    blend(g, args, BlendOp::Union)
}

fn hf_blend_int(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    blend(g, args, BlendOp::Inter)
}

// ---------------------------------------------------------------------------
// Transformations

/// The array to transform (argument 0), which must have at least 3 items.
fn xt_arg(args: &[LibArg], func: &str) -> Result<Vec<NodeId>, LibError> {
    array_min(args, 0, 3, func, "xt")
}

fn hf_scale3d(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, "hfScale3D")?;
    for (k, v) in xt.iter_mut().take(3).enumerate() {
        let s = scalar(args, 1 + k)?;
        *v = c.div(*v, s);
    }
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

fn hf_shift3d(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, "hfShift3D")?;
    for (k, v) in xt.iter_mut().take(3).enumerate() {
        let s = scalar(args, 1 + k)?;
        *v = c.sub(*v, s);
    }
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

/// Rotates the pair `(xt[p], xt[q])` by `theta`:
/// `(p*ct + q*st, -p*st + q*ct)`.
fn rotate_pair(c: &mut C, xt: &mut [NodeId], p: usize, q: usize, theta: NodeId) {
    let ct = c.cos(theta);
    let st = c.sin(theta);
    let a = c.mul(xt[p], ct);
    let b = c.mul(xt[q], st);
    let pr = c.add(a, b);
    let np = c.neg(xt[p]);
    let a = c.mul(np, st);
    let b = c.mul(xt[q], ct);
    let qr = c.add(a, b);
    xt[p] = pr;
    xt[q] = qr;
}

/// The rotated pair of each axis: X rotates (y, z), Y (z, x), Z (x, y).
fn rot_pair(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (2, 0),
        _ => (0, 1),
    }
}

fn rotate3d(
    g: &mut Graph,
    args: &mut [LibArg],
    axis: usize,
    func: &str,
) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, func)?;
    let theta = scalar(args, 1)?;
    let (p, q) = rot_pair(axis);
    rotate_pair(&mut c, &mut xt, p, q, theta);
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

fn hf_rotate3d_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    rotate3d(g, args, 0, "hfRotate3DX")
}
fn hf_rotate3d_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    rotate3d(g, args, 1, "hfRotate3DY")
}
fn hf_rotate3d_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    rotate3d(g, args, 2, "hfRotate3DZ")
}

fn twist(g: &mut Graph, args: &mut [LibArg], axis: usize, func: &str) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, func)?;
    let (x1, x2) = (scalar(args, 1)?, scalar(args, 2)?);
    let (th1, th2) = (scalar(args, 3)?, scalar(args, 4)?);
    // t = (xt - x1)/(x2 - x1); theta = (1-t)*theta1 + t*theta2
    let nu = c.sub(xt[axis], x1);
    let de = c.sub(x2, x1);
    let t = c.div(nu, de);
    let omt = c.ksub(1.0, t);
    let a = c.mul(omt, th1);
    let b = c.mul(t, th2);
    let theta = c.add(a, b);
    let (p, q) = rot_pair(axis);
    rotate_pair(&mut c, &mut xt, p, q, theta);
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

fn hf_twist_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    twist(g, args, 0, "hfTwistX")
}
fn hf_twist_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    twist(g, args, 1, "hfTwistY")
}
fn hf_twist_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    twist(g, args, 2, "hfTwistZ")
}

fn taper(g: &mut Graph, args: &mut [LibArg], axis: usize, func: &str) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, func)?;
    let (x1, x2) = (scalar(args, 1)?, scalar(args, 2)?);
    let (s1, s2) = (scalar(args, 3)?, scalar(args, 4)?);
    let v = xt[axis];
    let nu = c.sub(v, x1);
    let de = c.sub(x2, x1);
    let t = c.div(nu, de);
    let omt = c.ksub(1.0, t);
    let a = c.mul(omt, s1);
    let b = c.mul(t, s2);
    let lerp = c.add(a, b);
    let above = c.gt(v, x2);
    let upper = c.sel(above, s2, lerp);
    let below = c.lt(v, x1);
    let scale = c.sel(below, s1, upper);
    let tiny = c.tiny(scale);
    let one = c.k(1.0);
    let scale = c.sel(tiny, one, scale);
    // X scales (y, z), Y scales (z, x), Z scales (x, y)
    let (p, q) = rot_pair(axis);
    xt[p] = c.div(xt[p], scale);
    xt[q] = c.div(xt[q], scale);
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

fn hf_taper_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    taper(g, args, 0, "hfTaperX")
}
fn hf_taper_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    taper(g, args, 1, "hfTaperY")
}
fn hf_taper_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    taper(g, args, 2, "hfTaperZ")
}

fn hf_stretch3d(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, "hfStretch3D")?;
    let x0 = array_min(args, 1, 3, "hfStretch3D", "x0")?;
    for k in 0..3 {
        let s = scalar(args, 2 + k)?;
        let d = c.sub(xt[k], x0[k]);
        let d = c.div(d, s);
        xt[k] = c.add(x0[k], d);
    }
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

fn space_map(
    g: &mut Graph,
    args: &mut [LibArg],
    cubic: bool,
    func: &str,
) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let from = array(args, 1)?;
    let n = from.len();
    if n % 3 != 0 {
        return Err(err(
            1,
            format!("{func}: the source array's size ({n}) is not a multiple of 3"),
        ));
    }
    let to = array_min(args, 2, n, func, "target")?;
    let ratio = array_min(args, 3, n, func, "b")?;
    let mut xt = xt_arg(args, func)?;
    for i in (0..n).step_by(3) {
        let mut dt = [xt[0]; 3];
        let mut u = [xt[0]; 3];
        for k in 0..3 {
            dt[k] = c.sub(to[i + k], from[i + k]);
            let nu = c.sub(xt[k], to[i + k]);
            let d2 = c.sq(dt[k]);
            let ad = c.sqrt(d2);
            let de = c.kadd(1.0, ad);
            let de = c.mul(ratio[i + k], de);
            let q = c.div(nu, de);
            u[k] = c.sq(q);
        }
        let s = c.add(u[0], u[1]);
        let s = c.add(s, u[2]);
        if cubic {
            let tmp = c.sqrt(s);
            let om = c.ksub(1.0, tmp);
            let w = c.mul(om, om);
            let w = c.mul(w, om);
            let op = c.kadd(1.0, tmp);
            let w = c.div(w, op);
            let one = c.k(1.0);
            let inside = c.le(tmp, one);
            for k in 0..3 {
                let m = c.mul(w, dt[k]);
                let moved = c.sub(xt[k], m);
                xt[k] = c.sel(inside, moved, xt[k]);
            }
        } else {
            let ns = c.neg(s);
            let w = c.exp(ns);
            for k in 0..3 {
                let m = c.mul(w, dt[k]);
                xt[k] = c.sub(xt[k], m);
            }
        }
    }
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

fn hf_space_map_exp(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    space_map(g, args, false, "hfSpaceMapExp")
}
fn hf_space_map_cubic(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    space_map(g, args, true, "hfSpaceMapCubic")
}

// ---------------------------------------------------------------------------
// Attributes

fn hfa_set_color(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let f = scalar(args, 0)?;
    let mut s = array_min(args, 1, 3, "hfA_SetColor", "s")?;
    let zero = c.k(0.0);
    let inside = c.ge(f, zero);
    for (k, item) in s.iter_mut().take(3).enumerate() {
        let v = scalar(args, 2 + k)?;
        *item = c.sel(inside, v, *item);
    }
    set_array(args, 1, s);
    Ok(c.k(1.0))
}

fn hfa_set_attributes(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let f = scalar(args, 0)?;
    let mut s = array(args, 1)?;
    let s1 = array(args, 2)?;
    let zero = c.k(0.0);
    let inside = c.ge(f, zero);
    for (dst, &src) in s.iter_mut().zip(&s1) {
        *dst = c.sel(inside, src, *dst);
    }
    set_array(args, 1, s);
    Ok(c.k(1.0))
}

// ---------------------------------------------------------------------------
// Distance primitives

fn dcone(g: &mut Graph, args: &[LibArg], axis: usize, func: &str) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let r = scalar(args, 2)?;
    let Some(d) = centred(args, &mut c, func)? else {
        return Ok(c.k(SENTINEL_DCONE));
    };
    let t = c.atan(r);
    // X: sqrt(z*z+y*y); Y: sqrt(z*z+xx*xx); Z: sqrt(xx*xx+y*y)
    let (p, q) = match axis {
        0 => (2, 1),
        1 => (2, 0),
        _ => (0, 1),
    };
    let a = c.sq(d[p]);
    let b = c.sq(d[q]);
    let rho = c.add(a, b);
    let rho = c.sqrt(rho);
    let ct = c.cos(t);
    let u = c.mul(rho, ct);
    let h = c.abs(d[axis]);
    let st = c.sin(t);
    let v = c.mul(h, st);
    let dist = c.sub(u, v);
    Ok(c.neg(dist))
}

fn hf_dcone_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    dcone(g, args, 0, "hfDConeX")
}
fn hf_dcone_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    dcone(g, args, 1, "hfDConeY")
}
fn hf_dcone_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    dcone(g, args, 2, "hfDConeZ")
}

fn hf_dcylinder(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let r = scalar(args, 3)?;
    let u = array_min(args, 2, 3, "hfDCylinder", "u")?;
    let center = array_min(args, 1, 3, "hfDCylinder", "center")?;
    let Some(x) = point(args)? else {
        return Ok(c.k(SENTINEL_DCYL));
    };
    let mut x21 = [x[0]; 3];
    let mut x10 = [x[0]; 3];
    for k in 0..3 {
        let x2 = c.add(center[k], u[k]);
        x21[k] = c.sub(x2, center[k]);
        x10[k] = c.sub(center[k], x[k]);
    }
    let cross = |c: &mut C, i: usize, j: usize| {
        // x21[i]*x10[j] - x10[i]*x21[j]
        let a = c.mul(x21[i], x10[j]);
        let b = c.mul(x10[i], x21[j]);
        c.sub(a, b)
    };
    // cp0 = x21[1]*x10[2] - x10[1]*x21[2]; cp1 = x21[2]*x10[0] - x21[0]*x10[2];
    // cp2 = x21[0]*x10[1] - x21[1]*x10[0]
    let cp0 = cross(&mut c, 1, 2);
    let cp1 = {
        let a = c.mul(x21[2], x10[0]);
        let b = c.mul(x21[0], x10[2]);
        c.sub(a, b)
    };
    let cp2 = {
        let a = c.mul(x21[0], x10[1]);
        let b = c.mul(x21[1], x10[0]);
        c.sub(a, b)
    };
    let d1 = norm2(&mut c, [cp0, cp1, cp2]);
    let d2 = norm2(&mut c, x21);
    let d = c.div(d1, d2);
    let d = c.sqrt(d);
    Ok(c.sub(r, d))
}

fn dtorus(g: &mut Graph, args: &[LibArg], axis: usize, func: &str) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (big_r, r0) = (scalar(args, 2)?, scalar(args, 3)?);
    let [xx, y, z] = centred_or_sentinel!(args, c, func);
    // X: sqrt(y*y+z*z), then with xx; Y: sqrt(xx*xx + z*z), then y;
    // Z: sqrt(xx*xx + y*y), then z.
    let (p, q, a) = match axis {
        0 => (y, z, xx),
        1 => (xx, z, y),
        _ => (xx, y, z),
    };
    let pp = c.sq(p);
    let qq = c.sq(q);
    let s = c.add(pp, qq);
    let s = c.sqrt(s);
    let s = c.sub(s, big_r);
    let s2 = c.sq(s);
    let aa = c.sq(a);
    let t = c.add(s2, aa);
    let t = c.sqrt(t);
    let t = c.sub(t, r0);
    Ok(c.neg(t))
}

fn hf_dtorus_x(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    dtorus(g, args, 0, "hfDTorusX")
}
fn hf_dtorus_y(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    dtorus(g, args, 1, "hfDTorusY")
}
fn hf_dtorus_z(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    dtorus(g, args, 2, "hfDTorusZ")
}

#[cfg(test)]
#[path = "library_tests.rs"]
mod tests;
