//! The operations of the model graph and their exact scalar semantics.
//!
//! The scalar functions here are the single source of truth for what each
//! operation computes: constant folding and the point evaluator call them,
//! and every other evaluator is tested against them.
//!
//! Two families of operations exist side by side:
//! * **checked** operations are HyperFun's own operators and built-ins
//!   (`/`, `^`, `sqrt`, `log`, `logd`, `tan`, `asin`, `acos`); where the
//!   reference interpreter stops with a runtime error they return an
//!   [`EvalError`];
//! * **IEEE** operations (`DivF`, `PowF`, `SqrtF`) are what the C library
//!   functions (`hfEllipsoid`, `hfSuperell`, ...) compute: plain floating-point,
//!   giving infinities or NaN, never an error.
//!
//! The bulk evaluators (batch, interval, gradient) map every error to NaN.

/// HyperFun's tolerance: truth values, `=`, `/` and `^` use it.
pub const EPS: f64 = 1e-6;

pub use crate::error::EvalError;

/// Calls `$m!` with the name of every [`UnaryOp`] variant, in order.
///
/// This is the one list of unary operations. The evaluators stamp out one
/// loop per operation with it, so that each loop inlines its own lane
/// function; a new variant missing here fails to compile there.
macro_rules! unary_ops {
    ($m:ident) => {
        $m!(
            Neg,
            Abs,
            Sqrt,
            SqrtF,
            Exp,
            Log,
            Logd,
            Sin,
            Cos,
            Tan,
            Asin,
            Acos,
            Atan,
            Sinh,
            Cosh,
            Tanh,
            Ceil,
            Floor,
            Trunc,
            Frac,
            Not,
            RoundHalfUp
        )
    };
}
pub(crate) use unary_ops;

/// Calls `$m!` with the name of every [`BinaryOp`] variant, in order (the
/// one list of binary operations, as [`unary_ops`] is of unary ones).
macro_rules! binary_ops {
    ($m:ident) => {
        $m!(
            Add, Sub, Mul, Div, DivF, Pow, PowF, Min, Max, Atan2, Mod, RUnion, RInter, RDiff, Lt,
            Gt, Le, Ge, Eq, Ne, And, Or
        )
    };
}
pub(crate) use binary_ops;

macro_rules! unary_array {
    ($($v:ident),*) => { [$(UnaryOp::$v),*] };
}

macro_rules! binary_array {
    ($($v:ident),*) => { [$(BinaryOp::$v),*] };
}

/// One-argument operations.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum UnaryOp {
    /// `-a` (also `~a`)
    Neg,
    /// `abs`
    Abs,
    /// checked `sqrt` (error below 0)
    Sqrt,
    /// IEEE `sqrt` (NaN below 0), used inside library functions
    SqrtF,
    /// `exp`
    Exp,
    /// checked natural `log` (error at or below 0)
    Log,
    /// checked base-10 `logd`
    Logd,
    /// `sin`
    Sin,
    /// `cos`
    Cos,
    /// checked `tan` (error where `|cos| < 1e-6`)
    Tan,
    /// checked `asin` (error outside [-1, 1])
    Asin,
    /// checked `acos`
    Acos,
    /// `atan`
    Atan,
    /// `sinh`
    Sinh,
    /// `cosh`
    Cosh,
    /// `tanh`
    Tanh,
    /// `ceil`
    Ceil,
    /// `floor`
    Floor,
    /// `int`: truncation toward zero
    Trunc,
    /// `frac`: `a - trunc(a)`
    Frac,
    /// `not`: 1 if `|a| < 1e-6`, else 0
    Not,
    /// HyperFun's index rounding, half up (`ceil(v)`, minus 1 if that is more than 0.5 above)
    RoundHalfUp,
}

impl UnaryOp {
    /// Every unary operation (for exhaustive tests).
    pub const ALL: [UnaryOp; 22] = unary_ops!(unary_array);

    /// Whether some argument makes this operation a runtime error.
    pub fn fallible(self) -> bool {
        matches!(
            self,
            UnaryOp::Sqrt
                | UnaryOp::Log
                | UnaryOp::Logd
                | UnaryOp::Tan
                | UnaryOp::Asin
                | UnaryOp::Acos
        )
    }

    /// A short lower-case name (used in dumps and generated code comments).
    pub fn name(self) -> &'static str {
        match self {
            UnaryOp::Neg => "neg",
            UnaryOp::Abs => "abs",
            UnaryOp::Sqrt => "sqrt",
            UnaryOp::SqrtF => "sqrtf",
            UnaryOp::Exp => "exp",
            UnaryOp::Log => "log",
            UnaryOp::Logd => "logd",
            UnaryOp::Sin => "sin",
            UnaryOp::Cos => "cos",
            UnaryOp::Tan => "tan",
            UnaryOp::Asin => "asin",
            UnaryOp::Acos => "acos",
            UnaryOp::Atan => "atan",
            UnaryOp::Sinh => "sinh",
            UnaryOp::Cosh => "cosh",
            UnaryOp::Tanh => "tanh",
            UnaryOp::Ceil => "ceil",
            UnaryOp::Floor => "floor",
            UnaryOp::Trunc => "int",
            UnaryOp::Frac => "frac",
            UnaryOp::Not => "not",
            UnaryOp::RoundHalfUp => "round",
        }
    }
}

/// Two-argument operations. `a` is the left operand, `b` the right one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BinaryOp {
    /// `a + b`
    Add,
    /// `a - b`
    Sub,
    /// `a * b`
    Mul,
    /// checked `a / b` (error where `|b| < 1e-6`)
    Div,
    /// IEEE `a / b`, used inside library functions
    DivF,
    /// HyperFun's checked power `a ^ b` (integer exponents by repeated multiplication)
    Pow,
    /// C `pow(a, b)`, used inside library functions
    PowF,
    /// `min(a, b)` = `a < b ? a : b`
    Min,
    /// `max(a, b)` = `a > b ? a : b`
    Max,
    /// `atan2(a, b)` (a is y)
    Atan2,
    /// `mod(a, b)` = `fmod(round(a), round(b))`
    Mod,
    /// R-union `a | b` = `a + b + sqrt(a² + b²)`
    RUnion,
    /// R-intersection `a & b` (and `@`) = `a + b - sqrt(a² + b²)`
    RInter,
    /// R-difference `a \ b` = `a - b - sqrt(a² + b²)`
    RDiff,
    /// `a < b` as 1/0
    Lt,
    /// `a > b`
    Gt,
    /// `a <= b`
    Le,
    /// `a >= b`
    Ge,
    /// `|a - b| < 1e-6`
    Eq,
    /// `|a - b| >= 1e-6`
    Ne,
    /// both truthy (`|v| >= 1e-6`)
    And,
    /// either truthy
    Or,
}

impl BinaryOp {
    /// Every binary operation (for exhaustive tests).
    pub const ALL: [BinaryOp; 22] = binary_ops!(binary_array);

    /// Whether some arguments make this operation a runtime error.
    pub fn fallible(self) -> bool {
        matches!(self, BinaryOp::Div | BinaryOp::Pow)
    }

    /// Whether `op(a, b) == op(b, a)` bit for bit (used by hash-consing).
    pub fn commutative(self) -> bool {
        // Add/Mul are commutative in IEEE arithmetic; the R-functions compute
        // a + b + sqrt(a*a + b*b), also symmetric. Min/Max are not (NaN, ±0).
        matches!(
            self,
            BinaryOp::Add
                | BinaryOp::Mul
                | BinaryOp::RUnion
                | BinaryOp::RInter
                | BinaryOp::Eq
                | BinaryOp::Ne
                | BinaryOp::And
                | BinaryOp::Or
        )
    }

    /// A short lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            BinaryOp::Add => "add",
            BinaryOp::Sub => "sub",
            BinaryOp::Mul => "mul",
            BinaryOp::Div => "div",
            BinaryOp::DivF => "divf",
            BinaryOp::Pow => "pow",
            BinaryOp::PowF => "powf",
            BinaryOp::Min => "min",
            BinaryOp::Max => "max",
            BinaryOp::Atan2 => "atan2",
            BinaryOp::Mod => "mod",
            BinaryOp::RUnion => "runion",
            BinaryOp::RInter => "rinter",
            BinaryOp::RDiff => "rdiff",
            BinaryOp::Lt => "lt",
            BinaryOp::Gt => "gt",
            BinaryOp::Le => "le",
            BinaryOp::Ge => "ge",
            BinaryOp::Eq => "eq",
            BinaryOp::Ne => "ne",
            BinaryOp::And => "and",
            BinaryOp::Or => "or",
        }
    }
}

/// The two blends of the library, each with five arguments `(f1, f2, a0, a1, a2)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum BlendOp {
    /// `hfBlendUni`: `f1 + f2 + sqrt(f1²+f2²) + a0 / (1 + (f1/a1)² + (f2/a2)²)`
    Union,
    /// `hfBlendInt`: `f1 + f2 - sqrt(f1²+f2²) + a0 / (1 + (f1/a1)² + (f2/a2)²)`
    Inter,
}

/// Whether `v` counts as true in a HyperFun condition.
#[inline]
pub fn truthy(v: f64) -> bool {
    v.abs() >= EPS
}

#[inline]
fn bool_f(b: bool) -> f64 {
    if b {
        1.0
    } else {
        0.0
    }
}

/// HyperFun's rounding of indices and `mod` operands: half up.
#[inline]
pub fn round_half_up(v: f64) -> f64 {
    let r = v.ceil();
    if r - v > 0.5 {
        r - 1.0
    } else {
        r
    }
}

/// `a + b + sqrt(a² + b²)`, exactly as the reference computes it.
#[inline]
pub fn r_union(a: f64, b: f64) -> f64 {
    a + b + (a * a + b * b).sqrt()
}

/// `a + b - sqrt(a² + b²)`, exactly as the reference computes it.
#[inline]
pub fn r_inter(a: f64, b: f64) -> f64 {
    a + b - (a * a + b * b).sqrt()
}

/// `a - b - sqrt(a² + b²)` (the reference negates `b`, then intersects).
#[inline]
pub fn r_diff(a: f64, b: f64) -> f64 {
    let nb = -b;
    a + nb - (a * a + nb * nb).sqrt()
}

/// The blends, as `hfblenduni.c` / `hfblendint.c` compute them.
#[inline]
pub fn blend(op: BlendOp, f1: f64, f2: f64, a0: f64, a1: f64, a2: f64) -> f64 {
    let r = match op {
        BlendOp::Union => r_union(f1, f2),
        BlendOp::Inter => r_inter(f1, f2),
    };
    let t1 = f1 / a1;
    let t2 = f2 / a2;
    r + a0 / (1.0 + t1 * t1 + t2 * t2)
}

/// HyperFun's `b ^ e`.
#[inline]
pub fn hf_pow(b: f64, e: f64) -> Result<f64, EvalError> {
    if b.abs() < EPS {
        if e <= EPS {
            return Err(EvalError::ZeroPower);
        }
        return Ok(0.0);
    }
    if e - e.floor() < EPS {
        let n = round_half_up(e.abs());
        Ok(pow_repeated(b, n, e < 0.0))
    } else if b < 0.0 {
        Err(EvalError::NegativePower)
    } else {
        Ok((e * b.ln()).exp())
    }
}

/// `b` multiplied `n` times into 1.0, then inverted when `invert` (the
/// reference's integer power loop). Exponents above [`POW_LOOP_MAX`] use
/// `powf` instead of looping (a listed deviation: the last bits may differ).
#[inline]
pub fn pow_repeated(b: f64, n: f64, invert: bool) -> f64 {
    let v = if n <= POW_LOOP_MAX {
        let mut v = 1.0;
        let mut i = 0.0;
        while i < n {
            v *= b;
            i += 1.0;
        }
        v
    } else {
        b.powf(n)
    };
    if invert {
        1.0 / v
    } else {
        v
    }
}

/// The largest integer exponent computed by repeated multiplication.
pub const POW_LOOP_MAX: f64 = 4096.0;

/// Applies a unary operation at a point.
#[inline]
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub fn unary(op: UnaryOp, a: f64) -> Result<f64, EvalError> {
    Ok(match op {
        UnaryOp::Neg => -a,
        UnaryOp::Abs => a.abs(),
        UnaryOp::Sqrt => {
            if a < 0.0 {
                return Err(EvalError::NegativeSqrt);
            }
            a.sqrt()
        }
        UnaryOp::SqrtF => a.sqrt(),
        UnaryOp::Exp => a.exp(),
        UnaryOp::Log => {
            if !(a > 0.0) {
                return Err(EvalError::NegativeLog);
            }
            a.ln()
        }
        UnaryOp::Logd => {
            if !(a > 0.0) {
                return Err(EvalError::NegativeLog);
            }
            a.log10()
        }
        UnaryOp::Sin => a.sin(),
        UnaryOp::Cos => a.cos(),
        UnaryOp::Tan => {
            if a.cos().abs() < EPS {
                return Err(EvalError::Tan);
            }
            a.tan()
        }
        UnaryOp::Asin => {
            if a.abs() > 1.0 {
                return Err(EvalError::ArgumentRange);
            }
            a.asin()
        }
        UnaryOp::Acos => {
            if a.abs() > 1.0 {
                return Err(EvalError::ArgumentRange);
            }
            a.acos()
        }
        UnaryOp::Atan => a.atan(),
        UnaryOp::Sinh => a.sinh(),
        UnaryOp::Cosh => a.cosh(),
        UnaryOp::Tanh => a.tanh(),
        UnaryOp::Ceil => a.ceil(),
        UnaryOp::Floor => a.floor(),
        UnaryOp::Trunc => a.trunc(),
        UnaryOp::Frac => a - a.trunc(),
        UnaryOp::Not => bool_f(!truthy(a)),
        UnaryOp::RoundHalfUp => round_half_up(a),
    })
}

/// Applies a binary operation at a point.
#[inline]
pub fn binary(op: BinaryOp, a: f64, b: f64) -> Result<f64, EvalError> {
    Ok(match op {
        BinaryOp::Add => a + b,
        BinaryOp::Sub => a - b,
        BinaryOp::Mul => a * b,
        BinaryOp::Div => {
            if b.abs() < EPS {
                return Err(EvalError::DivisionByZero);
            }
            a / b
        }
        BinaryOp::DivF => a / b,
        BinaryOp::Pow => return hf_pow(a, b),
        BinaryOp::PowF => a.powf(b),
        BinaryOp::Min => {
            if a < b {
                a
            } else {
                b
            }
        }
        BinaryOp::Max => {
            if a > b {
                a
            } else {
                b
            }
        }
        BinaryOp::Atan2 => a.atan2(b),
        BinaryOp::Mod => round_half_up(a) % round_half_up(b),
        BinaryOp::RUnion => r_union(a, b),
        BinaryOp::RInter => r_inter(a, b),
        BinaryOp::RDiff => r_diff(a, b),
        BinaryOp::Lt => bool_f(a < b),
        BinaryOp::Gt => bool_f(a > b),
        BinaryOp::Le => bool_f(a <= b),
        BinaryOp::Ge => bool_f(a >= b),
        BinaryOp::Eq => bool_f((a - b).abs() < EPS),
        BinaryOp::Ne => bool_f((a - b).abs() >= EPS),
        BinaryOp::And => bool_f(truthy(a) && truthy(b)),
        BinaryOp::Or => bool_f(truthy(a) || truthy(b)),
    })
}

/// HyperFun's power with a constant integer exponent `n` (what `b ^ n`
/// compiles to when `n` is known): 0 where `|b| < 1e-6` and `n >= 1`, an error
/// there when `n <= 0`, otherwise repeated multiplication.
#[inline]
pub fn pow_int(b: f64, n: i32) -> Result<f64, EvalError> {
    if b.abs() < EPS {
        if n <= 0 {
            return Err(EvalError::ZeroPower);
        }
        return Ok(0.0);
    }
    Ok(pow_repeated(b, f64::from(n.unsigned_abs()), n < 0))
}

#[cfg(test)]
#[allow(clippy::excessive_precision)]
mod tests {
    use super::*;

    #[test]
    fn reference_examples() {
        assert_eq!(hf_pow(2.0, 9.0).unwrap(), 512.0);
        assert_eq!(hf_pow(-8.0, 3.0).unwrap(), -512.0);
        assert_eq!(hf_pow(-8.0, 1.0 / 3.0), Err(EvalError::NegativePower));
        assert_eq!(hf_pow(2.0, -1.0).unwrap(), 0.5);
        assert_eq!(hf_pow(0.0, 0.5).unwrap(), 0.0);
        assert_eq!(hf_pow(0.5, 0.0).unwrap(), 1.0);
        assert_eq!(hf_pow(0.0, 0.0), Err(EvalError::ZeroPower));
        assert_eq!(binary(BinaryOp::Mod, 7.5, 2.0).unwrap(), 0.0);
        assert_eq!(binary(BinaryOp::Mod, -7.0, 3.0).unwrap(), -1.0);
        assert_eq!(unary(UnaryOp::Trunc, -2.7).unwrap(), -2.0);
        assert_eq!(unary(UnaryOp::Frac, -2.7).unwrap(), -0.70000000000000018);
        assert_eq!(unary(UnaryOp::Logd, 100.0).unwrap(), 2.0);
        assert_eq!(
            binary(BinaryOp::Div, 1.0, 1e-7),
            Err(EvalError::DivisionByZero)
        );
        assert_eq!(unary(UnaryOp::Sqrt, -1e-10), Err(EvalError::NegativeSqrt));
        assert_eq!(binary(BinaryOp::Eq, 2.0000001, 2.0).unwrap(), 1.0);
        assert_eq!(round_half_up(2.5), 3.0);
        assert_eq!(round_half_up(2.4), 2.0);
        assert_eq!(round_half_up(-2.5), -2.0);
        assert_eq!(r_union(1.0 + 2.0, 12.0), 27.369316876852981);
        assert_eq!(r_inter(r_union(1.0, 2.0), 3.0), 2.2014670905314775);
        assert_eq!(r_diff(2.0, 3.0), -4.6055512754639896);
        assert_eq!(r_inter(2.0, 3.0), 1.3944487245360109);
    }

    #[test]
    fn repeated_power_matches_loop() {
        for &b in &[1.5, -1.5, 0.3, -0.7, 1.0, -1.0, 1e100, -1e100, 1e-100] {
            for n in 0..40 {
                let mut v = 1.0;
                for _ in 0..n {
                    v *= b;
                }
                assert_eq!(
                    pow_repeated(b, n as f64, false).to_bits(),
                    v.to_bits(),
                    "{b}^{n}"
                );
                assert_eq!(
                    pow_repeated(b, n as f64, true).to_bits(),
                    (1.0 / v).to_bits()
                );
            }
        }
        // Huge exponents finish quickly.
        assert_eq!(pow_repeated(1.0001, 1e15, false), f64::INFINITY);
    }
}
