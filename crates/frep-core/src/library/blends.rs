//! `hfBlendUni` and `hfBlendInt`: the blending set operations as graph
//! blend nodes.

use super::build::*;
use super::{LibArg, LibError};
use crate::graph::{Graph, NodeId};
use crate::ops::BlendOp;

pub(super) fn blend(g: &mut Graph, args: &[LibArg], op: BlendOp) -> Result<NodeId, LibError> {
    let mut v = [NodeId(0); 5];
    for (i, slot) in v.iter_mut().enumerate() {
        *slot = scalar(args, i)?;
    }
    Ok(g.blend(op, v))
}

pub(super) fn hf_blend_uni(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    blend(g, args, BlendOp::Union)
}

pub(super) fn hf_blend_int(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    blend(g, args, BlendOp::Inter)
}
