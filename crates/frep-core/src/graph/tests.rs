//! Tests of the expression graph: hash-consing, folding, tapes and
//! polynomial degrees.

use super::*;

#[test]
fn folds_and_dedups() {
    let mut g = Graph::new();
    let x = g.x(0);
    let two = g.constant(2.0);
    let three = g.constant(3.0);
    let five = g.binary(BinaryOp::Add, two, three);
    assert_eq!(g.const_value(five), Some(5.0));
    let a = g.binary(BinaryOp::Mul, x, five);
    let b = g.binary(BinaryOp::Mul, five, x);
    assert_eq!(a, b, "commutative twins are one node");
    let zero = g.constant(0.0);
    assert_eq!(g.binary(BinaryOp::Add, a, zero), a);
    let one = g.constant(1.0);
    let d = g.binary(BinaryOp::Div, one, zero);
    assert_eq!(g.error_value(d), Some(EvalError::DivisionByZero));
    let sq = g.binary(BinaryOp::Pow, x, two);
    assert_eq!(*g.node(sq), Node::PowI(x, 2));
}

#[test]
fn errors_keep_reference_order() {
    let mut g = Graph::new();
    let x = g.x(0);
    let zero = g.constant(0.0);
    let one = g.constant(1.0);
    let s = g.unary(UnaryOp::Sqrt, x); // may fail
    let e = g.binary(BinaryOp::Div, one, zero); // always fails
                                                // e + s: s (right) is evaluated first; its error wins where it fails.
    let sum = g.binary(BinaryOp::Add, e, s);
    assert_eq!(*g.node(sum), Node::Check(s, e));
    // s + e: e evaluated first, always fails.
    let sum2 = g.binary(BinaryOp::Add, s, e);
    assert_eq!(sum2, e);
}

#[test]
fn polynomial_degrees() {
    let mut g = Graph::new();
    let [x, y, z] = [0, 1, 2].map(|i| g.x(i));
    let w = g.x(3);
    let a = g.param(0);
    let deg = |g: &Graph, f: NodeId| g.tape(&[f]).polynomial_degree();
    // r² − x² − y² − z², the sphere, with a parameter radius.
    let r2 = g.pow_int(a, 2);
    let x2 = g.pow_int(x, 2);
    let yy = g.binary(BinaryOp::Mul, y, y);
    let z2 = g.pow_int(z, 2);
    let f = g.binary(BinaryOp::Sub, r2, x2);
    let f = g.binary(BinaryOp::Sub, f, yy);
    let sphere = g.binary(BinaryOp::Sub, f, z2);
    assert_eq!(deg(&g, sphere), Some(2));
    let plane = g.binary(BinaryOp::Sub, a, z);
    assert_eq!(deg(&g, plane), Some(1));
    let neg = g.unary(UnaryOp::Neg, plane);
    assert_eq!(deg(&g, neg), Some(1));
    // x[4] and functions of parameters are constants for a point.
    let s = g.unary(UnaryOp::Sin, a);
    let sw = g.binary(BinaryOp::Mul, s, w);
    assert_eq!(deg(&g, sw), Some(0));
    let xs = g.binary(BinaryOp::DivF, x, s);
    assert_eq!(deg(&g, xs), Some(1));
    let xyz = g.binary(BinaryOp::Mul, x, y);
    let xyz = g.binary(BinaryOp::Mul, xyz, z);
    assert_eq!(deg(&g, xyz), Some(3));
    let p = g.pow_int(xyz, 30);
    assert_eq!(deg(&g, p), None, "degree 90 is above the limit");
    let sel = g.select(s, x2, plane);
    assert_eq!(deg(&g, sel), Some(2));
    // Not polynomials in the point.
    let sel = g.select(x, x2, plane);
    assert_eq!(deg(&g, sel), None);
    let inv = g.pow_int(x, -1);
    assert_eq!(deg(&g, inv), None);
    let q = g.binary(BinaryOp::DivF, a, x);
    assert_eq!(deg(&g, q), None);
    let r = g.binary(BinaryOp::RInter, sphere, plane);
    assert_eq!(deg(&g, r), None);
    let sq = g.unary(UnaryOp::Sqrt, sphere);
    assert_eq!(deg(&g, sq), None);
    let m = g.binary(BinaryOp::Max, sphere, plane);
    assert_eq!(deg(&g, m), None);
}

#[test]
fn root_gaps() {
    let mut g = Graph::new();
    let [x, y, z] = [0, 1, 2].map(|i| g.x(i));
    let gap = |g: &Graph, f: NodeId| g.tape(&[f]).root_gap();
    // 0.8 − sqrt(x² + y² + z²), M1's sphere.
    let x2 = g.pow_int(x, 2);
    let y2 = g.pow_int(y, 2);
    let z2 = g.pow_int(z, 2);
    let p = g.binary(BinaryOp::Add, x2, y2);
    let p3 = g.binary(BinaryOp::Add, p, z2);
    let k = g.constant(0.8);
    for op in [UnaryOp::Sqrt, UnaryOp::SqrtF] {
        let r = g.unary(op, p3);
        let f = g.binary(BinaryOp::Sub, k, r);
        assert_eq!(gap(&g, f), Some(0.8));
    }
    // A cylinder, sqrt(x² + y²).
    let r = g.unary(UnaryOp::Sqrt, p);
    let f = g.binary(BinaryOp::Sub, k, r);
    assert_eq!(gap(&g, f), Some(0.8));
    // Not of the form: a non-positive or point-dependent `k`, a root of
    // degree 1 or 4, the reversed difference.
    let r = g.unary(UnaryOp::Sqrt, p3);
    for k in [g.constant(0.0), g.constant(-1.0), g.param(0), z] {
        let f = g.binary(BinaryOp::Sub, k, r);
        assert_eq!(gap(&g, f), None);
    }
    let f = g.binary(BinaryOp::Sub, r, k);
    assert_eq!(gap(&g, f), None);
    let lin = g.unary(UnaryOp::Sqrt, x);
    let f = g.binary(BinaryOp::Sub, k, lin);
    assert_eq!(gap(&g, f), None);
    let p4 = g.pow_int(p3, 2);
    let r4 = g.unary(UnaryOp::Sqrt, p4);
    let f = g.binary(BinaryOp::Sub, k, r4);
    assert_eq!(gap(&g, f), None);
}

#[test]
fn tape_drops_dead_nodes() {
    let mut g = Graph::new();
    let x = g.x(0);
    let y = g.x(1);
    let _dead = g.unary(UnaryOp::Sin, y);
    let c = g.constant(2.0);
    let f = g.binary(BinaryOp::Mul, x, c);
    let t = g.tape(&[f]);
    assert_eq!(t.len(), 3);
    assert_eq!(t.outputs, vec![NodeId(2)]);
    assert_eq!(t.x_slots(), 1);
}
