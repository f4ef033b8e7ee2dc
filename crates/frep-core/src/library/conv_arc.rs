//! `hfConvArc`: the Cauchy kernel integrated over circular arcs.
//!
//! The integral runs over the arc's *angle*, not its length: it is `r`
//! times smaller. It is singular (NaN) where the point's local x coordinate
//! is 0, as in C.
//!
//! `tan` and `atanh` have no IEEE graph operation. They are built from the
//! checked ones behind selects that keep them error-free:
//! - `tan` is `sin/cos` where `|cos| < 1e-6`, a value within a few ulps of
//!   libm's;
//! - `log` is NaN or `-inf` outside its domain, like C's.

use super::build::*;
use super::{LibArg, LibError, SENTINEL};
use crate::graph::{Graph, NodeId};
use crate::ops::EPS;

/// `PI` of `hfConvArc.c` (deliberately the truncated value).
#[allow(clippy::approx_constant)]
const ARC_PI: f64 = 3.141592;

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

pub(super) fn hf_conv_arc(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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
