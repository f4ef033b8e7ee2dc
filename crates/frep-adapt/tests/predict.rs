//! The cost model's directions: each prediction moves the right way when
//! one input gets worse, the server's load leaves client-side work alone,
//! and the hard checks refuse what a client cannot show.

use frep_adapt::correction::Corrections;
use frep_adapt::predict::{predict, refusal, Inputs};
use frep_adapt::{ClientCaps, Limits, Measured, ModelStats, ServerLoad};
use frep_wire::{ClientReport, ImageEncoding, Mode, ModeSettings, NetworkEstimate, Screen};

fn caps(webgl2: bool) -> ClientCaps {
    let report = ClientReport {
        user_agent: String::new(),
        webgl2,
        renderer: None,
        max_texture_size: 8192,
        max_3d_texture_size: 512,
        webgpu: false,
        gpu_bench_ms: Some(2.0),
        wasm_bench_meps: Some(30.0),
        cpu_bench_ms: Some(10.0),
        screen: Screen {
            width: 1280,
            height: 800,
            pixel_ratio: 1.0,
        },
        mobile: false,
        device_memory_gb: Some(8.0),
        cores: Some(4),
    };
    ClientCaps::from_report(&report, &Limits::default())
}

fn settings() -> ModeSettings {
    ModeSettings {
        width: 800,
        height: 600,
        quality: 75,
        moving_scale: 2.0,
        moving_quality: 50,
        format: ImageEncoding::Jpeg,
        views: 12,
        elevations: vec![20.0],
        mesh_depth: 7,
        coarse_depth: 5,
        volume_grid: 64,
    }
}

fn stats(tape: u32) -> ModelStats {
    ModelStats {
        tape_len: tape,
        nodes: tape,
        closed_form: false,
        attributes: 0,
        primitives: None,
        shader_statements: tape,
        measured: Measured::default(),
    }
}

/// First display of every mode with the given inputs.
fn firsts(c: &ClientCaps, mbps: f64, rtt: f64, tape: u32, load: ServerLoad) -> Vec<f64> {
    let net = NetworkEstimate {
        rtt_ms: rtt,
        bandwidth_bps: mbps * 1e6,
        samples: 1,
    };
    let st = stats(tape);
    let inputs = Inputs {
        caps: c,
        net: &net,
        stats: &st,
        load,
    };
    let corr = Corrections::default();
    Mode::ALL
        .iter()
        .map(|&m| predict(m, &settings(), &inputs, &Limits::default(), &corr).first_display_ms)
        .collect()
}

#[test]
fn predictions_move_the_right_way() {
    let c = caps(true);
    let idle = ServerLoad::default();
    let base = firsts(&c, 10.0, 50.0, 100, idle);
    let checks = [
        ("less bandwidth", firsts(&c, 1.0, 50.0, 100, idle)),
        ("longer round trips", firsts(&c, 10.0, 200.0, 100, idle)),
        ("a longer tape", firsts(&c, 10.0, 50.0, 1000, idle)),
        (
            "a busy server",
            firsts(
                &c,
                10.0,
                50.0,
                100,
                ServerLoad {
                    busy_workers: 2,
                    workers: 2,
                    queued: 4,
                },
            ),
        ),
    ];
    for (what, slower) in checks {
        for (i, (a, b)) in base.iter().zip(&slower).enumerate() {
            assert!(b >= a, "{what}: {:?} {a} -> {b}", Mode::ALL[i]);
            assert!(b.is_finite());
        }
    }
    // The server's load does not touch the client-side modes' work.
    let busy = firsts(
        &c,
        10.0,
        50.0,
        100,
        ServerLoad {
            busy_workers: 2,
            workers: 2,
            queued: 4,
        },
    );
    assert_eq!(busy[3], base[3]);
    assert_eq!(busy[4], base[4]);
    assert!(busy[0] > base[0] && busy[2] > base[2] && busy[5] > base[5]);
}

#[test]
fn hard_refusals() {
    let net = NetworkEstimate {
        rtt_ms: 10.0,
        bandwidth_bps: 1e7,
        samples: 1,
    };
    let st = stats(50);
    let no_gl = caps(false);
    let inputs = Inputs {
        caps: &no_gl,
        net: &net,
        stats: &st,
        load: ServerLoad::default(),
    };
    let limits = Limits::default();
    for m in Mode::ALL {
        let r = refusal(m, &inputs, &limits);
        assert_eq!(
            r.is_some(),
            !matches!(m, Mode::Still | Mode::ViewSet),
            "{m:?}"
        );
    }
    let mut small_3d = caps(true);
    small_3d.max_3d_texture = 32;
    small_3d.wasm_meps = None;
    let inputs = Inputs {
        caps: &small_3d,
        ..inputs
    };
    let vol = refusal(Mode::Volume, &inputs, &limits).unwrap_or_default();
    assert!(vol.contains("3D textures limited to 32"), "{vol}");
    let wasm = refusal(Mode::WasmMesh, &inputs, &limits).unwrap_or_default();
    assert!(wasm.contains("WebAssembly"), "{wasm}");
}
