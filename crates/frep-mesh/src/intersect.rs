//! Self-intersection detection: exact-sign-style triangle–triangle tests in `f64` over a
//! uniform grid of triangle bounding boxes.
//!
//! Two non-coplanar triangles intersect exactly when an edge of one meets the other: the
//! intersection is a segment whose ends lie on their boundaries.
//! - So the test is six segment–triangle tests, after a cheap separating-plane rejection.
//! - Coplanar pairs use 2D tests.
//! - Pairs that share vertices (by index) are judged by what they share. A shared edge counts
//!   only when the two triangles fold onto each other. A shared vertex counts only when they
//!   meet elsewhere.

use crate::mesh::{cross, dot, sub, to_f64, Mesh};

type V = [f64; 3];

fn orient(a: V, b: V, c: V, d: V) -> f64 {
    dot(cross(sub(b, a), sub(c, a)), sub(d, a))
}

/// Drops the coordinate along which `n` is largest, for 2D tests in the plane with normal `n`.
fn project(n: V) -> impl Fn(V) -> [f64; 2] {
    let k = (0..3)
        .max_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
        .unwrap_or(2);
    let (i, j) = ((k + 1) % 3, (k + 2) % 3);
    move |p: V| [p[i], p[j]]
}

fn orient2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Closed 2D segment–segment intersection.
fn segments_meet_2d(p: [f64; 2], q: [f64; 2], a: [f64; 2], b: [f64; 2]) -> bool {
    let d1 = orient2(p, q, a);
    let d2 = orient2(p, q, b);
    let d3 = orient2(a, b, p);
    let d4 = orient2(a, b, q);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |a: [f64; 2], b: [f64; 2], p: [f64; 2], d: f64| {
        d == 0.0
            && p[0] >= a[0].min(b[0])
            && p[0] <= a[0].max(b[0])
            && p[1] >= a[1].min(b[1])
            && p[1] <= a[1].max(b[1])
    };
    on(p, q, a, d1) || on(p, q, b, d2) || on(a, b, p, d3) || on(a, b, q, d4)
}

/// Closed 2D point-in-triangle test (either orientation).
fn inside_2d(p: [f64; 2], t: [[f64; 2]; 3]) -> bool {
    let d = [
        orient2(t[0], t[1], p),
        orient2(t[1], t[2], p),
        orient2(t[2], t[0], p),
    ];
    d.iter().all(|&x| x >= 0.0) || d.iter().all(|&x| x <= 0.0)
}

/// Closed 2D segment–triangle intersection.
fn segment_triangle_2d(p: [f64; 2], q: [f64; 2], t: [[f64; 2]; 3]) -> bool {
    inside_2d(p, t)
        || inside_2d(q, t)
        || (0..3).any(|k| segments_meet_2d(p, q, t[k], t[(k + 1) % 3]))
}

/// Closed segment–triangle intersection in 3D.
fn segment_triangle(p: V, q: V, t: [V; 3]) -> bool {
    let [a, b, c] = t;
    let sp = orient(a, b, c, p);
    let sq = orient(a, b, c, q);
    if (sp > 0.0 && sq > 0.0) || (sp < 0.0 && sq < 0.0) {
        return false;
    }
    if sp == 0.0 && sq == 0.0 {
        let pr = project(cross(sub(b, a), sub(c, a)));
        return segment_triangle_2d(pr(p), pr(q), t.map(&pr));
    }
    let s = [orient(p, q, a, b), orient(p, q, b, c), orient(p, q, c, a)];
    s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
}

/// Whether the projections of two triangles onto some coordinate plane are separated by an
/// edge line of one of them, the other triangle strictly on the far side. Then they are
/// disjoint. With `shared = Some((i, j))`, they meet only there: vertex `i` of `t1` is vertex
/// `j` of `t2`, and the edge line passes through it. The 2D tests are far better conditioned
/// than the 3D orientations, which misjudge nearly coplanar pairs.
fn projections_separated(t1: [V; 3], t2: [V; 3], shared: Option<(usize, usize)>) -> bool {
    (0..3).any(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        let a = t1.map(|p| [p[i], p[j]]);
        let b = t2.map(|p| [p[i], p[j]]);
        let (sa, sb) = (shared.map(|s| s.0), shared.map(|s| s.1));
        [(a, b, sa, sb), (b, a, sb, sa)]
            .iter()
            .any(|&(s, o, ss, os)| {
                (0..3).any(|e| {
                    if ss.is_some_and(|v| v != e && v != (e + 1) % 3) {
                        return false;
                    }
                    let (p, q, r) = (s[e], s[(e + 1) % 3], s[(e + 2) % 3]);
                    let side = orient2(p, q, r);
                    side != 0.0 && (0..3).all(|x| Some(x) == os || orient2(p, q, o[x]) * side < 0.0)
                })
            })
    })
}

/// Whether two triangles that share no vertex intersect (closed sets).
fn triangles_meet(t1: [V; 3], t2: [V; 3]) -> bool {
    if projections_separated(t1, t2, None) {
        return false;
    }
    let d2 = t1.map(|p| orient(t2[0], t2[1], t2[2], p));
    if d2.iter().all(|&d| d > 0.0) || d2.iter().all(|&d| d < 0.0) {
        return false;
    }
    let d1 = t2.map(|p| orient(t1[0], t1[1], t1[2], p));
    if d1.iter().all(|&d| d > 0.0) || d1.iter().all(|&d| d < 0.0) {
        return false;
    }
    if d1.iter().all(|&d| d == 0.0) {
        let pr = project(cross(sub(t1[1], t1[0]), sub(t1[2], t1[0])));
        let (a, b) = (t1.map(&pr), t2.map(&pr));
        return (0..3).any(|k| segment_triangle_2d(a[k], a[(k + 1) % 3], b));
    }
    (0..3).any(|k| segment_triangle(t1[k], t1[(k + 1) % 3], t2))
        || (0..3).any(|k| segment_triangle(t2[k], t2[(k + 1) % 3], t1))
}

/// Whether direction `d` lies strictly inside the wedge spanned by `u` and `v` (2D).
fn strictly_inside_wedge(u: [f64; 2], v: [f64; 2], d: [f64; 2]) -> bool {
    let o = [0.0, 0.0];
    let s = orient2(o, u, v);
    s != 0.0 && orient2(o, u, d) * s > 0.0 && orient2(o, d, v) * s > 0.0
}

/// Whether triangles `(v, a, b)` and `(v, c, d)` meet anywhere but at `v`.
fn meet_beyond_vertex(v: V, a: V, b: V, c: V, d: V) -> bool {
    let n = cross(sub(a, v), sub(b, v));
    let (oc, od) = (orient(v, a, b, c), orient(v, a, b, d));
    // One triangle strictly on one side of the other's plane (but for `v`): they meet only at `v`.
    let strictly_one_side = |x: f64, y: f64| (x > 0.0 && y > 0.0) || (x < 0.0 && y < 0.0);
    if strictly_one_side(oc, od) || strictly_one_side(orient(v, c, d, a), orient(v, c, d, b)) {
        return false;
    }
    if oc == 0.0 && od == 0.0 {
        // Coplanar: the triangles overlap near `v` exactly when their wedges at `v` overlap,
        // and otherwise meet only if the far edges cross the other triangle.
        let pr = project(n);
        let o = pr(v);
        let rel = |p: V| {
            let q = pr(p);
            [q[0] - o[0], q[1] - o[1]]
        };
        let (a2, b2, c2, d2) = (rel(a), rel(b), rel(c), rel(d));
        let mid = |x: [f64; 2], y: [f64; 2]| [x[0] + y[0], x[1] + y[1]];
        let overlap = [c2, d2, mid(c2, d2)]
            .iter()
            .any(|&x| strictly_inside_wedge(a2, b2, x))
            || [a2, b2, mid(a2, b2)]
                .iter()
                .any(|&x| strictly_inside_wedge(c2, d2, x));
        let t1 = [pr(v), pr(a), pr(b)];
        let t2 = [pr(v), pr(c), pr(d)];
        return overlap
            || segment_triangle_2d(t1[1], t1[2], t2)
            || segment_triangle_2d(t2[1], t2[2], t1);
    }
    segment_triangle(a, b, [v, c, d]) || segment_triangle(c, d, [v, a, b])
}

/// Whether two distinct triangles, given by index and position, intersect other than along
/// what they share.
fn pair_intersects(i1: [u32; 3], t1: [V; 3], i2: [u32; 3], t2: [V; 3]) -> bool {
    let mut shared = [(0usize, 0usize); 3];
    let mut count = 0;
    for (a, &x) in i1.iter().enumerate() {
        for (b, &y) in i2.iter().enumerate() {
            if x == y && count < 3 {
                shared[count] = (a, b);
                count += 1;
            }
        }
    }
    match count {
        0 => triangles_meet(t1, t2),
        1 => {
            let (a, b) = shared[0];
            if projections_separated(t1, t2, Some((a, b))) {
                return false;
            }
            meet_beyond_vertex(
                t1[a],
                t1[(a + 1) % 3],
                t1[(a + 2) % 3],
                t2[(b + 1) % 3],
                t2[(b + 2) % 3],
            )
        }
        2 => {
            // Shared edge (p, q); the triangles overlap when folded onto the same side.
            let (a0, b0) = shared[0];
            let (a1, _) = shared[1];
            let c = t1[3 - a0 - a1];
            let d = t2[3 - b0 - shared[1].1];
            let (p, q) = (t1[a0], t1[a1]);
            if orient(p, q, c, d) != 0.0 {
                return false;
            }
            let pr = project(cross(sub(q, p), sub(c, p)));
            orient2(pr(p), pr(q), pr(c)) * orient2(pr(p), pr(q), pr(d)) > 0.0
        }
        // The same three vertices: a duplicated face.
        _ => true,
    }
}

impl Mesh {
    /// Counts pairs of triangles that intersect (touching counts, sharing a vertex or an edge
    /// by index does not), stopping once `max_pairs` are found.
    ///
    /// Degenerate triangles (repeated indices) are skipped. Candidate pairs come from a
    /// uniform grid sized to the mean triangle, so meshes of a few hundred thousand triangles
    /// take well under a second in release builds.
    pub fn self_intersections(&self, max_pairs: usize) -> usize {
        self.self_intersection_pairs(max_pairs).len()
    }

    /// The intersecting pairs of triangles (indices into `triangles`) that
    /// [`Mesh::self_intersections`] counts, at most `max_pairs` of them.
    pub fn self_intersection_pairs(&self, max_pairs: usize) -> Vec<[usize; 2]> {
        let mut found = Vec::new();
        let tris: Vec<usize> = (0..self.triangles.len())
            .filter(|&i| {
                let t = self.triangles[i];
                t[0] != t[1] && t[1] != t[2] && t[2] != t[0]
            })
            .collect();
        if tris.len() < 2 || max_pairs == 0 {
            return found;
        }
        let pos = |i: usize| self.triangles[i].map(|v| to_f64(self.positions[v as usize]));
        let boxes: Vec<[V; 2]> = tris
            .iter()
            .map(|&i| {
                let t = pos(i);
                let lo = [0, 1, 2].map(|k| t[0][k].min(t[1][k]).min(t[2][k]));
                let hi = [0, 1, 2].map(|k| t[0][k].max(t[1][k]).max(t[2][k]));
                [lo, hi]
            })
            .collect();
        let grid = Grid::new(&boxes);
        for cell in 0..grid.cells() {
            let members = grid.members(cell);
            for (x, &a) in members.iter().enumerate() {
                for &b in &members[x + 1..] {
                    let (ba, bb) = (boxes[a as usize], boxes[b as usize]);
                    let lo = [0, 1, 2].map(|k| ba[0][k].max(bb[0][k]));
                    if (0..3).any(|k| lo[k] > ba[1][k].min(bb[1][k])) {
                        continue;
                    }
                    // Test each pair once: in the cell holding the low corner of the overlap.
                    if grid.cell_of(lo) != cell {
                        continue;
                    }
                    let (ta, tb) = (tris[a as usize], tris[b as usize]);
                    if pair_intersects(self.triangles[ta], pos(ta), self.triangles[tb], pos(tb)) {
                        found.push([ta, tb]);
                        if found.len() >= max_pairs {
                            return found;
                        }
                    }
                }
            }
        }
        found
    }
}

/// A uniform grid of boxes in compressed-row form.
struct Grid {
    origin: V,
    inv_cell: f64,
    dims: [usize; 3],
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Grid {
    fn new(boxes: &[[V; 2]]) -> Grid {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut mean_size = 0.0;
        for b in boxes {
            for k in 0..3 {
                lo[k] = lo[k].min(b[0][k]);
                hi[k] = hi[k].max(b[1][k]);
            }
            mean_size += (0..3).map(|k| b[1][k] - b[0][k]).fold(0.0, f64::max);
        }
        mean_size /= boxes.len() as f64;
        let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        // Cells about twice the mean triangle, with at most ~4 cells per triangle overall.
        let mut cell = (2.0 * mean_size).max(extent * 1e-6).max(f64::MIN_POSITIVE);
        let max_cells = (4 * boxes.len()).max(64) as f64;
        let dims_for = |cell: f64| {
            [0, 1, 2].map(|k| (((hi[k] - lo[k]) / cell).floor() as usize + 1).min(1 << 20))
        };
        while dims_for(cell).iter().map(|&d| d as f64).product::<f64>() > max_cells {
            cell *= 1.25;
        }
        let mut grid = Grid {
            origin: lo,
            inv_cell: 1.0 / cell,
            dims: dims_for(cell),
            start: Vec::new(),
            items: Vec::new(),
        };
        let n = grid.cells();
        let mut start = vec![0u32; n + 1];
        for b in boxes {
            grid.for_cells(b, |c| start[c + 1] += 1);
        }
        for c in 0..n {
            start[c + 1] += start[c];
        }
        let mut fill = start.clone();
        let mut items = vec![0u32; start[n] as usize];
        for (i, b) in boxes.iter().enumerate() {
            grid.for_cells(b, |c| {
                items[fill[c] as usize] = i as u32;
                fill[c] += 1;
            });
        }
        grid.start = start;
        grid.items = items;
        grid
    }

    fn cells(&self) -> usize {
        self.dims.iter().product()
    }

    fn coord(&self, p: V) -> [usize; 3] {
        [0, 1, 2].map(|k| {
            (((p[k] - self.origin[k]) * self.inv_cell).max(0.0) as usize).min(self.dims[k] - 1)
        })
    }

    fn cell_of(&self, p: V) -> usize {
        let c = self.coord(p);
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }

    fn for_cells(&self, b: &[V; 2], mut f: impl FnMut(usize)) {
        let (lo, hi) = (self.coord(b[0]), self.coord(b[1]));
        for z in lo[2]..=hi[2] {
            for y in lo[1]..=hi[1] {
                for x in lo[0]..=hi[0] {
                    f((z * self.dims[1] + y) * self.dims[0] + x);
                }
            }
        }
    }

    fn members(&self, cell: usize) -> &[u32] {
        &self.items[self.start[cell] as usize..self.start[cell + 1] as usize]
    }
}
