// frep-glsl browser harness (plain WebGL2, no bundler).
//
// window.frepRender({vert, frag, uniforms, width, height, overrides, frames})
//   vert, frag: GLSL sources (frep_glsl::vertex_shader / fragment_shader);
//   uniforms:   the parsed uniforms JSON (Shader::uniforms_json);
//   overrides:  {name: [values]} applied on top of the JSON defaults
//               (u_resolution is always set to the canvas size);
//   frames:     list of further override sets, each rendered with the SAME
//               program (uniform upload only, no recompile).
// Returns {renderer, linkMs, frames: [{ms, hits, capped, mask}]} where mask
// is one string per row, top row first: '#' hit, '.' background, 'M' capped.
// The background is classified by exact colour: pass u_background such that
// the shaded colours cannot equal it (the driver uses pure cyan).
'use strict';

function frepCompile(gl, type, src) {
  const s = gl.createShader(type);
  gl.shaderSource(s, src);
  gl.compileShader(s);
  if (!gl.getShaderParameter(s, gl.COMPILE_STATUS) && !gl.isContextLost()) {
    throw new Error('compile failed: ' + gl.getShaderInfoLog(s));
  }
  return s;
}

function frepSetUniform(gl, prog, u, values) {
  const loc = gl.getUniformLocation(prog, u.name) ||
    gl.getUniformLocation(prog, u.name + '[0]');
  if (loc === null) return; // optimized away
  const v = values.map((x) => (x === null ? NaN : x));
  const ty = u.type.replace(/\[\d+\]$/, '');
  switch (ty) {
    case 'float': gl.uniform1fv(loc, v); break;
    case 'vec2': gl.uniform2fv(loc, v); break;
    case 'vec3': gl.uniform3fv(loc, v); break;
    case 'vec4': gl.uniform4fv(loc, v); break;
    case 'mat4': gl.uniformMatrix4fv(loc, false, v); break;
    case 'int': gl.uniform1iv(loc, v.map((x) => Math.round(x))); break;
    default: throw new Error('unknown uniform type ' + u.type);
  }
}

function frepApply(gl, prog, uniforms, overrides, w, h) {
  for (const u of uniforms.uniforms) {
    let values = u.values;
    if (overrides && Object.prototype.hasOwnProperty.call(overrides, u.name)) values = overrides[u.name];
    if (u.name === 'u_resolution') values = [w, h];
    frepSetUniform(gl, prog, u, values);
  }
}

function frepFrame(gl, w, h, bg) {
  const t0 = performance.now();
  gl.drawArrays(gl.TRIANGLES, 0, 3);
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  const ms = performance.now() - t0;
  if (gl.isContextLost()) throw new Error('WebGL context lost during the draw');
  const mask = [];
  let hits = 0;
  let capped = 0;
  for (let y = h - 1; y >= 0; y--) {
    let row = '';
    for (let x = 0; x < w; x++) {
      const i = 4 * (y * w + x);
      const r = px[i], g = px[i + 1], b = px[i + 2];
      if (r === 255 && g === 0 && b === 255) { row += 'M'; capped++; }
      else if (Math.abs(r - bg[0]) <= 1 && Math.abs(g - bg[1]) <= 1 && Math.abs(b - bg[2]) <= 1) row += '.';
      else { row += '#'; hits++; }
    }
    mask.push(row);
  }
  return { ms, hits, capped, mask };
}

window.frepRender = function (job) {
  const w = job.width, h = job.height;
  const canvas = document.getElementById('c');
  canvas.width = w;
  canvas.height = h;
  const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
  if (!gl) throw new Error('no WebGL2 context');
  const dbg = gl.getExtension('WEBGL_debug_renderer_info');
  const renderer = dbg ? gl.getParameter(dbg.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER);
  const t0 = performance.now();
  const prog = gl.createProgram();
  gl.attachShader(prog, frepCompile(gl, gl.VERTEX_SHADER, job.vert));
  gl.attachShader(prog, frepCompile(gl, gl.FRAGMENT_SHADER, job.frag));
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) {
    throw new Error('link failed: ' + gl.getProgramInfoLog(prog));
  }
  const linkMs = performance.now() - t0;
  gl.useProgram(prog);
  gl.bindVertexArray(gl.createVertexArray());
  gl.viewport(0, 0, w, h);
  // Background as the shader writes it: pow(c, 1/2.2) of a linear colour.
  const bgOf = (ov) => {
    const u = job.uniforms.uniforms.find((x) => x.name === 'u_background');
    const c = (ov && ov.u_background) || (job.overrides && job.overrides.u_background) || u.values;
    return c.map((v) => Math.round(255 * Math.pow(Math.min(Math.max(v, 0), 1), 1 / 2.2)));
  };
  frepApply(gl, prog, job.uniforms, job.overrides, w, h);
  const frames = [frepFrame(gl, w, h, bgOf(null))];
  for (const ov of job.frames || []) {
    frepApply(gl, prog, job.uniforms, Object.assign({}, job.overrides, ov), w, h);
    frames.push(frepFrame(gl, w, h, bgOf(ov)));
  }
  const result = { renderer, linkMs, frames };
  document.getElementById('out').textContent = frames[0].mask.join('\n');
  document.title = 'frep-glsl harness: ' + frames[0].hits + ' hits in ' + Math.round(frames[0].ms) + ' ms';
  return result;
};
