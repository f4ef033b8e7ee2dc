//! Distance primitives: `hfDConeX/Y/Z`, `hfDCylinder`, `hfDTorusX/Y/Z`.
//!
//! They return signed distances and their own sentinels for a point
//! array without 3 items.

use super::build::*;
use super::{LibArg, LibError, SENTINEL};
use crate::graph::{Graph, NodeId};

/// `-11111111111.0`: the distance cones' sentinel.
const SENTINEL_DCONE: f64 = -11111111111.0;
/// `-11111111111.1`: `hfDCylinder`'s sentinel.
const SENTINEL_DCYL: f64 = -11111111111.1;

pub(super) fn dcone(
    g: &mut Graph,
    args: &[LibArg],
    axis: usize,
    func: &str,
) -> Result<NodeId, LibError> {
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

pub(super) fn hf_dcylinder(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn dtorus(
    g: &mut Graph,
    args: &[LibArg],
    axis: usize,
    func: &str,
) -> Result<NodeId, LibError> {
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
