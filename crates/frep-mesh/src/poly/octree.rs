//! The octree: nodes classified by interval arithmetic, pruned or
//! descended on a shortened tape, bricks evaluated in batches (with a
//! per-thread cache of batch evaluators).

use std::cell::Cell;
use std::hash::{Hash, Hasher};
use std::sync::Arc;

use frep_core::eval::batch::BatchEval;
use frep_core::eval::interval::IntervalEval;
use frep_core::hash::FastHasher;
use frep_core::simplify::{simplify, SimplifyMode};
use frep_core::Tape;

use super::crossings::{CrossingBufs, CROSSING_BUFS};
use super::grid::OFFS;
use super::settings::{MeshError, Method};
use super::{par_map, Ctx};

/// Batch evaluators compiled on this thread, by tape. Bricks mostly share a few shortened
/// tapes. Compiling one per brick (a copy of the tape, its register program and registers)
/// cost more than evaluating it.
#[derive(Default)]
struct BatchCache {
    /// (hash of the tape, its evaluator), most recently used last.
    pub(super) evals: Vec<(u64, BatchEval)>,
}

/// At most this many evaluators are kept per thread.
const BATCH_CACHE: usize = 16;

thread_local! {
    static BATCH_EVALS: Cell<BatchCache> = Cell::new(BatchCache::default());
}

/// Runs `f` with this thread's batch evaluator of `tape` (compiled on first use).
pub(super) fn with_batch<R>(tape: &Tape, f: impl FnOnce(&mut BatchEval) -> R) -> R {
    let mut cache = BATCH_EVALS.with(Cell::take);
    let mut hasher = FastHasher::default();
    tape.hash(&mut hasher);
    let h = hasher.finish();
    let evals = &mut cache.evals;
    match evals.iter().rposition(|(k, e)| *k == h && e.tape() == tape) {
        Some(i) => {
            let last = evals.len() - 1;
            evals.swap(i, last);
        }
        None => {
            if evals.len() >= BATCH_CACHE {
                evals.remove(0);
            }
            evals.push((h, BatchEval::new(tape)));
        }
    }
    let r = f(&mut evals.last_mut().expect("pushed above").1);
    BATCH_EVALS.with(|c| c.set(cache));
    r
}

/// `v` as `n` zeros, reusing its capacity.
pub(super) fn zeroed(v: &mut Vec<f64>, n: usize) {
    v.clear();
    v.resize(n, 0.0);
}

/// An evaluated brick.
pub(super) struct Brick {
    pub(super) origin: [i32; 3],
    pub(super) tape: Arc<Tape>,
    /// Inside bits of its `brick³` samples.
    pub(super) bits: Vec<u64>,
    /// Sample values (the uniform baseline only).
    pub(super) values: Option<Vec<f32>>,
}

pub(super) enum Leaf {
    Pruned {
        origin: [i32; 3],
        size: i32,
        inside: bool,
    },
    Brick(Brick),
}

pub(super) enum Class {
    Inside,
    Outside,
    Go(Arc<Tape>),
}

impl Ctx<'_> {
    pub(super) fn check(&self) -> Result<(), MeshError> {
        if self.cancel.is_cancelled() {
            Err(MeshError::Cancelled)
        } else {
            Ok(())
        }
    }

    fn bricks_in(&self, s: i32) -> u64 {
        let k = (s / self.grid.brick).max(1) as u64;
        k * k * k
    }

    pub(super) fn classify(
        &self,
        ev: &mut Option<IntervalEval>,
        tape: &Arc<Tape>,
        o: [i32; 3],
        s: i32,
    ) -> Class {
        if (0..3).any(|a| o[a] >= self.grid.n[a]) {
            return Class::Outside;
        }
        let Some(ev) = ev else {
            return Class::Go(tape.clone());
        };
        let [x, y, z] = self.grid.node_box(o, s);
        let iv = ev.eval(x, y, z, self.inputs);
        if iv.is_positive() {
            Class::Inside
        } else if iv.is_outside() {
            Class::Outside
        } else {
            let t = simplify(tape, ev.choices(), SimplifyMode::Sign);
            if t.len() < tape.len() {
                Class::Go(Arc::new(t))
            } else {
                Class::Go(tape.clone())
            }
        }
    }

    pub(super) fn descend(
        &self,
        tape: Arc<Tape>,
        o: [i32; 3],
        s: i32,
    ) -> Result<Vec<Leaf>, MeshError> {
        self.check()?;
        if s <= self.grid.brick {
            return Ok(vec![Leaf::Brick(self.eval_brick(tape, o))]);
        }
        let half = s / 2;
        let mut ev = (self.method != Method::MarchingCubes).then(|| IntervalEval::new(&tape));
        let mut leaves = Vec::new();
        let mut todo = Vec::new();
        for off in OFFS {
            let co = [
                o[0] + off[0] * half,
                o[1] + off[1] * half,
                o[2] + off[2] * half,
            ];
            match self.classify(&mut ev, &tape, co, half) {
                Class::Go(t) => todo.push((t, co)),
                c => {
                    self.progress.add(self.bricks_in(half));
                    leaves.push(Leaf::Pruned {
                        origin: co,
                        size: half,
                        inside: matches!(c, Class::Inside),
                    });
                }
            }
        }
        for r in par_map(&todo, |(t, co)| self.descend(t.clone(), *co, half)) {
            leaves.extend(r?);
        }
        Ok(leaves)
    }

    fn eval_brick(&self, tape: Arc<Tape>, o: [i32; 3]) -> Brick {
        let g = &self.grid;
        let b = g.brick;
        let m = (b * b * b) as usize;
        // The crossing search's buffers of this thread (not in use while descending).
        let mut bufs = CROSSING_BUFS.with(Cell::take);
        let CrossingBufs { xs, ys, zs, f, .. } = &mut bufs;
        for v in [&mut *xs, &mut *ys, &mut *zs] {
            v.clear();
        }
        // The brick's coordinates along x, then the rows and layers from them.
        xs.extend((0..b).map(|i| g.coord(0, o[0] + i)));
        let bu = b as usize;
        for _ in 1..bu * bu {
            xs.extend_from_within(..bu);
        }
        for k in 0..b {
            let z = g.coord(2, o[2] + k);
            for j in 0..b {
                let y = g.coord(1, o[1] + j);
                ys.extend(std::iter::repeat_n(y, bu));
                zs.extend(std::iter::repeat_n(z, bu));
            }
        }
        zeroed(f, m);
        with_batch(&tape, |be| be.eval(xs, ys, zs, self.inputs, f));
        let out = &f[..];
        let mut bits = vec![0u64; m.div_ceil(64)];
        // Samples past the grid's last (the virtual layer) stay outside.
        let clipped = (0..3).any(|a| o[a] + b > g.n[a]);
        let mut l = 0;
        for k in 0..b {
            for j in 0..b {
                for i in 0..b {
                    let real = !clipped || !g.is_virtual([o[0] + i, o[1] + j, o[2] + k]);
                    if out[l] >= 0.0 && real {
                        bits[l / 64] |= 1 << (l % 64);
                    }
                    l += 1;
                }
            }
        }
        let values = (self.method == Method::MarchingCubes).then(|| {
            out.iter()
                .map(|&v| {
                    // Keep the sign through the narrowing.
                    let f = v as f32;
                    if f == 0.0 && v < 0.0 {
                        -f32::MIN_POSITIVE
                    } else {
                        f
                    }
                })
                .collect()
        });
        CROSSING_BUFS.with(|c| c.set(bufs));
        self.progress.add(1);
        Brick {
            origin: o,
            tape,
            bits,
            values,
        }
    }
}
