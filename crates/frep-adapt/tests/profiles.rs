//! Client profiles through the engine: each a realistic client, network and
//! model, asserting what a person would call a sensible delivery.

mod common;

use common::*;
use frep_wire::{Decision, Mode};

#[test]
fn phone_on_a_slow_link_never_gets_a_big_download() {
    let cases = [
        (1.5, 150.0, 40, true),
        (1.5, 150.0, 300, true),
        (1.5, 150.0, 3000, true),
        (1.5, 150.0, 3000, false),
        (0.3, 400.0, 3000, false),
    ];
    for (mbps, rtt, tape, wasm) in cases {
        let mut report = phone();
        if !wasm {
            report.wasm_bench_meps = None;
        }
        let mut e = engine();
        let d = e.connect(report, net(mbps, rtt), model(tape), 0);
        let p = chosen(&d);
        assert!(
            p.bytes <= 150_000.0,
            "tape {tape}: {} bytes: {}",
            p.bytes,
            d.reason
        );
        if d.mode == Mode::ServerMesh {
            assert!(d.settings.mesh_depth <= 6, "{}", d.reason);
        }
        // A mode that is not the server's own images must orbit smoothly.
        if !matches!(d.mode, Mode::Still | Mode::ViewSet) {
            assert!(p.orbit_ms <= 50.0, "tape {tape}: {}", d.reason);
        }
        assert!(p.first_display_ms < 2000.0, "tape {tape}: {}", d.reason);
        assert!(
            d.reason.contains(&format!("{rtt} ms round trip")),
            "{}",
            d.reason
        );
    }
}

#[test]
fn desktop_without_webgl_gets_images_only() {
    for (mbps, rtt) in [(100.0, 5.0), (20.0, 30.0), (1.0, 200.0)] {
        let mut e = engine();
        let d = e.connect(desktop_without_webgl(), net(mbps, rtt), model(100), 0);
        assert!(
            matches!(d.mode, Mode::Still | Mode::ViewSet),
            "{}",
            d.reason
        );
        assert!(d.reason.starts_with("no WebGL2"), "{}", d.reason);
        for m in [
            Mode::ServerMesh,
            Mode::GpuRaycast,
            Mode::WasmMesh,
            Mode::Volume,
        ] {
            let p = prediction(&d, m);
            assert!(!p.feasible);
            assert_eq!(p.refusal.as_deref(), Some("no WebGL2"));
        }
    }
    // On a slow link with long round trips, streaming frames cannot orbit:
    // the view set orbits locally.
    let mut e = engine();
    let d = e.connect(desktop_without_webgl(), net(1.5, 150.0), model(100), 0);
    assert_eq!(d.mode, Mode::ViewSet, "{}", d.reason);
}

#[test]
fn software_renderer_does_not_ray_cast_a_heavy_model() {
    let mut e = engine();
    let d = e.connect(laptop_swiftshader(), net(50.0, 20.0), model(2000), 0);
    assert_ne!(d.mode, Mode::GpuRaycast, "{}", d.reason);
    assert!(d.reason.contains("SwiftShader"), "{}", d.reason);
    let gpu = prediction(&d, Mode::GpuRaycast);
    assert!(!gpu.feasible || gpu.cost > 10.0 * chosen(&d).cost);
    // A long shader of few, complex primitives is refused outright for its
    // compile time on a software renderer, not on a hardware GPU.
    let mut long = model(4000);
    long.primitives = Some(50);
    let d = engine().connect(laptop_swiftshader(), net(50.0, 20.0), long.clone(), 0);
    let gpu = prediction(&d, Mode::GpuRaycast);
    let why = gpu.refusal.as_deref().unwrap_or("");
    assert!(why.contains("on SwiftShader would take ≈ 20 s"), "{why}");
    let d = engine().connect(workstation(), lan(), long, 0);
    assert!(prediction(&d, Mode::GpuRaycast).feasible);
}

#[test]
fn workstation_on_a_lan_ray_casts_on_its_gpu() {
    let mut e = engine();
    let d = e.connect(workstation(), lan(), model(80), 0);
    assert_eq!(d.mode, Mode::GpuRaycast, "{}", d.reason);
    assert_eq!((d.settings.width, d.settings.height), (2560, 1440));
    assert!(chosen(&d).orbit_ms <= 50.0);
    assert!(!d.overridden);
    assert_eq!(d.trigger, "connect");
    assert_eq!(d.seq, 1);
}

#[test]
fn too_heavy_a_model_is_refused_for_the_shader_with_a_reason() {
    let mut stats = model(18_000);
    stats.primitives = Some(1500);
    let mut e = engine();
    let d = e.connect(workstation(), lan(), stats, 0);
    assert_ne!(d.mode, Mode::GpuRaycast);
    let gpu = prediction(&d, Mode::GpuRaycast);
    assert!(!gpu.feasible);
    let why = gpu.refusal.as_deref().unwrap_or("");
    assert!(
        why.contains("1500 primitives") && why.contains("1000"),
        "{why}"
    );
    assert!(d.reason.contains("GPU ray casting refused"), "{}", d.reason);

    // Few primitives but a very long shader: refused for its length.
    let mut stats = model(500);
    stats.primitives = Some(10);
    stats.shader_statements = 20_000;
    let d = engine().connect(workstation(), lan(), stats, 0);
    let why = prediction(&d, Mode::GpuRaycast)
        .refusal
        .clone()
        .unwrap_or_default();
    assert!(why.contains("20000 shader statements"), "{why}");
}

#[test]
fn every_decision_predicts_all_six_modes() {
    let d = engine().connect(phone(), net(1.5, 150.0), model(300), 0);
    let modes: Vec<Mode> = d.predictions.iter().map(|p| p.mode).collect();
    assert_eq!(modes, Mode::ALL.to_vec());
    for p in &d.predictions {
        assert_eq!(p.feasible, p.refusal.is_none());
        for v in [p.first_display_ms, p.orbit_ms, p.edit_ms, p.bytes, p.cost] {
            assert!(v.is_finite() && v >= 0.0, "{p:?}");
        }
    }
    // The wire form survives JSON (no infinities turned into null).
    let json = serde_json::to_string(&d).expect("serializes");
    let back: Decision = serde_json::from_str(&json).expect("parses back");
    assert_eq!(back, d);
}

#[test]
fn a_degrading_link_moves_to_a_lighter_mode_past_hysteresis() {
    let mut e = engine();
    let d0 = e.connect(desktop_without_webgl(), net(50.0, 20.0), model(100), 0);
    assert_eq!(d0.mode, Mode::Still, "{}", d0.reason);
    // Steady good measurements change nothing.
    for t in [2_000, 4_000, 6_000, 8_000] {
        assert_eq!(e.measurement(net(48.0, 21.0), t), None);
    }
    // The link degrades at 10 s. Within the hysteresis the mode stays; a
    // decision may only lighten the settings.
    let bad = net(1.0, 300.0);
    let mut last_bytes = chosen(&d0).bytes;
    let mut switched_at = None;
    for t in (10_000..20_000).step_by(500) {
        let Some(d) = e.measurement(bad.clone(), t) else {
            continue;
        };
        if d.mode == Mode::Still {
            assert!(chosen(&d).bytes < last_bytes, "{}", d.reason);
            last_bytes = chosen(&d).bytes;
            continue;
        }
        switched_at = Some(t);
        assert_eq!(d.mode, Mode::ViewSet, "{}", d.reason);
        assert_eq!(d.trigger, "measurement");
        assert!(d.reason.contains("fps, under 20"), "{}", d.reason);
        break;
    }
    let t = switched_at.expect("the engine left the still image");
    assert!(t >= 12_000, "switched at {t} ms, within the 2 s hysteresis");
    assert!(t <= 13_000, "switched at {t} ms, long after the hysteresis");
}

#[test]
fn frames_reported_too_slow_for_two_seconds_downgrade() {
    let mut e = engine();
    let d0 = e.connect(workstation(), lan(), model(80), 0);
    assert_eq!(d0.mode, Mode::GpuRaycast);
    // Fine frames first: nothing changes.
    assert_eq!(e.frame_rate(Mode::GpuRaycast, 60.0, 500), None);
    // Then 8 fps (the GPU is busy with something else).
    assert_eq!(e.frame_rate(Mode::GpuRaycast, 8.0, 1_000), None);
    assert_eq!(e.frame_rate(Mode::GpuRaycast, 8.0, 2_000), None);
    let d = e
        .frame_rate(Mode::GpuRaycast, 8.0, 3_000)
        .expect("two seconds of slow frames downgrade");
    assert_eq!(d.trigger, "slowFrames");
    assert!(
        d.mode != Mode::GpuRaycast || d.settings.width < d0.settings.width,
        "{:?} {}×{}: {}",
        d.mode,
        d.settings.width,
        d.settings.height,
        d.reason
    );
    assert!(
        d.reason.contains("frames stayed under 20 fps"),
        "{}",
        d.reason
    );
    // The report taught the engine: 4a's orbit prediction at full size now
    // matches what the client measured (125 ms), not the 28 ms it guessed.
    let f = e.corrections().get(Mode::GpuRaycast).orbit.value();
    assert!(f > 3.0, "orbit correction {f}");
}

#[test]
fn slow_frames_that_recover_do_not_downgrade() {
    let mut e = engine();
    e.connect(workstation(), lan(), model(80), 0);
    assert_eq!(e.frame_rate(Mode::GpuRaycast, 8.0, 1_000), None);
    assert_eq!(e.frame_rate(Mode::GpuRaycast, 40.0, 2_000), None);
    assert_eq!(e.frame_rate(Mode::GpuRaycast, 8.0, 2_500), None);
    assert_eq!(e.frame_rate(Mode::GpuRaycast, 40.0, 3_500), None);
    assert_eq!(e.current().map(|d| d.mode), Some(Mode::GpuRaycast));
}

#[test]
fn edits_slower_than_patience_downgrade_like_slow_frames() {
    // An integrated GPU without a WASM benchmark, a mid-size model on a
    // 3 Mbit/s link with 150 ms round trips: server slices ray marched on
    // the client.
    let mut report = client(
        "ANGLE (Intel, Intel(R) UHD Graphics 620)",
        Some(3.0),
        (1920, 1080, 1.0),
        false,
    );
    report.wasm_bench_meps = None;
    let mut e = engine();
    let d0 = e.connect(report, net(3.0, 150.0), model(300), 0);
    assert_eq!(d0.mode, Mode::Volume, "{}", d0.reason);
    // The link collapses to 30 kbit/s: the volume still orbits smoothly,
    // but every parameter edit would wait seconds for new slices. That is
    // failing too: the engine leaves after the short hysteresis, not ten
    // seconds.
    let mut switched = None;
    for t in (1_000..20_000).step_by(500) {
        if let Some(d) = e.measurement(net(0.03, 300.0), t) {
            if d.mode != Mode::Volume {
                switched = Some((t, d));
                break;
            }
        }
    }
    let (t, d) = switched.expect("left the volume");
    assert_eq!(t, 3_000, "{}", d.reason);
    assert!(
        d.reason.starts_with("volume slices: an edit takes ≈"),
        "{}",
        d.reason
    );
    assert!(chosen(&d).edit_ms < 1_000.0, "{}", d.reason);
}

#[test]
fn a_model_too_heavy_for_a_modest_gpu_is_not_ray_cast_there() {
    // 2000 operations compile fine (not refused), but an integrated GPU
    // cannot ray cast them at 20 fps even at a quarter of the resolution.
    let laptop = client(
        "ANGLE (Intel, Intel(R) UHD Graphics 620 Direct3D11)",
        Some(3.0),
        (1920, 1080, 1.0),
        false,
    );
    let d = engine().connect(laptop, net(50.0, 20.0), model(2000), 0);
    let gpu = prediction(&d, Mode::GpuRaycast);
    assert!(gpu.feasible, "{:?}", gpu.refusal);
    assert!(gpu.orbit_ms > 50.0, "{gpu:?}");
    assert_ne!(d.mode, Mode::GpuRaycast, "{}", d.reason);
    assert!(
        chosen(&d).orbit_ms <= 50.0 || d.mode == Mode::Still,
        "{}",
        d.reason
    );
    // The workstation's GPU ray casts the same model faster.
    let d = engine().connect(workstation(), lan(), model(2000), 0);
    assert!(prediction(&d, Mode::GpuRaycast).orbit_ms < gpu.orbit_ms);
}

#[test]
fn slow_frames_downgrade_even_when_the_gpu_bench_promised_far_more() {
    // The GPU benchmark says 0.02 ms a frame (a tiny shader on a fast
    // card), but the model's shader draws at 2 fps: 250× slower than
    // predicted, beyond any prior's correction. Measured frames decide.
    let mut e = engine();
    let mut fast = workstation();
    fast.gpu_bench_ms = Some(0.02);
    let d0 = e.connect(fast, lan(), model(80), 0);
    assert_eq!(d0.mode, Mode::GpuRaycast);
    let mut last = None;
    for t in (500..=6_000).step_by(500) {
        if let Some(d) = e.frame_rate(Mode::GpuRaycast, 2.0, t) {
            last = Some((t, d));
            break;
        }
    }
    let (t, d) = last.expect("two seconds of 2 fps frames downgrade");
    assert!(t <= 3_000, "downgraded only at {t} ms");
    assert_eq!(d.trigger, "slowFrames");
    assert!(
        d.mode != Mode::GpuRaycast || d.settings.width < d0.settings.width,
        "{:?} {}×{}: {}",
        d.mode,
        d.settings.width,
        d.settings.height,
        d.reason
    );
}
