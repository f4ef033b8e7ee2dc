//! Combinatorial checks: manifoldness, orientation, components, Euler characteristic.

use crate::mesh::{dot, Mesh};

/// Topological summary of a [`Mesh`], from [`Mesh::topology`].
///
/// Triangles with a repeated index are counted in `degenerate_triangles` and otherwise
/// ignored. Vertices that no triangle uses are counted in `isolated_vertices`, and left out of
/// `vertices` and the Euler characteristic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Topology {
    /// Vertices used by at least one non-degenerate triangle.
    pub vertices: usize,
    /// Distinct undirected edges.
    pub edges: usize,
    /// Non-degenerate triangles.
    pub faces: usize,
    /// Vertices used by no non-degenerate triangle.
    pub isolated_vertices: usize,
    /// Edges used by exactly one triangle.
    pub boundary_edges: usize,
    /// Edges shared by more than two triangles.
    pub non_manifold_edges: usize,
    /// Edges shared by exactly two triangles that traverse it in the same direction.
    pub inconsistent_edges: usize,
    /// Vertices whose triangle fan is not a single disc (a cycle, or a path on the boundary).
    pub non_manifold_vertices: usize,
    /// Triangles with a repeated index or exactly zero area.
    pub degenerate_triangles: usize,
    /// Connected components (triangles connected through shared vertices).
    pub components: usize,
}

impl Topology {
    /// The Euler characteristic V − E + F (2 per sphere-like component, 0 for a torus).
    pub fn euler_characteristic(&self) -> i64 {
        self.vertices as i64 - self.edges as i64 + self.faces as i64
    }

    /// True when every edge has exactly two triangles and every vertex fan is a disc.
    pub fn is_closed_manifold(&self) -> bool {
        self.boundary_edges == 0 && self.non_manifold_edges == 0 && self.non_manifold_vertices == 0
    }

    /// True when no two-triangle edge is traversed twice in the same direction.
    pub fn is_consistently_oriented(&self) -> bool {
        self.inconsistent_edges == 0
    }
}

fn find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[parent[x as usize] as usize];
        parent[x as usize] = p;
        x = p;
    }
    x
}

/// Whether the link of a vertex (the opposite edges of its triangles) is a single cycle or a
/// single path, i.e. its fan is one disc.
fn fan_is_disc(link: &[(u32, u32)]) -> bool {
    let mut nodes: Vec<u32> = link.iter().flat_map(|&(a, b)| [a, b]).collect();
    nodes.sort_unstable();
    let mut degree_one = 0;
    let mut i = 0;
    while i < nodes.len() {
        let j = nodes[i..]
            .iter()
            .position(|&x| x != nodes[i])
            .map_or(nodes.len(), |k| i + k);
        match j - i {
            1 => degree_one += 1,
            2 => {}
            _ => return false,
        }
        i = j;
    }
    if degree_one != 0 && degree_one != 2 {
        return false;
    }
    // With all degrees 1 or 2 the link is a union of paths and cycles; it is one piece when a
    // walk from one link edge reaches every link edge.
    let mut used = vec![false; link.len()];
    let start = 0;
    // Walk outward from `start` in both directions.
    used[start] = true;
    let mut reached = 1;
    for mut at in [link[start].0, link[start].1] {
        while let Some(k) =
            (0..link.len()).find(|&k| !used[k] && (link[k].0 == at || link[k].1 == at))
        {
            used[k] = true;
            reached += 1;
            at = if link[k].0 == at {
                link[k].1
            } else {
                link[k].0
            };
        }
    }
    reached == link.len()
}

impl Mesh {
    /// Computes the [`Topology`] summary. Indices must be in range (see [`Mesh::validate`]).
    pub fn topology(&self) -> Topology {
        let n = self.positions.len();
        let mut topo = Topology::default();
        let good: Vec<[u32; 3]> = self
            .triangles
            .iter()
            .copied()
            .filter(|t| {
                let repeated = t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
                let n = if repeated {
                    [0.0; 3]
                } else {
                    self.triangle_cross(*t)
                };
                if repeated || dot(n, n) == 0.0 {
                    topo.degenerate_triangles += 1;
                }
                !repeated
            })
            .collect();
        topo.faces = good.len();

        // Directed edges sorted by undirected key; the low bit records the direction.
        let mut edges: Vec<u64> = good
            .iter()
            .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
            .map(|(a, b)| ((a.min(b) as u64) << 33) | ((a.max(b) as u64) << 1) | (a > b) as u64)
            .collect();
        edges.sort_unstable();
        let mut i = 0;
        while i < edges.len() {
            let key = edges[i] >> 1;
            let j = edges[i..]
                .iter()
                .position(|&e| e >> 1 != key)
                .map_or(edges.len(), |k| i + k);
            topo.edges += 1;
            match j - i {
                1 => topo.boundary_edges += 1,
                2 if edges[i] == edges[i + 1] => topo.inconsistent_edges += 1,
                2 => {}
                _ => topo.non_manifold_edges += 1,
            }
            i = j;
        }

        // Vertex → triangle incidence (compressed rows), then each fan's link.
        let mut start = vec![0usize; n + 1];
        for t in &good {
            for &v in t {
                start[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            start[v + 1] += start[v];
        }
        let mut fill = start.clone();
        let mut incident = vec![0u32; good.len() * 3];
        for (ti, t) in good.iter().enumerate() {
            for &v in t {
                incident[fill[v as usize]] = ti as u32;
                fill[v as usize] += 1;
            }
        }
        let mut link = Vec::new();
        for v in 0..n {
            let fan = &incident[start[v]..start[v + 1]];
            if fan.is_empty() {
                topo.isolated_vertices += 1;
                continue;
            }
            topo.vertices += 1;
            link.clear();
            link.extend(fan.iter().map(|&ti| {
                let t = good[ti as usize];
                let k = t.iter().position(|&x| x as usize == v).unwrap_or(0);
                (t[(k + 1) % 3], t[(k + 2) % 3])
            }));
            if !fan_is_disc(&link) {
                topo.non_manifold_vertices += 1;
            }
        }

        // Components: union the vertices of each triangle.
        let mut parent: Vec<u32> = (0..n as u32).collect();
        for t in &good {
            let a = find(&mut parent, t[0]);
            for &v in &t[1..] {
                let b = find(&mut parent, v);
                parent[b as usize] = a;
            }
        }
        topo.components = (0..n as u32)
            .filter(|&v| start[v as usize + 1] > start[v as usize] && find(&mut parent, v) == v)
            .count();
        topo
    }
}
