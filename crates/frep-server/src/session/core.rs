//! One session's state and its reactions to the client's messages, its
//! tasks' events and the clock. Reactions change state and queue messages
//! in the outbox; the session loop writes them (see the module docs of
//! [`super`]). The engine's clock is ms since the session started.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::Arc;
use std::time::{Duration, Instant};

use axum::extract::ws::Message;
use frep_adapt::{ImageSample, ModelStats, ServerSample};
use frep_artefact::compute::image;
use frep_artefact::Cancel;
use frep_wire::{
    CameraView, Change, ClientMessage, ClientReport, Decision, Mode, SectionPlane, ServerMessage,
};
use tokio::sync::{mpsc, watch, Semaphore};
use tokio::task::JoinHandle;
use tracing::Instrument;

use super::config::SessionConfig;
use super::decide::Decider;
use super::deliver::Pusher;
use super::hub::Hub;
use super::open::{self, OpenRequest, Opened};
use super::probe::Prober;
use super::stream::{self, Ask, InFlight};
use super::{follow, wire, Event};
use crate::state::AppState;

/// One session.
pub struct Session {
    id: String,
    state: AppState,
    hub: Arc<Hub>,
    config: Arc<SessionConfig>,
    user: String,
    start: Instant,
    events: mpsc::Sender<Event>,
    outbox: Vec<Message>,
    prober: Prober,
    decider: Decider,
    hello: bool,
    /// When the first hello came (the first decision waits for a probe).
    hello_at: Option<Instant>,
    opened: Option<Opened>,
    open_gen: u64,
    opening: Option<JoinHandle<()>>,
    camera: CameraView,
    section: Option<SectionPlane>,
    moving: bool,
    viewport: (u32, u32),
    asked: Instant,
    camera_seen: bool,
    slot: watch::Sender<Option<Ask>>,
    ask_gen: u64,
    in_flight: HashMap<u32, InFlight>,
    streamer: JoinHandle<()>,
    stream_cancel: Cancel,
    pusher: Pusher,
    jobs: Vec<(String, JoinHandle<()>)>,
    last_tick: u64,
    frame_sample: Option<ServerSample>,
}

impl Session {
    /// A session; starts its frame renderer.
    pub fn new(
        id: String,
        state: AppState,
        hub: Arc<Hub>,
        user: String,
        peer: Option<IpAddr>,
        events: mpsc::Sender<Event>,
    ) -> Result<Session, String> {
        let config = hub.config.clone();
        let decider = Decider::new(&config)?;
        let (slot, slot_rx) = watch::channel(None);
        let stream_cancel = Cancel::new();
        let in_flight = Arc::new(Semaphore::new(config.frames_in_flight.max(1)));
        let streamer = tokio::spawn(
            stream::run(
                slot_rx,
                in_flight,
                hub.clone(),
                state.artefacts.limits().clone(),
                events.clone(),
                stream_cancel.clone(),
            )
            .in_current_span(),
        );
        let max_jobs = state.config.limits.jobs_per_client.max(1);
        let pusher = Pusher {
            artefacts: state.artefacts.clone(),
            session: id.clone(),
            client_jobs: state.jobs.clone(),
            peer,
            max_jobs,
            session_jobs: Arc::new(Semaphore::new(max_jobs)),
            progress_every: Duration::from_millis(config.progress_ms.max(10)),
            events: events.clone(),
        };
        Ok(Session {
            prober: Prober::new(config.clone(), &id),
            id,
            state,
            hub,
            config,
            user,
            start: Instant::now(),
            events,
            outbox: Vec::new(),
            decider,
            hello: false,
            hello_at: None,
            opened: None,
            open_gen: 0,
            opening: None,
            camera: CameraView::default(),
            section: None,
            moving: false,
            viewport: (0, 0),
            asked: Instant::now(),
            camera_seen: false,
            slot,
            ask_gen: 0,
            in_flight: HashMap::new(),
            streamer,
            stream_cancel,
            pusher,
            jobs: Vec::new(),
            last_tick: 0,
            frame_sample: None,
        })
    }

    /// The session settings.
    pub fn config(&self) -> Arc<SessionConfig> {
        self.config.clone()
    }

    /// The messages to write now.
    pub fn take_outbox(&mut self) -> Vec<Message> {
        std::mem::take(&mut self.outbox)
    }

    fn now(&self) -> u64 {
        self.start.elapsed().as_millis() as u64
    }

    fn push(&mut self, msg: &ServerMessage) {
        self.outbox.push(wire::text(msg));
    }

    /// Queues an error message for the client.
    pub fn error(&mut self, message: impl Into<String>) {
        let message = message.into();
        tracing::debug!(%message, "error sent to the client");
        self.outbox.push(wire::error(message));
    }

    /// The first message.
    pub fn welcome(&mut self) {
        self.push(&ServerMessage::Welcome {
            session_id: self.id.clone(),
            server: env!("CARGO_PKG_VERSION").to_string(),
        });
    }

    /// A text message from the client.
    pub fn client_text(&mut self, text: &str) {
        match wire::parse(text) {
            Ok(msg) => self.client(msg),
            Err(e) => self.error(e),
        }
    }

    /// Dispatches one client message; the engine's decision, if any, is applied last.
    fn client(&mut self, msg: ClientMessage) {
        let now = self.now();
        let at = Instant::now();
        let decided = match msg {
            ClientMessage::Hello { report } | ClientMessage::Report { report } => {
                self.on_report(report, now, at)
            }
            ClientMessage::Open {
                model_id,
                version,
                source,
                params,
            } => {
                self.open(OpenRequest {
                    model_id,
                    version,
                    source,
                    params,
                });
                None
            }
            ClientMessage::Pong { id } => {
                if !self.prober.pong(id, at) {
                    self.error(format!("pong {id} answers no ping"));
                }
                self.network()
            }
            ClientMessage::ProbeDone {
                id,
                bytes,
                client_ms,
            } => match self.prober.probe_done(id, bytes, client_ms, at) {
                Ok(msgs) => {
                    self.outbox.extend(msgs);
                    // The first probe may be what the first decision waits for.
                    self.network().or_else(|| self.connect())
                }
                Err(e) => {
                    self.error(e);
                    None
                }
            },
            ClientMessage::Camera {
                camera,
                moving,
                width,
                height,
                section,
            } => self.on_camera(camera, moving, (width, height), section, now, at),
            ClientMessage::FrameAck { seq, latency_ms } => {
                self.ack(seq, latency_ms, at);
                None
            }
            ClientMessage::Displayed { mode, ms, bytes } => {
                self.decider.displayed(mode, ms, bytes, now)
            }
            ClientMessage::FrameRate { mode, fps, .. } => self.decider.frame_rate(mode, fps, now),
            ClientMessage::Override { mode } => self.decider.set_override(mode, now),
            ClientMessage::Cancel { key } => {
                self.cancel(&key);
                None
            }
        };
        if let Some(d) = decided {
            self.apply(d);
        }
    }

    /// A hello or report: the engine hears it. After the first hello the network probing
    /// starts, and the engine connects once a model is open too.
    fn on_report(&mut self, report: ClientReport, now: u64, at: Instant) -> Option<Decision> {
        let first = !self.hello;
        self.hello = true;
        self.hello_at.get_or_insert(at);
        let d = self.decider.report(report, now);
        if first {
            self.outbox.push(self.prober.ping(at));
            if self.prober.round_due(at) {
                let msgs = self.prober.start_round(at);
                self.outbox.extend(msgs);
            }
        }
        d.or_else(|| self.connect())
    }

    /// A new camera (and section): checked, kept, and the stream restarted. A new cut in
    /// view-set mode delivers the view set of that cut instead.
    fn on_camera(
        &mut self,
        camera: CameraView,
        moving: bool,
        viewport: (u32, u32),
        section: Option<SectionPlane>,
        now: u64,
        at: Instant,
    ) -> Option<Decision> {
        if let Err(e) = check_camera(&camera) {
            self.error(e);
            return None;
        }
        if let Err(e) = image::check_section(section.as_ref()) {
            self.error(e.to_string());
            return None;
        }
        let cut = section != self.section;
        self.section = section;
        self.camera = camera;
        self.moving = moving;
        self.viewport = viewport;
        self.asked = at;
        self.camera_seen = true;
        self.decider.activity(now);
        let view_set = self
            .decider
            .current()
            .is_some_and(|d| d.mode == Mode::ViewSet);
        if cut && view_set {
            // The view set of the new cut (superseding the last).
            self.deliver();
        } else {
            self.restream();
        }
        None
    }

    /// Connects the engine when both the hello and a model are there, and
    /// the link is measured or `first_decision_wait_ms` has passed.
    fn connect(&mut self) -> Option<Decision> {
        if self.decider.connected() || self.awaiting_probe() {
            return None;
        }
        let stats = ModelStats::from_summary(self.opened.as_ref()?.compiled.summary());
        self.decider
            .model(stats, self.prober.estimate(), self.now())
    }

    /// Whether the first decision still waits for the first probe.
    fn awaiting_probe(&self) -> bool {
        self.first_decision_deadline().is_some()
    }

    /// When the first decision's wait for a probe ends, while it waits (the
    /// session loop calls [`Session::first_decision_due`] then).
    pub fn first_decision_deadline(&self) -> Option<Instant> {
        let wait = Duration::from_millis(self.config.first_decision_wait_ms);
        let waiting =
            !self.decider.connected() && !self.prober.has_bandwidth() && self.prober.probing();
        self.hello_at
            .filter(|t| waiting && t.elapsed() < wait)
            .map(|t| t + wait)
    }

    /// The first decision's wait for a probe is over: decide on the prior.
    pub fn first_decision_due(&mut self) {
        if let Some(d) = self.connect() {
            self.apply(d);
        }
    }

    fn network(&mut self) -> Option<Decision> {
        if self.prober.probing() {
            // The round's figure comes when it ends.
            return None;
        }
        let now = self.now();
        self.decider.network(self.prober.estimate(), now)
    }

    fn open(&mut self, req: OpenRequest) {
        self.open_gen += 1;
        if let Some(t) = self.opening.take() {
            t.abort();
        }
        let gen = self.open_gen;
        let previous = self.opened.as_ref().map(|o| o.compiled.clone());
        let (state, events) = (self.state.clone(), self.events.clone());
        self.opening = Some(tokio::spawn(
            async move {
                let result = open::resolve(state, req, previous).await;
                let _ = events.send(Event::Opened { gen, result }).await;
            }
            .in_current_span(),
        ));
    }

    fn opened(&mut self, opened: Opened) {
        let changed = self
            .opened
            .as_ref()
            .is_none_or(|o| o.compiled.graph_hash() != opened.compiled.graph_hash());
        tracing::info!(
            model = ?opened.model_id,
            version = ?opened.version,
            graph = opened.compiled.graph_hash(),
            params = opened.params.len(),
            "model open"
        );
        self.opened = Some(opened);
        let decided = if !self.decider.connected() {
            self.connect()
        } else if let Some(o) = self.opened.as_ref().filter(|_| changed) {
            let stats = ModelStats::from_summary(o.compiled.summary());
            let now = self.now();
            self.decider.model(stats, self.prober.estimate(), now)
        } else {
            None
        };
        let streaming = self.camera_seen
            && self
                .decider
                .current()
                .is_some_and(|d| d.mode == Mode::Still);
        match decided {
            Some(d) => self.apply(d),
            // New values while frames stream: the next frame shows them.
            None if streaming && !changed => self.restream(),
            // Same decision, new model or values: its artefacts again.
            None => self.deliver(),
        }
    }

    /// Pushes a decision and delivers its mode.
    fn apply(&mut self, d: Decision) {
        tracing::info!(
            seq = d.seq,
            mode = ?d.mode,
            trigger = %d.trigger,
            overridden = d.overridden,
            reason = %d.reason,
            "decision"
        );
        self.push(&ServerMessage::Decision { decision: d });
        self.deliver();
    }

    /// The artefacts of the current decision for the open model, and the
    /// stream's state.
    fn deliver(&mut self) {
        let (Some(d), Some(o)) = (self.decider.current().cloned(), self.opened.clone()) else {
            return;
        };
        let running: Vec<String> = self
            .jobs
            .iter()
            .filter(|(_, t)| !t.is_finished())
            .map(|(k, _)| k.clone())
            .collect();
        let (msgs, started) = self
            .pusher
            .push(&d, &o, &self.camera, self.section, &running);
        self.outbox.extend(msgs);
        self.jobs.retain(|(_, t)| !t.is_finished());
        self.jobs.extend(started);
        self.restream();
    }

    /// Puts the latest camera, model and settings in the stream's slot
    /// (mode 1 only, once the client sent a camera: before, the `image`
    /// artefact is the first display).
    fn restream(&mut self) {
        if !self.camera_seen {
            return;
        }
        let d = self.decider.current();
        let (Some(d), Some(o)) = (d.filter(|d| d.mode == Mode::Still), self.opened.as_ref()) else {
            return;
        };
        self.ask_gen += 1;
        let ask = Ask {
            gen: self.ask_gen,
            model: o.compiled.clone(),
            params: o.params.clone(),
            camera: self.camera.clone(),
            section: self.section,
            moving: self.moving,
            viewport: self.viewport,
            settings: d.settings.clone(),
            asked: self.asked,
        };
        self.slot.send_replace(Some(ask));
    }

    fn ack(&mut self, seq: u32, latency_ms: f64, at: Instant) {
        let Some(f) = self.in_flight.remove(&seq) else {
            self.error(format!("frameAck {seq} answers no frame in flight"));
            return;
        };
        let ms = at.duration_since(f.sent).as_secs_f64() * 1e3;
        self.prober.frame_delivered(f.bytes, ms);
        tracing::debug!(
            seq,
            latency_ms,
            delivery_ms = ms,
            bytes = f.bytes,
            "frame acknowledged"
        );
    }

    fn cancel(&mut self, key: &str) {
        let before = self.jobs.len();
        self.jobs.retain(|(k, t)| {
            let hit = k == key;
            if hit {
                t.abort();
            }
            !hit
        });
        if self.jobs.len() == before {
            self.error(format!("no job of this session for {key}"));
        }
    }

    /// An event of the session's tasks.
    pub fn event(&mut self, event: Event) {
        match event {
            Event::Send(m) => self.outbox.push(m),
            Event::Frame(f) => {
                self.outbox.push(f.message);
                self.in_flight.insert(
                    f.seq,
                    InFlight {
                        permit: f.permit,
                        sent: Instant::now(),
                        bytes: f.bytes,
                    },
                );
                // Frames come many per second: the engine hears the latest
                // at its next tick, not each one (every sample can move the
                // settings it picks).
                self.frame_sample = Some(ServerSample::Image(ImageSample {
                    pixels: f.pixels,
                    quality: f.quality,
                    server_ms: f.server_ms,
                    bytes: f.bytes,
                }));
            }
            Event::Opened { gen, result } => {
                if gen != self.open_gen {
                    return;
                }
                self.opening = None;
                match result {
                    Ok(o) => self.opened(o),
                    Err(e) => self.error(e),
                }
            }
            Event::Measured(sample) => {
                let now = self.now();
                if let Some(d) = self.decider.measured(sample, now) {
                    self.apply(d);
                }
            }
            Event::Error(e) => self.error(e),
        }
    }

    /// Housekeeping: pings, probe rounds, expired frames, the engine's
    /// periodic re-decision with the server's load.
    pub fn tick(&mut self) {
        let at = Instant::now();
        if !self.hello {
            return;
        }
        self.prober.expire(at);
        if self.prober.ping_due(at) {
            self.outbox.push(self.prober.ping(at));
        }
        if self.prober.round_due(at) {
            let msgs = self.prober.start_round(at);
            self.outbox.extend(msgs);
        }
        let timeout = Duration::from_millis(self.config.frame_ack_timeout_ms);
        self.in_flight
            .retain(|_, f| at.duration_since(f.sent) < timeout);
        let now = self.now();
        if now.saturating_sub(self.last_tick) >= self.config.tick_ms {
            self.last_tick = now;
            if let Some(sample) = self.frame_sample.take() {
                if let Some(d) = self.decider.measured(sample, now) {
                    self.apply(d);
                }
            }
            let load = self.hub.load(&self.state.artefacts);
            if let Some(d) = self.decider.tick(load, now) {
                self.apply(d);
            }
        }
    }

    /// A committed change on the server.
    pub fn change(&mut self, change: &Change) {
        if let Some(m) = follow::on_change(change, self.opened.as_ref(), &self.user) {
            if let (ServerMessage::ModelChanged { version, .. }, Some(o)) =
                (&m, self.opened.as_mut())
            {
                // Announced once; a later open sets the version it opens.
                o.version = Some(*version);
            }
            self.push(&m);
        }
    }

    /// The change feed overflowed: ask the store instead.
    pub fn lagged(&mut self, missed: u64) {
        tracing::warn!(missed, "session fell behind the change feed");
        let Some(o) = self.opened.as_ref() else {
            return;
        };
        let Some(id) = o.model_id.clone() else {
            return;
        };
        let (state, events, version) = (self.state.clone(), self.events.clone(), o.version);
        tokio::spawn(async move {
            if let Some(m) = follow::catch_up(state, id, version).await {
                let _ = events.send(Event::Send(wire::text(&m))).await;
            }
        });
    }

    /// Stops the session's tasks (their jobs leave the artefact flights,
    /// which cancels jobs nobody else waits for).
    pub fn close(&mut self) {
        self.stream_cancel.cancel();
        self.streamer.abort();
        if let Some(t) = self.opening.take() {
            t.abort();
        }
        for (_, t) in self.jobs.drain(..) {
            t.abort();
        }
    }
}

/// Refuses a camera the renderer cannot use (non-finite angles, a field
/// of view outside (0, 180) degrees, a zoom that is not positive).
fn check_camera(c: &CameraView) -> Result<(), String> {
    let finite = c.yaw.is_finite() && c.pitch.is_finite() && c.pan.iter().all(|p| p.is_finite());
    let fov_ok = c.fov.is_none_or(|f| f.is_finite() && f > 0.0 && f < 180.0);
    if finite && fov_ok && c.zoom.is_finite() && c.zoom > 0.0 {
        Ok(())
    } else {
        Err(format!(
            "camera {c:?} is not usable (finite angles, fov in (0, 180), zoom > 0)"
        ))
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        self.close();
    }
}
