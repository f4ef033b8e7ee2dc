//! Attribute setters: `hfA_SetColor` and `hfA_SetAttributes`.
//!
//! Inside the shape (`f >= 0`) they write the new values into the array;
//! outside they keep the old ones. They return the constant 1.

use super::build::*;
use super::LibArg;
use super::LibError;
use crate::graph::{Graph, NodeId};

pub(super) fn hfa_set_color(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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

pub(super) fn hfa_set_attributes(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
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
