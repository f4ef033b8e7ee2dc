//! The errors of frep-core, and the error policy of the whole workspace.
//!
//! # Policy
//! - Libraries return narrow `thiserror` types: one enum (or struct) per
//!   kind of failure, never a boxed or string error.
//! - Only binaries (the `frep` command, the server's `main`) use `anyhow`.
//!   They add context at their edge and print the chain once.
//! - Library code does not panic on bad input. An `unwrap` or `expect`
//!   carries a comment that says why it cannot fail.
//! - Messages are stable text: tests and the studio compare them.
//!
//! # frep-core's errors
//! - [`Diagnostic`](crate::diag::Diagnostic): an error in a model's source,
//!   with its line and column (lexer, parser, compiler).
//! - [`EvalError`]: a runtime error of the reference interpreter at one
//!   point. Re-exported as `ops::EvalError`.
//! - [`LibError`]: wrong arguments to a library function, found while
//!   compiling. Re-exported as `library::LibError`; the compiler turns it
//!   into a [`Diagnostic`](crate::diag::Diagnostic) at the argument's span.

/// A runtime error of the reference interpreter, reported per point.
///
/// Its text is the reference interpreter's message, see
/// [`EvalError::message`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, thiserror::Error)]
#[error("{}", self.message())]
pub enum EvalError {
    /// A variable read where its assignment was not executed.
    NotInitialized,
    /// `a / b` with `|b| < 1e-6`.
    DivisionByZero,
    /// `b ^ e` with `b < 0` and a non-integer `e`.
    NegativePower,
    /// `b ^ e` with `|b| < 1e-6` and `e <= 1e-6`.
    ZeroPower,
    /// `sqrt` of a negative number.
    NegativeSqrt,
    /// `log`/`logd` of a number `<= 0`.
    NegativeLog,
    /// `asin`/`acos` of a number outside `[-1, 1]`.
    ArgumentRange,
    /// `tan` where `|cos| < 1e-6`.
    Tan,
    /// An array index outside `1..=size`.
    IndexOutOfRange,
    /// An array with unassigned items passed to a function.
    UnassignedItems,
}

impl EvalError {
    /// The reference interpreter's message for this error.
    pub fn message(self) -> &'static str {
        match self {
            EvalError::NotInitialized => "Not initialized variable",
            EvalError::DivisionByZero => "Division by zero",
            EvalError::NegativePower => "Negative value for power",
            EvalError::ZeroPower => "Zero value in negative or zero power",
            EvalError::NegativeSqrt => "Negative value for square root",
            EvalError::NegativeLog => "Negative for log function",
            EvalError::ArgumentRange => "Argument must be in range -1.0 .. +1.0",
            EvalError::Tan => "Cannot compute tan for this argument",
            EvalError::IndexOutOfRange => "Array index out of range",
            EvalError::UnassignedItems => "Some items of array are unassigned",
        }
    }

    /// Every error kind (for exhaustive tests).
    pub const ALL: [EvalError; 10] = [
        EvalError::NotInitialized,
        EvalError::DivisionByZero,
        EvalError::NegativePower,
        EvalError::ZeroPower,
        EvalError::NegativeSqrt,
        EvalError::NegativeLog,
        EvalError::ArgumentRange,
        EvalError::Tan,
        EvalError::IndexOutOfRange,
        EvalError::UnassignedItems,
    ];
}

/// A compile-time error in the arguments of a call (wrong array size etc.),
/// reported by the compiler at the span of argument `arg` (0-based).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("argument {}: {message}", .arg + 1)]
pub struct LibError {
    /// The 0-based index of the offending argument.
    pub arg: usize,
    /// What is wrong.
    pub message: String,
}

#[cfg(test)]
mod tests {
    use super::{EvalError, LibError};

    #[test]
    fn display_is_the_reference_message() {
        for e in EvalError::ALL {
            assert_eq!(e.to_string(), e.message());
        }
        assert_eq!(EvalError::DivisionByZero.to_string(), "Division by zero");
        let e = LibError {
            arg: 1,
            message: "too short".into(),
        };
        assert_eq!(e.to_string(), "argument 2: too short");
    }
}
