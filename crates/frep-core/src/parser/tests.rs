//! Unit tests of the parser: precedence, statements and diagnostics.

use super::*;

fn model(body: &str) -> String {
    format!("m(x[3], a[1])\n{{\n{body}\n}}\n")
}

fn result_of(expr: &str) -> Expr {
    let p = parse(&model(&format!("m = {expr};"))).unwrap_or_else(|e| panic!("{expr}: {e}"));
    p.bodies[0].result.clone()
}

fn cond_of(cond: &str) -> Expr {
    let src = model(&format!("if {cond} then t = 1; endif;\nm = 1;"));
    let p = parse(&src).unwrap_or_else(|e| panic!("{cond}: {e}"));
    match &p.bodies[0].stmts[0] {
        Stmt::If { cond, .. } => cond.clone(),
        s => panic!("{s:?}"),
    }
}

/// A compact prefix rendering of an expression.
fn sx(e: &Expr) -> String {
    match e {
        Expr::Num { value, .. } => format!("{value}"),
        Expr::Ident(id) => id.name.clone(),
        Expr::Index { array, index, .. } => format!("{}[{}]", array.name, sx(index)),
        Expr::Unary { op, expr, .. } => format!("({op:?} {})", sx(expr)),
        Expr::Binary { op, lhs, rhs, .. } => format!("({op:?} {} {})", sx(lhs), sx(rhs)),
        Expr::Call { name, args, .. } => {
            let a: Vec<String> = args.iter().map(sx).collect();
            format!("{}({})", name.name, a.join(", "))
        }
    }
}

fn err(src: &str) -> Diagnostic {
    match parse(src) {
        Ok(p) => panic!("expected an error for {src:?}, got {p:?}"),
        Err(d) => d,
    }
}

#[test]
fn precedence() {
    let cases = [
        ("1 + 2 | 3*4", "(Union (Add 1 2) (Mul 3 4))"),
        ("2^3^2", "(Pow (Pow 2 3) 2)"),
        ("-x[1]^2", "(Pow (Minus x[1]) 2)"),
        ("b | c & d", "(Inter (Union b c) d)"),
        ("f - g | h", "(Union (Sub f g) h)"),
        ("2*x[1] | y", "(Union (Mul 2 x[1]) y)"),
        ("p \\ q @ r", "(Cart (Diff p q) r)"),
        ("~p", "(Tilde p)"),
        ("+p", "(Plus p)"),
        ("1 - 2 - 3", "(Sub (Sub 1 2) 3)"),
        ("8 / 4 / 2", "(Div (Div 8 4) 2)"),
        ("2^-1", "(Pow 2 (Minus 1))"),
        ("- -x[2]", "(Minus (Minus x[2]))"),
        (
            "2^-1 - -x[2]^2",
            "(Sub (Pow 2 (Minus 1)) (Pow (Minus x[2]) 2))",
        ),
        ("-2^2*3", "(Mul (Pow (Minus 2) 2) 3)"),
        ("(1 + 2) * 3", "(Mul (Add 1 2) 3)"),
        (
            "hfSphere(x, c, 0.35) | hfBlock(x, -1, -1, -1, 2, 2, 2)",
            "(Union hfsphere(x, c, 0.35) hfblock(x, (Minus 1), (Minus 1), (Minus 1), 2, 2, 2))",
        ),
        ("SQRT(X[1]) + B(X, A)", "(Add sqrt(x[1]) b(x, a))"),
        ("f(s, a)", "f(s, a)"),
        ("x[x[1] + 1]", "x[(Add x[1] 1)]"),
    ];
    for (src, want) in cases {
        assert_eq!(sx(&result_of(src)), want, "{src}");
    }
}

#[test]
fn conditions() {
    let cases = [
        ("not x[1] > 5", "(Gt (Not x[1]) 5)"),
        ("1 < x[1] < 3", "(Lt (Lt 1 x[1]) 3)"),
        (
            "x[1] = 2 and x[2] /= 3 or x[3] >= 1",
            "(Or (And (Eq x[1] 2) (Ne x[2] 3)) (Ge x[3] 1))",
        ),
        ("not (x[1] > 5)", "(Not (Gt x[1] 5))"),
        ("(x[1]+1) > 0", "(Gt (Add x[1] 1) 0)"),
        (
            "x[1] <= 2 and (x[2] < 1 or x[3] > 1)",
            "(And (Le x[1] 2) (Or (Lt x[2] 1) (Gt x[3] 1)))",
        ),
        ("not not x[1]", "(Not (Not x[1]))"),
        ("x[1]", "x[1]"),
    ];
    for (src, want) in cases {
        assert_eq!(sx(&cond_of(src)), want, "{src}");
    }
}

#[test]
fn parenthesised_condition_quirk() {
    let d = err(&model("if (x[1]+1)*2 > 0 then t = 1; endif;\nm = 1;"));
    assert_eq!(d.expected.as_deref(), Some("`then`"));
    assert!(d.message.contains("unexpected `*`"), "{d}");
    assert_eq!((d.span.line, d.span.col), (3, 12));
}

#[test]
fn statements_and_body() {
    let src = "Body1(x[3], a[2], s[4]) {\n array c[3], v[2.5];\n array w[1];\n c = [1, -2, +3.5];\n s = [0, 0, 0, 1];\n c[1] = x[1];\n s[2] = c[1];\n t = 1;\n if t > 0 then t = 2; else if t < 0 then t = 3; endif; endif;\n while t < 10 loop t = t + 1; endloop;\n BODY1 = t;\n}\nsecond(x[3],a[1]){second=body1(x,a);}";
    let p = parse(src).unwrap();
    assert_eq!(p.bodies.len(), 2);
    let b = &p.bodies[0];
    assert_eq!(b.name.name, "body1");
    assert_eq!(b.x_size.value, 3.0);
    assert_eq!(b.a_size.value, 2.0);
    assert_eq!(b.s_size.map(|s| s.value), Some(4.0));
    assert_eq!(b.arrays.len(), 3);
    assert_eq!(b.arrays[1].size.value, 2.5);
    assert_eq!(b.stmts.len(), 7);
    match &b.stmts[0] {
        Stmt::ArrayLiteral {
            target,
            values,
            span,
        } => {
            assert_eq!(target.name, "c");
            assert_eq!(values, &vec![1.0, -2.0, 3.5]);
            assert_eq!(&src[span.start..span.end], "[1, -2, +3.5]");
        }
        s => panic!("{s:?}"),
    }
    assert!(matches!(&b.stmts[1], Stmt::ArrayLiteral { target, .. } if target.name == "s"));
    assert!(matches!(&b.stmts[2], Stmt::IndexAssign { target, .. } if target.name == "c"));
    assert!(matches!(&b.stmts[3], Stmt::IndexAssign { target, .. } if target.name == "s"));
    assert!(matches!(&b.stmts[4], Stmt::Assign { target, .. } if target.name == "t"));
    match &b.stmts[5] {
        Stmt::If {
            then_branch,
            else_branch,
            ..
        } => {
            assert_eq!(then_branch.len(), 1);
            assert!(matches!(&else_branch[..], [Stmt::If { .. }]));
        }
        s => panic!("{s:?}"),
    }
    assert!(matches!(&b.stmts[6], Stmt::While { body, .. } if body.len() == 1));
    assert_eq!(sx(&b.result), "t");
    assert_eq!(&src[b.result_span.start..b.result_span.end], "BODY1");
    assert_eq!(&src[b.span.start..b.span.end][..5], "Body1");
    assert!(src[b.span.start..b.span.end].ends_with("= t;\n}"));
    assert_eq!(p.bodies[1].s_size, None);
    assert_eq!(sx(&p.bodies[1].result), "body1(x, a)");
}

#[test]
fn crlf_and_lenient_numbers() {
    let p =
        parse("m(x[3], a[1])\r\n{\r\n  t = 01 + 1e0 + 1e05;\r\n  m = t; -- done\r\n}\r\n").unwrap();
    match &p.bodies[0].stmts[0] {
        Stmt::Assign { value, .. } => assert_eq!(sx(value), "(Add (Add 1 1) 100000.0000000002)"),
        s => panic!("{s:?}"),
    }
}

fn check(src: &str, line: u32, col: u32, msg: &str, expected: Option<&str>) {
    let d = err(src);
    assert_eq!((d.span.line, d.span.col), (line, col), "{src:?}: {d}");
    assert!(
        d.message.contains(msg),
        "{src:?}: message {:?} lacks {msg:?}",
        d.message
    );
    assert_eq!(d.expected.as_deref(), expected, "{src:?}: {d}");
}

/// A list of cases, one `check` each: long, but flat.
#[test]
fn error_positions_and_expectations() {
    // Missing semicolon: reported at the next token.
    check(
        &model("t = 1\nm = t;"),
        4,
        1,
        "unexpected identifier `m`",
        Some("`;`"),
    );
    // Missing endif.
    check(
        &model("if x[1] > 0 then t = 1;\nm = t;"),
        4,
        1,
        "must be the last statement",
        Some("a statement, `else` or `endif`"),
    );
    check(
        &model("if x[1] > 0 then t = 1;\n"),
        5,
        1,
        "unexpected `}`",
        Some("a statement, `else` or `endif`"),
    );
    // Array declaration after a statement.
    check(
        &model("t = 1;\narray c[3];\nm = t;"),
        4,
        1,
        "`array` declarations must come before",
        Some("a statement or `m = expression;`"),
    );
    // Result not last.
    check(
        &model("m = 1;\nt = 2;"),
        4,
        1,
        "must be the last statement of the body",
        Some("`}`"),
    );
    // Unknown character, with a character column.
    check(
        &model("t = \"é\" + 1; m = t;"),
        3,
        5,
        "string literals are not allowed",
        Some("an expression"),
    );
    check(
        &model("t = é + 1; m = t;"),
        3,
        5,
        "unknown character `é`",
        Some("an operator, a name, a number or a comment"),
    );
    check(
        &model("t = 1 $ 2;"),
        3,
        7,
        "unknown character `$`",
        Some("an operator, a name, a number or a comment"),
    );
    // Unterminated string.
    check(
        &model("t = \"abc;\nm = t;"),
        3,
        5,
        "unterminated string",
        Some("a closing `\"` on the same line"),
    );
    // Empty input.
    check(
        "",
        1,
        1,
        "the model is empty",
        Some("a body such as `my_model(x[3], a[1]) { my_model = ...; }`"),
    );
    check(
        "  -- only a comment\n",
        2,
        1,
        "the model is empty",
        Some("a body such as `my_model(x[3], a[1]) { my_model = ...; }`"),
    );
    // A body without its result.
    check(
        &model("t = 1;"),
        4,
        1,
        "has no result assignment",
        Some("`m = expression;`"),
    );
    // Missing expression.
    check(
        &model("m = sqrt(x[1] + );"),
        3,
        17,
        "unexpected `)`",
        Some("an expression"),
    );
    // Read-only arrays.
    check(
        &model("x[1] = 5;\nm = 1;"),
        3,
        1,
        "`x` is read-only",
        Some("a statement or the result assignment"),
    );
    check(
        &model("a = [1];\nm = 1;"),
        3,
        1,
        "`a` is read-only",
        Some("a statement or the result assignment"),
    );
    // Relational operator outside a condition.
    check(
        &model("m = x[1] > 0;"),
        3,
        10,
        "only in `if` and `while` conditions",
        Some("`;`"),
    );
    // Bare x outside a call.
    check(
        &model("m = x + 1;"),
        3,
        7,
        "bare array name",
        Some("`[` (an item such as `x[1]`)"),
    );
    // Header errors.
    check(
        "m(y[3], a[1]) { m = 1; }",
        1,
        3,
        "unexpected identifier `y`",
        Some("`x`"),
    );
    check(
        "m(x[3] a[1]) { m = 1; }",
        1,
        8,
        "unexpected `a`",
        Some("`,`"),
    );
    check(
        "m(x[3], a[1] { m = 1; }",
        1,
        14,
        "unexpected `{`",
        Some("`,` or `)`"),
    );
    check(
        "m(x[3], a[1]) m = 1; }",
        1,
        15,
        "unexpected identifier `m`",
        Some("`{`"),
    );
    // Array size.
    check(
        &model("array c[0.4];\nm = 1;"),
        3,
        9,
        "must be at least 1",
        Some("a positive array size"),
    );
    // Array literals take constants only.
    check(
        &model("array c[2];\nc = [1, x[1]];\nm = 1;"),
        4,
        9,
        "unexpected `x`",
        Some("a number (array literals hold optionally signed number constants only)"),
    );
    // Duplicate body.
    check(
        "b(x[3],a[1]){b=1;}\nb(x[3],a[1]){b=2;}",
        2,
        1,
        "not unique",
        Some("a new body name"),
    );
    // Missing `;` after endif.
    check(
        &model("if 1 then t=1; endif\nm = 1;"),
        4,
        1,
        "unexpected identifier `m`",
        Some("`;` after `endif`"),
    );
    // while without endloop.
    check(
        &model("while 1 loop t=1;\n"),
        5,
        1,
        "unexpected `}`",
        Some("a statement or `endloop`"),
    );
    // Result inside a loop.
    check(
        &model("while 1 loop m = 1; endloop;\nm = 1;"),
        3,
        14,
        "not inside `if` or `while`",
        Some("a statement or `endloop`"),
    );
    // Something after the last body.
    check(
        "b(x[3],a[1]){b=1;} }",
        1,
        20,
        "unexpected `}`",
        Some("a body name (e.g. `my_model(x[3], a[1]) { ... }`) or the end of the file"),
    );
    // xor.
    check(
        &model("m = 1 xor 2;"),
        3,
        7,
        "unexpected `xor`",
        Some("`;`"),
    );
    // Arrays: only `s` and declared arrays take items and literals.
    check(
        &model("t = [1, 2];\nm = 1;"),
        3,
        1,
        "`t` is not a declared array: a list cannot be assigned",
        Some("an `array t[size];` declaration at the start of the body"),
    );
    check(
        &model("t[1] = 2;\nm = 1;"),
        3,
        1,
        "`t` is not a declared array: an item cannot be assigned",
        Some("an `array t[size];` declaration at the start of the body"),
    );
    check(
        &model("s = 1;\nm = 1;"),
        3,
        5,
        "`s` is an array",
        Some("`[` (e.g. `s = [1, 0, 0];`)"),
    );
    check(
        &model("array c[2];\nc = x[1];\nm = 1;"),
        4,
        5,
        "`c` is an array",
        Some("`[` (e.g. `c = [1, 0, 0];`)"),
    );
    check(
        &model("array c[2];\nc + 1;\nm = 1;"),
        4,
        3,
        "unexpected `+`",
        Some("`[` or `=`"),
    );
    check(
        &model("t + 1;\nm = 1;"),
        3,
        3,
        "unexpected `+`",
        Some("`=`"),
    );
    // Malformed number.
    check(
        &model("m = 1e+;"),
        3,
        5,
        "malformed number",
        Some("digits after the exponent mark"),
    );
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    for (open, close) in [("(", ")"), ("- ", ""), ("f(", ")"), ("x[", "]")] {
        let n = 10_000;
        let src = model(&format!("m = {}1{};", open.repeat(n), close.repeat(n)));
        let d = err(&src);
        assert!(d.message.contains("nesting is too deep"), "{open}: {d}");
        assert_eq!(d.span.line, 3);
    }
    let n = 10_000;
    let src = model(&format!(
        "if {}1{} then t=1; endif; m = 1;",
        "(".repeat(n),
        ")".repeat(n)
    ));
    assert!(err(&src).message.contains("nesting is too deep"));
    let src = model(&format!("if {}1 then t=1; endif; m = 1;", "not ".repeat(n)));
    assert!(err(&src).message.contains("nesting is too deep"));
    let src = model(&format!(
        "{}t=1;{} m = 1;",
        "if 1 then ".repeat(n),
        "endif;".repeat(n)
    ));
    assert!(err(&src).message.contains("nesting is too deep"));
    let src = model(&format!(
        "{}t=1;{} m = 1;",
        "while 1 loop ".repeat(n),
        "endloop;".repeat(n)
    ));
    assert!(err(&src).message.contains("nesting is too deep"));
    // Long operator chains make deep trees too.
    let src = model(&format!("m = 1{};", "+1".repeat(n)));
    assert!(err(&src).message.contains("nesting is too deep"));
    // Within the limit, everything is fine.
    let k = 60;
    let src = model(&format!("m = {}1{};", "(-".repeat(k), ")".repeat(k)));
    assert!(parse(&src).is_ok());
    let src = model(&format!("m = 1{};", "+1".repeat(200)));
    assert!(parse(&src).is_ok());
}

#[test]
fn source_size_limit() {
    let limits = ParseLimits {
        max_depth: 10,
        max_source_bytes: 10,
    };
    let d = parse_with("m(x[3], a[1]) { m = 1; }", &limits).unwrap_err();
    assert!(d.message.contains("too large"));
}

#[test]
fn nesting_at_the_limit_fits_a_small_stack() {
    // Every construct nested right up to the default limit, parsed on a
    // thread with a 1 MiB stack (debug build): must not overflow.
    let max = ParseLimits::default().max_depth;
    let handle = std::thread::Builder::new()
        .stack_size(1 << 20)
        .spawn(move || {
            let n = max - 2;
            let shapes: [(&str, &str); 5] = [
                ("(", ")"),
                ("- ", ""),
                ("f(", ")"),
                ("x[", "]"),
                ("g(x, -(", "))"),
            ];
            for (open, close) in shapes {
                // `g(x, -(` nests three levels: the argument, the sign, the parenthesis.
                let k = if open.len() > 3 { n / 3 } else { n };
                let src = model(&format!("m = {}1{};", open.repeat(k), close.repeat(k)));
                assert!(parse(&src).is_ok(), "{open}");
                let src = model(&format!(
                    "m = {}1{};",
                    open.repeat(max + 5),
                    close.repeat(max + 5)
                ));
                assert!(parse(&src).is_err(), "{open}");
            }
            for (open, close) in [("(", ")"), ("not ", "")] {
                let src = model(&format!(
                    "if {}1{} then t = 1; endif; m = 1;",
                    open.repeat(n - 2),
                    close.repeat(n - 2)
                ));
                assert!(parse(&src).is_ok(), "{open}");
            }
            let src = model(&format!(
                "{}t=1;{} m = 1;",
                "if 1 then ".repeat(n),
                "endif;".repeat(n)
            ));
            assert!(parse(&src).is_ok());
        })
        .expect("spawn");
    assert!(handle.join().is_ok());
}

#[test]
fn many_bodies_and_long_inputs_are_linear() {
    // 50k tiny bodies: the uniqueness check must not be quadratic.
    let mut src = String::new();
    for i in 0..50_000 {
        src.push_str(&format!("b{i}(x[1],a[1]){{b{i}=1;}}\n"));
    }
    let t = std::time::Instant::now();
    assert_eq!(parse(&src).map(|p| p.bodies.len()), Ok(50_000));
    assert!(t.elapsed().as_secs() < 20);
    // A long comment and a long statement list.
    let src = model(&format!(
        "-- {}\n{}m = t;",
        "c".repeat(1 << 20),
        "t = 1;".repeat(100_000)
    ));
    assert!(parse(&src).is_ok());
}
