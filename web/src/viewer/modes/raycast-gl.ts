/**
 * WebGL2 plumbing of mode 4a: compiling a program without blocking
 * (KHR_parallel_shader_compile: link, then poll COMPLETION_STATUS_KHR once a
 * frame; without the extension the status is read at once), counting every
 * compilation (tests read the count to prove a slider never recompiles), and
 * uploading uniforms by their GLSL type as frep-glsl lists them.
 */

/** A linked program and its uniform locations. */
export interface LinkedProgram {
  program: WebGLProgram;
  /** The fragment source it was built from (to skip identical rebuilds). */
  source: string;
  locations: Map<string, WebGLUniformLocation | null>;
}

/** The compile failed: the driver's log. */
export class ShaderCompileError extends Error {
  override name = 'ShaderCompileError';
}

const sleep = (ms: number): Promise<void> => new Promise((r) => setTimeout(r, ms));

/** Compiles programs for one context and counts them. */
export class ProgramCompiler {
  /** Fragment programs compiled so far (started, whether they succeed or not). */
  compilations = 0;
  private readonly parallel: { COMPLETION_STATUS_KHR: number } | null;

  constructor(private readonly gl: WebGL2RenderingContext) {
    this.parallel = gl.getExtension('KHR_parallel_shader_compile') as { COMPLETION_STATUS_KHR: number } | null;
  }

  /** Whether compiles run in the background (the extension is present). */
  get parallelCompile(): boolean {
    return this.parallel !== null;
  }

  private shader(type: number, source: string): WebGLShader {
    const gl = this.gl;
    const s = gl.createShader(type);
    if (!s) throw new ShaderCompileError('cannot create a shader (context lost?)');
    gl.shaderSource(s, source);
    gl.compileShader(s);
    return s;
  }

  /**
   * Compiles and links `vertex` + `fragment`; resolves once linked (the
   * page stays live meanwhile when the extension is present). Rejects with
   * the log on failure, or with an AbortError when `signal` aborts.
   */
  async compile(vertex: string, fragment: string, signal?: AbortSignal): Promise<LinkedProgram> {
    const gl = this.gl;
    this.compilations++;
    const vs = this.shader(gl.VERTEX_SHADER, vertex);
    const fs = this.shader(gl.FRAGMENT_SHADER, fragment);
    const program = gl.createProgram();
    if (!program) throw new ShaderCompileError('cannot create a program (context lost?)');
    gl.attachShader(program, vs);
    gl.attachShader(program, fs);
    gl.linkProgram(program);
    const cleanup = (): void => {
      gl.deleteShader(vs);
      gl.deleteShader(fs);
    };
    if (this.parallel) {
      const status = this.parallel.COMPLETION_STATUS_KHR;
      while (!gl.getProgramParameter(program, status)) {
        if (signal?.aborted) {
          cleanup();
          gl.deleteProgram(program);
          throw new DOMException('superseded', 'AbortError');
        }
        await sleep(16);
      }
    }
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
      const log = [gl.getShaderInfoLog(fs), gl.getShaderInfoLog(vs), gl.getProgramInfoLog(program)]
        .filter((l) => l)
        .join('\n');
      cleanup();
      gl.deleteProgram(program);
      throw new ShaderCompileError(`the shader does not compile: ${log.slice(0, 2000)}`);
    }
    cleanup();
    return { program, source: fragment, locations: new Map() };
  }
}

/** A uniform's location (cached per program). */
export function location(gl: WebGL2RenderingContext, p: LinkedProgram, name: string): WebGLUniformLocation | null {
  if (!p.locations.has(name)) p.locations.set(name, gl.getUniformLocation(p.program, name));
  return p.locations.get(name) ?? null;
}

/**
 * Uploads one uniform of frep-glsl's table by its type (`float[N]`,
 * `vec4[K]`, `vec2`, `vec3`, `mat4`, `int`, `float`); JSON nulls (non-finite
 * constants) become NaN. The program must be in use.
 */
export function setUniform(
  gl: WebGL2RenderingContext,
  p: LinkedProgram,
  name: string,
  type: string,
  values: readonly (number | null)[],
): void {
  const loc = location(gl, p, name);
  if (!loc) return; // optimised away by the driver
  const v = Float32Array.from(values, (x) => (x === null ? Number.NaN : x));
  const base = type.replace(/\[\d+\]$/, '');
  switch (base) {
    case 'float':
      gl.uniform1fv(loc, v);
      break;
    case 'vec2':
      gl.uniform2fv(loc, v);
      break;
    case 'vec3':
      gl.uniform3fv(loc, v);
      break;
    case 'vec4':
      gl.uniform4fv(loc, v);
      break;
    case 'mat4':
      gl.uniformMatrix4fv(loc, false, v);
      break;
    case 'int':
      gl.uniform1i(loc, Math.round(v[0] ?? 0));
      break;
    default:
      throw new Error(`unknown uniform type ${type} of ${name}`);
  }
}
