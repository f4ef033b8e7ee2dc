//! The compiler's semantics: the reference interpreter's behaviours listed in
//! SPEC §7, control flow, arrays, bodies, limits and diagnostics.

use frep_core::eval::batch::BatchEval;
use frep_core::{CompileOptions, EvalError, Inputs, Model, Node, PointEval};

fn model(src: &str) -> Model {
    Model::compile(src).unwrap_or_else(|d| panic!("{}", d.render(src, None)))
}

fn eval_at(src: &str, p: [f64; 3], params: &[f64]) -> Result<f64, EvalError> {
    let m = model(src);
    PointEval::new(m.point_tape()).eval(p[0], p[1], p[2], &Inputs::with_params(params))
}

/// A one-line model `my_model = EXPR;` evaluated at `p`.
fn expr_at(expr: &str, p: [f64; 3]) -> Result<f64, EvalError> {
    eval_at(
        &format!("my_model(x[3], a[1]) {{ my_model = {expr}; }}"),
        p,
        &[],
    )
}

#[test]
fn spec_section_7_examples() {
    let o = [0.0; 3];
    assert_eq!(expr_at("-x[1]^2", [2.0, 0.0, 0.0]), Ok(4.0));
    assert_eq!(expr_at("2^3^2", o), Ok(64.0));
    assert_eq!(expr_at("1 + 2 | 3*4", o), Ok(27.369316876852981));
    assert_eq!(expr_at("1 | 2 & 3", o), Ok(2.2014670905314775));
    assert_eq!(
        expr_at("x[1] \\ x[2]", [2.0, 3.0, 0.0]),
        Ok(-4.6055512754639896)
    );
    assert_eq!(
        expr_at("x[1] @ x[2]", [2.0, 3.0, 0.0]),
        Ok(1.3944487245360109)
    );
    assert_eq!(expr_at("sign(-5)", o), Ok(1.0));
    assert_eq!(expr_at("mod(7.5,2)", o), Ok(0.0));
    assert_eq!(expr_at("mod(-7,3)", o), Ok(-1.0));
    assert_eq!(expr_at("int(-2.7)", o), Ok(-2.0));
    assert_eq!(expr_at("frac(-2.7)", o), Ok(-0.70000000000000018));
    assert_eq!(expr_at("(-8)^3", o), Ok(-512.0));
    assert_eq!(expr_at("(-8)^(1/3)", o), Err(EvalError::NegativePower));
    assert_eq!(expr_at("2^-1", o), Ok(0.5));
    assert_eq!(
        expr_at("x[1]/1e-7", [1.0, 0.0, 0.0]),
        Err(EvalError::DivisionByZero)
    );
    assert_eq!(expr_at("sqrt(-1e-10)", o), Err(EvalError::NegativeSqrt));
    assert_eq!(expr_at("0^0.5", o), Ok(0.0));
    assert_eq!(expr_at("0.5^0", o), Ok(1.0));
    assert_eq!(expr_at("logd(100)", o), Ok(2.0));
    assert_eq!(expr_at("atan2(1,0)", o), Ok(std::f64::consts::FRAC_PI_2));
    assert_eq!(expr_at("x[2.5]", [1.0, 2.0, 3.0]), Ok(3.0));
    assert_eq!(expr_at("x[2.4]", [1.0, 2.0, 3.0]), Ok(2.0));
    assert_eq!(
        expr_at("x[4]", [1.0, 2.0, 3.0]),
        Err(EvalError::IndexOutOfRange)
    );
    assert_eq!(expr_at("2.5E+2", o), Ok(250.00000000000011));
    let c = "array c[3]; c = [0, 0, 0];";
    let blend = format!("my_model(x[3], a[1]) {{ {c} my_model = hfBlendUni(hfSphere(x,c,1), hfSphere(x,c,2), 1, 0, 1); }}");
    assert_eq!(eval_at(&blend, o, &[]), Ok(9.1231056256176615));
    assert!(eval_at(&blend, [0.0, 0.0, 1.0], &[]).unwrap().is_nan());
    let scale = "my_model(x[3], a[1]) { r = hfScale3D(x,2,2,2); my_model = x[1]; }";
    assert_eq!(eval_at(scale, [4.0, 0.0, 0.0], &[]), Ok(2.0));
    let calls = "b(x[3], a[1]) { b = 10*x[1]; } my_model(x[3], a[1]) { my_model = b(x,a)+1; }";
    assert_eq!(eval_at(calls, [2.0, 0.0, 0.0], &[]), Ok(21.0));
}

#[test]
fn conditions_follow_the_reference() {
    let m = |cond: &str| {
        format!("my_model(x[3], a[1]) {{ r = 0; if {cond} then r = 1; endif; my_model = r; }}")
    };
    assert_eq!(eval_at(&m("2.0000001 = 2"), [0.0; 3], &[]), Ok(1.0));
    assert_eq!(eval_at(&m("not x[1] > 5"), [2.0, 0.0, 0.0], &[]), Ok(0.0));
    assert_eq!(eval_at(&m("not (x[1] > 5)"), [2.0, 0.0, 0.0], &[]), Ok(1.0));
    assert_eq!(eval_at(&m("1 < x[1] < 3"), [2.0, 0.0, 0.0], &[]), Ok(1.0));
    assert_eq!(
        eval_at(&m("1 < x[1] < 3"), [9.0, 0.0, 0.0], &[]),
        Ok(1.0),
        "chains compare 0/1 with 3"
    );
    assert_eq!(
        eval_at(
            &m("x[1] > 0 and x[2] > 0 or x[3] > 0"),
            [-1.0, 1.0, 1.0],
            &[]
        ),
        Ok(1.0)
    );
}

#[test]
fn constant_loops_unroll_and_point_dependent_if_selects() {
    let sum = "my_model(x[3], a[1]) { i = 1; s1 = 0; while i <= 10 loop s1 = s1 + i; i = i + 1; endloop; my_model = s1; }";
    let m = model(sum);
    assert_eq!(
        m.tape().nodes,
        vec![Node::constant(55.0)],
        "the loop folds to a constant"
    );
    let branch =
        "my_model(x[3], a[1]) { if x[1] > 0 then f = x[2]; else f = x[3]; endif; my_model = f; }";
    assert_eq!(eval_at(branch, [1.0, 2.0, 3.0], &[]), Ok(2.0));
    assert_eq!(eval_at(branch, [-1.0, 2.0, 3.0], &[]), Ok(3.0));
    // A variable assigned in one branch only is uninitialised on the other path.
    let half = "my_model(x[3], a[1]) { if x[1] > 0 then f = 1; endif; my_model = f; }";
    assert_eq!(eval_at(half, [1.0, 0.0, 0.0], &[]), Ok(1.0));
    assert_eq!(
        eval_at(half, [-1.0, 0.0, 0.0], &[]),
        Err(EvalError::NotInitialized)
    );
    // An error in the branch not taken is not reported.
    let guarded =
        "my_model(x[3], a[1]) { if x[1] > 0 then f = 1/x[1]; else f = 0; endif; my_model = f; }";
    assert_eq!(eval_at(guarded, [0.0, 0.0, 0.0], &[]), Ok(0.0));
    assert_eq!(eval_at(guarded, [0.5, 0.0, 0.0], &[]), Ok(2.0));
}

#[test]
fn point_dependent_while_unrolls_within_its_bound() {
    // Halve until below 1, at most 40 times: ends by the counter.
    let src = "my_model(x[3], a[1]) { v = abs(x[1]); n = 0; while v >= 1 and n < 40 loop v = v / 2; n = n + 1; endloop; my_model = n; }";
    assert_eq!(eval_at(src, [8.0, 0.0, 0.0], &[]), Ok(4.0));
    assert_eq!(eval_at(src, [0.5, 0.0, 0.0], &[]), Ok(0.0));
    assert_eq!(eval_at(src, [1000.0, 0.0, 0.0], &[]), Ok(10.0));
    // Without a counter the loop cannot be unrolled: a clear compile error.
    let unbounded = "my_model(x[3], a[1]) { v = abs(x[1]); while v >= 1 loop v = v / 2; endloop; my_model = v; }";
    let err = Model::compile(unbounded).unwrap_err();
    assert!(err.message.contains("depends on the point"), "{err}");
    assert_eq!((err.span.line, err.span.col), (1, 39));
    let opts = CompileOptions {
        max_dependent_iterations: 3,
        ..Default::default()
    };
    assert!(
        Model::compile_with(src, &opts).is_err(),
        "a lower bound fails"
    );
}

#[test]
fn runaway_constant_loop_is_a_compile_error() {
    let src = "my_model(x[3], a[1]) { i = 0; while i >= 0 loop i = i + 1; endloop; my_model = i; }";
    let opts = CompileOptions {
        max_iterations: 1000,
        ..Default::default()
    };
    let err = Model::compile_with(src, &opts).unwrap_err();
    assert!(err.message.contains("1000 iterations"), "{err}");
}

#[test]
fn errors_are_reported_in_reference_order() {
    // A dead statement's error is still the reference's error.
    let dead = "my_model(x[3], a[1]) { t = 1/x[1]; my_model = 5; }";
    assert_eq!(eval_at(dead, [0.0; 3], &[]), Err(EvalError::DivisionByZero));
    assert_eq!(eval_at(dead, [1.0, 0.0, 0.0], &[]), Ok(5.0));
    // Right operand first.
    let order = "my_model(x[3], a[1]) { my_model = sqrt(x[1]) + 1/x[2]; }";
    assert_eq!(
        eval_at(order, [-1.0, 0.0, 0.0], &[]),
        Err(EvalError::DivisionByZero)
    );
    // Statements in order.
    let stmts = "my_model(x[3], a[1]) { p = sqrt(x[1]); q = 1/x[2]; my_model = p + q; }";
    assert_eq!(
        eval_at(stmts, [-1.0, 0.0, 0.0], &[]),
        Err(EvalError::NegativeSqrt)
    );
    // Side effects of transformations: the right operand runs first.
    let side = "my_model(x[3], a[1]) { array xt[3], c[3]; xt[1]=x[1]; xt[2]=x[2]; xt[3]=x[3]; c=[0,0,0]; my_model = hfSphere(xt,c,0) + 0*hfShift3D(xt,5,0,0); }";
    assert_eq!(eval_at(side, [0.0; 3], &[]), Ok(-25.0));
}

#[test]
fn parameters_stay_symbolic() {
    let src = "my_model(x[3], a[2]) { my_model = a[1] - x[1]*x[1] - a[2]; }";
    let m = model(src);
    assert_eq!(m.a_dim, 2);
    assert!(m.tape().nodes.iter().any(|n| matches!(n, Node::Param(0))));
    let mut ev = PointEval::new(m.point_tape());
    assert_eq!(
        ev.eval(1.0, 0.0, 0.0, &Inputs::with_params(&[3.0, 0.5])),
        Ok(1.5)
    );
    assert_eq!(
        ev.eval(1.0, 0.0, 0.0, &Inputs::with_params(&[5.0, 0.5])),
        Ok(3.5)
    );
}

#[test]
fn point_dependent_array_index() {
    let src =
        "my_model(x[3], a[1]) { array v[3]; v = [10, 20, 30]; v[x[2]] = 7; my_model = v[x[1]]; }";
    assert_eq!(eval_at(src, [2.0, 3.0, 0.0], &[]), Ok(20.0));
    assert_eq!(eval_at(src, [3.0, 3.0, 0.0], &[]), Ok(7.0));
    assert_eq!(eval_at(src, [0.6, 1.0, 0.0], &[]), Ok(7.0));
    assert_eq!(eval_at(src, [2.6, 1.0, 0.0], &[]), Ok(30.0));
    assert_eq!(
        eval_at(src, [1.0, 4.0, 0.0], &[]),
        Err(EvalError::IndexOutOfRange)
    );
    assert_eq!(
        eval_at(src, [0.0, 1.0, 0.0], &[]),
        Err(EvalError::IndexOutOfRange)
    );
}

#[test]
fn attributes_are_outputs() {
    let src = "my_model(x[3], a[1], s[3]) { s[1] = x[1]; s[3] = 2; my_model = 1; }";
    let m = model(src);
    assert!(m.has_attributes);
    let mut ev = PointEval::new(m.point_tape());
    assert_eq!(ev.eval(0.25, 0.0, 0.0, &Inputs::default()), Ok(1.0));
    assert_eq!(ev.output(1), Ok(0.25));
    assert_eq!(ev.output(2), Ok(0.0), "s starts at 0");
    assert_eq!(ev.output(3), Ok(2.0));
}

#[test]
fn attribute_tape_is_the_attributes_alone() {
    let src = "my_model(x[3], a[1], s[3]) {
        r = sqrt(x[1]^2 + x[2]^2 + x[3]^2);
        s[1] = 0.5; s[2] = x[2] * 2;
        if x[1] > 0 then s[3] = 1; endif;
        my_model = sin(r) * cos(r) - 0.5 * r;
    }";
    let m = model(src);
    let (full, attr) = (m.tape_with_attributes(), m.attribute_tape().unwrap());
    assert_eq!(attr.outputs.len(), 3);
    assert!(attr.len() < full.len(), "{} of {}", attr.len(), full.len());
    let (xs, ys, zs) = (
        vec![-0.5, 0.25, 1.0],
        vec![0.1, -0.3, 2.0],
        vec![0.0, 0.7, -1.0],
    );
    let (mut a, mut f) = (vec![Vec::new(); 3], vec![Vec::new(); 4]);
    let inputs = Inputs::default();
    BatchEval::new(&full).eval_outputs(&xs, &ys, &zs, &inputs, &mut f);
    BatchEval::new(&attr).eval_outputs(&xs, &ys, &zs, &inputs, &mut a);
    assert_eq!(a[..], f[1..]);
    assert_eq!(a[2], [0.0, 1.0, 1.0]);
    // No attributes: none.
    assert!(model("my_model(x[3], a[1]) { my_model = 1; }")
        .attribute_tape()
        .is_none());
}

#[test]
fn body_calls_copy_arrays_in_and_s_back() {
    let src = "
paint(x[3], a[1], s[3]) { s[1] = 0.5; x[1] = 0; paint = 1; }
my_model(x[3], a[1], s[3]) { array c[3]; c = [1, 1, 1]; v = paint(c, a, s); my_model = v + c[1]; }";
    // `x[1] = 0` assigns the read-only x: a compile error.
    assert!(Model::compile(src).is_err());
    let src = "
paint(x[3], a[1], s[3]) { s[1] = 0.5; r = hfShift3D(x, 1, 0, 0); paint = x[1]; }
my_model(x[3], a[1], s[3]) { array c[3]; c = [1, 1, 1]; v = paint(c, a, s); my_model = v + c[1]; }";
    let m = model(src);
    let mut ev = PointEval::new(m.point_tape());
    // The callee shifts its copy of c: 0; the caller's c is unchanged: 1.
    assert_eq!(ev.eval(0.0, 0.0, 0.0, &Inputs::default()), Ok(1.0));
    assert_eq!(ev.output(1), Ok(0.5), "s copied back");
    // Calling a body defined below, or with wrong sizes, is an error.
    let below = "my_model(x[3], a[1]) { my_model = b(x, a); } b(x[3], a[1]) { b = 1; }";
    let e = Model::compile(below).unwrap_err();
    assert!(e.message.contains("defined below"), "{e}");
    let sizes = "b(x[3], a[2]) { b = 1; } my_model(x[3], a[1]) { my_model = b(x, a); }";
    let e = Model::compile(sizes).unwrap_err();
    assert!(e.message.contains("wrong number of items"), "{e}");
}

#[test]
fn semantic_errors_name_line_and_column() {
    let cases: &[(&str, (u32, u32), &str)] = &[
        (
            "my_model(x[3], a[1]) {\n  my_model = y + 1;\n}",
            (2, 14),
            "used before any assignment",
        ),
        (
            "my_model(x[3], a[1]) {\n  my_model = hfSpere(x, x, 1);\n}",
            (2, 14),
            "unknown function",
        ),
        (
            "my_model(x[3], a[1]) {\n  array c[3];\n  c = [1, 2];\n  my_model = 1;\n}",
            (3, 7),
            "wrong number of items",
        ),
        (
            "my_model(x[3], a[1]) {\n  my_model = sqrt(1, 2);\n}",
            (2, 14),
            "takes 1 argument",
        ),
        (
            "my_model(x[3], a[1]) {\n  my_model = hfSphere(1, x, 1);\n}",
            (2, 23),
            "must be an array",
        ),
        (
            "my_model(x[3], a[1]) {\n  array c[3];\n  my_model = c + 1;\n}",
            (3, 14),
            "is an array",
        ),
    ];
    for (src, (line, col), msg) in cases {
        let d = Model::compile(src).unwrap_err();
        assert_eq!((d.span.line, d.span.col), (*line, *col), "{src}: {d}");
        assert!(d.message.contains(msg), "{src}: {d}");
        let r = d.render(src, Some("t.hf"));
        assert!(
            r.contains(&format!("t.hf:{line}:{col}")) && r.contains('^'),
            "{r}"
        );
    }
}

#[test]
fn graph_keeps_r_functions_and_blends_as_ops() {
    let src = "my_model(x[3], a[1]) { array c[3]; c = [0,0,0]; s1 = hfSphere(x,c,1); s2 = hfSphere(x,c,0.5); my_model = (s1 | s2) & hfBlendInt(s1, s2, 1, 1, 1) \\ x[1]; }";
    let tape = model(src).tape();
    use frep_core::ops::BinaryOp;
    let has = |op: BinaryOp| {
        tape.nodes
            .iter()
            .any(|n| matches!(n, Node::Binary(o, _, _) if *o == op))
    };
    assert!(has(BinaryOp::RUnion) && has(BinaryOp::RInter) && has(BinaryOp::RDiff));
    assert!(tape.nodes.iter().any(|n| matches!(n, Node::Blend(..))));
    assert!(
        !tape.nodes.iter().any(|n| matches!(
            n,
            Node::Unary(
                frep_core::ops::UnaryOp::Sqrt | frep_core::ops::UnaryOp::SqrtF,
                _
            )
        )),
        "no expanded sqrt"
    );
}

#[test]
fn node_limit_is_enforced() {
    let src = "my_model(x[3], a[1]) { i = 0; f = x[1]; while i < 10000 loop f = f * x[2] + i; i = i + 1; endloop; my_model = f; }";
    let opts = CompileOptions {
        max_nodes: 500,
        ..Default::default()
    };
    let e = Model::compile_with(src, &opts).unwrap_err();
    assert!(e.message.contains("500 nodes"), "{e}");
    assert!(Model::compile(src).is_ok());
}

#[test]
fn runaway_loop_with_point_dependent_branch_stops_at_a_limit() {
    // Found by the fuzzer: `i = i + 0` never ends the loop, and the `if`
    // inside adds selects on every iteration. A limit stops it with an error.
    let src = "my_model(x[3], a[1]) { s1 = 0; i = 1; while i < 10 loop if x[1] > i then s1 = s1 + x[2]; endif; i = i + 0; endloop; my_model = s1; }";
    let opts = CompileOptions {
        max_nodes: 20_000,
        ..Default::default()
    };
    let err = Model::compile_with(src, &opts).unwrap_err();
    assert!(err.message.contains("20000 nodes"), "{err}");
    assert_eq!(err.span.line, 1);
}
