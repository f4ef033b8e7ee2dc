//! The session's glue to the adaptive engine ([`frep_adapt::Engine`]).
//!
//! The engine is pure and clockless; this keeps it fed. It connects once the
//! client has said hello and a model is open (the engine needs the model's
//! statistics), with the network measured so far. From then on every event
//! goes to the engine with the session's clock (ms since the session
//! started): reports, network estimates, frame rates, displays, overrides,
//! model edits, the server's load, artefact timings and a periodic tick.
//! When the engine issues a decision, it is returned to be pushed; every
//! evaluation the engine logged (issued or held back by hysteresis) is
//! traced with its inputs and predictions.

use frep_adapt::{Engine, LogEntry, ModelStats, ServerLoad, ServerSample};
use frep_wire::{ClientReport, Decision, Mode, NetworkEstimate};

use super::config::SessionConfig;

/// One session's engine and what it waits for.
#[derive(Debug)]
pub struct Decider {
    engine: Engine,
    report: Option<ClientReport>,
    net: Option<NetworkEstimate>,
    load: Option<ServerLoad>,
    connected: bool,
    last_logged: Option<LogEntry>,
}

impl Decider {
    /// A decider with the session's engine windows.
    pub fn new(config: &SessionConfig) -> Result<Decider, String> {
        let engine = Engine::new(config.engine()).map_err(|e| e.to_string())?;
        Ok(Decider {
            engine,
            report: None,
            net: None,
            load: None,
            connected: false,
            last_logged: None,
        })
    }

    /// The decision in force.
    pub fn current(&self) -> Option<&Decision> {
        self.engine.current()
    }

    /// Whether the engine has connected (a decision exists).
    pub fn connected(&self) -> bool {
        self.connected
    }

    /// The client's hello or a new report.
    pub fn report(&mut self, report: ClientReport, now: u64) -> Option<Decision> {
        if self.connected {
            let d = self.engine.report(report, now);
            return self.trace(d);
        }
        self.report = Some(report);
        None
    }

    /// The model opened or edited: connects when the client said hello,
    /// else tells the engine the model changed.
    pub fn model(&mut self, stats: ModelStats, net: NetworkEstimate, now: u64) -> Option<Decision> {
        if self.connected {
            let d = self.engine.model_changed(stats, now);
            return self.trace(d);
        }
        let report = self.report.take()?;
        self.connected = true;
        self.net = Some(net.clone());
        let d = self.engine.connect(report, net, stats, now);
        self.trace(Some(d))
    }

    /// A new network estimate (only passed on when it differs).
    pub fn network(&mut self, net: NetworkEstimate, now: u64) -> Option<Decision> {
        if !self.connected || self.net.as_ref() == Some(&net) {
            return None;
        }
        self.net = Some(net.clone());
        let d = self.engine.measurement(net, now);
        self.trace(d)
    }

    /// The client's achieved frame rate.
    pub fn frame_rate(&mut self, mode: Mode, fps: f64, now: u64) -> Option<Decision> {
        let d = self.engine.frame_rate(mode, fps, now);
        self.trace(d)
    }

    /// A mode's first display time.
    pub fn displayed(&mut self, mode: Mode, ms: f64, bytes: u64, now: u64) -> Option<Decision> {
        let d = self.engine.displayed(mode, ms, bytes, now);
        self.trace(d)
    }

    /// The user's override (remembered before the engine connects).
    pub fn set_override(&mut self, mode: Option<Mode>, now: u64) -> Option<Decision> {
        let d = self.engine.set_override(mode, now);
        self.trace(d)
    }

    /// The user is interacting.
    pub fn activity(&mut self, now: u64) {
        self.engine.activity(now);
    }

    /// A measured artefact of the open model.
    pub fn measured(&mut self, sample: ServerSample, now: u64) -> Option<Decision> {
        let d = self.engine.server_measured(sample, now);
        self.trace(d)
    }

    /// The periodic re-evaluation, with the server's load (passed on when
    /// it changed).
    pub fn tick(&mut self, load: ServerLoad, now: u64) -> Option<Decision> {
        if !self.connected {
            return None;
        }
        if self.load != Some(load) {
            self.load = Some(load);
            if let Some(d) = self.engine.load(load, now) {
                return self.trace(Some(d));
            }
        }
        let d = self.engine.tick(now);
        self.trace(d)
    }

    /// Traces the engine's newest log entry (each call into the engine
    /// logs at most one) and passes the decision on.
    fn trace(&mut self, decision: Option<Decision>) -> Option<Decision> {
        let last = self.engine.log().last();
        if last.is_some() && last != self.last_logged.as_ref() {
            if let Some(entry) = last {
                let inputs = serde_json::to_string(&entry.inputs).unwrap_or_default();
                let predictions = serde_json::to_string(&entry.predictions).unwrap_or_default();
                tracing::info!(
                    target: "frep::decision",
                    at_ms = entry.at_ms,
                    trigger = entry.trigger.as_str(),
                    best = ?entry.best,
                    chosen = ?entry.chosen,
                    issued = ?entry.issued,
                    reason = %entry.reason,
                    inputs = %inputs,
                    predictions = %predictions,
                    "evaluation"
                );
            }
            self.last_logged = last.cloned();
        }
        decision
    }
}
