/**
 * The GPU micro-benchmark: a tiny WebGL2 fragment shader ray marching a
 * reference field (a sphere blended with a torus, 64 sphere-tracing steps
 * and a gradient) over a 256² target. The first frame (where drivers such
 * as SwiftShader compile) is excluded; then frames are drawn one at a time,
 * each synchronised by a 1-pixel `readPixels`, until `budgetMs` in all has
 * passed (first frame included) or `maxFrames` are timed. The result is the
 * median ms per frame; null when WebGL2 is missing or the shader fails.
 */

/** Benchmark settings. */
export interface GpuBenchOptions {
  /** Target side in pixels (256). */
  size?: number;
  /** Total time allowed, first frame included (200 ms). */
  budgetMs?: number;
  /** Timed frames at most (8). */
  maxFrames?: number;
}

/** A benchmark result. */
export interface GpuBenchResult {
  /** Median ms per frame after the first. */
  frameMs: number;
  /** ms of the first frame (compile + draw). */
  firstMs: number;
  /** Frames timed. */
  frames: number;
}

const VERTEX = `#version 300 es
in vec2 p;
void main() { gl_Position = vec4(p, 0.0, 1.0); }`;

const FRAGMENT = `#version 300 es
precision highp float;
uniform vec2 res;
uniform float t;
out vec4 col;
float field(vec3 q) {
  float s = length(q) - 1.0;
  vec2 w = vec2(length(q.xy) - 1.1, q.z);
  float tor = length(w) - 0.35;
  float k = 0.3;
  float h = clamp(0.5 + 0.5 * (tor - s) / k, 0.0, 1.0);
  return mix(tor, s, h) - k * h * (1.0 - h) + 0.05 * sin(6.0 * q.x + t) * sin(6.0 * q.y);
}
void main() {
  vec2 uv = (2.0 * gl_FragCoord.xy - res) / res.y;
  vec3 ro = vec3(0.0, -4.0, 1.5);
  vec3 rd = normalize(vec3(uv.x, 1.6, uv.y - 0.35));
  float d = 0.0;
  float hit = 0.0;
  for (int i = 0; i < 64; i++) {
    float f = field(ro + rd * d);
    if (f < 1e-3) { hit = 1.0; break; }
    d += f * 0.8;
    if (d > 10.0) break;
  }
  vec3 p = ro + rd * d;
  vec2 e = vec2(1e-3, 0.0);
  vec3 n = normalize(vec3(field(p + e.xyy) - field(p - e.xyy), field(p + e.yxy) - field(p - e.yxy), field(p + e.yyx) - field(p - e.yyx)));
  col = vec4(mix(vec3(0.1), vec3(0.5 + 0.5 * n), hit), 1.0);
}`;

function compile(gl: WebGL2RenderingContext, type: number, src: string): WebGLShader | null {
  const s = gl.createShader(type);
  if (!s) return null;
  gl.shaderSource(s, src);
  gl.compileShader(s);
  return s;
}

/** Runs the benchmark on its own small canvas. */
export function gpuBench(opts: GpuBenchOptions = {}, now: () => number = () => performance.now()): GpuBenchResult | null {
  const size = opts.size ?? 256;
  const budget = opts.budgetMs ?? 200;
  const maxFrames = opts.maxFrames ?? 8;
  if (typeof document === 'undefined') return null;
  const canvas = document.createElement('canvas');
  canvas.width = size;
  canvas.height = size;
  const gl = canvas.getContext('webgl2', { antialias: false, depth: false, preserveDrawingBuffer: false });
  if (!gl) return null;
  try {
    const vs = compile(gl, gl.VERTEX_SHADER, VERTEX);
    const fs = compile(gl, gl.FRAGMENT_SHADER, FRAGMENT);
    const prog = gl.createProgram();
    if (!vs || !fs || !prog) return null;
    gl.attachShader(prog, vs);
    gl.attachShader(prog, fs);
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) return null;
    gl.useProgram(prog);
    const buf = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
    const loc = gl.getAttribLocation(prog, 'p');
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, 2, gl.FLOAT, false, 0, 0);
    gl.viewport(0, 0, size, size);
    gl.uniform2f(gl.getUniformLocation(prog, 'res'), size, size);
    const tLoc = gl.getUniformLocation(prog, 't');
    const px = new Uint8Array(4);
    const frame = (i: number) => {
      gl.uniform1f(tLoc, i * 0.1);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    };
    const start = now();
    frame(0);
    const firstMs = now() - start;
    const times: number[] = [];
    for (let i = 1; i <= maxFrames; i++) {
      const t0 = now();
      // A frame that would overrun the budget (judged by the last one) is not started.
      const last = times.length ? times[times.length - 1] : firstMs;
      if (times.length && t0 - start + last > budget) break;
      frame(i);
      times.push(now() - t0);
      if (now() - start > budget) break;
    }
    if (!times.length) return { frameMs: firstMs, firstMs, frames: 0 };
    times.sort((a, b) => a - b);
    return { frameMs: times[times.length >> 1], firstMs, frames: times.length };
  } finally {
    gl.getExtension('WEBGL_lose_context')?.loseContext();
  }
}
