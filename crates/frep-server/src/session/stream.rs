//! Mode 1 streaming: frames of the latest camera while the user orbits.
//!
//! - The session keeps one slot, a `watch` channel holding what to show now,
//!   each change numbered. That is the model, parameters, camera, whether
//!   moving, viewport, and the decision's settings.
//! - One render loop per session takes the newest value only. So cameras
//!   that arrived during a render are skipped, never queued.
//! - A frame is in flight from the start of its render until the client's
//!   `frameAck` (or `frame_ack_timeout_ms`). At most `frames_in_flight` are,
//!   so a slow client gets fewer frames, never a backlog.
//! - Renders go through the server-wide frame pool ([`Hub::frames`]). So all
//!   sessions together use a bounded number of workers.
//! - Streamed frames skip the artefact cache, since each camera is seen
//!   once.
//!
//! Size: the viewport, scaled down to the decision's pixel budget
//! (`width × height`); while moving, each side is divided by `movingScale`
//! and the moving quality is used.

use std::sync::Arc;
use std::time::Instant;

use frep_artefact::compute::image;
use frep_artefact::{ArtefactLimits, Cancel, Compiled, ImagePool};
use frep_wire::{BinaryHeader, CameraView, ModeSettings, SectionPlane};
use tokio::sync::{mpsc, watch, OwnedSemaphorePermit, Semaphore};

use super::hub::Hub;
use super::wire;
use super::Event;

/// What the client should see now.
#[derive(Clone, Debug)]
pub struct Ask {
    /// Changes with every new ask.
    pub gen: u64,
    /// The model.
    pub model: Arc<Compiled>,
    /// Its parameter values.
    pub params: Arc<Vec<f64>>,
    /// The camera.
    pub camera: CameraView,
    /// The section plane cutting the model open, if any.
    pub section: Option<SectionPlane>,
    /// Whether the user is orbiting.
    pub moving: bool,
    /// Viewport in device pixels (0: the decision's size).
    pub viewport: (u32, u32),
    /// The decision's settings.
    pub settings: ModeSettings,
    /// When the camera message arrived.
    pub asked: Instant,
}

/// A frame sent and not yet acknowledged.
#[derive(Debug)]
pub struct InFlight {
    /// Holds one of the session's in-flight places.
    pub permit: OwnedSemaphorePermit,
    /// When it was sent.
    pub sent: Instant,
    /// Its encoded size.
    pub bytes: u64,
}

/// A rendered frame for the session loop to send.
#[derive(Debug)]
pub struct Frame {
    /// Its sequence number.
    pub seq: u32,
    /// The binary message.
    pub message: axum::extract::ws::Message,
    /// Its in-flight place.
    pub permit: OwnedSemaphorePermit,
    /// Encoded bytes.
    pub bytes: u64,
    /// Pixels and quality (for the engine's image measurement).
    pub pixels: u64,
    /// Encoder quality.
    pub quality: u8,
    /// Render and encode ms.
    pub server_ms: f64,
}

/// Frame size and quality for an ask (module docs).
pub fn frame_size(ask: &Ask, limits: &ArtefactLimits, min_side: u32) -> (u32, u32, u8) {
    let s = &ask.settings;
    let (vw, vh) = match ask.viewport {
        (w, h) if w > 0 && h > 0 => (f64::from(w), f64::from(h)),
        _ => (f64::from(s.width.max(1)), f64::from(s.height.max(1))),
    };
    let budget = f64::from(s.width) * f64::from(s.height);
    let mut scale = if budget > 0.0 {
        (budget / (vw * vh)).sqrt().min(1.0)
    } else {
        1.0
    };
    let quality = if ask.moving {
        if s.moving_scale.is_finite() && s.moving_scale > 1.0 {
            scale /= s.moving_scale;
        }
        s.moving_quality
    } else {
        s.quality
    };
    let max_side = f64::from(limits.max_image_side.max(1));
    scale = scale.min(max_side / vw.max(vh));
    let pixels = vw * vh * scale * scale;
    let max_pixels = limits.max_image_pixels.max(1) as f64;
    if pixels > max_pixels {
        scale *= (max_pixels / pixels).sqrt();
    }
    let side = |v: f64| ((v * scale).round() as u32).max(min_side.max(1));
    (side(vw), side(vh), quality.clamp(1, 100))
}

/// The session's render loop (module docs). Ends when the slot's sender
/// or the event channel closes.
pub async fn run(
    mut slot: watch::Receiver<Option<Ask>>,
    in_flight: Arc<Semaphore>,
    hub: Arc<Hub>,
    limits: ArtefactLimits,
    events: mpsc::Sender<Event>,
    cancel: Cancel,
) {
    let mut shown = 0u64;
    let mut seq = 0u32;
    loop {
        // Wait for an ask not yet rendered.
        while slot
            .borrow_and_update()
            .as_ref()
            .is_none_or(|a| a.gen == shown)
        {
            if slot.changed().await.is_err() {
                return;
            }
        }
        let Ok(permit) = in_flight.clone().acquire_owned().await else {
            return;
        };
        // The newest ask, which may be newer than the one that woke us.
        let Some(ask) = slot.borrow_and_update().clone() else {
            continue;
        };
        if ask.gen == shown {
            continue;
        }
        shown = ask.gen;
        seq = seq.wrapping_add(1);
        let event = match render(&ask, seq, &hub, &limits, &cancel, hub.config.frame_min_side).await
        {
            Ok((message, bytes, pixels, quality, server_ms)) => Event::Frame(Frame {
                seq,
                message,
                permit,
                bytes,
                pixels,
                quality,
                server_ms,
            }),
            Err(e) => {
                if cancel.is_cancelled() {
                    return;
                }
                Event::Error(format!("frame {seq}: {e}"))
            }
        };
        if events.send(event).await.is_err() {
            return;
        }
    }
}

type Rendered = (axum::extract::ws::Message, u64, u64, u8, f64);

/// Renders and encodes one frame on the frame pool.
async fn render(
    ask: &Ask,
    seq: u32,
    hub: &Hub,
    limits: &ArtefactLimits,
    cancel: &Cancel,
    min_side: u32,
) -> Result<Rendered, String> {
    let (width, height, quality) = frame_size(ask, limits, min_side);
    let format = ask.settings.format;
    let worker = hub
        .frames
        .clone()
        .acquire_owned()
        .await
        .map_err(|_| "the frame pool is closed".to_string())?;
    let (ask2, cancel2, pool) = (ask.clone(), cancel.clone(), hub.images.clone());
    let start = Instant::now();
    let bytes = tokio::task::spawn_blocking(move || {
        let _worker = worker;
        frame_bytes(&ask2, (width, height, quality), &cancel2, &pool)
    })
    .await
    .map_err(|e| format!("render task failed: {e}"))?
    .map_err(|e| e.to_string())?;
    let server_ms = start.elapsed().as_secs_f64() * 1e3;
    let header = BinaryHeader::Frame {
        seq,
        camera: ask.camera.clone(),
        width,
        height,
        format,
        server_ms,
        moving: ask.moving,
    };
    let message = wire::binary(&header, &bytes);
    Ok((
        message,
        bytes.len() as u64,
        u64::from(width) * u64::from(height),
        quality,
        server_ms,
    ))
}

/// The encoded picture of an ask at this size and quality: its model,
/// parameters, camera and section plane. The image's bytes come from
/// `pool` and go back to it.
fn frame_bytes(
    ask: &Ask,
    (width, height, quality): (u32, u32, u8),
    cancel: &Cancel,
    pool: &ImagePool,
) -> Result<Vec<u8>, frep_artefact::ArtefactError> {
    let inputs = ask.model.inputs(&ask.params);
    image::image(
        &ask.model,
        inputs,
        &ask.camera,
        width,
        height,
        ask.settings.format,
        quality,
        ask.section.as_ref(),
        cancel,
        pool,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use frep_wire::ImageEncoding;

    fn ask(moving: bool, viewport: (u32, u32)) -> Ask {
        let model = frep_artefact::compile(
            "my_model(x[3], a[1]) { my_model = 1 - x[1]^2 - x[2]^2 - x[3]^2; }",
            None,
            &Default::default(),
        )
        .unwrap();
        Ask {
            gen: 1,
            model,
            params: Arc::new(Vec::new()),
            camera: CameraView::default(),
            section: None,
            moving,
            viewport,
            settings: ModeSettings {
                width: 400,
                height: 300,
                quality: 80,
                moving_scale: 2.0,
                moving_quality: 50,
                format: ImageEncoding::Jpeg,
                views: 0,
                elevations: vec![],
                mesh_depth: 0,
                coarse_depth: 0,
                volume_grid: 0,
            },
            asked: Instant::now(),
        }
    }

    /// A frame of an ask with a section plane shows the cut: a plane that
    /// keeps nothing leaves the background alone; one through the centre
    /// changes the picture.
    #[test]
    fn frames_honour_the_section_plane() {
        let cancel = Cancel::new();
        let frame = |section| {
            let a = Ask {
                section,
                ..ask(true, (64, 48))
            };
            frame_bytes(&a, (64, 48, 90), &cancel, &ImagePool::default()).unwrap()
        };
        let whole = frame(None);
        let cut = frame(Some(SectionPlane {
            normal: [-0.5, -0.866, 0.3],
            offset: 0.0,
        }));
        let none = frame(Some(SectionPlane {
            normal: [0.0, 0.0, 1.0],
            offset: -10.0,
        }));
        let empty = Ask {
            model: frep_artefact::compile(
                "my_model(x[3], a[1]) { my_model = -1 - x[1]^2; }",
                None,
                &Default::default(),
            )
            .unwrap(),
            ..ask(true, (64, 48))
        };
        let background = frame_bytes(&empty, (64, 48, 90), &cancel, &ImagePool::default()).unwrap();
        assert_ne!(whole, cut);
        assert_ne!(whole, none);
        assert_eq!(none, background);
    }

    #[test]
    fn frames_fit_the_budget_and_shrink_while_moving() {
        let l = ArtefactLimits::default();
        assert_eq!(frame_size(&ask(false, (0, 0)), &l, 16), (400, 300, 80));
        let (w, h, q) = frame_size(&ask(false, (800, 600)), &l, 16);
        assert_eq!(
            (w, h, q),
            (400, 300, 80),
            "scaled to the budget, aspect kept"
        );
        assert_eq!(frame_size(&ask(true, (800, 600)), &l, 16), (200, 150, 50));
        assert_eq!(frame_size(&ask(false, (200, 100)), &l, 16), (200, 100, 80));
        let small = ArtefactLimits {
            max_image_side: 100,
            ..l
        };
        assert_eq!(
            frame_size(&ask(false, (200, 100)), &small, 16),
            (100, 50, 80)
        );
    }
}
