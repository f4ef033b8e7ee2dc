//! An analytic scene (ray–sphere intersection) for tests, demos and
//! benchmarks of everything around the ray caster, before the real caster
//! exists.

use crate::camera::{dot, normalize, sub, Camera, Ray};
use crate::image::{Hit, HitBuffer};
use crate::tiles::{Tile, TileCaster};

/// The first hit of `ray` with the sphere `center`, `radius`, if any.
pub fn ray_sphere(
    ray: &Ray,
    center: [f64; 3],
    radius: f64,
    color: Option<[f32; 3]>,
) -> Option<Hit> {
    let oc = sub(ray.origin, center);
    let b = dot(oc, ray.dir);
    let c = dot(oc, oc) - radius * radius;
    let disc = b * b - c;
    if disc < 0.0 {
        return None;
    }
    let s = disc.sqrt();
    let t = if -b - s > 0.0 { -b - s } else { -b + s };
    if t <= 0.0 {
        return None;
    }
    let position = ray.at(t);
    Some(Hit {
        t,
        position,
        normal: normalize(sub(position, center)),
        color,
    })
}

/// A [`HitBuffer`] of one sphere seen by `camera`, pixel by pixel.
pub fn sphere_hits(
    camera: &Camera,
    width: u32,
    height: u32,
    center: [f64; 3],
    radius: f64,
    color: Option<[f32; 3]>,
) -> HitBuffer {
    let mut buf = HitBuffer::new(*camera, width, height);
    for y in 0..height {
        for x in 0..width {
            let r = camera.ray(x, y, width, height);
            buf.set(x, y, ray_sphere(&r, center, radius, color));
        }
    }
    buf
}

/// A [`TileCaster`] that sees one sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereCaster {
    /// Centre of the sphere.
    pub center: [f64; 3],
    /// Radius of the sphere.
    pub radius: f64,
    /// Attribute colour of every hit.
    pub color: Option<[f32; 3]>,
}

impl TileCaster for SphereCaster {
    fn cast_tile(&self, camera: &Camera, tile: &Tile, out: &mut [Option<Hit>]) {
        let mut i = 0;
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                let r = camera.ray(x, y, tile.width, tile.height);
                out[i] = ray_sphere(&r, self.center, self.radius, self.color);
                i += 1;
            }
        }
    }
}

/// A [`TileCaster`] that sees a set of spheres (closest hit wins).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spheres {
    /// The spheres.
    pub spheres: Vec<SphereCaster>,
}

impl Spheres {
    /// The benchmark model M2 of the notes: 100 spheres of radius 0.2 on a
    /// 5×5×4 lattice in [-1, 1]³, coloured by position.
    pub fn lattice_m2() -> Spheres {
        let mut spheres = Vec::new();
        for a in 0..5 {
            for b in 0..5 {
                for c in 0..4 {
                    let center = [
                        -0.72 + 0.36 * a as f64,
                        -0.72 + 0.36 * b as f64,
                        -0.54 + 0.36 * c as f64,
                    ];
                    let color = [a as f32 / 4.0, b as f32 / 4.0, 0.3 + c as f32 / 5.0];
                    spheres.push(SphereCaster {
                        center,
                        radius: 0.2,
                        color: Some(color),
                    });
                }
            }
        }
        Spheres { spheres }
    }

    /// The closest hit of `ray`.
    pub fn hit(&self, ray: &Ray) -> Option<Hit> {
        self.spheres
            .iter()
            .filter_map(|s| ray_sphere(ray, s.center, s.radius, s.color))
            .min_by(|a, b| a.t.total_cmp(&b.t))
    }
}

impl TileCaster for Spheres {
    fn cast_tile(&self, camera: &Camera, tile: &Tile, out: &mut [Option<Hit>]) {
        let mut i = 0;
        for y in tile.y0..tile.y1 {
            for x in tile.x0..tile.x1 {
                out[i] = self.hit(&camera.ray(x, y, tile.width, tile.height));
                i += 1;
            }
        }
    }
}
