//! Tests of the library port: golden values of the reference interpreter,
//! independent f64 formulas, quadrature of the convolution kernels, and
//! symbolic builds evaluated against constant ones.

#![allow(
    clippy::excessive_precision,
    clippy::approx_constant,
    clippy::type_complexity
)]

use super::*;
use crate::graph::Node;
use crate::ops;

/// A test argument.
#[derive(Clone)]
enum Ta {
    S(f64),
    A(Vec<f64>),
}
use Ta::{A as Arr, S as Sc};

fn arr(v: &[f64]) -> Ta {
    Arr(v.to_vec())
}

fn to_args(g: &mut Graph, ta: &[Ta]) -> Vec<LibArg> {
    ta.iter()
        .map(|t| match t {
            Sc(v) => LibArg::Scalar(g.constant(*v)),
            Arr(v) => LibArg::Array(v.iter().map(|&x| g.constant(x)).collect()),
        })
        .collect()
}

fn consts(g: &Graph, v: &[NodeId]) -> Vec<f64> {
    v.iter()
        .map(|&n| g.const_value(n).expect("constant item"))
        .collect()
}

/// Calls `name` with constant arguments: its value and the final arrays.
fn run(name: &str, ta: &[Ta]) -> (f64, Vec<Vec<f64>>) {
    let f = lookup(name).unwrap_or_else(|| panic!("{name} missing"));
    assert_eq!(f.params.len(), ta.len(), "{name} arity");
    let mut g = Graph::new();
    let mut args = to_args(&mut g, ta);
    let r = (f.build)(&mut g, &mut args).unwrap_or_else(|e| panic!("{name}: {e}"));
    let v = g
        .const_value(r)
        .unwrap_or_else(|| panic!("{name} did not fold"));
    let arrays = args
        .iter()
        .map(|a| match a {
            LibArg::Array(v) => consts(&g, v),
            LibArg::Scalar(_) => Vec::new(),
        })
        .collect();
    (v, arrays)
}

fn val(name: &str, ta: &[Ta]) -> f64 {
    run(name, ta).0
}

fn run_err(name: &str, ta: &[Ta]) -> LibError {
    let f = lookup(name).unwrap();
    let mut g = Graph::new();
    let mut args = to_args(&mut g, ta);
    (f.build)(&mut g, &mut args).expect_err("expected a LibError")
}

fn close(got: f64, want: f64, rel: f64, abs: f64) -> bool {
    (got.is_nan() && want.is_nan()) || got == want || (got - want).abs() <= abs + rel * want.abs()
}

#[track_caller]
fn assert_close(got: f64, want: f64) {
    assert!(close(got, want, 1e-12, 1e-14), "got {got:e}, want {want:e}");
}

fn transform(p: [f64; 3], name: &str, rest: &[Ta]) -> Vec<f64> {
    let mut ta = vec![arr(&p)];
    ta.extend_from_slice(rest);
    let (r, arrays) = run(name, &ta);
    assert_eq!(r, 1.0);
    arrays[0].clone()
}

fn sq(v: f64) -> f64 {
    v * v
}

mod formulas;
const PTS: [[f64; 3]; 5] = [
    [0.0, 0.0, 0.0],
    [0.3, -0.7, 1.1],
    [-1.2, 0.4, 0.25],
    [2.0, 1.5, -0.5],
    [0.05, 0.9, -1.3],
];

mod golden;
mod quadrature;
mod symbolic;
mod table;
