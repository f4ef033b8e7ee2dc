//! Load bench of the WebSocket sessions: many studios orbiting and editing
//! at once against one in-process server, on loopback only.
//!
//! `cargo bench -p frep-server --bench load`. It starts a server on
//! 127.0.0.1:0 with its data in a temporary folder. It opens
//! `FREP_LOAD_SESSIONS` (100) sessions at once, and each:
//! 1. says hello (no WebGL2);
//! 2. asks for mode 1 (server frames);
//! 3. opens the example model `FREP_LOAD_MODEL` (`sphere`);
//! 4. for `FREP_LOAD_SECS` (15) seconds, sends camera moves at
//!    `FREP_LOAD_HZ` (15) per second. It stops moving now and then, for a
//!    full-quality still. It edits the parameter every `FREP_LOAD_EDIT_MS`
//!    (2000) ms, and acknowledges every frame.
//!
//! The frame latency is the time from sending a camera to receiving the
//! frame that shows it. Cameras skipped by the server have none. The bench
//! then closes every session, stops the server, and prints:
//! - p50/p99 latency;
//! - frames per second;
//! - the error count: server `error` messages, socket failures, sessions
//!   that saw no frame.
//!
//! It stops by itself: the run is bounded by its duration plus
//! `FREP_LOAD_GRACE_SECS` (30).

use std::collections::HashMap;
use std::time::{Duration, Instant};

use frep_server::Config;
use frep_wire::{
    BinaryHeader, CameraView, ClientMessage, ClientReport, Mode, ModelSummary, Screen,
    ServerMessage,
};
use futures_util::{SinkExt, StreamExt};
use tokio_tungstenite::tungstenite::Message;

fn env<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// What one session saw.
#[derive(Debug, Default)]
struct Outcome {
    latencies_ms: Vec<f64>,
    frames: u64,
    bytes: u64,
    errors: Vec<String>,
    decisions: u32,
    triggers: HashMap<String, u32>,
}

fn report() -> ClientReport {
    ClientReport {
        user_agent: "frep load bench".into(),
        webgl2: false,
        renderer: None,
        max_texture_size: 0,
        max_3d_texture_size: 0,
        webgpu: false,
        gpu_bench_ms: None,
        wasm_bench_meps: None,
        cpu_bench_ms: Some(10.0),
        screen: Screen {
            width: 1280,
            height: 800,
            pixel_ratio: 1.0,
        },
        mobile: false,
        device_memory_gb: None,
        cores: None,
    }
}

fn text(msg: &ClientMessage) -> Message {
    Message::Text(serde_json::to_string(msg).unwrap_or_default().into())
}

struct Plan {
    url: String,
    model_id: String,
    until: Instant,
    hz: f64,
    edit_every: Duration,
    viewport: (u32, u32),
}

/// One studio: connect, hello, mode 1, open, orbit and edit until `until`.
async fn session(n: usize, plan: std::sync::Arc<Plan>) -> Outcome {
    let mut out = Outcome::default();
    let ws = match tokio_tungstenite::connect_async(plan.url.as_str()).await {
        Ok((ws, _)) => ws,
        Err(e) => {
            out.errors.push(format!("connect: {e}"));
            return out;
        }
    };
    let (mut sink, mut stream) = ws.split();
    let open = |r: f64| ClientMessage::Open {
        model_id: Some(plan.model_id.clone()),
        version: None,
        source: None,
        params: vec![r],
    };
    let setup = [
        ClientMessage::Hello { report: report() },
        ClientMessage::Override {
            mode: Some(Mode::Still),
        },
        open(0.8),
    ];
    for m in &setup {
        if let Err(e) = sink.send(text(m)).await {
            out.errors.push(format!("send: {e}"));
            return out;
        }
    }
    let mut asked: HashMap<u64, Instant> = HashMap::new();
    let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / plan.hz.max(0.1)));
    let mut last_edit = Instant::now();
    let mut k: u64 = 0;
    let deadline = tokio::time::Instant::from_std(plan.until);
    loop {
        tokio::select! {
            _ = tokio::time::sleep_until(deadline) => break,
            _ = tick.tick() => {
                k += 1;
                // Distinct yaws per session so a frame's camera names its ask.
                let yaw = (n as f64 * 7.0 + k as f64 * 3.0) % 360.0 + (k as f64) * 1e-6;
                let moving = !k.is_multiple_of(20);
                let cam = ClientMessage::Camera {
                    camera: CameraView { yaw, ..CameraView::default() },
                    moving,
                    width: plan.viewport.0,
                    height: plan.viewport.1,
                    section: None,
                };
                asked.insert(yaw.to_bits(), Instant::now());
                if asked.len() > 256 {
                    asked.retain(|_, t| t.elapsed() < Duration::from_secs(10));
                }
                let mut msgs = vec![text(&cam)];
                if last_edit.elapsed() >= plan.edit_every {
                    last_edit = Instant::now();
                    msgs.push(text(&open(0.5 + 0.4 * ((k % 7) as f64 / 7.0))));
                }
                for m in msgs {
                    if let Err(e) = sink.send(m).await {
                        out.errors.push(format!("send: {e}"));
                        return out;
                    }
                }
            }
            msg = stream.next() => {
                let msg = match msg {
                    Some(Ok(m)) => m,
                    Some(Err(e)) => { out.errors.push(format!("socket: {e}")); return out; }
                    None => { out.errors.push("closed by the server".into()); return out; }
                };
                let reply = handle(msg, &mut asked, &mut out);
                if let Some(r) = reply {
                    if let Err(e) = sink.send(r).await {
                        out.errors.push(format!("send: {e}"));
                        return out;
                    }
                }
            }
        }
    }
    let _ = sink.send(Message::Close(None)).await;
    if out.frames == 0 {
        out.errors.push("no frame".into());
    }
    out
}

/// Handles one server message; answers what must be answered.
fn handle(msg: Message, asked: &mut HashMap<u64, Instant>, out: &mut Outcome) -> Option<Message> {
    match msg {
        Message::Text(t) => match serde_json::from_str::<ServerMessage>(t.as_str()) {
            Ok(ServerMessage::Ping { id }) => Some(text(&ClientMessage::Pong { id })),
            Ok(ServerMessage::Error { message }) => {
                out.errors.push(message);
                None
            }
            Ok(ServerMessage::Decision { decision }) => {
                out.decisions += 1;
                *out.triggers.entry(decision.trigger).or_default() += 1;
                None
            }
            Ok(_) => None,
            Err(e) => {
                out.errors.push(format!("bad message: {e}"));
                None
            }
        },
        Message::Binary(b) => {
            let n = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize;
            let header: BinaryHeader = serde_json::from_slice(&b[4..4 + n]).ok()?;
            match header {
                BinaryHeader::Probe { id, bytes } => Some(text(&ClientMessage::ProbeDone {
                    id,
                    bytes,
                    client_ms: 0.0,
                })),
                BinaryHeader::Frame { seq, camera, .. } => {
                    out.frames += 1;
                    out.bytes += (b.len() - 4 - n) as u64;
                    let latency = asked
                        .remove(&camera.yaw.to_bits())
                        .map(|t| t.elapsed().as_secs_f64() * 1e3);
                    if let Some(ms) = latency {
                        out.latencies_ms.push(ms);
                    }
                    Some(text(&ClientMessage::FrameAck {
                        seq,
                        latency_ms: latency.unwrap_or(0.0),
                    }))
                }
            }
        }
        _ => None,
    }
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

#[tokio::main]
async fn main() {
    let sessions: usize = env("FREP_LOAD_SESSIONS", 100);
    let secs: f64 = env("FREP_LOAD_SECS", 15.0);
    let hz: f64 = env("FREP_LOAD_HZ", 15.0);
    let edit_ms: u64 = env("FREP_LOAD_EDIT_MS", 2000);
    let grace: u64 = env("FREP_LOAD_GRACE_SECS", 30);
    let model: String = env("FREP_LOAD_MODEL", "sphere".to_string());
    let dir = tempfile::tempdir().expect("a temporary folder");
    let mut config = Config {
        data_dir: dir.path().to_path_buf(),
        static_dir: None,
        ..Config::default()
    };
    config.session.max_sessions = config.session.max_sessions.max(sessions + 1);
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("a loopback port");
    let addr = listener.local_addr().expect("its address");
    let (stop, stopped) = tokio::sync::oneshot::channel::<()>();
    let server = tokio::spawn(frep_server::run(listener, config, async move {
        let _ = stopped.await;
    }));
    let base = format!("http://{addr}");
    let client = reqwest::Client::new();
    let mut models: Option<Vec<ModelSummary>> = None;
    for _ in 0..500 {
        if let Ok(r) = client.get(format!("{base}/api/models")).send().await {
            if let Ok(m) = r.json().await {
                models = Some(m);
                break;
            }
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let models = models.expect("the server answers /api/models");
    let Some(m) = models.iter().find(|m| m.name == model) else {
        eprintln!("no example model named {model}");
        std::process::exit(2);
    };
    let plan = std::sync::Arc::new(Plan {
        url: format!("ws://{addr}/api/session"),
        model_id: m.id.clone(),
        until: Instant::now() + Duration::from_secs_f64(secs),
        hz,
        edit_every: Duration::from_millis(edit_ms),
        viewport: (480, 360),
    });
    let started = Instant::now();
    let tasks: Vec<_> = (0..sessions)
        .map(|n| tokio::spawn(session(n, plan.clone())))
        .collect();
    let bound = Duration::from_secs_f64(secs) + Duration::from_secs(grace);
    let mut outcomes = Vec::new();
    let mut errors = 0usize;
    for t in tasks {
        match tokio::time::timeout(bound.saturating_sub(started.elapsed()), t).await {
            Ok(Ok(o)) => outcomes.push(o),
            Ok(Err(e)) => {
                errors += 1;
                eprintln!("session task failed: {e}");
            }
            Err(_) => {
                errors += 1;
                eprintln!("a session did not finish in time");
            }
        }
    }
    let elapsed = started.elapsed().as_secs_f64();
    let _ = stop.send(());
    let _ = tokio::time::timeout(Duration::from_secs(grace), server).await;
    let mut lat: Vec<f64> = outcomes
        .iter()
        .flat_map(|o| o.latencies_ms.iter().copied())
        .collect();
    lat.sort_by(f64::total_cmp);
    let frames: u64 = outcomes.iter().map(|o| o.frames).sum();
    let bytes: u64 = outcomes.iter().map(|o| o.bytes).sum();
    let decisions: u32 = outcomes.iter().map(|o| o.decisions).sum();
    let mut triggers: HashMap<&str, u32> = HashMap::new();
    for (t, n) in outcomes.iter().flat_map(|o| o.triggers.iter()) {
        *triggers.entry(t.as_str()).or_default() += n;
    }
    let mut triggers: Vec<_> = triggers.into_iter().collect();
    triggers.sort();
    let mut samples: Vec<&String> = outcomes.iter().flat_map(|o| o.errors.iter()).collect();
    errors += samples.len();
    println!(
        "load: {sessions} sessions, {secs} s at {hz} Hz, edit every {edit_ms} ms, model {model}, {} cores",
        std::thread::available_parallelism().map(|n| n.get()).unwrap_or(0)
    );
    println!(
        "frames {frames} ({:.1}/s, {:.2}/s per session), {:.1} kB/frame, decisions {decisions}",
        frames as f64 / elapsed,
        frames as f64 / elapsed / sessions.max(1) as f64,
        bytes as f64 / frames.max(1) as f64 / 1e3,
    );
    println!(
        "frame latency ms: p50 {:.1}  p90 {:.1}  p99 {:.1}  max {:.1}  ({} frames matched)",
        percentile(&lat, 0.5),
        percentile(&lat, 0.9),
        percentile(&lat, 0.99),
        lat.last().copied().unwrap_or(f64::NAN),
        lat.len()
    );
    println!("decisions by trigger: {triggers:?}");
    println!("errors: {errors}");
    samples.sort();
    samples.dedup();
    for e in samples.iter().take(10) {
        println!("  {e}");
    }
    if errors > 0 {
        std::process::exit(1);
    }
}
