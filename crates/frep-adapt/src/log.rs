//! The decision log's vocabulary:
//! - what triggered an evaluation;
//! - a summary of its inputs;
//! - one log entry: its predictions, the best and the chosen mode, and
//!   whether a decision was issued or hysteresis held it.

use frep_wire::{Mode, ModePrediction, NetworkEstimate};
use serde::Serialize;

use crate::client::ClientCaps;
use crate::stats::ServerLoad;

/// What caused an evaluation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "camelCase")]
pub enum Trigger {
    /// The session started.
    Connect,
    /// A new network estimate or a server measurement of an artefact.
    Measurement,
    /// A new client report.
    Report,
    /// The model changed.
    Edit,
    /// The client's frames stayed under the target rate.
    SlowFrames,
    /// A frame rate report (fine or not yet long enough to act on).
    FrameRate,
    /// The client reported a displayed time.
    Displayed,
    /// The user's override.
    Override,
    /// The server's load changed.
    Load,
    /// A periodic re-evaluation.
    Periodic,
}

impl Trigger {
    /// The wire name (`Decision::trigger`).
    pub fn as_str(self) -> &'static str {
        match self {
            Trigger::Connect => "connect",
            Trigger::Measurement => "measurement",
            Trigger::Report => "report",
            Trigger::Edit => "edit",
            Trigger::SlowFrames => "slowFrames",
            Trigger::FrameRate => "frameRate",
            Trigger::Displayed => "displayed",
            Trigger::Override => "override",
            Trigger::Load => "load",
            Trigger::Periodic => "periodic",
        }
    }
}

/// The inputs of an evaluation, in short.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct InputSummary {
    /// The network.
    pub network: NetworkEstimate,
    /// The client as the engine sees it.
    pub caps: ClientCaps,
    /// Tape operations.
    pub tape_len: u32,
    /// Shader statements.
    pub statements: u32,
    /// Primitives (estimated or counted).
    pub primitives: u32,
    /// Closed form on the server.
    pub closed_form: bool,
    /// The server's load.
    pub load: ServerLoad,
    /// The user's override.
    pub override_mode: Option<Mode>,
}

/// One evaluation in the decision log.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct LogEntry {
    /// When (the caller's ms).
    pub at_ms: u64,
    /// What caused it.
    pub trigger: Trigger,
    /// The inputs.
    pub inputs: InputSummary,
    /// Every mode's prediction and cost.
    pub predictions: Vec<ModePrediction>,
    /// The cheapest feasible mode.
    pub best: Mode,
    /// The mode in use after it.
    pub chosen: Mode,
    /// The decision's sequence number when one was issued; `None` when
    /// hysteresis held a change back.
    pub issued: Option<u32>,
    /// The reason (of the decision, or of holding back).
    pub reason: String,
}
