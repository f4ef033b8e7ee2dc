//! The public render functions ([`render`], [`render_camera`],
//! [`render_with`], [`render_hits`]) and ambient occlusion.
//!
//! - Each takes a [`CancelToken`]: the caster checks it before each tile.
//! - Those that return an [`Image`] take its bytes from an [`ImagePool`]
//!   the caller owns; the caller may hand the image back with
//!   [`ImagePool::recycle`] once it is encoded.

use std::sync::atomic::Ordering;

use frep_core::eval::batch::BatchEval;
use frep_core::{CancelToken, Model};

use crate::camera::Camera;
use crate::image::{fill_background, Hit, HitBuffer, Image, ImagePool, Shader};
use crate::tiles::{cast_tiled, for_each_dynamic, tile_rows, tiles};

use super::caster::ModelCaster;
use super::normals::unit;
use super::settings::{check_size, RenderError, RenderSettings};

fn make_caster(
    model: &Model,
    settings: &RenderSettings,
    cancel: &CancelToken,
) -> Result<ModelCaster, RenderError> {
    let caster = ModelCaster::sectioned(
        model,
        settings.inputs.clone(),
        settings.bounds,
        settings.section.as_ref(),
    )
    .map_err(|e| RenderError::BadSection(e.to_string()))?;
    Ok(caster.with_cancel(cancel.clone()))
}

/// Casts the rays of `settings` and returns every hit (with ambient
/// occlusion when `settings.ao`).
pub fn render_hits(
    model: &Model,
    settings: &RenderSettings,
    cancel: &CancelToken,
) -> Result<HitBuffer, RenderError> {
    check_size(settings.size, settings.limits)?;
    let (w, h) = settings.size;
    let caster = make_caster(model, settings, cancel)?;
    let cam = settings.camera();
    let mut hits = cast_tiled(&caster, &cam, w, h, settings.tile_size.max(1));
    if cancel.is_cancelled() {
        return Err(RenderError::Cancelled);
    }
    if settings.ao {
        let mut ev = BatchEval::new(&caster.tape);
        let mut ao = vec![1.0; hits.hits.len()];
        ambient_occlusion(&mut ev, &caster, &hits.hits, &mut ao);
        hits.ao = Some(ao);
    }
    Ok(hits)
}

/// Renders a shaded image of `model` as `settings` describe. Tiles are cast
/// and shaded in parallel and only the image is kept whole (no full hit
/// buffer). `cancel`, when cancelled during the render, makes it stop early
/// with [`RenderError::Cancelled`]. The image's bytes come from `pool`.
pub fn render(
    model: &Model,
    settings: &RenderSettings,
    cancel: &CancelToken,
    pool: &ImagePool,
) -> Result<Image, RenderError> {
    render_camera(model, settings, &settings.camera(), cancel, pool)
}

/// [`render`] through any camera (e.g. one view of a view set, or a
/// benchmark's fixed view); `settings.yaw`, `pitch` and `fov` are ignored.
pub fn render_camera(
    model: &Model,
    settings: &RenderSettings,
    camera: &Camera,
    cancel: &CancelToken,
    pool: &ImagePool,
) -> Result<Image, RenderError> {
    let caster = make_caster(model, settings, cancel)?;
    render_with(&caster, settings, camera, cancel, pool)
}

/// [`render_camera`] with a prepared caster (whose [`CastStats`] then count
/// this render; its section plane, not `settings.section`, is the one cut:
/// [`ModelCaster::sectioned`]). The caster stops at the token it was
/// given ([`ModelCaster::with_cancel`]); `cancel` is checked at the end.
///
/// [`CastStats`]: crate::raycast::CastStats
pub fn render_with(
    caster: &ModelCaster,
    settings: &RenderSettings,
    camera: &Camera,
    cancel: &CancelToken,
    pool: &ImagePool,
) -> Result<Image, RenderError> {
    check_size(settings.size, settings.limits)?;
    let (w, h) = settings.size;
    let shader = Shader::new(camera, &settings.lighting, w, h);
    let ts = tiles(w, h, settings.tile_size.max(1));
    let mut img = Image {
        width: w,
        height: h,
        rgba: pool.zeroed(w as usize * h as usize * 4),
    };
    // Each tile is shaded straight into its rows of the image, or filled
    // with the background where no ray hit (nothing to shade). The hit
    // buffer is kept per worker, from tile to tile, and cleared only after
    // a tile with a hit (the caster writes nothing where no ray hits).
    let rows = tile_rows(&mut img.rgba, w as usize, 4, &ts);
    let work: Vec<_> = ts.into_iter().zip(rows).collect();
    // Models that are set expressions over quadrics: each tile solved and
    // shaded in closed form where every ray checks out.
    let closed_form = caster
        .csg_tree
        .as_ref()
        .filter(|_| caster.csg && caster.attr_tape.is_none() && !settings.ao)
        // (Shaded straight from the solution: the cut face would miss its
        // colour.)
        .filter(|_| caster.section.is_none());
    for_each_dynamic(
        work,
        || (None::<BatchEval>, Vec::<Option<Hit>>::new(), false),
        |(ao_eval, hits, dirty), (t, mut rows)| {
            if let Some(csg) = closed_form {
                if caster.closed_form_tile(csg, camera, &shader, &t, &mut rows) {
                    return;
                }
            }
            let n = (t.w() * t.h()) as usize;
            if *dirty || hits.len() != n {
                hits.clear();
                hits.resize(n, None);
            }
            *dirty = caster.cast_tile_hits(camera, &t, hits);
            if !*dirty {
                for (row, y) in rows.iter_mut().zip(t.y0..) {
                    fill_background(shader.background(y), row);
                }
                return;
            }
            let mut ao = Vec::new();
            if settings.ao {
                ao.resize(n, 1.0);
                let ev = ao_eval.get_or_insert_with(|| BatchEval::new(&caster.tape));
                ambient_occlusion(ev, caster, hits, &mut ao);
            }
            let tw = t.w() as usize;
            for ((r, row), y) in rows.iter_mut().enumerate().zip(t.y0..) {
                let span = r * tw..(r + 1) * tw;
                let a = (!ao.is_empty()).then(|| &ao[span.clone()]);
                shader.span(y, &hits[span], a, row);
            }
        },
    );
    if cancel.is_cancelled() {
        pool.recycle(img);
        return Err(RenderError::Cancelled);
    }
    Ok(img)
}

/// Ambient occlusion: the fraction of a few points along each normal (at
/// 1, 2, 4 and 8 % of the model box's radius) that lie outside the solid,
/// weighted towards the near ones.
fn ambient_occlusion(
    ev: &mut BatchEval,
    caster: &ModelCaster,
    hits: &[Option<Hit>],
    ao: &mut [f32],
) {
    const DIST: [f64; 4] = [0.01, 0.02, 0.04, 0.08];
    const WEIGHT: [f32; 4] = [0.4, 0.3, 0.2, 0.1];
    let r = caster.bounds.radius();
    let (mut xs, mut ys, mut zs) = (Vec::new(), Vec::new(), Vec::new());
    let mut idx = Vec::new();
    for (i, h) in hits.iter().enumerate() {
        let Some(h) = h else { continue };
        let n = unit(h.normal).unwrap_or([0.0; 3]);
        for d in DIST {
            xs.push(h.position[0] + n[0] * d * r);
            ys.push(h.position[1] + n[1] * d * r);
            zs.push(h.position[2] + n[2] * d * r);
        }
        idx.push(i);
    }
    if idx.is_empty() {
        return;
    }
    let mut vals = vec![0.0; xs.len()];
    ev.eval(&xs, &ys, &zs, &caster.inputs, &mut vals);
    caster
        .stats
        .point_evals
        .fetch_add(xs.len() as u64, Ordering::Relaxed);
    for (j, &i) in idx.iter().enumerate() {
        let mut occ = 0.0;
        for k in 0..4 {
            if vals[j * 4 + k] >= 0.0 {
                occ += WEIGHT[k];
            }
        }
        ao[i] = 1.0 - occ;
    }
}
