//! # frep-store (being written)
