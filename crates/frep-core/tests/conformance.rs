//! One conformance suite, stamped out for every evaluator: each must
//! reproduce the reference interpreter's golden values.
//!
//! The point evaluator reproduces errors exactly (`tests/golden.rs`). The bulk
//! evaluators give NaN where an error reaches the value; where the reference
//! stops on an error in a statement whose value is never used, they give the
//! value itself. So their expected outcome at each golden point is the point
//! evaluation of the *value* tape: `Err` → NaN (interval: the NaN flag),
//! `Ok(v)` → `v`, which for every non-error golden point is the golden value.

mod common;

use common::{close, golden_models, Expected, Golden};
use frep_core::eval::batch::BatchEval;
use frep_core::eval::grad::GradEval;
use frep_core::eval::interval::{Interval, IntervalEval};
use frep_core::{CompileOptions, Inputs, Model, PointEval};

/// What an evaluator under test returns at one point: output values.
type EvalFn = dyn FnMut(&Model, [f64; 3], &Inputs) -> Vec<Outcome>;

#[derive(Debug, Clone, Copy)]
enum Outcome {
    /// A value, NaN for errors.
    Value(f64),
    /// An interval that must contain the expected value.
    Range(Interval),
}

fn compile(src: &str, golden: &Golden) -> Model {
    let opts = CompileOptions {
        body: Some(golden.body.clone()),
        ..Default::default()
    };
    Model::compile_with(src, &opts)
        .unwrap_or_else(|d| panic!("{}: {}", golden.name, d.render(src, None)))
}

fn run_suite(name: &str, mut make: impl FnMut(&Model) -> Box<EvalFn>) {
    let models = golden_models();
    assert_eq!(
        models.len(),
        common::expected_golden_models(),
        "golden files missing"
    );
    let mut failures = Vec::new();
    let mut points = 0;
    for (src, golden) in &models {
        let model = compile(src, golden);
        let mut eval = make(&model);
        let mut reference = PointEval::new(model.tape_with_attributes());
        for p in &golden.points {
            let inputs = Inputs::with_params(&p.inputs[3..]);
            let xyz = [p.inputs[0], p.inputs[1], p.inputs[2]];
            // Expected outputs: golden values, or the value tape's outcome
            // (NaN for an error) where the reference stopped.
            let expected: Vec<Option<f64>> = match &p.expected {
                Expected::Values(v) => v.iter().map(|&x| Some(x)).collect(),
                Expected::Error(_) => {
                    let r = reference.eval(xyz[0], xyz[1], xyz[2], &inputs);
                    let mut out = vec![r.ok()];
                    for k in 1..reference.outputs() {
                        out.push(reference.output(k).ok());
                    }
                    out
                }
            };
            let got = eval(&model, xyz, &inputs);
            points += 1;
            for (k, (e, g)) in expected.iter().zip(&got).enumerate() {
                let ok = match (e, g) {
                    (Some(e), Outcome::Value(g)) => close(*e, *g),
                    (None, Outcome::Value(g)) => g.is_nan(),
                    (Some(e), Outcome::Range(iv)) => {
                        iv.contains(*e)
                            || (iv.lo - e).abs().max((iv.hi - e).abs()) <= 1e-9 * e.abs().max(1e-3)
                    }
                    (None, Outcome::Range(iv)) => iv.nan,
                };
                if !ok {
                    failures.push(format!(
                        "{}:{} output {k}: expected {e:?}, got {g:?}",
                        golden.name, p.line
                    ));
                }
            }
        }
    }
    eprintln!(
        "{name}: checked {points} golden points of {} models",
        models.len()
    );
    assert!(
        failures.is_empty(),
        "{name}: {} failures:\n{}",
        failures.len(),
        failures[..failures.len().min(30)].join("\n")
    );
}

#[test]
fn batch_evaluator_conformance() {
    run_suite("batch", |model| {
        let mut ev = BatchEval::new(&model.tape_with_attributes());
        Box::new(move |_, p, inputs| {
            // A block of identical points plus neighbours exercises the lanes.
            let xs = [p[0]; 5];
            let ys = [p[1]; 5];
            let zs = [p[2]; 5];
            let mut outs = vec![Vec::new(); ev.tape().outputs.len()];
            ev.eval_outputs(&xs, &ys, &zs, inputs, &mut outs);
            outs.iter().map(|o| Outcome::Value(o[3])).collect()
        })
    });
}

#[test]
fn interval_evaluator_conformance() {
    run_suite("interval", |model| {
        let mut ev = IntervalEval::new(&model.tape_with_attributes());
        Box::new(move |_, p, inputs| {
            let iv = |v: f64| Interval::new(v, v);
            ev.eval_outputs(iv(p[0]), iv(p[1]), iv(p[2]), inputs)
                .into_iter()
                .map(Outcome::Range)
                .collect()
        })
    });
}

#[test]
fn interval_evaluator_conformance_on_small_boxes() {
    // Boxes around each golden point must contain the golden value too.
    run_suite("interval-box", |model| {
        let mut ev = IntervalEval::new(&model.tape_with_attributes());
        Box::new(move |_, p, inputs| {
            let iv = |v: f64| Interval::new(v - 1e-3, v + 1e-3);
            ev.eval_outputs(iv(p[0]), iv(p[1]), iv(p[2]), inputs)
                .into_iter()
                .map(Outcome::Range)
                .collect()
        })
    });
}

#[test]
fn gradient_evaluator_conformance() {
    run_suite("grad", |model| {
        let mut ev = GradEval::new(&model.tape());
        Box::new(move |_, p, inputs| vec![Outcome::Value(ev.eval(p[0], p[1], p[2], inputs).v)])
    });
}
