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
//! - perspective (`fov` = Some(φ) degrees, clamped to 0.001..179): φ spans
//!   the image's **shorter** side. three.js's `PerspectiveCamera.fov` is
//!   vertical: use φ when width ≥ height, else `2·atan(tan(φ/2)·h/w)`. Eye
//!   `t + b · d` with `d = r / sin(φ/2) / zoom`. At zoom 1 the bounding
//!   sphere exactly fills the shorter side;
//! - orthographic (`fov` None): half the extent seen across the shorter
//!   side is `r / zoom`. In three.js's `OrthographicCamera`: `top = r / zoom`,
//!   `right = top · w / h` when width ≥ height, else `right = r / zoom`,
//!   `top = right · h / w`. Rays start on the plane through
//!   `t + b · (2r + |pan|)` facing `−b`. That is in front of the whole box,
//!   wherever it is panned to.
//!
//! Pixel `(px, py)` has its centre at `(px + 0.5, py + 0.5)`, y down the
//! image, as in frep-render's cameras.
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

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-9)
    }

    #[test]
    fn follows_the_documented_formulas() {
        let bounds = Aabb::new([-1.0, -2.0, -2.0], [3.0, 2.0, 2.0]);
        let r = bounds.radius();
        let view = CameraView {
            yaw: 0.0,
            pitch: 0.0,
            fov: Some(60.0),
            zoom: 1.0,
            pan: [0.0; 3],
        };
        // Zoom 1, no pan: frep-render's orbit, the CLI's camera.
        let cam = camera(&view, &bounds);
        assert_eq!(cam, Camera::orbit(&bounds, 0.0, 0.0, Some(60.0)));
        // Yaw 0, pitch 0: the eye on −y, looking along +y, z up, x right.
        assert!(close(cam.eye, [1.0, -r / 0.5, 0.0]));
        assert!(close(cam.up, [0.0, 0.0, 1.0]) && close(cam.right, [1.0, 0.0, 0.0]));
        // Zoom 2 halves the distance; pan moves eye and target together.
        let cam = camera(
            &CameraView {
                zoom: 2.0,
                pan: [0.0, 0.0, 1.0],
                ..view.clone()
            },
            &bounds,
        );
        assert!(close(cam.target, [1.0, 0.0, 1.0]));
        assert!(close(cam.eye, [1.0, -r, 1.0]));
        // Yaw 90: the eye on +x, looking along −x.
        let cam = camera(
            &CameraView {
                yaw: 90.0,
                ..view.clone()
            },
            &bounds,
        );
        assert!(close(cam.forward, [-1.0, 0.0, 0.0]));
        // Orthographic: half extent r / zoom, eye 2r + |pan| back.
        let cam = camera(
            &CameraView {
                fov: None,
                zoom: 4.0,
                pan: [3.0, 0.0, 4.0],
                ..view
            },
            &bounds,
        );
        assert_eq!(
            cam.projection,
            Projection::Orthographic {
                half_extent: r / 4.0
            }
        );
        assert!(close(cam.eye, [4.0, -(2.0 * r + 5.0), 4.0]));
    }
}
