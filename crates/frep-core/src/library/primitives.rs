//! Primitives of the library: spheres, tori, cylinders, cones, blocks,
//! superellipsoids, blobs, metaballs, soft objects and `hfNoiseG`.
//!
//! Each builder follows its C file's operation order, so constant folding
//! gives the reference's bits.

use super::build::*;
use super::{LibArg, LibError, SENTINEL};
use crate::graph::{Graph, NodeId};
use crate::ops::BinaryOp;

pub(super) fn hf_sphere(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hf_ellipsoid(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

/// `hfTorusX/Y/Z`: a torus around `axis`. Under the root is the sum of the
/// two squares across the axis, added in each C file's order.
pub(super) fn torus(
    g: &mut Graph,
    args: &mut [LibArg],
    axis: usize,
    func: &str,
) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let (big_r, r0) = (scalar(args, 2)?, scalar(args, 3)?);
    let d = centred_or_sentinel!(args, c, func);
    let sq = d.map(|v| c.sq(v));
    let (p, q) = [(2, 1), (2, 0), (0, 1)][axis];
    let s = c.add(sq[p], sq[q]);
    Ok(torus_tail(&mut c, r0, big_r, sq, s))
}

/// Elliptic cylinder along axis `skip`: `1 - (d_i/a)^2 - (d_j/b)^2`.
pub(super) fn ell_cyl(
    g: &mut Graph,
    args: &[LibArg],
    skip: usize,
    func: &str,
) -> Result<NodeId, LibError> {
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

pub(super) fn other_axes(axis: usize) -> (usize, usize) {
    match axis {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    }
}

/// Circular cylinder along axis `skip`: `R*R - d_i^2 - d_j^2`.
pub(super) fn cylinder(
    g: &mut Graph,
    args: &[LibArg],
    skip: usize,
    func: &str,
) -> Result<NodeId, LibError> {
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

/// (Elliptic) cone along `axis`: `d_axis^2 - (d_i/a)^2 - (d_j/b)^2`, where
/// the circular cone passes `a = b = R` (argument 2 twice).
pub(super) fn cone(
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

pub(super) fn hf_block(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hf_superell(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

/// The point array of the blob primitives: only its first 3 items are read
/// (the C code does not check its size).
fn blob_point(args: &[LibArg], func: &str) -> Result<Vec<NodeId>, LibError> {
    array_min(args, 0, 3, func, "x")
}

pub(super) fn hf_blobby(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hf_metaball(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hf_soft(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hf_noise_g(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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
