//! # frep-core
//!
//! The kernel of frep:
//! - the HyperFun language (lexer, parser, diagnostics);
//! - a staged compiler from HyperFun bodies to a pure expression graph over
//!   the point `x[]` and the parameters `a[]`;
//! - the evaluators every other part of frep uses (f64 point, batch,
//!   interval, gradient).
//!
//! This crate does no I/O, spawns no threads, and builds for
//! `wasm32-unknown-unknown`.
#![warn(missing_docs)]
// NaN-aware comparisons (`!(a > 0.0)`) are deliberate throughout; the other
// allowances keep the reference-exact literals and guards readable.
#![allow(
    clippy::neg_cmp_op_on_partial_ord,
    clippy::redundant_guards,
    clippy::wrong_self_convention,
    clippy::excessive_precision
)]

pub mod ast;
pub mod cancel;
pub mod compile;
pub mod diag;
pub mod error;
pub mod eval;
pub mod graph;
pub mod hash;
pub mod lexer;
pub mod library;
pub mod ops;
pub mod parser;
pub mod simplify;

pub use cancel::CancelToken;
pub use compile::{CompileOptions, Model};
pub use diag::{Diagnostic, Span};
pub use eval::{Inputs, PointEval};
pub use graph::{Graph, Node, NodeId, Tape};
pub use ops::EvalError;
pub use parser::{parse, parse_with, ParseLimits};
