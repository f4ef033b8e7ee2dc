//! The staged compiler: a HyperFun body becomes a [`Model`] — a pure
//! expression graph over the point `x[]` and the parameters `a[]`.
//!
//! Compilation is symbolic execution of the body. Every variable and array
//! item holds a graph node; whatever does not depend on the point or the
//! parameters folds to a constant as it is built. Hence:
//! * constants are folded and loops whose condition is constant are unrolled;
//! * arrays are tracked item by item, and library transformations
//!   (`hfRotate3DZ(xt, …)`) rewrite the items symbolically;
//! * calls of other bodies are inlined (arrays copied in, `s` copied back);
//! * an `if` on a point-dependent condition runs both branches and merges
//!   every variable with a select; a `while` on a point-dependent condition
//!   is unrolled up to [`CompileOptions::max_dependent_iterations`], beyond
//!   which compilation fails with a clear error;
//! * parameters `a[]` stay symbolic ([`Node::Param`](crate::Node::Param)), so
//!   changing one never recompiles.
//!
//! Runtime errors of the reference interpreter (division by `|b| < 1e-6`, …)
//! stay in the graph as checked operations. The compiler threads a chain of
//! [`Node::Check`](crate::Node::Check)s through the statements. So the point
//! evaluator reports, per point, the error the reference would report
//! first, even for a statement whose value is never used. See
//! [`crate::graph`].
//!
//! Every resource is bounded by [`CompileOptions`]: nodes, loop iterations,
//! inlined calls and total work (a step budget that stands in for a time
//! limit: the kernel has no clock, as it must run in WebAssembly).

mod exec;

use crate::ast::{Body, Program};
use crate::diag::{Diagnostic, Span};
use crate::graph::{Graph, NodeId, Tape};

/// Limits and choices for [`Model::compile_with`].
#[derive(Clone, Debug)]
pub struct CompileOptions {
    /// The body to compile; `None` means `my_model`, else the first body
    /// (the reference host's rule).
    pub body: Option<String>,
    /// Maximum number of graph nodes (the default, 1,000,000, is about 70 times
    /// the largest model of the corpus and keeps a runaway loop near 125 MB).
    pub max_nodes: usize,
    /// Maximum number of loop iterations executed at compile time, all loops
    /// together (constant-condition loops are unrolled).
    pub max_iterations: usize,
    /// Maximum number of iterations unrolled for one `while` whose condition
    /// depends on the point.
    pub max_dependent_iterations: usize,
    /// Maximum number of statements executed and calls inlined: a bound on
    /// compile time.
    pub max_steps: usize,
}

impl Default for CompileOptions {
    fn default() -> Self {
        CompileOptions {
            body: None,
            max_nodes: 1_000_000,
            max_iterations: 1_000_000,
            max_dependent_iterations: 64,
            max_steps: 20_000_000,
        }
    }
}

/// A compiled body: the expression graph and what it computes.
#[derive(Clone, Debug)]
pub struct Model {
    /// The graph holding every node below.
    pub graph: Graph,
    /// The compiled body's name.
    pub body: String,
    /// Names of all bodies in the file, in order.
    pub bodies: Vec<String>,
    /// Declared size of `x` (3 for ordinary models).
    pub x_dim: usize,
    /// Declared size of `a` (the number of parameters).
    pub a_dim: usize,
    /// Declared size of `s` (1 when the header has no `s`).
    pub s_dim: usize,
    /// Whether the header declares `s[]` (then the attributes are outputs).
    pub has_attributes: bool,
    /// The body's value `f` (`f >= 0` inside), for bulk evaluation.
    pub value: NodeId,
    /// `f` guarded by every statement's possible errors in reference order:
    /// what the point evaluator runs.
    pub guarded: NodeId,
    /// The final values of `s[1..=s_dim]`.
    pub attributes: Vec<NodeId>,
}

impl Model {
    /// Parses and compiles `source` with the default options.
    pub fn compile(source: &str) -> Result<Model, Diagnostic> {
        Self::compile_with(source, &CompileOptions::default())
    }

    /// Parses and compiles `source`.
    pub fn compile_with(source: &str, options: &CompileOptions) -> Result<Model, Diagnostic> {
        let program = crate::parser::parse(source)?;
        compile_program(&program, options)
    }

    /// The tape of the value alone (what meshing and rendering evaluate).
    pub fn tape(&self) -> Tape {
        self.graph.tape(&[self.value])
    }

    /// The tape of the value followed by the attributes `s[1..]` (when the
    /// body declares `s`).
    pub fn tape_with_attributes(&self) -> Tape {
        let mut outs = vec![self.value];
        if self.has_attributes {
            outs.extend_from_slice(&self.attributes);
        }
        self.graph.tape(&outs)
    }

    /// The tape of the attributes `s[1..]` alone, without the value (the
    /// nodes only the value needs left out); `None` when the body does not
    /// declare `s`. Its outputs are [`Model::tape_with_attributes`]'s after
    /// the first, the same values.
    pub fn attribute_tape(&self) -> Option<Tape> {
        (self.has_attributes && !self.attributes.is_empty())
            .then(|| self.graph.tape(&self.attributes))
    }

    /// The tape the point evaluator runs: the guarded value, then the
    /// attributes (when declared).
    pub fn point_tape(&self) -> Tape {
        let mut outs = vec![self.guarded];
        if self.has_attributes {
            outs.extend_from_slice(&self.attributes);
        }
        self.graph.tape(&outs)
    }

    /// Number of parameters the model reads (`a[]` size).
    pub fn params(&self) -> usize {
        self.a_dim
    }
}

/// Compiles one body of a parsed program.
pub fn compile_program(program: &Program, options: &CompileOptions) -> Result<Model, Diagnostic> {
    let body = select_body(program, options.body.as_deref())?;
    let mut cx = exec::Compiler::new(program, options);
    let out = cx.compile_top(body)?;
    Ok(Model {
        body: body.name.name.clone(),
        bodies: program.bodies.iter().map(|b| b.name.name.clone()).collect(),
        x_dim: out.x_dim,
        a_dim: out.a_dim,
        s_dim: out.s_dim,
        has_attributes: body.s_size.is_some(),
        value: out.value,
        guarded: out.guarded,
        attributes: out.attributes,
        graph: cx.into_graph(),
    })
}

/// The reference host's choice of body: by name, else `my_model`, else the first.
fn select_body<'p>(program: &'p Program, name: Option<&str>) -> Result<&'p Body, Diagnostic> {
    if let Some(name) = name {
        let lower = name.to_ascii_lowercase();
        return program
            .bodies
            .iter()
            .find(|b| b.name.name == lower)
            .ok_or_else(|| {
                let names: Vec<_> = program
                    .bodies
                    .iter()
                    .map(|b| b.name.name.as_str())
                    .collect();
                Diagnostic::new(
                    program
                        .bodies
                        .first()
                        .map_or(Span::default(), |b| b.name.span),
                    format!("no body named `{name}` in this file"),
                )
                .expected(format!("one of: {}", names.join(", ")))
            });
    }
    program
        .bodies
        .iter()
        .find(|b| b.name.name == "my_model")
        .or_else(|| program.bodies.first())
        .ok_or_else(|| {
            Diagnostic::new(Span::default(), "the file has no body")
                .expected("a body such as `my_model(x[3], a[1]) { ... }`")
        })
}
