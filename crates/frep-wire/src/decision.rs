//! The adaptive engine's vocabulary as clients see it: delivery modes, what a
//! client reports of itself, and the decisions pushed to it.

use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// How a model reaches a client's screen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub enum Mode {
    /// 1: a still image rendered on the server (frames streamed while
    /// orbiting).
    Still,
    /// 2: a set of server views the client rotates through.
    ViewSet,
    /// 3: a server mesh drawn with WebGL.
    ServerMesh,
    /// 4a: the generated shader ray casting the model on the client's GPU.
    GpuRaycast,
    /// 4b: the model polygonized in the browser by the WebAssembly kernel.
    WasmMesh,
    /// Image slices (an 8-bit volume) ray marched on the client's GPU.
    Volume,
}

impl Mode {
    /// Every mode, in the paper's order.
    pub const ALL: [Mode; 6] = [
        Mode::Still,
        Mode::ViewSet,
        Mode::ServerMesh,
        Mode::GpuRaycast,
        Mode::WasmMesh,
        Mode::Volume,
    ];
}

/// Screen size as the browser tells it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct Screen {
    /// CSS pixels.
    pub width: u32,
    /// CSS pixels.
    pub height: u32,
    /// `devicePixelRatio`.
    pub pixel_ratio: f64,
}

/// What a client reports of itself at connection and again when it
/// changes. Measurements the browser makes itself (benchmarks, frame rate)
/// are here; the network is measured by the server on the socket.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ClientReport {
    /// `navigator.userAgent`.
    pub user_agent: String,
    /// WebGL2 context available.
    pub webgl2: bool,
    /// Unmasked renderer string (`WEBGL_debug_renderer_info`), if given.
    pub renderer: Option<String>,
    /// `MAX_TEXTURE_SIZE`, `MAX_3D_TEXTURE_SIZE` (0 without WebGL2).
    pub max_texture_size: u32,
    /// 3D texture limit.
    pub max_3d_texture_size: u32,
    /// WebGPU adapter available.
    pub webgpu: bool,
    /// GPU micro-benchmark: ms per frame of a ray-marched reference field at
    /// 256², after the first frame (`None`: not run or no WebGL2).
    pub gpu_bench_ms: Option<f64>,
    /// WASM micro-benchmark: million point evaluations of a reference model
    /// per second (`None`: not run).
    pub wasm_bench_meps: Option<f64>,
    /// JS main-thread speed: ms of a fixed reference loop (slow CPUs and
    /// throttled pages show here).
    pub cpu_bench_ms: Option<f64>,
    /// Screen.
    pub screen: Screen,
    /// `navigator.userAgentData.mobile`, or guessed from the user agent.
    pub mobile: bool,
    /// `navigator.deviceMemory` (GiB, rounded by the browser).
    pub device_memory_gb: Option<f64>,
    /// `navigator.hardwareConcurrency`.
    pub cores: Option<u32>,
}

/// The settings a mode is delivered with.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ModeSettings {
    /// Image or view size in pixels (modes 1, 2), or the client's render
    /// resolution (4a, volume).
    pub width: u32,
    /// Pixels.
    pub height: u32,
    /// JPEG/WebP quality while still.
    pub quality: u8,
    /// Size divisor and quality while the user orbits (mode 1 streaming).
    pub moving_scale: f64,
    /// Quality while moving.
    pub moving_quality: u8,
    /// Image encoding.
    pub format: super::ImageEncoding,
    /// Views per ring and rings (mode 2).
    pub views: u32,
    /// Ring pitches (mode 2).
    pub elevations: Vec<f64>,
    /// Mesh depth (modes 3, 4b); a coarse level first is `coarse_depth`.
    pub mesh_depth: u8,
    /// Depth of the first, coarse mesh.
    pub coarse_depth: u8,
    /// Volume grid (volume mode).
    pub volume_grid: u32,
}

/// What the engine expects of one mode for this client and model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ModePrediction {
    /// The mode.
    pub mode: Mode,
    /// Whether the client can show it at all.
    pub feasible: bool,
    /// Why not, when not feasible.
    pub refusal: Option<String>,
    /// Predicted ms from the request to the first displayed frame.
    pub first_display_ms: f64,
    /// Predicted ms per frame while orbiting.
    pub orbit_ms: f64,
    /// Predicted ms from a parameter change to the updated display.
    pub edit_ms: f64,
    /// Bytes the first display transfers.
    pub bytes: f64,
    /// The engine's score (lower is better).
    pub cost: f64,
}

/// The network as the server measured it on the session's socket.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct NetworkEstimate {
    /// Median round trip, ms.
    pub rtt_ms: f64,
    /// Throughput to the client, bits per second.
    pub bandwidth_bps: f64,
    /// How many probes and pings it rests on.
    pub samples: u32,
}

/// A decision pushed to a client: the mode, its settings, and why.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct Decision {
    /// The mode to use.
    pub mode: Mode,
    /// Its settings.
    pub settings: ModeSettings,
    /// Why, in plain words with the numbers.
    pub reason: String,
    /// Whether the user's override chose it.
    pub overridden: bool,
    /// What the engine predicted for every mode.
    pub predictions: Vec<ModePrediction>,
    /// The network it assumed.
    pub network: NetworkEstimate,
    /// What caused this decision (`connect`, `measurement`, `edit`,
    /// `slowFrames`, `override`, `load`, `periodic`).
    pub trigger: String,
    /// 1, 2, 3, … per session.
    pub seq: u32,
}
