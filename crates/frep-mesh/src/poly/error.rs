//! How far a mesh is from a model's surface: a symmetric Hausdorff estimate.
//!
//! - **mesh → surface**: sample points are every vertex, and every triangle's centroid and
//!   edge midpoints.
//!   - Each is projected onto the surface `f = 0` by Newton steps along `∇f`
//!     (`p ← p − f ∇f / |∇f|²`, each step at most one cell).
//!   - The distance travelled is the point's error. Unlike the first-order `|f| / |∇f|`, this
//!     stays right away from the surface for fields that are not distances (R-functions,
//!     squared distances).
//!   - A Newton path follows `∇f`. Where the gradient is small (a saddle of an R-function's
//!     field), that can lead far from the nearest surface point.
//!   - So the distance to the nearest sign change along a fan of 256 rays, also an upper
//!     bound, is taken where it is smaller. It is checked for the points that decide the
//!     maximum.
//! - **surface → mesh**: dense surface points, each measured to its nearest triangle (a
//!   uniform grid of triangles). The points are the edge crossings of the lattice at twice
//!   the resolution: the vertices of [`Method::Watertight`] at `depth + 1`, projected the
//!   same way.
//!
//! Points within `margin` of the box faces are left out. Caps lie on the box, and other
//! meshers leave the mesh open there.

use frep_core::eval::grad::GradEval;
use frep_core::{Inputs, Model, Tape};

use super::{par_map, polygonize, CancelToken, MeshSettings, Method, Progress, Resolution};
use crate::Mesh;

/// Both directions of [`surface_error`], in model units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceError {
    /// Largest distance from a mesh sample point to the surface.
    pub mesh_to_surface: f64,
    /// Largest distance from a dense surface point to the mesh.
    pub surface_to_mesh: f64,
    /// Where `mesh_to_surface` was measured (a mesh sample point).
    pub worst_mesh_point: [f64; 3],
    /// Where `surface_to_mesh` was measured (a surface point).
    pub worst_surface_point: [f64; 3],
}

impl SurfaceError {
    /// The symmetric estimate: the larger direction.
    pub fn hausdorff(&self) -> f64 {
        self.mesh_to_surface.max(self.surface_to_mesh)
    }
}

/// Newton projection of `p` onto `f = 0`: (surface point, distance), `None` when it does not
/// converge (no gradient, NaN, or still more than `tol` off after the steps).
fn project(ge: &mut GradEval, inputs: &Inputs, p: [f64; 3], cell: f64) -> Option<([f64; 3], f64)> {
    let mut x = p;
    let tol = 1e-6 * cell;
    for _ in 0..24 {
        let g = ge.eval(x[0], x[1], x[2], inputs);
        let len2 = g.dx * g.dx + g.dy * g.dy + g.dz * g.dz;
        if !(len2 > 0.0 && len2.is_finite() && g.v.is_finite()) {
            return None;
        }
        let len = len2.sqrt();
        if g.v.abs() / len < tol {
            let d = ((0..3).map(|k| (x[k] - p[k]).powi(2)).sum::<f64>()).sqrt();
            return Some((x, d));
        }
        let mut s = g.v / len2;
        if (s * len).abs() > cell {
            s = s.signum() * cell / len;
        }
        x = [x[0] - s * g.dx, x[1] - s * g.dy, x[2] - s * g.dz];
    }
    None
}

fn first_order(ge: &mut GradEval, inputs: &Inputs, p: [f64; 3]) -> f64 {
    let g = ge.eval(p[0], p[1], p[2], inputs);
    let len = (g.dx * g.dx + g.dy * g.dy + g.dz * g.dz).sqrt();
    if len > 0.0 && g.v.is_finite() {
        g.v.abs() / len
    } else {
        0.0
    }
}

fn farther(a: (f64, [f64; 3]), b: (f64, [f64; 3])) -> (f64, [f64; 3]) {
    if b.0 > a.0 {
        b
    } else {
        a
    }
}

/// Ray directions of [`ray_distance`]: a Fibonacci sphere.
const RAYS: usize = 256;
/// Samples per cell along each ray of [`ray_distance`].
const RAY_STEPS_PER_CELL: f64 = 16.0;

/// The distance from `p` to the nearest sign change of `f` along [`RAYS`] directions, searched
/// up to `limit` (then bisected). Like the Newton projection's, it is an upper bound on the
/// distance to the surface. But it is not led astray where the gradient is small or turns. A
/// Newton path follows `∇f`, which near a saddle of an R-function's field points far from the
/// nearest surface point. `limit` when no ray changes sign before it.
fn ray_distance(ge: &mut GradEval, inputs: &Inputs, p: [f64; 3], limit: f64, cell: f64) -> f64 {
    let f0 = ge.eval(p[0], p[1], p[2], inputs).v;
    if !f0.is_finite() || f0 == 0.0 {
        return if f0 == 0.0 { 0.0 } else { limit };
    }
    let step = cell / RAY_STEPS_PER_CELL;
    let steps = (limit / step).ceil() as usize;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut best = limit;
    for i in 0..RAYS {
        let z = 1.0 - 2.0 * (i as f64 + 0.5) / RAYS as f64;
        let r = (1.0 - z * z).sqrt();
        let (s, c) = (golden * i as f64).sin_cos();
        let dir = [r * c, r * s, z];
        let at = |t: f64| [0, 1, 2].map(|k| p[k] + t * dir[k]);
        let mut t0 = 0.0;
        for k in 1..=steps {
            let t1 = (k as f64 * step).min(best);
            if t1 <= t0 {
                break;
            }
            let q = at(t1);
            let v = ge.eval(q[0], q[1], q[2], inputs).v;
            if !v.is_finite() {
                // NaN or infinity: no zero can be told from a pole here.
                break;
            }
            if (v >= 0.0) != (f0 >= 0.0) {
                // A crossing in (t0, t1]: bisect.
                let (mut a, mut b) = (t0, t1);
                for _ in 0..30 {
                    let m = 0.5 * (a + b);
                    let q = at(m);
                    let v = ge.eval(q[0], q[1], q[2], inputs).v;
                    if v.is_finite() && (v >= 0.0) == (f0 >= 0.0) {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                best = best.min(b);
                break;
            }
            t0 = t1;
        }
    }
    best
}

/// Largest distance to the surface over `pts`, and where.
/// - Each point's distance is its Newton projection distance, or the first-order
///   `|f| / |∇f|` where that does not converge.
/// - For the points that could be the largest, it is lowered to the nearest sign change along
///   a fan of rays ([`ray_distance`], also an upper bound).
/// - Those points are taken in decreasing order of the projection distance, until it falls
///   below the largest refined distance.
fn max_projection(tape: &Tape, inputs: &Inputs, pts: &[[f64; 3]], cell: f64) -> (f64, [f64; 3]) {
    let chunks: Vec<&[[f64; 3]]> = pts.chunks(4096).collect();
    let mut dist: Vec<(f64, [f64; 3])> = par_map(&chunks, |c| {
        let mut ge = GradEval::new(tape);
        c.iter()
            .map(|&p| match project(&mut ge, inputs, p, cell) {
                Some((_, d)) => (d, p),
                None => (first_order(&mut ge, inputs, p), p),
            })
            .collect::<Vec<_>>()
    })
    .into_iter()
    .flatten()
    .collect();
    dist.sort_by(|a, b| b.0.total_cmp(&a.0));
    let mut best = (0.0f64, [0.0; 3]);
    // A point whose projection distance is at most the largest refined one cannot be the
    // maximum (refining only lowers it): refined in parallel batches until then.
    for batch in dist.chunks(64) {
        let todo: Vec<&[(f64, [f64; 3])]> = batch
            .iter()
            .position(|x| x.0 <= best.0)
            .map_or(batch, |n| &batch[..n])
            .chunks(8)
            .collect();
        if todo.is_empty() {
            break;
        }
        best = par_map(&todo, |c| {
            let mut ge = GradEval::new(tape);
            c.iter()
                .map(|&(d, p)| (ray_distance(&mut ge, inputs, p, d, cell), p))
                .fold((0.0f64, [0.0; 3]), farther)
        })
        .into_iter()
        .fold(best, farther);
    }
    best
}

fn closest_on_triangle(p: [f64; 3], a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [f64; 3] {
    let sub = |u: [f64; 3], v: [f64; 3]| [u[0] - v[0], u[1] - v[1], u[2] - v[2]];
    let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let at = |o: [f64; 3], d: [f64; 3], t: f64| [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
    // Ericson, Real-Time Collision Detection, 5.1.5.
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return at(a, ab, d1 / (d1 - d3));
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return at(a, ac, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return at(b, sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    if !denom.is_finite() {
        return a;
    }
    let (v, w) = (vb * denom, vc * denom);
    [0, 1, 2].map(|k| a[k] + ab[k] * v + ac[k] * w)
}

/// Triangles binned in a uniform grid of `cell`-sized bins.
struct TriGrid<'a> {
    mesh: &'a Mesh,
    lo: [f64; 3],
    cell: f64,
    n: [i64; 3],
    start: Vec<u32>,
    items: Vec<u32>,
}

impl<'a> TriGrid<'a> {
    fn new(mesh: &'a Mesh, cell: f64) -> Option<TriGrid<'a>> {
        let (lo, hi) = mesh.bounds()?;
        let lo = lo.map(|c| c as f64 - cell);
        let n = [0, 1, 2].map(|k| (((hi[k] as f64 + cell - lo[k]) / cell).ceil() as i64).max(1));
        let total = (n[0] * n[1] * n[2]) as usize;
        if total > 1 << 28 {
            return None;
        }
        let mut g = TriGrid {
            mesh,
            lo,
            cell,
            n,
            start: vec![0; total + 1],
            items: Vec::new(),
        };
        for pass in 0..2 {
            for (t, tri) in mesh.triangles.iter().enumerate() {
                let ps = tri.map(|i| mesh.positions[i as usize]);
                let b0 = [0, 1, 2]
                    .map(|k| g.bin(k, ps.iter().map(|p| p[k]).fold(f32::MAX, f32::min) as f64));
                let b1 = [0, 1, 2]
                    .map(|k| g.bin(k, ps.iter().map(|p| p[k]).fold(f32::MIN, f32::max) as f64));
                for z in b0[2]..=b1[2] {
                    for y in b0[1]..=b1[1] {
                        for x in b0[0]..=b1[0] {
                            let id = g.id([x, y, z]);
                            if pass == 0 {
                                g.start[id + 1] += 1;
                            } else {
                                let s = g.start[id] as usize;
                                g.items[s] = t as u32;
                                g.start[id] += 1;
                            }
                        }
                    }
                }
            }
            if pass == 0 {
                for i in 0..total {
                    g.start[i + 1] += g.start[i];
                }
                g.items = vec![0; g.start[total] as usize];
            } else {
                // `start[id]` now holds the end of bin `id`: shift back.
                for i in (1..=total).rev() {
                    g.start[i] = g.start[i - 1];
                }
                g.start[0] = 0;
            }
        }
        Some(g)
    }

    fn bin(&self, k: usize, c: f64) -> i64 {
        (((c - self.lo[k]) / self.cell).floor() as i64).clamp(0, self.n[k] - 1)
    }

    fn id(&self, b: [i64; 3]) -> usize {
        (b[0] + self.n[0] * (b[1] + self.n[1] * b[2])) as usize
    }

    /// Distance to the nearest triangle, at most `cap` cells (searched ring by ring).
    fn distance(&self, p: [f64; 3], cap: i64) -> f64 {
        let c = [0, 1, 2].map(|k| ((p[k] - self.lo[k]) / self.cell).floor() as i64);
        let mut best = f64::MAX;
        for r in 0..=cap {
            // Rings 0..r-1 are searched: a triangle not yet seen is more than r - 1 cells
            // away.
            if best <= (r - 1) as f64 * self.cell {
                break;
            }
            for z in c[2] - r..=c[2] + r {
                for y in c[1] - r..=c[1] + r {
                    for x in c[0] - r..=c[0] + r {
                        let on_shell = [x - c[0], y - c[1], z - c[2]].iter().any(|d| d.abs() == r);
                        if !on_shell || x < 0 || y < 0 || z < 0 {
                            continue;
                        }
                        if x >= self.n[0] || y >= self.n[1] || z >= self.n[2] {
                            continue;
                        }
                        let id = self.id([x, y, z]);
                        for &t in &self.items[self.start[id] as usize..self.start[id + 1] as usize]
                        {
                            let tri = self.mesh.triangles[t as usize];
                            let v =
                                tri.map(|i| crate::mesh::to_f64(self.mesh.positions[i as usize]));
                            let q = closest_on_triangle(p, v[0], v[1], v[2]);
                            let d = ((0..3).map(|k| (q[k] - p[k]).powi(2)).sum::<f64>()).sqrt();
                            best = best.min(d);
                        }
                    }
                }
            }
        }
        best.min(cap as f64 * self.cell)
    }
}

/// The dense surface points of a model in a box (computed once, measured against any number
/// of meshes): see the module docs.
pub struct SurfaceSamples {
    tape: Tape,
    inputs: Inputs,
    bounds: [f64; 6],
    margin: f64,
    /// Cell size of the lattice at `depth`.
    pub cell: f64,
    /// Projected surface points (the box margin left out).
    pub points: Vec<[f64; 3]>,
}

impl SurfaceSamples {
    /// Samples `model`'s surface in `bounds` for meshes made at `depth`; points within
    /// `margin` of the box faces are left out.
    pub fn new(
        model: &Model,
        inputs: &Inputs,
        bounds: [f64; 6],
        depth: u8,
        margin: f64,
    ) -> SurfaceSamples {
        let ext = (0..3)
            .map(|k| bounds[k + 3] - bounds[k])
            .fold(0.0f64, f64::max);
        let cell = ext / (1u64 << depth) as f64;
        let tape = model.tape();
        let settings = MeshSettings {
            bounds,
            resolution: Resolution::Depth(depth + 1),
            method: Method::Watertight,
            colors: false,
            inputs: inputs.clone(),
            ..Default::default()
        };
        let dense = polygonize(model, &settings, &Progress::new(), &CancelToken::new())
            .map(|m| m.positions)
            .unwrap_or_default();
        let mut out = SurfaceSamples {
            tape,
            inputs: inputs.clone(),
            bounds,
            margin,
            cell,
            points: Vec::new(),
        };
        let dense: Vec<[f64; 3]> = dense
            .iter()
            .map(|&p| crate::mesh::to_f64(p))
            .filter(|&p| out.keep(p))
            .collect();
        let chunks: Vec<&[[f64; 3]]> = dense.chunks(4096).collect();
        let (tape, inputs) = (&out.tape, &out.inputs);
        let pts: Vec<Vec<[f64; 3]>> = par_map(&chunks, |c| {
            let mut ge = GradEval::new(tape);
            c.iter()
                .filter_map(|&p| project(&mut ge, inputs, p, cell).map(|(q, _)| q))
                .collect()
        });
        out.points = pts.into_iter().flatten().filter(|&p| out.keep(p)).collect();
        out
    }

    fn keep(&self, p: [f64; 3]) -> bool {
        let (b, m) = (self.bounds, self.margin);
        (0..3).all(|k| p[k] > b[k] + m && p[k] < b[k + 3] - m)
    }

    /// Both directions for `mesh`.
    pub fn error(&self, mesh: &Mesh) -> SurfaceError {
        let cell = self.cell;
        let mut pts: Vec<[f64; 3]> = mesh
            .positions
            .iter()
            .map(|&p| crate::mesh::to_f64(p))
            .collect();
        for t in &mesh.triangles {
            let v = t.map(|i| crate::mesh::to_f64(mesh.positions[i as usize]));
            pts.push([0, 1, 2].map(|k| (v[0][k] + v[1][k] + v[2][k]) / 3.0));
            for j in 0..3 {
                let (a, b) = (v[j], v[(j + 1) % 3]);
                pts.push([0, 1, 2].map(|k| 0.5 * (a[k] + b[k])));
            }
        }
        pts.retain(|&p| self.keep(p));
        let (mesh_to_surface, worst_mesh_point) =
            max_projection(&self.tape, &self.inputs, &pts, cell);
        drop(pts);
        let (surface_to_mesh, worst_surface_point) = match TriGrid::new(mesh, cell) {
            None if self.points.is_empty() => (0.0, [0.0; 3]),
            None => (4.0 * cell, self.points[0]),
            Some(grid) => {
                let chunks: Vec<&[[f64; 3]]> = self.points.chunks(4096).collect();
                par_map(&chunks, |c| {
                    c.iter()
                        .map(|&q| (grid.distance(q, 4), q))
                        .fold((0.0f64, [0.0; 3]), farther)
                })
                .into_iter()
                .fold((0.0, [0.0; 3]), farther)
            }
        };
        SurfaceError {
            mesh_to_surface,
            surface_to_mesh,
            worst_mesh_point,
            worst_surface_point,
        }
    }
}

/// The symmetric Hausdorff estimate of `mesh` against `model`'s surface in `bounds`, the
/// lattice of `depth` (see the module docs); points within `margin` of the box faces are left
/// out. `surface_to_mesh` is capped at 4 cells.
pub fn surface_error(
    model: &Model,
    inputs: &Inputs,
    mesh: &Mesh,
    bounds: [f64; 6],
    depth: u8,
    margin: f64,
) -> SurfaceError {
    SurfaceSamples::new(model, inputs, bounds, depth, margin).error(mesh)
}
