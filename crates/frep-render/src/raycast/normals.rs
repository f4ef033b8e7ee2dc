//! Hits and their shading inputs: normals (the gradient, central
//! differences, the model box's face) and attribute colours.

use frep_core::eval::batch::BatchEval;
use frep_core::eval::grad::Grad;
use frep_core::eval::interval::{Interval, IntervalEval};

use crate::camera::{dot, Aabb};
use crate::image::Hit;

use super::frustum::iv;
use super::rays::{entry_face, RayInfo};
use super::tile::TileCtx;

impl<'a> TileCtx<'a> {
    /// The hit of ray `i` at depth `z`; its normal is the model box face's
    /// where the solid is cut open there, else left for
    /// [`TileCtx::flush_normals`].
    pub(super) fn make_hit(&mut self, i: usize, z: f64, at_entry: bool) -> Hit {
        let r = self.sc.rays[i];
        let p = r.at_depth(z);
        let face = if at_entry && z > 0.0 {
            self.entry_face(&p)
        } else {
            None
        };
        let normal = match face {
            Some(n) => n,
            None => {
                self.sc.need_normal.push(i);
                [f64::NAN; 3]
            }
        };
        Hit {
            t: z / r.c,
            position: p,
            normal,
            color: None,
        }
    }

    /// Normals of the hits made since the last call: the gradient by
    /// forward-mode automatic differentiation ([`BatchEval::eval_grad`]),
    /// all hits in one batch (evaluator `e`); where it vanishes or is not
    /// finite, [`TileCtx::normal`].
    pub(super) fn flush_normals(&mut self, e: usize) {
        let sc = &mut *self.sc;
        if sc.need_normal.is_empty() {
            return;
        }
        let need = std::mem::take(&mut sc.need_normal);
        sc.set_points(need.len());
        let mut o = 0;
        for &i in &need {
            let Some(h) = &self.out[i] else { continue };
            [sc.xs[o], sc.ys[o], sc.zs[o]] = h.position;
            o += 1;
        }
        sc.np = o;
        self.stats.grad_evals += o as u64;
        sc.eval_grads(e, &self.caster.inputs);
        let grads = std::mem::take(&mut self.sc.grads);
        let mut j = 0;
        for &i in &need {
            let Some(h) = &self.out[i] else { continue };
            let g = grads[j];
            j += 1;
            let n = match unit([-g.dx, -g.dy, -g.dz]) {
                Some(n) => n,
                None => {
                    let (p, t) = (h.position, h.t);
                    let r = self.sc.rays[i];
                    self.normal(e, &r, p, t * r.c)
                }
            };
            if let Some(h) = &mut self.out[i] {
                h.normal = n;
            }
        }
        self.sc.grads = grads;
        self.sc.need_normal = need;
        self.sc.need_normal.clear();
    }

    /// [`entry_face`] of the model box.
    pub(super) fn entry_face(&self, p: &[f64; 3]) -> Option<[f64; 3]> {
        entry_face(&self.caster.bounds, p)
    }

    /// The normal at `p` where the gradient vanishes or is not finite: a
    /// field like `(r² − |p|²)³` on its surface, or a kink. It is the first
    /// of the central differences at half, 2 and 8 pixel footprints that
    /// does not vanish. Failing those, it is the direction back along the
    /// ray.
    fn normal(&mut self, e: usize, r: &RayInfo, p: [f64; 3], z: f64) -> [f64; 3] {
        let h = self.footprint(z).max(1e-9 * (1.0 + z.abs()));
        for scale in [0.5, 2.0, 8.0] {
            let d = h * scale;
            self.sc.clear_points();
            for k in 0..3 {
                for s in [d, -d] {
                    let mut q = p;
                    q[k] += s;
                    self.sc.push_point(q);
                }
            }
            self.stats.point_evals += 6;
            self.sc.eval_points(e, &self.caster.inputs);
            let v = &self.sc.vals;
            let n = [-(v[0] - v[1]), -(v[2] - v[3]), -(v[4] - v[5])];
            if let Some(n) = unit(n) {
                return n;
            }
        }
        [-r.dir[0], -r.dir[1], -r.dir[2]]
    }

    /// Attribute colours (`s[1..3]` as sRGB in `[0, 1]`) at the given hits.
    pub(super) fn colors(&mut self, hit_rays: &[usize]) {
        let Some(attr_tape) = &self.caster.attr_tape else {
            return;
        };
        if hit_rays.is_empty() {
            return;
        }
        let sc = &mut *self.sc;
        // Where the attributes are constant over the box of the hits (an
        // interval evaluation gives each a single value), that is every
        // hit's colour, without evaluating them point by point.
        let hull = hit_rays
            .iter()
            .filter_map(|&i| self.out[i].as_ref())
            .map(|h| Aabb::new(h.position, h.position))
            .reduce(|a, b| a.union(&b))
            .filter(|b| (0..3).all(|k| b.min[k] <= b.max[k]));
        if let Some(b) = hull {
            let ev = sc
                .attr_iv
                .get_or_insert_with(|| IntervalEval::new(attr_tape));
            let out = ev.eval_outputs(
                iv(b.min[0], b.max[0]),
                iv(b.min[1], b.max[1]),
                iv(b.min[2], b.max[2]),
                &self.caster.inputs,
            );
            self.stats.interval_evals += 1;
            let single = |r: &Interval| !r.nan && r.lo == r.hi && r.lo.is_finite();
            if out.len() >= 3 && out[..3].iter().all(single) {
                let c = [0, 1, 2].map(|k| out[k].lo.clamp(0.0, 1.0) as f32);
                for &i in hit_rays {
                    if let Some(h) = &mut self.out[i] {
                        h.color = Some(c);
                    }
                }
                return;
            }
        }
        sc.clear_points();
        for &i in hit_rays {
            let p = self.out[i].as_ref().map_or([0.0; 3], |h| h.position);
            sc.push_point(p);
        }
        let eval = sc.attr.get_or_insert_with(|| BatchEval::new(attr_tape));
        let mut outs = vec![Vec::new(); attr_tape.outputs.len()];
        self.stats.point_evals += hit_rays.len() as u64;
        let n = sc.np;
        eval.eval_outputs(
            &sc.xs[..n],
            &sc.ys[..n],
            &sc.zs[..n],
            &self.caster.inputs,
            &mut outs,
        );
        if outs.len() < 3 {
            return;
        }
        for (j, &i) in hit_rays.iter().enumerate() {
            let c = [outs[0][j], outs[1][j], outs[2][j]];
            if let Some(h) = &mut self.out[i] {
                if c.iter().all(|v| v.is_finite()) {
                    h.color = Some(c.map(|v| v.clamp(0.0, 1.0) as f32));
                }
            }
        }
    }
}

/// The squared length of a gradient.
#[inline]
pub(super) fn len2(g: &Grad) -> f64 {
    g.dx * g.dx + g.dy * g.dy + g.dz * g.dz
}

/// Squared lengths whose vector [`unit()`] scales by `1 / √l²`: normal finite
/// numbers (no component overflows or underflows in the sum).
pub(super) const NORMAL_LEN2: std::ops::Range<f64> = f64::MIN_POSITIVE..f64::MAX;

pub(super) fn unit(n: [f64; 3]) -> Option<[f64; 3]> {
    let l2 = dot(n, n);
    if NORMAL_LEN2.contains(&l2) {
        // The common case: one division (finite components, their squares
        // neither overflowing nor underflowing in sum).
        let k = 1.0 / l2.sqrt();
        return Some([n[0] * k, n[1] * k, n[2] * k]);
    }
    let l = l2.sqrt();
    if l > 0.0 && l.is_finite() {
        let u = [n[0] / l, n[1] / l, n[2] / l];
        u.iter().all(|v| v.is_finite()).then_some(u)
    } else if n.iter().all(|v| v.is_finite()) && n.iter().any(|&v| v != 0.0) {
        // Tiny components whose squares underflow: rescale first.
        let m = n.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        unit([n[0] / m, n[1] / m, n[2] / m])
    } else {
        None
    }
}
