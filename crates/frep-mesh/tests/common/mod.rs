//! Hand-made meshes and comparison helpers shared by the integration tests.
#![allow(dead_code)]

use std::collections::HashMap;

use frep_mesh::Mesh;

/// The unit cube [0, 1]³: 8 vertices, 12 outward (counter-clockwise) triangles.
pub fn cube() -> Mesh {
    cube_at([0.0; 3])
}

/// A unit cube with its minimum corner at `o`.
pub fn cube_at(o: [f32; 3]) -> Mesh {
    let positions = (0..8)
        .map(|i| {
            [
                o[0] + (i & 1) as f32,
                o[1] + ((i >> 1) & 1) as f32,
                o[2] + ((i >> 2) & 1) as f32,
            ]
        })
        .collect();
    // Each face as a quad (a, b, c, d) counter-clockwise from outside.
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let triangles = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    Mesh {
        positions,
        triangles,
        ..Mesh::default()
    }
}

/// Concatenates meshes (no merging).
pub fn concat(meshes: &[Mesh]) -> Mesh {
    let mut out = Mesh::default();
    for m in meshes {
        let base = out.positions.len() as u32;
        out.positions.extend(&m.positions);
        out.triangles
            .extend(m.triangles.iter().map(|t| t.map(|i| i + base)));
    }
    out
}

/// A torus around the z axis with radii `big` and `small`, `nu` × `nv` quads.
pub fn torus(big: f32, small: f32, nu: u32, nv: u32) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..nu {
        let u = i as f32 / nu as f32 * std::f32::consts::TAU;
        for j in 0..nv {
            let v = j as f32 / nv as f32 * std::f32::consts::TAU;
            let r = big + small * v.cos();
            m.positions
                .push([r * u.cos(), r * u.sin(), small * v.sin()]);
        }
    }
    let id = |i: u32, j: u32| (i % nu) * nv + (j % nv);
    for i in 0..nu {
        for j in 0..nv {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    m
}

/// A UV sphere of radius `r` with `lat` latitude bands and `lon` longitude segments:
/// `2 · lon · (lat − 1)` triangles, outward normals, and colours that vary smoothly.
pub fn uv_sphere(r: f32, lat: u32, lon: u32) -> Mesh {
    let mut m = Mesh::default();
    m.positions.push([0.0, 0.0, r]);
    for i in 1..lat {
        let theta = i as f32 / lat as f32 * std::f32::consts::PI;
        for j in 0..lon {
            let phi = j as f32 / lon as f32 * std::f32::consts::TAU;
            m.positions.push([
                r * theta.sin() * phi.cos(),
                r * theta.sin() * phi.sin(),
                r * theta.cos(),
            ]);
        }
    }
    m.positions.push([0.0, 0.0, -r]);
    let south = m.positions.len() as u32 - 1;
    let ring = |i: u32, j: u32| 1 + (i - 1) * lon + j % lon;
    for j in 0..lon {
        m.triangles.push([0, ring(1, j), ring(1, j + 1)]);
        m.triangles
            .push([south, ring(lat - 1, j + 1), ring(lat - 1, j)]);
    }
    for i in 1..lat - 1 {
        for j in 0..lon {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i + 1, j),
                ring(i + 1, j + 1),
                ring(i, j + 1),
            );
            m.triangles.push([a, b, c]);
            m.triangles.push([a, c, d]);
        }
    }
    m.colors = m
        .positions
        .iter()
        .map(|p| [0, 1, 2].map(|k| 0.5 + 0.5 * p[k] / r))
        .collect();
    m.compute_normals();
    m
}

pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// Tolerances for [`assert_same`].
#[derive(Clone, Copy)]
pub struct Tol {
    /// Largest distance between matching positions.
    pub position: f32,
    /// Smallest dot product between matching normals; `None` when normals are not kept.
    pub normal_dot: Option<f32>,
    /// Largest per-channel colour difference; `None` when colours are not kept.
    pub color: Option<f32>,
    /// Compare colours in linear space (glTF stores linear colours).
    pub linear_color: bool,
}

/// Asserts that `b` is `a` up to vertex and triangle order: each vertex of `b` matches one of
/// `a` within the tolerances, one to one, and the triangles agree as oriented index cycles.
pub fn assert_same(a: &Mesh, b: &Mesh, tol: Tol) {
    assert_eq!(a.positions.len(), b.positions.len(), "vertex count");
    assert_eq!(a.triangles.len(), b.triangles.len(), "triangle count");
    let cell = (2.0 * tol.position).max(1e-6);
    let key = |p: [f32; 3]| p.map(|c| (c / cell).floor() as i64);
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, &p) in a.positions.iter().enumerate() {
        grid.entry(key(p)).or_default().push(i);
    }
    let dist = |p: [f32; 3], q: [f32; 3]| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f32>().sqrt();
    let mut map = vec![usize::MAX; b.positions.len()];
    let mut taken = vec![false; a.positions.len()];
    for (i, &p) in b.positions.iter().enumerate() {
        let c = key(p);
        let mut best: Option<(f32, usize)> = None;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &j in grid
                        .get(&[c[0] + dx, c[1] + dy, c[2] + dz])
                        .into_iter()
                        .flatten()
                    {
                        let d = dist(p, a.positions[j]);
                        if d <= tol.position && best.is_none_or(|(bd, _)| d < bd) {
                            best = Some((d, j));
                        }
                    }
                }
            }
        }
        let (_, j) = best
            .unwrap_or_else(|| panic!("vertex {i} at {p:?} has no match within {}", tol.position));
        assert!(!taken[j], "two vertices match vertex {j}");
        taken[j] = true;
        map[i] = j;
    }
    let canon = |t: [u32; 3]| {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap();
        [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
    };
    let mut ta: Vec<[u32; 3]> = a.triangles.iter().map(|&t| canon(t)).collect();
    let mut tb: Vec<[u32; 3]> = b
        .triangles
        .iter()
        .map(|t| canon(t.map(|i| map[i as usize] as u32)))
        .collect();
    ta.sort_unstable();
    tb.sort_unstable();
    assert!(ta == tb, "connectivity differs");
    if let Some(min_dot) = tol.normal_dot {
        assert_eq!(b.normals.len(), b.positions.len(), "normals missing");
        for (i, n) in b.normals.iter().enumerate() {
            let m = a.normals[map[i]];
            let d: f32 = (0..3).map(|k| n[k] * m[k]).sum();
            assert!(d >= min_dot, "normal {i}: {n:?} vs {m:?}");
        }
    }
    if let Some(max) = tol.color {
        assert_eq!(b.colors.len(), b.positions.len(), "colours missing");
        for (i, c) in b.colors.iter().enumerate() {
            let o = a.colors[map[i]];
            for k in 0..3 {
                let (x, y) = if tol.linear_color {
                    (srgb_to_linear(c[k]), srgb_to_linear(o[k]))
                } else {
                    (c[k], o[k])
                };
                assert!((x - y).abs() <= max, "colour {i}: {c:?} vs {o:?}");
            }
        }
    }
}
