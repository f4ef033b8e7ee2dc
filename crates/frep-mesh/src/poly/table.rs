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
}
