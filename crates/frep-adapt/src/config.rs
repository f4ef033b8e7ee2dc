//! The engine's configuration: the limits of the modes, the weights of the
//! cost, how corrections learn, and the hysteresis timers and bands.
//! [`EngineConfig::validate`] checks them all before an engine is made.

use serde::Serialize;

use crate::choose::CostWeights;
use crate::client::Limits;
use crate::correction::CorrectionConfig;

/// The engine's settings.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct EngineConfig {
    /// Limits of the modes.
    pub limits: Limits,
    /// Weights of the cost.
    pub weights: CostWeights,
    /// How corrections learn.
    pub correction: CorrectionConfig,
    /// Slow frames for this long, or a failing mode's better alternative
    /// preferred this long, switches (ms).
    pub downgrade_after_ms: u64,
    /// A better alternative to a mode that is fine must be preferred this
    /// long (ms).
    pub upgrade_after_ms: u64,
    /// The user must have been idle this long for an upgrade (ms).
    pub idle_before_upgrade_ms: u64,
    /// A switch needs the new mode's cost below `(1 − margin) ×` the
    /// current's.
    pub switch_margin: f64,
    /// Settings are re-derived when bandwidth or round trip moved by more
    /// than this factor from the ones the current settings rest on.
    pub network_band: f64,
    /// The same for the server's load factor.
    pub load_band: f64,
    /// Frame rates at or above this are capped by the display: they teach
    /// nothing about the mode's cost.
    pub vsync_fps: f64,
    /// Decision log entries kept (oldest dropped first).
    pub log_capacity: usize,
}

impl Default for EngineConfig {
    fn default() -> Self {
        EngineConfig {
            limits: Limits::default(),
            weights: CostWeights::default(),
            correction: CorrectionConfig::default(),
            downgrade_after_ms: 2_000,
            upgrade_after_ms: 10_000,
            idle_before_upgrade_ms: 1_500,
            switch_margin: 0.15,
            network_band: 1.5,
            load_band: 1.5,
            vsync_fps: 55.0,
            log_capacity: 256,
        }
    }
}

/// A configuration the engine cannot work with.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// A field out of its range.
    #[error("engine config: {field} {why}")]
    Invalid {
        /// The field.
        field: &'static str,
        /// What is wrong with it.
        why: String,
    },
}

fn check(ok: bool, field: &'static str, why: &str) -> Result<(), ConfigError> {
    if ok {
        Ok(())
    } else {
        Err(ConfigError::Invalid {
            field,
            why: why.to_string(),
        })
    }
}

impl EngineConfig {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let c = self;
        check(
            (0.0..1.0).contains(&c.switch_margin),
            "switchMargin",
            "must be in [0, 1)",
        )?;
        check(c.network_band >= 1.0, "networkBand", "must be ≥ 1")?;
        check(c.load_band >= 1.0, "loadBand", "must be ≥ 1")?;
        check(c.vsync_fps > 0.0, "vsyncFps", "must be > 0")?;
        check(c.log_capacity >= 1, "logCapacity", "must be ≥ 1")?;
        let a = c.correction.alpha;
        check(a > 0.0 && a <= 1.0, "correction.alpha", "must be in (0, 1]")?;
        check(
            c.correction.max_ratio >= 1.0,
            "correction.maxRatio",
            "must be ≥ 1",
        )?;
        check(
            c.correction.max_factor >= 1.0,
            "correction.maxFactor",
            "must be ≥ 1",
        )?;
        check(
            c.correction.max_orbit_factor >= 1.0,
            "correction.maxOrbitFactor",
            "must be ≥ 1",
        )?;
        let w = &c.weights;
        let weights = [
            w.first,
            w.orbit,
            w.edit,
            w.slow_orbit,
            w.patience_ms,
            w.slow_first,
            w.per_quality_point,
            w.per_undersize,
            w.per_mesh_level,
        ];
        let all = weights.iter().chain(w.mode_penalty.iter());
        check(
            all.into_iter().all(|v| v.is_finite() && *v >= 0.0),
            "weights",
            "must be finite and ≥ 0",
        )?;
        check(w.min_orbit_fps > 0.0, "weights.minOrbitFps", "must be > 0")?;
        let l = &c.limits;
        for (field, (least, most)) in [
            ("limits.serverMeshDepths", l.server_mesh_depths),
            ("limits.wasmMeshDepths", l.wasm_mesh_depths),
        ] {
            check(
                least >= 1 && least <= most && most <= 12,
                field,
                "must be 1 ≤ least ≤ most ≤ 12",
            )?;
        }
        check(
            l.max_image_side >= 16,
            "limits.maxImageSide",
            "must be ≥ 16",
        )?;
        check(
            l.max_pixel_ratio >= 1.0,
            "limits.maxPixelRatio",
            "must be ≥ 1",
        )?;
        check(
            l.min_volume_grid >= 8,
            "limits.minVolumeGrid",
            "must be ≥ 8",
        )?;
        Ok(())
    }
}
