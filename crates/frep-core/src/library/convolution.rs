//! Convolution surfaces of points and line segments (`hfConvPoint`,
//! `hfConvLine`, `hfConvCurve`, `hfConvLineR`).
//!
//! The kernel is Cauchy's `1 / (1 + S²r²)²`. `hfConvLine` and `hfConvCurve`
//! integrate it along each segment's length. That integral has a closed
//! form: two rational terms and a sum of two arc tangents. `hfConvLineR`
//! uses the same form with its own middle term, then clamps the sum at 1.

use super::build::*;
use super::{LibArg, LibError, SENTINEL};
use crate::graph::{Graph, NodeId};

pub(super) fn hf_conv_point(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

/// The axis of segment `b → e`: its length `l` and its unit direction.
fn segment_axis(c: &mut C, b: [NodeId; 3], e: [NodeId; 3]) -> (NodeId, [NodeId; 3]) {
    let del = [c.sub(e[0], b[0]), c.sub(e[1], b[1]), c.sub(e[2], b[2])];
    let l = norm2(c, del);
    let l = c.sqrt(l);
    let ax = [c.div(del[0], l), c.div(del[1], l), c.div(del[2], l)];
    (l, ax)
}

/// How the middle term's denominator uses `q2 = 1 + S²(|d|² + l² − 2 l xx)`.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Q {
    /// `2p²·q·q` with `q = sqrt(q2)`, as `hfConvLine.c` writes it.
    Rooted,
    /// `2p²·q2`, as `hfConvLineR.c` writes it.
    Plain,
}

/// The Cauchy kernel integrated along the segment from `b` of length `l`
/// and unit axis `ax`, at point `x`, with width `s` (`ss = s·s`).
///
/// Both C files share this closed form; they differ only in the middle
/// term's denominator, which `q` picks so that each keeps its own bits.
#[allow(clippy::too_many_arguments)] // The C formula's own inputs.
fn line_integral(
    c: &mut C,
    x: [NodeId; 3],
    b: [NodeId; 3],
    (l, ax): (NodeId, [NodeId; 3]),
    s: NodeId,
    ss: NodeId,
    q: Q,
) -> NodeId {
    let d = [c.sub(x[0], b[0]), c.sub(x[1], b[1]), c.sub(x[2], b[2])];
    let xx = {
        let p0 = c.mul(d[0], ax[0]);
        let p1 = c.mul(d[1], ax[1]);
        let p2 = c.mul(d[2], ax[2]);
        let s01 = c.add(p0, p1);
        c.add(s01, p2)
    };
    let dd = norm2(c, d);
    let xx2 = c.sq(xx);
    // p = sqrt(1 + S²(|d|² − xx²))
    let p = {
        let t = c.sub(dd, xx2);
        let t = c.mul(ss, t);
        let t = c.kadd(1.0, t);
        c.sqrt(t)
    };
    // q2 = 1 + S²(|d|² + l² − 2 l xx)
    let q2 = {
        let ll = c.sq(l);
        let t = c.add(dd, ll);
        let tl = c.kmul(2.0, l);
        let tl = c.mul(tl, xx);
        let t = c.sub(t, tl);
        let t = c.mul(ss, t);
        c.kadd(1.0, t)
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
    // (l - xx) / (2*p*p*q*q), or / (2*p*p*q2)
    let lmx = c.sub(l, xx);
    let t2 = {
        let de = match q {
            Q::Rooted => {
                let q = c.sqrt(q2);
                let de = c.mul(two_pp, q);
                c.mul(de, q)
            }
            Q::Plain => c.mul(two_pp, q2),
        };
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
    c.add(sum, t3)
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
    let axis = segment_axis(c, b, e);
    let ss = c.sq(s);
    let sum = line_integral(c, x, b, axis, s, ss, Q::Rooted);
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
    let (l, _) = segment_axis(c, b, e);
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

pub(super) fn hf_conv_line(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hf_conv_curve(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hf_conv_line_r(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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
        let (l, ax) = segment_axis(&mut c, b, e);
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
        let ftmp = line_integral(&mut c, x, b, (l, ax), s, ss, Q::Plain);
        // if (f < 1) { f = f + f_tmp; if (f > 1) f = 1; }
        let sum = c.add(f, ftmp);
        let over = c.gt(sum, one);
        let clamped = c.sel(over, one, sum);
        let below = c.lt(f, one);
        f = c.sel(below, clamped, f);
    }
    Ok(c.sub(f, tt))
}
