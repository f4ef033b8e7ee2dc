//! Transformations: scale, shift, rotations, twists, tapers, stretch and
//! space maps.
//!
//! Each one rewrites the `xt` array it is given and returns the constant 1.

use super::build::*;
use super::{LibArg, LibError};
use crate::graph::{Graph, NodeId};

/// The array to transform (argument 0), which must have at least 3 items.
fn xt_arg(args: &[LibArg], func: &str) -> Result<Vec<NodeId>, LibError> {
    array_min(args, 0, 3, func, "xt")
}

pub(super) fn hf_scale3d(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, "hfScale3D")?;
    for (k, v) in xt.iter_mut().take(3).enumerate() {
        let s = scalar(args, 1 + k)?;
        *v = c.div(*v, s);
    }
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

pub(super) fn hf_shift3d(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn rotate3d(
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

/// `(1 − t)·y1 + t·y2` with `t = (v − x1) / (x2 − x1)`, in the C code's
/// order (twists interpolate the angle, tapers the scale).
fn lerp_along(
    c: &mut C,
    v: NodeId,
    (x1, x2): (NodeId, NodeId),
    (y1, y2): (NodeId, NodeId),
) -> NodeId {
    let nu = c.sub(v, x1);
    let de = c.sub(x2, x1);
    let t = c.div(nu, de);
    let omt = c.ksub(1.0, t);
    let a = c.mul(omt, y1);
    let b = c.mul(t, y2);
    c.add(a, b)
}

pub(super) fn twist(
    g: &mut Graph,
    args: &mut [LibArg],
    axis: usize,
    func: &str,
) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, func)?;
    let (x1, x2) = (scalar(args, 1)?, scalar(args, 2)?);
    let (th1, th2) = (scalar(args, 3)?, scalar(args, 4)?);
    let theta = lerp_along(&mut c, xt[axis], (x1, x2), (th1, th2));
    let (p, q) = rot_pair(axis);
    rotate_pair(&mut c, &mut xt, p, q, theta);
    set_array(args, 0, xt);
    Ok(c.k(1.0))
}

pub(super) fn taper(
    g: &mut Graph,
    args: &mut [LibArg],
    axis: usize,
    func: &str,
) -> Result<NodeId, LibError> {
    let mut c = C { g };
    let mut xt = xt_arg(args, func)?;
    let (x1, x2) = (scalar(args, 1)?, scalar(args, 2)?);
    let (s1, s2) = (scalar(args, 3)?, scalar(args, 4)?);
    let v = xt[axis];
    let lerp = lerp_along(&mut c, v, (x1, x2), (s1, s2));
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

pub(super) fn hf_stretch3d(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn space_map(
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
