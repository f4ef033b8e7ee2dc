//! # frep-wasm
//!
//! The frep kernel for the browser (mode 4): parse and compile with
//! diagnostics, evaluate, polygonize and generate the ray-casting shader.
//! It is the same Rust as the server: frep-core, frep-mesh without exports
//! or threads, frep-glsl. So no model semantics are copied into TypeScript.
//! This crate is bindings only: [`kernel`] calls the kernel crates, and
//! [`abi`] exposes those calls to JavaScript.
//!
//! ## Why a raw ABI, not wasm-bindgen
//! wasm-bindgen needs its CLI at a version matching the crate to the patch
//! level, installed on every machine that builds. The interface here is a
//! dozen functions over bytes. A raw `extern "C"` ABI needs no tool beyond
//! `cargo` and the `wasm32-unknown-unknown` target (`scripts/build-wasm.sh`).
//! There is no wasm-opt step: Debian's breaks its output. Its TypeScript side
//! (`web/src/wasm/kernel.ts`) is one small file.
//!
//! ## Protocol
//! * The caller gets input buffers with `frep_alloc(len)` (8-aligned),
//!   writes UTF-8 / JSON / f64 into them, calls, and frees them with
//!   `frep_dealloc(ptr, len)`.
//! * Each call leaves its output in one result buffer, valid until the next
//!   call: `frep_result_ptr()`, `frep_result_len()`. Memory may grow during
//!   a call: views of `memory.buffer` are re-made after each call.
//! * The calls:
//!   - `frep_compile(src, len, opts, len) -> handle` (0: errors; result:
//!     JSON with `diagnostics`);
//!   - `frep_free_model(handle)`, `frep_outputs(handle)`;
//!   - `frep_eval_points(handle, xyz, n, params, m) -> outputs` (result:
//!     f64);
//!   - `frep_eval_point(handle, x, y, z, params, m)` (0 values, 1 runtime
//!     error message);
//!   - `frep_polygonize(handle, json, len)` (result: [`buffers`] mesh);
//!   - `frep_shader(handle, json, len)` (result: frep-wire's
//!     `ShaderArtefact` JSON).
//! * A negative status means the result holds an error message.
//!
//! Build: `scripts/build-wasm.sh` (`+simd128`, release, into
//! `web/public/frep.wasm`). The module runs in a Web Worker
//! (`web/src/wasm/kernel.worker.ts`).
#![warn(missing_docs)]

// The ABI reads the caller's buffers through raw pointers: the only unsafe
// code of the crate, confined to this module.
#[allow(unsafe_code)]
pub mod abi;
pub mod buffers;
pub mod kernel;

pub use kernel::{CallError, CompileRequest, Compiled, Kernel, MeshRequest, ShaderRequest};
