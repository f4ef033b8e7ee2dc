//! Expressions by precedence, loosest first: `and`/`or`, comparisons, the
//! binary operators by binding power (`+ - | & \ @`, then `* /`, then `^`),
//! unary operators, then primaries (numbers, names, indexing, calls,
//! parentheses).

use super::*;

impl Parser<'_> {
    /// bexpr := cmp { (and|or) cmp }
    pub(super) fn bexpr(&mut self) -> PResult<HExpr> {
        let span = self.peek().span;
        self.enter(span)?;
        let mut lhs = self.cmp()?;
        loop {
            let op = match self.peek_kind() {
                TokenKind::And => BinaryOp::And,
                TokenKind::Or => BinaryOp::Or,
                _ => break,
            };
            let span = self.bump().span;
            let rhs = self.cmp()?;
            lhs = self.binary(op, span, lhs, rhs)?;
        }
        self.leave();
        Ok(lhs)
    }

    /// cmp := bterm { relop bterm }
    fn cmp(&mut self) -> PResult<HExpr> {
        let mut lhs = self.bterm()?;
        while let Some(op) = relop(self.peek_kind()) {
            let span = self.bump().span;
            let rhs = self.bterm()?;
            lhs = self.binary(op, span, lhs, rhs)?;
        }
        Ok(lhs)
    }

    /// bterm := 'not' bterm | '(' bexpr ')' | expr
    fn bterm(&mut self) -> PResult<HExpr> {
        match self.peek_kind() {
            TokenKind::Not => {
                let span = self.bump().span;
                self.enter(span)?;
                let (e, h) = self.bterm()?;
                self.leave();
                self.check_height(h + 1, span)?;
                Ok((
                    Box::new(Expr::Unary {
                        op: UnaryOp::Not,
                        expr: e,
                        span,
                    }),
                    h + 1,
                ))
            }
            TokenKind::LParen => {
                self.bump();
                let e = self.bexpr()?;
                self.expect(
                    &TokenKind::RParen,
                    "`)` (a condition starting with `(` is a parenthesised condition)",
                )?;
                Ok(e)
            }
            _ => self.expr(),
        }
    }

    // ----- arithmetic -------------------------------------------------------

    /// expr := term { (+|-|'|'|&|\|@) term }; term := factor { (*|/) factor };
    /// factor := unary { ^ unary } — all left-associative, parsed by
    /// precedence climbing (few stack frames per nesting level).
    pub(super) fn expr(&mut self) -> PResult<HExpr> {
        let span = self.peek().span;
        self.enter(span)?;
        let e = self.binops(0)?;
        self.leave();
        Ok(e)
    }

    /// Binary operators of precedence `min` (0: additive, 1: `* /`, 2: `^`) and above.
    fn binops(&mut self, min: u8) -> PResult<HExpr> {
        let mut lhs = self.unary()?;
        while let Some((op, prec)) = arith_op(self.peek_kind()) {
            if prec < min {
                break;
            }
            let span = self.bump().span;
            let rhs = self.binops(prec + 1)?;
            lhs = self.binary(op, span, lhs, rhs)?;
        }
        Ok(lhs)
    }

    /// unary := (+|-|~) unary | primary
    fn unary(&mut self) -> PResult<HExpr> {
        let op = match self.peek_kind() {
            TokenKind::Plus => UnaryOp::Plus,
            TokenKind::Minus => UnaryOp::Minus,
            TokenKind::Tilde => UnaryOp::Tilde,
            _ => return self.primary(),
        };
        let span = self.bump().span;
        self.enter(span)?;
        let (e, h) = self.unary()?;
        self.leave();
        self.check_height(h + 1, span)?;
        Ok((Box::new(Expr::Unary { op, expr: e, span }), h + 1))
    }

    fn primary(&mut self) -> PResult<HExpr> {
        match self.peek_kind() {
            TokenKind::Num(_) => Ok((Box::new(self.number()), 1)),
            TokenKind::LParen => self.paren(),
            TokenKind::X | TokenKind::A | TokenKind::S => self.xas_item(),
            TokenKind::Ident(_) => self.name_expr(),
            _ => Err(self.primary_error()),
        }
    }

    fn number(&mut self) -> Expr {
        let t = self.bump();
        let value = match t.kind {
            TokenKind::Num(v) => v,
            _ => f64::NAN,
        };
        Expr::Num {
            value,
            span: t.span,
        }
    }

    fn paren(&mut self) -> PResult<HExpr> {
        self.bump();
        let e = self.expr()?;
        self.expect(&TokenKind::RParen, "`)`")?;
        Ok(e)
    }

    /// `x[...]`, `a[...]` or `s[...]`.
    fn xas_item(&mut self) -> PResult<HExpr> {
        let t = self.bump();
        let name = t.kind.symbol();
        if !self.at(&TokenKind::LBracket) {
            return Err(self.bare_array_error(name));
        }
        let array = Ident {
            name: name.to_string(),
            span: t.span,
        };
        self.index(array)
    }

    /// A variable, an array item or a call.
    fn name_expr(&mut self) -> PResult<HExpr> {
        let t = self.bump();
        let name = match t.kind {
            TokenKind::Ident(n) => n,
            _ => String::new(),
        };
        let id = Ident { name, span: t.span };
        match self.peek_kind() {
            TokenKind::LBracket => self.index(id),
            TokenKind::LParen => self.call(id),
            _ => Ok((Box::new(Expr::Ident(id)), 1)),
        }
    }

    #[cold]
    #[inline(never)]
    fn bare_array_error(&mut self, name: &str) -> Box<Diagnostic> {
        self.unexpected_msg(
            format!(" after `{name}` (a bare array name is allowed only as a function argument)"),
            format!("`[` (an item such as `{name}[1]`)"),
        )
    }

    #[cold]
    #[inline(never)]
    fn primary_error(&mut self) -> Box<Diagnostic> {
        match self.peek_kind() {
            TokenKind::Not | TokenKind::And | TokenKind::Or => self.unexpected_msg(
                " (logical operators are allowed only in `if` and `while` conditions)".to_string(),
                "an expression",
            ),
            TokenKind::Xor => self.unexpected_msg(
                " (`xor` is a reserved word that HyperFun does not implement)".to_string(),
                "an expression",
            ),
            _ => self.unexpected("an expression"),
        }
    }

    /// `[ expr ]` after an array name.
    fn index(&mut self, array: Ident) -> PResult<HExpr> {
        self.bump(); // `[`
        let (index, h) = self.expr()?;
        let close = self.expect(&TokenKind::RBracket, "`]`")?;
        let span = array.span.to(close.span);
        self.check_height(h + 1, span)?;
        Ok((Box::new(Expr::Index { array, index, span }), h + 1))
    }

    /// `( args )` after a function or body name.
    fn call(&mut self, name: Ident) -> PResult<HExpr> {
        self.bump(); // `(`
        let mut args = Vec::new();
        let mut height = 1;
        if !self.at(&TokenKind::RParen) {
            loop {
                let (arg, h) = self.argument()?;
                height = height.max(h + 1);
                args.push(*arg);
                if !self.eat(&TokenKind::Comma) {
                    break;
                }
            }
        }
        let close = self.expect(&TokenKind::RParen, "`,` or `)`")?;
        let span = name.span.to(close.span);
        self.check_height(height, span)?;
        Ok((Box::new(Expr::Call { name, args, span }), height))
    }

    /// A call argument: an expression, or a bare `x`, `a` or `s`.
    fn argument(&mut self) -> PResult<HExpr> {
        let t = self.peek().clone();
        if matches!(t.kind, TokenKind::X | TokenKind::A | TokenKind::S)
            && matches!(self.peek2_kind(), TokenKind::Comma | TokenKind::RParen)
        {
            self.bump();
            let id = Ident {
                name: t.kind.symbol().to_string(),
                span: t.span,
            };
            return Ok((Box::new(Expr::Ident(id)), 1));
        }
        self.expr()
    }
}
