//! Tiles solved in closed form where the model is a set expression over
//! quadrics ([`Csg`]): the rays set up in blocks, the sure outcomes recorded.

use crate::camera::{Camera, Projection};
use crate::image::{fill_background, Hit, ShadeIn, Shader, SPAN};
use crate::tiles::Tile;

use super::caster::{CastStats, ModelCaster};
use super::csg::{Csg, Lanes, Solved, Work, BLOCK, ENTRY};
use super::rays::{
    entry_face, ortho_lanes, per_dir, put_ray_lanes, ray_lanes, RayLanes, SETUP_LANES,
};
use super::scratch::Scratch;
use super::tile::TileCtx;

impl ModelCaster {
    /// Casts and shades `tile` in closed form on the model's set expression
    /// ([`ModelCaster::csg`]), [`BLOCK`] rays at a time. It writes straight
    /// into the tile's `rows` of RGBA bytes, with no hit records. It serves
    /// [`render_with`] where no colours and no ambient occlusion are due.
    ///
    /// Returns `false` where a ray fails a check of [`Csg::solve`], is
    /// inside the solid at the eye, or the render was cancelled. The tile is
    /// then left to the general caster, its rows partly written. The rays'
    /// entry into the model box is tried as a hit only where
    /// [`ModelCaster::may_hold_at_entry`] cannot rule it out.
    ///
    /// [`render_with`]: crate::raycast::render_with
    pub(super) fn closed_form_tile(
        &self,
        csg: &Csg,
        camera: &Camera,
        shader: &Shader,
        tile: &Tile,
        rows: &mut [&mut [u8]],
    ) -> bool {
        if self.cancelled() {
            return false;
        }
        let mut sc = self.take_scratch();
        let mut stats = CastStats {
            interval_evals: 1,
            ..CastStats::default()
        };
        let done = self.closed_form_rows(csg, camera, shader, tile, rows, &mut sc, &mut stats);
        self.put_scratch(sc);
        self.add_stats(&stats);
        done
    }

    /// [`ModelCaster::closed_form_tile`] with a scratch.
    // Long on purpose: the loop that packs a tile's rays into lanes, block by block. Its
    // copies of known length are written out so the compiler emits no call; split, that
    // layout would rest on inlining.
    // Kept whole; no split was measured.
    #[allow(clippy::too_many_arguments)]
    fn closed_form_rows(
        &self,
        csg: &Csg,
        camera: &Camera,
        shader: &Shader,
        tile: &Tile,
        rows: &mut [&mut [u8]],
        sc: &mut Scratch,
        stats: &mut CastStats,
    ) -> bool {
        const L: usize = SETUP_LANES;
        let rm = camera.rays(tile.width, tile.height);
        // (Every pixel below is written whole, alpha 255 included.)
        let Some(bx) = self.live_tile_box(camera, &rm, tile, sc) else {
            stats.empty_tiles += 1;
            for (row, y) in rows.iter_mut().zip(tile.y0..) {
                fill_background(shader.background(y), row);
            }
            return true;
        };
        // Whether any ray may hit where it enters the box (else that
        // candidate is not checked).
        let entry = self.may_hold_at_entry(camera, &bx, sc, stats);
        let forward = camera.forward;
        let fixed = matches!(camera.projection, Projection::Orthographic { .. })
            .then(|| per_dir(forward, forward));
        let mut cf = sc.closed_form.take().unwrap_or_default();
        // (Orthographic: the origins' per-column terms, which every row
        // shares, once per tile.)
        let cols = &mut sc.columns;
        if fixed.is_some() {
            cols.resize((tile.x1 - tile.x0) as usize, 0.0);
            rm.ortho_columns(tile.x0, cols);
        }
        let (lanes, work, solved) = &mut *cf;
        // (Every ray of an orthographic view has the camera's direction:
        // the direction arrays are written once here, not per ray.)
        lanes.dir = fixed.map(|(_, dz, _)| dz);
        if let Some((_, dz, _)) = fixed {
            for (d, v) in lanes.d.iter_mut().zip(dz) {
                *d = [v; BLOCK];
            }
        }
        // Normals and positions of a partial pass (a whole one is read
        // where the solver wrote it).
        let mut shade = ([[0.0; SPAN]; 3], [[0.0; SPAN]; 3]);
        // The block's runs of pixels: (row, first column, first lane,
        // length).
        let mut runs = [(0u32, 0u32, 0usize, 0usize); BLOCK];
        let r = &mut RayLanes::default();
        let (mut nruns, mut n) = (0, 0);
        let mut ok = true;
        'rows: for py in tile.y0..tile.y1 {
            let mut x = tile.x0;
            while x < tile.x1 {
                let len = ((tile.x1 - x) as usize).min(BLOCK);
                if n + len > BLOCK {
                    ok = self.closed_form_block(
                        (csg, entry),
                        tile,
                        shader,
                        rows,
                        (lanes, work, solved),
                        &runs[..nruns],
                        n,
                        &mut shade,
                        stats,
                    );
                    if !ok {
                        break 'rows;
                    }
                    (nruns, n) = (0, 0);
                }
                let mut j = 0;
                while j < len {
                    let (k, m) = (n + j, L.min(len - j));
                    if let (Some((c, _, inv)), true) = (fixed, m == L) {
                        // (Straight into the lanes: origins and depths.)
                        let c0 = (x - tile.x0) as usize + j;
                        let uk = cols[c0..c0 + L].try_into().expect("SETUP_LANES columns");
                        ortho_lanes(&self.bounds, (c, inv), &rm, (uk, py), lanes, k);
                        j += L;
                        continue;
                    }
                    ray_lanes(&self.bounds, forward, fixed, &rm, (x + j as u32, py), r);
                    if m == L {
                        // (A copy of known length: no call. The other
                        // case is a function of its own, so that the
                        // compiler does not merge the two into one copy
                        // of either length, a call.)
                        for a in 0..3 {
                            lanes.o[a][k..k + L].copy_from_slice(&r.o[a]);
                            lanes.d[a][k..k + L].copy_from_slice(&r.dz[a]);
                        }
                        lanes.z0[k..k + L].copy_from_slice(&r.z0);
                        lanes.z1[k..k + L].copy_from_slice(&r.z1);
                    } else {
                        put_ray_lanes(lanes, r, k, m);
                    }
                    j += L;
                }
                runs[nruns] = (py, x, n, len);
                nruns += 1;
                n += len;
                x += len as u32;
            }
        }
        if ok && n > 0 {
            ok = self.closed_form_block(
                (csg, entry),
                tile,
                shader,
                rows,
                (lanes, work, solved),
                &runs[..nruns],
                n,
                &mut shade,
                stats,
            );
        }
        sc.closed_form = Some(cf);
        ok
    }

    /// Solves the `n` rays of a block of [`ModelCaster::closed_form_rows`]
    /// and shades its `runs` of pixels; `false` where a ray is unsure.
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn closed_form_block(
        &self,
        (csg, entry): (&Csg, bool),
        tile: &Tile,
        shader: &Shader,
        rows: &mut [&mut [u8]],
        (lanes, work, solved): (&mut Lanes, &mut Work, &mut Solved),
        runs: &[(u32, u32, usize, usize)],
        n: usize,
        (sn, sp): &mut ([[f64; SPAN]; 3], [[f64; SPAN]; 3]),
        stats: &mut CastStats,
    ) -> bool {
        csg.solve(lanes, n, work, solved, entry);
        let live = solved.live;
        if live & !solved.sure != 0 {
            return false;
        }
        stats.exact_rays += u64::from(live.count_ones());
        // Hits at the entry into the box: the box face's normal.
        let mut entries = solved.entry;
        while entries != 0 {
            let k = entries.trailing_zeros() as usize;
            entries &= entries - 1;
            let p = [solved.p[0][k], solved.p[1][k], solved.p[2][k]];
            match (solved.z[k] > 0.0)
                .then(|| entry_face(&self.bounds, &p))
                .flatten()
            {
                Some(f) => (0..3).for_each(|a| solved.n[a][k] = f[a]),
                None => return false,
            }
        }
        // Positions are read in perspective views only.
        let persp = shader.needs_positions();
        for &(py, x, first, len) in runs {
            let row = &mut rows[(py - tile.y0) as usize];
            let bg = shader.background(py);
            let mut c = 0;
            while c < len {
                let (m, k) = ((len - c).min(SPAN), first + c);
                let o = 4 * (x - tile.x0) as usize + 4 * c;
                let hit = ((solved.hit >> k) & (u64::MAX >> (64 - m))) as u32;
                if hit == 0 {
                    fill_background(bg, &mut row[o..o + 4 * m]);
                    c += m;
                    continue;
                }
                let span = (m == SPAN).then(|| (span_at(&solved.n, k), span_at(&solved.p, k)));
                let (n, p) = match span {
                    // A whole pass: read where the solver wrote (no copy).
                    Some((Some(n), Some(p))) => (n, p),
                    _ => {
                        for a in 0..3 {
                            sn[a][..m].copy_from_slice(&solved.n[a][k..k + m]);
                            if persp {
                                sp[a][..m].copy_from_slice(&solved.p[a][k..k + m]);
                            }
                        }
                        (sn.each_ref(), sp.each_ref())
                    }
                };
                // (The default material, fully open: no colours, no
                // occlusion here.)
                let lanes = ShadeIn {
                    n,
                    p,
                    material: None,
                };
                shader.shade_lanes(bg, lanes, hit, &mut row[o..o + 4 * m]);
                c += m;
            }
        }
        true
    }
}

/// Lanes `k..k + SPAN` of three arrays of a block, where they lie within
/// it.
fn span_at(v: &[[f64; BLOCK]; 3], k: usize) -> Option<[&[f64; SPAN]; 3]> {
    let [a, b, c] = v.each_ref().map(|v| v[k..].first_chunk::<SPAN>());
    Some([a?, b?, c?])
}

impl<'a> TileCtx<'a> {
    /// Solves the tile's live rays in closed form on the model's set
    /// expression ([`ModelCaster::csg`]), [`BLOCK`] at a time. The hits and
    /// misses that check out are final. The other rays are left as they
    /// were.
    pub(super) fn closed_form(&mut self, csg: &Csg) {
        let mut cf = self.sc.closed_form.take().unwrap_or_default();
        let (lanes, work, solved) = &mut *cf;
        // (Each lane's own direction: the arrays may come from a view
        // whose rays shared one.)
        lanes.dir = None;
        let mut idx = [0usize; BLOCK];
        let mut n = 0;
        for i in 0..self.sc.rays.len() {
            let (z0, z1) = (self.sc.z0s[i], self.sc.z1s[i]);
            if z0 > z1 {
                continue;
            }
            let r = &self.sc.rays[i];
            for a in 0..3 {
                lanes.o[a][n] = r.origin[a];
                lanes.d[a][n] = r.dz[a];
            }
            (lanes.z0[n], lanes.z1[n]) = (z0, z1);
            idx[n] = i;
            n += 1;
            if n == BLOCK {
                csg.solve(lanes, n, work, solved, true);
                self.take_solved(solved, &idx[..n]);
                n = 0;
            }
        }
        if n > 0 {
            csg.solve(lanes, n, work, solved, true);
            self.take_solved(solved, &idx[..n]);
        }
        self.sc.closed_form = Some(cf);
    }

    /// Records the sure outcomes of [`Csg::solve`] for rays `idx`.
    fn take_solved(&mut self, s: &Solved, idx: &[usize]) {
        for (k, &i) in idx.iter().enumerate() {
            if (s.sure >> k) & 1 == 0 {
                continue;
            }
            let z = s.z[k];
            if z == f64::INFINITY {
                self.sc.resolve(i);
                self.stats.exact_rays += 1;
                continue;
            }
            let r = &self.sc.rays[i];
            let position = [s.p[0][k], s.p[1][k], s.p[2][k]];
            let normal = if s.leaf[k] == ENTRY {
                // Inside where it enters the box: the box's face, as a
                // direct hit there gets (none at the eye: left alone).
                match (z > 0.0).then(|| self.entry_face(&position)).flatten() {
                    Some(n) => n,
                    None => continue,
                }
            } else {
                [s.n[0][k], s.n[1][k], s.n[2][k]]
            };
            let hit = Hit {
                t: z / r.c,
                position,
                normal,
                color: None,
            };
            self.set_hit(i, hit);
            self.stats.exact_rays += 1;
        }
    }
}
