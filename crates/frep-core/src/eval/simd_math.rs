//! Vectorisable `f64` elementary functions.
//!
//! Each function is written branch-free: selects instead of branches, bit
//! tricks instead of `f64 <-> i64` conversions. So a loop applying it to
//! every lane of an array compiles to SIMD code. A scalar libm call per lane
//! is what makes a JIT slow on trigonometry-heavy models (the gyroid).
//!
//! The algorithms are those of fdlibm / musl (Sun Microsystems' freely
//! distributable libm): the same argument reductions, polynomials and
//! coefficients, with their data-dependent branches replaced by selects.
//! Errors are below 1 ulp in the useful range (tests measure them against
//! `std` on millions of random arguments).
//!
//! `sin`, `cos` and `tan` reduce arguments with a Cody–Waite reduction by
//! π/2 in three 33-bit parts, exact up to |x| < 2^20·π/2. Beyond
//! [`TRIG_LIMIT`], and for infinities and NaN, the slice functions recompute
//! those lanes with `std`. That second pass runs only when such a lane
//! exists.
//!
//! The scalar functions (`sin`, `exp`, ...) give exactly the values the slice
//! functions (`sin_slice`, ...) give lane by lane.
//!
//! [`sin_cos_fast`] and its slices trade the last bits for speed: a
//! two-part reduction and shorter polynomials (fitted here, not fdlibm's),
//! within about `2e-14` of the value, for callers that only test signs.

/// Above this magnitude `sin`, `cos` and `tan` use `std` (the three-part
/// Cody–Waite reduction is exact for |x| < 2^20·π/2 ≈ 1.6e6).
pub const TRIG_LIMIT: f64 = 1.0e6;

const fn hex(hi: u32, lo: u32) -> f64 {
    f64::from_bits(((hi as u64) << 32) | lo as u64)
}

/// 1.5·2^52: adding it rounds a value of magnitude < 2^51 to an integer,
/// which then sits in the low mantissa bits.
const ROUND_MAGIC: f64 = 6755399441055744.0;

/// Rounds to the nearest integer (ties to even) for |x| < 2^51; returns the
/// rounded value and its integer in the low bits of a `u64` (two's complement).
#[inline(always)]
fn round_magic(x: f64) -> (f64, u64) {
    let t = x + ROUND_MAGIC;
    let k = t.to_bits().wrapping_sub(ROUND_MAGIC.to_bits());
    (t - ROUND_MAGIC, k)
}

#[inline(always)]
fn sel(c: bool, a: f64, b: f64) -> f64 {
    if c {
        a
    } else {
        b
    }
}

// ---------------------------------------------------------------- exp

const LN2_HI: f64 = hex(0x3fe62e42, 0xfee00000);
const LN2_LO: f64 = hex(0x3dea39ef, 0x35793c76);
const INV_LN2: f64 = hex(0x3ff71547, 0x652b82fe);
const EP1: f64 = hex(0x3FC55555, 0x5555553E);
const EP2: f64 = hex(0xBF66C16C, 0x16BEBD93);
const EP3: f64 = hex(0x3F11566A, 0xAF25DE2C);
const EP4: f64 = hex(0xBEBBBD41, 0xC5D26BF1);
const EP5: f64 = hex(0x3E663769, 0x72BEA4D0);

/// `e^x` (fdlibm's rational approximation; < 1 ulp).
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    // Clamp so that the scale exponent stays in range; written so that NaN
    // passes through (comparisons with NaN are false).
    let xc = sel(x > 710.0, 710.0, sel(x < -746.0, -746.0, x));
    let (kf, _) = round_magic(xc * INV_LN2);
    let hi = xc - kf * LN2_HI;
    let lo = kf * LN2_LO;
    let r = hi - lo;
    let rr = r * r;
    let c = r - rr * (EP1 + rr * (EP2 + rr * (EP3 + rr * (EP4 + rr * EP5))));
    let y = 1.0 + (r * c / (2.0 - c) - lo + hi);
    // y·2^k in two steps so that neither factor over- or underflows:
    // k in [-1077, 1025].
    let big = kf > 1000.0;
    let small = kf < -1000.0;
    let k2 = sel(big, kf - 100.0, sel(small, kf + 1000.0, kf));
    let (_, kb) = round_magic(k2);
    let scale = f64::from_bits(kb.wrapping_add(1023) << 52);
    let post = sel(big, hex(0x46300000, 0), sel(small, hex(0x01700000, 0), 1.0)); // 2^100, 2^-1000
    y * scale * post
}

// ---------------------------------------------------------------- ln, log10

const LG1: f64 = hex(0x3FE55555, 0x55555593);
const LG2: f64 = hex(0x3FD99999, 0x9997FA04);
const LG3: f64 = hex(0x3FD24924, 0x94229359);
const LG4: f64 = hex(0x3FCC71C5, 0x1D8E78AF);
const LG5: f64 = hex(0x3FC74664, 0x96CB03DE);
const LG6: f64 = hex(0x3FC39A09, 0xD078C69F);
const LG7: f64 = hex(0x3FC2F112, 0xDF3E5244);
const SQRT2: f64 = std::f64::consts::SQRT_2;
const TWO54: f64 = hex(0x43500000, 0);
const TWO52: f64 = hex(0x43300000, 0);

/// Splits a positive finite `x` into `k` (as f64) and `f` with
/// `x = 2^k·(1 + f)`, `1 + f` in `[√2/2, √2)`; then the fdlibm kernel parts
/// `(f, hfsq, s·(hfsq + R))`.
#[inline(always)]
fn log_parts(x: f64) -> (f64, f64, f64, f64) {
    let sub = x < f64::MIN_POSITIVE;
    let xs = sel(sub, x * TWO54, x);
    let bits = xs.to_bits();
    let e = (bits >> 52) & 0x7ff;
    let ef = f64::from_bits(TWO52.to_bits() | e) - TWO52;
    let m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    let hi_m = m > SQRT2;
    let m = sel(hi_m, m * 0.5, m);
    let k = ef - 1023.0 + sel(hi_m, 1.0, 0.0) - sel(sub, 54.0, 0.0);
    let f = m - 1.0;
    let hfsq = 0.5 * f * f;
    let s = f / (2.0 + f);
    let z = s * s;
    let w = z * z;
    let t1 = w * (LG2 + w * (LG4 + w * LG6));
    let t2 = z * (LG1 + w * (LG3 + w * (LG5 + w * LG7)));
    let r = t2 + t1;
    (k, f, hfsq, s * (hfsq + r))
}

/// The value for the special arguments of a logarithm (0, negative, +inf,
/// NaN), applied after the kernel.
#[inline(always)]
fn log_special(x: f64, v: f64) -> f64 {
    let v = sel(x == 0.0, f64::NEG_INFINITY, v);
    let v = sel(x == f64::INFINITY, f64::INFINITY, v);
    sel(x >= 0.0, v, f64::NAN)
}

/// Natural logarithm (fdlibm; < 1 ulp). `ln(0) = -inf`, negative → NaN.
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    let (k, f, hfsq, shr) = log_parts(x);
    let v = shr + k * LN2_LO - hfsq + f + k * LN2_HI;
    log_special(x, v)
}

const IVLN10_HI: f64 = hex(0x3fdbcb7b, 0x15200000);
const IVLN10_LO: f64 = hex(0x3dbb9438, 0xca9aadd5);
const LOG10_2_HI: f64 = hex(0x3FD34413, 0x509F6000);
const LOG10_2_LO: f64 = hex(0x3D59FEF3, 0x11F12B36);

/// Base-10 logarithm (musl's extra-precise splitting; exact on powers of ten
/// in practice).
#[inline(always)]
pub fn log10(x: f64) -> f64 {
    let (k, f, hfsq, shr) = log_parts(x);
    let hi = f - hfsq;
    let hi = f64::from_bits(hi.to_bits() & 0xffff_ffff_0000_0000);
    let lo = f - hi - hfsq + shr;
    let val_hi = hi * IVLN10_HI;
    let y = k * LOG10_2_HI;
    let val_lo = k * LOG10_2_LO + (lo + hi) * IVLN10_LO + lo * IVLN10_HI;
    let w = y + val_hi;
    let val_lo = val_lo + ((y - w) + val_hi);
    log_special(x, val_lo + w)
}

// ---------------------------------------------------------------- sin, cos, tan

const INV_PIO2: f64 = hex(0x3FE45F30, 0x6DC9C883);
const PIO2_1: f64 = hex(0x3FF921FB, 0x54400000);
const PIO2_2: f64 = hex(0x3DD0B461, 0x1A600000);
const PIO2_3: f64 = hex(0x3BA3198A, 0x2E000000);
const PIO2_3T: f64 = hex(0x397B839A, 0x252049C1);

const S1: f64 = hex(0xBFC55555, 0x55555549);
const S2: f64 = hex(0x3F811111, 0x1110F8A6);
const S3: f64 = hex(0xBF2A01A0, 0x19C161D5);
const S4: f64 = hex(0x3EC71DE3, 0x57B1FE7D);
const S5: f64 = hex(0xBE5AE5E6, 0x8A2B9CEB);
const S6: f64 = hex(0x3DE5D93A, 0x5ACFD57C);

const C1: f64 = hex(0x3FA55555, 0x5555554C);
const C2: f64 = hex(0xBF56C16C, 0x16C15177);
const C3: f64 = hex(0x3EFA01A0, 0x19CB1590);
const C4: f64 = hex(0xBE927E4F, 0x809C52AD);
const C5: f64 = hex(0x3E21EE9E, 0xBDB4B1C4);
const C6: f64 = hex(0xBDA8FAE9, 0xBE8838D4);

/// `x - k·π/2` as `y0 + y1` (|y0| ≲ π/4), `k` (a whole float) and the
/// quadrant `k mod 4`, for |x| < 2^20·π/2 (outside, the result is
/// meaningless but finite or NaN).
#[inline(always)]
fn rem_pio2(x: f64) -> (f64, f64, f64, u64) {
    // Outside the range, reduce 0 instead (the lane is recomputed later);
    // keeps the magic rounding valid.
    let xr = sel(x.abs() <= TRIG_LIMIT, x, 0.0);
    let (kf, kb) = round_magic(xr * INV_PIO2);
    // Step 1: exact, since k·PIO2_1 has at most 53 significant bits.
    let r = xr - kf * PIO2_1;
    // Steps 2 and 3 (fdlibm's __rem_pio2 medium case, done unconditionally),
    // carrying the rounding errors of both subtractions.
    let t = r;
    let w = kf * PIO2_2;
    let r = t - w;
    let e2 = (t - r) - w;
    let t = r;
    let w = kf * PIO2_3;
    let r = t - w;
    let e3 = (t - r) - w;
    let w = kf * PIO2_3T - e3 - e2;
    let y0 = r - w;
    let y1 = (r - y0) - w;
    (y0, y1, kf, kb & 3)
}

#[inline(always)]
fn k_sin(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = S2 + z * (S3 + z * S4) + z * w * (S5 + z * S6);
    let v = z * x;
    x - ((z * (0.5 * y - v * r) - y) - v * S1)
}

#[inline(always)]
fn k_cos(x: f64, y: f64) -> f64 {
    let z = x * x;
    let w = z * z;
    let r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    w + (((1.0 - w) - hz) + (z * r - x * y))
}

/// `(sin x, cos x)` for |x| <= [`TRIG_LIMIT`] (other lanes: garbage).
#[inline(always)]
fn sincos_core(x: f64) -> (f64, f64) {
    let (s, c, _, _) = sincos_quarter(x);
    (s, c)
}

/// [`sincos_core`], with where `x` lies among the multiples of π/2: `x ≈
/// k·π/2 + r` with `k` a whole number and `|r| ≲ π/4`, returned as
/// `(sin x, cos x, k, r)` (`r` the reduced argument's leading part, within
/// an ulp of `x`'s size of the true `x − k·π/2`).
#[inline(always)]
fn sincos_quarter(x: f64) -> (f64, f64, f64, f64) {
    let (y0, y1, kf, q) = rem_pio2(x);
    let s = k_sin(y0, y1);
    let c = k_cos(y0, y1);
    let swap = q & 1 != 0;
    let (s1, c1) = (sel(swap, c, s), sel(swap, s, c));
    let s_neg = q & 2 != 0;
    let c_neg = (q + 1) & 2 != 0;
    (sel(s_neg, -s1, s1), sel(c_neg, -c1, c1), kf, y0)
}

#[inline(always)]
fn trig_in_range(x: f64) -> bool {
    x.abs() <= TRIG_LIMIT
}

/// `sin x` (< 1 ulp; `std` beyond [`TRIG_LIMIT`]).
#[inline]
pub fn sin(x: f64) -> f64 {
    if trig_in_range(x) {
        sin_core(x)
    } else {
        x.sin()
    }
}

/// `cos x` (< 1 ulp; `std` beyond [`TRIG_LIMIT`]).
#[inline]
pub fn cos(x: f64) -> f64 {
    if trig_in_range(x) {
        cos_core(x)
    } else {
        x.cos()
    }
}

/// `(sin x, cos x)`: exactly `(sin(x), cos(x))`, from one argument
/// reduction.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if trig_in_range(x) {
        sincos_core(x)
    } else {
        (x.sin(), x.cos())
    }
}

/// `sin` and `cos` at the two ends of an interval, for the interval
/// evaluator: the values exactly as [`sin_cos`] gives them, and where each
/// end lies among the multiples of π/2 (the extremes of both functions).
/// `None` where an end is beyond [`TRIG_LIMIT`] or not finite.
#[inline]
pub fn sin_cos_ends(lo: f64, hi: f64) -> Option<TrigEnds> {
    if !(trig_in_range(lo) && trig_in_range(hi)) {
        return None;
    }
    let (s0, c0, k0, r0) = sincos_quarter(lo);
    let (s1, c1, k1, r1) = sincos_quarter(hi);
    Some(TrigEnds {
        sin: [s0, s1],
        cos: [c0, c1],
        k: [k0, k1],
        r: [r0, r1],
    })
}

/// See [`sin_cos_ends`]: per end, `sin` and `cos`, and `x ≈ k·π/2 + r`
/// with `k` a whole number (as a float) and `|r| ≲ π/4`, `r` within an ulp
/// of `x`'s size of the true remainder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrigEnds {
    /// `sin` of each end.
    pub sin: [f64; 2],
    /// `cos` of each end.
    pub cos: [f64; 2],
    /// Per end, the whole number `k` nearest `x / (π/2)`.
    pub k: [f64; 2],
    /// Per end, `x − k·π/2`.
    pub r: [f64; 2],
}

#[inline(always)]
fn sin_core(x: f64) -> f64 {
    sincos_core(x).0
}

#[inline(always)]
fn cos_core(x: f64) -> f64 {
    sincos_core(x).1
}

/// The tail of π/2 beyond [`PIO2_1`] (fdlibm's `pio2_1t`): `PIO2_1 +
/// PIO2_1T` is π/2 to about 86 bits.
const PIO2_1T: f64 = hex(0x3DD0B461, 0x1A626331);

/// `(sin r − r) / r³` as a polynomial of degree 4 in `z = r²` on
/// `|r| ≤ π/4` (Chebyshev fit; `r³` times its error is below `1.4e-14`).
const FS: [f64; 5] = [
    -0.166_666_666_666_638_85,
    0.008_333_333_331_078_323,
    -1.984_126_691_611_063_3e-4,
    2.755_599_066_472_897_2e-6,
    -2.480_561_171_212_247_5e-8,
];
/// `(cos r − 1 + r²/2) / r⁴` as a polynomial of degree 4 in `z = r²` on
/// `|r| ≤ π/4` (Chebyshev fit; `r⁴` times its error is below `1e-15`).
const FC: [f64; 5] = [
    0.041_666_666_666_664_68,
    -0.001_388_888_888_727_67,
    2.480_158_521_036_455e-5,
    -2.755_636_950_618_061e-7,
    2.070_058_294_127_130_3e-9,
];

/// [`sin_cos`] to about `2e-14` of the value instead of an ulp
/// (for |x| <= [`TRIG_LIMIT`]; other lanes: garbage): a two-part reduction
/// by π/2 (the third part and the reduced argument's tail dropped) and
/// polynomials two degrees shorter: about 30 % fewer instructions.
#[inline(always)]
fn sincos_fast_core(x: f64) -> (f64, f64) {
    let xr = sel(x.abs() <= TRIG_LIMIT, x, 0.0);
    let (kf, kb) = round_magic(xr * INV_PIO2);
    // `kf·PIO2_1` is exact (|k| < 2^20, PIO2_1 has 33 bits) and so is the
    // first subtraction; the second rounds once.
    let r = (xr - kf * PIO2_1) - kf * PIO2_1T;
    let z = r * r;
    let s = r + r * z * (FS[0] + z * (FS[1] + z * (FS[2] + z * (FS[3] + z * FS[4]))));
    let c4 = z * z * (FC[0] + z * (FC[1] + z * (FC[2] + z * (FC[3] + z * FC[4]))));
    // `1 − z/2` with its rounding error carried, as fdlibm's `k_cos`.
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let c = w + (((1.0 - w) - hz) + c4);
    let q = kb & 3;
    let swap = q & 1 != 0;
    let (s1, c1) = (sel(swap, c, s), sel(swap, s, c));
    let s_neg = q & 2 != 0;
    let c_neg = (q + 1) & 2 != 0;
    (sel(s_neg, -s1, s1), sel(c_neg, -c1, c1))
}

/// `(sin x, cos x)` to about `2e-14` of the value, not an ulp (tests bound
/// the error by `5e-14·|value| + 2e-26·|k|` for `x ≈ k·π/2`, the second
/// term the reduction's): for callers that only need the field's sign
/// and rough size, like a ray caster's samples. `std` beyond
/// [`TRIG_LIMIT`]. The values [`sincos_fast_slice`] gives.
#[inline]
pub fn sin_cos_fast(x: f64) -> (f64, f64) {
    if trig_in_range(x) {
        sincos_fast_core(x)
    } else {
        (x.sin(), x.cos())
    }
}

/// HyperFun's checked `tan` with errors as NaN: NaN where `|cos x| < 1e-6`,
/// otherwise `sin x / cos x` (≤ 2 ulp).
#[inline]
pub fn tan_checked(x: f64) -> f64 {
    if trig_in_range(x) {
        tan_checked_core(x)
    } else {
        crate::ops::unary(crate::ops::UnaryOp::Tan, x).unwrap_or(f64::NAN)
    }
}

#[inline(always)]
fn tan_checked_core(x: f64) -> f64 {
    let (s, c) = sincos_core(x);
    sel(c.abs() < crate::ops::EPS, f64::NAN, s / c)
}

// ---------------------------------------------------------------- atan

const ATANHI: [f64; 4] = [
    hex(0x3FDDAC67, 0x0561BB4F),
    hex(0x3FE921FB, 0x54442D18),
    hex(0x3FEF730B, 0xD281F69B),
    hex(0x3FF921FB, 0x54442D18),
];
const ATANLO: [f64; 4] = [
    hex(0x3C7A2B7F, 0x222F65E2),
    hex(0x3C81A626, 0x33145C07),
    hex(0x3C700788, 0x7AF0CBBD),
    hex(0x3C91A626, 0x33145C07),
];
const AT: [f64; 11] = [
    hex(0x3FD55555, 0x5555550D),
    hex(0xBFC99999, 0x9998EBC4),
    hex(0x3FC24924, 0x920083FF),
    hex(0xBFBC71C6, 0xFE231671),
    hex(0x3FB745CD, 0xC54C206E),
    hex(0xBFB3B0F2, 0xAF749A6D),
    hex(0x3FB10D66, 0xA0D03D51),
    hex(0xBFADDE2D, 0x52DEFD9A),
    hex(0x3FA97B4B, 0x24760DEB),
    hex(0xBFA2B444, 0x2C6A6C2F),
    hex(0x3F90AD3A, 0xE322DA11),
];

/// `atan x` (fdlibm's five-interval reduction as selects; < 1 ulp).
#[inline(always)]
pub fn atan(x: f64) -> f64 {
    let ax = x.abs();
    // Intervals: [0, 7/16) id -1, [7/16, 11/16) 0, [11/16, 19/16) 1,
    // [19/16, 39/16) 2, beyond (and NaN) 3.
    let i0 = ax < 0.4375;
    let i1 = ax < 0.6875;
    let i2 = ax < 1.1875;
    let i3 = ax < 2.4375;
    // Reduced argument num/den.
    let num = sel(
        i0,
        ax,
        sel(
            i1,
            2.0 * ax - 1.0,
            sel(i2, ax - 1.0, sel(i3, ax - 1.5, -1.0)),
        ),
    );
    let den = sel(
        i0,
        1.0,
        sel(i1, 2.0 + ax, sel(i2, ax + 1.0, sel(i3, 1.0 + 1.5 * ax, ax))),
    );
    let hi = sel(
        i0,
        0.0,
        sel(
            i1,
            ATANHI[0],
            sel(i2, ATANHI[1], sel(i3, ATANHI[2], ATANHI[3])),
        ),
    );
    let lo = sel(
        i0,
        0.0,
        sel(
            i1,
            ATANLO[0],
            sel(i2, ATANLO[1], sel(i3, ATANLO[2], ATANLO[3])),
        ),
    );
    let r = num / den;
    let z = r * r;
    let w = z * z;
    let s1 = z * (AT[0] + w * (AT[2] + w * (AT[4] + w * (AT[6] + w * (AT[8] + w * AT[10])))));
    let s2 = w * (AT[1] + w * (AT[3] + w * (AT[5] + w * (AT[7] + w * AT[9]))));
    let v = hi - ((r * (s1 + s2) - lo) - r);
    v.copysign(x)
}

// ---------------------------------------------------------------- rounding

/// `trunc x`, branch-free (exact; same signed zeros as `std`).
#[inline(always)]
pub fn trunc(x: f64) -> f64 {
    let ax = x.abs();
    let r = (ax + TWO52) - TWO52;
    let r = sel(r > ax, r - 1.0, r);
    sel(ax < TWO52, r.copysign(x), x)
}

/// `floor x`, branch-free (exact).
#[inline(always)]
pub fn floor(x: f64) -> f64 {
    let t = trunc(x);
    sel(t > x, t - 1.0, t)
}

/// `ceil x`, branch-free (exact).
#[inline(always)]
pub fn ceil(x: f64) -> f64 {
    let t = trunc(x);
    sel(t < x, t + 1.0, t)
}

// ---------------------------------------------------------------- slices

/// Applies `f` lane by lane (a loop LLVM vectorises when `f` is branch-free).
#[inline(always)]
pub fn map(input: &[f64], out: &mut [f64], f: impl Fn(f64) -> f64) {
    for (o, &x) in out.iter_mut().zip(input) {
        *o = f(x);
    }
}

/// Recomputes with `slow` the lanes where `in_range` fails (a vectorised
/// check first; the scalar pass runs only when some lane needs it).
#[inline(always)]
fn fix_up(
    input: &[f64],
    out: &mut [f64],
    in_range: impl Fn(f64) -> bool,
    slow: impl Fn(f64) -> f64,
) {
    let all = input.iter().fold(true, |acc, &x| acc & in_range(x));
    if !all {
        for (o, &x) in out.iter_mut().zip(input) {
            if !in_range(x) {
                *o = slow(x);
            }
        }
    }
}

/// `sin` of every lane.
pub fn sin_slice(input: &[f64], out: &mut [f64]) {
    map(input, out, sin_core);
    fix_up(input, out, trig_in_range, f64::sin);
}

/// `cos` of every lane.
pub fn cos_slice(input: &[f64], out: &mut [f64]) {
    map(input, out, cos_core);
    fix_up(input, out, trig_in_range, f64::cos);
}

/// `sin` and `cos` of every lane, from one argument reduction per lane (the
/// same values as [`sin_slice`] and [`cos_slice`]).
///
/// # Panics
/// If the three slices differ in length.
pub fn sincos_slice(input: &[f64], sin_out: &mut [f64], cos_out: &mut [f64]) {
    sincos_lanes("sincos_slice", input, sin_out, cos_out, sincos_core);
}

/// `core` of every lane into `sin_out` and `cos_out`, then `std` where an
/// argument is beyond [`TRIG_LIMIT`] (`name`: the caller, for the panic).
#[inline(always)]
fn sincos_lanes(
    name: &str,
    input: &[f64],
    sin_out: &mut [f64],
    cos_out: &mut [f64],
    core: impl Fn(f64) -> (f64, f64),
) {
    assert!(
        sin_out.len() == input.len() && cos_out.len() == input.len(),
        "{name}: slices of different lengths"
    );
    for ((s, c), &x) in sin_out.iter_mut().zip(cos_out.iter_mut()).zip(input) {
        (*s, *c) = core(x);
    }
    fix_up(input, sin_out, trig_in_range, f64::sin);
    fix_up(input, cos_out, trig_in_range, f64::cos);
}

/// [`sin_cos_fast`] of every lane (see there for its accuracy).
///
/// # Panics
/// If the three slices differ in length.
pub fn sincos_fast_slice(input: &[f64], sin_out: &mut [f64], cos_out: &mut [f64]) {
    sincos_lanes(
        "sincos_fast_slice",
        input,
        sin_out,
        cos_out,
        sincos_fast_core,
    );
}

/// `sin` of every lane as [`sin_cos_fast`] gives it.
pub fn sin_fast_slice(input: &[f64], out: &mut [f64]) {
    map(input, out, |x| sincos_fast_core(x).0);
    fix_up(input, out, trig_in_range, f64::sin);
}

/// `cos` of every lane as [`sin_cos_fast`] gives it.
pub fn cos_fast_slice(input: &[f64], out: &mut [f64]) {
    map(input, out, |x| sincos_fast_core(x).1);
    fix_up(input, out, trig_in_range, f64::cos);
}

/// [`tan_checked`] of every lane.
pub fn tan_checked_slice(input: &[f64], out: &mut [f64]) {
    map(input, out, tan_checked_core);
    fix_up(input, out, trig_in_range, tan_checked);
}

#[cfg(test)]
mod tests;
