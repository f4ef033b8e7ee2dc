//! The cost model: for one mode and its settings, the predicted time to
//! first display, time per orbit frame and latency of a parameter edit, or
//! a refusal with a reason.
//!
//! ## The model
//! Every prediction is a sum of stages, each from a measurement when there
//! is one and from a constant below otherwise:
//!
//! * **server**: ms to compute and encode the artefact, multiplied by the
//!   server's load factor (`1 + (busy + queued) / workers`).
//!   - Measured figures for this model ([`crate::Measured`]) are scaled to
//!     the settings: per pixel, per triangle, per cell.
//!   - Otherwise images cost [`RENDER_MS_PER_MPIX_CLOSED`] per megapixel in
//!     closed form (≈ 3.5 ms at 512²). In general they cost
//!     [`RENDER_MS_PER_MPIX_GENERAL`] × `w` per megapixel: ≈ 21 ms at 512²
//!     for 40 operations, ≈ 57 ms for 300. Encoding adds
//!     [`ENCODE_MS_PER_MPIX`].
//!   - Meshes have [`MESH_TRIANGLES_PER_CELL_FACTOR`] × 4^depth triangles,
//!     since a mesh grows ~4× per octree level. Each costs
//!     [`MESH_SERVER_US_PER_TRIANGLE`] × `w` µs.
//!   - Volumes cost grid³ point evaluations at [`SERVER_MEVALS_PER_S`] / `w`.
//!   - Here `w` = √(tape / [`REFERENCE_TAPE`]) ([`tape_work`]) is the work
//!     per point relative to the reference model. It is sublinear in the
//!     tape length, because interval pruning evaluates only the part of the
//!     tape that matters in each region.
//! * **bytes**:
//!   - JPEG takes [`JPEG_BYTES_PER_PIXEL_Q75`] bytes per pixel at q75 (22 kB
//!     at 512²). That is scaled by quality and, for small views, by
//!     (512² / pixels)^¼: 12 views of 256² ≈ 99 kB.
//!   - WebP takes [`WEBP_BYTES_FACTOR`] of that, for
//!     [`WEBP_EXTRA_ENCODE_MS_PER_MPIX`] more encoding. It is for stills and
//!     view sets only; streamed frames stay JPEG.
//!   - A meshopt glb takes [`MESH_BYTES_PER_TRIANGLE`] bytes per triangle.
//!   - Volumes take [`VOLUME_BYTES_PER_CELL`] per cell (narrow band,
//!     compressed).
//!   - Transfer is bytes × 8 / bandwidth, plus one round trip per request.
//!     An artefact fetched over HTTP after its reference arrives on the
//!     socket takes two.
//! * **code**: a mode's first display also fetches the code the page does
//!   not hold yet ([`code_bytes`]): its own chunk, three.js for the mesh
//!   modes, frep.wasm for 4b ([`MODE_CODE_BYTES`], [`THREE_CODE_BYTES`],
//!   [`WASM_CODE_BYTES`]).
//! * **client**:
//!   - The GPU benchmark `g` is the ms per 256² frame of a reference
//!     ray-marched field of [`REFERENCE_STATEMENTS`] statements. A fixed
//!     [`BENCH_OVERHEAD_MS`] of synchronising is taken off ([`gpu_work_ms`]).
//!   - `g` scales the generated shader's frame:
//!     `g × pixels / 256² × (s + 20) / (ref + 20)` for `s` statements. On a
//!     software renderer it is `g × pixels / 256² × (s + 4) / (ref + 4)`
//!     × [`SOFTWARE_SHADER_FACTOR`]: measured on SwiftShader at 576², the
//!     generated shader costs ~2.5e-5 ms per statement and pixel, 5–6
//!     times the benchmark's (sphere 137 ms, sake_pot 720, android_robot
//!     1450, complex_hemisphere 2600 a full frame, with a 13 ms benchmark).
//!   - Triangles draw at [`TRIANGLES_PER_MS_AT_1MS_BENCH`] / `g` per ms. A
//!     raster fill of [`RASTER_FILL_FRACTION`] of a ray-march pixel is added.
//!   - A software renderer rasterizes on the CPU: its triangles and fill
//!     cost far more against its benchmark
//!     ([`SOFTWARE_TRIANGLES_PER_MS_AT_1MS_BENCH`],
//!     [`SOFTWARE_RASTER_FILL_FRACTION`]). Its every frame has a fixed
//!     [`SOFTWARE_FRAME_BASE_MS`].
//!   - A volume frame is [`VOLUME_MARCH_FACTOR`] × g per 256² pixels ×
//!     grid / 64.
//!   - Shader compilation costs [`COMPILE_BASE_MS`] plus, per statement,
//!     [`COMPILE_MS_PER_STATEMENT_GPU`] (twice that on mobile). SwiftShader
//!     links at once and compiles at the first draw:
//!     [`SOFTWARE_COMPILE_BASE_MS`] plus
//!     [`COMPILE_MS_PER_STATEMENT_SOFTWARE`] per statement (its first frame
//!     took 260–2550 ms more than the next, for 14–303 statements).
//!   - The JS benchmark (`cpu_bench_ms` against [`CPU_BENCH_REFERENCE_MS`])
//!     scales decoding.
//!   - The WASM benchmark (million evaluations per second of a
//!     [`REFERENCE_TAPE`]-op model) scales browser polygonizing, at
//!     [`WASM_EVALS_PER_TRIANGLE`] evaluations per triangle.
//!
//! ## Per mode
//! | mode | first display | orbit frame | edit (parameter drag) |
//! |---|---|---|---|
//! | 1 still | 2 rtt + server image + transfer + decode | (rtt + reduced server frame + transfer + decode) / frames in flight | rtt + reduced frame + transfer + decode |
//! | 2 view set | 2 rtt + every view on the server + transfer + decode | local (~1 ms, fixed views) | the whole set again |
//! | 3 server mesh | 2 rtt + server mesh + transfer + decode + draw | draw | coarse mesh, fetched the same way |
//! | 4a GPU ray casting | 2 rtt + model transfer + compile + frame | frame | one frame (parameters are uniforms) |
//! | 4b WASM mesh | 2 rtt + model transfer + polygonize in WASM + upload + draw | draw | coarse mesh in WASM + draw |
//! | volume | 2 rtt + server slices + transfer + texture upload + frame | frame | the volume again |
//!
//! Missing benchmarks are guessed ([`crate::ClientCaps::from_report`]). A guess
//! is only a first estimate. The corrections learnt from the client's
//! reports ([`crate::Corrections`]) multiply the predictions of each mode.

use frep_wire::{ImageEncoding, Mode, ModePrediction, ModeSettings, NetworkEstimate};
use serde::Serialize;

use crate::client::{uses_three, ClientCaps, Limits};
use crate::correction::{mode_index, Corrections};
use crate::stats::{ModelStats, ServerLoad};

/// Server render ms per megapixel of a closed-form model.
pub const RENDER_MS_PER_MPIX_CLOSED: f64 = 14.0;
/// Server render ms per megapixel of a general model of
/// [`REFERENCE_TAPE`] operations.
pub const RENDER_MS_PER_MPIX_GENERAL: f64 = 80.0;
/// Server JPEG encoding ms per megapixel (8 ms at 512² on 2 cores).
pub const ENCODE_MS_PER_MPIX: f64 = 30.0;
/// JPEG bytes per pixel at quality 75 (22 kB at 512²).
pub const JPEG_BYTES_PER_PIXEL_Q75: f64 = 0.084;
/// WebP size relative to JPEG at the same quality (11 / 22 kB at 512²,
/// 52 / 99 kB for a 12-view turntable).
pub const WEBP_BYTES_FACTOR: f64 = 0.52;
/// WebP's extra encoding ms per megapixel over JPEG (43 vs 8 ms at 512²).
pub const WEBP_EXTRA_ENCODE_MS_PER_MPIX: f64 = 134.0;
/// PNG (fast) bytes per pixel (125 kB at 512²).
pub const PNG_BYTES_PER_PIXEL: f64 = 0.477;
/// Triangles = this × 4^depth. The Table I examples have 4.4–8.4 at depth
/// 7 (a compact solid filling a fair part of its box); a gyroid has ~10.
pub const MESH_TRIANGLES_PER_CELL_FACTOR: f64 = 7.0;
/// Server polygonizing µs per triangle for the reference tape.
pub const MESH_SERVER_US_PER_TRIANGLE: f64 = 2.0;
/// Fixed server ms of any mesh job.
pub const MESH_SERVER_BASE_MS: f64 = 10.0;
/// Quantized meshopt glb bytes per triangle.
pub const MESH_BYTES_PER_TRIANGLE: f64 = 4.5;
/// Server point evaluations (millions per second) of a reference tape.
pub const SERVER_MEVALS_PER_S: f64 = 40.0;
/// Tape length of the benchmarks' reference model.
pub const REFERENCE_TAPE: f64 = 40.0;
/// Compressed bytes per volume cell (8-bit narrow band, brotli).
pub const VOLUME_BYTES_PER_CELL: f64 = 0.1;
/// Pixels of the GPU benchmark's frame (256²).
pub const BENCH_PIXELS: f64 = 65_536.0;
/// Fixed ms of a benchmark frame that does not scale with pixels.
pub const BENCH_OVERHEAD_MS: f64 = 0.2;
/// Statements of the GPU benchmark's reference field.
pub const REFERENCE_STATEMENTS: f64 = 40.0;
/// Triangles per ms drawn by a GPU whose benchmark takes 1 ms.
pub const TRIANGLES_PER_MS_AT_1MS_BENCH: f64 = 5.0e5;
/// Cost of a rasterized pixel relative to a ray-marched one.
pub const RASTER_FILL_FRACTION: f64 = 0.02;
/// Cost of a volume ray-march pixel (64³) relative to the benchmark's.
pub const VOLUME_MARCH_FACTOR: f64 = 0.5;
/// Fixed ms of compiling and linking a generated shader.
pub const COMPILE_BASE_MS: f64 = 40.0;
/// Compile ms per statement on a hardware GPU (all shader flavours).
pub const COMPILE_MS_PER_STATEMENT_GPU: f64 = 0.05;
/// Compile ms per statement on a software renderer.
pub const COMPILE_MS_PER_STATEMENT_SOFTWARE: f64 = 5.0;
/// Fixed ms of compiling a generated shader on a software renderer.
pub const SOFTWARE_COMPILE_BASE_MS: f64 = 250.0;
/// The generated shader's cost per statement and pixel on a software
/// renderer, relative to the GPU benchmark's.
pub const SOFTWARE_SHADER_FACTOR: f64 = 5.5;
/// `cpu_bench_ms` of the reference desktop.
pub const CPU_BENCH_REFERENCE_MS: f64 = 10.0;
/// Client JPEG decode ms per megapixel on the reference desktop.
pub const DECODE_MS_PER_MPIX: f64 = 10.0;
/// Client meshopt decode and upload ms per triangle on the reference
/// desktop (864 k triangles ≈ 86 ms).
pub const MESH_DECODE_MS_PER_TRIANGLE: f64 = 1.0e-4;
/// WASM point evaluations per output triangle of the browser polygonizer.
/// Corners, edge roots and interval work are counted as points. On a 40 Meps
/// desktop that is ~4 µs a triangle, twice the server's native cost.
pub const WASM_EVALS_PER_TRIANGLE: f64 = 150.0;
/// Streamed frames rendering or on their way at once (mode 1): the
/// session's `frames_in_flight` default.
pub const STILL_FRAMES_IN_FLIGHT: f64 = 2.0;
/// Fixed ms of any client frame (the browser's own work).
pub const FRAME_BASE_MS: f64 = 0.5;
/// Fixed ms of a WebGL frame on a software renderer: SwiftShader presents
/// and composites on the CPU. Fitted to its simplest scenes' orbit frames
/// (50–70 ms at 576²), not measured alone.
pub const SOFTWARE_FRAME_BASE_MS: f64 = 20.0;
/// Triangles per ms of a software renderer whose benchmark takes 1 ms.
/// SwiftShader drew sake_pot's 138 k triangles at 576² in 71–99 ms with a
/// 13 ms benchmark (the hardware constant is 20 times this one).
pub const SOFTWARE_TRIANGLES_PER_MS_AT_1MS_BENCH: f64 = 2.5e4;
/// Cost of a rasterized pixel relative to a ray-marched one, in software.
pub const SOFTWARE_RASTER_FILL_FRACTION: f64 = 0.5;
/// Compressed bytes of each mode's own code chunk, in [`Mode::ALL`] order
/// (web/dist, brotli: `still`, `viewset`, `mesh` with GLTFLoader and the
/// meshopt decoder, `raycast*`, `wasmmesh` with the worker, `volume*`).
/// Read off the build of 2026-11-28; they drift with the studio's code.
pub const MODE_CODE_BYTES: [f64; 6] = [2_300.0, 1_900.0, 20_000.0, 6_500.0, 4_900.0, 6_000.0];
/// Compressed bytes of three.js and the shared scene (modes 3 and 4b).
pub const THREE_CODE_BYTES: f64 = 115_000.0;
/// Compressed bytes of the WebAssembly kernel (frep.wasm).
pub const WASM_CODE_BYTES: f64 = 225_000.0;

/// Everything a prediction depends on.
#[derive(Clone, Copy, Debug)]
pub struct Inputs<'a> {
    /// The client.
    pub caps: &'a ClientCaps,
    /// The network.
    pub net: &'a NetworkEstimate,
    /// The model.
    pub stats: &'a ModelStats,
    /// The server's load.
    pub load: ServerLoad,
}

impl Inputs<'_> {
    /// Round trip in ms (at least 0).
    pub fn rtt(&self) -> f64 {
        if self.net.rtt_ms.is_finite() {
            self.net.rtt_ms.max(0.0)
        } else {
            0.0
        }
    }

    /// Bandwidth in bits per second (at least 10 kbit/s).
    pub fn bandwidth(&self) -> f64 {
        if self.net.bandwidth_bps.is_finite() {
            self.net.bandwidth_bps.max(1.0e4)
        } else {
            1.0e4
        }
    }

    /// ms to transfer `bytes`.
    pub fn transfer_ms(&self, bytes: f64) -> f64 {
        bytes * 8.0 / self.bandwidth() * 1000.0
    }
}

/// The prediction for one mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Prediction {
    /// The mode.
    pub mode: Mode,
    /// The settings it was predicted for.
    pub settings: ModeSettings,
    /// Why not, when the client cannot show it (`None`: feasible).
    pub refusal: Option<String>,
    /// Request to first displayed frame, ms (corrected).
    pub first_display_ms: f64,
    /// Per orbit frame, ms (corrected).
    pub orbit_ms: f64,
    /// Parameter change to updated display, ms (corrected).
    pub edit_ms: f64,
    /// Bytes of the first display.
    pub bytes: f64,
    /// First display before correction (what reports are compared with).
    pub raw_first_display_ms: f64,
    /// Orbit frame before correction.
    pub raw_orbit_ms: f64,
}

impl Prediction {
    /// Whether the client can show it.
    pub fn feasible(&self) -> bool {
        self.refusal.is_none()
    }

    /// The wire form, with the engine's score.
    pub fn to_wire(&self, cost: f64) -> ModePrediction {
        let round = |v: f64| (v * 10.0).round() / 10.0;
        ModePrediction {
            mode: self.mode,
            feasible: self.feasible(),
            refusal: self.refusal.clone(),
            first_display_ms: round(self.first_display_ms),
            orbit_ms: round(self.orbit_ms),
            edit_ms: round(self.edit_ms),
            bytes: self.bytes.round(),
            cost: round(cost),
        }
    }
}

/// Stage times of one mode before correction.
struct Raw {
    first: f64,
    orbit: f64,
    edit: f64,
    bytes: f64,
}

/// Predicts one mode with the given settings.
pub fn predict(
    mode: Mode,
    settings: &ModeSettings,
    inputs: &Inputs,
    limits: &Limits,
    corrections: &Corrections,
) -> Prediction {
    let raw = match mode {
        Mode::Still => still(settings, inputs),
        Mode::ViewSet => view_set(settings, inputs),
        Mode::ServerMesh => server_mesh(settings, inputs),
        Mode::GpuRaycast => gpu_raycast(settings, inputs),
        Mode::WasmMesh => wasm_mesh(settings, inputs),
        Mode::Volume => volume(settings, inputs),
    };
    let f = corrections.get(mode);
    let fd = f.first_display.value();
    let orbit = f.orbit.value();
    // A 4a edit is one frame (an orbit-like cost); every other edit redoes
    // the first display's kind of work.
    let edit_factor = if mode == Mode::GpuRaycast { orbit } else { fd };
    let first_display_ms = raw.first * fd;
    let refusal = refusal(mode, inputs, limits).or_else(|| {
        (mode != Mode::Still && first_display_ms > limits.max_first_display_ms).then(|| {
            format!(
                "first display would take ≈ {:.0} s (limit {:.0} s)",
                first_display_ms / 1000.0,
                limits.max_first_display_ms / 1000.0
            )
        })
    });
    Prediction {
        mode,
        settings: settings.clone(),
        refusal,
        first_display_ms,
        orbit_ms: raw.orbit * orbit,
        edit_ms: raw.edit * edit_factor,
        bytes: raw.bytes,
        raw_first_display_ms: raw.first,
        raw_orbit_ms: raw.orbit,
    }
}

/// Why the client cannot use a mode at all, from hard checks.
pub fn refusal(mode: Mode, inputs: &Inputs, limits: &Limits) -> Option<String> {
    let caps = inputs.caps;
    let needs_gl = matches!(
        mode,
        Mode::ServerMesh | Mode::GpuRaycast | Mode::WasmMesh | Mode::Volume
    );
    if needs_gl && !caps.webgl2 {
        return Some("no WebGL2".to_string());
    }
    match mode {
        Mode::GpuRaycast => gpu_refusal(inputs, limits),
        Mode::WasmMesh => {
            if caps.wasm_meps.is_none() {
                return Some("no WebAssembly benchmark (WASM missing or not measured yet)".into());
            }
            match caps.memory_gb {
                Some(gb) if gb < limits.min_memory_gb_wasm => Some(format!(
                    "{gb} GB of device memory (browser meshing needs {} GB)",
                    limits.min_memory_gb_wasm
                )),
                _ => None,
            }
        }
        Mode::Volume if caps.max_3d_texture < limits.min_volume_grid => Some(format!(
            "3D textures limited to {} (volume needs {})",
            caps.max_3d_texture, limits.min_volume_grid
        )),
        _ => None,
    }
}

/// 4a's checks: primitives, statements, compile time.
fn gpu_refusal(inputs: &Inputs, limits: &Limits) -> Option<String> {
    let stats = inputs.stats;
    let prims = stats.primitives_estimate();
    if prims > limits.max_primitives_gpu {
        let how = if stats.primitives.is_some() {
            ""
        } else {
            "about "
        };
        return Some(format!(
            "{how}{prims} primitives: a browser shader is impractical beyond {}",
            limits.max_primitives_gpu
        ));
    }
    let statements = stats.statements();
    if statements > limits.max_statements_gpu {
        return Some(format!(
            "{statements} shader statements: too long for a browser shader (limit {})",
            limits.max_statements_gpu
        ));
    }
    let compile = compile_ms(inputs);
    if compile > limits.max_compile_ms {
        let on = inputs
            .caps
            .renderer_name
            .as_deref()
            .map_or(String::new(), |n| format!(" on {n}"));
        return Some(format!(
            "compiling {statements} shader statements{on} would take ≈ {:.0} s",
            compile / 1000.0
        ));
    }
    None
}

/// Work per point evaluation relative to the reference model's (see the
/// module doc).
pub fn tape_work(stats: &ModelStats) -> f64 {
    (f64::from(stats.tape_len.max(4)) / REFERENCE_TAPE).sqrt()
}

/// Predicted ms to compile the generated shader (to its first frame).
pub fn compile_ms(inputs: &Inputs) -> f64 {
    let caps = inputs.caps;
    let (base, per) = if caps.software {
        (SOFTWARE_COMPILE_BASE_MS, COMPILE_MS_PER_STATEMENT_SOFTWARE)
    } else if caps.mobile {
        (COMPILE_BASE_MS, 2.0 * COMPILE_MS_PER_STATEMENT_GPU)
    } else {
        (COMPILE_BASE_MS, COMPILE_MS_PER_STATEMENT_GPU)
    };
    base + per * f64::from(inputs.stats.statements())
}

/// Server ms to render and encode `pixels` at the current load (a
/// measured image counts as JPEG).
pub fn server_image_ms(inputs: &Inputs, pixels: f64, format: ImageEncoding) -> f64 {
    let stats = inputs.stats;
    let per_mpix = match stats.measured.image {
        Some(s) => s.server_ms / s.pixels as f64 * 1.0e6,
        None => {
            let render = if stats.closed_form {
                RENDER_MS_PER_MPIX_CLOSED
            } else {
                RENDER_MS_PER_MPIX_GENERAL * tape_work(stats)
            };
            render + ENCODE_MS_PER_MPIX
        }
    };
    let extra = match format {
        ImageEncoding::Webp => WEBP_EXTRA_ENCODE_MS_PER_MPIX,
        ImageEncoding::Jpeg | ImageEncoding::Png => 0.0,
    };
    (per_mpix + extra) * pixels / 1.0e6 * inputs.load.factor()
}

/// JPEG size relative to q75, by quality (interpolated).
fn quality_factor(quality: u8) -> f64 {
    const TABLE: [(f64, f64); 7] = [
        (10.0, 0.3),
        (30.0, 0.45),
        (50.0, 0.68),
        (60.0, 0.8),
        (75.0, 1.0),
        (85.0, 1.3),
        (100.0, 3.0),
    ];
    let q = f64::from(quality.clamp(10, 100));
    for w in TABLE.windows(2) {
        let ((q0, f0), (q1, f1)) = (w[0], w[1]);
        if q <= q1 {
            return f0 + (f1 - f0) * (q - q0) / (q1 - q0);
        }
    }
    TABLE[TABLE.len() - 1].1
}

/// Encoded bytes of one image of `pixels` at `quality`.
pub fn image_bytes(inputs: &Inputs, pixels: f64, quality: u8, format: ImageEncoding) -> f64 {
    if format == ImageEncoding::Png {
        return PNG_BYTES_PER_PIXEL * pixels;
    }
    // Small images compress worse per pixel.
    let small = (262_144.0 / pixels.max(1.0)).powf(0.25).clamp(0.7, 2.0);
    let per_pixel = match inputs.stats.measured.image {
        // A measured size carries the model's look (background share...).
        Some(s) => s.bytes as f64 / s.pixels as f64 / quality_factor(s.quality),
        None => JPEG_BYTES_PER_PIXEL_Q75,
    };
    let webp = if format == ImageEncoding::Webp {
        WEBP_BYTES_FACTOR
    } else {
        1.0
    };
    per_pixel * quality_factor(quality) * small * webp * pixels
}

/// Client ms to decode an image of `pixels`.
fn decode_ms(inputs: &Inputs, pixels: f64) -> f64 {
    DECODE_MS_PER_MPIX * pixels / 1.0e6 * inputs.caps.cpu_scale
}

fn pixels(settings: &ModeSettings) -> f64 {
    f64::from(settings.width.max(1)) * f64::from(settings.height.max(1))
}

/// Mode 1: one image per request; orbit frames are reduced images.
fn still(s: &ModeSettings, inputs: &Inputs) -> Raw {
    let px = pixels(s);
    let bytes = image_bytes(inputs, px, s.quality, s.format);
    // One round trip for the open and the artefact's address, one for
    // the image.
    let first = 2.0 * inputs.rtt()
        + server_image_ms(inputs, px, s.format)
        + inputs.transfer_ms(bytes + code_bytes(Mode::Still, inputs.caps))
        + decode_ms(inputs, px);
    let scale = s.moving_scale.max(1.0);
    let mpx = px / (scale * scale);
    // Streamed frames are JPEG whatever the still's format: WebP's encoder
    // is five times slower.
    let mbytes = image_bytes(inputs, mpx, s.moving_quality, ImageEncoding::Jpeg);
    let render = server_image_ms(inputs, mpx, ImageEncoding::Jpeg);
    let transfer = inputs.transfer_ms(mbytes);
    let decode = decode_ms(inputs, mpx);
    let latency = inputs.rtt() + render + transfer + decode;
    // Frames are pipelined: a new one every latency / in flight, unless
    // one stage alone is slower.
    let orbit = (latency / STILL_FRAMES_IN_FLIGHT).max(render.max(transfer).max(decode));
    Raw {
        first,
        orbit,
        // A drag streams reduced frames; each shows after the latency.
        edit: latency,
        bytes,
    }
}

/// Mode 2: a whole set of views fetched over HTTP; orbit is local.
fn view_set(s: &ModeSettings, inputs: &Inputs) -> Raw {
    let count = f64::from(s.views.max(1)) * s.elevations.len().max(1) as f64;
    let px = pixels(s);
    let bytes = image_bytes(inputs, px, s.quality, s.format) * count;
    let work = 2.0 * inputs.rtt()
        + server_image_ms(inputs, px * count, s.format)
        + inputs.transfer_ms(bytes)
        + decode_ms(inputs, px * count);
    Raw {
        first: work + inputs.transfer_ms(code_bytes(Mode::ViewSet, inputs.caps)),
        orbit: FRAME_BASE_MS + 0.5,
        edit: work,
        bytes,
    }
}

/// Triangles of a mesh at `depth`.
pub fn mesh_triangles(stats: &ModelStats, depth: u8) -> f64 {
    let k = match stats.measured.mesh {
        Some(m) if m.triangles > 0 => m.triangles as f64 / 4f64.powi(i32::from(m.depth)),
        _ => MESH_TRIANGLES_PER_CELL_FACTOR,
    };
    k * 4f64.powi(i32::from(depth))
}

/// Server ms to polygonize and encode at `depth`, at the current load.
pub fn server_mesh_ms(inputs: &Inputs, depth: u8) -> f64 {
    let stats = inputs.stats;
    let tris = mesh_triangles(stats, depth);
    let ms = match stats.measured.mesh {
        Some(m) if m.triangles > 0 => m.server_ms * tris / m.triangles as f64,
        _ => {
            let per = MESH_SERVER_US_PER_TRIANGLE * tape_work(stats) / 1000.0;
            MESH_SERVER_BASE_MS + per * tris
        }
    };
    ms * inputs.load.factor()
}

/// Encoded bytes of a mesh at `depth`.
pub fn mesh_bytes(stats: &ModelStats, depth: u8) -> f64 {
    let per = match stats.measured.mesh {
        Some(m) if m.triangles > 0 => m.bytes as f64 / m.triangles as f64,
        _ => MESH_BYTES_PER_TRIANGLE,
    };
    per * mesh_triangles(stats, depth)
}

/// The part of the GPU benchmark's frame that scales with pixels. The
/// measured frame includes a fixed [`BENCH_OVERHEAD_MS`] of synchronising
/// (finish, read back), which dominates on fast GPUs. At least a tenth of
/// the frame counts as work.
pub fn gpu_work_ms(caps: &ClientCaps) -> f64 {
    (caps.gpu_ms - BENCH_OVERHEAD_MS)
        .max(0.1 * caps.gpu_ms)
        .max(1e-4)
}

/// Client ms to draw a frame of `triangles` at `pixels`.
pub fn draw_ms(caps: &ClientCaps, triangles: f64, pixels: f64) -> f64 {
    let g = gpu_work_ms(caps);
    let (per_ms, fill) = if caps.software {
        (
            SOFTWARE_TRIANGLES_PER_MS_AT_1MS_BENCH,
            SOFTWARE_RASTER_FILL_FRACTION,
        )
    } else {
        (TRIANGLES_PER_MS_AT_1MS_BENCH, RASTER_FILL_FRACTION)
    };
    frame_base_ms(caps) + triangles * g / per_ms + g * pixels / BENCH_PIXELS * fill
}

/// Fixed ms of a WebGL frame.
pub fn frame_base_ms(caps: &ClientCaps) -> f64 {
    if caps.software {
        SOFTWARE_FRAME_BASE_MS
    } else {
        FRAME_BASE_MS
    }
}

/// Code bytes `mode`'s first display fetches (what the page lacks).
pub fn code_bytes(mode: Mode, caps: &ClientCaps) -> f64 {
    let code = &caps.code;
    let own = if code.modes[mode_index(mode)] {
        0.0
    } else {
        MODE_CODE_BYTES[mode_index(mode)]
    };
    let three = if uses_three(mode) && !code.three {
        THREE_CODE_BYTES
    } else {
        0.0
    };
    let wasm = if mode == Mode::WasmMesh && !code.wasm {
        WASM_CODE_BYTES
    } else {
        0.0
    };
    own + three + wasm
}

/// Client ms to decode and upload a mesh.
fn mesh_decode_ms(caps: &ClientCaps, triangles: f64) -> f64 {
    MESH_DECODE_MS_PER_TRIANGLE * triangles * caps.cpu_scale
}

/// Mode 3: the full mesh first; a coarse mesh while a parameter drags.
fn server_mesh(s: &ModeSettings, inputs: &Inputs) -> Raw {
    let caps = inputs.caps;
    let stats = inputs.stats;
    let fetch = |depth: u8| {
        let tris = mesh_triangles(stats, depth);
        let bytes = mesh_bytes(stats, depth);
        let ms = 2.0 * inputs.rtt()
            + server_mesh_ms(inputs, depth)
            + inputs.transfer_ms(bytes)
            + mesh_decode_ms(caps, tris);
        (ms, bytes)
    };
    let (first, bytes) = fetch(s.mesh_depth);
    let code = inputs.transfer_ms(code_bytes(Mode::ServerMesh, caps));
    let (edit, _) = fetch(s.coarse_depth.min(s.mesh_depth));
    let draw = draw_ms(
        caps,
        mesh_triangles(stats, s.mesh_depth),
        caps.device_pixels(),
    );
    Raw {
        first: first + code + draw,
        orbit: draw,
        edit: edit + draw,
        bytes,
    }
}

/// Client ms per frame of the generated shader at `pixels`.
pub fn shader_frame_ms(inputs: &Inputs, pixels: f64) -> f64 {
    let s = f64::from(inputs.stats.statements());
    let complexity = if inputs.caps.software {
        (s + 4.0) / (REFERENCE_STATEMENTS + 4.0) * SOFTWARE_SHADER_FACTOR
    } else {
        ((s + 20.0) / (REFERENCE_STATEMENTS + 20.0)).max(0.5)
    };
    frame_base_ms(inputs.caps) + gpu_work_ms(inputs.caps) * pixels / BENCH_PIXELS * complexity
}

/// Mode 4a: the model's shader compiled and ray cast on the client.
fn gpu_raycast(s: &ModeSettings, inputs: &Inputs) -> Raw {
    // The compiled model and its shader source: ~40 bytes per statement.
    let bytes = 2048.0 + 40.0 * f64::from(inputs.stats.statements());
    let frame = shader_frame_ms(inputs, pixels(s));
    Raw {
        first: 2.0 * inputs.rtt()
            + inputs.transfer_ms(bytes + code_bytes(Mode::GpuRaycast, inputs.caps))
            + compile_ms(inputs)
            + frame,
        orbit: frame,
        // A parameter is a uniform: one more frame.
        edit: frame,
        bytes,
    }
}

/// Client ms to polygonize at `depth` in WASM (infinite without WASM).
pub fn wasm_mesh_ms(inputs: &Inputs, depth: u8) -> f64 {
    let Some(meps) = inputs.caps.wasm_meps else {
        return f64::INFINITY;
    };
    let evals =
        mesh_triangles(inputs.stats, depth) * WASM_EVALS_PER_TRIANGLE * tape_work(inputs.stats);
    evals / (meps * 1000.0)
}

/// Mode 4b: the compiled model sent, polygonized in the browser.
fn wasm_mesh(s: &ModeSettings, inputs: &Inputs) -> Raw {
    let caps = inputs.caps;
    let bytes = 2048.0 + 16.0 * f64::from(inputs.stats.tape_len);
    let tris = mesh_triangles(inputs.stats, s.mesh_depth);
    let draw = draw_ms(caps, tris, caps.device_pixels());
    let upload = 0.2 * mesh_decode_ms(caps, tris);
    Raw {
        first: 2.0 * inputs.rtt()
            + inputs.transfer_ms(bytes + code_bytes(Mode::WasmMesh, caps))
            + wasm_mesh_ms(inputs, s.mesh_depth)
            + upload
            + draw,
        orbit: draw,
        edit: wasm_mesh_ms(inputs, s.coarse_depth.min(s.mesh_depth)) + draw,
        bytes,
    }
}

/// Server ms to evaluate and encode a volume of `grid`³ cells.
pub fn server_volume_ms(inputs: &Inputs, grid: u32) -> f64 {
    let cells = f64::from(grid).powi(3);
    let ms = match inputs.stats.measured.volume {
        Some(v) => v.server_ms * cells / f64::from(v.grid).powi(3),
        None => {
            // Evaluation plus compression (~1e-5 ms per cell).
            cells * tape_work(inputs.stats) / (SERVER_MEVALS_PER_S * 1000.0) + cells * 1.0e-5
        }
    };
    ms * inputs.load.factor()
}

/// Encoded bytes of a volume of `grid`³ cells.
pub fn volume_bytes(inputs: &Inputs, grid: u32) -> f64 {
    let cells = f64::from(grid).powi(3);
    match inputs.stats.measured.volume {
        Some(v) => v.bytes as f64 * cells / f64::from(v.grid).powi(3),
        None => cells * VOLUME_BYTES_PER_CELL,
    }
}

/// Client ms per volume frame at `pixels`.
pub fn volume_frame_ms(caps: &ClientCaps, grid: u32, pixels: f64) -> f64 {
    frame_base_ms(caps)
        + gpu_work_ms(caps) * pixels / BENCH_PIXELS * VOLUME_MARCH_FACTOR * f64::from(grid) / 64.0
}

/// Client ms to decompress and upload a 3D texture of `cells` bytes
/// (about a tenth of a mesh triangle's decode per cell).
fn texture_upload_ms(caps: &ClientCaps, cells: f64) -> f64 {
    MESH_DECODE_MS_PER_TRIANGLE * 0.1 * cells * caps.cpu_scale
}

/// Volume mode: slices from the server, ray marched on the client.
fn volume(s: &ModeSettings, inputs: &Inputs) -> Raw {
    let grid = s.volume_grid.max(8);
    let bytes = volume_bytes(inputs, grid);
    let cells = f64::from(grid).powi(3);
    let frame = volume_frame_ms(inputs.caps, grid, pixels(s));
    let work = 2.0 * inputs.rtt()
        + server_volume_ms(inputs, grid)
        + inputs.transfer_ms(bytes)
        + texture_upload_ms(inputs.caps, cells);
    Raw {
        first: work + inputs.transfer_ms(code_bytes(Mode::Volume, inputs.caps)) + frame,
        orbit: frame,
        edit: work + frame,
        bytes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn quality_table_is_monotone_and_anchored() {
        assert!((quality_factor(75) - 1.0).abs() < 1e-12);
        let mut last = 0.0;
        for q in 1..=100u8 {
            let f = quality_factor(q);
            assert!(f >= last, "q{q}");
            last = f;
        }
    }
}
