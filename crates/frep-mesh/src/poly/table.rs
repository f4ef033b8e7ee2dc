//! Marching-cubes cases, generated from one face rule instead of typed in.
//!
//! Corner `c` of a cube has offset `(c & 1, c >> 1 & 1, c >> 2 & 1)`. Edge `4a + u + 2v`
//! runs along axis `a` from the corner whose `a`-bit is 0; `u`, `v` are the bits of the
//! other two axes in increasing order.
//!
//! Each of the six faces is cut into segments from its corner signs alone; on an ambiguous
//! face (inside corners on a diagonal) the inside corners are **separated**. Because a face's
//! segments depend only on that face, two cubes sharing a face cut it the same way, so the
//! surface has no cracks. Every crossing edge belongs to two faces of the cube, once entering
//! and once leaving, so the segments chain into disjoint cycles: the components (polygons).
//! Segments are oriented so that each polygon is counter-clockwise seen from outside the
//! solid (outward normal, toward negative `f`).

use std::sync::OnceLock;

/// The polygons of one case: edge ids, cycles delimited by `starts`.
#[derive(Clone, Debug, Default)]
pub struct Case {
    /// Edge ids of all polygons, concatenated.
    pub edges: Vec<u8>,
    /// `edges[starts[k]..starts[k + 1]]` is polygon `k`.
    pub starts: Vec<u8>,
    /// For each of the 12 edges, the polygon it belongs to (255: no crossing).
    pub component: [u8; 12],
}

impl Case {
    /// Number of polygons.
    pub fn polygons(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// Polygon `k` as edge ids.
    pub fn polygon(&self, k: usize) -> &[u8] {
        &self.edges[self.starts[k] as usize..self.starts[k + 1] as usize]
    }
}

/// The edge between corners `c1` and `c2` (which differ in exactly one bit).
pub fn edge_between(c1: usize, c2: usize) -> u8 {
    let d = c1 ^ c2;
    let a = d.trailing_zeros() as usize;
    let lo = c1 & c2;
    let (b, c) = match a {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    (4 * a + ((lo >> b) & 1) + 2 * ((lo >> c) & 1)) as u8
}

/// The two corners of edge `e` (lower first).
pub fn edge_corners(e: u8) -> (usize, usize) {
    let a = (e / 4) as usize;
    let u = (e & 1) as usize;
    let v = ((e >> 1) & 1) as usize;
    let (b, c) = match a {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    let lo = (u << b) | (v << c);
    (lo, lo | (1 << a))
}

/// The two faces (`2·axis + side`) edge `e` lies on.
fn faces(e: u8) -> [u8; 2] {
    let a = e / 4;
    let (o1, o2) = match a {
        0 => (1, 2),
        1 => (0, 2),
        _ => (0, 1),
    };
    [2 * o1 + (e & 1), 2 * o2 + (e >> 1 & 1)]
}

/// Whether edges `e1` and `e2` lie on a common face of the cube.
pub fn share_face(e1: u8, e2: u8) -> bool {
    let (f, g) = (faces(e1), faces(e2));
    f.iter().any(|x| g.contains(x))
}

fn build(case: usize) -> Case {
    let inside = |c: usize| case >> c & 1 == 1;
    let mut next = [255u8; 12];
    for a in 0..3 {
        let (b, c) = ((a + 1) % 3, (a + 2) % 3);
        for s in 0..2 {
            // Corners counter-clockwise seen from outside the cube.
            let bc: [(usize, usize); 4] = if s == 1 {
                [(0, 0), (1, 0), (1, 1), (0, 1)]
            } else {
                [(0, 0), (0, 1), (1, 1), (1, 0)]
            };
            let p = bc.map(|(u, v)| (s << a) | (u << b) | (v << c));
            let e = |i: usize| edge_between(p[i % 4], p[(i + 1) % 4]);
            let ins = p.map(inside);
            let crossings = (0..4).filter(|&i| ins[i] != ins[(i + 1) % 4]).count();
            if crossings == 2 {
                let x_in = (0..4)
                    .find(|&i| !ins[i] && ins[(i + 1) % 4])
                    .expect("two crossings");
                let x_out = (0..4)
                    .find(|&i| ins[i] && !ins[(i + 1) % 4])
                    .expect("two crossings");
                next[e(x_in) as usize] = e(x_out);
            } else if crossings == 4 {
                // Separate the inside corners: around inside corner i, from the edge entering
                // it to the edge leaving it.
                for i in 0..4 {
                    if ins[i] {
                        next[e(i + 3) as usize] = e(i);
                    }
                }
            }
        }
    }
    let mut out = Case {
        component: [255; 12],
        ..Default::default()
    };
    out.starts.push(0);
    for start in 0..12u8 {
        if next[start as usize] == 255 || out.component[start as usize] != 255 {
            continue;
        }
        let k = out.polygons() as u8;
        let mut e = start;
        loop {
            out.component[e as usize] = k;
            out.edges.push(e);
            e = next[e as usize];
            if e == start {
                break;
            }
        }
        out.starts.push(out.edges.len() as u8);
    }
    out
}

/// The 256 cases, indexed by the bit mask of inside corners.
pub fn cases() -> &'static [Case; 256] {
    static CASES: OnceLock<Box<[Case; 256]>> = OnceLock::new();
    CASES.get_or_init(|| {
        let v: Vec<Case> = (0..256).map(build).collect();
        Box::new(v.try_into().expect("256 cases"))
    })
}

/// The polygons of a case for dual contouring. They are like [`Case`]'s, but a polygon that
/// crosses one face of the cube twice is split in two by a chord between its crossings, one
/// half per segment. Such a polygon holds both segments of an ambiguous face: 36 case
/// polygons, walls about one cell thick. Two polygons of neighbouring cubes then share at
/// most one segment, so their dual vertices share at most one edge. Without the split, a thin
/// wall can give two cubes' vertices two edges: a doubled, non-manifold edge of the dual mesh.
#[derive(Clone, Debug, Default)]
pub struct DualCase {
    /// Polygons (edge ids, counter-clockwise from outside).
    pub polygons: Vec<Vec<u8>>,
    /// Whether polygon `k` is half of a split one: its closing side (last edge to first) is
    /// the chord, inside the cube, not a segment on a face.
    pub chord: Vec<bool>,
    /// For each edge and each of its two faces (in [`edge_faces`] order), the polygon that
    /// holds the edge's segment on that face (255: no crossing). The two differ only at the
    /// ends of a chord.
    pub at: [[u8; 2]; 12],
}

/// The two faces (`2·axis + side`) edge `e` lies on.
pub fn edge_faces(e: u8) -> [u8; 2] {
    faces(e)
}

fn common_face(a: u8, b: u8) -> u8 {
    let fb = faces(b);
    faces(a)
        .into_iter()
        .find(|f| fb.contains(f))
        .expect("consecutive polygon edges share a face")
}

fn build_dual(c: &Case) -> DualCase {
    let mut polys: Vec<Vec<u8>> = Vec::new();
    let mut chord = Vec::new();
    for k in 0..c.polygons() {
        let p = c.polygon(k).to_vec();
        let n = p.len();
        let face = |i: usize| common_face(p[i], p[(i + 1) % n]);
        let twice = (0..n).find_map(|i| ((i + 1)..n).find(|&j| face(j) == face(i)).map(|j| (i, j)));
        let Some((i, j)) = twice else {
            polys.push(p);
            chord.push(false);
            continue;
        };
        // Segments (p[i], p[i+1]) and (p[j], p[j+1]); the chord joins a crossing strictly
        // between them on each side (the middle one).
        let x = i + 1 + (j - i) / 2;
        let y = (j + 1 + (n + i - j) / 2) % n;
        let x = x.clamp(i + 1, j);
        let walk = |from: usize, to: usize| {
            let mut v = vec![p[from]];
            let mut t = from;
            while t != to {
                t = (t + 1) % n;
                v.push(p[t]);
            }
            v
        };
        polys.push(walk(y, x));
        polys.push(walk(x, y));
        chord.extend([true, true]);
    }
    let mut at = [[255u8; 2]; 12];
    for (k, p) in polys.iter().enumerate() {
        let n = p.len();
        let sides = if chord[k] { n - 1 } else { n };
        for i in 0..sides {
            let (a, b) = (p[i], p[(i + 1) % n]);
            let f = common_face(a, b);
            for e in [a, b] {
                let slot = faces(e).iter().position(|&g| g == f).expect("face of edge");
                at[e as usize][slot] = k as u8;
            }
        }
    }
    DualCase {
        polygons: polys,
        chord,
        at,
    }
}

/// The 256 dual-contouring cases (see [`DualCase`]).
pub fn dual_cases() -> &'static [DualCase; 256] {
    static CASES: OnceLock<Box<[DualCase; 256]>> = OnceLock::new();
    CASES.get_or_init(|| {
        let v: Vec<DualCase> = cases().iter().map(build_dual).collect();
        Box::new(v.try_into().expect("256 cases"))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_crossing_edge_is_in_one_polygon() {
        for (case, c) in cases().iter().enumerate() {
            for e in 0..12u8 {
                let (a, b) = edge_corners(e);
                let crosses = (case >> a & 1) != (case >> b & 1);
                assert_eq!(
                    crosses,
                    c.component[e as usize] != 255,
                    "case {case} edge {e}"
                );
                assert_eq!(edge_between(a, b), e);
            }
            assert!(c.polygons() <= 4);
            for k in 0..c.polygons() {
                assert!(c.polygon(k).len() >= 3);
            }
        }
        assert_eq!(cases()[0].polygons(), 0);
        assert_eq!(cases()[1].polygons(), 1);
        assert_eq!(cases()[1].polygon(0).len(), 3);
    }

    #[test]
    fn dual_cases_cross_each_face_once() {
        let mut split = 0;
        for (case, d) in dual_cases().iter().enumerate() {
            let c = &cases()[case];
            split += d.polygons.len() - c.polygons();
            assert!(d.polygons.len() <= 8);
            for (k, p) in d.polygons.iter().enumerate() {
                assert!(p.len() >= 3, "case {case}");
                let mut seen = [0; 6];
                let sides = p.len() - usize::from(d.chord[k]);
                for i in 0..sides {
                    seen[common_face(p[i], p[(i + 1) % p.len()]) as usize] += 1;
                }
                assert!(
                    seen.iter().all(|&s| s <= 1),
                    "case {case} polygon {k}: {p:?}"
                );
            }
            for e in 0..12 {
                let crosses = c.component[e] != 255;
                assert_eq!(crosses, d.at[e][0] != 255, "case {case} edge {e}");
                assert_eq!(crosses, d.at[e][1] != 255, "case {case} edge {e}");
            }
        }
        assert_eq!(split, 36);
    }
}
