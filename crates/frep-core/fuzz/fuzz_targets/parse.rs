//! Fuzz target: the lexer, the parser and the compiler must never panic,
//! overflow the stack or hang, whatever UTF-8 text they are given;
//! diagnostics must render; and a compiled model must evaluate (point,
//! batch, interval, gradient) without panicking.
#![no_main]

use frep_core::eval::batch::BatchEval;
use frep_core::eval::grad::GradEval;
use frep_core::eval::interval::{Interval, IntervalEval};
use frep_core::{CompileOptions, Diagnostic, Inputs, Model, PointEval};
use libfuzzer_sys::fuzz_target;

fn check_diagnostic(source: &str, d: &Diagnostic) {
    assert!(d.span.line >= 1 && d.span.col >= 1);
    assert!(d.span.start <= d.span.end && d.span.end <= source.len());
    assert!(source.is_char_boundary(d.span.start) && source.is_char_boundary(d.span.end));
    let _ = d.render(source, Some("fuzz.hf"));
}

fuzz_target!(|data: &[u8]| {
    let Ok(source) = std::str::from_utf8(data) else {
        return;
    };
    let program = match frep_core::parse(source) {
        Ok(program) => program,
        Err(d) => return check_diagnostic(source, &d),
    };
    assert!(!program.bodies.is_empty());
    // Small limits keep every input fast; hitting one is a diagnostic.
    let options = CompileOptions {
        max_nodes: 100_000,
        max_iterations: 20_000,
        max_dependent_iterations: 8,
        max_steps: 200_000,
        ..Default::default()
    };
    let model = match frep_core::compile::compile_program(&program, &options) {
        Ok(model) => model,
        Err(d) => return check_diagnostic(source, &d),
    };
    let inputs = Inputs::with_params(&[0.5, -1.0, 2.0]);
    let mut point = PointEval::new(model.point_tape());
    let _ = point.eval(0.3, -0.2, 0.1, &inputs);
    let tape = model.tape_with_attributes();
    let mut outs = vec![Vec::new(); tape.outputs.len()];
    BatchEval::new(&tape).eval_outputs(
        &[0.3, 1e-7, -2.0],
        &[-0.2, 0.0, 5.0],
        &[0.1, 0.0, -1e3],
        &inputs,
        &mut outs,
    );
    let mut iv = IntervalEval::new(&model.tape());
    let r = iv.eval(
        Interval::new(-1.0, 1.0),
        Interval::new(-0.5, 0.5),
        Interval::new(0.0, 2.0),
        &inputs,
    );
    let _ = frep_core::simplify::simplify(
        iv.tape(),
        iv.choices(),
        frep_core::simplify::SimplifyMode::Sign,
    );
    assert!(r.lo <= r.hi || r.nan || r.is_empty());
    let _ = GradEval::new(&model.tape()).eval(0.3, -0.2, 0.1, &inputs);
});
