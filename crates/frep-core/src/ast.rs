//! The syntax tree of a HyperFun program, as the parser produces it.
//!
//! The tree is purely syntactic: names are not resolved (a bare identifier
//! may be a scalar variable, a local array, `x`, `a` or `s`; a call may name
//! a built-in, a library function or another body). The compiler resolves
//! them and reports semantic errors with the spans kept here.
//! All identifiers are lower-cased by the lexer (HyperFun is case-insensitive).

use crate::diag::Span;

/// A whole `.hf` file: one or more bodies.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// The bodies in source order (a body may call only bodies above it).
    pub bodies: Vec<Body>,
}

/// An identifier, lower-cased, with its span.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ident {
    /// The lower-cased name.
    pub name: String,
    /// Where it is written.
    pub span: Span,
}

/// `name(x[N], a[M] [, s[K]]) { arrays; statements; name = expr; }`
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// The body's name.
    pub name: Ident,
    /// Declared size of `x` (the number written, before rounding).
    pub x_size: Size,
    /// Declared size of `a`.
    pub a_size: Size,
    /// Declared size of `s`, if the header has `s[K]`.
    pub s_size: Option<Size>,
    /// Local array declarations (`array c[3], v[3];`).
    pub arrays: Vec<ArrayDecl>,
    /// The statements before the final assignment.
    pub stmts: Vec<Stmt>,
    /// The final `name = expr;` (its value is the body's value).
    pub result: Expr,
    /// Span of the final assignment's target (the body name written again).
    pub result_span: Span,
    /// The whole body, header to closing brace.
    pub span: Span,
}

/// A declared array size, as written (a number literal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Size {
    /// The literal's value (the reference rounds it half up; it must be >= 1).
    pub value: f64,
    /// Where it is written.
    pub span: Span,
}

/// `name[N]` in an `array` declaration.
#[derive(Clone, Debug, PartialEq)]
pub struct ArrayDecl {
    /// The array's name.
    pub name: Ident,
    /// Its size.
    pub size: Size,
}

/// A statement.
#[derive(Clone, Debug, PartialEq)]
pub enum Stmt {
    /// `name = expr;` (scalar; declared on its first assignment).
    Assign {
        /// The variable.
        target: Ident,
        /// The value.
        value: Expr,
    },
    /// `name = [c1, c2, ...];` — whole-array literal of signed constants
    /// (`name` may be `s` or a local array).
    ArrayLiteral {
        /// The array.
        target: Ident,
        /// The constants, signs applied.
        values: Vec<f64>,
        /// The bracketed list.
        span: Span,
    },
    /// `name[index] = expr;` (`name` may be `s` or a local array).
    IndexAssign {
        /// The array.
        target: Ident,
        /// The index expression (rounded half up at run time).
        index: Expr,
        /// The value.
        value: Expr,
    },
    /// `if cond then ... [else ...] endif;`
    If {
        /// The condition (a boolean expression).
        cond: Expr,
        /// Statements of the `then` branch.
        then_branch: Vec<Stmt>,
        /// Statements of the `else` branch (empty when absent).
        else_branch: Vec<Stmt>,
        /// The `if` keyword.
        span: Span,
    },
    /// `while cond loop ... endloop;`
    While {
        /// The condition.
        cond: Expr,
        /// The loop body.
        body: Vec<Stmt>,
        /// The `while` keyword.
        span: Span,
    },
}

/// Unary operators.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum UnaryOp {
    /// `+e`
    Plus,
    /// `-e`
    Minus,
    /// `~e` (set complement; identical to `-e`)
    Tilde,
    /// `not e` (in conditions)
    Not,
}

/// Binary operators, arithmetic, set-theoretic, relational and logical.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// `+`
    Add,
    /// `-`
    Sub,
    /// `*`
    Mul,
    /// `/`
    Div,
    /// `^`
    Pow,
    /// `|` R-union
    Union,
    /// `&` R-intersection
    Inter,
    /// `\` R-difference
    Diff,
    /// `@` Cartesian product (the reference computes it as `&`)
    Cart,
    /// `<`
    Lt,
    /// `>`
    Gt,
    /// `<=`
    Le,
    /// `>=`
    Ge,
    /// `=` in a condition
    Eq,
    /// `/=`
    Ne,
    /// `and`
    And,
    /// `or`
    Or,
}

/// An expression.
#[derive(Clone, Debug, PartialEq)]
pub enum Expr {
    /// A number literal (no sign: unary minus is an operator).
    Num {
        /// Its value as the reference computes it.
        value: f64,
        /// Where it is written.
        span: Span,
    },
    /// A bare identifier: a scalar variable, or an array name (`x`, `a`,
    /// `s` or a local array) when used as a call argument.
    Ident(Ident),
    /// `name[index]`
    Index {
        /// The array (`x`, `a`, `s` or a local array).
        array: Ident,
        /// The index expression.
        index: Box<Expr>,
        /// The whole indexing expression.
        span: Span,
    },
    /// A unary operation.
    Unary {
        /// The operator.
        op: UnaryOp,
        /// Its operand.
        expr: Box<Expr>,
        /// The operator token.
        span: Span,
    },
    /// A binary operation.
    Binary {
        /// The operator.
        op: BinaryOp,
        /// Left operand.
        lhs: Box<Expr>,
        /// Right operand.
        rhs: Box<Expr>,
        /// The operator token.
        span: Span,
    },
    /// `name(args)`: a built-in, a library function or a body.
    Call {
        /// The callee's name.
        name: Ident,
        /// Arguments in source order.
        args: Vec<Expr>,
        /// The whole call.
        span: Span,
    },
}

impl Expr {
    /// The span of the expression (for a binary or unary operation, its operator).
    pub fn span(&self) -> Span {
        match self {
            Expr::Num { span, .. }
            | Expr::Index { span, .. }
            | Expr::Unary { span, .. }
            | Expr::Binary { span, .. }
            | Expr::Call { span, .. } => *span,
            Expr::Ident(id) => id.span,
        }
    }
}
