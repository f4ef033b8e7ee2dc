//! Client profiles for the engine's tests: realistic clients, networks and
//! models.
#![allow(dead_code)] // Each test file uses a different part.

use frep_adapt::{Engine, EngineConfig, Measured, ModelStats};
use frep_wire::{ClientReport, Decision, Mode, ModePrediction, NetworkEstimate, Screen};

pub const NVIDIA: &str = "ANGLE (NVIDIA, NVIDIA GeForce RTX 4090 Direct3D11 vs_5_0 ps_5_0)";
pub const SWIFTSHADER: &str =
    "ANGLE (Google, Vulkan 1.3.0 (SwiftShader Device (Subzero) (0x0000C0DE)), SwiftShader driver)";
pub const ADRENO: &str = "Adreno (TM) 618";

/// A client; `gpu_ms` `None` means no WebGL2 at all.
pub fn client(
    renderer: &str,
    gpu_ms: Option<f64>,
    screen: (u32, u32, f64),
    mobile: bool,
) -> ClientReport {
    let webgl2 = gpu_ms.is_some();
    ClientReport {
        user_agent: "profile".into(),
        webgl2,
        renderer: webgl2.then(|| renderer.to_string()),
        max_texture_size: if webgl2 { 8192 } else { 0 },
        max_3d_texture_size: if webgl2 { 1024 } else { 0 },
        webgpu: false,
        gpu_bench_ms: gpu_ms,
        wasm_bench_meps: Some(if mobile { 10.0 } else { 40.0 }),
        cpu_bench_ms: Some(if mobile { 30.0 } else { 10.0 }),
        screen: Screen {
            width: screen.0,
            height: screen.1,
            pixel_ratio: screen.2,
        },
        mobile,
        device_memory_gb: Some(if mobile { 4.0 } else { 8.0 }),
        cores: Some(8),
    }
}

pub fn phone() -> ClientReport {
    client(ADRENO, Some(12.0), (390, 844, 3.0), true)
}

pub fn desktop_without_webgl() -> ClientReport {
    client("", None, (1920, 1080, 1.0), false)
}

pub fn laptop_swiftshader() -> ClientReport {
    client(SWIFTSHADER, Some(90.0), (1440, 900, 1.0), false)
}

pub fn workstation() -> ClientReport {
    client(NVIDIA, Some(0.3), (2560, 1440, 1.0), false)
}

pub fn net(mbps: f64, rtt_ms: f64) -> NetworkEstimate {
    NetworkEstimate {
        rtt_ms,
        bandwidth_bps: mbps * 1e6,
        samples: 8,
    }
}

pub fn lan() -> NetworkEstimate {
    net(1000.0, 1.0)
}

/// A general (not closed-form) model of `tape` operations.
pub fn model(tape: u32) -> ModelStats {
    ModelStats {
        tape_len: tape,
        nodes: tape + tape / 4,
        closed_form: false,
        attributes: 0,
        primitives: None,
        shader_statements: tape,
        measured: Measured::default(),
    }
}

pub fn engine() -> Engine {
    Engine::new(EngineConfig::default()).expect("default config is valid")
}

pub fn prediction(d: &Decision, mode: Mode) -> &ModePrediction {
    d.predictions
        .iter()
        .find(|p| p.mode == mode)
        .expect("every mode is predicted")
}

pub fn chosen(d: &Decision) -> &ModePrediction {
    prediction(d, d.mode)
}
