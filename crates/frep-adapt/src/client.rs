//! What the engine believes of a client ([`ClientCaps`]), from its report.
//! It takes measured figures where the browser measured, and guesses
//! otherwise. A software rasterizer is recognised by its unmasked renderer
//! string. Also the resource limits of the modes ([`Limits`]).
//!
//! Guesses when a benchmark is missing:
//! - GPU: 3 ms per 256² benchmark frame on a desktop, 8 ms on a mobile,
//!   80 ms on a software renderer;
//! - JS speed: 1× the reference desktop, 3× slower on a mobile.
//!
//! Non-finite or non-positive figures count as missing.
//!
//! [`LoadedCode`] is what of the studio's code the page holds already: a
//! mode's first display must fetch the rest.

use frep_wire::{ClientReport, Mode};
use serde::Serialize;

use crate::correction::mode_index;
use crate::predict::CPU_BENCH_REFERENCE_MS;

/// Resource limits of the modes: beyond them a mode is refused.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Limits {
    /// 4a: more primitives than this do not compile as a browser shader.
    pub max_primitives_gpu: u32,
    /// 4a: more shader statements than this are refused.
    pub max_statements_gpu: u32,
    /// 4a: a predicted compile longer than this is refused.
    pub max_compile_ms: f64,
    /// Any mode but 1: a predicted first display longer than this is refused.
    pub max_first_display_ms: f64,
    /// 4b: least device memory (GiB) when the browser reports it.
    pub min_memory_gb_wasm: f64,
    /// 3, 4b: most triangles a client holds (desktop).
    pub max_triangles_desktop: f64,
    /// 3, 4b: most triangles a mobile client holds.
    pub max_triangles_mobile: f64,
    /// Volume: least 3D texture size.
    pub min_volume_grid: u32,
    /// Largest image side the server renders (pixels).
    pub max_image_side: u32,
    /// Largest device pixel ratio honoured.
    pub max_pixel_ratio: f64,
    /// Mesh depths tried for a server mesh (least, most).
    pub server_mesh_depths: (u8, u8),
    /// Mesh depths tried in the browser (least, most).
    pub wasm_mesh_depths: (u8, u8),
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_primitives_gpu: 1000,
            max_statements_gpu: 12_000,
            max_compile_ms: 5_000.0,
            max_first_display_ms: 60_000.0,
            min_memory_gb_wasm: 2.0,
            max_triangles_desktop: 4.0e6,
            max_triangles_mobile: 1.0e6,
            min_volume_grid: 64,
            max_image_side: 1280,
            max_pixel_ratio: 2.0,
            server_mesh_depths: (5, 9),
            wasm_mesh_depths: (4, 7),
        }
    }
}

/// What the engine believes of a client, from its report: measured where
/// the browser measured, guessed otherwise.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ClientCaps {
    /// WebGL2 context.
    pub webgl2: bool,
    /// A software renderer (SwiftShader, llvmpipe, Basic Render).
    pub software: bool,
    /// The renderer string's short name for reasons (`SwiftShader`...).
    pub renderer_name: Option<String>,
    /// ms per 256² benchmark frame (0 without WebGL2).
    pub gpu_ms: f64,
    /// Whether `gpu_ms` was measured (not guessed).
    pub gpu_measured: bool,
    /// Million WASM evaluations per second (`None`: no WASM).
    pub wasm_meps: Option<f64>,
    /// JS speed relative to the reference desktop (2: twice as slow).
    pub cpu_scale: f64,
    /// Whether `cpu_scale` was measured (not guessed).
    pub cpu_measured: bool,
    /// Device pixels across (screen × capped pixel ratio).
    pub device_width: u32,
    /// Device pixels down.
    pub device_height: u32,
    /// Mobile device.
    pub mobile: bool,
    /// Device memory in GiB (`None`: not reported).
    pub memory_gb: Option<f64>,
    /// 3D texture limit.
    pub max_3d_texture: u32,
    /// Which of the modes' code the page has loaded already.
    pub code: LoadedCode,
}

/// What code the page has loaded, so a mode's first display does not count
/// it again. The engine learns it from the modes displayed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct LoadedCode {
    /// three.js and the shared scene (modes 3 and 4b).
    pub three: bool,
    /// The WebAssembly kernel (frep.wasm).
    pub wasm: bool,
    /// Each mode's own chunk, in [`Mode::ALL`] order.
    pub modes: [bool; 6],
}

impl LoadedCode {
    /// `mode` reached the screen: its code and what it needs are loaded.
    pub fn displayed(&mut self, mode: Mode) {
        self.modes[mode_index(mode)] = true;
        self.three |= uses_three(mode);
        self.wasm |= mode == Mode::WasmMesh;
    }

    /// Keeps what `old` knew had loaded (a new report knows only the WASM).
    pub fn merge(&mut self, old: &LoadedCode) {
        self.three |= old.three;
        self.wasm |= old.wasm;
        for (m, o) in self.modes.iter_mut().zip(old.modes) {
            *m |= o;
        }
    }
}

/// Whether a mode draws with three.js.
pub fn uses_three(mode: Mode) -> bool {
    matches!(mode, Mode::ServerMesh | Mode::WasmMesh)
}

/// Renderer strings of software rasterizers, lower case.
const SOFTWARE_RENDERERS: [(&str, &str); 5] = [
    ("swiftshader", "SwiftShader"),
    ("llvmpipe", "llvmpipe"),
    ("softpipe", "softpipe"),
    ("basic render", "Microsoft Basic Render"),
    ("software", "a software renderer"),
];

/// The software rasterizer an unmasked renderer string names, if any.
pub fn software_renderer(renderer: &str) -> Option<&'static str> {
    let lower = renderer.to_ascii_lowercase();
    SOFTWARE_RENDERERS
        .iter()
        .find(|(needle, _)| lower.contains(needle))
        .map(|(_, name)| *name)
}

/// A positive finite value, or `None`.
fn positive(v: Option<f64>) -> Option<f64> {
    v.filter(|x| x.is_finite() && *x > 0.0)
}

impl ClientCaps {
    /// Caps from a report; non-finite or non-positive figures count as
    /// missing.
    pub fn from_report(report: &ClientReport, limits: &Limits) -> ClientCaps {
        let software_name = report.renderer.as_deref().and_then(software_renderer);
        let software = report.webgl2 && software_name.is_some();
        let bench = positive(report.gpu_bench_ms).filter(|_| report.webgl2);
        let guess = if software {
            80.0
        } else if report.mobile {
            8.0
        } else {
            3.0
        };
        let gpu_ms = match (report.webgl2, bench) {
            (false, _) => 0.0,
            (true, Some(ms)) => ms,
            (true, None) => guess,
        };
        let cpu_bench = positive(report.cpu_bench_ms);
        let cpu_scale = cpu_bench
            .map(|ms| ms / CPU_BENCH_REFERENCE_MS)
            .unwrap_or(if report.mobile { 3.0 } else { 1.0 })
            .clamp(0.1, 100.0);
        let ratio = if report.screen.pixel_ratio.is_finite() && report.screen.pixel_ratio > 0.0 {
            report.screen.pixel_ratio.min(limits.max_pixel_ratio)
        } else {
            1.0
        };
        let side = |css: u32| ((f64::from(css.max(1)) * ratio).round() as u32).max(1);
        ClientCaps {
            webgl2: report.webgl2,
            software,
            renderer_name: software_name.map(str::to_string),
            gpu_ms,
            gpu_measured: bench.is_some(),
            wasm_meps: positive(report.wasm_bench_meps),
            cpu_scale,
            cpu_measured: cpu_bench.is_some(),
            device_width: side(report.screen.width),
            device_height: side(report.screen.height),
            mobile: report.mobile,
            memory_gb: positive(report.device_memory_gb),
            max_3d_texture: if report.webgl2 {
                report.max_3d_texture_size
            } else {
                0
            },
            // The WASM benchmark runs in the kernel: frep.wasm is loaded.
            code: LoadedCode {
                wasm: report.wasm_bench_meps.is_some(),
                ..LoadedCode::default()
            },
        }
    }

    /// How many of the three benchmarks (GPU, WASM, JS) were measured.
    pub fn measured_count(&self) -> u32 {
        u32::from(self.gpu_measured)
            + u32::from(self.wasm_meps.is_some())
            + u32::from(self.cpu_measured)
    }

    /// Device pixels of the viewport.
    pub fn device_pixels(&self) -> f64 {
        f64::from(self.device_width) * f64::from(self.device_height)
    }

    /// Most triangles this client should hold.
    pub fn max_triangles(&self, limits: &Limits) -> f64 {
        let base = if self.mobile {
            limits.max_triangles_mobile
        } else {
            limits.max_triangles_desktop
        };
        // Small memories hold proportionally less (1 M triangles per GiB
        // is generous for a meshopt mesh and its GPU buffers).
        self.memory_gb.map_or(base, |gb| base.min(gb * 1.0e6))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn software_renderers_are_recognised() {
        for s in [
            "ANGLE (Google, Vulkan 1.3.0 (SwiftShader Device (Subzero)), SwiftShader driver)",
            "llvmpipe (LLVM 15.0.7, 256 bits)",
            "ANGLE (Microsoft, Microsoft Basic Render Driver Direct3D11)",
        ] {
            assert!(software_renderer(s).is_some(), "{s}");
        }
        assert_eq!(
            software_renderer("ANGLE (NVIDIA, NVIDIA GeForce RTX 4090 Direct3D11)"),
            None
        );
    }
}
