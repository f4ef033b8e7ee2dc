//! Symbolic execution of HyperFun statements and expressions.
//!
//! - [`Compiler`] walks a body's statements in order and builds graph nodes
//!   for their values; branches merge through selects, loops unroll up to
//!   the configured limit.
//! - Calls (built-ins, library functions, other bodies) are in
//!   [`calls`]; the declaration checks run first, in [`declare`].

use std::collections::{HashMap, HashSet};

use crate::ast::{self, Body, Expr, Ident, Program, Size, Stmt};
use crate::diag::{Diagnostic, Span};
use crate::graph::{Graph, NodeId};
use crate::library::{self, LibArg, ParamKind};
use crate::ops::{self, BinaryOp, EvalError, UnaryOp};

use super::CompileOptions;

mod calls;
mod declare;

pub(crate) use calls::is_builtin;
use declare::check_declarations;

/// One array: its items (None = never assigned).
type Items = Vec<Option<NodeId>>;

/// The symbolic state of one body's execution.
#[derive(Clone, Debug)]
struct Env {
    /// Scalars assigned so far (a declared but unassigned one is absent).
    scalars: HashMap<String, NodeId>,
    /// Arrays: `x`, `a`, `s` and the locals.
    arrays: HashMap<String, Items>,
    /// Every error that executed statements may raise, in order.
    chain: NodeId,
}

/// What compiling the selected body produces.
pub(super) struct Compiled {
    pub x_dim: usize,
    pub a_dim: usize,
    pub s_dim: usize,
    pub value: NodeId,
    pub guarded: NodeId,
    pub attributes: Vec<NodeId>,
}

/// The compiler's state across bodies.
pub(super) struct Compiler<'p> {
    program: &'p Program,
    options: &'p CompileOptions,
    g: Graph,
    iterations: usize,
    steps: usize,
    /// Bodies whose declarations were checked.
    checked: HashSet<String>,
}

/// Array sizes of a body's header.
struct Header {
    x: usize,
    a: usize,
    s: usize,
}

fn size_of(size: &Size, what: &str) -> Result<usize, Diagnostic> {
    let n = ops::round_half_up(size.value);
    if n.is_nan() || n < 1.0 {
        return Err(Diagnostic::new(
            size.span,
            format!("the size of {what} must be at least 1"),
        ));
    }
    if n > 1_000_000.0 {
        return Err(Diagnostic::new(
            size.span,
            format!("the size of {what} is too large (at most 1000000)"),
        ));
    }
    Ok(n as usize)
}

fn header(body: &Body) -> Result<Header, Diagnostic> {
    Ok(Header {
        x: size_of(&body.x_size, "`x`")?,
        a: size_of(&body.a_size, "`a`")?,
        s: match &body.s_size {
            Some(s) => size_of(s, "`s`")?,
            None => 1,
        },
    })
}

impl<'p> Compiler<'p> {
    pub(super) fn new(program: &'p Program, options: &'p CompileOptions) -> Self {
        Compiler {
            program,
            options,
            g: Graph::new(),
            iterations: 0,
            steps: 0,
            checked: HashSet::new(),
        }
    }

    pub(super) fn into_graph(self) -> Graph {
        self.g
    }

    /// Compiles the top-level body with `x` = the point, `a` = parameters, `s` = zeros.
    pub(super) fn compile_top(&mut self, body: &'p Body) -> Result<Compiled, Diagnostic> {
        let h = header(body)?;
        let x: Items = (0..h.x as u32).map(|i| Some(self.g.x(i))).collect();
        let a: Items = (0..h.a as u32).map(|i| Some(self.g.param(i))).collect();
        let zero = self.g.constant(0.0);
        let s: Items = vec![Some(zero); h.s];
        let (value, chain, s_out) = self.run_body(body, x, a, s)?;
        let guarded = self.g.check(chain, value);
        let attributes = s_out.iter().map(|i| i.unwrap_or(zero)).collect();
        Ok(Compiled {
            x_dim: h.x,
            a_dim: h.a,
            s_dim: h.s,
            value,
            guarded,
            attributes,
        })
    }

    /// Executes a body with the given arrays; returns its value, its error
    /// chain and its final `s`.
    fn run_body(
        &mut self,
        body: &'p Body,
        x: Items,
        a: Items,
        s: Items,
    ) -> Result<(NodeId, NodeId, Items), Diagnostic> {
        if self.checked.insert(body.name.name.clone()) {
            check_declarations(self.program, body)?;
        }
        let mut env = Env {
            scalars: HashMap::new(),
            arrays: HashMap::new(),
            chain: self.g.constant(0.0),
        };
        env.arrays.insert("x".into(), x);
        env.arrays.insert("a".into(), a);
        env.arrays.insert("s".into(), s);
        for decl in &body.arrays {
            let n = size_of(&decl.size, &format!("array `{}`", decl.name.name))?;
            env.arrays.insert(decl.name.name.clone(), vec![None; n]);
        }
        self.stmts(&mut env, body, &body.stmts)?;
        let value = self.expr(&mut env, body, &body.result)?;
        let s_out = env.arrays.remove("s").unwrap_or_default();
        Ok((value, env.chain, s_out))
    }

    fn step(&mut self, span: Span) -> Result<(), Diagnostic> {
        self.steps += 1;
        if self.steps > self.options.max_steps {
            return Err(Diagnostic::new(
                span,
                format!(
                    "compilation exceeded its work limit of {} steps",
                    self.options.max_steps
                ),
            )
            .expected("a smaller model, or a larger `max_steps`"));
        }
        if self.g.len() > self.options.max_nodes {
            return Err(Diagnostic::new(
                span,
                format!(
                    "the model graph exceeded its limit of {} nodes",
                    self.options.max_nodes
                ),
            )
            .expected("a smaller model, or a larger `max_nodes`"));
        }
        Ok(())
    }

    fn stmts(
        &mut self,
        env: &mut Env,
        body: &'p Body,
        stmts: &'p [Stmt],
    ) -> Result<(), Diagnostic> {
        for s in stmts {
            self.stmt(env, body, s)?;
        }
        Ok(())
    }

    fn push_chain(&mut self, env: &mut Env, v: NodeId) {
        env.chain = self.g.check(env.chain, v);
    }

    fn stmt(&mut self, env: &mut Env, body: &'p Body, stmt: &'p Stmt) -> Result<(), Diagnostic> {
        match stmt {
            Stmt::Assign { target, value } => {
                self.step(target.span)?;
                if env.arrays.contains_key(&target.name) {
                    return Err(Diagnostic::new(
                        target.span,
                        format!(
                            "`{}` is an array; assign its items or a whole-array literal",
                            target.name
                        ),
                    )
                    .expected(format!("`{0}[i] = ...;` or `{0} = [...];`", target.name)));
                }
                let v = self.expr(env, body, value)?;
                self.push_chain(env, v);
                env.scalars.insert(target.name.clone(), v);
            }
            Stmt::ArrayLiteral {
                target,
                values,
                span,
            } => {
                self.step(target.span)?;
                let items = self.array_mut(env, target)?;
                if items.len() != values.len() {
                    let n = items.len();
                    return Err(Diagnostic::new(
                        *span,
                        format!(
                            "wrong number of items for `{}`: {} given",
                            target.name,
                            values.len()
                        ),
                    )
                    .expected(format!("exactly {n} items")));
                }
                let nodes: Vec<NodeId> = values.iter().map(|&v| self.g.constant(v)).collect();
                let items = self.array_mut(env, target)?;
                for (slot, n) in items.iter_mut().zip(nodes) {
                    *slot = Some(n);
                }
            }
            Stmt::IndexAssign {
                target,
                index,
                value,
            } => {
                self.step(target.span)?;
                self.array_mut(env, target)?;
                if target.name == "x" || target.name == "a" {
                    return Err(Diagnostic::new(
                        target.span,
                        format!("`{}` is read-only", target.name),
                    ));
                }
                let idx = self.expr(env, body, index)?;
                let v = self.expr(env, body, value)?;
                self.push_chain(env, idx);
                self.push_chain(env, v);
                self.write_item(env, target, idx, v)?;
            }
            Stmt::If {
                cond,
                then_branch,
                else_branch,
                span,
            } => {
                self.step(*span)?;
                let c = self.expr(env, body, cond)?;
                if let Some(cv) = self.g.const_value(c) {
                    let branch = if ops::truthy(cv) {
                        then_branch
                    } else {
                        else_branch
                    };
                    return self.stmts(env, body, branch);
                }
                if self.g.error_value(c).is_some() {
                    // The condition always fails: nothing after it matters
                    // at run time, but later statements must still compile.
                    self.push_chain(env, c);
                    return Ok(());
                }
                let mut then_env = env.clone();
                self.stmts(&mut then_env, body, then_branch)?;
                let mut else_env = env.clone();
                self.stmts(&mut else_env, body, else_branch)?;
                *env = self.merge(c, &then_env, &else_env);
            }
            Stmt::While {
                cond,
                body: loop_body,
                span,
            } => self.while_loop(env, body, cond, loop_body, *span)?,
        }
        Ok(())
    }

    /// `if truthy(c) then t else e` for every variable of two states.
    fn merge(&mut self, c: NodeId, t: &Env, e: &Env) -> Env {
        let uninit = self.g.error(EvalError::NotInitialized);
        let mut scalars = HashMap::with_capacity(t.scalars.len().max(e.scalars.len()));
        let names: HashSet<&String> = t.scalars.keys().chain(e.scalars.keys()).collect();
        for name in names {
            let tv = t.scalars.get(name).copied().unwrap_or(uninit);
            let ev = e.scalars.get(name).copied().unwrap_or(uninit);
            let v = if tv == ev {
                tv
            } else {
                self.g.select(c, tv, ev)
            };
            scalars.insert(name.clone(), v);
        }
        let mut arrays = HashMap::with_capacity(t.arrays.len());
        for (name, ti) in &t.arrays {
            let ei = &e.arrays[name];
            let items = ti
                .iter()
                .zip(ei)
                .map(|(&tv, &ev)| match (tv, ev) {
                    (None, None) => None,
                    (tv, ev) if tv == ev => tv,
                    (tv, ev) => Some(self.g.select(c, tv.unwrap_or(uninit), ev.unwrap_or(uninit))),
                })
                .collect();
            arrays.insert(name.clone(), items);
        }
        let chain = self.g.select(c, t.chain, e.chain);
        Env {
            scalars,
            arrays,
            chain,
        }
    }

    fn while_loop(
        &mut self,
        env: &mut Env,
        body: &'p Body,
        cond: &'p Expr,
        stmts: &'p [Stmt],
        span: Span,
    ) -> Result<(), Diagnostic> {
        // `merged` is None while every condition so far was constant true.
        // Once a condition depends on the point, `active` is "every condition
        // so far held" and `state` the state if the loop stopped now.
        let mut merged: Option<(NodeId, Env)> = None;
        let mut dependent = 0usize;
        loop {
            self.step(span)?;
            let c = self.expr(env, body, cond)?;
            self.push_chain(env, c);
            if let Some(cv) = self.g.const_under_checks(c) {
                if !ops::truthy(cv) {
                    break;
                }
                if merged.is_none() {
                    self.iterations += 1;
                    if self.iterations > self.options.max_iterations {
                        return Err(Diagnostic::new(
                            span,
                            format!(
                                "loops ran more than {} iterations in all while compiling",
                                self.options.max_iterations
                            ),
                        )
                        .expected("a loop that ends, or a larger `max_iterations`"));
                    }
                    self.stmts(env, body, stmts)?;
                    continue;
                }
            }
            if self.g.error_value(c).is_some() {
                break;
            }
            dependent += 1;
            if dependent > self.options.max_dependent_iterations {
                return Err(Diagnostic::new(
                    span,
                    format!(
                        "this loop's condition depends on the point and it did not end within {} unrolled iterations",
                        self.options.max_dependent_iterations
                    ),
                )
                .expected("a loop bounded by a counter, or a larger `max_dependent_iterations`"));
            }
            let (active, stopped) = match merged.take() {
                None => (c, env.clone()),
                Some((prev, state)) => {
                    let zero = self.g.constant(0.0);
                    (self.g.select(prev, c, zero), state)
                }
            };
            self.stmts(env, body, stmts)?;
            let state = self.merge(active, env, &stopped);
            merged = Some((active, state));
        }
        if let Some((_, state)) = merged {
            // The running state's chain already includes the final (false)
            // condition's errors only on the path that reached it.
            *env = state;
        }
        Ok(())
    }

    /// The items of an assignable array (`s` or a local).
    fn array_mut<'e>(&self, env: &'e mut Env, name: &Ident) -> Result<&'e mut Items, Diagnostic> {
        if name.name == "x" || name.name == "a" {
            return Err(Diagnostic::new(
                name.span,
                format!("`{}` is read-only", name.name),
            ));
        }
        if env.scalars.contains_key(&name.name) || !env.arrays.contains_key(&name.name) {
            return Err(
                Diagnostic::new(name.span, format!("`{}` is not an array", name.name))
                    .expected("a name declared with `array`, or `s`"),
            );
        }
        Ok(env.arrays.get_mut(&name.name).expect("checked above"))
    }

    fn write_item(
        &mut self,
        env: &mut Env,
        target: &Ident,
        idx: NodeId,
        v: NodeId,
    ) -> Result<(), Diagnostic> {
        let n = env.arrays[&target.name].len();
        if let Some(i) = self.g.const_value(idx) {
            let r = ops::round_half_up(i);
            if r >= 1.0 && r <= n as f64 {
                self.array_mut(env, target)?[r as usize - 1] = Some(v);
            } else {
                let e = self.g.error(EvalError::IndexOutOfRange);
                self.push_chain(env, e);
            }
            return Ok(());
        }
        if self.g.error_value(idx).is_some() {
            return Ok(()); // already in the chain
        }
        // A point-dependent index: every item may be the one written.
        let r = self.g.unary(UnaryOp::RoundHalfUp, idx);
        let guard = self.index_guard(r, n);
        self.push_chain(env, guard);
        let uninit = self.g.error(EvalError::NotInitialized);
        let items = env.arrays[&target.name].clone();
        let mut new = Vec::with_capacity(n);
        for (k, old) in items.into_iter().enumerate() {
            let kc = self.g.constant((k + 1) as f64);
            let hit = self.g.binary(BinaryOp::Eq, r, kc);
            new.push(Some(self.g.select(hit, v, old.unwrap_or(uninit))));
        }
        *self.array_mut(env, target)? = new;
        Ok(())
    }

    /// 0 where the rounded index `r` is in `1..=n`, an error elsewhere.
    fn index_guard(&mut self, r: NodeId, n: usize) -> NodeId {
        let one = self.g.constant(1.0);
        let nn = self.g.constant(n as f64);
        let lo = self.g.binary(BinaryOp::Ge, r, one);
        let hi = self.g.binary(BinaryOp::Le, r, nn);
        let ok = self.g.binary(BinaryOp::And, lo, hi);
        let zero = self.g.constant(0.0);
        let err = self.g.error(EvalError::IndexOutOfRange);
        self.g.select(ok, zero, err)
    }

    fn read_item(&mut self, items: &Items, idx: NodeId) -> NodeId {
        let uninit = self.g.error(EvalError::NotInitialized);
        if let Some(i) = self.g.const_value(idx) {
            let r = ops::round_half_up(i);
            if r >= 1.0 && r <= items.len() as f64 {
                return items[r as usize - 1].unwrap_or(uninit);
            }
            return self.g.error(EvalError::IndexOutOfRange);
        }
        if self.g.error_value(idx).is_some() {
            return idx;
        }
        let r = self.g.unary(UnaryOp::RoundHalfUp, idx);
        let mut out = self.g.error(EvalError::IndexOutOfRange);
        for (k, item) in items.iter().enumerate().rev() {
            let kc = self.g.constant((k + 1) as f64);
            let hit = self.g.binary(BinaryOp::Eq, r, kc);
            out = self.g.select(hit, item.unwrap_or(uninit), out);
        }
        out
    }

    fn expr(&mut self, env: &mut Env, body: &'p Body, e: &'p Expr) -> Result<NodeId, Diagnostic> {
        Ok(match e {
            Expr::Num { value, .. } => self.g.constant(*value),
            Expr::Ident(id) => {
                if let Some(&v) = env.scalars.get(&id.name) {
                    v
                } else if env.arrays.contains_key(&id.name) {
                    return Err(Diagnostic::new(
                        id.span,
                        format!("`{}` is an array, not a number", id.name),
                    )
                    .expected(format!("an item such as `{}[1]`", id.name)));
                } else {
                    // Declared textually (checked before execution) but not
                    // assigned on this path.
                    self.g.error(EvalError::NotInitialized)
                }
            }
            Expr::Index { array, index, .. } => {
                let idx = self.expr(env, body, index)?;
                let Some(items) = env.arrays.get(&array.name) else {
                    return Err(Diagnostic::new(
                        array.span,
                        format!("`{}` is not an array", array.name),
                    )
                    .expected("`x`, `a`, `s` or a name declared with `array`"));
                };
                let items = items.clone();
                self.read_item(&items, idx)
            }
            Expr::Unary { op, expr, .. } => {
                let v = self.expr(env, body, expr)?;
                match op {
                    ast::UnaryOp::Plus => v,
                    ast::UnaryOp::Minus | ast::UnaryOp::Tilde => self.g.unary(UnaryOp::Neg, v),
                    ast::UnaryOp::Not => self.g.unary(UnaryOp::Not, v),
                }
            }
            Expr::Binary { op, lhs, rhs, .. } => {
                // The reference evaluates the right operand first (it matters
                // when both contain transformations of the same array).
                let b = self.expr(env, body, rhs)?;
                let a = self.expr(env, body, lhs)?;
                let op = match op {
                    ast::BinaryOp::Add => BinaryOp::Add,
                    ast::BinaryOp::Sub => BinaryOp::Sub,
                    ast::BinaryOp::Mul => BinaryOp::Mul,
                    ast::BinaryOp::Div => BinaryOp::Div,
                    ast::BinaryOp::Pow => BinaryOp::Pow,
                    ast::BinaryOp::Union => BinaryOp::RUnion,
                    ast::BinaryOp::Inter | ast::BinaryOp::Cart => BinaryOp::RInter,
                    ast::BinaryOp::Diff => BinaryOp::RDiff,
                    ast::BinaryOp::Lt => BinaryOp::Lt,
                    ast::BinaryOp::Gt => BinaryOp::Gt,
                    ast::BinaryOp::Le => BinaryOp::Le,
                    ast::BinaryOp::Ge => BinaryOp::Ge,
                    ast::BinaryOp::Eq => BinaryOp::Eq,
                    ast::BinaryOp::Ne => BinaryOp::Ne,
                    ast::BinaryOp::And => BinaryOp::And,
                    ast::BinaryOp::Or => BinaryOp::Or,
                };
                self.g.binary(op, a, b)
            }
            Expr::Call { name, args, span } => self.call(env, body, name, args, *span)?,
        })
    }
}
