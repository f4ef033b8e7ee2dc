//! The WebSocket session (`GET /api/session`) against a real server on
//! 127.0.0.1:0 with a tokio-tungstenite client: hello and welcome, pings,
//! the bandwidth probe, decisions (reason, predictions, the client's
//! capabilities, overrides), mode 1 frame streaming (latest camera, at most
//! two in flight, smaller frames while moving), re-decisions when the
//! client's report or frame rate changes, other editors' saves, and bad
//! messages. Hysteresis windows are shortened in the configuration so no
//! test waits for them.

mod harness;

use std::time::Duration;

use frep_server::session::SessionConfig;
use frep_wire::{
    BinaryHeader, CameraView, ClientMessage, ClientReport, Decision, Mode, Screen, ServerMessage,
};
use futures_util::{SinkExt, StreamExt};
use harness::{config, Server, SPHERE};
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::Message;

type Ws =
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

/// Longest wait for one expected message (a generous bound for a loaded
/// machine, not a speed assertion).
const WAIT: Duration = Duration::from_secs(30);

/// What arrived: a server message, or a frame with its header and bytes.
#[derive(Debug)]
enum In {
    Text(ServerMessage),
    Frame(BinaryHeader, Vec<u8>),
    /// A probe the double answered.
    Probed,
}

/// A studio double: answers pings and probes itself (unless told not to)
/// and hands everything else to the test.
struct Client {
    ws: Ws,
    auto: bool,
    last_arrival: std::time::Instant,
    probes: u32,
}

impl Client {
    async fn connect(server: &Server, user: &str) -> Client {
        let url = server.base.replace("http://", "ws://") + "/api/session";
        let mut req = url.into_client_request().unwrap();
        req.headers_mut()
            .insert("x-frep-user", user.parse().unwrap());
        let (ws, _) = tokio_tungstenite::connect_async(req).await.unwrap();
        Client {
            ws,
            auto: true,
            last_arrival: std::time::Instant::now(),
            probes: 0,
        }
    }

    async fn send(&mut self, msg: &ClientMessage) {
        let text = serde_json::to_string(msg).unwrap();
        self.ws.send(Message::Text(text.into())).await.unwrap();
    }

    async fn raw(&mut self, text: &str) {
        self.ws.send(Message::Text(text.into())).await.unwrap();
    }

    /// The next message the test should see.
    async fn next(&mut self) -> In {
        loop {
            let msg = tokio::time::timeout(WAIT, self.ws.next())
                .await
                .expect("a message within the wait")
                .expect("the socket is open")
                .unwrap();
            let gap = self.last_arrival.elapsed().as_secs_f64() * 1e3;
            self.last_arrival = std::time::Instant::now();
            match msg {
                Message::Text(t) => {
                    let m: ServerMessage = serde_json::from_str(t.as_str()).unwrap();
                    if let (true, ServerMessage::Ping { id }) = (self.auto, &m) {
                        let id = *id;
                        self.send(&ClientMessage::Pong { id }).await;
                        continue;
                    }
                    return In::Text(m);
                }
                Message::Binary(b) => {
                    let n = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize;
                    let header: BinaryHeader = serde_json::from_slice(&b[4..4 + n]).unwrap();
                    let payload = b[4 + n..].to_vec();
                    if let (true, BinaryHeader::Probe { id, bytes }) = (self.auto, &header) {
                        assert_eq!(*bytes as usize, payload.len());
                        self.probes += 1;
                        let done = ClientMessage::ProbeDone {
                            id: *id,
                            bytes: payload.len() as u64,
                            client_ms: gap,
                        };
                        self.send(&done).await;
                        return In::Probed;
                    }
                    return In::Frame(header, payload);
                }
                _ => continue,
            }
        }
    }

    /// The next server text message (frames are skipped).
    async fn text(&mut self) -> ServerMessage {
        loop {
            if let In::Text(m) = self.next().await {
                return m;
            }
        }
    }

    /// The next decision (other texts skipped; errors fail the test).
    async fn decision(&mut self) -> Decision {
        loop {
            match self.text().await {
                ServerMessage::Decision { decision } => return decision,
                ServerMessage::Error { message } => panic!("error: {message}"),
                _ => {}
            }
        }
    }

    /// The next decision of `trigger` (others skipped: artefact timings
    /// and pings may re-decide in between).
    async fn decision_by(&mut self, trigger: &str) -> Decision {
        loop {
            let d = self.decision().await;
            if d.trigger == trigger {
                return d;
            }
        }
    }

    /// The next frame (texts skipped).
    async fn frame(&mut self) -> (BinaryHeader, Vec<u8>) {
        loop {
            if let In::Frame(h, p) = self.next().await {
                return (h, p);
            }
        }
    }

    async fn hello(&mut self, report: ClientReport) -> String {
        let ServerMessage::Welcome { session_id, .. } = self.text().await else {
            panic!("welcome first");
        };
        self.send(&ClientMessage::Hello { report }).await;
        session_id
    }

    async fn open_source(&mut self, source: &str) {
        let open = ClientMessage::Open {
            model_id: None,
            version: None,
            source: Some(source.to_string()),
            params: vec![],
        };
        self.send(&open).await;
    }
}

/// A report: with WebGL2, a GPU that takes `gpu_ms` for the benchmark.
fn report_gpu(webgl2: bool, gpu_ms: f64) -> ClientReport {
    ClientReport {
        user_agent: "session test".into(),
        webgl2,
        renderer: webgl2.then(|| "ANGLE (NVIDIA GeForce RTX 4090)".to_string()),
        max_texture_size: if webgl2 { 16384 } else { 0 },
        max_3d_texture_size: if webgl2 { 2048 } else { 0 },
        webgpu: false,
        gpu_bench_ms: webgl2.then_some(gpu_ms),
        wasm_bench_meps: Some(50.0),
        cpu_bench_ms: Some(10.0),
        screen: Screen {
            width: 1280,
            height: 800,
            pixel_ratio: 1.0,
        },
        mobile: false,
        device_memory_gb: Some(8.0),
        cores: Some(8),
    }
}

/// A report with a fast GPU when it has WebGL2.
fn report(webgl2: bool) -> ClientReport {
    report_gpu(webgl2, 0.5)
}

/// A server whose engine switches without waiting (tests of re-decision).
async fn server() -> (Server, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let mut c = config(dir.path());
    c.session = SessionConfig {
        downgrade_after_ms: 0,
        upgrade_after_ms: 0,
        idle_before_upgrade_ms: 0,
        probe_sizes: vec![16 << 10, 64 << 10],
        ..SessionConfig::default()
    };
    (Server::start(c).await, dir)
}

/// Width and height of a baseline or progressive JPEG (its SOF marker).
fn jpeg_size(b: &[u8]) -> (u32, u32) {
    assert_eq!(&b[..2], &[0xFF, 0xD8], "JPEG SOI");
    let mut i = 2;
    while i + 9 < b.len() {
        assert_eq!(b[i], 0xFF, "marker at {i}");
        let marker = b[i + 1];
        let len = u16::from_be_bytes([b[i + 2], b[i + 3]]) as usize;
        if (0xC0..=0xC3).contains(&marker) {
            let h = u16::from_be_bytes([b[i + 5], b[i + 6]]) as u32;
            let w = u16::from_be_bytes([b[i + 7], b[i + 8]]) as u32;
            return (w, h);
        }
        i += 2 + len;
    }
    panic!("no SOF marker");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn probes_then_decides_with_reason_predictions_and_network() {
    let (server, _dir) = server().await;
    let mut c = Client::connect(&server, "ann").await;
    let id = c.hello(report(true)).await;
    assert!(!id.is_empty());
    // The probe round (two sizes) is answered by the client double; then
    // the open decides with the measured network.
    while c.probes < 2 {
        if let In::Text(ServerMessage::Error { message }) = c.next().await {
            panic!("{message}");
        }
    }
    c.open_source(SPHERE).await;
    let d = c.decision().await;
    assert_eq!(d.trigger, "connect");
    assert_eq!(d.seq, 1);
    assert!(!d.reason.is_empty());
    assert_eq!(d.predictions.len(), 6);
    let modes: Vec<Mode> = d.predictions.iter().map(|p| p.mode).collect();
    assert_eq!(modes, Mode::ALL.to_vec());
    assert!(d.network.samples >= 2, "{:?}", d.network);
    assert_ne!(
        d.network.bandwidth_bps,
        SessionConfig::default().prior_bandwidth_bps
    );
    assert!(d.network.bandwidth_bps > 0.0);
    // The mode's artefacts follow.
    loop {
        if let ServerMessage::Artefact { artefact, .. } = c.text().await {
            assert!(artefact.url.starts_with("/api/artefacts/"));
            break;
        }
    }
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_first_decision_waits_for_the_first_probe() {
    // A server whose first decisions wait `wait_ms` for a probe.
    let waiting = |wait_ms: u64| async move {
        let dir = tempfile::tempdir().unwrap();
        let mut c = config(dir.path());
        c.session = SessionConfig {
            probe_sizes: vec![16 << 10, 64 << 10],
            first_decision_wait_ms: wait_ms,
            ..SessionConfig::default()
        };
        (Server::start(c).await, dir)
    };
    // Open at once: the decision still rests on a measured link. The wait
    // is long, so only the probe's answer can end it.
    let (server, _dir) = waiting(600_000).await;
    let mut c = Client::connect(&server, "ann").await;
    c.hello(report(true)).await;
    c.open_source(SPHERE).await;
    let d = c.decision().await;
    assert_eq!(d.trigger, "connect");
    assert!(c.probes >= 1);
    assert_ne!(
        d.network.bandwidth_bps,
        SessionConfig::default().prior_bandwidth_bps,
        "{:?}",
        d.network
    );
    server.stop().await;
    // A client that never answers a probe gets a decision on the prior
    // once the wait is over.
    let (server, _dir) = waiting(200).await;
    let mut mute = Client::connect(&server, "bob").await;
    mute.auto = false;
    mute.hello(report(true)).await;
    mute.open_source(SPHERE).await;
    let d = mute.decision().await;
    assert_eq!(d.trigger, "connect");
    assert_eq!(
        d.network.bandwidth_bps,
        SessionConfig::default().prior_bandwidth_bps
    );
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn without_webgl2_server_images_and_overrides_are_obeyed() {
    let (server, _dir) = server().await;
    let mut c = Client::connect(&server, "ann").await;
    c.hello(report(false)).await;
    c.open_source(SPHERE).await;
    let d = c.decision().await;
    assert!(
        matches!(d.mode, Mode::Still | Mode::ViewSet),
        "{:?}",
        d.mode
    );
    assert!(!d.overridden);
    let other = if d.mode == Mode::Still {
        Mode::ViewSet
    } else {
        Mode::Still
    };
    c.send(&ClientMessage::Override { mode: Some(other) }).await;
    let d2 = c.decision_by("override").await;
    assert_eq!(d2.mode, other);
    assert!(d2.overridden);
    assert_eq!(d2.trigger, "override");
    // A mode this client cannot show is not obeyed.
    c.send(&ClientMessage::Override {
        mode: Some(Mode::GpuRaycast),
    })
    .await;
    let d3 = c.decision_by("override").await;
    assert_ne!(d3.mode, Mode::GpuRaycast);
    assert!(!d3.overridden);
    server.stop().await;
}

fn camera(yaw: f64) -> CameraView {
    CameraView {
        yaw,
        ..CameraView::default()
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn streams_frames_of_the_latest_camera_two_in_flight() {
    let (server, _dir) = server().await;
    let models: Vec<frep_wire::ModelSummary> = server.get_json("/api/models").await;
    let sphere = models.iter().find(|m| m.name == "sphere").expect("example");
    let mut c = Client::connect(&server, "ann").await;
    c.hello(report(false)).await;
    c.send(&ClientMessage::Override {
        mode: Some(Mode::Still),
    })
    .await;
    c.send(&ClientMessage::Open {
        model_id: Some(sphere.id.clone()),
        version: None,
        source: None,
        params: vec![],
    })
    .await;
    let d = c.decision().await;
    assert_eq!(d.mode, Mode::Still);
    for yaw in [0.0, 10.0, 20.0, 30.0, 40.0] {
        let cam = ClientMessage::Camera {
            camera: camera(yaw),
            moving: true,
            width: 640,
            height: 480,
            section: None,
        };
        c.send(&cam).await;
    }
    // Two frames come unacknowledged; no third until one is acked.
    let (h1, p1) = c.frame().await;
    let (h2, _) = c.frame().await;
    let extra = tokio::time::timeout(Duration::from_millis(800), c.frame()).await;
    assert!(extra.is_err(), "a third frame came without an ack");
    let BinaryHeader::Frame {
        seq: s1,
        width: w1,
        height: ht1,
        moving: m1,
        ..
    } = h1
    else {
        panic!()
    };
    assert!(m1);
    assert_eq!(jpeg_size(&p1), (w1, ht1));
    let BinaryHeader::Frame {
        seq: s2,
        camera: cam2,
        ..
    } = h2
    else {
        panic!()
    };
    for s in [s1, s2] {
        c.send(&ClientMessage::FrameAck {
            seq: s,
            latency_ms: 5.0,
        })
        .await;
    }
    // The latest camera's frame arrives (stale cameras were skipped).
    let mut last = cam2;
    while last.yaw != 40.0 {
        let (h, _) = c.frame().await;
        let BinaryHeader::Frame { seq, camera, .. } = h else {
            panic!()
        };
        c.send(&ClientMessage::FrameAck {
            seq,
            latency_ms: 5.0,
        })
        .await;
        last = camera;
    }
    // Still: full size, larger than the moving frames.
    c.send(&ClientMessage::Camera {
        camera: camera(40.0),
        moving: false,
        width: 640,
        height: 480,
        section: None,
    })
    .await;
    // Moving frames already under way may come first; the still follows.
    let (h, p) = loop {
        let (h, p) = c.frame().await;
        let BinaryHeader::Frame { seq, moving, .. } = &h else {
            panic!()
        };
        c.send(&ClientMessage::FrameAck {
            seq: *seq,
            latency_ms: 5.0,
        })
        .await;
        if !moving {
            break (h, p);
        }
    };
    let BinaryHeader::Frame {
        width,
        height,
        camera,
        ..
    } = h
    else {
        panic!()
    };
    assert_eq!(camera.yaw, 40.0);
    assert!(width > w1 && height > ht1, "{width}x{height} vs {w1}x{ht1}");
    assert_eq!(jpeg_size(&p), (width, height));
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn re_decides_when_the_report_changes() {
    let (server, _dir) = server().await;
    let mut c = Client::connect(&server, "ann").await;
    c.hello(report(false)).await;
    c.open_source(SPHERE).await;
    let d = c.decision().await;
    assert!(matches!(d.mode, Mode::Still | Mode::ViewSet));
    // The benchmarks finished: WebGL2 with a fast GPU.
    c.send(&ClientMessage::Report {
        report: report(true),
    })
    .await;
    // A measurement may re-decide first (the probe round ends).
    let d2 = c.decision_by("report").await;
    assert!(d2.seq > d.seq);
    assert_ne!(d2.mode, d.mode, "{}", d2.reason);
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn slow_frames_downgrade() {
    let (server, _dir) = server().await;
    let mut c = Client::connect(&server, "ann").await;
    // A modest GPU: its frames could be slow, unlike a fast one's.
    c.hello(report_gpu(true, 2.0)).await;
    c.open_source(SPHERE).await;
    let d = c.decision().await;
    // The client's frames stay far under the target in this mode.
    let mut next = None;
    for _ in 0..20 {
        let slow = ClientMessage::FrameRate {
            mode: d.mode,
            fps: 2.0,
            frame_ms: 500.0,
        };
        c.send(&slow).await;
        c.send(&ClientMessage::Pong { id: 0 }).await; // a marker: answered with an error
        loop {
            match c.text().await {
                ServerMessage::Decision { decision } => {
                    next = Some(decision);
                    break;
                }
                ServerMessage::Error { .. } => break,
                _ => {}
            }
        }
        if next.is_some() {
            break;
        }
    }
    let d2 = next.expect("a re-decision after slow frames");
    assert_eq!(d2.trigger, "slowFrames", "{}", d2.reason);
    assert_ne!(d2.mode, d.mode);
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_messages_get_errors_and_the_session_lives_on() {
    let (server, _dir) = server().await;
    let mut c = Client::connect(&server, "ann").await;
    c.hello(report(false)).await;
    c.raw("not json").await;
    assert!(matches!(c.text().await, ServerMessage::Error { .. }));
    c.raw(r#"{"type":"teleport"}"#).await;
    assert!(matches!(c.text().await, ServerMessage::Error { .. }));
    c.ws.send(Message::Binary(vec![1, 2, 3].into()))
        .await
        .unwrap();
    assert!(matches!(c.text().await, ServerMessage::Error { .. }));
    c.open_source("my_model(x[3]) { my_model = ; }").await;
    let ServerMessage::Error { message } = c.text().await else {
        panic!("a compile error")
    };
    assert!(message.contains("error"), "{message}");
    c.send(&ClientMessage::FrameAck {
        seq: 77,
        latency_ms: 1.0,
    })
    .await;
    assert!(matches!(c.text().await, ServerMessage::Error { .. }));
    let bad_camera = r#"{"type":"camera","camera":{"yaw":0,"pitch":0,"fov":400,"zoom":1,"pan":[0,0,0]},"moving":true,"width":10,"height":10}"#;
    c.raw(bad_camera).await;
    assert!(matches!(c.text().await, ServerMessage::Error { .. }));
    // Still alive: an open decides.
    c.open_source(SPHERE).await;
    let d = c.decision().await;
    assert_eq!(d.predictions.len(), 6);
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn another_editors_save_is_announced() {
    let (server, _dir) = server().await;
    let m = server.create("shared", SPHERE).await;
    let mut c = Client::connect(&server, "ann").await;
    c.hello(report(false)).await;
    c.send(&ClientMessage::Open {
        model_id: Some(m.model.id.clone()),
        version: None,
        source: None,
        params: vec![],
    })
    .await;
    c.decision().await;
    let save = frep_wire::SaveVersion {
        source: SPHERE.replace("0.8", "0.7"),
        params: vec![],
        message: "smaller".into(),
        base: Some(1),
        assets: vec![],
    };
    let r = server
        .client
        .post(server.url(&format!("/api/models/{}/versions", m.model.id)))
        .header("x-frep-user", "bob")
        .json(&save)
        .send()
        .await
        .unwrap();
    assert!(r.status().is_success(), "{}", r.status());
    loop {
        if let ServerMessage::ModelChanged {
            model_id,
            version,
            author,
        } = c.text().await
        {
            assert_eq!(model_id, m.model.id);
            assert_eq!(version, 2);
            assert_eq!(author, "bob");
            break;
        }
    }
    server.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_mesh_mode_gets_its_artefacts_and_their_progress() {
    let (server, _dir) = server().await;
    let mut c = Client::connect(&server, "ann").await;
    c.hello(report(true)).await;
    c.send(&ClientMessage::Override {
        mode: Some(Mode::ServerMesh),
    })
    .await;
    c.open_source(SPHERE).await;
    let d = c.decision().await;
    assert_eq!(d.mode, Mode::ServerMesh);
    // Both meshes are pushed; the session computes them and says when each
    // is done. Messages may come in any order: a mesh's last progress can
    // come before the coarse one's push, and a re-decision on the coarse
    // mesh's measured cost may replace the mesh with another depth, perhaps
    // one already computed (then it comes ready).
    let mut mesh: Option<frep_wire::ArtefactRef> = None;
    let mut coarse = false;
    let mut done = std::collections::HashSet::new();
    let finished = |mesh: &Option<frep_wire::ArtefactRef>,
                    done: &std::collections::HashSet<String>| {
        mesh.as_ref()
            .is_some_and(|m| m.ready || done.contains(&m.key))
    };
    // A mesh superseded while its GET waits answers 503 `cancelled`: then a
    // newer one was pushed, and that is the one to fetch.
    let wait = async {
        loop {
            while !(coarse && finished(&mesh, &done)) {
                match c.text().await {
                    ServerMessage::Artefact { role, artefact } => match role.as_str() {
                        "mesh" => mesh = Some(artefact),
                        "meshCoarse" => coarse = true,
                        r => panic!("role {r} in mode 3"),
                    },
                    ServerMessage::Progress { key, fraction } => {
                        assert!((0.0..=1.0).contains(&fraction));
                        if fraction == 1.0 {
                            done.insert(key);
                        }
                    }
                    _ => {}
                }
            }
            let m = mesh.clone().unwrap();
            assert_eq!(m.media_type, "model/gltf-binary");
            let body = server.client.get(server.url(&m.url)).send().await.unwrap();
            let status = body.status();
            let bytes = body.bytes().await.unwrap();
            let text = String::from_utf8_lossy(&bytes).to_string();
            if status == reqwest::StatusCode::SERVICE_UNAVAILABLE && text.contains("cancelled") {
                mesh = None;
                continue;
            }
            assert!(status.is_success(), "{status}: {text}");
            break bytes;
        }
    };
    let bytes = tokio::time::timeout(Duration::from_secs(120), wait)
        .await
        .expect("the meshes and their progress within 2 minutes");
    assert_eq!(&bytes[..4], b"glTF");
    server.stop().await;
}
