//! Learning from what the client reports: per-mode correction factors.
//!
//! The cost model's constants are rough, and every client and model differs.
//! A client reports how long a mode actually took to reach the screen
//! (`displayed`), or how fast it actually orbits (`frameRate`).
//! - The ratio actual / predicted is folded into a factor for that mode. The
//!   prediction is the one *before* correction, for the settings that were
//!   in use.
//! - Later predictions of that mode are multiplied by the factor.
//! - Each factor is a moving average in log space: a 3× and a ⅓× report
//!   cancel out.
//! - Each ratio is clamped to `[1/max_ratio, max_ratio]`, so one absurd
//!   report cannot take over. The factor is clamped to
//!   `[1/max_factor, max_factor]`.
//!
//! Frame times get a far wider clamp (`max_orbit_factor`, both bounds).
//! The client measures the very thing predicted, and the prior can be off
//! by hundreds: the GPU benchmark draws a tiny shader, a model's shader may
//! be slow on the same card. A narrow clamp would keep a mode that draws at
//! 2 fps looking fast enough to stay.

use frep_wire::Mode;
use serde::Serialize;

/// How corrections learn.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CorrectionConfig {
    /// Weight of a new ratio in the moving average (0 < alpha ≤ 1).
    pub alpha: f64,
    /// Clamp of one observed ratio (≥ 1).
    pub max_ratio: f64,
    /// Clamp of the factor (≥ 1).
    pub max_factor: f64,
    /// Clamp of an orbit ratio and factor (≥ 1).
    pub max_orbit_factor: f64,
}

impl Default for CorrectionConfig {
    fn default() -> Self {
        CorrectionConfig {
            alpha: 0.5,
            max_ratio: 10.0,
            max_factor: 5.0,
            max_orbit_factor: 1000.0,
        }
    }
}

/// One smoothed ratio actual / predicted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Factor {
    /// ln of the factor (0: no correction).
    log: f64,
    /// Observations folded in.
    pub samples: u32,
}

impl Factor {
    /// The factor predictions are multiplied by.
    pub fn value(&self) -> f64 {
        self.log.exp()
    }

    /// Folds in one observation; ignored unless both times are positive
    /// and finite. The ratio is clamped to `max_ratio`, the factor to
    /// `max_factor` (both ≥ 1, either way).
    pub fn observe(
        &mut self,
        actual: f64,
        predicted: f64,
        config: &CorrectionConfig,
        max_ratio: f64,
        max_factor: f64,
    ) {
        if !(actual.is_finite() && predicted.is_finite() && actual > 0.0 && predicted > 0.0) {
            return;
        }
        let max_r = max_ratio.ln();
        let max_f = max_factor.ln();
        let r = (actual / predicted).ln().clamp(-max_r, max_r);
        // The first observation is taken whole: the prior (1.0) is a guess.
        let alpha = if self.samples == 0 { 1.0 } else { config.alpha };
        self.log = (self.log * (1.0 - alpha) + r * alpha).clamp(-max_f, max_f);
        self.samples = self.samples.saturating_add(1);
    }
}

/// The factors of one mode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ModeFactors {
    /// Time to first display (and, for server-made artefacts, an edit's
    /// update, which is the same work again).
    pub first_display: Factor,
    /// Time per orbit frame.
    pub orbit: Factor,
}

/// The correction factors of every mode, for one session.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Corrections {
    /// Per mode, in [`Mode::ALL`] order.
    pub modes: [ModeFactors; 6],
    /// How they learn.
    pub config: CorrectionConfig,
}

/// Index of a mode in [`Mode::ALL`].
pub fn mode_index(mode: Mode) -> usize {
    match mode {
        Mode::Still => 0,
        Mode::ViewSet => 1,
        Mode::ServerMesh => 2,
        Mode::GpuRaycast => 3,
        Mode::WasmMesh => 4,
        Mode::Volume => 5,
    }
}

impl Corrections {
    /// No corrections yet.
    pub fn new(config: CorrectionConfig) -> Corrections {
        Corrections {
            modes: [ModeFactors::default(); 6],
            config,
        }
    }

    /// The factors of a mode.
    pub fn get(&self, mode: Mode) -> &ModeFactors {
        &self.modes[mode_index(mode)]
    }

    /// A displayed time against the uncorrected prediction.
    pub fn observe_first_display(&mut self, mode: Mode, actual_ms: f64, predicted_ms: f64) {
        let config = self.config;
        self.modes[mode_index(mode)].first_display.observe(
            actual_ms,
            predicted_ms,
            &config,
            config.max_ratio,
            config.max_factor,
        );
    }

    /// A frame time against the uncorrected prediction.
    pub fn observe_orbit(&mut self, mode: Mode, actual_ms: f64, predicted_ms: f64) {
        let config = self.config;
        self.modes[mode_index(mode)].orbit.observe(
            actual_ms,
            predicted_ms,
            &config,
            config.max_orbit_factor,
            config.max_orbit_factor,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn moves_toward_reports_and_clamps() {
        let mut c = Corrections::new(CorrectionConfig::default());
        assert_eq!(c.get(Mode::ServerMesh).first_display.value(), 1.0);
        c.observe_first_display(Mode::ServerMesh, 300.0, 100.0);
        let f = c.get(Mode::ServerMesh).first_display.value();
        assert!((f - 3.0).abs() < 1e-9, "{f}");
        c.observe_first_display(Mode::ServerMesh, 100.0, 100.0);
        let g = c.get(Mode::ServerMesh).first_display.value();
        assert!(g > 1.0 && g < 3.0, "{g}");
        // An absurd report is clamped: one ratio of 1000 cannot exceed the
        // factor's clamp.
        for _ in 0..20 {
            c.observe_first_display(Mode::ServerMesh, 1e9, 1.0);
        }
        let h = c.get(Mode::ServerMesh).first_display.value();
        assert!((h - 5.0).abs() < 1e-9, "{h}");
        // Other modes are untouched.
        assert_eq!(c.get(Mode::Still).first_display.samples, 0);
    }

    #[test]
    fn ignores_nonsense() {
        let mut c = Corrections::new(CorrectionConfig::default());
        c.observe_orbit(Mode::GpuRaycast, f64::NAN, 10.0);
        c.observe_orbit(Mode::GpuRaycast, 10.0, 0.0);
        c.observe_orbit(Mode::GpuRaycast, -1.0, 10.0);
        assert_eq!(c.get(Mode::GpuRaycast).orbit.samples, 0);
        assert_eq!(c.get(Mode::GpuRaycast).orbit.value(), 1.0);
    }
}
