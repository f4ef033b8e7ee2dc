//! The engine's behaviour over time: overrides, learning from reports,
//! hysteresis against jitter, upgrades only after a steady advantage and an
//! idle user, server load, and the decision log.

mod common;

use common::*;
use frep_adapt::predict::{predict, MESH_TRIANGLES_PER_CELL_FACTOR};
use frep_adapt::{ClientCaps, Inputs};
use frep_adapt::{ConfigError, Engine, EngineConfig, ServerLoad};
use frep_wire::Mode;

#[test]
fn an_override_is_obeyed_until_released() {
    let mut e = engine();
    let d0 = e.connect(workstation(), lan(), model(80), 0);
    assert_eq!(d0.mode, Mode::GpuRaycast);
    let d = e
        .set_override(Some(Mode::ViewSet), 1_000)
        .expect("an override decides");
    assert_eq!((d.mode, d.overridden), (Mode::ViewSet, true));
    assert_eq!(d.trigger, "override");
    assert!(
        d.reason.starts_with("your choice: server view set"),
        "{}",
        d.reason
    );
    assert_eq!(e.override_mode(), Some(Mode::ViewSet));
    // Time passes, the network changes: still the user's mode.
    for t in (2_000..40_000).step_by(1_000) {
        if let Some(d) = e.measurement(net(2.0, 80.0), t) {
            assert_eq!(d.mode, Mode::ViewSet);
        }
        if let Some(d) = e.tick(t + 500) {
            assert_eq!(d.mode, Mode::ViewSet);
        }
    }
    let d = e
        .set_override(None, 41_000)
        .expect("automatic again decides");
    assert!(!d.overridden);
    assert_eq!(d.mode, Mode::GpuRaycast, "{}", d.reason);
    assert_eq!(e.override_mode(), None);
}

#[test]
fn an_impossible_override_is_refused_with_the_reason() {
    let mut e = engine();
    e.connect(desktop_without_webgl(), net(20.0, 30.0), model(100), 0);
    let d = e
        .set_override(Some(Mode::GpuRaycast), 1_000)
        .expect("decides");
    assert!(matches!(d.mode, Mode::Still | Mode::ViewSet));
    assert!(!d.overridden);
    assert!(
        d.reason
            .starts_with("GPU ray casting is not possible here (no WebGL2)"),
        "{}",
        d.reason
    );
}

#[test]
fn displayed_times_correct_the_next_prediction() {
    let report = desktop_without_webgl();
    let mut e = engine();
    let d = e.connect(report.clone(), net(20.0, 30.0), model(100), 0);
    assert_eq!(d.mode, Mode::Still);
    let predicted = chosen(&d).first_display_ms;
    let caps = ClientCaps::from_report(&report, &e.config().limits);
    let again = |e: &Engine| {
        let stats = e.stats().expect("connected").clone();
        let net = net(20.0, 30.0);
        let inputs = Inputs {
            caps: &caps,
            net: &net,
            stats: &stats,
            load: ServerLoad::default(),
        };
        predict(
            Mode::Still,
            &d.settings,
            &inputs,
            &e.config().limits,
            e.corrections(),
        )
        .first_display_ms
    };
    assert!((again(&e) - predicted).abs() < 0.1);
    // The client took three times as long.
    e.displayed(Mode::Still, 3.0 * predicted, 40_000, 1_000);
    let next = again(&e);
    assert!(
        next > 2.0 * predicted && next <= 3.0 * predicted + 0.1,
        "{predicted} → {next}"
    );
    // Again three times: it stays there; then as predicted: it moves back.
    e.displayed(Mode::Still, 3.0 * predicted, 40_000, 2_000);
    assert!((again(&e) - 3.0 * predicted).abs() < 0.01 * predicted);
    e.displayed(Mode::Still, predicted, 40_000, 3_000);
    let back = again(&e);
    assert!(back > predicted && back < 3.0 * predicted, "{back}");
    // Other modes learnt nothing.
    assert_eq!(e.corrections().get(Mode::ViewSet).first_display.samples, 0);
}

/// The round trip (ms) on a 20 Mbit/s link where a desktop without WebGL
/// changes its mode at connection (streamed stills on short round trips, a
/// view set on long ones), found by bisection.
fn mode_threshold() -> f64 {
    let mode_at = |rtt: f64| {
        engine()
            .connect(desktop_without_webgl(), net(20.0, rtt), model(100), 0)
            .mode
    };
    let (mut lo, mut hi) = (5.0, 400.0);
    assert_eq!(mode_at(lo), Mode::Still);
    assert_eq!(mode_at(hi), Mode::ViewSet);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if mode_at(mid) == Mode::Still {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Mode changes over two minutes of jittery measurements around the
/// `threshold` round trip, and decisions issued.
fn jitter(mut e: Engine, threshold: f64, start: f64) -> (Vec<Mode>, u32) {
    let d0 = e.connect(
        desktop_without_webgl(),
        net(20.0, threshold * start),
        model(100),
        0,
    );
    let mut modes = vec![d0.mode];
    let mut decisions = 0;
    // A pseudo-random ±15 % round trip and ±20 % bandwidth every 250 ms (a
    // linear congruential sequence: reproducible).
    let mut x: u64 = 12345;
    let mut next = || {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (x >> 33) as f64 / (1u64 << 31) as f64 // [0, 1)
    };
    for step in 1..480u64 {
        let rtt = threshold * (0.85 + 0.3 * next());
        let mbps = 20.0 * (0.8 + 0.4 * next());
        let t = step * 250;
        for d in [e.measurement(net(mbps, rtt), t), e.tick(t + 100)]
            .into_iter()
            .flatten()
        {
            decisions += 1;
            if modes.last() != Some(&d.mode) {
                modes.push(d.mode);
            }
        }
    }
    (modes, decisions)
}

#[test]
fn jitter_around_a_threshold_does_not_flap() {
    let threshold = mode_threshold();
    // Without hysteresis the same measurements flap: the threshold is real.
    let eager = EngineConfig {
        switch_margin: 0.0,
        downgrade_after_ms: 0,
        upgrade_after_ms: 0,
        idle_before_upgrade_ms: 0,
        network_band: 1.0,
        ..EngineConfig::default()
    };
    let (modes, _) = jitter(Engine::new(eager).expect("valid"), threshold, 1.0);
    assert!(
        modes.len() > 10,
        "no flapping even without hysteresis: {modes:?}"
    );
    for start in [0.9, 1.1] {
        let (modes, decisions) = jitter(engine(), threshold, start);
        assert!(modes.len() <= 2, "flapped: {modes:?}");
        assert!(decisions <= 3, "{decisions} decisions for jitter");
    }
}

#[test]
fn a_better_mode_waits_ten_seconds_and_an_idle_user() {
    let mut heavy = model(18_000);
    heavy.primitives = Some(1500);
    let mut e = engine();
    let d0 = e.connect(workstation(), lan(), heavy, 0);
    assert_ne!(d0.mode, Mode::GpuRaycast);
    assert!(
        chosen(&d0).orbit_ms < 50.0,
        "the first mode is fine: {}",
        d0.reason
    );
    // The user simplifies the model: ray casting becomes possible and best,
    // but the current mode is fine, so the engine waits (the current mode's
    // settings may follow the new model at once).
    if let Some(d) = e.model_changed(model(80), 1_000) {
        assert_eq!(d.mode, d0.mode, "{}", d.reason);
    }
    for t in [3_000, 6_000, 9_000, 10_900] {
        assert_eq!(e.tick(t), None, "at {t} ms");
    }
    // Ten seconds have passed, but the user is dragging.
    e.activity(10_500);
    assert_eq!(e.tick(11_500), None);
    let d = e
        .tick(12_100)
        .expect("idle and ten seconds better: upgrade");
    assert_eq!(d.mode, Mode::GpuRaycast);
    assert_eq!(d.trigger, "periodic");
    assert!(d.reason.contains("better than"), "{}", d.reason);
}

#[test]
fn a_mode_made_impossible_by_an_edit_is_left_at_once() {
    let mut e = engine();
    let d0 = e.connect(workstation(), lan(), model(80), 0);
    assert_eq!(d0.mode, Mode::GpuRaycast);
    let mut heavy = model(18_000);
    heavy.primitives = Some(1500);
    let d = e.model_changed(heavy, 1_000).expect("4a is refused now");
    assert_ne!(d.mode, Mode::GpuRaycast);
    assert_eq!(d.trigger, "edit");
    assert!(d.reason.contains("no longer possible"), "{}", d.reason);
}

#[test]
fn a_loaded_server_pushes_work_to_the_client() {
    // A desktop GPU, no WASM benchmark, a fast link: streamed still frames
    // while the server is idle.
    let mut report = client(
        "ANGLE (Intel, Intel(R) UHD Graphics 620 Direct3D11)",
        Some(1.0),
        (1920, 1080, 1.0),
        false,
    );
    report.wasm_bench_meps = None;
    let mut e = engine();
    let d0 = e.connect(report, net(100.0, 5.0), model(300), 0);
    assert_eq!(d0.mode, Mode::Still, "{}", d0.reason);
    let busy = ServerLoad {
        busy_workers: 4,
        workers: 4,
        queued: 40,
    };
    let mut switched = None;
    for t in (1_000..6_000).step_by(500) {
        if let Some(d) = e.load(busy, t) {
            if d.mode != Mode::Still {
                switched = Some((t, d));
                break;
            }
        }
    }
    let (t, d) = switched.expect("left the server-rendered mode");
    assert!(t >= 3_000, "hysteresis: switched at {t}");
    assert_eq!(d.mode, Mode::GpuRaycast, "{}", d.reason);
    assert!(d.reason.contains("server load ×12"), "{}", d.reason);
}

#[test]
fn a_loaded_server_without_client_modes_sends_lighter_frames() {
    let mut e = engine();
    let d0 = e.connect(desktop_without_webgl(), net(100.0, 5.0), model(300), 0);
    assert_eq!(d0.mode, Mode::Still, "{}", d0.reason);
    let busy = ServerLoad {
        busy_workers: 4,
        workers: 4,
        queued: 40,
    };
    // The load factor left its band: the settings follow at once.
    let d = e.load(busy, 1_000).expect("lighter settings");
    assert_eq!(d.mode, Mode::Still);
    let pixels = |d: &frep_wire::Decision| d.settings.width * d.settings.height;
    assert!(pixels(&d) < pixels(&d0), "{}", d.reason);
    // A load that stays put changes nothing more.
    for t in [2_000, 3_000, 10_000] {
        assert_eq!(e.load(busy, t), None);
    }
}

#[test]
fn decisions_are_logged_with_inputs_and_predictions() {
    let config = EngineConfig {
        log_capacity: 4,
        ..EngineConfig::default()
    };
    let mut e = Engine::new(config).expect("valid");
    let d = e.connect(workstation(), lan(), model(80), 0);
    let entry = e.log().last().expect("logged");
    assert_eq!(entry.issued, Some(d.seq));
    assert_eq!(entry.predictions, d.predictions);
    assert_eq!(entry.reason, d.reason);
    assert_eq!(entry.inputs.tape_len, 80);
    assert_eq!(entry.inputs.network, lan());
    let mut seqs = vec![d.seq];
    for (i, m) in [
        Mode::Still,
        Mode::ViewSet,
        Mode::ServerMesh,
        Mode::Volume,
        Mode::WasmMesh,
    ]
    .into_iter()
    .enumerate()
    {
        let d = e
            .set_override(Some(m), 1_000 * (i as u64 + 1))
            .expect("decides");
        seqs.push(d.seq);
    }
    assert_eq!(seqs, vec![1, 2, 3, 4, 5, 6]);
    let kept: Vec<Option<u32>> = e.log().map(|l| l.issued).collect();
    assert_eq!(kept, vec![Some(3), Some(4), Some(5), Some(6)]);
    // The log serializes for the server's trace.
    let json = serde_json::to_string(e.log().last().expect("logged")).expect("serializes");
    assert!(json.contains("\"trigger\":\"override\""), "{json}");
}

#[test]
fn events_before_connect_decide_nothing() {
    let mut e = engine();
    assert_eq!(e.measurement(lan(), 0), None);
    assert_eq!(e.tick(10), None);
    assert_eq!(e.set_override(Some(Mode::Still), 20), None);
    assert!(e.current().is_none());
    // The override is kept for when the session starts.
    let d = e.connect(workstation(), lan(), model(80), 30);
    assert_eq!((d.mode, d.overridden), (Mode::Still, true));
}

#[test]
fn bad_configs_are_refused() {
    let bad = [
        EngineConfig {
            switch_margin: 1.5,
            ..EngineConfig::default()
        },
        EngineConfig {
            network_band: 0.5,
            ..EngineConfig::default()
        },
        EngineConfig {
            log_capacity: 0,
            ..EngineConfig::default()
        },
    ];
    for c in bad {
        assert!(matches!(Engine::new(c), Err(ConfigError::Invalid { .. })));
    }
    let mut c = EngineConfig::default();
    c.limits.server_mesh_depths = (8, 5);
    let err = Engine::new(c).expect_err("depths reversed");
    assert!(err.to_string().contains("serverMeshDepths"), "{err}");
}

#[test]
fn nonsense_measurements_do_not_break_decisions() {
    let mut e = engine();
    let mut report = workstation();
    report.gpu_bench_ms = Some(f64::NAN);
    report.screen.pixel_ratio = 0.0;
    let d = e.connect(report, net(f64::INFINITY, -5.0), model(80), 0);
    for p in &d.predictions {
        assert!(
            p.cost.is_finite() && p.first_display_ms.is_finite(),
            "{p:?}"
        );
    }
    assert_eq!(e.frame_rate(Mode::GpuRaycast, f64::NAN, 100), None);
    e.displayed(Mode::GpuRaycast, -1.0, 0, 200);
    assert_eq!(
        e.corrections().get(Mode::GpuRaycast).first_display.samples,
        0
    );
}

#[test]
fn a_report_without_webgl_leaves_a_gpu_mode_at_once() {
    let mut e = engine();
    assert_eq!(
        e.connect(workstation(), lan(), model(80), 0).mode,
        Mode::GpuRaycast
    );
    // The context was lost: the client reports again without WebGL2.
    let mut lost = workstation();
    lost.webgl2 = false;
    let d = e.report(lost, 1_000).expect("4a is impossible now");
    assert!(matches!(d.mode, Mode::Still | Mode::ViewSet));
    assert_eq!(d.trigger, "report");
    assert!(
        d.reason
            .contains("GPU ray casting no longer possible (no WebGL2)"),
        "{}",
        d.reason
    );
}

#[test]
fn server_measurements_replace_the_estimates() {
    use frep_adapt::{MeshSample, ServerSample};
    let report = workstation();
    let mut e = engine();
    e.connect(report.clone(), lan(), model(100), 0);
    // The server mesh's settings as the engine chose them.
    let all = e.predictions().expect("connected");
    let settings = all[2].prediction.settings.clone();
    assert_eq!(all[2].prediction.mode, Mode::ServerMesh);
    let caps = ClientCaps::from_report(&report, &e.config().limits);
    let mesh = |e: &Engine| {
        let stats = e.stats().expect("connected").clone();
        let inputs = Inputs {
            caps: &caps,
            net: &lan(),
            stats: &stats,
            load: ServerLoad::default(),
        };
        predict(
            Mode::ServerMesh,
            &settings,
            &inputs,
            &e.config().limits,
            e.corrections(),
        )
    };
    let before = mesh(&e);
    // The server polygonized this model at depth 6: 10 ms per thousand
    // triangles (five times the estimate) and 9 bytes per triangle.
    e.server_measured(
        ServerSample::Mesh(MeshSample {
            depth: 6,
            triangles: 40_000,
            server_ms: 400.0,
            bytes: 360_000,
        }),
        1_000,
    );
    assert_eq!(
        e.stats().and_then(|s| s.measured.mesh).map(|m| m.depth),
        Some(6)
    );
    let after = mesh(&e);
    // 40 000 triangles at depth 6 is 9.8 per 4^depth: more triangles, and
    // each costs more to make and to send.
    let ratio = 40_000.0 / 4096.0 / MESH_TRIANGLES_PER_CELL_FACTOR;
    let bytes = 9.0 * 40_000.0 * 4f64.powi(i32::from(settings.mesh_depth) - 6);
    assert!(
        (after.bytes - bytes).abs() < 1.0,
        "{} vs {bytes}",
        after.bytes
    );
    assert!(after.bytes > 2.0 * ratio * before.bytes * 0.99);
    assert!(after.first_display_ms > 2.0 * before.first_display_ms);
}

#[test]
fn measured_benchmarks_replace_guesses_at_once() {
    // Connected before the GPU benchmark ran: the engine guesses an
    // ordinary desktop GPU (3 ms) and ray casting is not chosen.
    let mut early = workstation();
    early.gpu_bench_ms = None;
    let mut e = engine();
    let d0 = e.connect(early, lan(), model(80), 0);
    assert_ne!(d0.mode, Mode::GpuRaycast, "{}", d0.reason);
    // The benchmark says 0.3 ms: no ten-second wait for the upgrade.
    let d = e.report(workstation(), 500).expect("re-decided");
    assert_eq!(d.mode, Mode::GpuRaycast, "{}", d.reason);
    assert_eq!(d.trigger, "report");
    assert!(
        d.reason
            .starts_with("measured benchmarks replace the guesses"),
        "{}",
        d.reason
    );
    // The same report again changes nothing.
    assert_eq!(e.report(workstation(), 1_000), None);
}

#[test]
fn a_lasting_hold_is_logged_once() {
    let mut heavy = model(18_000);
    heavy.primitives = Some(1500);
    let mut e = engine();
    e.connect(workstation(), lan(), heavy, 0);
    e.activity(0);
    e.model_changed(model(80), 1_000);
    // The user keeps dragging: the upgrade waits, tick after tick.
    for t in (2_000..30_000).step_by(1_000) {
        e.activity(t);
        assert_eq!(e.tick(t + 500), None);
    }
    let holds: Vec<_> = e.log().filter(|l| l.issued.is_none()).collect();
    assert_eq!(holds.len(), 1, "{holds:?}");
    assert_eq!(holds[0].best, Mode::GpuRaycast);
    assert!(holds[0]
        .reason
        .starts_with("held: GPU ray casting preferred since 1000 ms"));
}

#[test]
fn a_slow_display_lowers_the_settings_next_time() {
    let mut e = engine();
    e.connect(workstation(), net(5.0, 40.0), model(300), 0);
    let d0 = e
        .set_override(Some(Mode::ServerMesh), 100)
        .expect("decides");
    assert_eq!(d0.mode, Mode::ServerMesh);
    let predicted = chosen(&d0).first_display_ms;
    // The mesh took ten times as long to show: the next one is coarser.
    let d = e
        .displayed(Mode::ServerMesh, 10.0 * predicted, 300_000, 5_000)
        .expect("settings follow the correction");
    assert_eq!((d.mode, d.overridden), (Mode::ServerMesh, true));
    assert_eq!(d.trigger, "displayed");
    assert!(
        d.settings.mesh_depth < d0.settings.mesh_depth,
        "{} → {}",
        d0.settings.mesh_depth,
        d.settings.mesh_depth
    );
}

#[test]
fn a_mode_once_shown_no_longer_pays_for_its_code() {
    // A 1.5 Mbit/s link: three.js (115 kB) is ~0.6 s of a first mesh.
    let mut e = engine();
    e.connect(workstation(), net(1.5, 50.0), model(80), 0);
    let d0 = e
        .set_override(Some(Mode::ServerMesh), 100)
        .expect("decides");
    let before = chosen(&d0).first_display_ms;
    // Shown exactly as predicted: no correction, only the code is loaded.
    e.displayed(Mode::ServerMesh, before, 100_000, 2_000);
    let last = e.log().last().expect("logged");
    assert!(last.inputs.caps.code.three);
    let after = last
        .predictions
        .iter()
        .find(|p| p.mode == Mode::ServerMesh)
        .expect("predicted")
        .first_display_ms;
    assert!(before - after > 600.0, "{before} → {after}");
    // Mode 4b shares three.js; its own chunk is still to load.
    let caps = &last.inputs.caps;
    assert!(frep_adapt::predict::code_bytes(Mode::WasmMesh, caps) < 10_000.0);
}
