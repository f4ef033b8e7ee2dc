//! The conformance suite: every golden file of the reference interpreter,
//! reproduced by the point evaluator (errors included).

mod common;

use common::{close, golden_models, Expected};
use frep_core::{CompileOptions, Inputs, Model, PointEval};

#[test]
fn point_evaluator_reproduces_every_golden_file() {
    let models = golden_models();
    assert_eq!(
        models.len(),
        common::expected_golden_models(),
        "golden files missing"
    );
    let mut failures = Vec::new();
    let mut checked = 0;
    for (src, golden) in &models {
        let opts = CompileOptions {
            body: Some(golden.body.clone()),
            ..Default::default()
        };
        let model = match Model::compile_with(src, &opts) {
            Ok(m) => m,
            Err(d) => {
                failures.push(format!(
                    "{}: compile error: {}",
                    golden.name,
                    d.render(src, None)
                ));
                continue;
            }
        };
        let mut ev = PointEval::new(model.point_tape());
        for p in &golden.points {
            let inputs = Inputs::with_params(&p.inputs[3..]);
            let r = ev.eval(p.inputs[0], p.inputs[1], p.inputs[2], &inputs);
            checked += 1;
            match (&p.expected, r) {
                (Expected::Error(msg), Err(e)) if e.message() == msg => {}
                (Expected::Values(vals), Ok(v)) => {
                    let mut got = vec![v];
                    for k in 1..ev.outputs() {
                        got.push(ev.output(k).unwrap());
                    }
                    if got.len() != vals.len() || !got.iter().zip(vals).all(|(a, b)| close(*a, *b))
                    {
                        failures.push(format!(
                            "{}:{}: expected {:?}, got {:?}",
                            golden.name, p.line, vals, got
                        ));
                    }
                }
                (exp, got) => failures.push(format!(
                    "{}:{}: expected {:?}, got {:?}",
                    golden.name, p.line, exp, got
                )),
            }
        }
    }
    eprintln!("checked {checked} golden points of {} models", models.len());
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
