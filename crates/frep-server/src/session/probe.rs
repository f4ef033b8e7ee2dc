//! Measuring the link to the client on its own socket: round trips and
//! bandwidth.
//!
//! Round trip: a `ping` every `ping_ms`. Its `pong` gives one sample, from
//! send to answer on the server's clock. The estimate is the median of the
//! last `rtt_window` samples.
//!
//! Bandwidth: a round of probes of growing size (`probe_sizes`).
//! - Probes are random bytes, so no compression helps. They go one at a
//!   time.
//! - Each is preceded by a ping. The client can then time the transfer
//!   from the ping's arrival to the probe's (its `clientMs`).
//! - A probe's transfer time is the client's figure when it gave one, which
//!   excludes the trip back. But a hop that buffers can deliver the ping
//!   with the probe, and the client then times almost nothing: a figure
//!   under a quarter of the server's (over 20 ms) gives way to the server's.
//! - Else it is the server's time from sending to the `probeDone`, less one
//!   round trip: the first byte's trip out and the answer's trip back.
//! - The round's bandwidth is its bytes over the sum of its transfer times,
//!   so the largest probes weigh most. Before the first round ends, its
//!   probes so far give the figure.
//! - A round stops after its sizes, `probe_round_bytes`, or
//!   `probe_budget_ms`. It also stops before a probe that the round's
//!   bandwidth so far says would take over `probe_max_transfer_ms`. On a
//!   1.5 Mbit/s link 16 kB measure it; 256 kB more would hold up the first
//!   display for 1.4 s.
//! - Rounds repeat every `reprobe_ms`. They come sooner (never within
//!   `reprobe_min_ms`) when acknowledged frames imply a throughput far under
//!   the estimate: the link changed.

use std::collections::{HashMap, VecDeque};
use std::time::{Duration, Instant};

use axum::extract::ws::Message;
use frep_wire::{BinaryHeader, NetworkEstimate, ServerMessage};

use super::config::SessionConfig;
use super::wire;

/// Shortest transfer time believed, ms (loopback transfers round to 0).
const MIN_TRANSFER_MS: f64 = 0.01;
/// A server-timed transfer over this long, ms, tells a coalesced probe
/// (the client's figure under a quarter of it) from loopback jitter.
const COALESCED_MIN_MS: f64 = 20.0;
/// Acknowledged frames looked at to decide that the link changed.
const FRAME_WINDOW: usize = 8;
/// Frames implying under `1 / FRAME_DROP` of the estimate ask for a probe.
const FRAME_DROP: f64 = 4.0;

/// One probe round under way.
#[derive(Debug)]
struct Round {
    sizes: VecDeque<u64>,
    started: Instant,
    sent_bytes: u64,
    bytes: u64,
    transfer_ms: f64,
}

impl Round {
    /// Bits per second so far, once a probe came back.
    fn bandwidth(&self) -> Option<f64> {
        (self.bytes > 0 && self.transfer_ms > 0.0)
            .then(|| self.bytes as f64 * 8.0 / (self.transfer_ms / 1e3))
    }

    /// ms to send `bytes` at the round's bandwidth so far (0 before any).
    fn predicted_ms(&self, bytes: u64) -> f64 {
        self.bandwidth()
            .map_or(0.0, |bps| bytes as f64 * 8.0 / bps * 1e3)
    }
}

/// A probe waiting for its `probeDone`.
#[derive(Debug)]
struct Outstanding {
    id: u32,
    bytes: u64,
    sent: Instant,
}

/// The link's measurements of one session.
#[derive(Debug)]
pub struct Prober {
    config: std::sync::Arc<SessionConfig>,
    seed: String,
    next_id: u32,
    pings: HashMap<u32, Instant>,
    rtts: VecDeque<f64>,
    round: Option<Round>,
    outstanding: Option<Outstanding>,
    bandwidth: Option<f64>,
    probes: u32,
    last_round: Option<Instant>,
    last_ping: Option<Instant>,
    frames: VecDeque<f64>,
}

impl Prober {
    /// A prober; `seed` makes the session's probe bytes its own.
    pub fn new(config: std::sync::Arc<SessionConfig>, seed: &str) -> Prober {
        Prober {
            config,
            seed: seed.to_string(),
            next_id: 0,
            pings: HashMap::new(),
            rtts: VecDeque::new(),
            round: None,
            outstanding: None,
            bandwidth: None,
            probes: 0,
            last_round: None,
            last_ping: None,
            frames: VecDeque::new(),
        }
    }

    fn id(&mut self) -> u32 {
        self.next_id = self.next_id.wrapping_add(1);
        self.next_id
    }

    /// A ping to send now.
    pub fn ping(&mut self, now: Instant) -> Message {
        let id = self.id();
        // Unanswered pings are forgotten after a while so the map stays small.
        let timeout = Duration::from_millis(self.config.probe_timeout_ms);
        self.pings.retain(|_, t| now.duration_since(*t) < timeout);
        self.pings.insert(id, now);
        self.last_ping = Some(now);
        wire::text(&ServerMessage::Ping { id })
    }

    /// A pong: one round-trip sample. False for an unknown id.
    pub fn pong(&mut self, id: u32, now: Instant) -> bool {
        let Some(sent) = self.pings.remove(&id) else {
            return false;
        };
        self.rtts
            .push_back(now.duration_since(sent).as_secs_f64() * 1e3);
        while self.rtts.len() > self.config.rtt_window.max(1) {
            self.rtts.pop_front();
        }
        true
    }

    /// The median round trip, or the prior.
    pub fn rtt_ms(&self) -> f64 {
        median(self.rtts.iter().copied()).unwrap_or(self.config.prior_rtt_ms)
    }

    /// The current estimate (priors where nothing is measured; `samples`
    /// counts pongs and probes).
    pub fn estimate(&self) -> NetworkEstimate {
        NetworkEstimate {
            rtt_ms: self.rtt_ms(),
            bandwidth_bps: self
                .measured_bandwidth()
                .unwrap_or(self.config.prior_bandwidth_bps),
            samples: self.rtts.len() as u32 + self.probes,
        }
    }

    /// The last round's bandwidth, else the one under way's so far.
    fn measured_bandwidth(&self) -> Option<f64> {
        self.bandwidth
            .or_else(|| self.round.as_ref().and_then(Round::bandwidth))
    }

    /// Whether a bandwidth figure was measured (a round, or a probe of the
    /// one under way).
    pub fn has_bandwidth(&self) -> bool {
        self.measured_bandwidth().is_some()
    }

    /// Whether a ping is due.
    pub fn ping_due(&self, now: Instant) -> bool {
        self.last_ping
            .is_none_or(|t| now.duration_since(t) >= Duration::from_millis(self.config.ping_ms))
    }

    /// Whether a probe round should start now (none running, the last one
    /// old enough, or the frames asked for one).
    pub fn round_due(&self, now: Instant) -> bool {
        if self.round.is_some() || self.config.probe_sizes.is_empty() {
            return false;
        }
        let Some(last) = self.last_round else {
            return true;
        };
        let since = now.duration_since(last);
        let periodic =
            self.config.reprobe_ms > 0 && since >= Duration::from_millis(self.config.reprobe_ms);
        let asked =
            self.link_changed() && since >= Duration::from_millis(self.config.reprobe_min_ms);
        periodic || asked
    }

    /// Starts a round: the messages to send (a ping, then the first probe).
    pub fn start_round(&mut self, now: Instant) -> Vec<Message> {
        self.round = Some(Round {
            sizes: self.config.probe_sizes.iter().copied().collect(),
            started: now,
            sent_bytes: 0,
            bytes: 0,
            transfer_ms: 0.0,
        });
        self.last_round = Some(now);
        self.frames.clear();
        self.next_probe(now)
    }

    /// The next probe of the round (with its ping), or nothing when the
    /// round is over (then the round's figure is kept).
    fn next_probe(&mut self, now: Instant) -> Vec<Message> {
        let cap = self.config.probe_round_bytes;
        let budget = Duration::from_millis(self.config.probe_budget_ms);
        let Some(round) = self.round.as_mut() else {
            return Vec::new();
        };
        let max_ms = self.config.probe_max_transfer_ms;
        let size = round.sizes.pop_front().filter(|s| {
            *s > 0
                && round.sent_bytes + s <= cap
                && now.duration_since(round.started) < budget
                && round.predicted_ms(*s) <= max_ms
        });
        let Some(size) = size else {
            self.finish_round();
            return Vec::new();
        };
        round.sent_bytes += size;
        let ping = self.ping(now);
        let id = self.id();
        self.outstanding = Some(Outstanding {
            id,
            bytes: size,
            sent: now,
        });
        let payload = random_bytes(&self.seed, id, size as usize);
        let probe = wire::binary(&BinaryHeader::Probe { id, bytes: size }, &payload);
        vec![ping, probe]
    }

    fn finish_round(&mut self) {
        if let Some(bps) = self.round.take().and_then(|r| r.bandwidth()) {
            self.bandwidth = Some(bps);
        }
        self.outstanding = None;
    }

    /// The client's `probeDone`: records the probe and answers the next
    /// messages to send. `Err` for an unknown probe or a wrong byte count.
    pub fn probe_done(
        &mut self,
        id: u32,
        bytes: u64,
        client_ms: f64,
        now: Instant,
    ) -> Result<Vec<Message>, String> {
        let Some(out) = self.outstanding.take_if(|o| o.id == id) else {
            return Err(format!("probeDone for probe {id}, which is not waiting"));
        };
        if bytes != out.bytes {
            self.finish_round();
            return Err(format!(
                "probe {id} was {} bytes, the client counted {bytes}",
                out.bytes
            ));
        }
        let server_ms = now.duration_since(out.sent).as_secs_f64() * 1e3;
        // The server's time less a round trip. But never less than half of
        // it: the rtt is a median and can exceed this one trip.
        let by_server = (server_ms - self.rtt_ms()).max(server_ms * 0.5);
        let client_ok = client_ms.is_finite() && client_ms > 0.0 && client_ms <= server_ms;
        // A buffering hop can hand the ping and the probe over at once: the
        // client then times nearly nothing. Its figure far under the
        // server's, on a transfer long enough to tell, is not believed.
        let coalesced = by_server > COALESCED_MIN_MS && client_ms < by_server / 4.0;
        let transfer = if client_ok && !coalesced {
            client_ms
        } else {
            by_server
        };
        if let Some(r) = self.round.as_mut() {
            r.bytes += bytes;
            r.transfer_ms += transfer.max(MIN_TRANSFER_MS);
        }
        self.probes = self.probes.saturating_add(1);
        Ok(self.next_probe(now))
    }

    /// Gives up a probe the client never answered (checked on ticks).
    pub fn expire(&mut self, now: Instant) {
        let timeout = Duration::from_millis(self.config.probe_timeout_ms);
        if self
            .outstanding
            .as_ref()
            .is_some_and(|o| now.duration_since(o.sent) >= timeout)
        {
            self.finish_round();
        }
    }

    /// Whether a round is running.
    pub fn probing(&self) -> bool {
        self.round.is_some()
    }

    /// An acknowledged frame: `bytes` delivered `ms` after sending (to the
    /// client's display). Its implied throughput is a lower bound of the
    /// link's; many far under the estimate mean the link changed.
    pub fn frame_delivered(&mut self, bytes: u64, ms: f64) {
        let transfer = (ms - self.rtt_ms()).max(MIN_TRANSFER_MS);
        self.frames.push_back(bytes as f64 * 8.0 / (transfer / 1e3));
        while self.frames.len() > FRAME_WINDOW {
            self.frames.pop_front();
        }
    }

    fn link_changed(&self) -> bool {
        let (Some(bw), true) = (self.bandwidth, self.frames.len() >= FRAME_WINDOW) else {
            return false;
        };
        median(self.frames.iter().copied()).is_some_and(|m| m < bw / FRAME_DROP)
    }
}

/// Incompressible bytes: BLAKE3's extendable output of the seed and id.
pub fn random_bytes(seed: &str, id: u32, len: usize) -> Vec<u8> {
    let mut h = blake3::Hasher::new();
    h.update(seed.as_bytes());
    h.update(&id.to_le_bytes());
    let mut out = vec![0u8; len];
    h.finalize_xof().fill(&mut out);
    out
}

/// The median of finite values.
pub fn median(values: impl Iterator<Item = f64>) -> Option<f64> {
    let mut v: Vec<f64> = values.filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;

    fn config() -> Arc<SessionConfig> {
        Arc::new(SessionConfig {
            probe_sizes: vec![1000, 4000],
            ..SessionConfig::default()
        })
    }

    fn probe_id(msgs: &[Message]) -> (u32, u64) {
        let Some(Message::Binary(b)) = msgs.last() else {
            panic!("no probe in {msgs:?}");
        };
        let n = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize;
        match serde_json::from_slice(&b[4..4 + n]).unwrap() {
            BinaryHeader::Probe { id, bytes } => {
                assert_eq!(b.len() - 4 - n, bytes as usize);
                (id, bytes)
            }
            h => panic!("{h:?}"),
        }
    }

    #[test]
    fn a_round_measures_bytes_over_transfer_time() {
        let mut p = Prober::new(config(), "s");
        let t0 = Instant::now();
        assert!(p.round_due(t0));
        let m = p.start_round(t0);
        assert_eq!(m.len(), 2, "a ping precedes the probe");
        let (id, bytes) = probe_id(&m);
        assert_eq!(bytes, 1000);
        let t1 = t0 + Duration::from_millis(40);
        let m = p.probe_done(id, bytes, 1.0, t1).unwrap();
        let (id2, bytes2) = probe_id(&m);
        assert_eq!(bytes2, 4000);
        let t2 = t1 + Duration::from_millis(40);
        assert!(p.probe_done(id2, bytes2, 3.0, t2).unwrap().is_empty());
        assert!(!p.probing());
        let e = p.estimate();
        // 5000 bytes in 4 ms of client-timed transfer: 10 Mb/s.
        assert!((e.bandwidth_bps - 10e6).abs() < 1.0, "{e:?}");
        assert_eq!(e.samples, 2);
        assert!(!p.round_due(t2), "not again so soon");
    }

    #[test]
    fn a_slow_link_gets_no_larger_probe() {
        let cfg = Arc::new(SessionConfig {
            probe_sizes: vec![16_000, 64_000, 256_000],
            probe_max_transfer_ms: 250.0,
            ..SessionConfig::default()
        });
        let mut p = Prober::new(cfg, "s");
        let t0 = Instant::now();
        let (id, bytes) = probe_id(&p.start_round(t0));
        // 16 kB in 85 ms is 1.5 Mbit/s: 64 kB would take 340 ms.
        let t1 = t0 + Duration::from_millis(240);
        assert!(p.probe_done(id, bytes, 85.0, t1).unwrap().is_empty());
        assert!(!p.probing(), "the round ends");
        let e = p.estimate();
        assert!(
            (e.bandwidth_bps - 16_000.0 * 8.0 / 0.085).abs() < 1.0,
            "{e:?}"
        );
    }

    #[test]
    fn a_coalesced_probe_is_timed_by_the_server() {
        let mut p = Prober::new(config(), "s");
        let t0 = Instant::now();
        let (id, bytes) = probe_id(&p.start_round(t0));
        // The client timed 0.1 ms, but the answer took 100 ms (a 50 ms
        // prior round trip): 50 ms of transfer is believed.
        let t1 = t0 + Duration::from_millis(100);
        p.probe_done(id, bytes, 0.1, t1).unwrap();
        let e = p.estimate();
        assert!((e.bandwidth_bps - 1000.0 * 8.0 / 0.05).abs() < 1.0, "{e:?}");
    }

    #[test]
    fn wrong_answers_are_refused() {
        let mut p = Prober::new(config(), "s");
        let t0 = Instant::now();
        let (id, _) = probe_id(&p.start_round(t0));
        assert!(p.probe_done(id + 7, 1000, 1.0, t0).is_err());
        assert!(p.probe_done(id, 999, 1.0, t0).is_err());
        assert!(!p.probing(), "a wrong count ends the round");
    }

    #[test]
    fn pongs_give_the_median_round_trip() {
        let mut p = Prober::new(config(), "s");
        let t0 = Instant::now();
        assert_eq!(p.rtt_ms(), 50.0, "prior");
        for ms in [10, 30, 20] {
            let Message::Text(t) = p.ping(t0) else {
                panic!()
            };
            let ServerMessage::Ping { id } = serde_json::from_str(t.as_str()).unwrap() else {
                panic!()
            };
            assert!(p.pong(id, t0 + Duration::from_millis(ms)));
            assert!(!p.pong(id, t0), "answered once");
        }
        assert!((p.rtt_ms() - 20.0).abs() < 1e-9);
    }

    #[test]
    fn slow_frames_ask_for_a_new_round() {
        let cfg = Arc::new(SessionConfig {
            probe_sizes: vec![1000],
            reprobe_ms: 0,
            reprobe_min_ms: 0,
            ..SessionConfig::default()
        });
        let mut p = Prober::new(cfg, "s");
        let t0 = Instant::now();
        let (id, b) = probe_id(&p.start_round(t0));
        p.probe_done(id, b, 0.1, t0).unwrap();
        assert!(!p.round_due(t0));
        for _ in 0..FRAME_WINDOW {
            p.frame_delivered(10_000, 5_000.0);
        }
        assert!(p.round_due(t0));
    }

    #[test]
    fn probe_bytes_are_random_and_distinct() {
        let a = random_bytes("s", 1, 4096);
        let b = random_bytes("s", 2, 4096);
        assert_ne!(a, b);
        let zeros = a.iter().filter(|&&x| x == 0).count();
        assert!(zeros < 64, "{zeros} zero bytes");
    }
}
