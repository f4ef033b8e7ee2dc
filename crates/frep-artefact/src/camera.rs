//! The one camera of every mode: [`CameraView`] (yaw, pitch, fov or
//! orthographic, zoom, pan) as the ray caster's [`Camera`]. The browser's
//! three.js views follow the same formulas, so switching modes keeps the
//! view.
//!
//! With the model box's centre `c`, its bounding-sphere radius
//! `r = |max − min| / 2` (at least `1e-12`), yaw `ψ` and pitch `θ` in
//! radians:
//!
//! - target `t = c + pan`;
//! - back (unit, target → eye) `b = (cos θ sin ψ, −cos θ cos ψ, sin θ)`;
//!   world z is up; yaw 0 looks along +y; pitch 90° looks straight down;
//! - right `R = (cos ψ, sin ψ, 0)`; up `U = normalize(R × (−b))` (three.js:
//!   `camera.up = U`, then `lookAt(t)`), defined even at pitch ±90°;
//! - perspective (`fov` = Some(φ) degrees, clamped to 0.001..179, across the
//!   **shorter** image side: three.js's vertical `fov` when the image is
//!   wider than tall, else `2·atan(tan(φ/2)·h/w)`... i.e. set its vertical fov
//!   from the shorter side): eye `t + b · d` with `d = r / sin(φ/2) / zoom`
//!   (at zoom 1 the bounding sphere exactly fills the shorter side);
//! - orthographic (`fov` None): half the extent seen across the shorter
//!   side is `r / zoom`; rays start on the plane through `t + b · (2r + |pan|)`
//!   facing `−b` (in front of the whole box wherever it is panned to).
//!
//! `zoom` must be positive and finite; anything else is taken as 1.

use frep_render::{Aabb, Camera, Projection};
use frep_wire::CameraView;

/// The ray caster's camera for `view` of a model boxed in `bounds`.
pub fn camera(view: &CameraView, bounds: &Aabb) -> Camera {
    let mut cam = Camera::orbit(bounds, view.yaw, view.pitch, view.fov);
    let zoom = if view.zoom.is_finite() && view.zoom > 0.0 {
        view.zoom
    } else {
        1.0
    };
    let pan = view.pan.map(|p| if p.is_finite() { p } else { 0.0 });
    let c = bounds.center();
    let r = bounds.radius().max(1e-12);
    let target = [c[0] + pan[0], c[1] + pan[1], c[2] + pan[2]];
    // Camera::orbit's forward is −back, unit length.
    let back = cam.forward.map(|f| -f);
    let distance = match view.fov {
        Some(fov) => {
            let half = (0.5 * fov.clamp(1e-3, 179.0)).to_radians();
            r / half.sin() / zoom
        }
        None => {
            cam.projection = Projection::Orthographic {
                half_extent: r / zoom,
            };
            let p = (pan[0] * pan[0] + pan[1] * pan[1] + pan[2] * pan[2]).sqrt();
            2.0 * r + p
        }
    };
    cam.target = target;
    cam.eye = std::array::from_fn(|k| target[k] + back[k] * distance);
    cam
}
