//! Delivering a decision's artefacts.
//! 1. Each is registered with the artefact service ([`Artefacts::request`]).
//!    Requests are grouped per session and role, so a newer request
//!    supersedes the older job.
//! 2. Each is pushed as an `artefact` message.
//! 3. The session computes those not ready, each taking one of the client's
//!    `jobs_per_client` places. Without a free place, the client's own GET
//!    computes it, joining nothing.
//! 4. It pushes `progress` while they run.
//! 5. It hands the engine their measured cost.

use std::net::IpAddr;
use std::sync::Arc;
use std::time::Duration;

use frep_adapt::{ImageSample, MeshSample, ServerSample, VolumeSample};
use frep_artefact::{ArtefactBody, Artefacts, SupersedeGroup};
use frep_wire::{ArtefactRef, ArtefactSpec, CameraView, Decision, SectionPlane, ServerMessage};
use tokio::sync::{mpsc, Semaphore};

use super::open::Opened;
use super::specs::{fit, specs};
use super::{wire, Event};
use crate::state::{ClientJobs, JobSlot};

/// Registers the decided mode's artefacts and starts those not ready;
/// answers the messages to push now, or an error message.
pub struct Pusher {
    /// The artefact service.
    pub artefacts: Arc<Artefacts>,
    /// The session's id (superseding groups).
    pub session: String,
    /// Job places per client address (`jobs_per_client`).
    pub client_jobs: Arc<ClientJobs>,
    /// The client's address, when the server knows it.
    pub peer: Option<IpAddr>,
    /// `jobs_per_client`.
    pub max_jobs: usize,
    /// Job places of this session when the address is unknown.
    pub session_jobs: Arc<Semaphore>,
    /// Progress pushes at most this often.
    pub progress_every: Duration,
    /// Where the jobs report.
    pub events: mpsc::Sender<Event>,
}

impl Pusher {
    /// Registers and starts the artefacts of `decision` for `opened`;
    /// returns the messages and the started jobs (key, task).
    pub fn push(
        &self,
        decision: &Decision,
        opened: &Opened,
        camera: &CameraView,
        section: Option<SectionPlane>,
        running: &[String],
    ) -> (
        Vec<axum::extract::ws::Message>,
        Vec<(String, tokio::task::JoinHandle<()>)>,
    ) {
        let mut messages = Vec::new();
        let mut jobs = Vec::new();
        let limits = self.artefacts.limits().clone();
        for (role, spec) in specs(decision, camera, section) {
            let spec = fit(spec, &limits);
            let group = SupersedeGroup(format!("{}/{role}", self.session));
            let r = match self.artefacts.request(
                opened.compiled.clone(),
                &opened.params,
                spec.clone(),
                Some(group),
            ) {
                Ok(r) => r,
                Err(e) => {
                    messages.push(wire::error(format!("{role}: {e}")));
                    continue;
                }
            };
            messages.push(wire::text(&ServerMessage::Artefact {
                role: role.to_string(),
                artefact: r.clone(),
            }));
            if r.ready {
                continue;
            }
            if running.contains(&r.key) {
                continue;
            }
            // Without a free job place the client's own GET computes it.
            if let Some(permit) = self.place() {
                let task = tokio::spawn(prefetch(
                    self.artefacts.clone(),
                    r.clone(),
                    spec,
                    self.progress_every,
                    self.events.clone(),
                    permit,
                ));
                jobs.push((r.key, task));
            }
        }
        (messages, jobs)
    }

    /// One job place: the client's (by address), else the session's.
    fn place(&self) -> Option<JobPlace> {
        match self.peer {
            Some(ip) => self
                .client_jobs
                .acquire(ip, self.max_jobs)
                .ok()
                .map(JobPlace::Client),
            None => self
                .session_jobs
                .clone()
                .try_acquire_owned()
                .ok()
                .map(JobPlace::Session),
        }
    }
}

/// A taken job place, given back on drop.
#[derive(Debug)]
pub enum JobPlace {
    /// One of the client address's `jobs_per_client`.
    Client(JobSlot),
    /// One of the session's own (address unknown).
    Session(tokio::sync::OwnedSemaphorePermit),
}

/// Computes one artefact, pushing progress, then its measured cost.
async fn prefetch(
    artefacts: Arc<Artefacts>,
    r: ArtefactRef,
    spec: ArtefactSpec,
    every: Duration,
    events: mpsc::Sender<Event>,
    _place: JobPlace,
) {
    let get = artefacts.get(&r.key);
    tokio::pin!(get);
    let mut last = -1.0;
    let body = loop {
        tokio::select! {
            body = &mut get => break body,
            _ = tokio::time::sleep(every) => {
                let f = artefacts.progress(&r.key).unwrap_or(0.0);
                if f != last {
                    last = f;
                    let msg = ServerMessage::Progress { key: r.key.clone(), fraction: f };
                    if events.send(Event::Send(wire::text(&msg))).await.is_err() {
                        return;
                    }
                }
            }
        }
    };
    let event = match body {
        Ok(body) => {
            let done = ServerMessage::Progress {
                key: r.key.clone(),
                fraction: 1.0,
            };
            if events.send(Event::Send(wire::text(&done))).await.is_err() {
                return;
            }
            match sample(&spec, &body) {
                Some(s) => Event::Measured(s),
                None => return,
            }
        }
        Err(frep_artefact::ArtefactError::Cancelled) => return,
        Err(e) => Event::Error(format!("artefact {}: {e}", r.key)),
    };
    let _ = events.send(event).await;
}

/// The engine's measurement of a computed artefact.
pub fn sample(spec: &ArtefactSpec, body: &ArtefactBody) -> Option<ServerSample> {
    let bytes = body.bytes.len() as u64;
    let server_ms = body.server_ms;
    Some(match spec {
        ArtefactSpec::Image {
            width,
            height,
            quality,
            ..
        } => ServerSample::Image(ImageSample {
            pixels: u64::from(*width) * u64::from(*height),
            quality: *quality,
            server_ms,
            bytes,
        }),
        ArtefactSpec::ViewSet {
            views,
            elevations,
            width,
            height,
            quality,
            ..
        } => ServerSample::Image(ImageSample {
            pixels: u64::from(*width)
                * u64::from(*height)
                * u64::from(*views)
                * elevations.len().max(1) as u64,
            quality: *quality,
            server_ms,
            bytes,
        }),
        ArtefactSpec::Mesh { depth } => ServerSample::Mesh(MeshSample {
            depth: *depth,
            triangles: glb_triangles(&body.bytes).unwrap_or(0),
            server_ms,
            bytes,
        }),
        ArtefactSpec::Slices { grid } => ServerSample::Volume(VolumeSample {
            grid: *grid,
            server_ms,
            bytes,
        }),
        _ => return None,
    })
}

/// Triangles of a glb: the index count of its first mesh's primitives over
/// three (read from the JSON chunk; meshopt compression keeps the counts).
pub fn glb_triangles(glb: &[u8]) -> Option<u64> {
    let word =
        |i: usize| -> Option<u32> { Some(u32::from_le_bytes(glb.get(i..i + 4)?.try_into().ok()?)) };
    if glb.get(0..4)? != b"glTF" || word(16)? != 0x4E4F_534A {
        return None;
    }
    let len = word(12)? as usize;
    let json: serde_json::Value = serde_json::from_slice(glb.get(20..20 + len)?).ok()?;
    let accessors = json.get("accessors")?.as_array()?;
    let mut total = 0;
    for mesh in json.get("meshes")?.as_array()? {
        for prim in mesh.get("primitives")?.as_array()? {
            let i = prim.get("indices")?.as_u64()? as usize;
            total += accessors.get(i)?.get("count")?.as_u64()? / 3;
        }
    }
    Some(total)
}
