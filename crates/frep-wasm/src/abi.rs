//! The raw WebAssembly ABI: `extern "C"` functions over pointers into the
//! module's linear memory (see the crate docs for the protocol).
//!
//! Inputs are buffers the caller got from [`frep_alloc`] and filled; outputs
//! go to one result buffer per module instance, read through
//! [`frep_result_ptr`] / [`frep_result_len`] until the next call. A
//! WebAssembly instance runs on one thread, so the state lives in a
//! thread-local.
//!
//! The values of [`frep_eval_points`] are the result as they are: its `f64`
//! buffer, kept from one evaluation to the next, so that repeated
//! evaluations neither allocate nor convert (wasm32 is little-endian: the
//! bytes are the `f64`s). Any other result frees that buffer.

use std::alloc::{alloc, dealloc, Layout};
use std::cell::RefCell;

use crate::kernel::{CompileRequest, Kernel, MeshRequest, ShaderRequest};

/// Version of this ABI; the loader refuses a module of another version.
pub const ABI_VERSION: u32 = 1;

/// Alignment of every buffer [`frep_alloc`] gives: enough for `f64`.
const ALIGN: usize = 8;

#[derive(Default)]
struct State {
    kernel: Kernel,
    /// The last call's result, unless `values_current`.
    result: Vec<u8>,
    /// The values of the last evaluation of points.
    values: Vec<f64>,
    /// Whether the last call's result is `values`.
    values_current: bool,
}

thread_local! {
    static STATE: RefCell<State> = RefCell::new(State::default());
}

fn with<R>(f: impl FnOnce(&mut State) -> R) -> R {
    STATE.with(|s| f(&mut s.borrow_mut()))
}

fn set_result(bytes: Vec<u8>) {
    with(|s| {
        s.result = bytes;
        s.values = Vec::new();
        s.values_current = false;
    });
}

/// The result is an error message; returns -1.
fn fail(msg: &str) -> i32 {
    set_result(msg.as_bytes().to_vec());
    -1
}

/// Reads `len` bytes at `ptr` (empty for a null pointer or length 0).
///
/// # Safety
/// `ptr..ptr + len` must be memory the caller owns and does not change during
/// the call (a buffer from [`frep_alloc`]).
unsafe fn bytes<'a>(ptr: *const u8, len: usize) -> &'a [u8] {
    if ptr.is_null() || len == 0 {
        &[]
    } else {
        // SAFETY: the caller's contract above.
        unsafe { std::slice::from_raw_parts(ptr, len) }
    }
}

/// Reads `n` f64 at `ptr`; `None` when misaligned.
///
/// # Safety
/// As `bytes` for `8 n` bytes.
unsafe fn f64s<'a>(ptr: *const f64, n: usize) -> Option<&'a [f64]> {
    if ptr.is_null() || n == 0 {
        return Some(&[]);
    }
    if !ptr.is_aligned() {
        return None;
    }
    // SAFETY: aligned, and the caller's contract above.
    Some(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// JSON options (an empty buffer reads as `{}`).
fn json<T: serde::de::DeserializeOwned>(b: &[u8]) -> Result<T, String> {
    let b: &[u8] = if b.is_empty() { b"{}" } else { b };
    serde_json::from_slice(b).map_err(|e| format!("bad options: {e}"))
}

fn f64_bytes(v: &[f64]) -> Vec<u8> {
    let mut out = Vec::with_capacity(8 * v.len());
    for x in v {
        out.extend_from_slice(&x.to_le_bytes());
    }
    out
}

/// The ABI version ([`ABI_VERSION`]).
#[no_mangle]
pub extern "C" fn frep_abi_version() -> u32 {
    ABI_VERSION
}

/// A buffer of `len` bytes aligned to 8 (null for a length the allocator
/// refuses); give it back with [`frep_dealloc`] and the same length.
#[no_mangle]
pub extern "C" fn frep_alloc(len: usize) -> *mut u8 {
    match Layout::from_size_align(len.max(1), ALIGN) {
        // SAFETY: the layout's size is at least 1.
        Ok(l) => unsafe { alloc(l) },
        Err(_) => std::ptr::null_mut(),
    }
}

/// Frees a buffer of [`frep_alloc`].
///
/// # Safety
/// `ptr` must come from [`frep_alloc`] with this `len`, and not be freed yet.
#[no_mangle]
pub unsafe extern "C" fn frep_dealloc(ptr: *mut u8, len: usize) {
    if ptr.is_null() {
        return;
    }
    if let Ok(l) = Layout::from_size_align(len.max(1), ALIGN) {
        // SAFETY: the caller's contract: allocated with this layout.
        unsafe { dealloc(ptr, l) }
    }
}

/// Where the last call's result is.
#[no_mangle]
pub extern "C" fn frep_result_ptr() -> *const u8 {
    with(|s| {
        if s.values_current {
            s.values.as_ptr().cast()
        } else {
            s.result.as_ptr()
        }
    })
}

/// The last call's result's length in bytes.
#[no_mangle]
pub extern "C" fn frep_result_len() -> usize {
    with(|s| {
        if s.values_current {
            std::mem::size_of_val(s.values.as_slice())
        } else {
            s.result.len()
        }
    })
}

/// Compiles a source (UTF-8) with JSON options ([`CompileRequest`]). The
/// result is the [`crate::kernel::Compiled`] JSON. Returns the handle, or 0
/// when the model has errors. It is also 0 when the input is not UTF-8 or
/// the options are bad; the result is then a JSON `{"ok":false,"error":…}`.
///
/// # Safety
/// The buffers as in the crate docs (from `frep_alloc`).
#[no_mangle]
pub unsafe extern "C" fn frep_compile(
    src: *const u8,
    src_len: usize,
    opts: *const u8,
    opts_len: usize,
) -> u32 {
    // SAFETY: the caller's contract.
    let (src, opts) = unsafe { (bytes(src, src_len), bytes(opts, opts_len)) };
    let parsed = std::str::from_utf8(src)
        .map_err(|_| "the source is not UTF-8".to_string())
        .and_then(|s| json::<CompileRequest>(opts).map(|o| (s, o)));
    let (source, req) = match parsed {
        Ok(p) => p,
        Err(e) => {
            let body = serde_json::json!({ "ok": false, "error": e });
            set_result(body.to_string().into_bytes());
            return 0;
        }
    };
    let compiled = with(|s| s.kernel.compile(source, &req));
    let text = serde_json::to_vec(&compiled).unwrap_or_default();
    set_result(text);
    compiled.handle
}

/// Forgets a model: 1 when it was there, 0 otherwise.
#[no_mangle]
pub extern "C" fn frep_free_model(handle: u32) -> i32 {
    i32::from(with(|s| s.kernel.free(handle)))
}

/// Number of outputs of the model (value, then attributes), -1 for a bad
/// handle (message in the result).
#[no_mangle]
pub extern "C" fn frep_outputs(handle: u32) -> i32 {
    match with(|s| s.kernel.outputs(handle)) {
        Ok(k) => k as i32,
        Err(e) => fail(&e.0),
    }
}

/// Evaluates `n` points given planar (`3n` f64: all x, all y, all z) with
/// `n_params` parameters; the result is `k·n` f64, output-major, NaN for an
/// error (little-endian, 8-aligned). Returns `k`, or -1 (message in the
/// result).
///
/// # Safety
/// The buffers as in the crate docs (from `frep_alloc`), 8-aligned.
#[no_mangle]
pub unsafe extern "C" fn frep_eval_points(
    handle: u32,
    xyz: *const f64,
    n: usize,
    params: *const f64,
    n_params: usize,
) -> i32 {
    // SAFETY: the caller's contract.
    let (Some(xyz), Some(params)) = (unsafe { f64s(xyz, 3 * n) }, unsafe {
        f64s(params, n_params)
    }) else {
        return fail("misaligned buffer: f64 needs 8-byte alignment");
    };
    // Into the kept buffer: no allocation when the size repeats.
    let r = with(|s| {
        let r = s.kernel.eval_points(handle, xyz, params, &mut s.values);
        s.values_current = r.is_ok();
        if s.values_current {
            s.result = Vec::new();
        }
        r
    });
    match r {
        Ok(k) => k as i32,
        Err(e) => fail(&e.0),
    }
}

/// Evaluates one point with the reference interpreter's errors: 0 with the
/// outputs (f64) in the result, 1 with the runtime error's message in the
/// result, -1 for a bad call.
///
/// # Safety
/// The parameter buffer as in the crate docs (from `frep_alloc`), 8-aligned.
#[no_mangle]
pub unsafe extern "C" fn frep_eval_point(
    handle: u32,
    x: f64,
    y: f64,
    z: f64,
    params: *const f64,
    n_params: usize,
) -> i32 {
    // SAFETY: the caller's contract.
    let Some(params) = (unsafe { f64s(params, n_params) }) else {
        return fail("misaligned buffer: f64 needs 8-byte alignment");
    };
    match with(|s| s.kernel.eval_point(handle, [x, y, z], params)) {
        Ok(Ok(vals)) => {
            set_result(f64_bytes(&vals));
            0
        }
        Ok(Err(msg)) => {
            set_result(msg.into_bytes());
            1
        }
        Err(e) => fail(&e.0),
    }
}

/// Polygonizes with JSON settings ([`MeshRequest`]); 0 with the packed mesh
/// ([`crate::buffers`]) in the result, -1 with a message.
///
/// # Safety
/// The buffer as in the crate docs (from `frep_alloc`).
#[no_mangle]
pub unsafe extern "C" fn frep_polygonize(handle: u32, opts: *const u8, opts_len: usize) -> i32 {
    // SAFETY: the caller's contract.
    let opts = unsafe { bytes(opts, opts_len) };
    let req = match json::<MeshRequest>(opts) {
        Ok(r) => r,
        Err(e) => return fail(&e),
    };
    match with(|s| s.kernel.polygonize(handle, &req)) {
        Ok(b) => {
            set_result(b);
            0
        }
        Err(e) => fail(&e.0),
    }
}

/// The ray-casting shader with JSON options ([`ShaderRequest`]); 0 with
/// frep-wire's `ShaderArtefact` JSON in the result, -1 with a message.
///
/// # Safety
/// The buffer as in the crate docs (from `frep_alloc`).
#[no_mangle]
pub unsafe extern "C" fn frep_shader(handle: u32, opts: *const u8, opts_len: usize) -> i32 {
    // SAFETY: the caller's contract.
    let opts = unsafe { bytes(opts, opts_len) };
    let req = match json::<ShaderRequest>(opts) {
        Ok(r) => r,
        Err(e) => return fail(&e),
    };
    match with(|s| s.kernel.shader(handle, &req)) {
        Ok(a) => match serde_json::to_vec(&a) {
            Ok(b) => {
                set_result(b);
                0
            }
            Err(e) => fail(&e.to_string()),
        },
        Err(e) => fail(&e.0),
    }
}
