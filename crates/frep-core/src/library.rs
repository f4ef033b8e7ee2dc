//! TEMPORARY stub (replaced by the library branch).
#![allow(missing_docs)]
use crate::graph::{Graph, NodeId};
use crate::ops::BinaryOp;
pub enum ParamKind { Scalar, Array }
pub enum LibArg { Scalar(NodeId), Array(Vec<NodeId>) }
pub struct LibError { pub arg: usize, pub message: String }
pub struct LibFn { pub name: &'static str, pub params: &'static [ParamKind], pub build: fn(&mut Graph, &mut [LibArg]) -> Result<NodeId, LibError> }
fn sphere(g: &mut Graph, args: &mut [LibArg]) -> Result<NodeId, LibError> {
    let (LibArg::Array(x), LibArg::Array(c), LibArg::Scalar(r)) = (&args[0], &args[1], &args[2]) else { unreachable!() };
    let mut s = g.binary(BinaryOp::Mul, *r, *r);
    for i in 0..3 { let d = g.binary(BinaryOp::Sub, x[i], c[i]); let d2 = g.binary(BinaryOp::Mul, d, d); s = g.binary(BinaryOp::Sub, s, d2); }
    Ok(s)
}
static ALL: [LibFn; 1] = [LibFn { name: "hfsphere", params: &[ParamKind::Array, ParamKind::Array, ParamKind::Scalar], build: sphere }];
pub fn lookup(name: &str) -> Option<&'static LibFn> { ALL.iter().find(|f| f.name == name) }
