//! The reason of a decision in plain words, with its numbers:
//! - what ruled modes out;
//! - the mode and its settings, and what it is expected to do;
//! - the network and load it assumed.

use frep_wire::{ImageEncoding, Mode, ModeSettings};

use crate::choose::Scored;
use crate::correction::mode_index;
use crate::predict::Inputs;

/// A mode's name as a user reads it.
pub fn mode_name(mode: Mode) -> &'static str {
    match mode {
        Mode::Still => "server still image",
        Mode::ViewSet => "server view set",
        Mode::ServerMesh => "server mesh",
        Mode::GpuRaycast => "GPU ray casting",
        Mode::WasmMesh => "browser (WASM) mesh",
        Mode::Volume => "volume slices",
    }
}

/// `1.5 Mbit/s`, `20 Mbit/s`, `1 Gbit/s`, `300 kbit/s`.
pub fn bandwidth_words(bps: f64) -> String {
    if bps >= 1.0e9 {
        format!("{} Gbit/s", round_sig(bps / 1.0e9))
    } else if bps >= 1.0e6 {
        format!("{} Mbit/s", round_sig(bps / 1.0e6))
    } else {
        format!("{} kbit/s", round_sig(bps / 1.0e3))
    }
}

/// Two significant digits, no trailing zeros.
fn round_sig(v: f64) -> String {
    if v >= 10.0 {
        format!("{:.0}", v)
    } else {
        let s = format!("{:.1}", v);
        s.trim_end_matches(".0").to_string()
    }
}

/// `0.4 s` or `35 ms`.
pub fn duration_words(ms: f64) -> String {
    if ms >= 1000.0 {
        format!("{} s", round_sig(ms / 1000.0))
    } else {
        format!("{:.0} ms", ms)
    }
}

/// `24 kB`, `1.2 MB`.
pub fn bytes_words(bytes: f64) -> String {
    if bytes >= 1.0e6 {
        format!("{} MB", round_sig(bytes / 1.0e6))
    } else {
        format!("{:.0} kB", (bytes / 1000.0).max(1.0))
    }
}

/// The settings of a mode in a few words.
pub fn settings_words(mode: Mode, s: &ModeSettings, bytes: f64, inputs: &Inputs) -> String {
    let size = bytes_words(bytes);
    match mode {
        Mode::Still => format!(
            "{}×{} {} q{} ({size})",
            s.width,
            s.height,
            format_name(s.format),
            s.quality
        ),
        Mode::ViewSet => format!(
            "{} views of {}×{} {} q{} ({size})",
            s.views as usize * s.elevations.len().max(1),
            s.width,
            s.height,
            format_name(s.format),
            s.quality
        ),
        Mode::ServerMesh => {
            let tris = crate::predict::mesh_triangles(inputs.stats, s.mesh_depth);
            format!(
                "depth {} (≈ {} triangles, {size})",
                s.mesh_depth,
                count_words(tris)
            )
        }
        Mode::WasmMesh => {
            let tris = crate::predict::mesh_triangles(inputs.stats, s.mesh_depth);
            format!("depth {} (≈ {} triangles)", s.mesh_depth, count_words(tris))
        }
        Mode::GpuRaycast => format!(
            "rendered at {}×{}, {} shader statements",
            s.width,
            s.height,
            inputs.stats.statements()
        ),
        Mode::Volume => format!(
            "{}³ grid ({size}), rendered at {}×{}",
            s.volume_grid, s.width, s.height
        ),
    }
}

fn format_name(f: ImageEncoding) -> &'static str {
    match f {
        ImageEncoding::Jpeg => "JPEG",
        ImageEncoding::Webp => "WebP",
        ImageEncoding::Png => "PNG",
    }
}

fn count_words(n: f64) -> String {
    if n >= 1.0e6 {
        format!("{}M", round_sig(n / 1.0e6))
    } else if n >= 1.0e3 {
        format!("{:.0}k", n / 1.0e3)
    } else {
        format!("{:.0}", n)
    }
}

/// Orbit frames per second from a frame time.
pub fn fps(orbit_ms: f64) -> f64 {
    if orbit_ms > 0.0 {
        1000.0 / orbit_ms
    } else {
        f64::INFINITY
    }
}

/// What ruled out the richer modes: the refusals of GPU ray casting and of
/// the WebGL modes, once each.
fn constraints(scored: &[Scored], inputs: &Inputs) -> Vec<String> {
    let mut out = Vec::new();
    if !inputs.caps.webgl2 {
        out.push("no WebGL2: server images only".to_string());
        return out;
    }
    if let Some(name) = &inputs.caps.renderer_name {
        out.push(format!("software renderer ({name})"));
    }
    let gpu = &scored[mode_index(Mode::GpuRaycast)].prediction;
    if let Some(r) = &gpu.refusal {
        out.push(format!("GPU ray casting refused: {r}"));
    }
    out
}

/// The full reason: `note` (what caused it), constraints, the chosen mode
/// with its settings and expected figures, the network and the load.
pub fn explain(note: Option<&str>, scored: &[Scored], chosen: usize, inputs: &Inputs) -> String {
    let p = &scored[chosen].prediction;
    let mut parts: Vec<String> = Vec::new();
    if let Some(n) = note {
        parts.push(n.to_string());
    }
    parts.extend(constraints(scored, inputs));
    let orbit = match p.mode {
        Mode::ViewSet => "orbit through fixed views".to_string(),
        _ => format!("orbit ≈ {:.0} fps", fps(p.orbit_ms).min(999.0)),
    };
    parts.push(format!(
        "{}: {}; first display ≈ {}, {}, edit ≈ {}",
        mode_name(p.mode),
        settings_words(p.mode, &p.settings, p.bytes, inputs),
        duration_words(p.first_display_ms),
        orbit,
        duration_words(p.edit_ms)
    ));
    let mut net = format!(
        "{}, {:.0} ms round trip",
        bandwidth_words(inputs.bandwidth()),
        inputs.rtt()
    );
    let load = inputs.load.factor();
    if load > 1.05 {
        net.push_str(&format!(", server load ×{load:.1}"));
    }
    parts.push(net);
    parts.join("; ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words() {
        assert_eq!(bandwidth_words(1.5e6), "1.5 Mbit/s");
        assert_eq!(bandwidth_words(1.0e9), "1 Gbit/s");
        assert_eq!(bandwidth_words(300e3), "300 kbit/s");
        assert_eq!(duration_words(420.0), "420 ms");
        assert_eq!(duration_words(1500.0), "1.5 s");
        assert_eq!(bytes_words(24_300.0), "24 kB");
        assert_eq!(bytes_words(1.24e6), "1.2 MB");
    }
}
