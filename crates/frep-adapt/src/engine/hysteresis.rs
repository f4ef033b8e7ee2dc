//! The engine's hysteresis. It picks which mode an evaluation targets: an
//! override, the mode in force, or a better one whose timer has run. It
//! also says whether the settings of the mode in force should change. The
//! rules are in the parent module's doc.

use frep_wire::Decision;

use super::{Engine, Outcome, Pending};
use crate::choose::{self, Scored};
use crate::correction::mode_index;
use crate::log::Trigger;
use crate::predict::{predict, Inputs, Prediction};
use crate::reason;

impl Engine {
    /// Keeps the uncorrected figures for learning, and plans the target:
    /// the outcome and the index of the best mode.
    pub(super) fn plan(
        &mut self,
        trigger: Trigger,
        scored: &[Scored],
        now_ms: u64,
    ) -> (Outcome, usize) {
        for (i, s) in scored.iter().enumerate() {
            self.raw[i] = (s.prediction.raw_first_display_ms, s.prediction.raw_orbit_ms);
        }
        let best = choose::best(scored);
        let outcome = match self.override_outcome(trigger, scored, best) {
            Some(o) => o,
            None => self.hysteresis(trigger, scored, best, now_ms),
        };
        (outcome, best)
    }

    /// The outcome under an override (`None`: automatic). An override the
    /// client cannot show falls back to the best mode, saying why.
    fn override_outcome(
        &self,
        trigger: Trigger,
        scored: &[Scored],
        best: usize,
    ) -> Option<Outcome> {
        let m = self.override_mode?;
        let forced = matches!(trigger, Trigger::Connect | Trigger::Override);
        let i = mode_index(m);
        Some(match &scored[i].prediction.refusal {
            None => Outcome {
                target: i,
                issue: forced || self.mode_differs(i),
                note: Some(format!("your choice: {}", reason::mode_name(m))),
            },
            Some(r) => Outcome {
                target: best,
                issue: forced || self.mode_differs(best),
                note: Some(format!(
                    "{} is not possible here ({r})",
                    reason::mode_name(m)
                )),
            },
        })
    }

    /// Which mode to use, and whether to issue even with the same settings.
    fn hysteresis(
        &mut self,
        trigger: Trigger,
        scored: &[Scored],
        best: usize,
        now: u64,
    ) -> Outcome {
        let forced = matches!(trigger, Trigger::Connect | Trigger::Override);
        let Some(current) = self.current.as_ref().map(|d| mode_index(d.mode)) else {
            return Outcome {
                target: best,
                issue: true,
                note: None,
            };
        };
        if forced {
            return Outcome {
                target: best,
                issue: true,
                note: None,
            };
        }
        let cur = &scored[current].prediction;
        if let Some(r) = &cur.refusal {
            let note = format!("{} no longer possible ({r})", reason::mode_name(cur.mode));
            return Outcome {
                target: best,
                issue: true,
                note: Some(note),
            };
        }
        let keep = Outcome {
            target: current,
            issue: false,
            note: None,
        };
        if best == current
            || scored[best].cost >= scored[current].cost * (1.0 - self.config.switch_margin)
        {
            self.pending = None;
            return keep;
        }
        // Failing its targets: orbit under the frame rate (predicted or
        // reported), or edits slower than a user's patience.
        let w = &self.config.weights;
        let failing = cur.orbit_ms > 1000.0 / w.min_orbit_fps
            || cur.edit_ms > w.patience_ms
            || self.slow_since.is_some();
        let immediate = trigger == Trigger::SlowFrames
            || (trigger == Trigger::Edit && failing)
            || (trigger == Trigger::Report && self.guess_replaced);
        let since = match self.pending {
            Some(p) if p.mode == scored[best].prediction.mode => p.since_ms,
            _ => now,
        };
        self.pending = Some(Pending {
            mode: scored[best].prediction.mode,
            since_ms: since,
        });
        let waited = now.saturating_sub(since);
        let idle = self
            .last_activity_ms
            .is_none_or(|t| now.saturating_sub(t) >= self.config.idle_before_upgrade_ms);
        let go = immediate
            || (failing && waited >= self.config.downgrade_after_ms)
            || (!failing && idle && waited >= self.config.upgrade_after_ms);
        if !go {
            return keep;
        }
        let note = self.switch_note(trigger, cur, failing, waited);
        Outcome {
            target: best,
            issue: true,
            note: Some(note),
        }
    }

    /// Why the engine leaves the current mode, in words.
    fn switch_note(
        &self,
        trigger: Trigger,
        cur: &Prediction,
        failing: bool,
        waited: u64,
    ) -> String {
        let name = reason::mode_name(cur.mode);
        let fps = self.config.weights.min_orbit_fps;
        if trigger == Trigger::SlowFrames {
            format!("frames stayed under {fps:.0} fps in {name}")
        } else if trigger == Trigger::Report && self.guess_replaced {
            format!("measured benchmarks replace the guesses {name} rested on")
        } else if failing && cur.orbit_ms > 1000.0 / fps {
            format!(
                "{name}: orbit ≈ {:.0} fps, under {fps:.0}",
                reason::fps(cur.orbit_ms)
            )
        } else if failing {
            format!(
                "{name}: an edit takes ≈ {}",
                reason::duration_words(cur.edit_ms)
            )
        } else {
            format!(
                "better than {name} for {}",
                reason::duration_words(waited as f64)
            )
        }
    }

    fn mode_differs(&self, i: usize) -> bool {
        self.current
            .as_ref()
            .is_none_or(|d| mode_index(d.mode) != i)
    }

    /// Whether the target keeps the current mode but its settings should
    /// change. That is so when their inputs changed discretely (report,
    /// edit, slow frames) or moved out of band (network, load). It is also
    /// so when the new settings beat the ones in force by the switch margin
    /// (corrections learnt, server measurements).
    pub(super) fn settings_changed(&self, trigger: Trigger, target: &Scored) -> bool {
        let Some(cur) = self.current.as_ref() else {
            return false;
        };
        if cur.mode != target.prediction.mode || cur.settings == target.prediction.settings {
            return false;
        }
        match trigger {
            Trigger::Connect | Trigger::Override => false,
            Trigger::Report | Trigger::Edit | Trigger::SlowFrames => true,
            // A frame rate acts through the slow-frames timer, not at once.
            Trigger::FrameRate => self.network_moved() || self.load_moved(),
            _ => {
                self.network_moved()
                    || self.load_moved()
                    || (self.slow_since.is_none() && self.settings_gain(cur, target))
            }
        }
    }

    /// Why the settings of the current mode change, in words.
    pub(super) fn settings_note(&self, trigger: Trigger) -> String {
        let mode = self
            .current
            .as_ref()
            .map_or("", |d| reason::mode_name(d.mode));
        match trigger {
            Trigger::SlowFrames => format!(
                "frames stayed under {:.0} fps in {mode}: lighter settings",
                self.config.weights.min_orbit_fps
            ),
            Trigger::Edit => "the model changed: settings for it".to_string(),
            Trigger::Report => "the client's report changed: settings for it".to_string(),
            Trigger::Load => "the server's load changed: settings for it".to_string(),
            Trigger::Displayed => {
                "learnt from the client's display times: new settings".to_string()
            }
            _ if self.network_moved() => "the network changed: settings for it".to_string(),
            _ => "new measurements: better settings".to_string(),
        }
    }

    /// Whether the load factor left the band around the settings' basis.
    fn load_moved(&self) -> bool {
        let f = self.load.factor() / self.basis_load;
        f > self.config.load_band || f < 1.0 / self.config.load_band
    }

    /// Whether `target` is better than the settings in force, re-predicted
    /// now, by the switch margin.
    fn settings_gain(&self, cur: &Decision, target: &Scored) -> bool {
        let (Some(caps), Some(net), Some(stats)) =
            (self.caps.as_ref(), self.net.as_ref(), self.stats.as_ref())
        else {
            return false;
        };
        let inputs = Inputs {
            caps,
            net,
            stats,
            load: self.load,
        };
        let c = &self.config;
        let now = predict(
            cur.mode,
            &cur.settings,
            &inputs,
            &c.limits,
            &self.corrections,
        );
        let now_cost = choose::cost(&now, &c.weights, &c.limits, &inputs);
        target.cost < now_cost * (1.0 - c.switch_margin)
    }

    /// Whether the network left the band around the current settings' basis.
    pub(super) fn network_moved(&self) -> bool {
        let (Some(b), Some(n)) = (self.basis_net.as_ref(), self.net.as_ref()) else {
            return false;
        };
        let band = self.config.network_band;
        let bw = n.bandwidth_bps / b.bandwidth_bps.max(1.0);
        let rtt_moved = (n.rtt_ms - b.rtt_ms).abs() > (b.rtt_ms * (band - 1.0)).max(20.0);
        !(bw.is_finite() && bw <= band && bw >= 1.0 / band) || rtt_moved
    }
}
