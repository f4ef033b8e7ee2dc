//! One session's engine: its state, its events, hysteresis and the
//! decision log.
//!
//! Every event updates what the engine knows and re-evaluates all modes
//! ([`crate::choose::evaluate`]). Whether the result becomes a new
//! [`Decision`] is governed by hysteresis, so that the mode does not flap:
//!
//! * **immediately**:
//!   - at connection, and on an override;
//!   - when the current mode became impossible: a report without WebGL2, a
//!     model too heavy for the shader;
//!   - when the client's frames have stayed under the target frame rate for
//!     `downgrade_after_ms`. The slow mode's orbit correction is learnt
//!     first, so the predictions already show it;
//!   - after a model edit that makes the current mode miss the target frame
//!     rate;
//! * **after `downgrade_after_ms` (~2 s)** of a better mode being preferred,
//!   by at least `switch_margin` of the cost, while the current mode fails
//!   its targets. Failing means orbit under the target frame rate (predicted
//!   or reported), or edits slower than the weights' `patience_ms`;
//! * **after `upgrade_after_ms` (~10 s)** of a better mode being preferred,
//!   the whole time, while the current mode is fine. Only when the user has
//!   been idle for `idle_before_upgrade_ms`.
//!
//! A preference that lapses for one evaluation restarts its timer.
//!
//! Settings within the same mode change when:
//! - their inputs changed discretely: report, model edit, slow frames;
//! - their inputs moved out of a band: the network by more than
//!   `network_band` ×, the load factor by `load_band` ×;
//! - new settings beat the ones in force by `switch_margin`, after learning
//!   from the client's reports or from the server's measurements.
//!
//! An override is obeyed whenever the client can show the mode. A hold (a
//! better mode waiting) is logged when it starts; every decision is logged.
//! Corrections and the override survive a reconnection.

use std::collections::VecDeque;

use frep_wire::{ClientReport, Decision, Mode, NetworkEstimate};

use crate::choose::{self, Scored};
use crate::client::ClientCaps;
use crate::config::{ConfigError, EngineConfig};
use crate::correction::{mode_index, Corrections};
use crate::log::{InputSummary, LogEntry, Trigger};
use crate::predict::Inputs;
use crate::reason;
use crate::stats::{ModelStats, ServerLoad, ServerSample};

mod hysteresis;

/// A preferred mode waiting for its hysteresis timer.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Pending {
    mode: Mode,
    since_ms: u64,
}

/// What an evaluation decided to do.
struct Outcome {
    target: usize,
    issue: bool,
    note: Option<String>,
}

/// The adaptive engine of one session.
#[derive(Clone, Debug)]
pub struct Engine {
    config: EngineConfig,
    caps: Option<ClientCaps>,
    net: Option<NetworkEstimate>,
    stats: Option<ModelStats>,
    load: ServerLoad,
    connected: bool,
    current: Option<Decision>,
    /// Uncorrected first-display and orbit ms of each mode at the last
    /// evaluation, for learning from reports.
    raw: [(f64, f64); 6],
    /// The same for the decision in force, with its own settings (the
    /// client reports on those).
    current_raw: (f64, f64),
    /// What the current settings rest on.
    basis_net: Option<NetworkEstimate>,
    basis_load: f64,
    override_mode: Option<Mode>,
    pending: Option<Pending>,
    slow_since: Option<u64>,
    last_activity_ms: Option<u64>,
    /// The last hold logged: the preferred mode and since when.
    last_held: Option<(Mode, Option<u64>)>,
    /// The report being evaluated replaced a guessed benchmark.
    guess_replaced: bool,
    corrections: Corrections,
    log: VecDeque<LogEntry>,
    seq: u32,
}

impl Engine {
    /// An engine with a checked configuration.
    pub fn new(config: EngineConfig) -> Result<Engine, ConfigError> {
        config.validate()?;
        Ok(Engine {
            corrections: Corrections::new(config.correction),
            config,
            caps: None,
            net: None,
            stats: None,
            load: ServerLoad::default(),
            connected: false,
            current: None,
            raw: [(0.0, 0.0); 6],
            current_raw: (0.0, 0.0),
            basis_net: None,
            basis_load: 1.0,
            override_mode: None,
            pending: None,
            slow_since: None,
            last_activity_ms: None,
            guess_replaced: false,
            last_held: None,
            log: VecDeque::new(),
            seq: 0,
        })
    }

    /// Starts (or restarts) the session: the client's report, the network
    /// measured so far and the opened model. Always decides.
    pub fn connect(
        &mut self,
        report: ClientReport,
        net: NetworkEstimate,
        stats: ModelStats,
        now_ms: u64,
    ) -> Decision {
        let caps = self.caps_from(&report);
        let inputs = Inputs {
            caps: &caps,
            net: &net,
            stats: &stats,
            load: self.load,
        };
        let c = &self.config;
        let scored = choose::evaluate(&inputs, &c.limits, &c.weights, &self.corrections);
        self.caps = Some(caps);
        self.net = Some(net);
        self.stats = Some(stats);
        self.connected = true;
        self.current = None;
        self.pending = None;
        self.slow_since = None;
        let (outcome, best) = self.plan(Trigger::Connect, &scored, now_ms);
        self.commit(Trigger::Connect, now_ms, &scored, best, &outcome)
    }

    /// A new network estimate (pings, probes, payload throughput).
    pub fn measurement(&mut self, net: NetworkEstimate, now_ms: u64) -> Option<Decision> {
        self.net = Some(net);
        self.evaluate(Trigger::Measurement, now_ms)
    }

    /// A changed client report (benchmarks done, screen resized).
    /// A report that brings a benchmark the engine had only guessed
    /// re-decides at once: the first decision rested on the guess.
    pub fn report(&mut self, report: ClientReport, now_ms: u64) -> Option<Decision> {
        let before = self.caps.as_ref().map_or(0, ClientCaps::measured_count);
        self.set_report(report);
        let after = self.caps.as_ref().map_or(0, ClientCaps::measured_count);
        self.guess_replaced = after > before;
        let d = self.evaluate(Trigger::Report, now_ms);
        self.guess_replaced = false;
        d
    }

    /// The frame rate the client achieved in `mode` while interacting.
    /// Frames under the target rate for `downgrade_after_ms` downgrade.
    pub fn frame_rate(&mut self, mode: Mode, fps: f64, now_ms: u64) -> Option<Decision> {
        if !(fps.is_finite() && fps >= 0.0) {
            return None;
        }
        self.last_activity_ms = Some(now_ms);
        if fps > 0.0 && fps < self.config.vsync_fps {
            let raw = self.raw_of(mode).1;
            self.corrections.observe_orbit(mode, 1000.0 / fps, raw);
        }
        let current = self.current.as_ref().map(|d| d.mode);
        let mut trigger = Trigger::FrameRate;
        if current == Some(mode) {
            if fps < self.config.weights.min_orbit_fps {
                let since = *self.slow_since.get_or_insert(now_ms);
                if now_ms.saturating_sub(since) >= self.config.downgrade_after_ms {
                    trigger = Trigger::SlowFrames;
                }
            } else {
                self.slow_since = None;
            }
        }
        self.evaluate(trigger, now_ms)
    }

    /// The client showed `mode`'s first frame `ms` after asking, having
    /// transferred `bytes`: the first-display prediction learns from it.
    pub fn displayed(&mut self, mode: Mode, ms: f64, bytes: u64, now_ms: u64) -> Option<Decision> {
        let _ = bytes; // The time already includes the transfer.
        let raw = self.raw_of(mode).0;
        self.corrections.observe_first_display(mode, ms, raw);
        // Its code is loaded now: later predictions do not count it.
        if let Some(caps) = self.caps.as_mut() {
            caps.code.displayed(mode);
        }
        self.evaluate(Trigger::Displayed, now_ms)
    }

    /// The model changed (an edit, another version opened). Measured
    /// artefact costs of the old model should not be carried over.
    pub fn model_changed(&mut self, stats: ModelStats, now_ms: u64) -> Option<Decision> {
        self.stats = Some(stats);
        self.evaluate(Trigger::Edit, now_ms)
    }

    /// The server measured one of this model's artefacts.
    pub fn server_measured(&mut self, sample: ServerSample, now_ms: u64) -> Option<Decision> {
        if let Some(s) = self.stats.as_mut() {
            s.record(sample);
        }
        self.evaluate(Trigger::Measurement, now_ms)
    }

    /// The user's override: a mode, or `None` for automatic. Always decides
    /// (once connected).
    pub fn set_override(&mut self, mode: Option<Mode>, now_ms: u64) -> Option<Decision> {
        self.override_mode = mode;
        self.pending = None;
        self.evaluate(Trigger::Override, now_ms)
    }

    /// The server's load changed.
    pub fn load(&mut self, load: ServerLoad, now_ms: u64) -> Option<Decision> {
        self.load = load;
        self.evaluate(Trigger::Load, now_ms)
    }

    /// The user is interacting (camera, drags): upgrades wait for idleness.
    pub fn activity(&mut self, now_ms: u64) {
        self.last_activity_ms = Some(now_ms);
    }

    /// Periodic re-evaluation (hysteresis timers advance only on events;
    /// call this every second or so).
    pub fn tick(&mut self, now_ms: u64) -> Option<Decision> {
        self.evaluate(Trigger::Periodic, now_ms)
    }

    /// The decision in force.
    pub fn current(&self) -> Option<&Decision> {
        self.current.as_ref()
    }

    /// The user's override.
    pub fn override_mode(&self) -> Option<Mode> {
        self.override_mode
    }

    /// The decision log, oldest first.
    pub fn log(&self) -> impl Iterator<Item = &LogEntry> {
        self.log.iter()
    }

    /// The learnt corrections.
    pub fn corrections(&self) -> &Corrections {
        &self.corrections
    }

    /// The model's stats (with the server's measurements).
    pub fn stats(&self) -> Option<&ModelStats> {
        self.stats.as_ref()
    }

    /// The configuration.
    pub fn config(&self) -> &EngineConfig {
        &self.config
    }

    /// Every mode's prediction for the current inputs, without deciding
    /// (`None` before `connect`).
    pub fn predictions(&self) -> Option<Vec<Scored>> {
        let (caps, net, stats) = (
            self.caps.as_ref()?,
            self.net.as_ref()?,
            self.stats.as_ref()?,
        );
        let inputs = Inputs {
            caps,
            net,
            stats,
            load: self.load,
        };
        let c = &self.config;
        Some(choose::evaluate(
            &inputs,
            &c.limits,
            &c.weights,
            &self.corrections,
        ))
    }

    /// Uncorrected (first display, orbit) ms of a mode: of the decision in
    /// force for its mode, else of the last evaluation.
    fn raw_of(&self, mode: Mode) -> (f64, f64) {
        match &self.current {
            Some(d) if d.mode == mode => self.current_raw,
            _ => self.raw[mode_index(mode)],
        }
    }

    fn set_report(&mut self, report: ClientReport) {
        let caps = self.caps_from(&report);
        self.caps = Some(caps);
    }

    /// Caps from a report, keeping what code the page is known to hold.
    fn caps_from(&self, report: &ClientReport) -> ClientCaps {
        let mut caps = ClientCaps::from_report(report, &self.config.limits);
        if let Some(old) = &self.caps {
            caps.code.merge(&old.code);
        }
        caps
    }

    /// Re-evaluates every mode and decides whether to issue a decision.
    fn evaluate(&mut self, trigger: Trigger, now_ms: u64) -> Option<Decision> {
        if !self.connected {
            return None;
        }
        let scored = self.predictions()?;
        let (mut outcome, best) = self.plan(trigger, &scored, now_ms);
        if outcome.issue {
            Some(self.commit(trigger, now_ms, &scored, best, &outcome))
        } else if self.settings_changed(trigger, &scored[outcome.target]) {
            outcome.note = outcome.note.or_else(|| Some(self.settings_note(trigger)));
            Some(self.commit(trigger, now_ms, &scored, best, &outcome))
        } else {
            self.record(trigger, now_ms, &scored, best, &outcome, None);
            None
        }
    }

    /// Issues, logs and returns a decision for the planned target.
    fn commit(
        &mut self,
        trigger: Trigger,
        now_ms: u64,
        scored: &[Scored],
        best: usize,
        outcome: &Outcome,
    ) -> Decision {
        let before = self.current.as_ref().map(|d| d.mode);
        let d = self.issue(trigger, scored, outcome);
        let p = &scored[outcome.target].prediction;
        self.current_raw = (p.raw_first_display_ms, p.raw_orbit_ms);
        self.record(trigger, now_ms, scored, best, outcome, Some(&d));
        // New settings or a new mode need new frame-rate measurements; a
        // preferred mode keeps waiting unless the mode changed.
        self.slow_since = None;
        if before != Some(d.mode) {
            self.pending = None;
        }
        d
    }

    /// Builds, keeps and returns a decision.
    fn issue(&mut self, trigger: Trigger, scored: &[Scored], outcome: &Outcome) -> Decision {
        self.seq = self.seq.saturating_add(1);
        let chosen = &scored[outcome.target];
        let reason = self.reason(outcome, scored);
        let overridden =
            self.override_mode == Some(chosen.prediction.mode) && chosen.prediction.feasible();
        let net = self.net.clone().unwrap_or(NetworkEstimate {
            rtt_ms: 0.0,
            bandwidth_bps: 0.0,
            samples: 0,
        });
        let decision = Decision {
            mode: chosen.prediction.mode,
            settings: chosen.prediction.settings.clone(),
            reason,
            overridden,
            predictions: scored
                .iter()
                .map(|s| s.prediction.to_wire(s.cost))
                .collect(),
            network: net.clone(),
            trigger: trigger.as_str().to_string(),
            seq: self.seq,
        };
        self.basis_net = Some(net);
        self.basis_load = self.load.factor();
        self.current = Some(decision.clone());
        decision
    }

    fn reason(&self, outcome: &Outcome, scored: &[Scored]) -> String {
        match (self.caps.as_ref(), self.net.as_ref(), self.stats.as_ref()) {
            (Some(caps), Some(net), Some(stats)) => {
                let inputs = Inputs {
                    caps,
                    net,
                    stats,
                    load: self.load,
                };
                reason::explain(outcome.note.as_deref(), scored, outcome.target, &inputs)
            }
            _ => outcome.note.clone().unwrap_or_default(),
        }
    }

    /// Logs an evaluation that issued a decision or held a change back.
    fn record(
        &mut self,
        trigger: Trigger,
        now: u64,
        scored: &[Scored],
        best: usize,
        outcome: &Outcome,
        decision: Option<&Decision>,
    ) {
        if decision.is_none() {
            // A hold is logged when it starts or changes, not at every tick
            // it lasts.
            let held = (
                scored[best].prediction.mode,
                self.pending.map(|p| p.since_ms),
            );
            if best == outcome.target || self.last_held == Some(held) {
                return;
            }
            self.last_held = Some(held);
        } else {
            self.last_held = None;
        }
        let (Some(caps), Some(net), Some(stats)) =
            (self.caps.clone(), self.net.clone(), self.stats.as_ref())
        else {
            return;
        };
        let reason = match (decision, &self.pending) {
            (Some(d), _) => d.reason.clone(),
            (None, Some(p)) => format!(
                "held: {} preferred since {} ms, hysteresis not passed",
                reason::mode_name(p.mode),
                p.since_ms
            ),
            (None, None) => format!(
                "held: {} not better by the switch margin",
                reason::mode_name(scored[best].prediction.mode)
            ),
        };
        let entry = LogEntry {
            at_ms: now,
            trigger,
            inputs: InputSummary {
                network: net,
                caps,
                tape_len: stats.tape_len,
                statements: stats.statements(),
                primitives: stats.primitives_estimate(),
                closed_form: stats.closed_form,
                load: self.load,
                override_mode: self.override_mode,
            },
            predictions: scored
                .iter()
                .map(|s| s.prediction.to_wire(s.cost))
                .collect(),
            best: scored[best].prediction.mode,
            chosen: scored[outcome.target].prediction.mode,
            issued: decision.map(|d| d.seq),
            reason,
        };
        while self.log.len() >= self.config.log_capacity {
            self.log.pop_front();
        }
        self.log.push_back(entry);
    }
}
