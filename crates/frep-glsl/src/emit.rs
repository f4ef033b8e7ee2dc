//! Straight-line code generation: one SSA statement per live tape node, in
//! three flavours (point, interval, dual) sharing one set of uniforms.

use std::fmt::Write as _;

use frep_core::ops::{BinaryOp, BlendOp, UnaryOp};
use frep_core::{Node, NodeId, Tape};

/// Which field function is being generated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Flavour {
    /// `float field(vec3 p)`
    Point,
    /// `vec2 field_iv(vec2 x, vec2 y, vec2 z)`
    Interval,
    /// `vec4 field_grad(vec3 p)`
    Dual,
}

impl Flavour {
    fn ty(self) -> &'static str {
        match self {
            Flavour::Point => "float",
            Flavour::Interval => "vec2",
            Flavour::Dual => "vec4",
        }
    }

    fn var(self) -> char {
        match self {
            Flavour::Point => 't',
            Flavour::Interval => 'i',
            Flavour::Dual => 'd',
        }
    }

    /// Wraps a scalar (uniform or literal) as a value of this flavour.
    fn scalar(self, s: &str) -> String {
        match self {
            Flavour::Point => s.to_string(),
            Flavour::Interval => format!("iv_pt({s})"),
            Flavour::Dual => format!("du_c({s})"),
        }
    }
}

/// How the uniform-backed leaves of the tape are referenced.
pub(crate) struct Leaves {
    /// For each tape node: its constant's GLSL expression (uniform slot or
    /// literal), for `Const` nodes that are live.
    pub consts: Vec<Option<String>>,
    /// Values of the constant uniforms in slot order.
    pub const_values: Vec<f32>,
    /// Whether constants are inlined as literals rather than uniforms.
    pub inlined: bool,
}

/// The nodes needed for `outputs` on the GPU: a `Check(g, v)` needs only `v`
/// (bulk evaluators ignore the guard).
pub(crate) fn live_nodes(tape: &Tape, outputs: &[NodeId]) -> Vec<bool> {
    let mut live = vec![false; tape.nodes.len()];
    for o in outputs {
        live[o.index()] = true;
    }
    for i in (0..tape.nodes.len()).rev() {
        if !live[i] {
            continue;
        }
        match tape.nodes[i] {
            Node::Check(_, v) => live[v.index()] = true,
            n => {
                for c in n.children() {
                    live[c.index()] = true;
                }
            }
        }
    }
    live
}

/// A GLSL float literal for `v` (NaN and infinities through helpers).
pub(crate) fn float_literal(v: f32) -> String {
    if v.is_nan() {
        "hf_nan()".to_string()
    } else if v.is_infinite() {
        if v > 0.0 {
            "hf_inf()".to_string()
        } else {
            "(-hf_inf())".to_string()
        }
    } else {
        // Debug always prints a '.' or an exponent: "1.0", "1e-7", "-2.5".
        format!("{v:?}")
    }
}

impl Leaves {
    /// Assigns constant slots to the live `Const` nodes, in tape order; when
    /// there are more than `max_uniform_consts`, every constant is a literal.
    pub fn new(tape: &Tape, live: &[bool], max_uniform_consts: usize) -> Leaves {
        let live_consts: Vec<(usize, f32)> = tape
            .nodes
            .iter()
            .enumerate()
            .filter(|(i, _)| live[*i])
            .filter_map(|(i, n)| n.const_value().map(|v| (i, v as f32)))
            .collect();
        let inlined = live_consts.len() > max_uniform_consts;
        let mut consts = vec![None; tape.nodes.len()];
        let mut const_values = Vec::new();
        for (slot, &(i, v)) in live_consts.iter().enumerate() {
            consts[i] = Some(if inlined {
                float_literal(v)
            } else {
                const_values.push(v);
                format!("u_consts[{}].{}", slot / 4, ["x", "y", "z", "w"][slot % 4])
            });
        }
        Leaves {
            consts,
            const_values,
            inlined,
        }
    }
}

fn unary_point(op: UnaryOp) -> &'static str {
    match op {
        UnaryOp::Neg => "-",
        UnaryOp::Abs => "abs",
        UnaryOp::Sqrt | UnaryOp::SqrtF => "hf_sqrt",
        UnaryOp::Exp => "exp",
        UnaryOp::Log => "hf_log",
        UnaryOp::Logd => "hf_logd",
        UnaryOp::Sin => "sin",
        UnaryOp::Cos => "cos",
        UnaryOp::Tan => "hf_tan",
        UnaryOp::Asin => "hf_asin",
        UnaryOp::Acos => "hf_acos",
        UnaryOp::Atan => "atan",
        UnaryOp::Sinh => "sinh",
        UnaryOp::Cosh => "cosh",
        UnaryOp::Tanh => "hf_tanh",
        UnaryOp::Ceil => "ceil",
        UnaryOp::Floor => "floor",
        UnaryOp::Trunc => "trunc",
        UnaryOp::Frac => "hf_frac",
        UnaryOp::Not => "hf_not",
        UnaryOp::RoundHalfUp => "hf_round",
    }
}

/// Suffix of the `iv_` / `du_` helper of a unary operation: frep-core's
/// name, except where one helper serves two operations or GLSL's name wins.
fn unary_suffix(op: UnaryOp) -> &'static str {
    match op {
        // Checked and IEEE sqrt share one helper: the bulk semantics map
        // errors to NaN anyway.
        UnaryOp::SqrtF => "sqrt",
        UnaryOp::Trunc => "trunc",
        _ => op.name(),
    }
}

/// Suffix of the `hf_` / `iv_` / `du_` helper of a binary operation:
/// frep-core's name, with the R-functions shortened.
fn binary_suffix(op: BinaryOp) -> &'static str {
    match op {
        BinaryOp::RUnion => "ru",
        BinaryOp::RInter => "ri",
        BinaryOp::RDiff => "rd",
        _ => op.name(),
    }
}

fn prefix(fl: Flavour) -> &'static str {
    match fl {
        Flavour::Point => "hf_",
        Flavour::Interval => "iv_",
        Flavour::Dual => "du_",
    }
}

/// The right-hand side of node `node`'s statement.
fn expr(fl: Flavour, node: &Node, i: usize, leaves: &Leaves) -> String {
    let v = |id: NodeId| format!("{}{}", fl.var(), id.index());
    let p = prefix(fl);
    match *node {
        Node::Const(_) => fl.scalar(
            leaves.consts[i]
                .as_deref()
                .expect("live constant has a slot"),
        ),
        Node::X(k) if k < 3 => {
            let axis = ["x", "y", "z"][k as usize];
            match fl {
                Flavour::Point => format!("p.{axis}"),
                Flavour::Interval => axis.to_string(),
                Flavour::Dual => {
                    let mut g = [" 0.0"; 3];
                    g[k as usize] = " 1.0";
                    format!("vec4(p.{axis},{},{},{})", g[0], g[1], g[2])
                }
            }
        }
        Node::X(k) => fl.scalar(&format!("u_xextra[{}]", k - 3)),
        Node::Param(k) => fl.scalar(&format!("u_params[{k}]")),
        Node::Error(_) => match fl {
            Flavour::Point => "hf_nan()".into(),
            Flavour::Interval => "iv_all()".into(),
            Flavour::Dual => "du_nan()".into(),
        },
        Node::Unary(op, a) => match fl {
            Flavour::Point if op == UnaryOp::Neg => format!("-{}", v(a)),
            Flavour::Point => format!("{}({})", unary_point(op), v(a)),
            _ => format!("{p}{}({})", unary_suffix(op), v(a)),
        },
        Node::Binary(op, a, b) => match (fl, op) {
            (Flavour::Point, BinaryOp::Add) => format!("{} + {}", v(a), v(b)),
            (Flavour::Point, BinaryOp::Sub) => format!("{} - {}", v(a), v(b)),
            (Flavour::Point, BinaryOp::Mul) => format!("{} * {}", v(a), v(b)),
            (Flavour::Point, BinaryOp::DivF) => format!("{} / {}", v(a), v(b)),
            (Flavour::Interval, BinaryOp::Mul) if a == b => format!("iv_sqr({})", v(a)),
            _ => format!("{p}{}({}, {})", binary_suffix(op), v(a), v(b)),
        },
        Node::PowI(a, 2) => format!("{p}sq({})", v(a)),
        Node::PowI(a, n) => {
            let k = n.unsigned_abs();
            match fl {
                Flavour::Point => format!("hf_powi({a}, hf_pw{k}({a}), {n})", a = v(a)),
                Flavour::Interval => format!(
                    "iv_powi({a}, hf_pw{k}(iv_powi_base({a}, {k})), {n})",
                    a = v(a)
                ),
                Flavour::Dual => format!(
                    "du_powi({a}, hf_pw{k}({a}.x), hf_pw{k1}({a}.x), {n})",
                    a = v(a),
                    k1 = (i64::from(n) - 1).unsigned_abs()
                ),
            }
        }
        Node::Select(c, t, e) => match fl {
            Flavour::Point => format!("hf_truthy({}) ? {} : {}", v(c), v(t), v(e)),
            _ => format!("{p}select({}, {}, {})", v(c), v(t), v(e)),
        },
        Node::Blend(op, [f1, f2, a0, a1, a2]) => {
            let r = match op {
                BlendOp::Union => "ru",
                BlendOp::Inter => "ri",
            };
            format!(
                "{p}blend({p}{r}({f1}, {f2}), {f1}, {f2}, {}, {}, {})",
                v(a0),
                v(a1),
                v(a2),
                f1 = v(f1),
                f2 = v(f2)
            )
        }
        Node::Check(_, val) => v(val),
    }
}

/// Appends the statements of the live nodes; returns how many.
pub(crate) fn statements(
    out: &mut String,
    fl: Flavour,
    tape: &Tape,
    live: &[bool],
    leaves: &Leaves,
) -> usize {
    let mut n = 0;
    for (i, node) in tape.nodes.iter().enumerate() {
        if !live[i] {
            continue;
        }
        let _ = writeln!(
            out,
            "  {} {}{i} = {};",
            fl.ty(),
            fl.var(),
            expr(fl, node, i, leaves)
        );
        n += 1;
    }
    n
}

/// Appends a complete function of one flavour returning `outputs[0]`.
pub(crate) fn field_function(
    out: &mut String,
    fl: Flavour,
    tape: &Tape,
    output: NodeId,
    leaves: &Leaves,
) -> usize {
    let live = live_nodes(tape, &[output]);
    let sig = match fl {
        Flavour::Point => "float field(vec3 p)",
        Flavour::Interval => "vec2 field_iv(vec2 x, vec2 y, vec2 z)",
        Flavour::Dual => "vec4 field_grad(vec3 p)",
    };
    let _ = writeln!(out, "{sig} {{");
    let n = statements(out, fl, tape, &live, leaves);
    let _ = writeln!(out, "  return {}{};\n}}", fl.var(), output.index());
    n
}

/// Appends `vec3 attrs(vec3 p)` returning the point values of three outputs.
pub(crate) fn attrs_function(
    out: &mut String,
    tape: &Tape,
    outs: [NodeId; 3],
    leaves: &Leaves,
) -> usize {
    let live = live_nodes(tape, &outs);
    let _ = writeln!(out, "vec3 attrs(vec3 p) {{");
    let n = statements(out, Flavour::Point, tape, &live, leaves);
    let _ = writeln!(
        out,
        "  return vec3(t{}, t{}, t{});\n}}",
        outs[0].index(),
        outs[1].index(),
        outs[2].index()
    );
    n
}

/// `hf_pwK(float)` and `hf_pwK(vec2)` for every exponent `K` the `PowI`
/// nodes of `live` need: `|n|`, and `|n - 1|` for the derivative. Each is
/// componentwise `b^K` by repeated squaring, written out with no loop.
pub(crate) fn power_functions(out: &mut String, tape: &Tape, live: &[bool]) {
    let mut ks = std::collections::BTreeSet::new();
    for (i, n) in tape.nodes.iter().enumerate() {
        if let Node::PowI(_, n) = *n {
            if live[i] && n != 2 {
                ks.insert(u64::from(n.unsigned_abs()));
                ks.insert((i64::from(n) - 1).unsigned_abs());
            }
        }
    }
    for k in ks {
        for ty in ["float", "vec2"] {
            let _ = write!(out, "{ty} hf_pw{k}({ty} b) {{ {ty} r = {ty}(1.0);");
            if k > 0 {
                let _ = write!(out, " {ty} x = b;");
            }
            let mut e = k;
            while e > 0 {
                if e & 1 == 1 {
                    out.push_str(" r *= x;");
                }
                e >>= 1;
                if e > 0 {
                    out.push_str(" x *= x;");
                }
            }
            out.push_str(" return r; }\n");
        }
    }
}
