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

/// A client like the paper bench's desktop: a 576² viewport, a 13 ms GPU
/// benchmark, on SwiftShader or on a hardware GPU.
fn bench_desktop(renderer: &str) -> ClientCaps {
    let report = ClientReport {
        user_agent: String::new(),
        webgl2: true,
        renderer: Some(renderer.into()),
        max_texture_size: 8192,
        max_3d_texture_size: 512,
        webgpu: false,
        gpu_bench_ms: Some(13.0),
        wasm_bench_meps: Some(7.0),
        cpu_bench_ms: Some(14.0),
        screen: Screen {
            width: 576,
            height: 576,
            pixel_ratio: 1.0,
        },
        mobile: false,
        device_memory_gb: Some(8.0),
        cores: Some(2),
    };
    ClientCaps::from_report(&report, &Limits::default())
}

const SWIFTSHADER: &str =
    "ANGLE (Google, Vulkan 1.3.0 (SwiftShader Device (Subzero) (0x0000C0DE)), SwiftShader driver)";

#[test]
fn a_software_renderer_draws_meshes_slowly() {
    use frep_adapt::predict::draw_ms;
    // SwiftShader drew sake_pot's 138 k triangles at 576² in 71–99 ms
    // (docs/paper.md) with a 13 ms benchmark.
    let soft = bench_desktop(SWIFTSHADER);
    let ms = draw_ms(&soft, 137_564.0, soft.device_pixels());
    assert!((60.0..150.0).contains(&ms), "{ms}");
    // The same benchmark on a hardware GPU: the triangles are nearly free.
    let hard = bench_desktop("ANGLE (NVIDIA, NVIDIA GeForce RTX 4090 Direct3D11)");
    let hw = draw_ms(&hard, 137_564.0, hard.device_pixels());
    assert!(hw < ms / 10.0, "{hw} vs {ms}");
}

#[test]
fn a_first_display_fetches_the_code_the_page_lacks() {
    use frep_adapt::predict::{code_bytes, THREE_CODE_BYTES, WASM_CODE_BYTES};
    let mut c = bench_desktop(SWIFTSHADER);
    // The WASM benchmark ran in the kernel: frep.wasm is loaded.
    assert!(c.code.wasm);
    let mesh = code_bytes(Mode::ServerMesh, &c);
    assert!(mesh > THREE_CODE_BYTES, "{mesh}");
    let still = code_bytes(Mode::Still, &c);
    assert!(still < 10_000.0, "{still}");
    // On a 1.5 Mbit/s link three.js alone is ~0.6 s of the mesh's first display.
    let first = |c: &ClientCaps| {
        let net = NetworkEstimate {
            rtt_ms: 150.0,
            bandwidth_bps: 1.5e6,
            samples: 4,
        };
        let st = stats(40);
        let inputs = Inputs {
            caps: c,
            net: &net,
            stats: &st,
            load: ServerLoad::default(),
        };
        predict(
            Mode::ServerMesh,
            &settings(),
            &inputs,
            &Limits::default(),
            &Corrections::default(),
        )
        .first_display_ms
    };
    let cold = first(&c);
    // Once a mesh mode was shown, the other finds three.js loaded.
    c.code.displayed(Mode::ServerMesh);
    let warm = first(&c);
    assert!(cold - warm > 600.0, "{cold} → {warm}");
    assert_eq!(code_bytes(Mode::ServerMesh, &c), 0.0);
    assert!(code_bytes(Mode::WasmMesh, &c) < 10_000.0);
    // Without the WASM benchmark, 4b also fetches the kernel.
    c.code.wasm = false;
    assert!(code_bytes(Mode::WasmMesh, &c) >= WASM_CODE_BYTES);
}

#[test]
fn a_software_renderer_ray_casts_the_generated_shader_slowly() {
    use frep_adapt::predict::shader_frame_ms;
    // SwiftShader drew sake_pot's 69-statement shader at 576² in ~720 ms
    // a full frame, with a 13 ms benchmark.
    let soft = bench_desktop(SWIFTSHADER);
    let net = NetworkEstimate {
        rtt_ms: 1.0,
        bandwidth_bps: 1e9,
        samples: 4,
    };
    let mut st = stats(70);
    st.shader_statements = 69;
    let inputs = Inputs {
        caps: &soft,
        net: &net,
        stats: &st,
        load: ServerLoad::default(),
    };
    let ms = shader_frame_ms(&inputs, 576.0 * 576.0);
    assert!((360.0..1440.0).contains(&ms), "{ms}");
}
