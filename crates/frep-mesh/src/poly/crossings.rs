//! Crossings on the lattice edges: Illinois regula falsi on each edge,
//! batched over a brick's edges, their normals, and the Newton steps that
//! move a dual-contouring vertex onto the surface.

use std::cell::Cell;

use frep_core::eval::batch::BatchEval;
use frep_core::eval::grad::GradEval;

use super::extract::EdgeRec;
use super::grid::{norm, Lattice};
use super::octree::{with_batch, zeroed, Brick};
use super::settings::Method;
use super::{Ctx, EDGE_MARGIN, NORMAL_STEP, ROOT_STEPS, ROOT_TOL, SNAP_STEPS};

/// The point and bracket buffers of [`Ctx::crossings`], kept per thread between bricks.
#[derive(Default)]
pub(super) struct CrossingBufs {
    pub(super) xs: Vec<f64>,
    pub(super) ys: Vec<f64>,
    pub(super) zs: Vec<f64>,
    pub(super) f: Vec<f64>,
    pub(super) ts: Vec<f64>,
    pub(super) last: Vec<f64>,
    pub(super) active: Vec<usize>,
    /// Per edge: (t inside, f there, t outside, f there, side of the last move).
    pub(super) st: Vec<(f64, f64, f64, f64, i8)>,
}

thread_local! {
    pub(super) static CROSSING_BUFS: Cell<CrossingBufs> = Cell::new(CrossingBufs::default());
}

impl Ctx<'_> {
    /// Finds the crossings of `edges` (positions and outward unit normals).
    pub(super) fn crossings(
        &self,
        lat: &Lattice,
        brick: Option<&Brick>,
        edges: &[EdgeRec],
    ) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        let g = &self.grid;
        let mut pos = vec![[0.0; 3]; edges.len()];
        let mut nrm = vec![[0.0; 3]; edges.len()];
        // Real edges to refine: (edge index, inside point, outside point).
        let mut todo: Vec<(usize, [f64; 3], [f64; 3])> = Vec::with_capacity(edges.len());
        for (i, e) in edges.iter().enumerate() {
            let mut hi = e.p;
            hi[e.axis] += 1;
            let (pin, pout) = if e.inside_low { (e.p, hi) } else { (hi, e.p) };
            if g.is_virtual(pout) {
                pos[i] = g.point(pout);
                let mut n = [0.0; 3];
                n[e.axis] = if e.inside_low { 1.0 } else { -1.0 };
                nrm[i] = n;
                continue;
            }
            let (a, b) = (g.point(pin), g.point(pout));
            if self.method == Method::MarchingCubes || brick.is_none() {
                let (fa, fb) = (lat.value(pin), lat.value(pout));
                let t = if fa >= 0.0 && fb < 0.0 {
                    fa / (fa - fb)
                } else {
                    0.5
                };
                let t = t.clamp(EDGE_MARGIN, 1.0 - EDGE_MARGIN);
                pos[i] = [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
            } else {
                todo.push((i, a, b));
            }
        }
        let Some(brick) = brick.filter(|_| !todo.is_empty()) else {
            return (pos, nrm);
        };
        with_batch(&brick.tape, |be| {
            self.crossings_with(brick, be, todo, pos, nrm)
        })
    }

    /// [`Ctx::crossings`] of the edges `todo` to refine, with the brick's evaluator.
    fn crossings_with(
        &self,
        brick: &Brick,
        be: &mut BatchEval,
        todo: Vec<(usize, [f64; 3], [f64; 3])>,
        mut pos: Vec<[f64; 3]>,
        mut nrm: Vec<[f64; 3]>,
    ) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
        // This thread's buffers: no allocation per brick (the allocator's locks are shared).
        let mut bufs = CROSSING_BUFS.with(Cell::take);
        self.roots(be, &todo, &mut bufs, &mut pos);
        self.normals(brick, be, &todo, &mut bufs, &pos, &mut nrm);
        CROSSING_BUFS.with(|c| c.set(bufs));
        (pos, nrm)
    }

    /// Illinois regula falsi on the edges `todo`, all of them in one batch per step: their
    /// crossings into `pos`.
    fn roots(
        &self,
        be: &mut BatchEval,
        todo: &[(usize, [f64; 3], [f64; 3])],
        bufs: &mut CrossingBufs,
        pos: &mut [[f64; 3]],
    ) {
        let n = todo.len();
        let CrossingBufs {
            xs,
            ys,
            zs,
            f,
            ts,
            last,
            active,
            st,
        } = bufs;
        for v in [&mut *xs, &mut *ys, &mut *zs, &mut *f] {
            zeroed(v, 2 * n);
        }
        for (j, (_, a, b)) in todo.iter().enumerate() {
            (xs[j], ys[j], zs[j]) = (a[0], a[1], a[2]);
            (xs[n + j], ys[n + j], zs[n + j]) = (b[0], b[1], b[2]);
        }
        be.eval(xs, ys, zs, self.inputs, f);
        // Brackets: t0 inside (f0 ≥ 0), t1 outside; side of the last move for Illinois.
        st.clear();
        st.extend((0..n).map(|j| (0.0, f[j], 1.0, f[n + j], 0)));
        let next_t = |s: &(f64, f64, f64, f64, i8)| {
            let (t0, f0, t1, f1, _) = *s;
            if f0.is_finite() && f1.is_finite() && f0 >= 0.0 && f1 < 0.0 {
                let t = t0 + (t1 - t0) * f0 / (f0 - f1);
                if t > t0 && t < t1 {
                    return t;
                }
            }
            0.5 * (t0 + t1)
        };
        xs.truncate(n);
        ys.truncate(n);
        zs.truncate(n);
        f.truncate(n);
        zeroed(ts, n);
        // Edges still searched: an edge whose estimate moved by less than `ROOT_TOL` of the
        // edge (or that hit `f = 0`) is done and leaves the batch.
        active.clear();
        active.extend(0..n);
        last.clear();
        last.resize(n, f64::NAN);
        for _ in 0..ROOT_STEPS {
            let m = active.len();
            if m == 0 {
                break;
            }
            for (k, &j) in active.iter().enumerate() {
                let (a, b) = (todo[j].1, todo[j].2);
                let t = next_t(&st[j]);
                ts[k] = t;
                xs[k] = a[0] + t * (b[0] - a[0]);
                ys[k] = a[1] + t * (b[1] - a[1]);
                zs[k] = a[2] + t * (b[2] - a[2]);
            }
            be.eval(&xs[..m], &ys[..m], &zs[..m], self.inputs, &mut f[..m]);
            for (k, &j) in active.iter().enumerate() {
                let s = &mut st[j];
                if f[k] >= 0.0 {
                    *s = (ts[k], f[k], s.2, if s.4 == 1 { 0.5 * s.3 } else { s.3 }, 1);
                } else {
                    let f1 = if f[k].is_nan() { s.3 } else { f[k] };
                    *s = (s.0, if s.4 == -1 { 0.5 * s.1 } else { s.1 }, ts[k], f1, -1);
                }
            }
            let mut k = 0;
            active.retain(|&j| {
                let done = f[k] == 0.0 || (ts[k] - last[j]).abs() < ROOT_TOL;
                last[j] = ts[k];
                k += 1;
                !done
            });
        }
        for (j, (i, a, b)) in todo.iter().enumerate() {
            let t = next_t(&st[j]).clamp(EDGE_MARGIN, 1.0 - EDGE_MARGIN);
            pos[*i] = [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]));
        }
    }

    /// Normals at the crossings `pos` of the edges `todo`: central differences at
    /// `NORMAL_STEP` of a cell, all crossings of the brick in one batch (six points each).
    /// Where they vanish or are not finite (a flat or singular field there), forward-mode
    /// differentiation.
    fn normals(
        &self,
        brick: &Brick,
        be: &mut BatchEval,
        todo: &[(usize, [f64; 3], [f64; 3])],
        bufs: &mut CrossingBufs,
        pos: &[[f64; 3]],
        nrm: &mut [[f64; 3]],
    ) {
        let n = todo.len();
        let CrossingBufs { xs, ys, zs, f, .. } = bufs;
        let hs = self.grid.h.map(|c| c * NORMAL_STEP);
        for v in [&mut *xs, &mut *ys, &mut *zs, &mut *f] {
            zeroed(v, 6 * n);
        }
        for (j, (i, _, _)) in todo.iter().enumerate() {
            let p = pos[*i];
            for o in 0..6 {
                let (ax, k) = (o / 2, 6 * j + o);
                let mut q = p;
                q[ax] += if o % 2 == 0 { hs[ax] } else { -hs[ax] };
                (xs[k], ys[k], zs[k]) = (q[0], q[1], q[2]);
            }
        }
        be.eval(xs, ys, zs, self.inputs, f);
        let mut ge: Option<GradEval> = None;
        for (j, (i, _, _)) in todo.iter().enumerate() {
            let v = &f[6 * j..6 * j + 6];
            let d = [0, 1, 2].map(|k| -(v[2 * k] - v[2 * k + 1]) / hs[k]);
            let mut nv = norm(d);
            if nv == [0.0; 3] {
                let p = pos[*i];
                let gr = ge.get_or_insert_with(|| GradEval::new(&brick.tape)).eval(
                    p[0],
                    p[1],
                    p[2],
                    self.inputs,
                );
                nv = norm([-gr.dx, -gr.dy, -gr.dz]);
            }
            nrm[*i] = nv;
        }
    }

    /// Moves a dual-contouring vertex onto the surface by Newton steps along the gradient,
    /// staying in the cube `[lo, hi]`. Without it, the vertex would sit off the surface where
    /// the QEF minimizer had to be clamped (a crease that leaves the cube), or where the
    /// tangent planes disagree (curvature). On a crease `f ≈ 0` already and nothing moves.
    pub(super) fn snap(
        &self,
        ge: &mut GradEval,
        x: [f64; 3],
        lo: [f64; 3],
        hi: [f64; 3],
    ) -> [f64; 3] {
        let mut x = x;
        for _ in 0..SNAP_STEPS {
            let g = ge.eval(x[0], x[1], x[2], self.inputs);
            let len2 = g.dx * g.dx + g.dy * g.dy + g.dz * g.dz;
            if !(len2 > 0.0 && len2.is_finite() && g.v.is_finite()) || g.v == 0.0 {
                break;
            }
            let s = g.v / len2;
            let y = [
                (x[0] - s * g.dx).clamp(lo[0], hi[0]),
                (x[1] - s * g.dy).clamp(lo[1], hi[1]),
                (x[2] - s * g.dz).clamp(lo[2], hi[2]),
            ];
            if y == x {
                break;
            }
            x = y;
        }
        x
    }
}
