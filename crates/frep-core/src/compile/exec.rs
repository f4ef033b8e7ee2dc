//! Symbolic execution of HyperFun statements and expressions.

use std::collections::{HashMap, HashSet};

use crate::ast::{self, Body, Expr, Ident, Program, Size, Stmt};
use crate::diag::{Diagnostic, Span};
use crate::graph::{Graph, NodeId};
use crate::library::{self, LibArg, ParamKind};
use crate::ops::{self, BinaryOp, EvalError, UnaryOp};

use super::CompileOptions;

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

const BUILTINS1: &[(&str, UnaryOp)] = &[
    ("sqrt", UnaryOp::Sqrt),
    ("exp", UnaryOp::Exp),
    ("log", UnaryOp::Log),
    ("logd", UnaryOp::Logd),
    ("sin", UnaryOp::Sin),
    ("cos", UnaryOp::Cos),
    ("tan", UnaryOp::Tan),
    ("asin", UnaryOp::Asin),
    ("acos", UnaryOp::Acos),
    ("atan", UnaryOp::Atan),
    ("abs", UnaryOp::Abs),
    ("sinh", UnaryOp::Sinh),
    ("cosh", UnaryOp::Cosh),
    ("tanh", UnaryOp::Tanh),
    ("ceil", UnaryOp::Ceil),
    ("floor", UnaryOp::Floor),
    ("int", UnaryOp::Trunc),
    ("frac", UnaryOp::Frac),
];

const BUILTINS2: &[(&str, BinaryOp)] = &[
    ("mod", BinaryOp::Mod),
    ("max", BinaryOp::Max),
    ("min", BinaryOp::Min),
    ("atan2", BinaryOp::Atan2),
];

/// Whether `name` is a built-in function (including `sign`).
pub(crate) fn is_builtin(name: &str) -> bool {
    name == "sign" || BUILTINS1.iter().any(|b| b.0 == name) || BUILTINS2.iter().any(|b| b.0 == name)
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

    fn arity_error(name: &Ident, n: usize, given: usize, span: Span) -> Diagnostic {
        Diagnostic::new(
            span,
            format!(
                "`{}` takes {n} argument{}, {given} given",
                name.name,
                if n == 1 { "" } else { "s" }
            ),
        )
        .expected(format!("{n} argument{}", if n == 1 { "" } else { "s" }))
    }

    fn call(
        &mut self,
        env: &mut Env,
        body: &'p Body,
        name: &'p Ident,
        args: &'p [Expr],
        span: Span,
    ) -> Result<NodeId, Diagnostic> {
        let fname = name.name.as_str();
        if fname == "sign" {
            if args.len() != 1 {
                return Err(Self::arity_error(name, 1, args.len(), span));
            }
            // The reference's `sign` always returns 1 (a listed deviation we
            // keep); its argument is still evaluated for its errors.
            let v = self.expr(env, body, &args[0])?;
            let one = self.g.constant(1.0);
            return Ok(self.g.check(v, one));
        }
        if let Some(&(_, op)) = BUILTINS1.iter().find(|b| b.0 == fname) {
            if args.len() != 1 {
                return Err(Self::arity_error(name, 1, args.len(), span));
            }
            let v = self.expr(env, body, &args[0])?;
            return Ok(self.g.unary(op, v));
        }
        if let Some(&(_, op)) = BUILTINS2.iter().find(|b| b.0 == fname) {
            if args.len() != 2 {
                return Err(Self::arity_error(name, 2, args.len(), span));
            }
            let b = self.expr(env, body, &args[1])?;
            let a = self.expr(env, body, &args[0])?;
            return Ok(self.g.binary(op, a, b));
        }
        if let Some(lib) = library::lookup(fname) {
            return self.library_call(env, body, name, lib, args, span);
        }
        if let Some(callee) = self.find_body(body, fname) {
            return self.body_call(env, callee, name, args, span);
        }
        if self.program.bodies.iter().any(|b| b.name.name == fname) {
            return Err(Diagnostic::new(
                name.span,
                format!(
                    "body `{fname}` is defined below `{}`; a body may call only bodies above it",
                    body.name.name
                ),
            ));
        }
        Err(
            Diagnostic::new(name.span, format!("unknown function `{}`", name.name)).expected(
                "a built-in function, a library function (hf...) or a body defined above",
            ),
        )
    }

    fn find_body(&self, current: &Body, name: &str) -> Option<&'p Body> {
        let pos = self
            .program
            .bodies
            .iter()
            .position(|b| std::ptr::eq(b, current))?;
        self.program.bodies[..pos]
            .iter()
            .find(|b| b.name.name == name)
    }

    /// The items of an array argument, or an error naming the argument.
    fn array_arg(
        env: &Env,
        arg: &Expr,
        fname: &str,
        k: usize,
    ) -> Result<(String, Items), Diagnostic> {
        if let Expr::Ident(id) = arg {
            if let Some(items) = env.arrays.get(&id.name) {
                if !env.scalars.contains_key(&id.name) {
                    return Ok((id.name.clone(), items.clone()));
                }
            }
        }
        Err(Diagnostic::new(
            arg.span(),
            format!("argument {} of `{fname}` must be an array", k + 1),
        )
        .expected("an array name (`x`, `a`, `s` or a declared array)"))
    }

    fn library_call(
        &mut self,
        env: &mut Env,
        body: &'p Body,
        name: &Ident,
        lib: &'static library::LibFn,
        args: &'p [Expr],
        span: Span,
    ) -> Result<NodeId, Diagnostic> {
        if args.len() != lib.params.len() {
            return Err(Self::arity_error(name, lib.params.len(), args.len(), span));
        }
        // Scalars right to left, as the reference evaluates them; arrays are
        // read when the function runs, after every argument.
        let mut scalars = vec![None; args.len()];
        for k in (0..args.len()).rev() {
            if matches!(lib.params[k], ParamKind::Scalar) {
                scalars[k] = Some(self.expr(env, body, &args[k])?);
            }
        }
        let mut lib_args = Vec::with_capacity(args.len());
        let mut array_names = Vec::new();
        let mut unassigned = false;
        for (k, kind) in lib.params.iter().enumerate() {
            match kind {
                ParamKind::Scalar => {
                    lib_args.push(LibArg::Scalar(scalars[k].expect("evaluated above")))
                }
                ParamKind::Array => {
                    let (aname, items) = Self::array_arg(env, &args[k], &name.name, k)?;
                    unassigned |= items.iter().any(Option::is_none);
                    array_names.push((k, aname));
                    lib_args.push(LibArg::Array(
                        items.into_iter().map(|i| i.unwrap_or(NodeId(0))).collect(),
                    ));
                }
            }
        }
        // Errors of the scalar arguments, in evaluation order.
        let mut guard = self.g.constant(0.0);
        for s in scalars.iter().rev().flatten() {
            guard = self.g.check(guard, *s);
        }
        if unassigned {
            let e = self.g.error(EvalError::UnassignedItems);
            return Ok(self.g.check(guard, e));
        }
        let result = (lib.build)(&mut self.g, &mut lib_args).map_err(|e| {
            let at = args.get(e.arg).map_or(span, Expr::span);
            Diagnostic::new(at, format!("in `{}`: {}", name.name, e.message))
        })?;
        for (k, aname) in array_names {
            if let LibArg::Array(items) = &lib_args[k] {
                if let Some(target) = env.arrays.get_mut(&aname) {
                    for (slot, &n) in target.iter_mut().zip(items) {
                        *slot = Some(n);
                    }
                }
            }
        }
        Ok(self.g.check(guard, result))
    }

    fn body_call(
        &mut self,
        env: &mut Env,
        callee: &'p Body,
        name: &Ident,
        args: &'p [Expr],
        span: Span,
    ) -> Result<NodeId, Diagnostic> {
        self.step(span)?;
        if args.len() != 2 && args.len() != 3 {
            return Err(Diagnostic::new(
                span,
                format!(
                    "a call of body `{}` takes 2 or 3 array arguments, {} given",
                    name.name,
                    args.len()
                ),
            )
            .expected("`body(x, a)` or `body(x, a, s)`"));
        }
        let h = header(callee)?;
        let mut arrays = Vec::with_capacity(3);
        for (k, arg) in args.iter().enumerate() {
            arrays.push(Self::array_arg(env, arg, &name.name, k)?);
        }
        let want = [h.x, h.a, h.s];
        for (k, (_, items)) in arrays.iter().enumerate() {
            if items.len() != want[k] {
                return Err(Diagnostic::new(
                    args[k].span(),
                    format!(
                        "wrong number of items in array: `{}` declares {} here, {} given",
                        callee.name.name,
                        ["x", "a", "s"][k],
                        items.len()
                    ),
                )
                .expected(format!("an array of {} items", want[k])));
            }
        }
        if args.len() == 2 && h.s != 1 {
            return Err(Diagnostic::new(
                span,
                format!(
                    "`{}` declares s[{}]; pass an array for it",
                    callee.name.name, h.s
                ),
            )
            .expected("a third array argument"));
        }
        if arrays
            .iter()
            .any(|(_, items)| items.iter().any(Option::is_none))
        {
            return Ok(self.g.error(EvalError::UnassignedItems));
        }
        let zero = self.g.constant(0.0);
        let s_in = if args.len() == 3 {
            arrays[2].1.clone()
        } else {
            vec![Some(zero)]
        };
        let (value, chain, s_out) =
            self.run_body(callee, arrays[0].1.clone(), arrays[1].1.clone(), s_in)?;
        if args.len() == 3 {
            let target = &arrays[2].0;
            if let Some(items) = env.arrays.get_mut(target) {
                *items = s_out;
            }
        }
        Ok(self.g.check(chain, value))
    }
}

/// The reference declares a variable when its first assignment is parsed:
/// a name read textually before any assignment is an error, as is an
/// unknown name.
fn check_declarations(program: &Program, body: &Body) -> Result<(), Diagnostic> {
    let mut declared: HashSet<&str> = ["x", "a", "s"].into_iter().collect();
    for d in &body.arrays {
        if !declared.insert(d.name.name.as_str()) {
            return Err(Diagnostic::new(
                d.name.span,
                format!("`{}` is declared twice", d.name.name),
            ));
        }
        if library::lookup(&d.name.name).is_some() || is_builtin(&d.name.name) {
            return Err(Diagnostic::new(
                d.name.span,
                format!("`{}` is a function name", d.name.name),
            ));
        }
    }
    let arrays: HashSet<&str> = declared.clone();
    let body_pos = program
        .bodies
        .iter()
        .position(|b| std::ptr::eq(b, body))
        .unwrap_or(0);
    let bodies: HashSet<&str> = program.bodies[..body_pos]
        .iter()
        .map(|b| b.name.name.as_str())
        .collect();
    declared_stmts(&body.stmts, &mut declared, &arrays, &bodies)?;
    declared_expr(&body.result, &declared, &bodies)
}

/// [`check_declarations`] of an expression: every name it reads is
/// declared.
fn declared_expr<'a>(
    e: &'a Expr,
    declared: &HashSet<&'a str>,
    bodies: &HashSet<&str>,
) -> Result<(), Diagnostic> {
    match e {
        Expr::Num { .. } => Ok(()),
        Expr::Ident(id) => {
            if declared.contains(id.name.as_str()) {
                Ok(())
            } else if bodies.contains(id.name.as_str()) {
                Err(Diagnostic::new(
                    id.span,
                    format!("`{}` is a body; call it with its arrays", id.name),
                )
                .expected(format!("`{}(x, a)`", id.name)))
            } else {
                Err(Diagnostic::new(
                    id.span,
                    format!("`{}` is used before any assignment to it", id.name),
                )
                .expected("a variable assigned above, an array or a number"))
            }
        }
        Expr::Index { array, index, .. } => {
            if !declared.contains(array.name.as_str()) {
                return Err(
                    Diagnostic::new(array.span, format!("unknown array `{}`", array.name))
                        .expected("`x`, `a`, `s` or a name declared with `array`"),
                );
            }
            declared_expr(index, declared, bodies)
        }
        Expr::Unary { expr, .. } => declared_expr(expr, declared, bodies),
        Expr::Binary { lhs, rhs, .. } => {
            declared_expr(lhs, declared, bodies)?;
            declared_expr(rhs, declared, bodies)
        }
        Expr::Call { args, .. } => args
            .iter()
            .try_for_each(|a| declared_expr(a, declared, bodies)),
    }
}
/// [`check_declarations`] of statements in order: each assignment
/// declares its target for what follows.
fn declared_stmts<'a>(
    stmts: &'a [Stmt],
    declared: &mut HashSet<&'a str>,
    arrays: &HashSet<&str>,
    bodies: &HashSet<&str>,
) -> Result<(), Diagnostic> {
    for s in stmts {
        match s {
            Stmt::Assign { target, value } => {
                declared_expr(value, declared, bodies)?;
                if arrays.contains(target.name.as_str()) {
                    return Err(Diagnostic::new(
                        target.span,
                        format!(
                            "`{}` is an array; assign its items or a whole-array literal",
                            target.name
                        ),
                    ));
                }
                if library::lookup(&target.name).is_some() || is_builtin(&target.name) {
                    return Err(Diagnostic::new(
                        target.span,
                        format!(
                            "`{}` is a function name and cannot be assigned",
                            target.name
                        ),
                    ));
                }
                declared.insert(target.name.as_str());
            }
            Stmt::ArrayLiteral { target, .. } => {
                if !arrays.contains(target.name.as_str()) {
                    return Err(Diagnostic::new(
                        target.span,
                        format!("`{}` is not a declared array", target.name),
                    )
                    .expected("an `array` declaration at the top of the body"));
                }
            }
            Stmt::IndexAssign {
                target,
                index,
                value,
            } => {
                if !arrays.contains(target.name.as_str()) {
                    return Err(Diagnostic::new(
                        target.span,
                        format!("`{}` is not a declared array", target.name),
                    )
                    .expected("an `array` declaration at the top of the body"));
                }
                declared_expr(index, declared, bodies)?;
                declared_expr(value, declared, bodies)?;
            }
            Stmt::If {
                cond,
                then_branch,
                else_branch,
                ..
            } => {
                declared_expr(cond, declared, bodies)?;
                declared_stmts(then_branch, declared, arrays, bodies)?;
                declared_stmts(else_branch, declared, arrays, bodies)?;
            }
            Stmt::While { cond, body, .. } => {
                declared_expr(cond, declared, bodies)?;
                declared_stmts(body, declared, arrays, bodies)?;
            }
        }
    }
    Ok(())
}
