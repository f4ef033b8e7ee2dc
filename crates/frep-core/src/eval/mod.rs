//! Evaluators of a [`Tape`](crate::Tape).
