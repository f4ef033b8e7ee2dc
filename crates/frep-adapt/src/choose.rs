//! Scoring and settings: which settings suit each mode, and which mode is
//! best.
//!
//! The score of a prediction is a cost in "ms-equivalents" (lower is
//! better):
//!
//! ```text
//! cost = first × first_display_ms + orbit × orbit_ms + edit × edit_ms
//!      + slow_orbit × max(0, orbit_ms − 1000 / min_orbit_fps)
//!      + slow_first × max(0, first_display_ms − patience_ms)
//!      + mode_penalty[mode] + settings penalty
//! ```
//!
//! - The mode penalty says what a mode gives up whatever its speed. A view
//!   set only shows fixed views, a volume is blurred by its grid, and a
//!   still image's orbit frames come from the server.
//! - The settings penalty says what lower settings give up: image quality
//!   and size below the screen's, mesh depth, render scale of the client's
//!   ray casters, view count.
//!
//! Settings are chosen by the same cost. For each mode a small ladder of
//! candidate settings is predicted, and the cheapest kept. So on a slow link
//! images get smaller and lossier and meshes coarser. A slow GPU ray casts
//! at a reduced resolution. Each goes exactly as far as it pays.

use frep_wire::{ImageEncoding, Mode, ModeSettings};
use serde::Serialize;

use crate::client::Limits;
use crate::correction::{mode_index, Corrections};
use crate::predict::{predict, Inputs, Prediction};

/// Cost of an infeasible mode (finite so that it serializes as JSON).
pub const INFEASIBLE_COST: f64 = 1.0e9;

/// Screen pixels per mesh cell at which a mesh looks smooth enough.
pub const MESH_PIXELS_PER_CELL: f64 = 6.0;

/// Weights of the cost.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct CostWeights {
    /// Per ms of first display.
    pub first: f64,
    /// Per ms of an orbit frame.
    pub orbit: f64,
    /// Per ms of an edit's latency.
    pub edit: f64,
    /// Orbit frame rate below which a mode is penalised.
    pub min_orbit_fps: f64,
    /// Per ms of orbit frame beyond `1000 / min_orbit_fps`.
    pub slow_orbit: f64,
    /// First display a user waits for without noticing much, ms.
    pub patience_ms: f64,
    /// Per ms of first display beyond `patience_ms`.
    pub slow_first: f64,
    /// Penalty per mode, in [`Mode::ALL`] order.
    pub mode_penalty: [f64; 6],
    /// Per quality point below [`CostWeights::full_quality`].
    pub per_quality_point: f64,
    /// Quality that is not penalised.
    pub full_quality: u8,
    /// Per unit of (screen side / rendered side − 1).
    pub per_undersize: f64,
    /// Mesh coarseness: `per_mesh_level × (2^deficit − 1)` where the
    /// deficit is the levels below the depth that puts one cell under
    /// ~[`MESH_PIXELS_PER_CELL`] screen pixels.
    pub per_mesh_level: f64,
}

impl Default for CostWeights {
    fn default() -> Self {
        CostWeights {
            first: 0.5,
            orbit: 2.0,
            edit: 0.5,
            min_orbit_fps: 20.0,
            slow_orbit: 50.0,
            patience_ms: 3000.0,
            slow_first: 1.0,
            // Still, view set, server mesh, 4a, 4b, volume.
            mode_penalty: [40.0, 200.0, 15.0, 0.0, 15.0, 120.0],
            per_quality_point: 3.0,
            full_quality: 85,
            per_undersize: 150.0,
            per_mesh_level: 60.0,
        }
    }
}

/// A prediction with its cost.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Scored {
    /// The prediction.
    pub prediction: Prediction,
    /// Its cost ([`INFEASIBLE_COST`] when infeasible).
    pub cost: f64,
}

/// The cost of a prediction (see the module doc).
pub fn cost(p: &Prediction, w: &CostWeights, limits: &Limits, inputs: &Inputs) -> f64 {
    if !p.feasible() {
        return INFEASIBLE_COST;
    }
    cost_if_feasible(p, w, limits, inputs)
}

/// The cost as if the mode were feasible (to choose the settings a refused
/// mode is shown with).
fn cost_if_feasible(p: &Prediction, w: &CostWeights, limits: &Limits, inputs: &Inputs) -> f64 {
    let frame_target = 1000.0 / w.min_orbit_fps.max(1.0);
    let c = w.first * p.first_display_ms
        + w.orbit * p.orbit_ms
        + w.edit * p.edit_ms
        + w.slow_orbit * (p.orbit_ms - frame_target).max(0.0)
        + w.slow_first * (p.first_display_ms - w.patience_ms).max(0.0)
        + w.mode_penalty[mode_index(p.mode)]
        + settings_penalty(p.mode, &p.settings, w, limits, inputs);
    if c.is_finite() {
        c.min(INFEASIBLE_COST)
    } else {
        INFEASIBLE_COST
    }
}

/// What lower settings give up, in ms-equivalents.
fn settings_penalty(
    mode: Mode,
    s: &ModeSettings,
    w: &CostWeights,
    limits: &Limits,
    inputs: &Inputs,
) -> f64 {
    let quality = f64::from(w.full_quality.saturating_sub(s.quality)) * w.per_quality_point;
    let screen_side = f64::from(inputs.caps.device_width.max(inputs.caps.device_height));
    let side = f64::from(s.width.max(s.height).max(1));
    // Rendering larger than the image cap is not asked for.
    let wanted = screen_side.min(f64::from(limits.max_image_side));
    let undersize = |wanted: f64| (wanted / side - 1.0).max(0.0) * w.per_undersize;
    match mode {
        // Orbit frames below the still's size blur while moving (trame
        // sends them at 1/devicePixelRatio): a smaller penalty per step.
        Mode::Still => quality + undersize(wanted) + (s.moving_scale - 1.0).max(0.0) * 20.0,
        Mode::ViewSet => {
            let rings = s.elevations.len().max(1) as f64;
            let sparse = (24.0 / f64::from(s.views.max(1)) - 1.0).max(0.0) * 40.0;
            quality + undersize(wanted.min(512.0)) + sparse + 20.0 / rings
        }
        Mode::ServerMesh | Mode::WasmMesh => {
            let wanted = (screen_side / MESH_PIXELS_PER_CELL).log2().clamp(5.0, 9.0);
            let deficit = (wanted - f64::from(s.mesh_depth)).max(0.0);
            (deficit.exp2() - 1.0) * w.per_mesh_level
        }
        Mode::GpuRaycast => undersize(screen_side),
        Mode::Volume => {
            let coarse = (128.0 / f64::from(s.volume_grid.max(1)) - 1.0).max(0.0) * 60.0;
            undersize(screen_side) + coarse
        }
    }
}

/// Image settings everything starts from: the screen's device pixels capped
/// at the image limit, JPEG q75.
pub fn base_settings(inputs: &Inputs, limits: &Limits) -> ModeSettings {
    let (w, h) = fit(
        inputs.caps.device_width,
        inputs.caps.device_height,
        limits.max_image_side,
    );
    ModeSettings {
        width: w,
        height: h,
        quality: 75,
        moving_scale: 2.0,
        moving_quality: 50,
        format: ImageEncoding::Jpeg,
        views: 12,
        elevations: vec![20.0],
        mesh_depth: 7,
        coarse_depth: 5,
        volume_grid: 64,
    }
}

/// `w × h` scaled down to fit `max_side` (aspect kept, at least 1).
fn fit(w: u32, h: u32, max_side: u32) -> (u32, u32) {
    let side = w.max(h).max(1);
    if side <= max_side {
        return (w.max(1), h.max(1));
    }
    let k = f64::from(max_side) / f64::from(side);
    scale((w, h), k)
}

fn scale((w, h): (u32, u32), k: f64) -> (u32, u32) {
    let s = |v: u32| ((f64::from(v) * k).round() as u32).max(1);
    (s(w), s(h))
}

/// Mode 1: orbit frame scales and the still's encoding.
const STILL_STREAMS: [(f64, ImageEncoding); 4] = [
    (2.0, ImageEncoding::Jpeg),
    (2.0, ImageEncoding::Webp),
    (3.0, ImageEncoding::Jpeg),
    (3.0, ImageEncoding::Webp),
];

/// Mode 2: quality and encoding of the views.
const VIEW_SET_ENCODINGS: [(u8, ImageEncoding); 4] = [
    (75, ImageEncoding::Jpeg),
    (75, ImageEncoding::Webp),
    (60, ImageEncoding::Jpeg),
    (60, ImageEncoding::Webp),
];

/// Candidate settings of a mode, best quality first.
pub fn candidates(mode: Mode, inputs: &Inputs, limits: &Limits) -> Vec<ModeSettings> {
    let base = base_settings(inputs, limits);
    let screen = (inputs.caps.device_width, inputs.caps.device_height);
    let mut out = Vec::new();
    match mode {
        Mode::Still => {
            for k in [1.0, 0.75, 0.5] {
                for q in [85u8, 75, 60, 50, 40] {
                    let (width, height) = scale((base.width, base.height), k);
                    for (moving_scale, format) in STILL_STREAMS {
                        out.push(ModeSettings {
                            width,
                            height,
                            quality: q,
                            moving_scale,
                            moving_quality: q.saturating_sub(25).max(30),
                            format,
                            ..base.clone()
                        });
                    }
                }
            }
        }
        Mode::ViewSet => {
            let most = base.width.min(base.height).max(64);
            for side in [512u32, 384, 256] {
                let side = side.min(most);
                for (views, elevations) in
                    [(24, vec![0.0, 35.0]), (24, vec![20.0]), (12, vec![20.0])]
                {
                    for (q, format) in VIEW_SET_ENCODINGS {
                        out.push(ModeSettings {
                            width: side,
                            height: side,
                            quality: q,
                            views,
                            elevations: elevations.clone(),
                            format,
                            ..base.clone()
                        });
                    }
                }
            }
        }
        Mode::ServerMesh | Mode::WasmMesh => {
            let (least, most) = if mode == Mode::ServerMesh {
                limits.server_mesh_depths
            } else {
                limits.wasm_mesh_depths
            };
            let max_tris = inputs.caps.max_triangles(limits);
            for depth in (least..=most.max(least)).rev() {
                // A client's memory bounds the depth whatever the cost.
                if depth > least && crate::predict::mesh_triangles(inputs.stats, depth) > max_tris {
                    continue;
                }
                out.push(ModeSettings {
                    mesh_depth: depth,
                    coarse_depth: depth.saturating_sub(2).max(least.min(4)),
                    ..base.clone()
                });
            }
        }
        Mode::GpuRaycast => {
            for k in [1.0, 0.75, 0.5, 0.35, 0.25] {
                let (width, height) = scale(screen, k);
                out.push(ModeSettings {
                    width,
                    height,
                    ..base.clone()
                });
            }
        }
        Mode::Volume => {
            let limit = inputs.caps.max_3d_texture.max(limits.min_volume_grid);
            for grid in [128u32, 96, 64] {
                if grid > limit {
                    continue;
                }
                for k in [1.0, 0.75, 0.5, 0.35] {
                    let (width, height) = scale(screen, k);
                    out.push(ModeSettings {
                        width,
                        height,
                        volume_grid: grid,
                        ..base.clone()
                    });
                }
            }
        }
    }
    out
}

/// The cheapest settings of one mode, predicted and scored.
pub fn best_of_mode(
    mode: Mode,
    inputs: &Inputs,
    limits: &Limits,
    weights: &CostWeights,
    corrections: &Corrections,
) -> Scored {
    // Settings are chosen as if the mode were feasible, so that a refused
    // mode shows the figures it would have had.
    let mut best: Option<(Prediction, f64)> = None;
    for settings in candidates(mode, inputs, limits) {
        let prediction = predict(mode, &settings, inputs, limits, corrections);
        let c = cost_if_feasible(&prediction, weights, limits, inputs);
        // Strictly cheaper only: ties keep the higher quality listed first.
        if best.as_ref().is_none_or(|b| c < b.1) {
            best = Some((prediction, c));
        }
    }
    match best {
        Some((prediction, _)) => {
            let cost = cost(&prediction, weights, limits, inputs);
            Scored { prediction, cost }
        }
        // Every ladder above has at least one entry; base settings stand in
        // should one ever be empty.
        None => {
            let settings = base_settings(inputs, limits);
            let prediction = predict(mode, &settings, inputs, limits, corrections);
            let cost = cost(&prediction, weights, limits, inputs);
            Scored { prediction, cost }
        }
    }
}

/// Every mode, each with its cheapest settings, in [`Mode::ALL`] order.
pub fn evaluate(
    inputs: &Inputs,
    limits: &Limits,
    weights: &CostWeights,
    corrections: &Corrections,
) -> Vec<Scored> {
    Mode::ALL
        .iter()
        .map(|&m| best_of_mode(m, inputs, limits, weights, corrections))
        .collect()
}

/// Index of the cheapest feasible entry (the still image, always feasible,
/// when every cost ties at infeasible).
pub fn best(scored: &[Scored]) -> usize {
    let mut best = 0;
    for (i, s) in scored.iter().enumerate() {
        let b = &scored[best];
        let better = match (s.prediction.feasible(), b.prediction.feasible()) {
            (true, false) => true,
            (false, _) => false,
            (true, true) => s.cost < b.cost,
        };
        if better {
            best = i;
        }
    }
    best
}
