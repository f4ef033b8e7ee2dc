// ---- ray traversal ---------------------------------------------------------
// Interval bisection along a ray over [t0, t1]: field_iv over the bounding
// box of a segment (strictly negative = outside, discarded; entirely >= 0 =
// inside, hit at its start; otherwise split, nearest half first, down to the
// pixel footprint fp0 + fp1 * t), then point samples and bisection on the
// sign of field() in the first undecided pixel-sized segment that has an
// inside sample. f >= 0 is inside. Reads u_max_steps.

// Deepest subdivision of the ray (segments of 2^-HF_LEVELS of its length)
// and bisection steps on the point sign.
const int HF_LEVELS = 22;
const int HF_BISECT = 12;

vec2 hf_segment_iv(vec3 o, vec3 d, vec2 seg) {
  vec3 pa = o + d * seg.x;
  vec3 pb = o + d * seg.y;
  vec3 lo = min(pa, pb);
  vec3 hi = max(pa, pb);
  return field_iv(vec2(lo.x, hi.x), vec2(lo.y, hi.y), vec2(lo.z, hi.z));
}

const int HF_MISS = 0;
const int HF_HIT = 1;
const int HF_CAPPED = 2;

// The first hit of o + t d in [t0, t1]: HF_HIT with `hit`, HF_MISS, or
// HF_CAPPED when u_max_steps interval tests did not decide. Call it from
// one place only: SwiftShader inlines every call site.
int hf_trace(vec3 o, vec3 d, float t0, float t1, float fp0, float fp1, out float hit) {
  // One loop, bounded by a uniform, with exactly one call site of field_iv
  // and one of field (SwiftShader inlines every call site and unrolls loops
  // of constant bounds; a stack array indexed dynamically is slow there).
  // The segments form an implicit binary tree over [t0, t1]: segment `idx`
  // of level `lvl` is [t0 + idx len, t0 + (idx + 1) len], len = (t1 - t0) /
  // 2^lvl; the next segment in ray order is idx + 1 with its trailing zero
  // bits dropped (back up the tree), so no stack is needed.
  // mode 0: interval test of the segment; mode 1: point samples at its
  // start, middle and end; mode 2: bisection between lo (outside) and hi.
  hit = 0.0;
  int lvl = 0;
  int idx = 0;
  int mode = 0;
  int j = 0;
  int steps = 0;
  float lo = t0;
  float hi = t1;
  vec2 seg = vec2(t0, t1);
  int iters = u_max_steps * (4 + HF_BISECT);
  for (int it = 0; it < iters; it++) {
    bool next = false;
    if (mode == 0) {
      if (steps >= u_max_steps) return HF_CAPPED;
      steps++;
      vec2 f = hf_segment_iv(o, d, seg);
      if (f.y < 0.0) {
        next = true;
      } else if (f.x >= 0.0) {
        hit = seg.x;
        return HF_HIT;
      } else if (seg.y - seg.x > fp0 + fp1 * seg.y && lvl < HF_LEVELS) {
        lvl++;
        idx *= 2;
      } else {
        // Pixel-sized and undecided: point samples.
        mode = 1;
        j = 0;
        lo = seg.x;
        hi = seg.y;
      }
    } else {
      float t = mode == 1 ? seg.x + float(j) * 0.5 * (seg.y - seg.x) : 0.5 * (lo + hi);
      bool inside = field(o + d * t) >= 0.0;
      if (mode == 1) {
        if (inside && j == 0) { hit = t; return HF_HIT; }
        if (inside) {
          hi = t;
          mode = 2;
          j = 0;
        } else {
          lo = t;
          j++;
          if (j == 3) { mode = 0; next = true; }
        }
      } else {
        if (inside) hi = t; else lo = t;
        j++;
        if (j == HF_BISECT) { hit = hi; return HF_HIT; }
      }
    }
    if (next) {
      idx++;
      // Drop the trailing zero bits of idx: back up to the parent level.
      int tz = int(round(log2(float(idx & -idx))));
      idx = idx >> tz;
      lvl -= tz;
      if (lvl <= 0) return HF_MISS;
    }
    float len = (t1 - t0) / float(1 << lvl);
    seg = vec2(t0 + float(idx) * len, t0 + float(idx + 1) * len);
  }
  return HF_MISS;
}
