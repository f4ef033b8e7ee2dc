//! The indexed triangle mesh and its geometric helpers.

use std::collections::HashMap;

/// An indexed triangle mesh with optional per-vertex normals and colours.
///
/// Triangles are counter-clockwise when seen from outside (the glTF and STL convention), so
/// that [`Mesh::signed_volume`] is positive for a closed mesh with outward normals.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<[f32; 3]>,
    /// Unit vertex normals: empty, or one per vertex.
    pub normals: Vec<[f32; 3]>,
    /// Vertex colours, RGB in `[0, 1]`: empty, or one per vertex.
    pub colors: Vec<[f32; 3]>,
    /// Triangles as indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
}

/// Why a [`Mesh`] is malformed (see [`Mesh::validate`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum InvalidMesh {
    /// `normals` is neither empty nor one per vertex.
    #[error("{normals} normals for {vertices} vertices")]
    NormalCount {
        /// Number of normals.
        normals: usize,
        /// Number of vertices.
        vertices: usize,
    },
    /// `colors` is neither empty nor one per vertex.
    #[error("{colors} colours for {vertices} vertices")]
    ColorCount {
        /// Number of colours.
        colors: usize,
        /// Number of vertices.
        vertices: usize,
    },
    /// A triangle refers to a vertex that does not exist.
    #[error("triangle {triangle} refers to vertex {index} of {vertices}")]
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The offending index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A position is NaN or infinite.
    #[error("vertex {0} has a non-finite coordinate")]
    NonFinite(usize),
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn to_f64(p: [f32; 3]) -> [f64; 3] {
    [p[0] as f64, p[1] as f64, p[2] as f64]
}

impl Mesh {
    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Checks that attribute lengths match and that every index and position is valid.
    pub fn validate(&self) -> Result<(), InvalidMesh> {
        let vertices = self.positions.len();
        if !self.normals.is_empty() && self.normals.len() != vertices {
            return Err(InvalidMesh::NormalCount {
                normals: self.normals.len(),
                vertices,
            });
        }
        if !self.colors.is_empty() && self.colors.len() != vertices {
            return Err(InvalidMesh::ColorCount {
                colors: self.colors.len(),
                vertices,
            });
        }
        if let Some(i) = self
            .positions
            .iter()
            .position(|p| p.iter().any(|c| !c.is_finite()))
        {
            return Err(InvalidMesh::NonFinite(i));
        }
        for (triangle, t) in self.triangles.iter().enumerate() {
            if let Some(&index) = t.iter().find(|&&i| i as usize >= vertices) {
                return Err(InvalidMesh::IndexOutOfRange {
                    triangle,
                    index,
                    vertices,
                });
            }
        }
        Ok(())
    }

    /// The axis-aligned bounding box `(min, max)` of all positions, `None` when there are none.
    pub fn bounds(&self) -> Option<([f32; 3], [f32; 3])> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(mut lo, mut hi), p| {
                    for k in 0..3 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                    (lo, hi)
                }),
        )
    }

    /// The unnormalized normal of triangle `t` (twice its area times its unit normal).
    pub(crate) fn triangle_cross(&self, t: [u32; 3]) -> [f64; 3] {
        let [a, b, c] = t.map(|i| to_f64(self.positions[i as usize]));
        cross(sub(b, a), sub(c, a))
    }

    /// Replaces `normals` by area-weighted averages of the incident triangles' normals.
    ///
    /// A vertex whose incident triangles cancel out (or that has none) gets `[0, 0, 1]`, so that
    /// every normal is a unit vector that quantizers can encode.
    pub fn compute_normals(&mut self) {
        let mut acc = vec![[0.0f64; 3]; self.positions.len()];
        for &t in &self.triangles {
            let n = self.triangle_cross(t);
            for i in t {
                let a = &mut acc[i as usize];
                for k in 0..3 {
                    a[k] += n[k];
                }
            }
        }
        self.normals = acc
            .into_iter()
            .map(|n| {
                let len = dot(n, n).sqrt();
                if len > 0.0 && len.is_finite() {
                    n.map(|c| (c / len) as f32)
                } else {
                    [0.0, 0.0, 1.0]
                }
            })
            .collect();
    }

    /// Merges vertices closer than `eps` (Euclidean distance) into the first of them, remaps
    /// the triangles and drops triangles that lose a corner; `eps <= 0` merges bit-identical
    /// positions only. The merged vertex keeps its first occurrence's normal and colour.
    /// Returns the number of vertices removed.
    pub fn merge_duplicate_vertices(&mut self, eps: f32) -> usize {
        let n = self.positions.len();
        let mut remap = vec![0u32; n];
        let mut kept: Vec<usize> = Vec::with_capacity(n);
        if eps <= 0.0 {
            let mut seen: HashMap<[u32; 3], u32> = HashMap::with_capacity(n);
            for (i, p) in self.positions.iter().enumerate() {
                // +0.0 and -0.0 are the same point.
                let key = p.map(|c| (c + 0.0).to_bits());
                remap[i] = *seen.entry(key).or_insert_with(|| {
                    kept.push(i);
                    (kept.len() - 1) as u32
                });
            }
        } else {
            let cell = |p: [f32; 3]| p.map(|c| (c / eps).floor() as i64);
            let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::with_capacity(n);
            for (i, &p) in self.positions.iter().enumerate() {
                let c = cell(p);
                let mut found = None;
                'search: for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let key = [c[0] + dx, c[1] + dy, c[2] + dz];
                            for &r in grid.get(&key).into_iter().flatten() {
                                let q = self.positions[kept[r as usize]];
                                let d = sub(to_f64(p), to_f64(q));
                                if dot(d, d) <= (eps as f64) * (eps as f64) {
                                    found = Some(r);
                                    break 'search;
                                }
                            }
                        }
                    }
                }
                remap[i] = found.unwrap_or_else(|| {
                    kept.push(i);
                    let r = (kept.len() - 1) as u32;
                    grid.entry(c).or_default().push(r);
                    r
                });
            }
        }
        let removed = n - kept.len();
        let pick = |v: &[[f32; 3]]| -> Vec<[f32; 3]> {
            if v.is_empty() {
                Vec::new()
            } else {
                kept.iter().map(|&i| v[i]).collect()
            }
        };
        self.positions = pick(&self.positions);
        self.normals = pick(&self.normals);
        self.colors = pick(&self.colors);
        self.triangles = self
            .triangles
            .iter()
            .map(|t| t.map(|i| remap[i as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
            .collect();
        removed
    }

    /// The signed volume enclosed by the triangles; positive when they are counter-clockwise
    /// seen from outside (normals pointing outward). Meaningful for closed meshes.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| to_f64(self.positions[i as usize]));
                dot(a, cross(b, c))
            })
            .sum::<f64>()
            / 6.0
    }

    /// The total area of the triangles.
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|&t| {
                let n = self.triangle_cross(t);
                dot(n, n).sqrt() / 2.0
            })
            .sum()
    }

    /// The largest `|f(p)|` over all vertices and triangle centroids, where `f` is a signed
    /// distance function: a one-sided (mesh to surface) Hausdorff-style distance estimate.
    /// Returns 0 for an empty mesh and NaN when `f` returns NaN.
    pub fn max_distance_to(&self, f: impl Fn([f64; 3]) -> f64) -> f64 {
        let vertices = self.positions.iter().map(|&p| to_f64(p));
        let centroids = self.triangles.iter().map(|t| {
            let [a, b, c] = t.map(|i| to_f64(self.positions[i as usize]));
            [0, 1, 2].map(|k| (a[k] + b[k] + c[k]) / 3.0)
        });
        vertices
            .chain(centroids)
            .map(|p| f(p).abs())
            .fold(0.0, |m: f64, d| {
                if d.is_nan() || m.is_nan() {
                    f64::NAN
                } else {
                    m.max(d)
                }
            })
    }
}
