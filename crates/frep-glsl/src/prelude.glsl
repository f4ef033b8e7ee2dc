// ---- frep-glsl helpers: HyperFun semantics in f32 ----------------------
// Point values follow frep_core::ops (errors become NaN). Intervals are vec2
// [lo, hi], never NaN (an unknown or possibly-NaN value is [-inf, +inf]).
// Duals are vec4 (value, d/dx, d/dy, d/dz).
const float HF_EPS = 1e-6;
const float HF_PI = 3.14159265358979;
const float HF_TAU = 6.28318530717959;
const float HF_HALF_PI = 1.57079632679490;
float hf_inf() { return uintBitsToFloat(0x7f800000u); }
float hf_nan() { return uintBitsToFloat(0x7fc00000u); }
// Every helper is branch-free and loop-free (one return, selects through
// mix() with a bool): SwiftShader (software WebGL) inlines them at every
// use, and branches or loops there made the first draw of models of a few
// hundred nodes take minutes.
float hf_sel(bool c, float a, float b) { return mix(b, a, c); }
vec2 iv_sel(bool c, vec2 a, vec2 b) { return mix(b, a, bvec2(c)); }
vec4 du_sel(bool c, vec4 a, vec4 b) { return mix(b, a, bvec4(c)); }
bool hf_both(bool a, bool b) { return all(bvec2(a, b)); }
bool hf_either(bool a, bool b) { return any(bvec2(a, b)); }
bool hf_truthy(float v) { return abs(v) >= HF_EPS; }
float hf_min(float a, float b) { return hf_sel(a < b, a, b); }
float hf_max(float a, float b) { return hf_sel(a > b, a, b); }
float hf_div(float a, float b) { return hf_sel(abs(b) < HF_EPS, hf_nan(), a / b); }
float hf_sqrt(float a) { return hf_sel(a < 0.0, hf_nan(), sqrt(a)); }
float hf_log(float a) { return hf_sel(a > 0.0, log(a), hf_nan()); }
float hf_logd(float a) { return hf_sel(a > 0.0, log(a) * 0.434294481903252, hf_nan()); }
float hf_tan(float a) { return hf_sel(abs(cos(a)) < HF_EPS, hf_nan(), tan(a)); }
float hf_asin(float a) { return hf_sel(abs(a) > 1.0, hf_nan(), asin(a)); }
float hf_acos(float a) { return hf_sel(abs(a) > 1.0, hf_nan(), acos(a)); }
// tanh saturates to +-1 in f32 beyond |a| = 10; clamping avoids inf/inf.
float hf_tanh(float a) { return tanh(clamp(a, -10.0, 10.0)); }
float hf_atan2(float y, float x) { return hf_sel(hf_both(x == 0.0, y == 0.0), 0.0, atan(y, x)); }
// HyperFun's rounding of indices and mod operands: half up.
float hf_round(float v) { float r = ceil(v); return hf_sel(r - v > 0.5, r - 1.0, r); }
float hf_frac(float a) { return a - trunc(a); }
float hf_not(float a) { return float(abs(a) < HF_EPS); }
float hf_and(float a, float b) { return float(hf_both(hf_truthy(a), hf_truthy(b))); }
float hf_or(float a, float b) { return float(hf_either(hf_truthy(a), hf_truthy(b))); }
float hf_eq(float a, float b) { return float(abs(a - b) < HF_EPS); }
float hf_ne(float a, float b) { return float(abs(a - b) >= HF_EPS); }
float hf_lt(float a, float b) { return float(a < b); }
float hf_gt(float a, float b) { return float(a > b); }
float hf_le(float a, float b) { return float(a <= b); }
float hf_ge(float a, float b) { return float(a >= b); }
// C fmod of the half-up rounded operands (GLSL mod() is floor-based; fmod
// truncates). The f32 quotient may be off by one: fix r into (-|y|, |y|) with
// the sign of x.
float hf_mod(float a, float b) {
  float x = hf_round(a);
  float y = hf_round(b);
  bool bad = any(bvec4(y == 0.0, isinf(x), isnan(x), isnan(y)));
  float ay = abs(y);
  float r = x - y * trunc(x / y);
  float rp = r + hf_sel(r < 0.0, ay, 0.0);
  rp -= hf_sel(rp >= ay, ay, 0.0);
  float rn = r - hf_sel(r > 0.0, ay, 0.0);
  rn += hf_sel(rn <= -ay, ay, 0.0);
  r = hf_sel(isinf(y), x, hf_sel(x >= 0.0, rp, rn));
  return hf_sel(bad, hf_nan(), r);
}
// HyperFun b^n for a constant integer n, given raw = b^|n| (computed by the
// generated loop-free hf_pwK): |b| < 1e-6 gives 0 (n >= 1) or an error;
// n < 0 inverts.
float hf_powi(float b, float raw, int n) {
  float v = hf_sel(n < 0, 1.0 / raw, raw);
  return hf_sel(abs(b) < HF_EPS, hf_sel(n <= 0, hf_nan(), 0.0), v);
}
float hf_sq(float b) { return hf_sel(abs(b) < HF_EPS, 0.0, b * b); }
// HyperFun b^e (checked).
float hf_pow(float b, float e) {
  float n = hf_round(abs(e));
  float r = pow(abs(b), n);
  r = hf_sel(hf_both(b < 0.0, mod(n, 2.0) == 1.0), -r, r);
  float vi = hf_sel(e < 0.0, 1.0 / r, r);
  float vf = hf_sel(b < 0.0, hf_nan(), exp(e * log(b)));
  float v = hf_sel(e - floor(e) < HF_EPS, vi, vf);
  return hf_sel(abs(b) < HF_EPS, hf_sel(e <= HF_EPS, hf_nan(), 0.0), v);
}
// C pow(b, e).
float hf_powf(float b, float e) {
  float r = pow(-b, e);
  float v = hf_sel(e == floor(e), hf_sel(mod(abs(e), 2.0) == 1.0, -r, r), hf_nan());
  v = hf_sel(b == 0.0, hf_sel(e > 0.0, 0.0, hf_inf()), v);
  v = hf_sel(b > 0.0, pow(b, e), v);
  return hf_sel(e == 0.0, 1.0, v);
}
// R-union a + b + sqrt(a^2 + b^2) in a form stable in f32: where a + b < 0
// it is 2ab / (a + b - sqrt(a^2 + b^2)) (no cancellation); operands beyond
// 1e18 are scaled (no overflow of a^2); at infinities the limits:
// u(+inf, b) = +inf, u(-inf, b) = b.
float hf_ru(float a, float b) {
  float m = max(abs(a), abs(b));
  float vinf = hf_sel(hf_both(a > 0.0, isinf(a)), a,
                      hf_sel(hf_both(b > 0.0, isinf(b)), b, hf_sel(isinf(a), b, a)));
  float k = hf_sel(m > 1e18, m, 1.0);
  float x = a / k;
  float y = b / k;
  float s = sqrt(x * x + y * y);
  float t = x + y;
  float r = hf_sel(t >= 0.0, t + s, (2.0 * x * y) / (t - s));
  return hf_sel(isinf(m), vinf, r * k);
}
// R-intersection a + b - sqrt(a^2 + b^2) = -u(-a, -b).
float hf_ri(float a, float b) { return -hf_ru(-a, -b); }
// R-difference a - b - sqrt(a^2 + b^2) = -u(-a, b).
float hf_rd(float a, float b) { return -hf_ru(-a, b); }
// hfBlendUni / hfBlendInt: r is the R-union / R-intersection of f1, f2.
float hf_blend(float r, float f1, float f2, float a0, float a1, float a2) {
  float t1 = f1 / a1;
  float t2 = f2 / a2;
  return r + a0 / (1.0 + t1 * t1 + t2 * t2);
}

// ---- intervals ----------------------------------------------------------
vec2 iv_all() { return vec2(-hf_inf(), hf_inf()); }
// NaN bounds (inf - inf, 0 * inf) widen to infinity.
vec2 iv_fix(vec2 a) { return mix(a, iv_all(), isnan(a)); }
vec2 iv_pt(float v) { return iv_sel(isnan(v), iv_all(), vec2(v)); }
vec2 iv_hull(vec2 a, vec2 b) { return vec2(min(a.x, b.x), max(a.y, b.y)); }
vec2 iv_neg(vec2 a) { return vec2(-a.y, -a.x); }
vec2 iv_add(vec2 a, vec2 b) { return iv_fix(a + b); }
vec2 iv_sub(vec2 a, vec2 b) { return iv_fix(vec2(a.x - b.y, a.y - b.x)); }
vec2 iv_mul(vec2 a, vec2 b) {
  vec4 p = vec4(a.x * b.x, a.x * b.y, a.y * b.x, a.y * b.y);
  p = mix(p, vec4(0.0), isnan(p));
  return vec2(min(min(p.x, p.y), min(p.z, p.w)), max(max(p.x, p.y), max(p.z, p.w)));
}
vec2 iv_abs(vec2 a) { return vec2(max(max(a.x, -a.y), 0.0), max(-a.x, a.y)); }
vec2 iv_sqr(vec2 a) { vec2 m = iv_abs(a); return m * m; }
// a / b, b not containing 0.
vec2 iv_divnz(vec2 a, vec2 b) { return iv_mul(a, vec2(1.0 / b.y, 1.0 / b.x)); }
// checked division: a divisor within 1e-6 of 0 is an error (NaN) somewhere.
vec2 iv_div(vec2 a, vec2 b) { return iv_sel(hf_both(b.x < HF_EPS, b.y > -HF_EPS), iv_all(), iv_divnz(a, b)); }
vec2 iv_divf(vec2 a, vec2 b) { return iv_sel(hf_both(b.x <= 0.0, b.y >= 0.0), iv_all(), iv_divnz(a, b)); }
vec2 iv_min(vec2 a, vec2 b) { return min(a, b); }
vec2 iv_max(vec2 a, vec2 b) { return max(a, b); }
vec2 iv_sqrt(vec2 a) { return iv_sel(a.x < 0.0, iv_all(), sqrt(a)); }
vec2 iv_exp(vec2 a) { return exp(a); }
vec2 iv_log(vec2 a) { return iv_sel(a.x > 0.0, log(a), iv_all()); }
vec2 iv_logd(vec2 a) { return iv_sel(a.x > 0.0, log(a) * 0.434294481903252, iv_all()); }
vec2 iv_sin(vec2 a) {
  float s0 = sin(a.x);
  float s1 = sin(a.y);
  float hi = hf_sel(HF_HALF_PI + HF_TAU * ceil((a.x - HF_HALF_PI) / HF_TAU) <= a.y, 1.0, max(s0, s1));
  float lo = hf_sel(-HF_HALF_PI + HF_TAU * ceil((a.x + HF_HALF_PI) / HF_TAU) <= a.y, -1.0, min(s0, s1));
  return iv_sel(a.y - a.x < HF_TAU, vec2(lo, hi), vec2(-1.0, 1.0));
}
vec2 iv_cos(vec2 a) {
  float c0 = cos(a.x);
  float c1 = cos(a.y);
  float hi = hf_sel(HF_TAU * ceil(a.x / HF_TAU) <= a.y, 1.0, max(c0, c1));
  float lo = hf_sel(HF_PI + HF_TAU * ceil((a.x - HF_PI) / HF_TAU) <= a.y, -1.0, min(c0, c1));
  return iv_sel(a.y - a.x < HF_TAU, vec2(lo, hi), vec2(-1.0, 1.0));
}
vec2 iv_tan(vec2 a) {
  float margin = 1e-5 + 1e-6 * max(abs(a.x), abs(a.y));
  bool pole = HF_HALF_PI + HF_PI * ceil((a.x - margin - HF_HALF_PI) / HF_PI) <= a.y + margin;
  return iv_sel(hf_both(a.y - a.x < HF_PI, !pole), vec2(tan(a.x), tan(a.y)), iv_all());
}
vec2 iv_asin(vec2 a) { return iv_sel(hf_either(a.x < -1.0, a.y > 1.0), iv_all(), asin(a)); }
vec2 iv_acos(vec2 a) { return iv_sel(hf_either(a.x < -1.0, a.y > 1.0), iv_all(), vec2(acos(a.y), acos(a.x))); }
vec2 iv_atan(vec2 a) { return atan(a); }
vec2 iv_sinh(vec2 a) { return iv_fix(sinh(a)); }
vec2 iv_cosh(vec2 a) { vec2 m = iv_abs(a); return iv_fix(cosh(m)); }
vec2 iv_tanh(vec2 a) { return tanh(clamp(a, -10.0, 10.0)); }
vec2 iv_ceil(vec2 a) { return ceil(a); }
vec2 iv_floor(vec2 a) { return floor(a); }
vec2 iv_trunc(vec2 a) { return trunc(a); }
vec2 iv_round(vec2 a) { return vec2(hf_round(a.x), hf_round(a.y)); }
vec2 iv_frac(vec2 a) {
  vec2 wide = vec2(hf_sel(a.x >= 0.0, 0.0, -1.0), hf_sel(a.y <= 0.0, 0.0, 1.0));
  bool same = hf_both(!any(isinf(a)), trunc(a.x) == trunc(a.y));
  return iv_sel(same, a - trunc(a.x), wide);
}
// Truth of a value as an interval: x = 1 when surely truthy, y = 0 when surely falsy.
vec2 iv_truth(vec2 a) {
  bool t = hf_either(a.x >= HF_EPS, a.y <= -HF_EPS);
  bool f = hf_both(a.x > -HF_EPS, a.y < HF_EPS);
  return vec2(float(t), float(!f));
}
vec2 iv_not(vec2 a) { vec2 t = iv_truth(a); return vec2(1.0 - t.y, 1.0 - t.x); }
vec2 iv_and(vec2 a, vec2 b) { return min(iv_truth(a), iv_truth(b)); }
vec2 iv_or(vec2 a, vec2 b) { return max(iv_truth(a), iv_truth(b)); }
vec2 iv_lt(vec2 a, vec2 b) { return vec2(float(a.y < b.x), float(a.x < b.y)); }
vec2 iv_gt(vec2 a, vec2 b) { return vec2(float(a.x > b.y), float(a.y > b.x)); }
vec2 iv_le(vec2 a, vec2 b) { return vec2(float(a.y <= b.x), float(a.x <= b.y)); }
vec2 iv_ge(vec2 a, vec2 b) { return vec2(float(a.x >= b.y), float(a.y >= b.x)); }
vec2 iv_eq(vec2 a, vec2 b) {
  vec2 d = iv_sub(a, b);
  return vec2(float(hf_both(d.x > -HF_EPS, d.y < HF_EPS)), float(hf_both(d.y > -HF_EPS, d.x < HF_EPS)));
}
vec2 iv_ne(vec2 a, vec2 b) { vec2 e = iv_eq(a, b); return vec2(1.0 - e.y, 1.0 - e.x); }
vec2 iv_select(vec2 c, vec2 t, vec2 e) {
  vec2 k = iv_truth(c);
  return iv_sel(k.x == 1.0, t, iv_sel(k.y == 0.0, e, iv_hull(t, e)));
}
// atan2(y, x): over a box clear of the branch cut (x <= 0, y = 0) the angle
// is extremal at the corners.
vec2 iv_atan2(vec2 y, vec2 x) {
  vec4 c = vec4(atan(y.x, x.x), atan(y.x, x.y), atan(y.y, x.x), atan(y.y, x.y));
  vec2 r = vec2(min(min(c.x, c.y), min(c.z, c.w)), max(max(c.x, c.y), max(c.z, c.w)));
  return iv_sel(all(bvec3(y.x <= 0.0, y.y >= 0.0, x.x <= 0.0)), vec2(-HF_PI, HF_PI), r);
}
// fmod of rounded integers: |r| <= |y| - 1, sign of x.
vec2 iv_mod(vec2 a, vec2 b) {
  vec2 x = iv_round(a);
  vec2 y = iv_round(b);
  float m = max(abs(y.x), abs(y.y)) - 1.0;
  vec2 r = vec2(hf_sel(x.x >= 0.0, 0.0, max(x.x, -m)), hf_sel(x.y <= 0.0, 0.0, min(x.y, m)));
  return iv_sel(hf_both(y.x <= 0.0, y.y >= 0.0), iv_all(), r);
}
// The base whose end points, raised to |n|, bound a^|n|: a for odd |n|,
// |a| for even.
vec2 iv_powi_base(vec2 a, int k) { return iv_sel((k & 1) == 1, a, iv_abs(a)); }
// HyperFun b^n (constant integer n), raw = the end points of
// iv_powi_base(a, |n|) raised to |n|: where a meets |b| < 1e-6 the value is
// 0 (n >= 1) or an error (n <= 0).
vec2 iv_powi(vec2 a, vec2 raw, int n) {
  bool band = hf_both(a.x < HF_EPS, a.y > -HF_EPS);
  vec2 r = iv_sel(n < 0, vec2(1.0 / raw.y, 1.0 / raw.x), raw);
  r = iv_sel(band, vec2(min(r.x, 0.0), max(r.y, 0.0)), r);
  r = iv_sel(n == 0, vec2(1.0), r);
  return iv_sel(hf_both(n <= 0, band), iv_all(), r);
}
vec2 iv_sq(vec2 a) {
  vec2 r = iv_sqr(a);
  return iv_sel(hf_both(a.x < HF_EPS, a.y > -HF_EPS), vec2(0.0, r.y), r);
}
// b^e = exp(e log b) for b > 0 (integer exponents too); otherwise unknown.
vec2 iv_pow(vec2 b, vec2 e) { return iv_sel(b.x >= HF_EPS, iv_fix(exp(iv_mul(e, log(b)))), iv_all()); }
vec2 iv_powf(vec2 b, vec2 e) { return iv_sel(b.x > 0.0, iv_fix(exp(iv_mul(e, log(b)))), iv_all()); }
// R-functions are non-decreasing in both arguments (R-difference:
// non-increasing in the second): exact bounds from the end points.
vec2 iv_ru(vec2 a, vec2 b) { return iv_fix(vec2(hf_ru(a.x, b.x), hf_ru(a.y, b.y))); }
vec2 iv_ri(vec2 a, vec2 b) { return iv_fix(vec2(hf_ri(a.x, b.x), hf_ri(a.y, b.y))); }
vec2 iv_rd(vec2 a, vec2 b) { return iv_fix(vec2(hf_rd(a.x, b.y), hf_rd(a.y, b.x))); }
// Blend: r (the R-function's interval) + a0 / q, q = 1 + (f1/a1)^2 + (f2/a2)^2 in [1, inf].
vec2 iv_blend(vec2 r, vec2 f1, vec2 f2, vec2 a0, vec2 a1, vec2 a2) {
  vec2 q = vec2(1.0) + iv_sqr(iv_divf(f1, a1)) + iv_sqr(iv_divf(f2, a2));
  vec2 w = vec2(1.0 / q.y, 1.0 / q.x);
  return iv_add(r, iv_mul(a0, w));
}

// ---- duals (value, gradient) ----------------------------------------------
vec4 du_c(float v) { return vec4(v, 0.0, 0.0, 0.0); }
vec4 du_nan() { return vec4(hf_nan()); }
vec4 du_chain(float v, float dv, vec4 a) { return vec4(v, dv * a.yzw); }
vec4 du_neg(vec4 a) { return -a; }
vec4 du_add(vec4 a, vec4 b) { return a + b; }
vec4 du_sub(vec4 a, vec4 b) { return a - b; }
vec4 du_mul(vec4 a, vec4 b) { return vec4(a.x * b.x, a.x * b.yzw + b.x * a.yzw); }
vec4 du_divf(vec4 a, vec4 b) { return vec4(a.x / b.x, (a.yzw * b.x - a.x * b.yzw) / (b.x * b.x)); }
vec4 du_div(vec4 a, vec4 b) { return du_sel(abs(b.x) < HF_EPS, du_nan(), du_divf(a, b)); }
vec4 du_abs(vec4 a) { return du_sel(a.x < 0.0, -a, a); }
vec4 du_sqrt(vec4 a) { float s = hf_sqrt(a.x); return du_chain(s, 0.5 / s, a); }
vec4 du_exp(vec4 a) { float e = exp(a.x); return du_chain(e, e, a); }
vec4 du_log(vec4 a) { return du_chain(hf_log(a.x), 1.0 / a.x, a); }
vec4 du_logd(vec4 a) { return du_chain(hf_logd(a.x), 0.434294481903252 / a.x, a); }
vec4 du_sin(vec4 a) { return du_chain(sin(a.x), cos(a.x), a); }
vec4 du_cos(vec4 a) { return du_chain(cos(a.x), -sin(a.x), a); }
vec4 du_tan(vec4 a) { float c = cos(a.x); return du_chain(hf_tan(a.x), 1.0 / (c * c), a); }
vec4 du_asin(vec4 a) { return du_chain(hf_asin(a.x), inversesqrt(1.0 - a.x * a.x), a); }
vec4 du_acos(vec4 a) { return du_chain(hf_acos(a.x), -inversesqrt(1.0 - a.x * a.x), a); }
vec4 du_atan(vec4 a) { return du_chain(atan(a.x), 1.0 / (1.0 + a.x * a.x), a); }
vec4 du_sinh(vec4 a) { return du_chain(sinh(a.x), cosh(a.x), a); }
vec4 du_cosh(vec4 a) { return du_chain(cosh(a.x), sinh(a.x), a); }
vec4 du_tanh(vec4 a) { float t = hf_tanh(a.x); return du_chain(t, 1.0 - t * t, a); }
vec4 du_ceil(vec4 a) { return du_c(ceil(a.x)); }
vec4 du_floor(vec4 a) { return du_c(floor(a.x)); }
vec4 du_trunc(vec4 a) { return du_c(trunc(a.x)); }
vec4 du_round(vec4 a) { return du_c(hf_round(a.x)); }
vec4 du_frac(vec4 a) { return vec4(hf_frac(a.x), a.yzw); }
vec4 du_not(vec4 a) { return du_c(hf_not(a.x)); }
vec4 du_min(vec4 a, vec4 b) { return du_sel(a.x < b.x, a, b); }
vec4 du_max(vec4 a, vec4 b) { return du_sel(a.x > b.x, a, b); }
vec4 du_atan2(vec4 a, vec4 b) {
  float r = a.x * a.x + b.x * b.x;
  return vec4(hf_atan2(a.x, b.x), mix(vec3(0.0), (b.x * a.yzw - a.x * b.yzw) / r, bvec3(r > 0.0)));
}
vec4 du_mod(vec4 a, vec4 b) { return du_c(hf_mod(a.x, b.x)); }
vec4 du_lt(vec4 a, vec4 b) { return du_c(hf_lt(a.x, b.x)); }
vec4 du_gt(vec4 a, vec4 b) { return du_c(hf_gt(a.x, b.x)); }
vec4 du_le(vec4 a, vec4 b) { return du_c(hf_le(a.x, b.x)); }
vec4 du_ge(vec4 a, vec4 b) { return du_c(hf_ge(a.x, b.x)); }
vec4 du_eq(vec4 a, vec4 b) { return du_c(hf_eq(a.x, b.x)); }
vec4 du_ne(vec4 a, vec4 b) { return du_c(hf_ne(a.x, b.x)); }
vec4 du_and(vec4 a, vec4 b) { return du_c(hf_and(a.x, b.x)); }
vec4 du_or(vec4 a, vec4 b) { return du_c(hf_or(a.x, b.x)); }
vec4 du_select(vec4 c, vec4 t, vec4 e) { return du_sel(hf_truthy(c.x), t, e); }
// raw = a.x^|n|, raw1 = a.x^|n - 1| (generated loop-free hf_pwK).
vec4 du_powi(vec4 a, float raw, float raw1, int n) {
  float v = hf_powi(a.x, raw, n);
  float p1 = hf_sel(n - 1 < 0, 1.0 / raw1, raw1);
  float dv = hf_sel(hf_either(n == 0, abs(a.x) < HF_EPS), 0.0, float(n) * p1);
  return du_chain(v, dv, a);
}
vec4 du_sq(vec4 a) { return du_chain(hf_sq(a.x), 2.0 * a.x, a); }
// d(b^e) = b^e (e db / b + de log|b|)
vec4 du_powv(float v, vec4 b, vec4 e) {
  vec3 g = v * (e.x * b.yzw / b.x);
  g += mix(vec3(0.0), v * log(abs(b.x)) * e.yzw, bvec3(any(notEqual(e.yzw, vec3(0.0)))));
  return du_sel(hf_either(abs(b.x) < HF_EPS, v == 0.0), vec4(v, 0.0, 0.0, 0.0), vec4(v, g));
}
vec4 du_pow(vec4 b, vec4 e) { return du_powv(hf_pow(b.x, e.x), b, e); }
vec4 du_powf(vec4 b, vec4 e) { return du_powv(hf_powf(b.x, e.x), b, e); }
// R-union gradient: (1 + a/s) da + (1 + b/s) db with s = sqrt(a^2 + b^2),
// computed on the scaled operands (a/m, b/m).
vec4 du_ru(vec4 a, vec4 b) {
  float v = hf_ru(a.x, b.x);
  float m = max(abs(a.x), abs(b.x));
  float x = a.x / m;
  float y = b.x / m;
  float s = sqrt(x * x + y * y);
  return du_sel(hf_either(!(m > 0.0), isinf(m)), vec4(v, a.yzw + b.yzw),
                vec4(v, (1.0 + x / s) * a.yzw + (1.0 + y / s) * b.yzw));
}
vec4 du_ri(vec4 a, vec4 b) { return -du_ru(-a, -b); }
vec4 du_rd(vec4 a, vec4 b) { return -du_ru(-a, b); }
// r: dual of the R-function of f1, f2.
vec4 du_blend(vec4 r, vec4 f1, vec4 f2, vec4 a0, vec4 a1, vec4 a2) {
  vec4 t1 = du_divf(f1, a1);
  vec4 t2 = du_divf(f2, a2);
  vec4 q = du_c(1.0) + du_mul(t1, t1) + du_mul(t2, t2);
  return r + du_divf(a0, q);
}
