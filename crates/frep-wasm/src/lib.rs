//! # frep-wasm (being written)
