//! A look-at camera and its inverse view-projection matrix, the ray caster's
//! `u_inv_view_proj` uniform.

/// A camera looking from `eye` at `target`.
#[derive(Clone, Debug, PartialEq)]
pub struct Camera {
    /// The eye position.
    pub eye: [f64; 3],
    /// The point looked at.
    pub target: [f64; 3],
    /// The approximate up direction.
    pub up: [f64; 3],
    /// Vertical field of view in degrees (perspective).
    pub fov_y_deg: f64,
    /// `Some(h)`: orthographic projection showing `2h` vertically.
    pub ortho_half_height: Option<f64>,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: [f64; 3]) -> [f64; 3] {
    let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    if l > 0.0 {
        [a[0] / l, a[1] / l, a[2] / l]
    } else {
        a
    }
}

impl Camera {
    /// A perspective camera that frames the box `[lo, hi]` from a fixed
    /// oblique direction (y up).
    pub fn framing(lo: [f64; 3], hi: [f64; 3]) -> Camera {
        let c = [
            0.5 * (lo[0] + hi[0]),
            0.5 * (lo[1] + hi[1]),
            0.5 * (lo[2] + hi[2]),
        ];
        let r = 0.5 * (sub(hi, lo).iter().map(|v| v * v).sum::<f64>()).sqrt();
        let dir = normalize([0.6, 0.45, 1.0]);
        let fov: f64 = 40.0;
        let dist = r / (0.5 * fov.to_radians()).sin() * 1.05;
        Camera {
            eye: [
                c[0] + dir[0] * dist,
                c[1] + dir[1] * dist,
                c[2] + dir[2] * dist,
            ],
            target: c,
            up: [0.0, 1.0, 0.0],
            fov_y_deg: fov,
            ortho_half_height: None,
        }
    }

    /// The inverse of projection × view, column-major (as
    /// `gl.uniformMatrix4fv` takes it), for a viewport of this aspect
    /// (width / height). It maps normalized device coordinates to world
    /// space. The shader unprojects `z = -1`, the ray's origin on the near
    /// plane, and `z = 0` for its direction. The far point `z = 1` would
    /// lose all precision in f32 when far/near is large. The near plane is
    /// at a tenth of the eye–target distance, the far plane at ten times.
    pub fn inv_view_proj(&self, aspect: f64) -> [f32; 16] {
        let f = normalize(sub(self.target, self.eye));
        let dist = {
            let d = sub(self.target, self.eye);
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-9)
        };
        let s = normalize(cross(f, self.up));
        let u = cross(s, f);
        // Camera-to-world (inverse view), row-major.
        let vinv = [
            [s[0], u[0], -f[0], self.eye[0]],
            [s[1], u[1], -f[1], self.eye[1]],
            [s[2], u[2], -f[2], self.eye[2]],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let near = 0.1 * dist;
        let far = 10.0 * dist;
        let pinv = match self.ortho_half_height {
            Some(h) => {
                // Orthographic: the near plane sits well behind the eye.
                let (n, fa) = (-far, far);
                [
                    [aspect * h, 0.0, 0.0, 0.0],
                    [0.0, h, 0.0, 0.0],
                    [0.0, 0.0, -(fa - n) / 2.0, -(fa + n) / 2.0],
                    [0.0, 0.0, 0.0, 1.0],
                ]
            }
            None => {
                let t = 1.0 / (0.5 * self.fov_y_deg.to_radians()).tan();
                [
                    [aspect / t, 0.0, 0.0, 0.0],
                    [0.0, 1.0 / t, 0.0, 0.0],
                    [0.0, 0.0, 0.0, -1.0],
                    [
                        0.0,
                        0.0,
                        (near - far) / (2.0 * near * far),
                        (near + far) / (2.0 * near * far),
                    ],
                ]
            }
        };
        let mut out = [0f32; 16];
        for col in 0..4 {
            for row in 0..4 {
                let v: f64 = (0..4).map(|k| vinv[row][k] * pinv[k][col]).sum();
                out[col * 4 + row] = v as f32;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn apply(m: &[f32; 16], v: [f64; 4]) -> [f64; 3] {
        let mut r = [0.0; 4];
        for (row, r) in r.iter_mut().enumerate() {
            *r = (0..4).map(|c| m[c * 4 + row] as f64 * v[c]).sum();
        }
        [r[0] / r[3], r[1] / r[3], r[2] / r[3]]
    }

    #[test]
    fn centre_ray_hits_target() {
        for ortho in [None, Some(1.5)] {
            let cam = Camera {
                ortho_half_height: ortho,
                ..Camera::framing([-1.0; 3], [1.0; 3])
            };
            let m = cam.inv_view_proj(1.5);
            let a = apply(&m, [0.0, 0.0, -1.0, 1.0]);
            let b = apply(&m, [0.0, 0.0, 0.0, 1.0]);
            let d = normalize(sub(b, a));
            let f = normalize(sub(cam.target, cam.eye));
            for k in 0..3 {
                assert!((d[k] - f[k]).abs() < 1e-4, "{ortho:?} {d:?} {f:?}");
            }
            // The ray passes through the target.
            let to = sub(cam.target, a);
            let c = cross(to, d);
            assert!(c.iter().all(|v| v.abs() < 1e-3), "{c:?}");
        }
        // Perspective: the top edge of the screen is fov/2 above the axis.
        let cam = Camera::framing([-1.0; 3], [1.0; 3]);
        let m = cam.inv_view_proj(1.0);
        let a = apply(&m, [0.0, 1.0, -1.0, 1.0]);
        let b = apply(&m, [0.0, 1.0, 0.0, 1.0]);
        let d = normalize(sub(b, a));
        let f = normalize(sub(cam.target, cam.eye));
        let cosang: f64 = (0..3).map(|k| d[k] * f[k]).sum();
        assert!((cosang.acos().to_degrees() - 20.0).abs() < 1e-3);
    }
}
