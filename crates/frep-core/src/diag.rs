//! Diagnostics: errors in a model's source text, each with a line and a column.
//!
//! Every error the lexer, parser or compiler reports is a [`Diagnostic`]. It
//! carries a [`Span`] (byte range plus 1-based line and column), a message, and
//! optionally what was expected. [`Diagnostic::render`] shows the source line
//! with a caret under the offending text.

/// A range of the source text.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Span {
    /// Byte offset of the first character.
    pub start: usize,
    /// Byte offset one past the last character.
    pub end: usize,
    /// 1-based line of `start`.
    pub line: u32,
    /// 1-based column (in characters) of `start`.
    pub col: u32,
}

impl Span {
    /// A span covering both `self` and `other` (line/column of the earlier one).
    pub fn to(self, other: Span) -> Span {
        if other.start < self.start {
            return other.to(self);
        }
        Span {
            start: self.start,
            end: self.end.max(other.end),
            line: self.line,
            col: self.col,
        }
    }
}

/// One error in a model's source.
///
/// Its text is the message, then `, expected ...` when that is known.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message}{}", expected_suffix(.expected))]
pub struct Diagnostic {
    /// Where the error is.
    pub span: Span,
    /// What is wrong, e.g. "unknown function `hfSpere`".
    pub message: String,
    /// What was expected instead, e.g. "`;`", when that is known.
    pub expected: Option<String>,
}

impl Diagnostic {
    /// A diagnostic with a message and no expectation.
    pub fn new(span: Span, message: impl Into<String>) -> Self {
        Diagnostic {
            span,
            message: message.into(),
            expected: None,
        }
    }

    /// Adds what was expected.
    pub fn expected(mut self, what: impl Into<String>) -> Self {
        self.expected = Some(what.into());
        self
    }

    /// Renders the diagnostic with the source line and a caret, e.g.
    ///
    /// ```text
    /// error: 3:14: unexpected `)`, expected an expression
    ///   |
    /// 3 |   f = sqrt(x[1] + );
    ///   |              ^
    /// ```
    pub fn render(&self, source: &str, file: Option<&str>) -> String {
        let line_text = source
            .split('\n')
            .nth(self.span.line.saturating_sub(1) as usize)
            .unwrap_or("")
            .trim_end_matches('\r');
        let num = self.span.line.to_string();
        let pad = " ".repeat(num.len());
        let col = self.span.col.max(1) as usize;
        // Width of the caret: the span's characters on this line, at least one.
        let line_start = source[..self.span.start.min(source.len())]
            .rfind('\n')
            .map_or(0, |i| i + 1);
        let line_end = line_start + line_text.len();
        let end = self
            .span
            .end
            .clamp(self.span.start, line_end.max(self.span.start));
        let width = source
            .get(self.span.start.min(source.len())..end.min(source.len()))
            .map_or(1, |s| s.chars().count().max(1));
        // Keep tabs so the caret lines up under them.
        let indent: String = line_text
            .chars()
            .take(col - 1)
            .map(|c| if c == '\t' { '\t' } else { ' ' })
            .collect();
        let location = match file {
            Some(f) => format!("{f}:{}:{}", self.span.line, self.span.col),
            None => format!("{}:{}", self.span.line, self.span.col),
        };
        format!(
            "error: {location}: {self}\n{pad} |\n{num} | {line_text}\n{pad} | {indent}{}\n",
            "^".repeat(width)
        )
    }
}

/// `, expected X` when `X` is known, else nothing.
fn expected_suffix(expected: &Option<String>) -> String {
    expected
        .as_ref()
        .map_or_else(String::new, |e| format!(", expected {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn render_points_at_column() {
        let src = "a\n  bad = ;\n";
        let d = Diagnostic::new(
            Span {
                start: 10,
                end: 11,
                line: 2,
                col: 9,
            },
            "unexpected `;`",
        )
        .expected("an expression");
        let r = d.render(src, Some("m.hf"));
        assert!(r.starts_with("error: m.hf:2:9: unexpected `;`, expected an expression"));
        assert!(r.contains("2 |   bad = ;\n"));
        assert!(r.contains("  |         ^\n"), "{r}");
    }
}
