//! Adaptive dual contouring: blocks of cubes collapsed to one vertex,
//! bottom-up, where topology and the merged QEF allow.

use frep_core::eval::grad::GradEval;

use super::grid::{add, norm, point_key, OFFS};
use super::table::cases;
use super::{qef, table};
use super::{Ctx, KeyMap, DC_SLACK};

/// A block: no surface, not collapsible, or collapsed (its cubes' vertex keys and
/// crossings).
#[derive(Clone)]
enum Block {
    Empty,
    Blocked,
    Merged(Vec<u64>, Vec<u32>),
}

impl Ctx<'_> {
    /// Adaptive dual contouring ([`MeshSettings::adaptive`]): the blocks of 2×2×2, 4×4×4, …
    /// cubes of brick `o` that collapse to one vertex. They come as `cube's vertex key →
    /// (merged vertex's key, position, normal)`. The work goes bottom-up (Ju et al. 2002,
    /// "Dual Contouring of Hermite Data", §4.2). A block of side `S` collapses when
    /// - its 8 sub-blocks are empty or collapsed (cubes: one polygon), and all its samples are
    ///   real (no cap);
    /// - as one cube (its 8 corner samples) it has one polygon and no ambiguous face;
    /// - its topology is the coarse cube's. The sample in the middle of each coarse edge has
    ///   the sign of one of the edge's ends. The one in the middle of each face has the sign
    ///   of one of the face's corners, and the centre that of one of the corners. The finer
    ///   samples were checked by the sub-blocks;
    /// - the vertex of the QEF of all its crossings, snapped onto the surface, lies within
    ///   `tol` cell of every crossing's tangent plane.
    ///
    /// [`MeshSettings::adaptive`]: crate::poly::MeshSettings::adaptive
    #[allow(clippy::too_many_arguments)]
    pub(super) fn collapse(
        &self,
        ge: &mut GradEval,
        o: [i32; 3],
        sign: &[bool],
        cubes: &[([i32; 3], usize, [u32; 12])],
        pos: &[[f64; 3]],
        nrm: &[[f64; 3]],
        tol: f64,
    ) -> KeyMap<(u64, [f64; 3], [f64; 3])> {
        let g = &self.grid;
        let b = g.brick;
        let e = (b + 2) as usize;
        let at = |p: [i32; 3]| {
            sign[(p[0] - o[0] + 1) as usize
                + e * ((p[1] - o[1] + 1) as usize + e * (p[2] - o[2] + 1) as usize)]
        };
        let dual = table::dual_cases();
        let idx = |k: [i32; 3], n: i32| (k[0] + n * (k[1] + n * k[2])) as usize;
        // Level 0: the cubes of the brick.
        let mut level = vec![Block::Empty; (b * b * b) as usize];
        for (q, mask, local) in cubes {
            let k = [0, 1, 2].map(|a| q[a] - o[a]);
            if k.iter().any(|&c| c < 0 || c >= b) {
                continue;
            }
            level[idx(k, b)] = match &dual[*mask].polygons[..] {
                [poly] => Block::Merged(
                    vec![point_key(*q) << 3],
                    poly.iter().map(|&ei| local[ei as usize]).collect(),
                ),
                _ => Block::Blocked,
            };
        }
        let mut out = KeyMap::default();
        let (mut pts, mut ns) = (Vec::new(), Vec::new());
        let mut side = 2;
        while side <= b {
            let n = b / side;
            let mut next = vec![Block::Empty; (n * n * n) as usize];
            for kz in 0..n {
                for ky in 0..n {
                    for kx in 0..n {
                        let k = [kx, ky, kz];
                        let q0 = [0, 1, 2].map(|a| o[a] + side * k[a]);
                        let subs: Vec<&Block> = OFFS
                            .iter()
                            .map(|off| &level[idx([0, 1, 2].map(|a| 2 * k[a] + off[a]), 2 * n)])
                            .collect();
                        let blocked = subs.iter().any(|s| matches!(s, Block::Blocked))
                            || (subs.iter().any(|s| matches!(s, Block::Merged(..)))
                                && !self.coarse_ok(&at, q0, side));
                        next[idx(k, n)] = if blocked {
                            Block::Blocked
                        } else {
                            let (mut members, mut edges) = (Vec::new(), Vec::new());
                            for s in subs {
                                if let Block::Merged(m, es) = s {
                                    members.extend_from_slice(m);
                                    edges.extend_from_slice(es);
                                }
                            }
                            edges.sort_unstable();
                            edges.dedup();
                            if members.is_empty() {
                                Block::Empty
                            } else if members.len() == 1 {
                                Block::Merged(members, edges)
                            } else {
                                let hermite = (pos, nrm);
                                let scratch = (&mut pts, &mut ns);
                                match self.merged_vertex(
                                    ge,
                                    &edges,
                                    (q0, side),
                                    hermite,
                                    tol,
                                    scratch,
                                ) {
                                    None => Block::Blocked,
                                    Some((x, n)) => {
                                        let rep = members[0];
                                        for &m in &members {
                                            out.insert(m, (rep, x, n));
                                        }
                                        Block::Merged(members, edges)
                                    }
                                }
                            }
                        };
                    }
                }
            }
            level = next;
            side *= 2;
        }
        out
    }

    /// The vertex of the block of `side` cubes at `q0` whose crossings are `edges` (in
    /// `hermite`: positions, normals): the merged QEF's minimizer snapped onto the surface,
    /// and the mean normal. `None` when it lies farther than `tol` cell from a crossing's
    /// tangent plane. `scratch` holds the points and normals between calls.
    fn merged_vertex(
        &self,
        ge: &mut GradEval,
        edges: &[u32],
        (q0, side): ([i32; 3], i32),
        (pos, nrm): (&[[f64; 3]], &[[f64; 3]]),
        tol: f64,
        (pts, ns): (&mut Vec<[f64; 3]>, &mut Vec<[f64; 3]>),
    ) -> Option<([f64; 3], [f64; 3])> {
        let g = &self.grid;
        let h = g.h.iter().fold(0.0f64, |a, &c| a.max(c));
        pts.clear();
        ns.clear();
        let mut avg = [0.0; 3];
        for &v in edges {
            pts.push(pos[v as usize]);
            ns.push(nrm[v as usize]);
            for c in 0..3 {
                avg[c] += nrm[v as usize][c];
            }
        }
        let lo = [0, 1, 2].map(|a| g.coord(a, q0[a]) - DC_SLACK * g.h[a]);
        let hi = [0, 1, 2].map(|a| g.coord(a, q0[a] + side) + DC_SLACK * g.h[a]);
        let x = self.snap(ge, qef::solve(pts, ns, lo, hi), lo, hi);
        let far = pts.iter().zip(ns.iter()).any(|(p, nr)| {
            let d = (0..3).map(|c| nr[c] * (x[c] - p[c])).sum::<f64>();
            d.is_nan() || d.abs() > tol * h
        });
        (!far).then(|| (x, norm(avg)))
    }

    /// Whether the block of `side` cubes at `q0` is one coarse cube topologically (see
    /// [`Ctx::collapse`]). It needs real samples, one polygon and no ambiguous face. The signs
    /// in the middle of its edges and faces and at its centre are those of one of their
    /// corners.
    fn coarse_ok(&self, at: &impl Fn([i32; 3]) -> bool, q0: [i32; 3], side: i32) -> bool {
        let g = &self.grid;
        if (0..3).any(|a| q0[a] + side >= g.n[a]) {
            return false;
        }
        let half = side / 2;
        let corner = |c: usize| add(q0, OFFS[c].map(|v| side * v));
        let mut cm = 0usize;
        for c in 0..8 {
            cm |= (at(corner(c)) as usize) << c;
        }
        if cm == 0 || cm == 255 || cases()[cm].polygons() != 1 {
            return false;
        }
        for (c0, off0) in OFFS.iter().enumerate() {
            for a in 0..3 {
                let c1 = c0 | 1 << a;
                if c1 == c0 {
                    continue;
                }
                let (s0, s1) = (at(corner(c0)), at(corner(c1)));
                let mid = at(add(q0, add(*off0, OFFS[c1]).map(|v| half * v)));
                if s0 == s1 && mid != s0 {
                    return false;
                }
            }
        }
        for a in 0..3 {
            for sd in 0..2 {
                let cs: Vec<usize> = (0..8).filter(|c| (c >> a) & 1 == sd).collect();
                let mut centre = q0.map(|v| v + half);
                centre[a] = q0[a] + side * sd as i32;
                let sc = at(centre);
                if !cs.iter().any(|&c| at(corner(c)) == sc) {
                    return false;
                }
                // Two inside corners on a diagonal (their indices differ in two bits).
                let inside: Vec<usize> = cs.iter().copied().filter(|&c| at(corner(c))).collect();
                if let [i, j] = inside[..] {
                    if (i ^ j).count_ones() == 2 {
                        return false;
                    }
                }
            }
        }
        let sc = at(q0.map(|v| v + half));
        (0..8).any(|c| at(corner(c)) == sc)
    }
}
