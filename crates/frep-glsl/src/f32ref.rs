//! Rust mirrors, in `f32`, of the generated shader's numerically delicate
//! helpers (`hf_ru`, `hf_ri`, `hf_rd`, `hf_mod`), line for line. Their
//! accuracy can then be unit-tested against the `f64` semantics of
//! [`frep_core::ops`].
//!
//! ## The stable R-function forms
//! - The reference R-union `u = a + b + √(a² + b²)` cancels catastrophically
//!   in f32 where `a + b < 0`. The result is then tiny next to `|a|`: the
//!   union of two strongly negative fields, or `|a| ≫ |b|` with `a < 0`.
//! - There `(a + b + s)(a + b − s) = 2ab` gives the cancellation-free
//!   `u = 2ab / (a + b − √(a² + b²))`. The denominator is `< 0`.
//! - Where `a + b ≥ 0` the direct sum has no cancellation.
//! - Both branches are symmetric in `a, b`.
//! - The intersection and difference reuse it:
//!   `a + b − √(a²+b²) = −u(−a, −b)` and `a − b − √(a²+b²) = −u(−a, b)`.
//! - Operands beyond `1e18` are scaled by `max(|a|, |b|)`, so `a²` cannot
//!   overflow.
//! - At infinities the limits are returned: `u(+∞, b) = +∞`,
//!   `u(−∞, b) = b`. The interval flavour relies on them for unbounded
//!   intervals.

/// The shader's `hf_ru`: stable R-union.
pub fn r_union(a: f32, b: f32) -> f32 {
    let m = a.abs().max(b.abs());
    if m.is_infinite() {
        if a > 0.0 && a.is_infinite() {
            return a;
        }
        if b > 0.0 && b.is_infinite() {
            return b;
        }
        return if a.is_infinite() { b } else { a };
    }
    let (mut a, mut b, mut k) = (a, b, 1.0f32);
    if m > 1e18 {
        k = m;
        a /= m;
        b /= m;
    }
    let s = (a * a + b * b).sqrt();
    let t = a + b;
    let r = if t >= 0.0 {
        t + s
    } else {
        (2.0 * a * b) / (t - s)
    };
    r * k
}

/// The shader's `hf_ri`: stable R-intersection `−u(−a, −b)`.
pub fn r_inter(a: f32, b: f32) -> f32 {
    -r_union(-a, -b)
}

/// The shader's `hf_rd`: stable R-difference `−u(−a, b)`.
pub fn r_diff(a: f32, b: f32) -> f32 {
    -r_union(-a, b)
}

/// The shader's `hf_round` (half up).
pub fn round_half_up(v: f32) -> f32 {
    let r = v.ceil();
    if r - v > 0.5 {
        r - 1.0
    } else {
        r
    }
}

/// The shader's `hf_mod`: C `fmod` of the half-up rounded operands, with the
/// f32 quotient's off-by-one corrected.
pub fn hf_mod(a: f32, b: f32) -> f32 {
    let x = round_half_up(a);
    let y = round_half_up(b);
    if y == 0.0 || x.is_infinite() || x.is_nan() || y.is_nan() {
        return f32::NAN;
    }
    if y.is_infinite() {
        return x;
    }
    let ay = y.abs();
    let mut r = x - y * (x / y).trunc();
    if x >= 0.0 {
        if r < 0.0 {
            r += ay;
        }
        if r >= ay {
            r -= ay;
        }
    } else {
        if r > 0.0 {
            r -= ay;
        }
        if r <= -ay {
            r += ay;
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use frep_core::ops;

    fn rel_err(got: f32, want: f64) -> f64 {
        let d = (f64::from(got) - want).abs();
        d / want.abs().max(1e-30)
    }

    /// Operand pairs covering cancellation, mixed signs, large ratios.
    fn pairs() -> Vec<(f64, f64)> {
        let mags = [1e-6, 1e-3, 0.1, 0.7, 1.0, 3.0, 1e3, 1e6, 1e12];
        let mut v = Vec::new();
        for &x in &mags {
            for &y in &mags {
                for (sx, sy) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                    v.push((sx * x, sy * y * 1.37));
                }
            }
        }
        v
    }

    #[test]
    fn stable_r_functions_match_f64() {
        let mut worst_naive: f64 = 0.0;
        for (a, b) in pairs() {
            let (af, bf) = (a as f32, b as f32);
            // Reference in f64 from the f32-rounded operands.
            let (a64, b64) = (f64::from(af), f64::from(bf));
            for (got, want) in [
                (r_union(af, bf), ops::r_union(a64, b64)),
                (r_inter(af, bf), ops::r_inter(a64, b64)),
                (r_diff(af, bf), ops::r_diff(a64, b64)),
            ] {
                // The f64 reference itself cancels: compare to the exact
                // value through the f64 stable form where it is tiny.
                let exact = if want.abs() < 1e-6 * a64.abs().max(b64.abs()) {
                    continue;
                } else {
                    want
                };
                assert!(rel_err(got, exact) < 1e-5, "{a} {b}: {got} vs {exact}");
            }
            let naive = af + bf + (af * af + bf * bf).sqrt();
            worst_naive = worst_naive.max(rel_err(naive, ops::r_union(a64, b64)));
        }
        // The naive f32 form is badly wrong somewhere in this set.
        assert!(worst_naive > 0.1, "{worst_naive}");
    }

    #[test]
    fn stable_union_where_f64_reference_cancels() {
        // u(-1e6, -0.01) = -0.01 (nearly): the naive f32 sum cancels to 0.
        let (a, b) = (-1e6f64, -0.01f64);
        let s = (a * a + b * b).sqrt();
        let exact = 2.0 * a * b / (a + b - s);
        let got = r_union(a as f32, b as f32);
        assert!(rel_err(got, exact) < 1e-6, "{got} {exact}");
        let naive = (a as f32) + (b as f32) + ((a * a + b * b) as f32).sqrt();
        assert!(rel_err(naive, exact) > 0.5, "naive {naive}");
    }

    #[test]
    fn r_functions_limits_and_symmetry() {
        let inf = f32::INFINITY;
        assert_eq!(r_union(inf, -3.0), inf);
        assert_eq!(r_union(-inf, -3.0), -3.0);
        assert_eq!(r_union(-inf, 2.0), 2.0);
        assert_eq!(r_union(-inf, -inf), -inf);
        assert_eq!(r_inter(inf, 2.0), 2.0);
        assert_eq!(r_inter(-inf, 2.0), -inf);
        assert_eq!(r_diff(1.0, -inf), 1.0);
        assert_eq!(r_diff(1.0, inf), -inf);
        assert!(r_union(f32::NAN, 1.0).is_nan());
        // Huge operands do not overflow.
        let g = r_union(-3e30, 1e30);
        let want = ops::r_union(-3e30, 1e30);
        assert!(rel_err(g, want) < 1e-5, "{g} {want}");
        for (a, b) in pairs() {
            let (a, b) = (a as f32, b as f32);
            assert_eq!(r_union(a, b), r_union(b, a));
            assert_eq!(r_inter(a, b), r_inter(b, a));
        }
    }

    #[test]
    fn r_functions_are_monotone() {
        // The interval rule [u(lo, lo), u(hi, hi)] needs the f32 formula
        // itself to be monotone, across the branch switch at a + b = 0 too.
        let xs: Vec<f32> = (-200..=200).map(|i| i as f32 * 0.05).collect();
        for &b in &[-3.0f32, -0.5, 0.0, 0.25, 2.0] {
            for w in xs.windows(2) {
                assert!(r_union(w[0], b) <= r_union(w[1], b), "{w:?} {b}");
                assert!(r_inter(w[0], b) <= r_inter(w[1], b), "{w:?} {b}");
                assert!(r_diff(b, w[0]) >= r_diff(b, w[1]), "{w:?} {b}");
            }
        }
    }

    #[test]
    fn mod_matches_fmod_of_rounded() {
        for a in -300..=300 {
            for b in [-7.0, -3.0, -2.0, -1.0, 1.0, 2.0, 3.0, 5.0, 16.0, 1000.0] {
                let a = a as f64 * 0.5;
                let want = ops::binary(ops::BinaryOp::Mod, a, b).unwrap();
                let got = hf_mod(a as f32, b as f32);
                assert_eq!(f64::from(got), want, "mod({a}, {b})");
            }
        }
        // Large integers where the f32 quotient rounds.
        for (x, y) in [
            (16_777_215.0f32, 3.0f32),
            (16_777_213.0, 7.0),
            (-16_777_215.0, 11.0),
            (9_999_999.0, 9_999_998.0),
        ] {
            let want = (f64::from(x)) % f64::from(y);
            assert_eq!(f64::from(hf_mod(x, y)), want, "{x} % {y}");
        }
        assert!(hf_mod(3.0, 0.2).is_nan());
    }
}
