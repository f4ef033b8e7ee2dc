//! The HyperFun lexer (SPEC §1).
//!
//! Turns source text into [`Token`]s on demand. Identifiers and reserved
//! words are case-insensitive: identifiers come out lower-cased. `--`
//! comments run to the end of the line and are skipped.
//!
//! Number values are computed with exactly the reference scanner's arithmetic
//! (`int_scanner.c`), so that constants are bit-identical to the reference:
//! - the integer part is accumulated as `v = v*10 + d`;
//! - each fraction digit adds `d / t`, where `t` starts at 10 and is
//!   multiplied by 10 per digit;
//! - an exponent multiplies by `exp(e * ln 10)`.
//!
//! The exponent itself is accumulated as the reference does it: `e = sign *
//! d1`, then `e = e*10 + d` for every further digit. So the reference
//! mis-reads a negative exponent of several digits: `1e-12` is `1e-8` there
//! (`-1*10 + 2 = -8`). This quirk is **replicated** for bit-compatibility.
//!
//! # Deliberate deviations from the reference scanner (leniency)
//!
//! * `'\r'` is whitespace (the reference rejects CRLF files on Linux).
//! * Numbers with leading zeros (`01`, `007.5`) are accepted, with their
//!   natural value.
//! * Exponents starting with `0` are accepted (`1e0`, `1e05`, `1e-05`): the
//!   leading zeros of the exponent are skipped, then the reference arithmetic
//!   above is applied to the remaining digits (`1e-05` = `1e-5`; an
//!   all-zero exponent multiplies by `exp(0) = 1`).
//! * Comments, identifiers and strings may be of any length (the reference
//!   limits them to 255 characters).
//! * Identifiers are never classified as built-in/library function names
//!   here: every name lexes as an identifier and the compiler resolves it.

use crate::diag::{Diagnostic, Span};

/// The kind of a token.
#[derive(Clone, Debug, PartialEq)]
pub enum TokenKind {
    /// A number literal and its value (no sign).
    Num(f64),
    /// An identifier that is not a reserved word, lower-cased.
    Ident(String),
    /// A string literal `"..."` (contents without the quotes). The grammar
    /// accepts none; it exists to give a clear error.
    Str(String),
    /// `x`
    X,
    /// `a`
    A,
    /// `s`
    S,
    /// `array`
    Array,
    /// `if`
    If,
    /// `then`
    Then,
    /// `else`
    Else,
    /// `endif`
    EndIf,
    /// `while`
    While,
    /// `loop`
    Loop,
    /// `endloop`
    EndLoop,
    /// `and`
    And,
    /// `or`
    Or,
    /// `not`
    Not,
    /// `xor` (reserved by the reference, never accepted by its grammar)
    Xor,
    /// `^`
    Caret,
    /// `+`
    Plus,
    /// `-`
    Minus,
    /// `~`
    Tilde,
    /// `/`
    Slash,
    /// `*`
    Star,
    /// `&`
    Amp,
    /// `|`
    Pipe,
    /// `\`
    Backslash,
    /// `@`
    At,
    /// `,`
    Comma,
    /// `;`
    Semi,
    /// `=`
    Assign,
    /// `(`
    LParen,
    /// `)`
    RParen,
    /// `[`
    LBracket,
    /// `]`
    RBracket,
    /// `{`
    LBrace,
    /// `}`
    RBrace,
    /// `<`
    Lt,
    /// `<=`
    Le,
    /// `>`
    Gt,
    /// `>=`
    Ge,
    /// `/=`
    Ne,
    /// End of the source.
    Eof,
    /// A lexical error; the lexer returns [`TokenKind::Eof`] after it.
    Error(Box<Diagnostic>),
}

impl TokenKind {
    /// A short English description for diagnostics, e.g. "`then`",
    /// "identifier `foo`", "end of file".
    pub fn describe(&self) -> String {
        match self {
            TokenKind::Num(v) => format!("number `{v}`"),
            TokenKind::Ident(n) => format!("identifier `{n}`"),
            TokenKind::Str(s) => format!("string \"{}\"", s.escape_debug()),
            TokenKind::Eof => "end of file".to_string(),
            TokenKind::Error(d) => d.message.clone(),
            other => format!("`{}`", other.symbol()),
        }
    }

    /// The fixed spelling of a keyword or punctuation token ("" for the others).
    pub fn symbol(&self) -> &'static str {
        use TokenKind::*;
        match self {
            X => "x",
            A => "a",
            S => "s",
            Array => "array",
            If => "if",
            Then => "then",
            Else => "else",
            EndIf => "endif",
            While => "while",
            Loop => "loop",
            EndLoop => "endloop",
            And => "and",
            Or => "or",
            Not => "not",
            Xor => "xor",
            Caret => "^",
            Plus => "+",
            Minus => "-",
            Tilde => "~",
            Slash => "/",
            Star => "*",
            Amp => "&",
            Pipe => "|",
            Backslash => "\\",
            At => "@",
            Comma => ",",
            Semi => ";",
            Assign => "=",
            LParen => "(",
            RParen => ")",
            LBracket => "[",
            RBracket => "]",
            LBrace => "{",
            RBrace => "}",
            Lt => "<",
            Le => "<=",
            Gt => ">",
            Ge => ">=",
            Ne => "/=",
            Num(_) | Ident(_) | Str(_) | Eof | Error(_) => "",
        }
    }
}

/// A token with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// What it is.
    pub kind: TokenKind,
    /// Where it is.
    pub span: Span,
}

/// An on-demand lexer over a source string.
#[derive(Clone, Debug)]
pub struct Lexer<'a> {
    src: &'a str,
    pos: usize,
    line: u32,
    col: u32,
    finished: bool,
}

/// The reserved word spelled `word` (lower case), if it is one.
fn keyword(word: &str) -> Option<TokenKind> {
    use TokenKind::*;
    Some(match word {
        "x" => X,
        "a" => A,
        "s" => S,
        "array" => Array,
        "if" => If,
        "then" => Then,
        "else" => Else,
        "endif" => EndIf,
        "while" => While,
        "loop" => Loop,
        "endloop" => EndLoop,
        "and" => And,
        "or" => Or,
        "not" => Not,
        "xor" => Xor,
        _ => return None,
    })
}

/// The value of a number literal, computed as the reference scanner does.
///
/// `int_digits` and `frac_digits` are ASCII digits (either may be empty);
/// `exponent` is the exponent's sign (true = negative) and digits.
pub fn number_value(int_digits: &[u8], frac_digits: &[u8], exponent: Option<(bool, &[u8])>) -> f64 {
    let mut v = 0.0_f64;
    for &d in int_digits {
        v = v * 10.0 + f64::from(d - b'0');
    }
    let mut t = 10.0_f64;
    for &d in frac_digits {
        v += f64::from(d - b'0') / t;
        t *= 10.0;
    }
    if let Some((negative, digits)) = exponent {
        // Leniency: skip the exponent's leading zeros (rejected by the reference).
        let first_nonzero = digits
            .iter()
            .position(|&d| d != b'0')
            .unwrap_or(digits.len());
        let digits = &digits[first_nonzero..];
        let mut e = 0.0_f64;
        if let Some((&first, rest)) = digits.split_first() {
            e = if negative { -1.0 } else { 1.0 } * f64::from(first - b'0');
            for &d in rest {
                e = e * 10.0 + f64::from(d - b'0');
            }
        }
        v *= (e * std::f64::consts::LN_10).exp();
    }
    v
}

impl<'a> Lexer<'a> {
    /// A lexer at the start of `src`.
    pub fn new(src: &'a str) -> Self {
        Lexer {
            src,
            pos: 0,
            line: 1,
            col: 1,
            finished: false,
        }
    }

    fn peek_byte(&self, ahead: usize) -> Option<u8> {
        self.src.as_bytes().get(self.pos + ahead).copied()
    }

    /// Advances over one ASCII byte on the current line.
    fn bump(&mut self) {
        self.pos += 1;
        self.col = self.col.saturating_add(1);
    }

    fn span_from(&self, start: usize, line: u32, col: u32) -> Span {
        Span {
            start,
            end: self.pos,
            line,
            col,
        }
    }

    /// Skips whitespace and comments.
    fn skip_trivia(&mut self) {
        while let Some(b) = self.peek_byte(0) {
            match b {
                b'\n' => {
                    self.pos += 1;
                    self.line = self.line.saturating_add(1);
                    self.col = 1;
                }
                b' ' | b'\t' | b'\r' => self.bump(),
                b'-' if self.peek_byte(1) == Some(b'-') => {
                    // A comment: skip to the end of the line (not the newline).
                    let rest = &self.src[self.pos..];
                    let len = rest.find('\n').unwrap_or(rest.len());
                    let chars = rest[..len].chars().count();
                    self.pos += len;
                    self.col = self
                        .col
                        .saturating_add(u32::try_from(chars).unwrap_or(u32::MAX));
                }
                _ => break,
            }
        }
    }

    /// The next token; [`TokenKind::Eof`] forever at the end or after an error.
    pub fn next_token(&mut self) -> Token {
        if self.finished {
            return Token {
                kind: TokenKind::Eof,
                span: self.span_from(self.pos, self.line, self.col),
            };
        }
        self.skip_trivia();
        let (start, line, col) = (self.pos, self.line, self.col);
        let Some(b) = self.peek_byte(0) else {
            self.finished = true;
            return Token {
                kind: TokenKind::Eof,
                span: self.span_from(start, line, col),
            };
        };
        let kind = match b {
            b'0'..=b'9' | b'.' => self.number(),
            b'a'..=b'z' | b'A'..=b'Z' => self.word(),
            b'"' => self.string(),
            _ => self.punct(),
        };
        if matches!(kind, TokenKind::Error(_)) {
            self.finished = true;
        }
        Token {
            kind,
            span: self.span_from(start, line, col),
        }
    }

    fn error(&self, start: usize, line: u32, col: u32, msg: String, expected: &str) -> TokenKind {
        let span = Span {
            start,
            end: self.pos.max(start),
            line,
            col,
        };
        TokenKind::Error(Box::new(Diagnostic::new(span, msg).expected(expected)))
    }

    fn digits(&mut self) -> &'a [u8] {
        let start = self.pos;
        while matches!(self.peek_byte(0), Some(b'0'..=b'9')) {
            self.bump();
        }
        &self.src.as_bytes()[start..self.pos]
    }

    fn number(&mut self) -> TokenKind {
        let (start, line, col) = (self.pos, self.line, self.col);
        let int_digits = self.digits();
        let mut frac_digits: &[u8] = &[];
        if self.peek_byte(0) == Some(b'.') {
            self.bump();
            frac_digits = self.digits();
            if int_digits.is_empty() && frac_digits.is_empty() {
                return self.error(
                    start,
                    line,
                    col,
                    "malformed number: `.` is not followed by a digit".to_string(),
                    "a digit after `.`",
                );
            }
        }
        let mut exponent = None;
        if matches!(self.peek_byte(0), Some(b'e' | b'E')) {
            self.bump();
            let mut negative = false;
            match self.peek_byte(0) {
                Some(b'-') => {
                    negative = true;
                    self.bump();
                }
                Some(b'+') => self.bump(),
                _ => {}
            }
            let exp_digits = self.digits();
            if exp_digits.is_empty() {
                let text = &self.src[start..self.pos];
                return self.error(
                    start,
                    line,
                    col,
                    format!("malformed number `{text}`: the exponent has no digits"),
                    "digits after the exponent mark",
                );
            }
            exponent = Some((negative, exp_digits));
        }
        TokenKind::Num(number_value(int_digits, frac_digits, exponent))
    }

    fn word(&mut self) -> TokenKind {
        let start = self.pos;
        while matches!(
            self.peek_byte(0),
            Some(b'a'..=b'z' | b'A'..=b'Z' | b'0'..=b'9' | b'_')
        ) {
            self.bump();
        }
        let name = self.src[start..self.pos].to_ascii_lowercase();
        keyword(&name).unwrap_or(TokenKind::Ident(name))
    }

    fn string(&mut self) -> TokenKind {
        let (start, line, col) = (self.pos, self.line, self.col);
        self.bump(); // opening quote
        let rest = &self.src[self.pos..];
        match rest.find(['"', '\n']) {
            Some(len) if rest.as_bytes()[len] == b'"' => {
                let text = &rest[..len];
                self.pos += len + 1;
                let chars = u32::try_from(text.chars().count()).unwrap_or(u32::MAX);
                self.col = self.col.saturating_add(chars).saturating_add(1);
                TokenKind::Str(text.to_string())
            }
            other => {
                let len = other.unwrap_or(rest.len());
                let chars = u32::try_from(rest[..len].chars().count()).unwrap_or(u32::MAX);
                self.pos += len;
                self.col = self.col.saturating_add(chars);
                self.error(
                    start,
                    line,
                    col,
                    "unterminated string".to_string(),
                    "a closing `\"` on the same line",
                )
            }
        }
    }

    fn punct(&mut self) -> TokenKind {
        use TokenKind::*;
        let (start, line, col) = (self.pos, self.line, self.col);
        let Some(b) = self.peek_byte(0) else {
            return Eof;
        };
        let next = self.peek_byte(1);
        let (kind, len) = match (b, next) {
            (b'/', Some(b'=')) => (Ne, 2),
            (b'<', Some(b'=')) => (Le, 2),
            (b'>', Some(b'=')) => (Ge, 2),
            (b'^', _) => (Caret, 1),
            (b'+', _) => (Plus, 1),
            (b'-', _) => (Minus, 1),
            (b'~', _) => (Tilde, 1),
            (b'/', _) => (Slash, 1),
            (b'*', _) => (Star, 1),
            (b'&', _) => (Amp, 1),
            (b'|', _) => (Pipe, 1),
            (b'\\', _) => (Backslash, 1),
            (b'@', _) => (At, 1),
            (b',', _) => (Comma, 1),
            (b';', _) => (Semi, 1),
            (b'=', _) => (Assign, 1),
            (b'(', _) => (LParen, 1),
            (b')', _) => (RParen, 1),
            (b'[', _) => (LBracket, 1),
            (b']', _) => (RBracket, 1),
            (b'{', _) => (LBrace, 1),
            (b'}', _) => (RBrace, 1),
            (b'<', _) => (Lt, 1),
            (b'>', _) => (Gt, 1),
            _ => {
                let c = self.src[self.pos..].chars().next().unwrap_or('\u{FFFD}');
                self.pos += c.len_utf8();
                self.col = self.col.saturating_add(1);
                let shown = if c.is_control() || c.is_whitespace() {
                    format!("{}", c.escape_unicode())
                } else {
                    format!("`{c}`")
                };
                return self.error(
                    start,
                    line,
                    col,
                    format!("unknown character {shown} (U+{:04X})", u32::from(c)),
                    "an operator, a name, a number or a comment",
                );
            }
        };
        for _ in 0..len {
            self.bump();
        }
        kind
    }
}

#[cfg(test)]
mod tests;
