//! Extraction: the cubes a brick owns turned into polygons (marching
//! cubes) or dual-contouring vertices and quads, and their colours.

use std::cell::Cell;

use frep_core::eval::grad::GradEval;

use super::grid::{add, dist2, norm, point_key, Lattice, INSIDE, OFFS, OUTSIDE};
use super::octree::{with_batch, Brick};
use super::settings::{MeshError, Method};
use super::table::{cases, edge_between, edge_corners};
use super::{qef, table};
use super::{Ctx, KeyMap, DC_SLACK};

/// The per-brick buffers of [`Ctx::extract`], kept per thread between bricks.
#[derive(Default)]
struct ExtractBufs {
    /// Signs of the samples `o − 1 ..= o + b` around the brick.
    sign: Vec<bool>,
    /// Per row of `sign` along x: 0 all outside, 1 all inside, 2 mixed.
    rows: Vec<u8>,
    /// Per edge of the brick's samples (`3 × (b + 2)³`, by lower end and axis): its index in
    /// `edges`, `u32::MAX` before it is met (and again after the brick).
    edge_index: Vec<u32>,
    edges: Vec<EdgeRec>,
    edge_keys: Vec<u64>,
    /// Cubes with surface: (min corner, case, local edge indices).
    cubes: Vec<([i32; 3], usize, [u32; 12])>,
}

thread_local! {
    static EXTRACT_BUFS: Cell<ExtractBufs> = Cell::new(ExtractBufs::default());
}

/// What one brick contributes.
#[derive(Default)]
pub(super) struct BrickOut {
    /// Dual contouring: the vertices' keys (one per position).
    pub(super) keys: Vec<u64>,
    pub(super) positions: Vec<[f32; 3]>,
    pub(super) normals: Vec<[f32; 3]>,
    pub(super) colors: Vec<[f32; 3]>,
    /// Marching cubes: triangles of this brick's vertex indices.
    pub(super) tris: Vec<[u32; 3]>,
    /// Marching cubes: `(vertex index, key)` of the vertices on edges that cubes of other
    /// bricks may share, by increasing index (the others are this brick's alone).
    pub(super) shared: Vec<(u32, u64)>,
    /// Dual contouring: triangles of vertex keys.
    pub(super) triangles: Vec<[u64; 3]>,
    /// Dual contouring: quads of vertex keys, counter-clockwise from outside.
    pub(super) quads: Vec<[u64; 4]>,
    /// Adaptive dual contouring: `(key, merged vertex's key)` of the vertices of collapsed
    /// blocks.
    pub(super) aliases: Vec<(u64, u64)>,
}

pub(super) struct EdgeRec {
    /// Lower end.
    pub(super) p: [i32; 3],
    pub(super) axis: usize,
    /// Whether the lower end is the inside one.
    pub(super) inside_low: bool,
}

impl Ctx<'_> {
    fn colors_at(&self, brick: Option<&Brick>, pts: &[[f64; 3]]) -> Vec<[f32; 3]> {
        let Some(brick) = brick.filter(|_| self.colors > 0 && !pts.is_empty()) else {
            return Vec::new();
        };
        let xs: Vec<f64> = pts.iter().map(|p| p[0]).collect();
        let ys: Vec<f64> = pts.iter().map(|p| p[1]).collect();
        let zs: Vec<f64> = pts.iter().map(|p| p[2]).collect();
        let mut outs = vec![Vec::new(); brick.tape.outputs.len()];
        with_batch(&brick.tape, |be| {
            be.eval_outputs(&xs, &ys, &zs, self.inputs, &mut outs)
        });
        (0..pts.len())
            .map(|i| {
                [0, 1, 2].map(|c| {
                    let k = (c + 1).min(self.colors);
                    let v = outs[k][i] as f32;
                    if v.is_finite() {
                        v.clamp(0.0, 1.0)
                    } else {
                        0.0
                    }
                })
            })
            .collect()
    }

    /// Extracts the cubes owned by brick `id` (evaluated brick `eval`, if any).
    pub(super) fn extract(
        &self,
        lat: &Lattice,
        id: usize,
        eval: Option<usize>,
    ) -> Result<BrickOut, MeshError> {
        // This thread's buffers: no allocation per brick for them.
        let mut bufs = EXTRACT_BUFS.with(Cell::take);
        let out = self.extract_with(lat, id, eval, &mut bufs);
        EXTRACT_BUFS.with(|c| c.set(bufs));
        out
    }

    /// [`Ctx::extract`] with the buffers given.
    fn extract_with(
        &self,
        lat: &Lattice,
        id: usize,
        eval: Option<usize>,
        bufs: &mut ExtractBufs,
    ) -> Result<BrickOut, MeshError> {
        self.check()?;
        let b = self.grid.brick;
        let nb = self.grid.nb as usize;
        let o = [id % nb, id / nb % nb, id / (nb * nb)].map(|c| c as i32 * b);
        let brick = eval.map(|k| &lat.bricks[k]);
        self.fill_signs(lat, o, &mut bufs.sign);
        self.find_cubes(lat, id, o, bufs);
        let (pos, nrm) = self.crossings(lat, brick, &bufs.edges);
        if self.method != Method::DualContouring {
            return Ok(self.marching_out(brick, o, bufs, &pos, &nrm));
        }
        Ok(self.dual_out(lat, brick, o, bufs, &pos, &nrm))
    }

    /// Fills `sign` with the signs of the samples `o − 1 ..= o + b` around the brick at
    /// `o`, read from the 27 bricks around it (this one included).
    fn fill_signs(&self, lat: &Lattice, o: [i32; 3], sign: &mut Vec<bool>) {
        let g = &self.grid;
        let b = g.brick;
        let nb = g.nb as usize;
        let e = (b + 2) as usize;
        sign.clear();
        sign.resize(e * e * e, false);
        // Per neighbour brick: the layer below (−1), the brick's own samples (0), the layer
        // above (+1) along each axis.
        let span = |d: i32| match d {
            -1 => -1..=-1,
            0 => 0..=b - 1,
            _ => b..=b,
        };
        let bc = o.map(|c| c / b);
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let nc = [bc[0] + dx, bc[1] + dy, bc[2] + dz];
                    if nc.iter().any(|&c| c < 0 || c >= g.nb) {
                        continue;
                    }
                    let nid = nc[0] as usize + nb * (nc[1] as usize + nb * nc[2] as usize);
                    let bits = match lat.map[nid] {
                        OUTSIDE => continue,
                        INSIDE => None,
                        k => Some(&lat.bricks[(k - 2) as usize].bits),
                    };
                    let d = [dx, dy, dz].map(|c| c * b);
                    for k in span(dz) {
                        for j in span(dy) {
                            for i in span(dx) {
                                let l = (i + 1) as usize
                                    + e * ((j + 1) as usize + e * (k + 1) as usize);
                                sign[l] = match bits {
                                    // Virtual samples are outside (not set in the bits).
                                    None => !g.is_virtual([o[0] + i, o[1] + j, o[2] + k]),
                                    Some(bits) => {
                                        let m =
                                            (i - d[0] + b * (j - d[1] + b * (k - d[2]))) as usize;
                                        bits[m / 64] >> (m % 64) & 1 == 1
                                    }
                                };
                            }
                        }
                    }
                }
            }
        }
        debug_assert!((0..e * e * e).all(|l| {
            let c = [l % e, l / e % e, l / (e * e)].map(|c| c as i32 - 1);
            sign[l] == lat.inside([o[0] + c[0], o[1] + c[1], o[2] + c[2]])
        }));
    }

    /// Finds the cubes with surface that brick `id` (at `o`) owns, from `bufs.sign`: fills
    /// `bufs.cubes`, and `bufs.edges` / `bufs.edge_keys` with each crossing edge once.
    fn find_cubes(&self, lat: &Lattice, id: usize, o: [i32; 3], bufs: &mut ExtractBufs) {
        let g = &self.grid;
        let b = g.brick;
        let e = (b + 2) as usize;
        let ExtractBufs {
            sign,
            rows,
            edge_index,
            edges,
            edge_keys,
            cubes,
        } = bufs;
        let table = cases();
        let edge_slot = |p: [i32; 3], axis: usize| {
            let l = [0, 1, 2].map(|a| (p[a] - o[a] + 1) as usize);
            axis + 3 * (l[0] + e * (l[1] + e * l[2]))
        };
        // Every entry is `u32::MAX` between bricks (reset below).
        if edge_index.len() < 3 * e * e * e {
            edge_index.resize(3 * e * e * e, u32::MAX);
        }
        edges.clear();
        edge_keys.clear();
        cubes.clear();
        let upper = [0, 1, 2].map(|a| (b - 1).min(g.n[a] - 1 - o[a]));
        // Per row of samples along x: 0 all outside, 1 all inside, 2 mixed.
        rows.clear();
        rows.extend(sign.chunks_exact(e).map(|r| {
            if r.iter().all(|&v| v) {
                1u8
            } else if r.iter().all(|&v| !v) {
                0
            } else {
                2
            }
        }));
        for k in -1..=upper[2] {
            for j in -1..=upper[1] {
                // The four rows of this row of cubes; all alike and not mixed: no surface.
                let r = [(j, k), (j + 1, k), (j, k + 1), (j + 1, k + 1)]
                    .map(|(y, z)| (y + 1) as usize * e + (z + 1) as usize * e * e);
                let st = r.map(|l| rows[l / e]);
                if st[0] != 2 && st.iter().all(|&v| v == st[0]) {
                    continue;
                }
                // Corner bits of the cubes' x = i face: bits 0, 2, 4, 6 of the case.
                let face = |x: usize| {
                    sign[r[0] + x] as usize
                        | (sign[r[1] + x] as usize) << 2
                        | (sign[r[2] + x] as usize) << 4
                        | (sign[r[3] + x] as usize) << 6
                };
                let mut left = face(0);
                for i in -1..=upper[0] {
                    let q = [o[0] + i, o[1] + j, o[2] + k];
                    let right = face((i + 2) as usize);
                    let mask = left | right << 1;
                    left = right;
                    if mask == 0 || mask == 255 {
                        continue;
                    }
                    let border = [i, j, k].iter().any(|&c| c < 0 || c >= b - 1);
                    if border && lat.owner(q) != Some(id) {
                        continue;
                    }
                    let case = &table[mask];
                    let mut local = [u32::MAX; 12];
                    for (ei, comp) in case.component.iter().enumerate() {
                        if *comp == 255 {
                            continue;
                        }
                        let (c0, c1) = edge_corners(ei as u8);
                        let p = add(q, OFFS[c0]);
                        let axis = (c0 ^ c1).trailing_zeros() as usize;
                        let slot = &mut edge_index[edge_slot(p, axis)];
                        if *slot == u32::MAX {
                            *slot = edges.len() as u32;
                            edges.push(EdgeRec {
                                p,
                                axis,
                                inside_low: mask >> c0 & 1 == 1,
                            });
                            edge_keys.push(point_key(p) << 2 | axis as u64);
                        }
                        local[ei] = *slot;
                    }
                    cubes.push((q, mask, local));
                }
            }
        }
        for r in edges.iter() {
            edge_index[edge_slot(r.p, r.axis)] = u32::MAX;
        }
    }

    /// Marching cubes: the brick's triangles over the edges' crossings `pos` (normals `nrm`).
    fn marching_out(
        &self,
        brick: Option<&Brick>,
        o: [i32; 3],
        bufs: &ExtractBufs,
        pos: &[[f64; 3]],
        nrm: &[[f64; 3]],
    ) -> BrickOut {
        let b = self.grid.brick;
        let table = cases();
        let mut out = BrickOut {
            colors: self.colors_at(brick, pos),
            positions: pos.iter().map(|p| p.map(|c| c as f32)).collect(),
            normals: nrm.iter().map(|p| p.map(|c| c as f32)).collect(),
            ..BrickOut::default()
        };
        // Most cases are one or two triangles (no regrowth in the common case).
        out.tris.reserve(2 * bufs.cubes.len());
        out.shared.reserve(bufs.edges.len());
        // An edge is this brick's alone when its four cubes are inner cubes of the
        // brick (every corner sample in it: only this brick makes them). Along the
        // edge its lower end is such a cube's lower corner, across it the lower end
        // is a cube's lower or upper corner.
        for (v, e) in bufs.edges.iter().enumerate() {
            let inner = (0..3).all(|a| {
                let c = e.p[a] - o[a];
                c >= i32::from(a != e.axis) && c <= b - 2
            });
            if !inner {
                out.shared.push((v as u32, bufs.edge_keys[v]));
            }
        }
        for (_, mask, local) in bufs.cubes.iter() {
            let case = &table[*mask];
            for k in 0..case.polygons() {
                triangulate(&mut out, case.polygon(k), local, pos, nrm);
            }
        }
        out
    }

    /// Dual contouring: one vertex per polygon (split where a polygon crosses a face
    /// twice, see `DualCase`), one quad per crossing lower edge.
    fn dual_out(
        &self,
        lat: &Lattice,
        brick: Option<&Brick>,
        o: [i32; 3],
        bufs: &ExtractBufs,
        pos: &[[f64; 3]],
        nrm: &[[f64; 3]],
    ) -> BrickOut {
        let dual = table::dual_cases();
        let mut out = BrickOut::default();
        let mut ge = brick.map(|b| GradEval::new(&b.tape));
        let mut pts = Vec::new();
        let mut ns = Vec::new();
        let mut dc_pos = Vec::new();
        let merged = match (self.adaptive, ge.as_mut()) {
            (Some(t), Some(ge)) => self.collapse(ge, o, &bufs.sign, &bufs.cubes, pos, nrm, t),
            _ => KeyMap::default(),
        };
        for (q, mask, local) in bufs.cubes.iter() {
            let case = &dual[*mask];
            let key = point_key(*q) << 3;
            if let Some(&(rep, x, n)) = merged.get(&key) {
                if rep == key {
                    dc_pos.push(x);
                    out.keys.push(key);
                    out.positions.push(x.map(|c| c as f32));
                    out.normals.push(n.map(|c| c as f32));
                } else {
                    out.aliases.push((key, rep));
                }
            }
            let (lo, hi) = self.vertex_box(*q);
            for (k, poly) in case.polygons.iter().enumerate() {
                if merged.contains_key(&key) {
                    break;
                }
                pts.clear();
                ns.clear();
                let mut avg = [0.0; 3];
                for &ei in poly {
                    let v = local[ei as usize] as usize;
                    pts.push(pos[v]);
                    ns.push(nrm[v]);
                    for c in 0..3 {
                        avg[c] += nrm[v][c];
                    }
                }
                let mut x = qef::solve(&pts, &ns, lo, hi);
                if let Some(ge) = ge.as_mut() {
                    x = self.snap(ge, x, lo, hi);
                }
                dc_pos.push(x);
                out.keys.push(point_key(*q) << 3 | k as u64);
                out.positions.push(x.map(|c| c as f32));
                out.normals.push(norm(avg).map(|c| c as f32));
            }
            for axis in 0..3 {
                let e0 = edge_between(0, 1 << axis) as usize;
                if case.at[e0][0] == 255 {
                    continue;
                }
                let ring = edge_ring(lat, *q, *mask, axis);
                if let [a, b, c, d] = ring[..] {
                    out.quads.push([a, b, c, d]);
                    continue;
                }
                // A chord ends here: a fan around the edge's crossing (a new vertex, so that
                // no new edge can duplicate an existing one).
                let v = local[e0] as usize;
                let ck = 1 << 63 | point_key(*q) << 2 | axis as u64;
                dc_pos.push(pos[v]);
                out.keys.push(ck);
                out.positions.push(pos[v].map(|c| c as f32));
                out.normals.push(nrm[v].map(|c| c as f32));
                for j in 0..ring.len() {
                    out.triangles
                        .push([ck, ring[j], ring[(j + 1) % ring.len()]]);
                }
            }
        }
        out.colors = self.colors_at(brick, &dc_pos);
        out
    }

    /// The box a dual-contouring vertex of cube `q` may lie in.
    fn vertex_box(&self, q: [i32; 3]) -> ([f64; 3], [f64; 3]) {
        let g = &self.grid;
        // Vertices may leave their cube by up to a cell. A crease (a groove of a union)
        // can run outside the cubes whose crossings see both of its sheets, through cubes
        // whose samples all lie inside. On M2's necks with half a cell, the groove was cut
        // off by 0.25 cell at depth 7.
        // Not on the box: cap vertices stay on its faces.
        let slack = if g.is_virtual(q) || g.is_virtual(add(q, [1, 1, 1])) {
            0.0
        } else {
            DC_SLACK
        };
        let lo = [0, 1, 2].map(|k| g.coord(k, q[k]) - slack * g.h[k]);
        let hi = [0, 1, 2].map(|k| g.coord(k, q[k] + 1) + slack * g.h[k]);
        (lo, hi)
    }
}

/// Marching cubes: polygon `poly` (edge ids of a cube with local edge indices `local`) as
/// triangles in `out`.
fn triangulate(
    out: &mut BrickOut,
    poly: &[u8],
    local: &[u32; 12],
    pos: &[[f64; 3]],
    nrm: &[[f64; 3]],
) {
    let key = |e: u8| local[e as usize];
    let p = |e: u8| pos[local[e as usize] as usize];
    let n = poly.len();
    if n == 3 {
        out.tris.push([key(poly[0]), key(poly[1]), key(poly[2])]);
        return;
    }
    // A fan whose diagonals avoid the cube's faces: a diagonal on a face
    // would be a diagonal of the neighbouring cube too (a non-manifold edge).
    let fan_ok =
        |apex: usize| (2..n - 1).all(|j| !table::share_face(poly[apex], poly[(apex + j) % n]));
    let mut apexes: Vec<usize> = (0..n).filter(|&a| fan_ok(a)).collect();
    if n == 4 && apexes.len() == 2 {
        // The shorter diagonal.
        if dist2(p(poly[1]), p(poly[3])) < dist2(p(poly[0]), p(poly[2])) {
            apexes.swap(0, 1);
        }
    }
    if let Some(&a) = apexes.first() {
        for j in 1..n - 1 {
            out.tris.push([
                key(poly[a]),
                key(poly[(a + j) % n]),
                key(poly[(a + j + 1) % n]),
            ]);
        }
        return;
    }
    // No such fan: a centre vertex.
    let mut c = [0.0; 3];
    let mut nc = [0.0; 3];
    for &e in poly {
        let v = local[e as usize] as usize;
        for d in 0..3 {
            c[d] += pos[v][d] / n as f64;
            nc[d] += nrm[v][d];
        }
    }
    let ck = out.positions.len() as u32;
    out.positions.push(c.map(|x| x as f32));
    out.normals.push(norm(nc).map(|x| x as f32));
    if !out.colors.is_empty() {
        let col = out.colors[local[poly[0] as usize] as usize];
        out.colors.push(col);
    }
    for j in 0..n {
        out.tris.push([ck, key(poly[j]), key(poly[(j + 1) % n])]);
    }
}

/// Dual contouring: the vertex keys around the lower `axis` edge of cube `q` (case `mask`),
/// counter-clockwise from outside. The cubes around the edge in order; in each, first the
/// polygon holding the segment on the face shared with the previous cube, then, when the
/// edge ends a chord there, the one on the face shared with the next.
fn edge_ring(lat: &Lattice, q: [i32; 3], mask: usize, axis: usize) -> Vec<u64> {
    let dual = table::dual_cases();
    let c1 = 1usize << axis;
    let (bx, cx) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut eb = [0; 3];
    eb[bx] = 1;
    let mut ec = [0; 3];
    ec[cx] = 1;
    let mut ring: Vec<u64> = Vec::with_capacity(4);
    for (slot, d) in [[0, 0, 0], eb, add(eb, ec), ec].iter().enumerate() {
        let qn = [q[0] - d[0], q[1] - d[1], q[2] - d[2]];
        let m = if slot == 0 { mask } else { lat.case_at(qn) };
        let lo_c = (d[0] | d[1] << 1 | d[2] << 2) as usize;
        let e = edge_between(lo_c, lo_c | c1);
        let (prev_ax, next_ax) = if slot % 2 == 0 { (cx, bx) } else { (bx, cx) };
        let ef = table::edge_faces(e);
        let id = |ax: usize| {
            let f = (2 * ax + d[ax] as usize) as u8;
            let s = usize::from(ef[1] == f);
            dual[m].at[e as usize][s] as u64
        };
        let (a, b) = (id(prev_ax), id(next_ax));
        ring.push(point_key(qn) << 3 | a);
        if b != a {
            ring.push(point_key(qn) << 3 | b);
        }
    }
    if mask & 1 == 0 {
        ring.reverse();
    }
    ring
}
