//! The studio's WebSocket session (`GET /api/session`).
//!
//! Text messages are JSON: [`ClientMessage`] up, [`ServerMessage`] down.
//! Binary messages carry payloads (probe bytes, streamed frames): a 4-byte
//! little-endian length `n`, then `n` bytes of a JSON [`BinaryHeader`], then
//! the payload.

use serde::{Deserialize, Serialize};
use ts_rs::TS;

use crate::{ArtefactRef, CameraView, ClientReport, Decision, ImageEncoding, Mode, SectionPlane};

/// What the client sends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "type", rename_all = "camelCase")]
pub enum ClientMessage {
    /// First message: what the client is (sent again when it changes).
    #[serde(rename_all = "camelCase")]
    Hello {
        /// The report.
        report: ClientReport,
    },
    /// A changed report (benchmarks finished, screen resized).
    #[serde(rename_all = "camelCase")]
    Report {
        /// The report.
        report: ClientReport,
    },
    /// The model the studio shows now (and its parameter values).
    #[serde(rename_all = "camelCase")]
    Open {
        /// Model id, or `None` for an unsaved source.
        model_id: Option<String>,
        /// Version (`None`: latest).
        version: Option<u32>,
        /// The source when unsaved or edited.
        source: Option<String>,
        /// Parameter values.
        params: Vec<f64>,
    },
    /// Answer to a [`ServerMessage::Ping`].
    #[serde(rename_all = "camelCase")]
    Pong {
        /// The ping's id.
        id: u32,
    },
    /// The client received a probe payload completely.
    #[serde(rename_all = "camelCase")]
    ProbeDone {
        /// The probe's id.
        id: u32,
        /// Bytes received.
        #[ts(type = "number")]
        bytes: u64,
        /// ms from the probe's header to its last byte, as the client saw it.
        client_ms: f64,
    },
    /// The camera moved (mode 1 streams frames for the latest one).
    #[serde(rename_all = "camelCase")]
    Camera {
        /// The camera.
        camera: CameraView,
        /// Whether the user is still dragging (lower resolution frames).
        moving: bool,
        /// Viewport in device pixels.
        width: u32,
        /// Viewport in device pixels.
        height: u32,
        /// The section plane the frames cut the model by (absent: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[ts(optional)]
        section: Option<SectionPlane>,
    },
    /// A streamed frame was displayed.
    #[serde(rename_all = "camelCase")]
    FrameAck {
        /// The frame's sequence number.
        seq: u32,
        /// ms from the camera message that asked for it to its display.
        latency_ms: f64,
    },
    /// An artefact or mode reached the screen: how long it took.
    #[serde(rename_all = "camelCase")]
    Displayed {
        /// The mode shown.
        mode: Mode,
        /// ms from the request to the first displayed frame.
        ms: f64,
        /// Bytes transferred for it.
        #[ts(type = "number")]
        bytes: u64,
    },
    /// The frame rate achieved in the current mode while interacting.
    #[serde(rename_all = "camelCase")]
    FrameRate {
        /// The mode.
        mode: Mode,
        /// Frames per second.
        fps: f64,
        /// ms per frame (median of the window).
        frame_ms: f64,
    },
    /// The user's choice: a mode, or `None` for automatic.
    #[serde(rename_all = "camelCase")]
    Override {
        /// The mode, or automatic.
        mode: Option<Mode>,
    },
    /// Cancel work for an artefact the client no longer waits for.
    #[serde(rename_all = "camelCase")]
    Cancel {
        /// The artefact key.
        key: String,
    },
}

/// What the server sends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "type", rename_all = "camelCase")]
pub enum ServerMessage {
    /// First message.
    #[serde(rename_all = "camelCase")]
    Welcome {
        /// The session's id.
        session_id: String,
        /// Server version.
        server: String,
    },
    /// A round-trip measurement; answer with `pong`.
    #[serde(rename_all = "camelCase")]
    Ping {
        /// Echoed in the pong.
        id: u32,
    },
    /// A decision (the mode to use and why).
    #[serde(rename_all = "camelCase")]
    Decision {
        /// The decision.
        decision: Decision,
    },
    /// An artefact of the current mode is ready or being made.
    #[serde(rename_all = "camelCase")]
    Artefact {
        /// What it is for (`image`, `viewSet`, `mesh`, `meshCoarse`, …).
        role: String,
        /// Where it is.
        artefact: ArtefactRef,
    },
    /// Progress of a job the client waits for.
    #[serde(rename_all = "camelCase")]
    Progress {
        /// The artefact key.
        key: String,
        /// 0 to 1.
        fraction: f64,
    },
    /// The opened model changed on the server (another editor saved).
    #[serde(rename_all = "camelCase")]
    ModelChanged {
        /// Model id.
        model_id: String,
        /// The new latest version.
        version: u32,
        /// Who saved it.
        author: String,
    },
    /// A problem with the session's last request.
    #[serde(rename_all = "camelCase")]
    Error {
        /// What went wrong.
        message: String,
    },
}

/// The JSON header of a binary message.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "type", rename_all = "camelCase")]
pub enum BinaryHeader {
    /// Bandwidth probe bytes (random, incompressible).
    #[serde(rename_all = "camelCase")]
    Probe {
        /// Probe id.
        id: u32,
        /// Payload bytes.
        #[ts(type = "number")]
        bytes: u64,
    },
    /// A streamed frame (mode 1).
    #[serde(rename_all = "camelCase")]
    Frame {
        /// Sequence number.
        seq: u32,
        /// The camera it shows.
        camera: CameraView,
        /// Pixels.
        width: u32,
        /// Pixels.
        height: u32,
        /// Encoding of the payload.
        format: ImageEncoding,
        /// Server ms to render and encode.
        server_ms: f64,
        /// Whether it was a moving (reduced) frame.
        moving: bool,
    },
}
