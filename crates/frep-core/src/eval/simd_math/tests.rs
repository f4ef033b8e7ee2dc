//! Tests of the vectorised math: ulps against `std` over reduced ranges,
//! special values, and slices against the scalar functions.

use super::*;

use crate::eval::reference::ulps;

/// xorshift64*.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545F4914F6CDD1D)
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [-m, m].
    fn sym(&mut self, m: f64) -> f64 {
        (2.0 * self.unit() - 1.0) * m
    }
    /// Log-uniform magnitude in [2^lo, 2^hi], random sign.
    fn log(&mut self, lo: f64, hi: f64) -> f64 {
        let e = lo + (hi - lo) * self.unit();
        let v = e.exp2();
        if self.next() & 1 == 0 {
            v
        } else {
            -v
        }
    }
    /// Random bits (any double, including NaN, inf, subnormals).
    fn bits(&mut self) -> f64 {
        f64::from_bits(self.next())
    }
}

const SPECIALS: [f64; 16] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::NAN,
    f64::MIN_POSITIVE,
    -f64::MIN_POSITIVE,
    5e-324,
    -5e-324,
    f64::MAX,
    f64::MIN,
    1e-300,
    std::f64::consts::FRAC_PI_2,
    std::f64::consts::PI,
];

type SliceFn = fn(&[f64], &mut [f64]);

/// Checks `f` against `g` on `args`, through the slice form too; returns
/// the worst ulp distance.
fn check(
    name: &str,
    args: &[f64],
    f: impl Fn(f64) -> f64,
    slice: Option<SliceFn>,
    g: impl Fn(f64) -> f64,
    max_ulps: u64,
) -> u64 {
    let mut worst = 0;
    let mut out = vec![0.0; args.len()];
    if let Some(s) = slice {
        s(args, &mut out);
    } else {
        map(args, &mut out, &f);
    }
    for (&x, &o) in args.iter().zip(&out) {
        let v = f(x);
        assert!(
            v.to_bits() == o.to_bits() || (v.is_nan() && o.is_nan()),
            "{name}({x:e}): scalar {v:e} vs slice {o:e}"
        );
        let u = ulps(v, g(x));
        assert!(
            u <= max_ulps,
            "{name}({x:e}) = {v:e}, std {:e} ({u} ulp)",
            g(x)
        );
        worst = worst.max(u);
    }
    worst
}

fn args(rng: &mut Rng, n: usize, gen: impl Fn(&mut Rng) -> f64) -> Vec<f64> {
    let mut v: Vec<f64> = SPECIALS.to_vec();
    v.extend((0..n).map(|_| gen(rng)));
    v
}

const N: usize = 1_000_000;

#[test]
fn exp_accuracy() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let mut w = 0;
    for gen in [
        &(|r: &mut Rng| r.sym(745.5)) as &dyn Fn(&mut Rng) -> f64,
        &|r: &mut Rng| r.sym(2.0),
        &|r: &mut Rng| r.log(-60.0, 10.0),
        &|r: &mut Rng| -700.0 - 50.0 * r.unit(),
        &|r: &mut Rng| r.bits(),
    ] {
        let a = args(&mut rng, N / 4, gen);
        // Subnormal results may differ by 1 ulp of the subnormal.
        w = w.max(check("exp", &a, exp, None, f64::exp, 1));
    }
    eprintln!("exp: worst {w} ulp");
}

#[test]
fn ln_log10_accuracy() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let (mut w1, mut w2) = (0, 0);
    for gen in [
        &(|r: &mut Rng| r.log(-1074.0, 1024.0).abs()) as &dyn Fn(&mut Rng) -> f64,
        &|r: &mut Rng| 0.5 + r.unit(),
        &|r: &mut Rng| 1.0 + r.sym(1e-6),
        &|r: &mut Rng| r.bits(),
    ] {
        let a = args(&mut rng, N / 4, gen);
        w1 = w1.max(check("ln", &a, ln, None, f64::ln, 1));
        // glibc's log10 itself is off by up to ~2 ulp (e.g. at 1.324396686474031).
        w2 = w2.max(check("log10", &a, log10, None, f64::log10, 2));
    }
    for i in -300..=300 {
        let x = format!("1e{i}").parse::<f64>().unwrap();
        assert_eq!(log10(x), x.log10(), "log10(1e{i})");
    }
    eprintln!("ln: worst {w1} ulp, log10: worst {w2} ulp");
}

#[test]
fn sin_cos_tan_accuracy() {
    let mut rng = Rng(0xdead_beef_cafe_f00d);
    let (mut ws, mut wc, mut wt) = (0, 0, 0);
    for gen in [
        &(|r: &mut Rng| r.sym(10.0)) as &dyn Fn(&mut Rng) -> f64,
        &|r: &mut Rng| r.sym(2e6),
        &|r: &mut Rng| r.log(-1074.0, 30.0),
        &|r: &mut Rng| {
            // Near multiples of π/2.
            let k = (r.sym(600_000.0)).round();
            k * std::f64::consts::FRAC_PI_2 * (1.0 + r.sym(1e-15))
        },
        &|r: &mut Rng| r.bits(),
    ] {
        let a = args(&mut rng, N / 4, gen);
        ws = ws.max(check("sin", &a, sin, Some(sin_slice), f64::sin, 1));
        wc = wc.max(check("cos", &a, cos, Some(cos_slice), f64::cos, 1));
        let tan_ref = |x: f64| crate::ops::unary(crate::ops::UnaryOp::Tan, x).unwrap_or(f64::NAN);
        // Near the poles the check |cos| < 1e-6 may flip on the last bit of cos.
        let a: Vec<f64> = a
            .into_iter()
            .filter(|x| (x.cos().abs() - crate::ops::EPS).abs() > 1e-12)
            .collect();
        wt = wt.max(check(
            "tan",
            &a,
            tan_checked,
            Some(tan_checked_slice),
            tan_ref,
            4,
        ));
    }
    eprintln!("sin: worst {ws} ulp, cos: worst {wc} ulp, tan: worst {wt} ulp");
}

/// The fast `sin`/`cos` of `x ≈ k·π/2 + r` are within `5e-14` of `std`'s
/// value plus `2e-26·|k|` (the reduction's error). That holds over the
/// whole reduced range, near multiples of π/2 and far out. The slices
/// give the scalar's bits. Beyond the range, and at infinities and NaN,
/// they are `std`'s.
#[test]
fn fast_sin_cos_accuracy() {
    let mut rng = Rng(0x0ddb_a11c_0ffe_e123);
    let mut worst = 0.0f64;
    for gen in [
        &(|r: &mut Rng| r.sym(10.0)) as &dyn Fn(&mut Rng) -> f64,
        &|r: &mut Rng| r.sym(1.0),
        &|r: &mut Rng| r.sym(2e6),
        &|r: &mut Rng| r.log(-1074.0, 30.0),
        &|r: &mut Rng| {
            let k = (r.sym(600_000.0)).round();
            k * std::f64::consts::FRAC_PI_2 * (1.0 + r.sym(1e-15))
        },
        &|r: &mut Rng| {
            // Where the reduced argument is near ±π/4 (the polynomials'
            // worst).
            let k = (r.sym(1000.0)).round();
            (k + 0.5) * std::f64::consts::FRAC_PI_2 + r.sym(1e-3)
        },
        &|r: &mut Rng| r.bits(),
    ] {
        let a = args(&mut rng, N / 4, gen);
        let (mut s, mut c) = (vec![0.0; a.len()], vec![0.0; a.len()]);
        sincos_fast_slice(&a, &mut s, &mut c);
        let (mut s1, mut c1) = (vec![0.0; a.len()], vec![0.0; a.len()]);
        sin_fast_slice(&a, &mut s1);
        cos_fast_slice(&a, &mut c1);
        for (i, &x) in a.iter().enumerate() {
            let (fs, fc) = sin_cos_fast(x);
            for (v, w) in [(fs, s[i]), (fs, s1[i]), (fc, c[i]), (fc, c1[i])] {
                assert!(
                    v.to_bits() == w.to_bits() || (v.is_nan() && w.is_nan()),
                    "fast sin/cos({x:e}): scalar {v:e} vs slice {w:e}"
                );
            }
            if !x.is_finite() || x.abs() > TRIG_LIMIT {
                assert_eq!(ulps(fs, x.sin()), 0, "sin({x:e}) beyond the range");
                assert_eq!(ulps(fc, x.cos()), 0, "cos({x:e}) beyond the range");
                continue;
            }
            // Within 5e-14 of the value, and the reduction's error.
            let k = (x * std::f64::consts::FRAC_2_PI).round().abs();
            for (v, want) in [(fs, x.sin()), (fc, x.cos())] {
                let e = (v - want).abs();
                assert!(
                    e <= 5e-14 * want.abs() + 2e-26 * k,
                    "fast sin/cos({x:e}): {v:e} vs {want:e}"
                );
                worst = worst.max(e / (want.abs() + 1e-300));
            }
        }
    }
    eprintln!("fast sin/cos: worst relative error {worst:e}");
}

#[test]
fn sin_cos_is_sin_and_cos() {
    let mut rng = Rng(0x5eed_0f5c_05aa_1234);
    for x in (0..20_000)
        .map(|k| match k % 4 {
            0 => rng.sym(10.0),
            1 => rng.sym(2e6),
            2 => rng.log(-1074.0, 30.0),
            _ => rng.bits(),
        })
        .chain([
            0.0,
            -0.0,
            TRIG_LIMIT,
            -TRIG_LIMIT,
            1e300,
            f64::INFINITY,
            f64::NAN,
        ])
    {
        let (s, c) = sin_cos(x);
        assert_eq!(s.to_bits(), sin(x).to_bits(), "sin {x:e}");
        assert_eq!(c.to_bits(), cos(x).to_bits(), "cos {x:e}");
    }
}

#[test]
fn atan_accuracy() {
    let mut rng = Rng(0x0123_4567_89ab_cdef);
    let mut w = 0;
    for gen in [
        &(|r: &mut Rng| r.sym(4.0)) as &dyn Fn(&mut Rng) -> f64,
        &|r: &mut Rng| r.log(-1074.0, 1024.0),
        &|r: &mut Rng| r.bits(),
    ] {
        let a = args(&mut rng, N / 3, gen);
        w = w.max(check("atan", &a, atan, None, f64::atan, 1));
    }
    eprintln!("atan: worst {w} ulp");
}

#[test]
fn rounding_exact() {
    let mut rng = Rng(0x5555_aaaa_1234_4321);
    let a = args(&mut rng, N / 4, |r| r.sym(10.0));
    let b = args(&mut rng, N / 4, |r| r.bits());
    let c = args(&mut rng, 1000, |r| {
        r.sym(8.0).round() + [0.0, 0.5, -0.5][r.next() as usize % 3]
    });
    for a in [a, b, c] {
        for &x in &a {
            for (f, g, n) in [
                (
                    trunc as fn(f64) -> f64,
                    f64::trunc as fn(f64) -> f64,
                    "trunc",
                ),
                (floor, f64::floor, "floor"),
                (ceil, f64::ceil, "ceil"),
            ] {
                let (v, w) = (f(x), g(x));
                assert!(
                    v.to_bits() == w.to_bits() || (v.is_nan() && w.is_nan()),
                    "{n}({x:e}): {v:e} vs {w:e}"
                );
            }
        }
    }
}
