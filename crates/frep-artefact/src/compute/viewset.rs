//! View sets: `views` renders per ring around the model on one sprite sheet,
//! and the sheet's index. The renders are the ray caster's
//! `render_view_set`, as `frep render --views` calls it.
//!
//! The index is a function of the settings alone ([`layout`]).
//! - It has one row per ring when that fits in 16 383 pixels (WebP's
//!   limit). Else it is a near-square grid, as frep-render lays sheets out.
//! - The sheet is rendered with those columns given explicitly, so the two
//!   always agree.
//! - The index never waits for the renders.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

use frep_core::Inputs;
use frep_render::{encode, render_camera, render_view_set, Image, ImagePool, ViewSetOptions};
use frep_wire::{ImageEncoding, SectionPlane, ViewSetLayout};

use super::{image, limit, Cancel, JobProgress};
use crate::compiled::Compiled;
use crate::config::ArtefactLimits;
use crate::error::ArtefactError;
use crate::key::image_format;

/// The settings of a view set (the wire spec's fields).
#[derive(Clone, Debug, PartialEq)]
pub struct ViewSetSpec {
    /// Views per ring.
    pub views: u32,
    /// Pitch of each ring, degrees (empty: one ring at 0).
    pub elevations: Vec<f64>,
    /// Pixels per view.
    pub width: u32,
    /// Pixels per view.
    pub height: u32,
    /// Encoding of the sheet.
    pub format: ImageEncoding,
    /// Quality 1–100.
    pub quality: u8,
    /// Field of view (`None`: orthographic).
    pub fov: Option<f64>,
    /// A section plane cutting the model open in every view.
    pub section: Option<SectionPlane>,
}

/// The widest sprite sheet frep-render lays out in one row per ring.
const MAX_ROW: u32 = 16_383;

/// Refuses a view set over the limits.
pub fn check(
    views: u32,
    elevations: &[f64],
    width: u32,
    height: u32,
    limits: &ArtefactLimits,
) -> Result<(), ArtefactError> {
    image::check_size(width, height, limits)?;
    if views == 0 {
        return Err(ArtefactError::BadRequest("a view set of 0 views".into()));
    }
    if elevations.iter().any(|e| !e.is_finite()) {
        return Err(ArtefactError::BadRequest(
            "an elevation is not finite".into(),
        ));
    }
    let rings = elevations.len().max(1) as u64;
    let count = views as u64 * rings;
    limit("views", limits.max_views.into(), count)?;
    let l = layout(views, elevations, width, height);
    limit(
        "sheet pixels",
        limits.max_sheet_pixels,
        l.sheet_size[0] as u64 * l.sheet_size[1] as u64,
    )
}

/// The index of a view set: where each view lies on the sheet.
pub fn layout(views: u32, elevations: &[f64], width: u32, height: u32) -> ViewSetLayout {
    let per_ring = views.max(1);
    let rings: Vec<f64> = if elevations.is_empty() {
        vec![0.0]
    } else {
        elevations.to_vec()
    };
    let count = per_ring.saturating_mul(rings.len() as u32);
    let columns = if per_ring.saturating_mul(width) <= MAX_ROW {
        per_ring
    } else {
        (count as f64).sqrt().ceil().max(1.0) as u32
    };
    let rows = count.div_ceil(columns);
    ViewSetLayout {
        views_per_ring: per_ring,
        elevations: rings,
        start_yaw: 0.0,
        view_size: [width, height],
        columns,
        sheet_size: [columns.saturating_mul(width), rows.saturating_mul(height)],
    }
}

/// Renders the views and encodes the sheet.
pub fn sheet(
    compiled: &Compiled,
    inputs: Inputs,
    spec: &ViewSetSpec,
    cancel: &Cancel,
    progress: &JobProgress,
    pool: &ImagePool,
) -> Result<Vec<u8>, ArtefactError> {
    let l = layout(spec.views, &spec.elevations, spec.width, spec.height);
    let format = image_format(spec.format);
    let opts = ViewSetOptions {
        views: l.views_per_ring,
        elevations: l.elevations.clone(),
        size: (spec.width, spec.height),
        format,
        quality: spec.quality.clamp(1, 100),
        fov_deg: spec.fov,
        start_yaw: l.start_yaw,
        sheet_columns: Some(l.columns),
    };
    let settings = image::settings(
        compiled,
        inputs,
        spec.width,
        spec.height,
        spec.quality,
        spec.section.as_ref(),
    );
    let total = (l.views_per_ring * l.elevations.len() as u32).max(1);
    let done = AtomicU32::new(0);
    let failed = Mutex::new(None::<ArtefactError>);
    let set = render_view_set(&settings.bounds, &opts, cancel.token(), |cam, w, h| {
        let s = frep_render::RenderSettings {
            size: (w, h),
            ..settings.clone()
        };
        let img = render_camera(compiled.model(), &s, cam, cancel.token(), pool);
        let n = done.fetch_add(1, Ordering::Relaxed) + 1;
        progress.set(0.95 * n as f64 / total as f64);
        img.unwrap_or_else(|e| {
            // The first error is kept; the views left render nothing once
            // the caster sees the cancel token.
            cancel.cancel();
            let mut f = failed.lock().unwrap_or_else(|p| p.into_inner());
            f.get_or_insert(e.into());
            Image::filled(w, h, [0, 0, 0, 255])
        })
    });
    // The first error, not the cancel it caused.
    if let Some(e) = failed.into_inner().unwrap_or_else(|p| p.into_inner()) {
        return Err(e);
    }
    let set = set?;
    let bytes = encode(&set.sheet, format, opts.quality);
    for img in set.images {
        pool.recycle(img);
    }
    pool.recycle(set.sheet);
    Ok(bytes?)
}
