//! Throughput of the interval evaluator on the benchmark models M1-M4 (and
//! the sphere example): the 16³ cells of each model's `-- bounds:` box, one
//! `IntervalEval::eval` each. Run with
//! `cargo test --release -p frep-core --test interval_bench -- --ignored --nocapture`
//! (`FREP_IV_MODEL=<name>` for one model only).

use std::time::Instant;

use frep_core::eval::interval::{Interval, IntervalEval};
use frep_core::{Inputs, Model};

const CELLS: usize = 16;

fn model(name: &str) -> (frep_core::Tape, [f64; 6]) {
    let path = format!("{}/../../examples/{name}.hf", env!("CARGO_MANIFEST_DIR"));
    let src = std::fs::read_to_string(&path).expect("example");
    let bounds = src
        .lines()
        .find_map(|l| {
            let v: Vec<f64> = l
                .strip_prefix("-- bounds:")?
                .split(',')
                .map(|t| t.trim().parse().ok())
                .collect::<Option<_>>()?;
            <[f64; 6]>::try_from(v).ok()
        })
        .expect("bounds");
    let m = Model::compile(&src).expect("compiles");
    (m.tape(), bounds)
}

fn boxes(b: [f64; 6]) -> Vec<[Interval; 3]> {
    let mut out = Vec::new();
    let step = |k: usize| (b[k + 3] - b[k]) / CELLS as f64;
    for i in 0..CELLS {
        for j in 0..CELLS {
            for k in 0..CELLS {
                let c = [i, j, k];
                out.push([0, 1, 2].map(|a| {
                    let lo = b[a] + step(a) * c[a] as f64;
                    Interval::new(lo, lo + step(a))
                }));
            }
        }
    }
    out
}

/// Boxes per second (millions): the best of several timed passes.
fn rate(eval: &mut IntervalEval, boxes: &[[Interval; 3]]) -> f64 {
    let inputs = Inputs::default();
    let mut best = f64::INFINITY;
    let start = Instant::now();
    let mut runs = 0;
    while runs < 5 || (start.elapsed().as_secs_f64() < 0.5 && runs < 50) {
        let t = Instant::now();
        let mut amb = 0usize;
        for [x, y, z] in boxes {
            amb += usize::from(eval.eval(*x, *y, *z, &inputs).contains(0.0));
        }
        std::hint::black_box(amb);
        best = best.min(t.elapsed().as_secs_f64());
        runs += 1;
    }
    boxes.len() as f64 / best / 1e6
}

#[test]
#[ignore]
fn interval_throughput() {
    println!("{:<16} {:>6} {:>12}", "model", "nodes", "Mboxes/s");
    for name in [
        "m1_sphere",
        "m2_spheres100",
        "m3_gyroid",
        "m4_rblend10",
        "sphere",
    ] {
        if std::env::var("FREP_IV_MODEL").is_ok_and(|m| m != name) {
            continue;
        }
        let (tape, b) = model(name);
        let bx = boxes(b);
        let mut ev = IntervalEval::new(&tape);
        let r = rate(&mut ev, &bx);
        println!("{name:<16} {:>6} {r:>12.3}", tape.nodes.len());
    }
}
