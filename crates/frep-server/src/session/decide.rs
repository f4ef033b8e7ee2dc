//! The session's glue to the adaptive engine ([`frep_adapt::Engine`]).
//!
//! The engine is pure and clockless; this keeps it fed.
//! - It connects once the client has said hello and a model is open, with
//!   the network measured so far. The engine needs the model's statistics.
//! - From then on every event goes to the engine with the session's clock
//!   (ms since the session started). Events are reports, network estimates,
//!   frame rates, displays, overrides, model edits, the server's load,
//!   artefact timings and a periodic tick.
//! - When the engine issues a decision, it is returned to be pushed.
//! - Every evaluation the engine logged is traced with its inputs and
//!   predictions, whether issued or held back by hysteresis.

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

    /// Makes every number of a decision finite: JSON has no infinity or
    /// NaN (serde writes `null`, which a client's `number` cannot read).
    /// An impossible time stays recognisable as the largest double.
    fn finite(mut d: Decision) -> Decision {
        let fix = |v: &mut f64| {
            if !v.is_finite() {
                *v = if v.is_nan() || *v > 0.0 {
                    f64::MAX
                } else {
                    f64::MIN
                };
            }
        };
        for p in &mut d.predictions {
            for v in [
                &mut p.first_display_ms,
                &mut p.orbit_ms,
                &mut p.edit_ms,
                &mut p.bytes,
                &mut p.cost,
            ] {
                fix(v);
            }
        }
        fix(&mut d.network.rtt_ms);
        fix(&mut d.network.bandwidth_bps);
        fix(&mut d.settings.moving_scale);
        d.settings.elevations.iter_mut().for_each(fix);
        d
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
        decision.map(Decider::finite)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use frep_wire::Screen;

    #[test]
    fn decisions_carry_only_finite_numbers() {
        let mut d = Decider::new(&SessionConfig::default()).unwrap();
        let report = ClientReport {
            user_agent: "t".into(),
            webgl2: false,
            renderer: None,
            max_texture_size: 0,
            max_3d_texture_size: 0,
            webgpu: false,
            gpu_bench_ms: None,
            wasm_bench_meps: None,
            cpu_bench_ms: None,
            screen: Screen {
                width: 800,
                height: 600,
                pixel_ratio: 1.0,
            },
            mobile: false,
            device_memory_gb: None,
            cores: None,
        };
        assert!(d.report(report, 0).is_none(), "no model yet");
        let stats = ModelStats {
            tape_len: 40,
            nodes: 50,
            closed_form: false,
            attributes: 0,
            primitives: None,
            shader_statements: 40,
            measured: Default::default(),
        };
        let net = NetworkEstimate {
            rtt_ms: 20.0,
            bandwidth_bps: 1e7,
            samples: 3,
        };
        let decision = d.model(stats, net, 0).expect("connects");
        let json = serde_json::to_string(&decision).unwrap();
        // serde reads no `null` as an f64: a decision with an infinite
        // prediction would fail here.
        let back: Decision = serde_json::from_str(&json).expect("a client can read it");
        assert_eq!(back.predictions.len(), 6);
        assert!(d.connected());
    }
}
