//! Statements: assignments, array literals, `if` and `while` blocks, with
//! the reference's error messages for what it rejects.

use super::*;

impl Parser<'_> {
    /// Statements until one that does not start a statement.
    fn statements(&mut self, body: &Ident, block: Block) -> PResult<Vec<Stmt>> {
        let mut out = Vec::new();
        while self.statement(body, block, &mut out)? {}
        // What ends the block is checked by the caller; give a clear error for
        // the result assignment written inside a block.
        if self.result_target(body).is_some() {
            return Err(self.result_in_block_error(body, block));
        }
        Ok(out)
    }

    #[cold]
    #[inline(never)]
    fn result_in_block_error(&mut self, body: &Ident, block: Block) -> Box<Diagnostic> {
        let span = self.peek().span;
        Box::new(
            Diagnostic::new(
                span,
                format!(
                    "the result assignment `{} = ...;` must be the last statement of the body, not inside `if` or `while`",
                    body.name
                ),
            )
            .expected(block.terminators()),
        )
    }

    #[cold]
    #[inline(never)]
    fn read_only_error(&mut self, block: Block) -> Box<Diagnostic> {
        let t = self.peek();
        let name = t.kind.symbol();
        Box::new(
            Diagnostic::new(
                t.span,
                format!("`{name}` is read-only: it cannot be assigned"),
            )
            .expected(block.terminators()),
        )
    }

    /// Parses one statement into `out`; returns false (consuming nothing) if
    /// the current token does not start one. The body's own name does not
    /// start one. Statements are pushed rather than returned to keep the
    /// stack frames of nested `if`/`while` small.
    pub(super) fn statement(
        &mut self,
        body: &Ident,
        block: Block,
        out: &mut Vec<Stmt>,
    ) -> PResult<bool> {
        match self.peek_kind() {
            TokenKind::If => self.if_stmt(body, out)?,
            TokenKind::While => self.while_stmt(body, out)?,
            TokenKind::X | TokenKind::A => return Err(self.read_only_error(block)),
            TokenKind::S => {
                let t = self.bump();
                let target = Ident {
                    name: "s".to_string(),
                    span: t.span,
                };
                self.assignment(target, out)?;
            }
            TokenKind::Ident(n) if *n != body.name => {
                let t = self.bump();
                let name = match t.kind {
                    TokenKind::Ident(n) => n,
                    _ => String::new(),
                };
                let target = Ident { name, span: t.span };
                self.assignment(target, out)?;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// After the target name: `= expr;`, `= [list];` or `[index] = expr;`.
    fn assignment(&mut self, target: Ident, out: &mut Vec<Stmt>) -> PResult<()> {
        // `s` and the declared local arrays take items or whole literals; any
        // other name is a scalar variable.
        let is_array = target.name == "s" || self.local_arrays.contains(&target.name);
        let stmt = match self.peek_kind() {
            TokenKind::LBracket if is_array => {
                self.bump();
                let (index, _) = self.expr()?;
                self.expect(&TokenKind::RBracket, "`]`")?;
                self.expect(&TokenKind::Assign, "`=`")?;
                let (value, _) = self.expr()?;
                Stmt::IndexAssign {
                    target,
                    index: *index,
                    value: *value,
                }
            }
            TokenKind::Assign => {
                self.bump();
                if is_array {
                    if !self.at(&TokenKind::LBracket) {
                        return Err(self.whole_array_error(&target));
                    }
                    let (values, span) = self.array_literal()?;
                    Stmt::ArrayLiteral {
                        target,
                        values,
                        span,
                    }
                } else {
                    if self.at(&TokenKind::LBracket) {
                        return Err(self.not_an_array_error(&target, "a list"));
                    }
                    let (value, _) = self.expr()?;
                    Stmt::Assign {
                        target,
                        value: *value,
                    }
                }
            }
            TokenKind::LBracket => return Err(self.not_an_array_error(&target, "an item")),
            _ if is_array => return Err(self.unexpected("`[` or `=`")),
            _ => return Err(self.unexpected("`=`")),
        };
        self.semicolon()?;
        out.push(stmt);
        Ok(())
    }

    #[cold]
    #[inline(never)]
    fn whole_array_error(&mut self, target: &Ident) -> Box<Diagnostic> {
        let name = &target.name;
        self.unexpected_msg(
            format!(
                " (`{name}` is an array: it is assigned as a whole only from a list of numbers)"
            ),
            format!("`[` (e.g. `{name} = [1, 0, 0];`)"),
        )
    }

    #[cold]
    #[inline(never)]
    fn not_an_array_error(&mut self, target: &Ident, what: &str) -> Box<Diagnostic> {
        let name = &target.name;
        Diagnostic::new(
            target.span,
            format!("`{name}` is not a declared array: {what} cannot be assigned to it"),
        )
        .expected(format!(
            "an `array {name}[size];` declaration at the start of the body"
        ))
        .into()
    }

    /// The `;` ending an assignment, with a hint when a condition operator
    /// was written in an arithmetic expression.
    pub(super) fn semicolon(&mut self) -> PResult<()> {
        if self.eat(&TokenKind::Semi) {
            return Ok(());
        }
        let k = self.peek_kind();
        let hint = if relop(k).is_some()
            || matches!(
                k,
                TokenKind::And | TokenKind::Or | TokenKind::Not | TokenKind::Xor
            ) {
            " (relational and logical operators are allowed only in `if` and `while` conditions)"
        } else {
            ""
        };
        Err(self.unexpected_msg(hint.to_string(), "`;`"))
    }

    /// `[ ±NUM {, ±NUM} ]`.
    fn array_literal(&mut self) -> PResult<(Vec<f64>, Span)> {
        let open = self.bump();
        let mut values = Vec::new();
        loop {
            let negative = match self.peek_kind() {
                TokenKind::Minus => {
                    self.bump();
                    true
                }
                TokenKind::Plus => {
                    self.bump();
                    false
                }
                _ => false,
            };
            let t = self.peek().clone();
            let TokenKind::Num(v) = t.kind else {
                return Err(self.unexpected(
                    "a number (array literals hold optionally signed number constants only)",
                ));
            };
            self.bump();
            values.push(if negative { -v } else { v });
            if !self.eat(&TokenKind::Comma) {
                break;
            }
        }
        let close = self.expect(&TokenKind::RBracket, "`,` or `]`")?;
        Ok((values, open.span.to(close.span)))
    }

    fn if_stmt(&mut self, body: &Ident, out: &mut Vec<Stmt>) -> PResult<()> {
        let span = self.bump().span;
        self.enter(span)?;
        let cond = self.bexpr()?.0;
        self.expect(&TokenKind::Then, "`then`")?;
        let then_branch = self.statements(body, Block::Then)?;
        let else_branch = if self.eat(&TokenKind::Else) {
            let b = self.statements(body, Block::Else)?;
            self.expect(&TokenKind::EndIf, Block::Else.terminators())?;
            b
        } else {
            self.expect(&TokenKind::EndIf, Block::Then.terminators())?;
            Vec::new()
        };
        self.expect(&TokenKind::Semi, "`;` after `endif`")?;
        self.leave();
        out.push(Stmt::If {
            cond: *cond,
            then_branch,
            else_branch,
            span,
        });
        Ok(())
    }

    fn while_stmt(&mut self, body: &Ident, out: &mut Vec<Stmt>) -> PResult<()> {
        let span = self.bump().span;
        self.enter(span)?;
        let cond = self.bexpr()?.0;
        self.expect(&TokenKind::Loop, "`loop`")?;
        let stmts = self.statements(body, Block::Loop)?;
        self.expect(&TokenKind::EndLoop, Block::Loop.terminators())?;
        self.expect(&TokenKind::Semi, "`;` after `endloop`")?;
        self.leave();
        out.push(Stmt::While {
            cond: *cond,
            body: stmts,
            span,
        });
        Ok(())
    }

    // ----- conditions -------------------------------------------------------
}
