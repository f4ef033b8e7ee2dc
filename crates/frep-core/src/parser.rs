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

mod expr;
mod stmt;

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
}

#[cfg(test)]
mod tests;
