//! The f64 point evaluator: the reference interpreter's semantics, runtime
//! errors included.
//!
//! It runs a model's [`point tape`](crate::Model::point_tape) and returns,
//! per point, either the value (and the attributes) or the error the
//! reference interpreter would stop with. Errors propagate through the tape
//! in the reference's evaluation order: the right operand's error before the
//! left's, a [`Check`](crate::Node::Check)'s guard before its value, and only
//! the chosen branch of a select.

use crate::eval::Inputs;
use crate::graph::{Node, Tape};
use crate::ops::{self, EvalError};

/// Evaluates a tape at one point at a time.
#[derive(Clone, Debug)]
pub struct PointEval {
    tape: Tape,
    slots: Vec<Result<f64, EvalError>>,
}

impl PointEval {
    /// An evaluator for `tape`.
    pub fn new(tape: Tape) -> Self {
        let n = tape.len();
        PointEval {
            tape,
            slots: vec![Ok(0.0); n],
        }
    }

    /// The tape being evaluated.
    pub fn tape(&self) -> &Tape {
        &self.tape
    }

    /// Evaluates every node at `(x, y, z)`; returns output 0.
    pub fn eval(&mut self, x: f64, y: f64, z: f64, inputs: &Inputs) -> Result<f64, EvalError> {
        let slots = &mut self.slots;
        for (i, node) in self.tape.nodes.iter().enumerate() {
            let r = match *node {
                Node::Const(b) => Ok(f64::from_bits(b)),
                Node::X(0) => Ok(x),
                Node::X(1) => Ok(y),
                Node::X(2) => Ok(z),
                Node::X(k) => Ok(inputs.extra_x(k)),
                Node::Param(k) => Ok(inputs.param(k)),
                Node::Error(e) => Err(e),
                Node::Unary(op, a) => slots[a.index()].and_then(|a| ops::unary(op, a)),
                Node::Binary(op, a, b) => {
                    let b = slots[b.index()];
                    let a = slots[a.index()];
                    b.and_then(|b| a.and_then(|a| ops::binary(op, a, b)))
                }
                Node::PowI(a, n) => slots[a.index()].and_then(|a| ops::pow_int(a, n)),
                Node::Select(c, t, e) => slots[c.index()].and_then(|c| {
                    if ops::truthy(c) {
                        slots[t.index()]
                    } else {
                        slots[e.index()]
                    }
                }),
                Node::Blend(op, [f1, f2, a0, a1, a2]) => {
                    // Arguments are evaluated last to first.
                    let mut v = [0.0; 5];
                    let mut err = None;
                    for (k, id) in [f1, f2, a0, a1, a2].into_iter().enumerate().rev() {
                        match slots[id.index()] {
                            Ok(x) => v[k] = x,
                            Err(e) => {
                                err = Some(e);
                                break;
                            }
                        }
                    }
                    match err {
                        Some(e) => Err(e),
                        None => Ok(ops::blend(op, v[0], v[1], v[2], v[3], v[4])),
                    }
                }
                Node::Check(g, v) => slots[g.index()].and(slots[v.index()]),
            };
            slots[i] = r;
        }
        self.output(0)
    }

    /// Output `k` of the last evaluation (0 is the value; attributes follow).
    pub fn output(&self, k: usize) -> Result<f64, EvalError> {
        self.slots[self.tape.outputs[k].index()]
    }

    /// Number of outputs.
    pub fn outputs(&self) -> usize {
        self.tape.outputs.len()
    }
}
