//! Properties of the evaluators on real models (the examples, the
//! conformance models and, when present, the corpus): intervals contain the
//! point values inside their box, simplified tapes agree with the full tape
//! inside their region, gradients agree with finite differences.

mod common;

use std::path::Path;

use frep_core::eval::batch::BatchEval;
use frep_core::eval::grad::GradEval;
use frep_core::eval::interval::{Interval, IntervalEval};
use frep_core::simplify::{simplify, SimplifyMode};
use frep_core::{Inputs, Model};

/// A small deterministic generator (xorshift), so failures reproduce.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// Every model to check, with a box around it.
fn models() -> Vec<(String, Model, [f64; 6])> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files: Vec<_> = std::fs::read_dir(root.join("examples"))
        .unwrap()
        .chain(std::fs::read_dir(common::data_dir().join("conformance")).unwrap())
        .map(|e| e.unwrap().path())
        .collect();
    if let Some(corpus) = common::corpus_dir() {
        files.extend(
            std::fs::read_dir(corpus)
                .unwrap()
                .map(|e| e.unwrap().path()),
        );
    }
    files.retain(|p| p.extension().is_some_and(|e| e == "hf"));
    files.sort();
    files
        .into_iter()
        .map(|path| {
            let src = std::fs::read_to_string(&path).unwrap();
            let model = Model::compile(&src).unwrap_or_else(|d| panic!("{}: {d}", path.display()));
            let bounds = src
                .lines()
                .find_map(|l| l.trim().strip_prefix("-- bounds:"))
                .map(|b| {
                    let v: Vec<f64> = b.split(',').map(|t| t.trim().parse().unwrap()).collect();
                    [v[0], v[1], v[2], v[3], v[4], v[5]]
                })
                .unwrap_or([-2.0, -2.0, -2.0, 2.0, 2.0, 2.0]);
            (
                path.file_name().unwrap().to_string_lossy().into_owned(),
                model,
                bounds,
            )
        })
        .collect()
}

/// A random sub-box of `b` whose size is a random fraction of it.
fn random_box(rng: &mut Rng, b: &[f64; 6]) -> [f64; 6] {
    let mut out = [0.0; 6];
    let frac = [0.5, 0.1, 0.02][(rng.next() * 3.0) as usize % 3];
    for k in 0..3 {
        let w = (b[k + 3] - b[k]) * frac;
        let lo = rng.range(b[k], b[k + 3] - w);
        out[k] = lo;
        out[k + 3] = lo + w;
    }
    out
}

fn points_in(rng: &mut Rng, b: &[f64; 6], n: usize) -> [Vec<f64>; 3] {
    let mut p = [Vec::new(), Vec::new(), Vec::new()];
    for _ in 0..n {
        for (k, axis) in p.iter_mut().enumerate() {
            axis.push(rng.range(b[k], b[k + 3]));
        }
    }
    p
}

#[test]
fn intervals_contain_values_and_simplified_tapes_agree() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let inputs = Inputs::default();
    let mut checked = 0usize;
    for (name, model, bounds) in models() {
        let tape = model.tape();
        let mut full = BatchEval::new(&tape);
        let mut iv = IntervalEval::new(&tape);
        for _ in 0..12 {
            let b = random_box(&mut rng, &bounds);
            let r = iv.eval(
                Interval::new(b[0], b[3]),
                Interval::new(b[1], b[4]),
                Interval::new(b[2], b[5]),
                &inputs,
            );
            let [xs, ys, zs] = points_in(&mut rng, &b, 300);
            let mut vals = vec![0.0; xs.len()];
            full.eval(&xs, &ys, &zs, &inputs, &mut vals);
            for (i, &v) in vals.iter().enumerate() {
                assert!(
                    r.contains(v),
                    "{name}: interval {r:?} over {b:?} misses {v} at ({}, {}, {})",
                    xs[i],
                    ys[i],
                    zs[i]
                );
            }
            let exact = simplify(&tape, iv.choices(), SimplifyMode::Exact);
            let sign = simplify(&tape, iv.choices(), SimplifyMode::Sign);
            assert!(exact.len() <= tape.len() && sign.len() <= exact.len());
            let mut e_vals = vec![0.0; xs.len()];
            BatchEval::new(&exact).eval(&xs, &ys, &zs, &inputs, &mut e_vals);
            let mut s_vals = vec![0.0; xs.len()];
            BatchEval::new(&sign).eval(&xs, &ys, &zs, &inputs, &mut s_vals);
            for i in 0..xs.len() {
                let (v, e, s) = (vals[i], e_vals[i], s_vals[i]);
                assert!(
                    v.to_bits() == e.to_bits() || (v.is_nan() && e.is_nan()),
                    "{name}: exact simplification changed {v} to {e}"
                );
                let inside = |x: f64| x >= 0.0; // NaN is outside
                if v.abs() > 1e-9 * (1.0 + v.abs()) || v.is_nan() {
                    assert_eq!(
                        inside(v),
                        inside(s),
                        "{name}: sign simplification changed {v} to {s} at ({}, {}, {})",
                        xs[i],
                        ys[i],
                        zs[i]
                    );
                }
            }
            checked += xs.len();
        }
    }
    eprintln!("checked {checked} points in random boxes");
}

#[test]
fn gradients_agree_with_finite_differences() {
    let mut rng = Rng(0x2545_f491_4f6c_dd1d);
    let inputs = Inputs::default();
    let mut compared = 0usize;
    for (name, model, bounds) in models() {
        let tape = model.tape();
        let mut g = GradEval::new(&tape);
        let mut b = BatchEval::new(&tape);
        for _ in 0..40 {
            let p = [0, 1, 2].map(|k| rng.range(bounds[k], bounds[k + 3]));
            let gr = g.eval(p[0], p[1], p[2], &inputs);
            if !gr.v.is_finite() {
                continue;
            }
            // Central differences at two step sizes; skip where they disagree
            // (kinks of min/max/abs, selects, steep regions).
            let scale = (bounds[3] - bounds[0]).abs().max(1e-9);
            let fd = |h: f64, b: &mut BatchEval| {
                let mut out = [0.0; 6];
                let xs = [p[0] + h, p[0] - h, p[0], p[0], p[0], p[0]];
                let ys = [p[1], p[1], p[1] + h, p[1] - h, p[1], p[1]];
                let zs = [p[2], p[2], p[2], p[2], p[2] + h, p[2] - h];
                b.eval(&xs, &ys, &zs, &inputs, &mut out);
                [
                    (out[0] - out[1]) / (2.0 * h),
                    (out[2] - out[3]) / (2.0 * h),
                    (out[4] - out[5]) / (2.0 * h),
                ]
            };
            let d1 = fd(1e-5 * scale, &mut b);
            let d2 = fd(2e-5 * scale, &mut b);
            let ad = [gr.dx, gr.dy, gr.dz];
            for k in 0..3 {
                let tol = 1e-4 * (1.0 + d1[k].abs());
                if !d1[k].is_finite() || (d1[k] - d2[k]).abs() > tol {
                    continue;
                }
                assert!(
                    (ad[k] - d1[k]).abs() <= 10.0 * tol,
                    "{name}: d/d{} at {p:?}: AD {} vs FD {}",
                    ["x", "y", "z"][k],
                    ad[k],
                    d1[k]
                );
                compared += 1;
            }
        }
    }
    assert!(compared > 1000, "only {compared} derivatives compared");
    eprintln!("compared {compared} partial derivatives");
}
