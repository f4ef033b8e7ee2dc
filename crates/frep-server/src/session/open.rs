//! Opening a model in a session, and the artefacts its mode needs.
//!
//! `open` names a stored version (`modelId`, `version`) or carries a
//! source (unsaved, or edited on top of `modelId`), with parameter values.
//! The source is compiled off the async threads at its default parameters
//! (so the model box, and with it the camera, stays put while a slider is
//! dragged); the session's last compiled model is reused when the source is
//! the same, so a parameter edit costs no compile.
//!
//! After each decision or open, the artefacts of the decided mode are
//! registered with the artefact service ([`Artefacts::request`], grouped
//! per session and role so a newer request supersedes the older job) and
//! pushed as `artefact` messages: `image` (mode 1's first display),
//! `viewSetIndex` + `viewSet` (2), `meshCoarse` + `mesh` (3), `shader`
//! (4a), `slices` (volume). The session then starts computing those not
//! ready (at most `jobs_per_client` at once; the client's GET joins the
//! same job), pushing `progress` while they run, and hands the engine the
//! measured cost.

use std::net::IpAddr;
use std::sync::Arc;
use std::time::Duration;

use frep_adapt::{ImageSample, MeshSample, ServerSample, VolumeSample};
use frep_artefact::{ArtefactBody, ArtefactLimits, Artefacts, Compiled, SupersedeGroup};
use frep_wire::{ArtefactRef, ArtefactSpec, CameraView, Decision, Mode, ServerMessage};
use tokio::sync::{mpsc, Semaphore};

use super::{wire, Event};
use crate::compile::{check_params, check_source, compile_source};
use crate::state::{AppState, ClientJobs, JobSlot};
use crate::versions::load_version;

/// What `open` asked for.
#[derive(Clone, Debug)]
pub struct OpenRequest {
    /// Stored model.
    pub model_id: Option<String>,
    /// Its version (`None`: latest).
    pub version: Option<u32>,
    /// Source text (unsaved or edited).
    pub source: Option<String>,
    /// Parameter values.
    pub params: Vec<f64>,
}

/// A model open in a session.
#[derive(Clone, Debug)]
pub struct Opened {
    /// Stored model, if any.
    pub model_id: Option<String>,
    /// The stored version it is (or was edited from).
    pub version: Option<u32>,
    /// The compiled model.
    pub compiled: Arc<Compiled>,
    /// Parameter values.
    pub params: Arc<Vec<f64>>,
}

/// Resolves and compiles an open request (`previous`: the session's last
/// model, reused when the source is the same).
pub async fn resolve(
    state: AppState,
    req: OpenRequest,
    previous: Option<Arc<Compiled>>,
) -> Result<Opened, String> {
    check_params(&state, &req.params).map_err(|e| e.to_string())?;
    let (source, version, stored_params) = match (&req.source, &req.model_id) {
        (Some(s), _) => (s.clone(), req.version, Vec::new()),
        (None, Some(id)) => {
            let v = load_version(&state, id.clone(), req.version)
                .await
                .map_err(|e| e.to_string())?;
            (v.source, Some(v.number), v.params)
        }
        (None, None) => return Err("open needs a modelId or a source".to_string()),
    };
    check_source(&state, &source).map_err(|e| e.to_string())?;
    let params = if req.params.is_empty() {
        stored_params
    } else {
        req.params.clone()
    };
    let compiled = match previous.filter(|p| p.source() == source) {
        Some(p) => p,
        None => {
            // The box is detected at the defaults, so a slider does not
            // move the camera; the compile does not depend on the values.
            let c = compile_source(&state, source, None, Vec::new())
                .await
                .map_err(|e| e.to_string())?
                .map_err(|d| {
                    let first = d.first().map(|d| d.rendered.clone()).unwrap_or_default();
                    format!("the model has {} error(s): {first}", d.len())
                })?;
            // The summary generates the shader: off the async threads.
            let c2 = c.clone();
            tokio::task::spawn_blocking(move || {
                let _ = c2.summary();
            })
            .await
            .map_err(|e| format!("summary task failed: {e}"))?;
            c
        }
    };
    Ok(Opened {
        model_id: req.model_id,
        version,
        compiled,
        params: Arc::new(params),
    })
}

/// The artefacts a mode needs, by role (module docs).
pub fn specs(decision: &Decision, camera: &CameraView) -> Vec<(&'static str, ArtefactSpec)> {
    let s = &decision.settings;
    match decision.mode {
        Mode::Still => vec![(
            "image",
            ArtefactSpec::Image {
                camera: camera.clone(),
                width: s.width,
                height: s.height,
                format: s.format,
                quality: s.quality,
            },
        )],
        Mode::ViewSet => {
            let (views, elevations) = (s.views, s.elevations.clone());
            let (width, height, format, quality) = (s.width, s.height, s.format, s.quality);
            let fov = camera.fov;
            vec![
                (
                    "viewSetIndex",
                    ArtefactSpec::ViewSetIndex {
                        views,
                        elevations: elevations.clone(),
                        width,
                        height,
                        format,
                        quality,
                        fov,
                    },
                ),
                (
                    "viewSet",
                    ArtefactSpec::ViewSet {
                        views,
                        elevations,
                        width,
                        height,
                        format,
                        quality,
                        fov,
                    },
                ),
            ]
        }
        Mode::ServerMesh => {
            let mut v = Vec::new();
            if s.coarse_depth > 0 && s.coarse_depth < s.mesh_depth {
                v.push((
                    "meshCoarse",
                    ArtefactSpec::Mesh {
                        depth: s.coarse_depth,
                    },
                ));
            }
            v.push((
                "mesh",
                ArtefactSpec::Mesh {
                    depth: s.mesh_depth,
                },
            ));
            v
        }
        Mode::GpuRaycast => vec![("shader", ArtefactSpec::Shader)],
        Mode::Volume => vec![(
            "slices",
            ArtefactSpec::Slices {
                grid: s.volume_grid,
            },
        )],
        // The browser polygonizes from the source it already has.
        Mode::WasmMesh => Vec::new(),
    }
}

/// `(width, height)` scaled down (aspect kept) to at most `max_side` and
/// `max_pixels`.
fn fit_size(width: u32, height: u32, max_side: u32, max_pixels: u64) -> (u32, u32) {
    let (w, h) = (f64::from(width.max(1)), f64::from(height.max(1)));
    let mut scale = (f64::from(max_side.max(1)) / w.max(h)).min(1.0);
    let px = w * h * scale * scale;
    if px > max_pixels.max(1) as f64 {
        scale *= (max_pixels.max(1) as f64 / px).sqrt();
    }
    let side = |v: f64| ((v * scale).floor() as u32).max(1);
    (side(w), side(h))
}

/// A spec brought within the server's limits: the engine does not know
/// them, and a decision must never ask for what the service refuses.
pub fn fit(spec: ArtefactSpec, limits: &ArtefactLimits) -> ArtefactSpec {
    let (side, pixels) = (limits.max_image_side, limits.max_image_pixels);
    match spec {
        ArtefactSpec::Image {
            camera,
            width,
            height,
            format,
            quality,
        } => {
            let (width, height) = fit_size(width, height, side, pixels);
            ArtefactSpec::Image {
                camera,
                width,
                height,
                format,
                quality,
            }
        }
        ArtefactSpec::ViewSet {
            views,
            elevations,
            width,
            height,
            format,
            quality,
            fov,
        } => {
            let (views, width, height) = fit_views(views, &elevations, width, height, limits);
            ArtefactSpec::ViewSet {
                views,
                elevations,
                width,
                height,
                format,
                quality,
                fov,
            }
        }
        ArtefactSpec::ViewSetIndex {
            views,
            elevations,
            width,
            height,
            format,
            quality,
            fov,
        } => {
            let (views, width, height) = fit_views(views, &elevations, width, height, limits);
            ArtefactSpec::ViewSetIndex {
                views,
                elevations,
                width,
                height,
                format,
                quality,
                fov,
            }
        }
        ArtefactSpec::Mesh { depth } => ArtefactSpec::Mesh {
            depth: depth.min(limits.max_mesh_depth),
        },
        ArtefactSpec::Slices { grid } => ArtefactSpec::Slices {
            grid: grid.min(limits.max_volume_grid),
        },
        other => other,
    }
}

/// Views per ring and view size within the view and sheet limits.
fn fit_views(
    views: u32,
    elevations: &[f64],
    width: u32,
    height: u32,
    limits: &ArtefactLimits,
) -> (u32, u32, u32) {
    let rings = elevations.len().max(1) as u32;
    let views = views.clamp(1, (limits.max_views / rings).max(1));
    let count = u64::from(views) * u64::from(rings);
    // Each view gets its share of the sheet's pixels.
    let share = limits.max_sheet_pixels / count.max(1);
    let (w, h) = fit_size(
        width,
        height,
        limits.max_image_side,
        limits.max_image_pixels.min(share),
    );
    (views, w, h)
}

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
        running: &[String],
    ) -> (
        Vec<axum::extract::ws::Message>,
        Vec<(String, tokio::task::JoinHandle<()>)>,
    ) {
        let mut messages = Vec::new();
        let mut jobs = Vec::new();
        let limits = self.artefacts.limits().clone();
        for (role, spec) in specs(decision, camera) {
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

#[cfg(test)]
mod tests {
    use super::*;
    use frep_wire::ImageEncoding;

    #[test]
    fn specs_are_fitted_to_the_limits() {
        let limits = ArtefactLimits {
            max_image_side: 1000,
            max_image_pixels: 200_000,
            max_views: 24,
            max_sheet_pixels: 2_400_000,
            max_mesh_depth: 7,
            max_volume_grid: 64,
            ..ArtefactLimits::default()
        };
        let image = ArtefactSpec::Image {
            camera: CameraView::default(),
            width: 2000,
            height: 1000,
            format: ImageEncoding::Jpeg,
            quality: 80,
        };
        let ArtefactSpec::Image { width, height, .. } = fit(image, &limits) else {
            panic!()
        };
        assert!(width <= 1000 && u64::from(width * height) <= 200_000);
        assert!((f64::from(width) / f64::from(height) - 2.0).abs() < 0.01);
        let set = ArtefactSpec::ViewSet {
            views: 36,
            elevations: vec![0.0, 30.0],
            width: 512,
            height: 512,
            format: ImageEncoding::Jpeg,
            quality: 75,
            fov: None,
        };
        let ArtefactSpec::ViewSet { views, width, .. } = fit(set, &limits) else {
            panic!()
        };
        assert_eq!(views, 12);
        assert!(u64::from(width * width) * 24 <= 2_400_000);
        assert_eq!(
            fit(ArtefactSpec::Mesh { depth: 9 }, &limits),
            ArtefactSpec::Mesh { depth: 7 }
        );
        assert_eq!(
            fit(ArtefactSpec::Slices { grid: 128 }, &limits),
            ArtefactSpec::Slices { grid: 64 }
        );
    }

    #[test]
    fn a_mode_asks_for_its_roles() {
        let d = |mode| Decision {
            mode,
            settings: frep_wire::ModeSettings {
                width: 100,
                height: 100,
                quality: 80,
                moving_scale: 2.0,
                moving_quality: 50,
                format: ImageEncoding::Jpeg,
                views: 12,
                elevations: vec![0.0],
                mesh_depth: 6,
                coarse_depth: 4,
                volume_grid: 64,
            },
            reason: String::new(),
            overridden: false,
            predictions: vec![],
            network: frep_wire::NetworkEstimate {
                rtt_ms: 1.0,
                bandwidth_bps: 1e6,
                samples: 0,
            },
            trigger: "connect".into(),
            seq: 1,
        };
        let roles = |m| -> Vec<&str> {
            specs(&d(m), &CameraView::default())
                .into_iter()
                .map(|(r, _)| r)
                .collect()
        };
        assert_eq!(roles(Mode::Still), ["image"]);
        assert_eq!(roles(Mode::ViewSet), ["viewSetIndex", "viewSet"]);
        assert_eq!(roles(Mode::ServerMesh), ["meshCoarse", "mesh"]);
        assert_eq!(roles(Mode::GpuRaycast), ["shader"]);
        assert_eq!(roles(Mode::Volume), ["slices"]);
        assert!(roles(Mode::WasmMesh).is_empty());
    }
}
