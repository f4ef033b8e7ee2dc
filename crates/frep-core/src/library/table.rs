//! The table of library functions: names, parameters and one-line docs.
//!
//! - Each row names the builder that ports the C function.
//! - Editors complete from it; `tests/library_table.rs` writes it to
//!   `web/src/editor/library.json`.
//! - It is flat data, so it stays one long static.

use super::attributes::*;
use super::blends::*;
use super::conv_arc::*;
use super::conv_triangle::*;
use super::convolution::*;
use super::distance::*;
use super::primitives::*;
use super::transformations::*;
use super::{LibFn, ParamKind};
use crate::ops::BlendOp;

const S: ParamKind = ParamKind::Scalar;
const A: ParamKind = ParamKind::Array;

macro_rules! lib {
    ($name:literal, $display:literal, [$($k:ident $p:literal),*], $f:expr, $doc:literal) => {
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

pub(super) static ALL: &[LibFn] = &[
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
        |g, args| torus(g, args, 2, "hfTorusZ"),
        "Torus around an axis parallel to z: major radius R, minor radius r0."
    ),
    lib!(
        "hftorusx",
        "hfTorusX",
        [A "x", A "center", S "R", S "r0"],
        |g, args| torus(g, args, 0, "hfTorusX"),
        "Torus around an axis parallel to x: major radius R, minor radius r0."
    ),
    lib!(
        "hftorusy",
        "hfTorusY",
        [A "x", A "center", S "R", S "r0"],
        |g, args| torus(g, args, 1, "hfTorusY"),
        "Torus around an axis parallel to y: major radius R, minor radius r0."
    ),
    lib!(
        "hfellcylx",
        "hfEllCylX",
        [A "x", A "center", S "a", S "b"],
        |g, args| ell_cyl(g, args, 0, "hfEllCylX"),
        "Infinite elliptic cylinder along x with semi-axes a, b."
    ),
    lib!(
        "hfellcyly",
        "hfEllCylY",
        [A "x", A "center", S "a", S "b"],
        |g, args| ell_cyl(g, args, 1, "hfEllCylY"),
        "Infinite elliptic cylinder along y with semi-axes a, b."
    ),
    lib!(
        "hfellcylz",
        "hfEllCylZ",
        [A "x", A "center", S "a", S "b"],
        |g, args| ell_cyl(g, args, 2, "hfEllCylZ"),
        "Infinite elliptic cylinder along z with semi-axes a, b."
    ),
    lib!(
        "hfcylinderx",
        "hfCylinderX",
        [A "x", A "center", S "R"],
        |g, args| cylinder(g, args, 0, "hfCylinderX"),
        "Infinite circular cylinder along x of radius R."
    ),
    lib!(
        "hfcylindery",
        "hfCylinderY",
        [A "x", A "center", S "R"],
        |g, args| cylinder(g, args, 1, "hfCylinderY"),
        "Infinite circular cylinder along y of radius R."
    ),
    lib!(
        "hfcylinderz",
        "hfCylinderZ",
        [A "x", A "center", S "R"],
        |g, args| cylinder(g, args, 2, "hfCylinderZ"),
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
        |g, args| rotate3d(g, args, 2, "hfRotate3DZ"),
        "Rotates the coordinates xt around z by theta radians."
    ),
    lib!(
        "hfrotate3dy",
        "hfRotate3DY",
        [A "xt", S "theta"],
        |g, args| rotate3d(g, args, 1, "hfRotate3DY"),
        "Rotates the coordinates xt around y by theta radians."
    ),
    lib!(
        "hfrotate3dx",
        "hfRotate3DX",
        [A "xt", S "theta"],
        |g, args| rotate3d(g, args, 0, "hfRotate3DX"),
        "Rotates the coordinates xt around x by theta radians."
    ),
    lib!(
        "hfblenduni",
        "hfBlendUni",
        [S "f1", S "f2", S "a0", S "a1", S "a2"],
        |g, args| blend(g, args, BlendOp::Union),
        "Blending union of f1 and f2: displacement a0, shape a1, a2."
    ),
    lib!(
        "hfblendint",
        "hfBlendInt",
        [S "f1", S "f2", S "a0", S "a1", S "a2"],
        |g, args| blend(g, args, BlendOp::Inter),
        "Blending intersection of f1 and f2: displacement a0, shape a1, a2."
    ),
    lib!(
        "hftwistz",
        "hfTwistZ",
        [A "xt", S "z1", S "z2", S "theta1", S "theta2"],
        |g, args| twist(g, args, 2, "hfTwistZ"),
        "Twists xt around z from angle theta1 at z1 to theta2 at z2."
    ),
    lib!(
        "hftwisty",
        "hfTwistY",
        [A "xt", S "y1", S "y2", S "theta1", S "theta2"],
        |g, args| twist(g, args, 1, "hfTwistY"),
        "Twists xt around y from angle theta1 at y1 to theta2 at y2."
    ),
    lib!(
        "hftwistx",
        "hfTwistX",
        [A "xt", S "x1", S "x2", S "theta1", S "theta2"],
        |g, args| twist(g, args, 0, "hfTwistX"),
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
        |g, args| taper(g, args, 2, "hfTaperZ"),
        "Tapers xt along z: scale s1 at z1 to s2 at z2."
    ),
    lib!(
        "hftapery",
        "hfTaperY",
        [A "xt", S "y1", S "y2", S "s1", S "s2"],
        |g, args| taper(g, args, 1, "hfTaperY"),
        "Tapers xt along y: scale s1 at y1 to s2 at y2."
    ),
    lib!(
        "hftaperx",
        "hfTaperX",
        [A "xt", S "x1", S "x2", S "s1", S "s2"],
        |g, args| taper(g, args, 0, "hfTaperX"),
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
        |g, args| cone(g, args, 0, false, "hfConeX"),
        "Infinite circular cone along x, apex at center, slope R."
    ),
    lib!(
        "hfconey",
        "hfConeY",
        [A "x", A "center", S "R"],
        |g, args| cone(g, args, 1, false, "hfConeY"),
        "Infinite circular cone along y, apex at center, slope R."
    ),
    lib!(
        "hfconez",
        "hfConeZ",
        [A "x", A "center", S "R"],
        |g, args| cone(g, args, 2, false, "hfConeZ"),
        "Infinite circular cone along z, apex at center, slope R."
    ),
    lib!(
        "hfellconex",
        "hfEllConeX",
        [A "x", A "center", S "a", S "b"],
        |g, args| cone(g, args, 0, true, "hfEllConeX"),
        "Infinite elliptic cone along x, apex at center, slopes a, b."
    ),
    lib!(
        "hfellconey",
        "hfEllConeY",
        [A "x", A "center", S "a", S "b"],
        |g, args| cone(g, args, 1, true, "hfEllConeY"),
        "Infinite elliptic cone along y, apex at center, slopes a, b."
    ),
    lib!(
        "hfellconez",
        "hfEllConeZ",
        [A "x", A "center", S "a", S "b"],
        |g, args| cone(g, args, 2, true, "hfEllConeZ"),
        "Infinite elliptic cone along z, apex at center, slopes a, b."
    ),
    lib!(
        "hfspacemapcubic",
        "hfSpaceMapCubic",
        [A "xt", A "source", A "target", A "b"],
        |g, args| space_map(g, args, true, "hfSpaceMapCubic"),
        "Space mapping moving the points source to target with cubic falloff b."
    ),
    lib!(
        "hfspacemapexp",
        "hfSpaceMapExp",
        [A "xt", A "source", A "target", A "b"],
        |g, args| space_map(g, args, false, "hfSpaceMapExp"),
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
        |g, args| dcone(g, args, 0, "hfDConeX"),
        "Distance-based cone along x, apex at center, slope R."
    ),
    lib!(
        "hfdconey",
        "hfDConeY",
        [A "x", A "center", S "R"],
        |g, args| dcone(g, args, 1, "hfDConeY"),
        "Distance-based cone along y, apex at center, slope R."
    ),
    lib!(
        "hfdconez",
        "hfDConeZ",
        [A "x", A "center", S "R"],
        |g, args| dcone(g, args, 2, "hfDConeZ"),
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
        |g, args| dtorus(g, args, 0, "hfDTorusX"),
        "Distance-based torus around x: major radius R, minor radius r0."
    ),
    lib!(
        "hfdtorusy",
        "hfDTorusY",
        [A "x", A "center", S "R", S "r0"],
        |g, args| dtorus(g, args, 1, "hfDTorusY"),
        "Distance-based torus around y: major radius R, minor radius r0."
    ),
    lib!(
        "hfdtorusz",
        "hfDTorusZ",
        [A "x", A "center", S "R", S "r0"],
        |g, args| dtorus(g, args, 2, "hfDTorusZ"),
        "Distance-based torus around z: major radius R, minor radius r0."
    ),
];
