//! Declaration checks done before a body runs: every name is read after
//! its first assignment, arrays are declared once, and no variable takes a
//! function's name.

use super::*;

/// The reference declares a variable when its first assignment is parsed:
/// a name read textually before any assignment is an error, as is an
/// unknown name.
pub(super) fn check_declarations(program: &Program, body: &Body) -> Result<(), Diagnostic> {
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
