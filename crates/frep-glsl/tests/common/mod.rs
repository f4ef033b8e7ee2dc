//! Shared helpers: glslangValidator and the benchmark models M1–M4.
#![allow(dead_code)]

use std::io::Write;
use std::process::{Command, Stdio};

use frep_core::ops::{BinaryOp, BlendOp, EvalError, UnaryOp};
use frep_core::{Graph, Node, NodeId, Tape};

/// Validates a complete GLSL ES 3.00 fragment shader with glslangValidator.
/// Returns `Err(log)` when it is rejected. Panics when the validator is
/// missing, unless `FREP_SKIP_GLSLANG=1` (then returns Ok after a note).
pub fn validate_frag(source: &str) -> Result<(), String> {
    validate(source, "frag")
}

/// Validates a vertex shader.
pub fn validate_vert(source: &str) -> Result<(), String> {
    validate(source, "vert")
}

fn validate(source: &str, stage: &str) -> Result<(), String> {
    let child = Command::new("glslangValidator")
        .args(["--stdin", "-S", stage])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn();
    let mut child = match child {
        Ok(c) => c,
        Err(e) => {
            if std::env::var("FREP_SKIP_GLSLANG").as_deref() == Ok("1") {
                eprintln!("note: glslangValidator not run ({e}); FREP_SKIP_GLSLANG=1");
                return Ok(());
            }
            panic!(
                "glslangValidator is required to validate generated shaders ({e}). \
                 Install it (Debian: apt-get install -y glslang-tools) or set FREP_SKIP_GLSLANG=1 to skip."
            );
        }
    };
    {
        let mut stdin = child.stdin.take().expect("stdin");
        // The validator may stop reading early on a fatal error.
        let _ = stdin.write_all(source.as_bytes());
    }
    let out = child.wait_with_output().expect("glslangValidator ran");
    if out.status.success() {
        Ok(())
    } else {
        Err(format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ))
    }
}

/// Panics with the validator's log and the offending lines.
pub fn assert_valid(name: &str, source: &str) {
    if let Err(log) = validate_frag(source) {
        let lines: Vec<&str> = source.lines().collect();
        let mut ctx = String::new();
        for l in log.lines() {
            // "ERROR: 0:123: ..."
            if let Some(n) = l
                .split(':')
                .nth(2)
                .and_then(|s| s.trim().parse::<usize>().ok())
            {
                if let Some(src) = lines.get(n.saturating_sub(1)) {
                    ctx.push_str(&format!("{n}: {src}\n"));
                }
            }
        }
        panic!("{name}: glslangValidator rejected the shader:\n{log}\n{ctx}");
    }
}

fn sq(g: &mut Graph, a: NodeId) -> NodeId {
    g.pow_int(a, 2)
}

fn dist2(g: &mut Graph, c: [f64; 3]) -> NodeId {
    let mut terms = Vec::new();
    for (k, &ck) in c.iter().enumerate() {
        let x = g.x(k as u32);
        let cc = g.constant(ck);
        let d = g.binary(BinaryOp::Sub, x, cc);
        terms.push(sq(g, d));
    }
    let s = g.binary(BinaryOp::Add, terms[0], terms[1]);
    g.binary(BinaryOp::Add, s, terms[2])
}

/// M1: `0.8 - sqrt(x²+y²+z²)`.
pub fn m1() -> Tape {
    let mut g = Graph::new();
    let d2 = dist2(&mut g, [0.0; 3]);
    let r = g.unary(UnaryOp::Sqrt, d2);
    let c = g.constant(0.8);
    let f = g.binary(BinaryOp::Sub, c, r);
    g.tape(&[f])
}

/// M2: max over 100 spheres of `0.2 - |p - c|`.
pub fn m2() -> Tape {
    let mut g = Graph::new();
    let rad = g.constant(0.2);
    let mut acc: Option<NodeId> = None;
    for a in 0..5 {
        for b in 0..5 {
            for c in 0..4 {
                let ctr = [
                    -0.72 + 0.36 * a as f64,
                    -0.72 + 0.36 * b as f64,
                    -0.54 + 0.36 * c as f64,
                ];
                let d2 = dist2(&mut g, ctr);
                let d = g.unary(UnaryOp::Sqrt, d2);
                let s = g.binary(BinaryOp::Sub, rad, d);
                acc = Some(match acc {
                    None => s,
                    Some(p) => g.binary(BinaryOp::Max, p, s),
                });
            }
        }
    }
    g.tape(&[acc.unwrap()])
}

/// M3: `min(-gyroid(8p), 0.9 - |p|)`.
pub fn m3() -> Tape {
    let mut g = Graph::new();
    let eight = g.constant(8.0);
    let mut s = Vec::new();
    let mut c = Vec::new();
    for k in 0..3 {
        let x = g.x(k);
        let x8 = g.binary(BinaryOp::Mul, eight, x);
        s.push(g.unary(UnaryOp::Sin, x8));
        c.push(g.unary(UnaryOp::Cos, x8));
    }
    let t0 = g.binary(BinaryOp::Mul, s[0], c[1]);
    let t1 = g.binary(BinaryOp::Mul, s[1], c[2]);
    let t2 = g.binary(BinaryOp::Mul, s[2], c[0]);
    let gy = g.binary(BinaryOp::Add, t0, t1);
    let gy = g.binary(BinaryOp::Add, gy, t2);
    let ngy = g.unary(UnaryOp::Neg, gy);
    let d2 = dist2(&mut g, [0.0; 3]);
    let r = g.unary(UnaryOp::Sqrt, d2);
    let c9 = g.constant(0.9);
    let ball = g.binary(BinaryOp::Sub, c9, r);
    let f = g.binary(BinaryOp::Min, ngy, ball);
    g.tape(&[f])
}

/// M4: R-union chain of 10 spheres `0.0625 - |p - c_i|²`.
pub fn m4() -> Tape {
    let mut g = Graph::new();
    let r2 = g.constant(0.0625);
    let mut acc: Option<NodeId> = None;
    for i in 0..10 {
        let t = 0.6 * i as f64;
        let ctr = [0.6 * t.cos(), 0.6 * t.sin(), -0.8 + 0.16 * i as f64];
        let d2 = dist2(&mut g, ctr);
        let s = g.binary(BinaryOp::Sub, r2, d2);
        acc = Some(match acc {
            None => s,
            Some(p) => g.binary(BinaryOp::RUnion, p, s),
        });
    }
    g.tape(&[acc.unwrap()])
}

/// A tape with every operation of the graph.
pub fn exhaustive() -> Tape {
    let mut g = Graph::new();
    let (x, y, z, w) = (g.x(0), g.x(1), g.x(2), g.x(3));
    let (p0, p1) = (g.param(0), g.param(1));
    let c = g.constant(0.37);
    let xy = g.binary(BinaryOp::Add, x, w);
    let mut terms = vec![xy, p0];
    for op in UnaryOp::ALL {
        let t = g.unary(op, x);
        terms.push(t);
    }
    for op in BinaryOp::ALL {
        let t = g.binary(op, x, y);
        terms.push(t);
    }
    for op in [BlendOp::Union, BlendOp::Inter] {
        let t = g.blend(op, [x, y, c, p1, z]);
        terms.push(t);
    }
    for n in [3, 2, 1, 0, -1, -2, -5] {
        let t = g.pow_int(z, n);
        terms.push(t);
    }
    let sel = g.select(x, y, z);
    terms.push(sel);
    // An error node under a select (the graph folds errors elsewhere).
    let err = g.error(EvalError::DivisionByZero);
    let sel_err = g.select(y, err, x);
    terms.push(sel_err);
    // A check: the value of y, with sqrt(x)'s error first.
    let sx = g.unary(UnaryOp::Sqrt, x);
    let chk = g.check(sx, y);
    assert!(matches!(g.node(chk), Node::Check(..)));
    terms.push(chk);
    let mut acc = terms[0];
    for &t in &terms[1..] {
        acc = g.binary(BinaryOp::Add, acc, t);
    }
    let tape = g.tape(&[acc]);
    // Every kind of node is present.
    let has = |f: &dyn Fn(&Node) -> bool| tape.nodes.iter().any(f);
    for op in UnaryOp::ALL {
        assert!(
            has(&|n| matches!(n, Node::Unary(o, _) if *o == op)),
            "{op:?}"
        );
    }
    for op in BinaryOp::ALL {
        assert!(
            has(&|n| matches!(n, Node::Binary(o, ..) if *o == op)),
            "{op:?}"
        );
    }
    for k in 0..4 {
        assert!(has(&|n| *n == Node::X(k)));
    }
    assert!(has(&|n| matches!(n, Node::Blend(BlendOp::Union, _))));
    assert!(has(&|n| matches!(n, Node::Blend(BlendOp::Inter, _))));
    assert!(has(&|n| matches!(n, Node::PowI(_, 0))));
    assert!(has(&|n| matches!(n, Node::PowI(_, k) if *k < 0)));
    assert!(has(&|n| matches!(n, Node::Error(_))));
    assert!(has(&|n| matches!(n, Node::Check(..))));
    assert!(has(&|n| matches!(n, Node::Select(..))));
    assert!(has(&|n| matches!(n, Node::Param(_))));
    assert!(has(&|n| matches!(n, Node::Const(_))));
    tape
}
