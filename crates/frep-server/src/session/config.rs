//! The session's settings: every limit and timer of a WebSocket session,
//! with defaults that suit a studio on a real network.
//!
//! It is a plain serde struct, with snake_case keys, every key optional. So
//! the server's configuration can carry it as `session`. Tests can shorten
//! the timers (hysteresis windows, probe budget) instead of waiting.

use serde::{Deserialize, Serialize};

/// Limits and timers of one WebSocket session.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SessionConfig {
    /// Largest message a client may send, bytes (an `open` carries a
    /// source; the socket closes on a larger one).
    pub max_message_bytes: usize,
    /// Sessions open at once on the server; more are refused.
    pub max_sessions: usize,
    /// Messages from the session's tasks waiting for the socket.
    pub outbox: usize,
    /// Sizes of one bandwidth probe round, bytes, in order.
    pub probe_sizes: Vec<u64>,
    /// Most probe bytes of one round.
    pub probe_round_bytes: u64,
    /// A round stops starting new probes after this long, ms.
    pub probe_budget_ms: u64,
    /// A probe is sent only if the round's bandwidth so far says it takes
    /// at most this long, ms. So probes stay short on a slow link, where
    /// they would hold up the first display.
    pub probe_max_transfer_ms: f64,
    /// A probe the client has not answered after this long is given up, ms.
    pub probe_timeout_ms: u64,
    /// Re-probe this often, ms (0: only at the start and when frames show
    /// the link changed).
    pub reprobe_ms: u64,
    /// Fewest ms between two rounds (frames can ask for one sooner than
    /// `reprobe_ms`, never sooner than this).
    pub reprobe_min_ms: u64,
    /// Ping every this many ms.
    pub ping_ms: u64,
    /// Round trips kept for the median.
    pub rtt_window: usize,
    /// Prior round trip before any pong, ms.
    pub prior_rtt_ms: f64,
    /// Prior bandwidth before any probe, bits/s.
    pub prior_bandwidth_bps: f64,
    /// The first decision waits this long after the hello for the first
    /// probe's figure, ms (0: decide on the prior at once). A guessed link
    /// can send a 1 MB mesh down a 1.5 Mbit/s line; the wait is one round
    /// trip and 16 kB.
    pub first_decision_wait_ms: u64,
    /// The engine re-decides at least this often, ms.
    pub tick_ms: u64,
    /// Streamed frames rendering or unacknowledged at once (mode 1).
    pub frames_in_flight: usize,
    /// A frame not acknowledged after this long no longer counts as in
    /// flight, ms (a client that never acks still gets frames).
    pub frame_ack_timeout_ms: u64,
    /// Frames rendered at once on the server for all sessions (0: the
    /// artefact workers' count).
    pub frame_workers: usize,
    /// Smallest frame side, pixels.
    pub frame_min_side: u32,
    /// Progress of a job is pushed at most this often, ms.
    pub progress_ms: u64,
    /// Engine: slow frames for this long downgrade, ms.
    pub downgrade_after_ms: u64,
    /// Engine: a better mode must be preferred this long to upgrade, ms.
    pub upgrade_after_ms: u64,
    /// Engine: the user must be idle this long for an upgrade, ms.
    pub idle_before_upgrade_ms: u64,
}

impl Default for SessionConfig {
    fn default() -> Self {
        SessionConfig {
            max_message_bytes: 2 << 20,
            max_sessions: 1_000,
            outbox: 64,
            probe_sizes: vec![16 << 10, 64 << 10, 256 << 10],
            probe_round_bytes: 1 << 20,
            probe_budget_ms: 2_000,
            probe_max_transfer_ms: 250.0,
            probe_timeout_ms: 10_000,
            reprobe_ms: 30_000,
            reprobe_min_ms: 5_000,
            ping_ms: 3_000,
            rtt_window: 16,
            prior_rtt_ms: 50.0,
            prior_bandwidth_bps: 10e6,
            first_decision_wait_ms: 400,
            tick_ms: 1_000,
            frames_in_flight: 2,
            frame_ack_timeout_ms: 5_000,
            frame_workers: 0,
            frame_min_side: 16,
            progress_ms: 100,
            downgrade_after_ms: 2_000,
            upgrade_after_ms: 10_000,
            idle_before_upgrade_ms: 1_500,
        }
    }
}

impl SessionConfig {
    /// The adaptive engine's configuration with this session's windows.
    pub fn engine(&self) -> frep_adapt::EngineConfig {
        frep_adapt::EngineConfig {
            downgrade_after_ms: self.downgrade_after_ms,
            upgrade_after_ms: self.upgrade_after_ms,
            idle_before_upgrade_ms: self.idle_before_upgrade_ms,
            ..frep_adapt::EngineConfig::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_engine_predicts_the_frames_in_flight_the_session_allows() {
        let d = SessionConfig::default();
        assert_eq!(
            d.frames_in_flight as f64,
            frep_adapt::predict::STILL_FRAMES_IN_FLIGHT
        );
    }
}
