//! # frep-adapt
//!
//! The adaptive delivery engine, one per WebSocket session. From a client's
//! measurements, a model's statistics and the server's load, it decides a
//! delivery mode, its settings and the reason. Pure code: no I/O, no
//! threads, and no clock. Every event carries the time in ms from any fixed
//! origin, monotonic.
//!
//! ## How it decides
//! The modes are 1 still, 2 view set, 3 server mesh, 4a GPU ray casting,
//! 4b WASM mesh, and volume.
//! 1. For every mode, [`choose`] tries a short ladder of settings
//!    ([`choose::candidates`]): image size and quality, view count, mesh
//!    depth, render scale, volume grid.
//! 2. For each, [`predict`] predicts the time to first display, the time
//!    per orbit frame and the latency of a parameter edit.
//! 3. [`predict`] may refuse the mode instead, with a reason: no WebGL2, a
//!    shader too long for a browser or too slow to compile on a software
//!    renderer, too many primitives, no WASM...
//! 4. [`choose`] scores them: first display, orbit smoothness with a penalty
//!    under 20 fps, edits, and what each mode and lower settings give up.
//! 5. It keeps the cheapest settings of each mode, and the cheapest feasible
//!    mode.
//!
//! [`Engine`] keeps one session's state.
//! - It re-decides on every event, with hysteresis. It leaves a mode that
//!   fails its targets after ~2 s. It switches to a better mode only after
//!   ~10 s of steady advantage and an idle user.
//! - It obeys the user's override.
//! - It learns correction factors from what the client reports it actually
//!   took ([`correction`]).
//! - It logs every decision with its inputs and predictions ([`log`]).
//!
//! [`reason`] words the why with its numbers.
//!
//! ## Feeding it
//! - [`Engine::connect`] once the client's report and a model are known.
//! - Then [`Engine::measurement`] (network), [`Engine::report`],
//!   [`Engine::frame_rate`], [`Engine::displayed`], [`Engine::model_changed`],
//!   [`Engine::server_measured`] (an artefact's measured cost),
//!   [`Engine::set_override`] and [`Engine::load`].
//! - [`Engine::activity`]: camera moves and drags. Upgrades wait for an idle
//!   user.
//! - [`Engine::tick`] about every second, since hysteresis timers advance
//!   only on events.
//!
//! Each returns `Some(decision)` when there is something new to push.

//! ## Use
//! ```
//! use frep_adapt::{Engine, EngineConfig, ModelStats, Measured};
//! use frep_wire::{ClientReport, NetworkEstimate, Screen};
//!
//! let mut engine = Engine::new(EngineConfig::default()).expect("default config is valid");
//! let report = ClientReport {
//!     user_agent: "test".into(), webgl2: false, renderer: None,
//!     max_texture_size: 0, max_3d_texture_size: 0, webgpu: false,
//!     gpu_bench_ms: None, wasm_bench_meps: None, cpu_bench_ms: None,
//!     screen: Screen { width: 1280, height: 800, pixel_ratio: 1.0 },
//!     mobile: false, device_memory_gb: None, cores: None,
//! };
//! let net = NetworkEstimate { rtt_ms: 30.0, bandwidth_bps: 20e6, samples: 4 };
//! let stats = ModelStats {
//!     tape_len: 40, nodes: 50, closed_form: true, attributes: 0,
//!     primitives: None, shader_statements: 40, measured: Measured::default(),
//! };
//! let decision = engine.connect(report, net, stats, 0);
//! // Without WebGL only the server's images can be shown.
//! assert!(matches!(decision.mode, frep_wire::Mode::Still | frep_wire::Mode::ViewSet));
//! ```
#![warn(missing_docs)]

pub mod choose;
pub mod client;
pub mod config;
pub mod correction;
pub mod engine;
pub mod log;
pub mod predict;
pub mod reason;
pub mod stats;

pub use choose::{CostWeights, Scored};
pub use client::{ClientCaps, Limits, LoadedCode};
pub use config::{ConfigError, EngineConfig};
pub use correction::{CorrectionConfig, Corrections, Factor, ModeFactors};
pub use engine::Engine;
pub use log::{InputSummary, LogEntry, Trigger};
pub use predict::{Inputs, Prediction};
pub use stats::{
    ImageSample, Measured, MeshSample, ModelStats, ServerLoad, ServerSample, VolumeSample,
};

pub use frep_wire::{ClientReport, Decision, Mode, ModePrediction, ModeSettings, NetworkEstimate};
