//! Forward-mode automatic differentiation over the batch evaluator's
//! register program: [`BatchEval::eval_grad`].
//!
//! Each register holds a block of values and the three partial derivatives
//! of each, structure of arrays. Every instruction is one loop over the
//! lanes of a block, as in [`BatchEval::eval`].
//!
//! Values are what [`BatchEval::eval`] computes, bit for bit: the same lane
//! functions. Derivatives follow the conventions of
//! [`GradEval`](crate::eval::grad), with its products grouped as it groups
//! them:
//! - a NaN value of a unary, binary or power operation has NaN
//!   derivatives; a select's or blend's keeps what its terms give;
//! - piecewise-constant operations and uniform values have derivative 0;
//! - `min`, `max` and selects take the derivative of what they pick;
//! - R-functions and blends take 0 for the `√(a² + b²)` term where it
//!   vanishes;
//! - `b ^ e` drops `ln(b)·b^e·de` where `de = 0`.

use super::{
    binary_lane, pow_int_kernel, select_lane, sm, split, unary_lane, BatchEval, Instr, Src, Trig,
    LANES,
};
use crate::eval::grad::{pow_factors, r_signs, unary_factor, Grad};
use crate::eval::Inputs;
use crate::ops::{self, binary_ops, unary_ops, BinaryOp, BlendOp, UnaryOp, EPS};

/// The registers [`BatchEval::eval_grad`] works in, kept between calls by
/// the caller (one set serves every evaluator: a thread that differentiates
/// with many shortened tapes holds them once).
#[derive(Clone, Debug, Default)]
pub struct GradRegs {
    blocks: Vec<Box<GBlock>>,
}

/// A register of the gradient program: values and partial derivatives.
#[derive(Clone, Debug)]
struct GBlock {
    v: [f64; LANES],
    d: [[f64; LANES]; 3],
}

impl GBlock {
    fn zeroed() -> Box<GBlock> {
        Box::new(GBlock {
            v: [0.0; LANES],
            d: [[0.0; LANES]; 3],
        })
    }

    /// `m` lanes of the constant `c` (derivatives 0).
    fn fill(&mut self, c: f64, m: usize) {
        self.v[..m].fill(c);
        for d in &mut self.d {
            d[..m].fill(0.0);
        }
    }
}

impl BatchEval {
    /// The value and gradient `(∂/∂x, ∂/∂y, ∂/∂z)` of output 0 at the
    /// points `(xs[i], ys[i], zs[i])` into `out[i]`: one pass of the
    /// register program with the derivatives carried along (forward-mode
    /// automatic differentiation), instead of finite differences.
    ///
    /// Values are what [`BatchEval::eval`] gives, bit for bit; derivatives
    /// follow [`GradEval`](crate::eval::grad::GradEval)'s conventions, its
    /// products grouped as it groups them (uniform values have derivative
    /// 0).
    ///
    /// `regs` are working registers, grown as needed and kept for the next
    /// call.
    ///
    /// # Panics
    /// If the four slices differ in length.
    pub fn eval_grad(
        &mut self,
        xs: &[f64],
        ys: &[f64],
        zs: &[f64],
        inputs: &Inputs,
        regs: &mut GradRegs,
        out: &mut [Grad],
    ) {
        assert!(
            xs.len() == out.len() && ys.len() == out.len() && zs.len() == out.len(),
            "BatchEval::eval_grad: slices of different lengths"
        );
        self.update_uniforms(inputs);
        let uni = std::mem::take(&mut self.uni);
        let blocks = &mut regs.blocks;
        let prog = self.program(false);
        let n_regs = prog.regs.len();
        if blocks.len() < n_regs + 2 {
            blocks.resize_with(n_regs + 2, GBlock::zeroed);
        }
        // The last two blocks hold uniform operands of binary operations.
        let (g, tmp) = blocks.split_at_mut(n_regs);
        let n = xs.len();
        for &(r, u) in &prog.bcast {
            g[r as usize].fill(uni[u as usize], LANES);
        }
        let mut start = 0;
        while start < n {
            let m = LANES.min(n - start);
            for (k, input) in [xs, ys, zs].into_iter().enumerate() {
                if prog.xyz[k] {
                    let r = &mut g[k];
                    r.v[..m].copy_from_slice(&input[start..start + m]);
                    for (a, d) in r.d.iter_mut().enumerate() {
                        d[..m].fill(if a == k { 1.0 } else { 0.0 });
                    }
                }
            }
            for ins in &prog.instrs {
                gexec(ins, g, tmp, &uni, m, prog.trig);
            }
            let o = &mut out[start..start + m];
            match prog.outputs.first() {
                Some(&Src::Reg(r)) => {
                    let r = &g[r as usize];
                    for (j, o) in o.iter_mut().enumerate() {
                        *o = Grad {
                            v: r.v[j],
                            dx: r.d[0][j],
                            dy: r.d[1][j],
                            dz: r.d[2][j],
                        };
                    }
                }
                Some(&Src::Uni(u)) => {
                    let v = uni[u as usize];
                    let d = if v.is_nan() { f64::NAN } else { 0.0 };
                    o.fill(Grad {
                        v,
                        dx: d,
                        dy: d,
                        dz: d,
                    })
                }
                None => o.fill(Grad {
                    v: f64::NAN,
                    dx: f64::NAN,
                    dy: f64::NAN,
                    dz: f64::NAN,
                }),
            }
            start += m;
        }
        self.uni = uni;
    }
}

/// How a lane's result derives from its operands' derivatives.
#[derive(Clone, Copy)]
enum Rule {
    /// `ka·a'` (one operand).
    Chain1,
    /// `ka·a' + kb·b'`.
    Chain,
    /// An R-function `a + sb·b + sh·√(a² + b²)`: `(a' + sb·b') + sh·(ka·a'
    /// + kb·b')` with `ka = a/r`, `kb = b/r` (grouped as
    /// [`GradEval`](crate::eval::grad::GradEval) groups it: the same bits).
    R(f64, f64),
    /// `a'` as it is.
    PickA,
    /// `b'` as it is.
    PickB,
    /// 0 (piecewise constant).
    Zero,
}

/// Writes lane `j` of `d` from the rule (a NaN value gives NaN
/// derivatives).
#[inline(always)]
fn put(
    d: &mut GBlock,
    j: usize,
    v: f64,
    rule: Rule,
    (ka, a): (f64, &GBlock),
    (kb, b): (f64, &GBlock),
) {
    d.v[j] = v;
    for k in 0..3 {
        let (da, db) = (a.d[k][j], b.d[k][j]);
        let r = match rule {
            Rule::Chain1 => ka * da,
            Rule::Chain => ka * da + kb * db,
            Rule::R(sb, sh) => (da + sb * db) + sh * (ka * da + kb * db),
            Rule::PickA => da,
            Rule::PickB => db,
            Rule::Zero => 0.0,
        };
        d.d[k][j] = if v.is_nan() { f64::NAN } else { r };
    }
}

fn gexec(
    ins: &Instr,
    g: &mut [Box<GBlock>],
    tmp: &mut [Box<GBlock>],
    uni: &[f64],
    m: usize,
    mode: Trig,
) {
    match *ins {
        Instr::Unary(op, dst, a) => {
            let (d, [a]) = split(g, dst, [a]);
            gunary(op, d, a, m, mode);
        }
        Instr::SinCos(ds, dc, a) => {
            // The destinations are distinct from the operand and each other.
            let (sv, cv) = sincos(&g[a as usize], m, mode);
            let (s, [x]) = split(g, ds, [a]);
            trig(s, x, &sv, &cv, false, m);
            let (c, [x]) = split(g, dc, [a]);
            trig(c, x, &cv, &sv, true, m);
        }
        Instr::Binary(op, dst, a, b) => {
            let (t0, t1) = tmp.split_at_mut(1);
            let (t0, t1) = (&mut t0[0], &mut t1[0]);
            if let Src::Uni(u) = a {
                t0.fill(uni[u as usize], m);
            }
            if let Src::Uni(u) = b {
                t1.fill(uni[u as usize], m);
            }
            match (a, b) {
                (Src::Reg(a), Src::Reg(b)) => {
                    let (d, [a, b]) = split(g, dst, [a, b]);
                    gbinary(op, d, a, b, m);
                }
                (Src::Reg(a), Src::Uni(_)) => {
                    let (d, [a]) = split(g, dst, [a]);
                    gbinary(op, d, a, t1, m);
                }
                (Src::Uni(_), Src::Reg(b)) => {
                    let (d, [b]) = split(g, dst, [b]);
                    gbinary(op, d, t0, b, m);
                }
                (Src::Uni(_), Src::Uni(_)) => {
                    gbinary(op, &mut g[dst as usize], t0, t1, m);
                }
            }
        }
        Instr::PowI(dst, a, n) => {
            let (d, [a]) = split(g, dst, [a]);
            // The values as the point batch computes them; the derivative
            // `n·x^(n−1)`, in closed form (and so vectorised) for the small
            // exponents (`x.powi(1) == x`, `x.powi(2) == x·x` exactly).
            pow_int_kernel(&mut d.v[..m], &a.v[..m], n);
            let mut k = [0.0; LANES];
            let x = &a.v[..m];
            match n {
                0 => {}
                1 => k[..m].fill(1.0),
                2 => k[..m].iter_mut().zip(x).for_each(|(k, &x)| *k = 2.0 * x),
                3 => k[..m]
                    .iter_mut()
                    .zip(x)
                    .for_each(|(k, &x)| *k = 3.0 * (x * x)),
                _ => k[..m]
                    .iter_mut()
                    .zip(x)
                    .for_each(|(k, &x)| *k = f64::from(n) * x.powi(n - 1)),
            }
            for (dc, ac) in d.d.iter_mut().zip(&a.d) {
                for (((o, &k), &da), &v) in
                    dc[..m].iter_mut().zip(&k[..m]).zip(&ac[..m]).zip(&d.v[..m])
                {
                    *o = if v.is_nan() { f64::NAN } else { k * da };
                }
            }
        }
        Instr::Select(dst, [c, t, e]) => {
            let (d, [c, t, e]) = split(g, dst, [c, t, e]);
            for j in 0..m {
                // As GradEval: the picked branch as it is (no NaN check),
                // picked as `select_lane` picks.
                let src = if c.v[j].abs() >= EPS { t } else { e };
                d.v[j] = select_lane(c.v[j], t.v[j], e.v[j]);
                for k in 0..3 {
                    d.d[k][j] = src.d[k][j];
                }
            }
        }
        Instr::Blend(op, dst, s) => {
            let (d, [f1, f2, a0, a1, a2]) = split(g, dst, s);
            for j in 0..m {
                gblend(op, d, j, [f1, f2, a0, a1, a2]);
            }
        }
    }
}

/// `sin` and `cos` of the first `m` values of `a` (the batch kernels'
/// values, one argument reduction for both).
fn sincos(a: &GBlock, m: usize, mode: Trig) -> ([f64; LANES], [f64; LANES]) {
    let (mut s, mut c) = ([0.0; LANES], [0.0; LANES]);
    match mode {
        Trig::Exact => sm::sincos_slice(&a.v[..m], &mut s[..m], &mut c[..m]),
        Trig::Fast => sm::sincos_fast_slice(&a.v[..m], &mut s[..m], &mut c[..m]),
    }
    (s, c)
}

/// `sin` (value `v`, derivative factor `k`) or, with `neg`, `cos` (value
/// `v`, factor `−k`).
fn trig(d: &mut GBlock, a: &GBlock, v: &[f64; LANES], k: &[f64; LANES], neg: bool, m: usize) {
    let sign = if neg { -1.0 } else { 1.0 };
    for j in 0..m {
        put(d, j, v[j], Rule::Chain1, (sign * k[j], a), (0.0, a));
    }
}

fn gunary(op: UnaryOp, d: &mut GBlock, a: &GBlock, m: usize, mode: Trig) {
    // Vectorised with one reduction (a branch per lane to `std`'s
    // functions would be if-converted into calls for every lane).
    if let UnaryOp::Sin | UnaryOp::Cos = op {
        let (s, c) = sincos(a, m, mode);
        if op == UnaryOp::Sin {
            trig(d, a, &s, &c, false, m);
        } else {
            trig(d, a, &c, &s, true, m);
        }
        return;
    }
    macro_rules! each {
        ($($v:ident),*) => {
            match op {
                $(UnaryOp::$v => for j in 0..m {
                    let x = a.v[j];
                    let v = unary_lane(UnaryOp::$v, x);
                    let (rule, k) = unary_rule(UnaryOp::$v, x, v);
                    put(d, j, v, rule, (k, a), (0.0, a));
                },)*
            }
        };
    }
    unary_ops!(each);
}

/// [`unary_factor`] as a rule (`sin` and `cos` never come here: see
/// `gunary`).
#[inline(always)]
fn unary_rule(op: UnaryOp, x: f64, v: f64) -> (Rule, f64) {
    match unary_factor(op, x, v) {
        Some(k) => (Rule::Chain1, k),
        None => (Rule::Zero, 0.0),
    }
}

fn gbinary(op: BinaryOp, d: &mut GBlock, a: &GBlock, b: &GBlock, m: usize) {
    macro_rules! each {
        ($($v:ident),*) => {
            match op {
                $(BinaryOp::$v => for j in 0..m {
                    let (x, y) = (a.v[j], b.v[j]);
                    let v = binary_lane(BinaryOp::$v, x, y);
                    let db = b.d[0][j] != 0.0 || b.d[1][j] != 0.0 || b.d[2][j] != 0.0;
                    let (rule, ka, kb) = binary_rule(BinaryOp::$v, x, y, v, db);
                    put(d, j, v, rule, (ka, a), (kb, b));
                },)*
            }
        };
    }
    binary_ops!(each);
}

/// The derivative rule of a binary operation at `(a, b)` with value `v`;
/// `db`: whether `b` has a nonzero derivative.
#[inline(always)]
fn binary_rule(op: BinaryOp, a: f64, b: f64, v: f64, db: bool) -> (Rule, f64, f64) {
    use Rule::*;
    match op {
        BinaryOp::Add => (Chain, 1.0, 1.0),
        BinaryOp::Sub => (Chain, 1.0, -1.0),
        BinaryOp::Mul => (Chain, b, a),
        BinaryOp::Div | BinaryOp::DivF => (Chain, 1.0 / b, -v / b),
        BinaryOp::Pow | BinaryOp::PowF => {
            let (ka, kb) = pow_factors(op, a, b, v, db);
            (Chain, ka, kb)
        }
        BinaryOp::Min => (if a < b { PickA } else { PickB }, 0.0, 0.0),
        BinaryOp::Max => (if a > b { PickA } else { PickB }, 0.0, 0.0),
        BinaryOp::Atan2 => {
            let r2 = a * a + b * b;
            if r2 == 0.0 {
                (Zero, 0.0, 0.0)
            } else {
                (Chain, b / r2, -a / r2)
            }
        }
        BinaryOp::RUnion | BinaryOp::RInter | BinaryOp::RDiff => {
            let (sb, sh) = r_signs(op);
            let r = (a * a + b * b).sqrt();
            let (ha, hb) = if r == 0.0 { (0.0, 0.0) } else { (a / r, b / r) };
            (R(sb, sh), ha, hb)
        }
        BinaryOp::Mod
        | BinaryOp::Lt
        | BinaryOp::Gt
        | BinaryOp::Le
        | BinaryOp::Ge
        | BinaryOp::Eq
        | BinaryOp::Ne
        | BinaryOp::And
        | BinaryOp::Or => (Zero, 0.0, 0.0),
    }
}

/// A blend on lane `j`: `f1 + f2 ± √(f1² + f2²) + a0 / (1 + (f1/a1)² +
/// (f2/a2)²)` and its derivative (the same terms as
/// [`GradEval`](crate::eval::grad::GradEval)).
#[inline(always)]
fn gblend(op: BlendOp, d: &mut GBlock, j: usize, [f1, f2, a0, a1, a2]: [&GBlock; 5]) {
    let (x1, x2, y0, y1, y2) = (f1.v[j], f2.v[j], a0.v[j], a1.v[j], a2.v[j]);
    let v = ops::blend(op, x1, x2, y0, y1, y2);
    d.v[j] = v;
    let s = if op == BlendOp::Union { 1.0 } else { -1.0 };
    let r = (x1 * x1 + x2 * x2).sqrt();
    let (h1, h2) = if r == 0.0 {
        (0.0, 0.0)
    } else {
        (x1 / r, x2 / r)
    };
    let t1 = x1 / y1;
    let t2 = x2 / y2;
    let dd = 1.0 + t1 * t1 + t2 * t2;
    let q = y0 / dd;
    for k in 0..3 {
        let (df1, df2, da0, da1, da2) =
            (f1.d[k][j], f2.d[k][j], a0.d[k][j], a1.d[k][j], a2.d[k][j]);
        let base = (df1 + df2) + s * (h1 * df1 + h2 * df2);
        let dt1 = (1.0 / y1) * df1 + (-t1 / y1) * da1;
        let dt2 = (1.0 / y2) * df2 + (-t2 / y2) * da2;
        let d_dd = 2.0 * t1 * dt1 + 2.0 * t2 * dt2;
        // An infinite denominator (a1 or a2 = 0) makes the term 0 near here.
        let dq = if dd.is_infinite() {
            0.0
        } else {
            (1.0 / dd) * da0 + (-q / dd) * d_dd
        };
        // As GradEval: no NaN check (a NaN `a0` does not matter where the
        // denominator is infinite).
        d.d[k][j] = base + dq;
    }
}
