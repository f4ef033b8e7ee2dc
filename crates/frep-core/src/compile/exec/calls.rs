//! Calls: HyperFun's built-in functions, the FRep library and other
//! bodies of the program.
//!
//! - A built-in becomes one graph operation (`sign` a select).
//! - A library call passes its arrays by value and writes them back.
//! - A body call runs the callee's statements with the caller's arrays.

use super::*;

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

    pub(super) fn call(
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
