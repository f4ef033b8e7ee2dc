//! Translation of a frep [`Tape`] into a fidget [`Tree`], so that fidget can
//! evaluate the same models as frep in the same benchmark run.
//!
//! The tree is what a fidget user would write by hand for the same field:
//! * **negated** — fidget's convention is negative inside, HyperFun's
//!   positive inside. The negation is pushed into the expression where that is
//!   free: `-(a - b)` is `b - a`, `-min(a, b)` is `max(-a, -b)`, `-(a | b)`
//!   is the R-intersection of `-a` and `-b`, constants flip their sign. So
//!   the translated M1–M4 have the same operations as the hand-written
//!   anchors of [`anchors`](crate::anchors);
//! * R-functions expanded as `a + b ± sqrt(a² + b²)`, blends as
//!   `r + a0 / (1 + (f1/a1)² + (f2/a2)²)`;
//! * integer powers by squaring ([`Tree::pow`]);
//! * checked operations (`/`, `sqrt`, `log`, `asin`, ...) as their plain
//!   math: fidget gives NaN or infinities where frep's bulk evaluators give
//!   NaN;
//! * comparisons, `and`, `or`, `not` and selects through fidget's `compare`,
//!   `and`, `or` and `not`, with HyperFun's truth test `|v| >= 1e-6`;
//! * sub-expressions that do not depend on the point, folded in `f64` by
//!   frep's own scalar operations, then rounded to `f32`. They are constants,
//!   parameters and extra coordinates, all read as 0 like
//!   [`Inputs::default`](frep_core::Inputs).
//!
//! fidget evaluates in `f32`, so values agree with frep's `f64` ones to about
//! `1e-6` relative. Operations fidget cannot express give a
//! [`TranslateError`]: HyperFun's `^` with an exponent that depends on the
//! point (integer exponents of negative bases have no `f32` formula there).

use std::fmt;

use fidget::context::Tree;
use frep_core::eval::batch::{binary_lane, unary_lane};
use frep_core::graph::{Node, NodeId, Tape};
use frep_core::ops::{self, BinaryOp, BlendOp, UnaryOp, EPS};

/// Why a tape has no fidget translation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum TranslateError {
    /// The tape has no output.
    NoOutput,
    /// An operation fidget cannot express (its name).
    Unsupported(&'static str),
}

impl fmt::Display for TranslateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TranslateError::NoOutput => f.write_str("the tape has no output"),
            TranslateError::Unsupported(op) => {
                write!(f, "fidget has no equivalent of frep's `{op}`")
            }
        }
    }
}

impl std::error::Error for TranslateError {}

const POS: u8 = 1;
const NEG: u8 = 2;

/// `tree` seen through the map from fidget's `[-1, 1]³` onto the cube `(centre, half)`. The
/// map is x ↦ centre + half·x on each axis, so fidget's native box covers that cube. The same
/// tree when the cube is `[-1, 1]³`.
pub fn in_cube(tree: &Tree, (c, half): ([f64; 3], f64)) -> Tree {
    if c == [0.0; 3] && half == 1.0 {
        return tree.clone();
    }
    let (x, y, z) = Tree::axes();
    let m = |t: Tree, k: usize| t * half as f32 + c[k] as f32;
    tree.remap_xyz(m(x, 0), m(y, 1), m(z, 2))
}

/// Translates output 0 of `tape` (positive inside) into a fidget tree of its
/// negation (negative inside). See the module docs.
pub fn tape_to_tree(tape: &Tape) -> Result<Tree, TranslateError> {
    let root = *tape.outputs.first().ok_or(TranslateError::NoOutput)?;
    let nodes = &tape.nodes;
    let uniform = uniform_values(nodes);
    let cheap = cheap_negations(nodes, &uniform);
    let need = needed_signs(nodes, root, &uniform, &cheap)?;
    let neg = build_trees(nodes, &uniform, &cheap, &need)?;
    Ok(neg[root.index()].clone().expect("root built"))
}

/// Values of the nodes that do not depend on the point, folded in f64.
fn uniform_values(nodes: &[Node]) -> Vec<Option<f64>> {
    let n = nodes.len();
    let mut uniform: Vec<Option<f64>> = Vec::with_capacity(n);
    for node in nodes {
        let u = |c: NodeId| uniform[c.index()];
        let v = match *node {
            Node::Const(_) => node.const_value(),
            Node::X(k) => (k >= 3).then_some(0.0),
            Node::Param(_) => Some(0.0),
            Node::Error(_) => Some(f64::NAN),
            Node::Unary(op, a) => u(a).map(|a| unary_lane(op, a)),
            Node::Binary(op, a, b) => u(a).zip(u(b)).map(|(a, b)| binary_lane(op, a, b)),
            Node::PowI(a, k) => u(a).map(|a| ops::pow_int(a, k).unwrap_or(f64::NAN)),
            Node::Select(c, t, e) => match (u(c), u(t), u(e)) {
                (Some(c), Some(t), Some(e)) => Some(if ops::truthy(c) { t } else { e }),
                _ => None,
            },
            Node::Blend(op, a) => {
                let v: Option<Vec<f64>> = a.iter().map(|&c| u(c)).collect();
                v.map(|v| ops::blend(op, v[0], v[1], v[2], v[3], v[4]))
            }
            Node::Check(_, v) => u(v),
        };
        uniform.push(v);
    }
    uniform
}

/// Whether the negation of each node costs no extra operation.
fn cheap_negations(nodes: &[Node], uniform: &[Option<f64>]) -> Vec<bool> {
    let n = nodes.len();
    let is_const = |c: NodeId| uniform[c.index()].is_some();
    let mut cheap = vec![false; n];
    for (i, node) in nodes.iter().enumerate() {
        let ch = |c: NodeId| cheap[c.index()];
        cheap[i] = uniform[i].is_some()
            || match *node {
                Node::Unary(UnaryOp::Neg, _) | Node::Binary(BinaryOp::Sub, _, _) => true,
                Node::Binary(BinaryOp::Add, a, b) => is_const(a) || is_const(b) || ch(a),
                Node::Binary(BinaryOp::Mul | BinaryOp::Div | BinaryOp::DivF, a, b) => {
                    is_const(a) || is_const(b) || ch(a) || ch(b)
                }
                Node::Binary(
                    BinaryOp::Min | BinaryOp::Max | BinaryOp::RUnion | BinaryOp::RInter,
                    a,
                    b,
                ) => ch(a) && ch(b),
                Node::Binary(BinaryOp::RDiff, a, _) => ch(a),
                Node::Select(_, t, e) => ch(t) && ch(e),
                Node::Blend(_, [f1, f2, a0, _, _]) => ch(f1) && ch(f2) && is_const(a0),
                Node::Check(_, v) => ch(v),
                _ => false,
            };
    }

    cheap
}

/// Which signs (`POS`, `NEG` flags) of which nodes the root's negation needs, top-down.
fn needed_signs(
    nodes: &[Node],
    root: NodeId,
    uniform: &[Option<f64>],
    cheap: &[bool],
) -> Result<Vec<u8>, TranslateError> {
    let n = nodes.len();
    let is_const = |c: NodeId| uniform[c.index()].is_some();
    let mut need = vec![0u8; n];
    need[root.index()] = NEG;
    for i in (0..n).rev() {
        if uniform[i].is_some() || need[i] == 0 {
            continue;
        }
        let mut flags = need[i];
        let mut reqs: Vec<(NodeId, u8)> = Vec::new();
        let mut req = |c: NodeId, s: u8| reqs.push((c, s));
        if flags & NEG != 0 {
            if cheap[i] {
                match nodes[i] {
                    Node::Unary(UnaryOp::Neg, a) => req(a, POS),
                    Node::Binary(BinaryOp::Sub, a, b) => {
                        req(a, POS);
                        req(b, POS);
                    }
                    Node::Binary(BinaryOp::Add, a, b) => {
                        if is_const(a) || is_const(b) {
                            req(a, POS);
                            req(b, POS);
                        } else {
                            req(a, NEG);
                            req(b, POS);
                        }
                    }
                    Node::Binary(BinaryOp::Mul | BinaryOp::Div | BinaryOp::DivF, a, b) => {
                        if is_const(a) || is_const(b) {
                            req(a, POS);
                            req(b, POS);
                        } else if cheap[a.index()] {
                            req(a, NEG);
                            req(b, POS);
                        } else {
                            req(a, POS);
                            req(b, NEG);
                        }
                    }
                    Node::Binary(BinaryOp::RDiff, a, b) => {
                        req(a, NEG);
                        req(b, POS);
                    }
                    Node::Binary(
                        BinaryOp::Min | BinaryOp::Max | BinaryOp::RUnion | BinaryOp::RInter,
                        a,
                        b,
                    ) => {
                        req(a, NEG);
                        req(b, NEG);
                    }
                    Node::Select(c, t, e) => {
                        req(c, POS);
                        req(t, NEG);
                        req(e, NEG);
                    }
                    Node::Blend(_, [f1, f2, _, a1, a2]) => {
                        req(f1, NEG);
                        req(f2, NEG);
                        req(a1, POS);
                        req(a2, POS);
                    }
                    Node::Check(_, v) => req(v, NEG),
                    _ => unreachable!("cheap negation of {:?}", nodes[i]),
                }
            } else {
                flags |= POS;
            }
        }
        if flags & POS != 0 {
            match nodes[i] {
                Node::Check(_, v) => req(v, POS),
                Node::Binary(BinaryOp::Pow, _, _) => {
                    return Err(TranslateError::Unsupported("^ with a varying exponent"))
                }
                node => {
                    for c in node.children() {
                        req(c, POS);
                    }
                }
            }
        }
        need[i] = flags;
        for (c, s) in reqs {
            need[c.index()] |= s;
        }
    }

    Ok(need)
}

/// The needed trees bottom-up: `(positive, negated)` per node, `None` where not needed.
/// Returns the negated ones.
fn build_trees(
    nodes: &[Node],
    uniform: &[Option<f64>],
    cheap: &[bool],
    need: &[u8],
) -> Result<Vec<Option<Tree>>, TranslateError> {
    let n = nodes.len();
    let mut pos: Vec<Option<Tree>> = vec![None; n];
    let mut neg: Vec<Option<Tree>> = vec![None; n];
    for i in 0..n {
        if let Some(v) = uniform[i] {
            if need[i] & POS != 0 {
                pos[i] = Some(Tree::constant(v as f32));
            }
            if need[i] & NEG != 0 {
                neg[i] = Some(Tree::constant(-v as f32));
            }
            continue;
        }
        let p = |c: NodeId| pos[c.index()].clone().expect("positive child built");
        let m = |c: NodeId| neg[c.index()].clone().expect("negated child built");
        let new_pos = if need[i] & POS == 0 {
            None
        } else {
            Some(positive(&nodes[i], p)?)
        };
        let new_neg = if need[i] & NEG == 0 {
            None
        } else {
            let c = |id: NodeId| uniform[id.index()];
            let k = |v: f64| Tree::constant(v as f32);
            Some(if !cheap[i] {
                -new_pos.clone().expect("positive built")
            } else {
                match nodes[i] {
                    Node::Unary(UnaryOp::Neg, a) => p(a),
                    Node::Binary(BinaryOp::Sub, a, b) => p(b) - p(a),
                    Node::Binary(BinaryOp::Add, a, b) => match (c(a), c(b)) {
                        (_, Some(vb)) => k(-vb) - p(a),
                        (Some(va), _) => k(-va) - p(b),
                        _ => m(a) - p(b),
                    },
                    Node::Binary(op @ (BinaryOp::Mul | BinaryOp::Div | BinaryOp::DivF), a, b) => {
                        // -(a op b) with the sign moved onto one operand.
                        let (x, y) = match (c(a), c(b)) {
                            (_, Some(vb)) => (p(a), k(-vb)),
                            (Some(va), _) => (k(-va), p(b)),
                            _ if cheap[a.index()] => (m(a), p(b)),
                            _ => (p(a), m(b)),
                        };
                        if op == BinaryOp::Mul {
                            x * y
                        } else {
                            x / y
                        }
                    }
                    Node::Binary(BinaryOp::Min, a, b) => m(a).max(m(b)),
                    Node::Binary(BinaryOp::Max, a, b) => m(a).min(m(b)),
                    Node::Binary(BinaryOp::RUnion, a, b) => r_inter(m(a), m(b)),
                    Node::Binary(BinaryOp::RInter, a, b) => r_union(m(a), m(b)),
                    Node::Binary(BinaryOp::RDiff, a, b) => r_union(m(a), p(b)),
                    Node::Select(cond, t, e) => select(p(cond), m(t), m(e)),
                    Node::Blend(op, [f1, f2, a0, a1, a2]) => {
                        let (f1, f2) = (m(f1), m(f2));
                        // -(r(f1, f2)) is the dual R-function of the negated
                        // operands; the bump's squares do not see the sign.
                        let r = match op {
                            BlendOp::Union => r_inter(f1.clone(), f2.clone()),
                            BlendOp::Inter => r_union(f1.clone(), f2.clone()),
                        };
                        let a0 = c(a0).expect("cheap blends have a constant a0");
                        r + k(-a0) / blend_denominator(f1, f2, p(a1), p(a2))
                    }
                    Node::Check(_, v) => m(v),
                    ref other => unreachable!("cheap negation of {other:?}"),
                }
            })
        };
        pos[i] = new_pos;
        neg[i] = new_neg;
    }
    Ok(neg)
}

/// The tree of a non-uniform `node`, its children's trees given by `p`.
fn positive(node: &Node, p: impl Fn(NodeId) -> Tree) -> Result<Tree, TranslateError> {
    Ok(match *node {
        Node::X(0) => Tree::x(),
        Node::X(1) => Tree::y(),
        Node::X(2) => Tree::z(),
        Node::Unary(op, a) => unary(op, p(a)),
        Node::Binary(op, a, b) => binary(op, p(a), p(b))?,
        Node::PowI(a, k) => p(a).pow(i64::from(k)),
        Node::Select(c, t, e) => select(p(c), p(t), p(e)),
        Node::Blend(op, [f1, f2, a0, a1, a2]) => {
            let (f1, f2) = (p(f1), p(f2));
            let r = match op {
                BlendOp::Union => r_union(f1.clone(), f2.clone()),
                BlendOp::Inter => r_inter(f1.clone(), f2.clone()),
            };
            r + p(a0) / blend_denominator(f1, f2, p(a1), p(a2))
        }
        Node::Check(_, v) => p(v),
        ref other => unreachable!("non-uniform leaf {other:?}"),
    })
}

fn r_union(a: Tree, b: Tree) -> Tree {
    a.clone() + b.clone() + (a.square() + b.square()).sqrt()
}

fn r_inter(a: Tree, b: Tree) -> Tree {
    a.clone() + b.clone() - (a.square() + b.square()).sqrt()
}

fn blend_denominator(f1: Tree, f2: Tree, a1: Tree, a2: Tree) -> Tree {
    1.0 + (f1 / a1).square() + (f2 / a2).square()
}

/// 1 where `|v| >= 1e-6` (HyperFun's truth), else 0; NaN gives 0 as in frep
/// (`compare` of NaN is NaN, and `not(NaN)` is 0).
fn truthy(v: Tree) -> Tree {
    // compare is -1 exactly when |v| < eps; `not(compare + 1)` is then 1.
    less(v.abs(), Tree::constant(EPS as f32)).not()
}

/// 1 where `a < b`, else 0.
fn less(a: Tree, b: Tree) -> Tree {
    (a.compare(b) + 1.0).not()
}

/// 1 where `a > b`, else 0.
fn greater(a: Tree, b: Tree) -> Tree {
    (a.compare(b) - 1.0).not()
}

/// `if truthy(c) { t } else { e }` with fidget's `and`/`or` (what its
/// `Context::if_nonzero_else` builds).
fn select(c: Tree, t: Tree, e: Tree) -> Tree {
    let c = truthy(c);
    c.and(t).or(c.not().and(e))
}

/// Truncation toward zero: `sign(a) * floor(|a|)`.
fn trunc(a: Tree) -> Tree {
    a.compare(0.0) * a.abs().floor()
}

fn unary(op: UnaryOp, a: Tree) -> Tree {
    match op {
        UnaryOp::Neg => -a,
        UnaryOp::Abs => a.abs(),
        UnaryOp::Sqrt | UnaryOp::SqrtF => a.sqrt(),
        UnaryOp::Exp => a.exp(),
        UnaryOp::Log => a.ln(),
        UnaryOp::Logd => a.ln() * std::f32::consts::LOG10_E,
        UnaryOp::Sin => a.sin(),
        UnaryOp::Cos => a.cos(),
        UnaryOp::Tan => a.tan(),
        UnaryOp::Asin => a.asin(),
        UnaryOp::Acos => a.acos(),
        UnaryOp::Atan => a.atan(),
        UnaryOp::Sinh => (a.exp() - (-a).exp()) * 0.5,
        UnaryOp::Cosh => (a.exp() + (-a).exp()) * 0.5,
        // 1 - 2 / (e^2a + 1): ±1 (not NaN) for large |a|.
        UnaryOp::Tanh => 1.0 - 2.0 / ((a * 2.0).exp() + 1.0),
        UnaryOp::Ceil => a.ceil(),
        UnaryOp::Floor => a.floor(),
        UnaryOp::Trunc => trunc(a),
        UnaryOp::Frac => a.clone() - trunc(a),
        UnaryOp::Not => truthy(a).not(),
        // ceil(v), minus 1 if that is more than 0.5 above v: floor(v + 0.5).
        UnaryOp::RoundHalfUp => (a + 0.5).floor(),
    }
}

fn binary(op: BinaryOp, a: Tree, b: Tree) -> Result<Tree, TranslateError> {
    let eps = || Tree::constant(EPS as f32);
    Ok(match op {
        BinaryOp::Add => a + b,
        BinaryOp::Sub => a - b,
        BinaryOp::Mul => a * b,
        BinaryOp::Div | BinaryOp::DivF => a / b,
        BinaryOp::Pow => return Err(TranslateError::Unsupported("^ with a varying exponent")),
        // C pow of a non-negative base (what the library functions use).
        BinaryOp::PowF => (b * a.ln()).exp(),
        BinaryOp::Min => a.min(b),
        BinaryOp::Max => a.max(b),
        BinaryOp::Atan2 => a.atan2(b),
        // fmod(round(a), round(b)) = x - trunc(x / y) * y.
        BinaryOp::Mod => {
            let (x, y) = ((a + 0.5).floor(), (b + 0.5).floor());
            x.clone() - trunc(x / y.clone()) * y
        }
        BinaryOp::RUnion => r_union(a, b),
        BinaryOp::RInter => r_inter(a, b),
        BinaryOp::RDiff => r_inter(a, -b),
        BinaryOp::Lt => less(a, b),
        BinaryOp::Gt => greater(a, b),
        BinaryOp::Le => 1.0 - greater(a, b),
        BinaryOp::Ge => 1.0 - less(a, b),
        BinaryOp::Eq => less((a - b).abs(), eps()),
        BinaryOp::Ne => 1.0 - less((a - b).abs(), eps()),
        BinaryOp::And => truthy(a).and(truthy(b)),
        BinaryOp::Or => truthy(a).or(truthy(b)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use fidget::shape::EzShape;
    use fidget::vm::VmShape;
    use frep_core::eval::batch::BatchEval;
    use frep_core::{Inputs, Model};
    use std::path::Path;

    fn examples() -> Vec<(String, String)> {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
        let mut out: Vec<(String, String)> = std::fs::read_dir(&dir)
            .expect("examples/")
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|x| x == "hf"))
            .map(|p| {
                let name = p
                    .file_stem()
                    .expect("file name")
                    .to_string_lossy()
                    .into_owned();
                (name, std::fs::read_to_string(&p).expect("readable example"))
            })
            .collect();
        out.sort();
        out
    }

    /// A small xorshift generator: reproducible points without a dependency.
    fn points(count: usize, lo: f32, hi: f32) -> [Vec<f32>; 3] {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            lo + (hi - lo) * ((s >> 40) as f32 / (1u64 << 24) as f32)
        };
        let mut p: [Vec<f32>; 3] = Default::default();
        for _ in 0..count {
            for axis in &mut p {
                axis.push(next());
            }
        }
        p
    }

    /// Whether `src` translates; if it does, asserts that fidget's values are
    /// within `rel` (relative to the value, or to 1 near zero) of frep's.
    fn check_model(name: &str, src: &str, rel: f64) -> bool {
        let model = Model::compile(src).unwrap_or_else(|d| panic!("{name}: {}", d.message));
        let tape = model.tape();
        let tree = match tape_to_tree(&tape) {
            Ok(t) => t,
            Err(e) => {
                println!("{name}: not translated: {e}");
                return false;
            }
        };
        let [xs, ys, zs] = points(2000, -1.3, 1.3);
        let to64 = |v: &[f32]| v.iter().map(|&x| f64::from(x)).collect::<Vec<_>>();
        let mut frep = vec![0.0; xs.len()];
        BatchEval::new(&tape).eval(
            &to64(&xs),
            &to64(&ys),
            &to64(&zs),
            &Inputs::default(),
            &mut frep,
        );
        let shape = VmShape::from(tree);
        let slice_tape = shape.ez_float_slice_tape();
        let mut eval = VmShape::new_float_slice_eval();
        let fidget = eval
            .eval(&slice_tape, &xs, &ys, &zs)
            .expect("fidget evaluation");
        let point_tape = shape.ez_point_tape();
        let mut point_eval = VmShape::new_point_eval();
        let mut worst = 0.0f64;
        for i in 0..xs.len() {
            let want = -frep[i];
            let got = f64::from(fidget[i]);
            let (pv, _) = point_eval
                .eval(&point_tape, xs[i], ys[i], zs[i])
                .expect("fidget point evaluation");
            assert_eq!(
                pv.to_bits(),
                fidget[i].to_bits(),
                "{name}: point vs slice at {i}"
            );
            if want.is_nan() {
                assert!(got.is_nan(), "{name}: {got} where frep gives NaN");
                continue;
            }
            let err = (got - want).abs() / want.abs().max(1.0);
            worst = worst.max(err);
            assert!(
                err <= rel,
                "{name} at ({}, {}, {}): fidget {got}, -frep {want}",
                xs[i],
                ys[i],
                zs[i]
            );
        }
        println!("{name}: largest relative difference {worst:.1e}");
        true
    }

    #[test]
    fn translations_match_frep() {
        let mut translated = Vec::new();
        for (name, src) in examples() {
            // fidget evaluates in f32: 1e-5 on M1-M4; the Table I models
            // chain up to 42 R-functions, whose f32 rounding errors add up
            // (complex_hemisphere: about 1e-4).
            let rel = if name.starts_with('m') { 1e-5 } else { 1e-3 };
            if check_model(&name, &src, rel) {
                translated.push(name);
            }
        }
        for m in ["m1_sphere", "m2_spheres100", "m3_gyroid", "m4_rblend10"] {
            assert!(translated.iter().any(|t| t == m), "{m} translates");
        }
    }

    #[test]
    fn operators_match_frep() {
        // Every operation the translation handles, on a field of the point.
        let exprs = [
            "sin(x[1]) + cos(x[2]) * tan(x[3] * 0.5) + atan(x[1])",
            "exp(x[1]) + log(x[2] + 2) + logd(x[3] + 2) + sqrt(x[1] + 2)",
            "asin(x[1] * 0.7) - acos(x[2] * 0.7) + atan2(x[1], x[2] + 0.1)",
            "sinh(x[1]) + cosh(x[2]) + tanh(x[3] * 3)",
            "ceil(x[1] * 3) + floor(x[2] * 3) + int(x[3] * 3) + frac(x[1] * 3)",
            "abs(x[1]) - x[2] ^ 3 + x[3] ^ 2 + 1 / (x[1] ^ 2 + 1)",
            "min(x[1], x[2]) - max(x[2], x[3])",
            "(x[1] | x[2]) + (x[2] & x[3]) + (x[1] \\ x[3])",
            "mod(x[1] * 7, 3) + mod(x[2] * 7 + 9, 2)",
            "-(x[1] * x[2] - x[3]) * 2",
        ];
        for (i, e) in exprs.iter().enumerate() {
            let src = format!("my_model(x[3], a[1]) {{ my_model = {e}; }}");
            assert!(check_model(&format!("expr {i}: {e}"), &src, 1e-5));
        }
        let select = "my_model(x[3], a[1]) { f = 0; \
                      if x[1] < x[2] then f = f + 1; endif; \
                      if x[1] > x[3] then f = f + 2; endif; \
                      if x[2] <= x[3] and x[1] >= 0 then f = f + 4; endif; \
                      if x[1] = x[1] or x[2] /= x[3] then f = f + 8; endif; \
                      if not(x[2] > 0.5) then f = f - x[3]; else f = f + x[1] * 2; endif; \
                      my_model = f; }";
        assert!(check_model("select", select, 1e-5));
        let blend = "my_model(x[3], a[1]) { array c[3]; c = [0, 0, 0]; \
                     my_model = hfBlendUni(hfSphere(x, c, 0.5), x[3], 0.3, 0.2, 0.2) \
                     - hfBlendInt(x[1], -x[2], 0.1, 0.5, 0.4); }";
        assert!(check_model("blend", blend, 1e-5));
    }

    #[test]
    fn translated_anchors_have_the_hand_written_size() {
        use crate::anchors;
        let size = |t: Tree| VmShape::from(t).size();
        for (file, anchor) in [
            ("m1_sphere", anchors::m1_sphere()),
            ("m2_spheres100", anchors::m2_spheres100()),
            ("m3_gyroid", anchors::m3_gyroid()),
            ("m4_rblend10", anchors::m4_rblend10()),
        ] {
            let src = examples()
                .into_iter()
                .find(|(n, _)| n == file)
                .expect("example")
                .1;
            let tape = Model::compile(&src).expect("compiles").tape();
            let ours = size(tape_to_tree(&tape).expect("translates"));
            assert!(ours <= size(anchor) + 1, "{file}: {ours} vs anchor");
        }
    }
}
