//! The HyperFun parser (SPEC §2.1, §2.2): source text to [`crate::ast::Program`].
//!
//! A hand-written recursive-descent parser that follows the reference
//! interpreter's grammar (`int_parse_N.c`) exactly, including its quirks:
//!
//! * `+ - | & \ @` share one precedence level (left-assoc), below `* /`,
//!   below `^` (left-assoc: `2^3^2 = 64`), below unary `+ - ~` (so
//!   `-x^2 = (-x)^2`); repeated unary signs (`- -x`, `2^-1`) are accepted,
//!   as by the reference.
//! * Conditions: `and`/`or` share one level (left-assoc), relational
//!   operators chain (`1 < x < 3` = `(1 < x) < 3`), `not` applies to the next
//!   boolean term only, and a term starting with `(` is a parenthesised
//!   *boolean* expression (so `if (x[1]+1)*2 > 0 then` is an error).
//! * All `array` declarations precede all statements; the body ends with
//!   `name = expr;` directly followed by `}` (stored in [`Body::result`],
//!   not in [`Body::stmts`]). An assignment to the body's name anywhere else
//!   is an error, as in the reference.
//! * `x` and `a` are read-only. `s` and the local arrays declared with
//!   `array` are the only targets of [`Stmt::IndexAssign`] and
//!   [`Stmt::ArrayLiteral`] (`name = [±c, ...];`), and they are never the
//!   target of a [`Stmt::Assign`]; any other name assigned is a scalar.
//!   The number of items of a literal is not checked here.
//! * In expressions, `x`, `a` and `s` must be indexed, except as a whole call
//!   argument (`hfSphere(x, c, 1)`), where they are an [`Expr::Ident`]; other
//!   names may be bare ([`Expr::Ident`]), indexed or called — the compiler
//!   resolves them.
//!
//! The parser stops at the first error and reports it as a [`Diagnostic`]
//! with line, column, what was found and what was expected. It never
//! panics, and its recursion and the height of the produced syntax trees
//! are bounded by [`ParseLimits::max_depth`]: consumers may walk any tree it
//! returns recursively without overflowing the stack.

use std::collections::{HashMap, HashSet};

use crate::ast::{ArrayDecl, BinaryOp, Body, Expr, Ident, Program, Size, Stmt, UnaryOp};
use crate::diag::{Diagnostic, Span};
use crate::lexer::{Lexer, Token, TokenKind};

/// Limits that keep parsing bounded on hostile input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParseLimits {
    /// Maximum nesting: the height of any expression tree (operator chains
    /// included, so `1+1+...+1` with more terms is rejected), and the
    /// nesting of parentheses, unary operators, `not`, `if` and `while`.
    pub max_depth: usize,
    /// Maximum source length in bytes.
    pub max_source_bytes: usize,
}

impl Default for ParseLimits {
    fn default() -> Self {
        ParseLimits {
            max_depth: 256,
            max_source_bytes: 16 << 20,
        }
    }
}

/// Parses a whole `.hf` source with the default [`ParseLimits`].
pub fn parse(source: &str) -> Result<Program, Diagnostic> {
    parse_with(source, &ParseLimits::default())
}

/// Parses a whole `.hf` source with the given limits.
pub fn parse_with(source: &str, limits: &ParseLimits) -> Result<Program, Diagnostic> {
    if source.len() > limits.max_source_bytes {
        let span = Span {
            start: 0,
            end: 0,
            line: 1,
            col: 1,
        };
        return Err(Diagnostic::new(
            span,
            format!(
                "the source is too large ({} bytes; the limit is {} bytes)",
                source.len(),
                limits.max_source_bytes
            ),
        ));
    }
    let mut p = Parser::new(source, limits);
    p.program().map_err(|d| *d)
}

type PResult<T> = Result<T, Box<Diagnostic>>;

/// An expression (boxed, to keep stack frames small) with the height of its tree.
type HExpr = (Box<Expr>, usize);

/// Where a statement list is, which decides what may end it.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Block {
    /// The body's top level: ends with the result assignment.
    Body,
    /// The `then` branch: ends with `else` or `endif`.
    Then,
    /// The `else` branch: ends with `endif`.
    Else,
    /// A `while` loop: ends with `endloop`.
    Loop,
}

impl Block {
    fn terminators(self) -> &'static str {
        match self {
            Block::Body => "a statement or the result assignment",
            Block::Then => "a statement, `else` or `endif`",
            Block::Else => "a statement or `endif`",
            Block::Loop => "a statement or `endloop`",
        }
    }
}

struct Parser<'a> {
    src: &'a str,
    lexer: Lexer<'a>,
    /// Lookahead buffer (at most two tokens).
    ahead: Vec<Token>,
    /// Span of the last consumed token.
    prev: Span,
    depth: usize,
    max_depth: usize,
    /// Names of the bodies parsed so far.
    body_names: HashMap<String, Span>,
    /// The local arrays declared in the current body.
    local_arrays: HashSet<String>,
}

fn relop(kind: &TokenKind) -> Option<BinaryOp> {
    Some(match kind {
        TokenKind::Lt => BinaryOp::Lt,
        TokenKind::Gt => BinaryOp::Gt,
        TokenKind::Le => BinaryOp::Le,
        TokenKind::Ge => BinaryOp::Ge,
        TokenKind::Assign => BinaryOp::Eq,
        TokenKind::Ne => BinaryOp::Ne,
        _ => return None,
    })
}

/// An arithmetic or set-theoretic binary operator and its precedence.
fn arith_op(kind: &TokenKind) -> Option<(BinaryOp, u8)> {
    Some(match kind {
        TokenKind::Plus => (BinaryOp::Add, 0),
        TokenKind::Minus => (BinaryOp::Sub, 0),
        TokenKind::Pipe => (BinaryOp::Union, 0),
        TokenKind::Amp => (BinaryOp::Inter, 0),
        TokenKind::Backslash => (BinaryOp::Diff, 0),
        TokenKind::At => (BinaryOp::Cart, 0),
        TokenKind::Star => (BinaryOp::Mul, 1),
        TokenKind::Slash => (BinaryOp::Div, 1),
        TokenKind::Caret => (BinaryOp::Pow, 2),
        _ => return None,
    })
}

/// An error result (boxed, to keep the parser's stack frames small).
fn err<T>(d: Diagnostic) -> PResult<T> {
    Err(Box::new(d))
}

/// Round half up, as the reference rounds sizes and indices.
fn round_half_up(v: f64) -> f64 {
    let r = v.ceil();
    if r - v > 0.5 {
        r - 1.0
    } else {
        r
    }
}

impl<'a> Parser<'a> {
    fn new(src: &'a str, limits: &ParseLimits) -> Self {
        Parser {
            src,
            lexer: Lexer::new(src),
            ahead: Vec::with_capacity(2),
            prev: Span::default(),
            depth: 0,
            max_depth: limits.max_depth,
            body_names: HashMap::new(),
            local_arrays: HashSet::new(),
        }
    }

    // ----- token access -------------------------------------------------

    fn fill(&mut self, n: usize) {
        while self.ahead.len() <= n {
            let t = self.lexer.next_token();
            self.ahead.push(t);
        }
    }

    fn peek(&mut self) -> &Token {
        self.fill(0);
        &self.ahead[0]
    }

    fn peek_kind(&mut self) -> &TokenKind {
        &self.peek().kind
    }

    fn peek2_kind(&mut self) -> &TokenKind {
        self.fill(1);
        &self.ahead[1].kind
    }

    fn bump(&mut self) -> Token {
        self.fill(0);
        let t = self.ahead.remove(0);
        self.prev = t.span;
        t
    }

    fn at(&mut self, kind: &TokenKind) -> bool {
        self.peek_kind() == kind
    }

    fn eat(&mut self, kind: &TokenKind) -> bool {
        if self.at(kind) {
            self.bump();
            true
        } else {
            false
        }
    }

    /// How the current token is described in a diagnostic.
    fn describe(&mut self) -> String {
        let src = self.src;
        let t = self.peek();
        match &t.kind {
            TokenKind::Num(_) => {
                let text = src.get(t.span.start..t.span.end).unwrap_or("?");
                format!("number `{text}`")
            }
            k => k.describe(),
        }
    }

    /// "unexpected X" at the current token, or the lexical error there.
    fn unexpected(&mut self, expected: impl Into<String>) -> Box<Diagnostic> {
        self.unexpected_msg(String::new(), expected)
    }

    /// Like [`Self::unexpected`], with a hint appended to the message.
    fn unexpected_msg(&mut self, hint: String, expected: impl Into<String>) -> Box<Diagnostic> {
        let found = self.describe();
        let t = self.peek();
        match &t.kind {
            TokenKind::Error(d) => d.clone(),
            TokenKind::Str(_) => Diagnostic::new(
                t.span,
                format!(
                    "unexpected {found}: string literals are not allowed in HyperFun models{hint}"
                ),
            )
            .expected(expected)
            .into(),
            _ => Diagnostic::new(t.span, format!("unexpected {found}{hint}"))
                .expected(expected)
                .into(),
        }
    }

    fn expect(&mut self, kind: &TokenKind, expected: &str) -> PResult<Token> {
        if self.at(kind) {
            Ok(self.bump())
        } else {
            Err(self.unexpected(expected))
        }
    }

    // ----- depth control --------------------------------------------------

    fn too_deep(&self, span: Span) -> Box<Diagnostic> {
        Diagnostic::new(
            span,
            format!(
                "nesting is too deep (the limit is {} levels)",
                self.max_depth
            ),
        )
        .expected("a simpler expression or fewer nested statements")
        .into()
    }

    fn enter(&mut self, span: Span) -> PResult<()> {
        if self.depth >= self.max_depth {
            return Err(self.too_deep(span));
        }
        self.depth += 1;
        Ok(())
    }

    fn leave(&mut self) {
        self.depth = self.depth.saturating_sub(1);
    }

    fn check_height(&self, height: usize, span: Span) -> PResult<()> {
        if height > self.max_depth {
            Err(self.too_deep(span))
        } else {
            Ok(())
        }
    }

    fn binary(&self, op: BinaryOp, span: Span, lhs: HExpr, rhs: HExpr) -> PResult<HExpr> {
        let height = 1 + lhs.1.max(rhs.1);
        self.check_height(height, span)?;
        Ok((
            Box::new(Expr::Binary {
                op,
                lhs: lhs.0,
                rhs: rhs.0,
                span,
            }),
            height,
        ))
    }

    // ----- program and bodies --------------------------------------------

    fn program(&mut self) -> PResult<Program> {
        let mut bodies: Vec<Body> = Vec::new();
        loop {
            match self.peek_kind() {
                TokenKind::Eof => break,
                TokenKind::Ident(_) => {}
                _ => {
                    let expected = "a body name (e.g. `my_model(x[3], a[1]) { ... }`)";
                    return Err(self.unexpected(if bodies.is_empty() {
                        expected.to_string()
                    } else {
                        format!("{expected} or the end of the file")
                    }));
                }
            }
            let body = self.body()?;
            bodies.push(body);
        }
        if bodies.is_empty() {
            let span = self.peek().span;
            return err(
                Diagnostic::new(span, "the model is empty: it defines no body")
                    .expected("a body such as `my_model(x[3], a[1]) { my_model = ...; }`"),
            );
        }
        Ok(Program { bodies })
    }

    fn ident(&mut self, expected: &str) -> PResult<Ident> {
        let t = self.peek().clone();
        match t.kind {
            TokenKind::Ident(name) => {
                self.bump();
                Ok(Ident { name, span: t.span })
            }
            _ => Err(self.unexpected(expected)),
        }
    }

    /// `[` NUM `]` of a header or an array declaration.
    fn size(&mut self, of: &str) -> PResult<Size> {
        self.expect(&TokenKind::LBracket, &format!("`[` after `{of}`"))?;
        let t = self.peek().clone();
        let TokenKind::Num(value) = t.kind else {
            return Err(self.unexpected(format!("the size of `{of}` (a number)")));
        };
        self.bump();
        self.expect(&TokenKind::RBracket, "`]`")?;
        Ok(Size {
            value,
            span: t.span,
        })
    }

    fn header_array(&mut self, kind: TokenKind, name: &str) -> PResult<Size> {
        self.expect(&kind, &format!("`{name}`"))?;
        self.size(name)
    }

    fn body(&mut self) -> PResult<Body> {
        let name = self.ident("a body name")?;
        if let Some(prev) = self.body_names.get(&name.name) {
            return err(Diagnostic::new(
                name.span,
                format!(
                    "body name `{}` is not unique (already defined at line {}, column {})",
                    name.name, prev.line, prev.col
                ),
            )
            .expected("a new body name"));
        }
        self.body_names.insert(name.name.clone(), name.span);
        self.expect(&TokenKind::LParen, "`(` after the body name")?;
        let x_size = self.header_array(TokenKind::X, "x")?;
        self.expect(&TokenKind::Comma, "`,`")?;
        let a_size = self.header_array(TokenKind::A, "a")?;
        let s_size = if self.eat(&TokenKind::Comma) {
            Some(self.header_array(TokenKind::S, "s")?)
        } else {
            None
        };
        self.expect(
            &TokenKind::RParen,
            if s_size.is_some() {
                "`)`"
            } else {
                "`,` or `)`"
            },
        )?;
        self.expect(&TokenKind::LBrace, "`{`")?;

        let mut arrays = Vec::new();
        while self.eat(&TokenKind::Array) {
            loop {
                let name = self.ident("an array name")?;
                let size = self.size(&name.name)?;
                let rounded = round_half_up(size.value);
                if rounded.is_nan() || rounded < 1.0 {
                    return err(Diagnostic::new(
                        size.span,
                        format!("the size of array `{}` must be at least 1", name.name),
                    )
                    .expected("a positive array size"));
                }
                arrays.push(ArrayDecl { name, size });
                if !self.eat(&TokenKind::Comma) {
                    break;
                }
            }
            self.expect(&TokenKind::Semi, "`,` or `;`")?;
        }

        self.local_arrays = arrays.iter().map(|d| d.name.name.clone()).collect();
        let mut stmts = Vec::new();
        let (result_span, result) = loop {
            if let Some(target) = self.result_target(&name) {
                self.bump();
                self.expect(&TokenKind::Assign, "`=` (the result assignment)")?;
                let (value, _) = self.expr()?;
                self.semicolon()?;
                if self.at(&TokenKind::RBrace) {
                    break (target, value);
                }
                return Err(self.unexpected_msg(
                    format!(
                        " after the result assignment `{} = ...;`, which must be the last statement of the body",
                        name.name
                    ),
                    "`}`",
                ));
            }
            if !self.statement(&name, Block::Body, &mut stmts)? {
                return Err(self.body_statement_error(&name));
            }
        };
        let close = self.bump(); // the `}` seen above
        Ok(Body {
            span: name.span.to(close.span),
            name,
            x_size,
            a_size,
            s_size,
            arrays,
            stmts,
            result: *result,
            result_span,
        })
    }

    /// The error when the current token neither starts a statement nor the
    /// result assignment at the top level of a body.
    #[cold]
    #[inline(never)]
    fn body_statement_error(&mut self, name: &Ident) -> Box<Diagnostic> {
        let span = self.peek().span;
        if self.at(&TokenKind::RBrace) {
            Diagnostic::new(
                span,
                format!("body `{}` has no result assignment before `}}`", name.name),
            )
            .expected(format!("`{} = expression;`", name.name))
            .into()
        } else if self.at(&TokenKind::Array) {
            Diagnostic::new(
                span,
                "`array` declarations must come before all statements of the body",
            )
            .expected(format!("a statement or `{} = expression;`", name.name))
            .into()
        } else {
            self.unexpected(format!(
                "a statement or the result assignment `{} = ...;`",
                name.name
            ))
        }
    }

    /// The span of the current token if it is the body's own name.
    fn result_target(&mut self, body: &Ident) -> Option<Span> {
        let t = self.peek();
        match &t.kind {
            TokenKind::Ident(n) if *n == body.name => Some(t.span),
            _ => None,
        }
    }

    // ----- statements -------------------------------------------------------

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
    fn statement(&mut self, body: &Ident, block: Block, out: &mut Vec<Stmt>) -> PResult<bool> {
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
    fn semicolon(&mut self) -> PResult<()> {
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

    /// bexpr := cmp { (and|or) cmp }
    fn bexpr(&mut self) -> PResult<HExpr> {
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
    fn expr(&mut self) -> PResult<HExpr> {
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

#[cfg(test)]
mod tests;
