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
