//! `hfConvTriangle` and `hfConvMesh`: the Cauchy kernel integrated over
//! triangles.
//!
//! Each triangle is split at the foot of its longest side into two right
//! triangles with a closed-form integral; the result is `S³` times the area
//! integral.

use super::build::*;
use super::{LibArg, LibError, SENTINEL};
use crate::graph::{Graph, NodeId};

/// `|p − q|`.
fn edge_len(c: &mut C, p: [NodeId; 3], q: [NodeId; 3]) -> NodeId {
    let d = [c.sub(p[0], q[0]), c.sub(p[1], q[1]), c.sub(p[2], q[2])];
    let n = norm2(c, d);
    c.sqrt(n)
}

/// `u · v`, in the C code's order.
fn dot(c: &mut C, u: [NodeId; 3], v: [NodeId; 3]) -> NodeId {
    let p0 = c.mul(u[0], v[0]);
    let p1 = c.mul(u[1], v[1]);
    let s = c.add(p0, p1);
    let p2 = c.mul(u[2], v[2]);
    c.add(s, p2)
}

/// The corners reordered so that the longest edge is `a1-a2`, with
/// selects (the corners need not be constants).
fn longest_first(c: &mut C, tri: [[NodeId; 3]; 3]) -> [[NodeId; 3]; 3] {
    let [mut a1, mut a2, mut a3] = tri;
    let l0 = edge_len(c, a2, a1);
    let l1 = edge_len(c, a3, a2);
    let l2 = edge_len(c, a1, a3);

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
    [a1, a2, a3]
}

/// The triangle in the frame of the foot `bp` of `a3` on the edge `a1-a2`.
#[derive(Clone, Copy)]
struct Frame {
    /// `|x − bp|²`.
    d2: NodeId,
    /// `x − bp` along `a2 − bp` and along `a3 − bp`.
    u: NodeId,
    v: NodeId,
    /// The height `|a3 − bp|` and the parts `|a1 − bp|`, `|a2 − bp|` of
    /// the longest edge.
    h: NodeId,
    a1l: NodeId,
    a2l: NodeId,
    /// `v − h`.
    g: NodeId,
}

/// [`Frame`] of point `x` for the corners `a1, a2, a3` (longest edge first).
fn foot_frame(c: &mut C, x: [NodeId; 3], [a1, a2, a3]: [[NodeId; 3]; 3]) -> Frame {
    let l0 = edge_len(c, a2, a1);
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
    let h = edge_len(c, a3, bp);
    let a1l = edge_len(c, a1, bp);
    let a2l = edge_len(c, a2, bp);
    let g = c.sub(v, h);
    Frame {
        d2,
        u,
        v,
        h,
        a1l,
        a2l,
        g,
    }
}

/// The closed form of `hfConvTriangle.c` in the foot's frame, for width `s`.
fn frame_integral(c: &mut C, fr: Frame, s: NodeId) -> NodeId {
    let Frame {
        d2,
        u,
        v,
        h,
        a1l,
        a2l,
        g,
    } = fr;
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
    c.div(sum, de)
}

/// One triangle of `hfConvTriangle.c` / `hfConvMesh.c`, added to `f`.
pub(super) fn conv_triangle(
    c: &mut C,
    f: NodeId,
    x: [NodeId; 3],
    tri: [[NodeId; 3]; 3],
    s: NodeId,
) -> NodeId {
    let tri = longest_first(c, tri);
    let frame = foot_frame(c, x, tri);
    let term = frame_integral(c, frame, s);
    c.add(f, term)
}

pub(super) fn hf_conv_triangle(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hf_conv_mesh(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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
