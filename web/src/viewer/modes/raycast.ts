/**
 * Mode 4a: the model ray cast on the client's GPU by its generated shader.
 *
 * The shader comes from the server (`shader` artefact) or, when the server
 * cannot give it, from the WebAssembly kernel — frep-glsl either way, whole:
 * fields, traversal and the viewer's camera, section and lighting
 * (raycast-glsl.ts). The client compiles it and sets uniforms.
 *
 * * Compiling is asynchronous (KHR_parallel_shader_compile where present);
 *   the previous program keeps drawing until the new one's first frame.
 * * Parameters and constants are uniforms: `setParams` uploads `u_params`
 *   and never compiles; an edit whose generated source is unchanged (a
 *   number edited) uploads `u_consts` only. `data-compilations` on the
 *   layer counts compilations (the tests read it).
 * * Resolution adapts while orbiting (raycast-resolution.ts), full when
 *   still; every displayed frame is reported (`ctx.frame()`), from which
 *   the viewer reports the achieved frame rate to the server.
 * * A model whose shader is too large for a browser to compile (above
 *   `maxStatements`, about a thousand primitives) is refused before any
 *   work, with the reason.
 * * Frames are paced by a fence: a new frame is drawn only when the last
 *   one has finished, so slow frames never queue up and input stays live.
 */
import type { CameraView, Mode, ShaderArtefact } from '../../wire';
import type { ModeContext, ModeModel, ModeView, SectionPlane } from '../types';
import { VERTEX_SHADER, viewerShader } from './raycast-glsl';
import { type LinkedProgram, ProgramCompiler, setUniform } from './raycast-gl';
import { ResolutionController } from './raycast-resolution';
import { setSceneUniforms } from './raycast-scene';

export { lightToWorld } from './raycast-scene';

/** Mode 4a's limits and choices. */
export interface RaycastOptions {
  /** Largest shader (statements per field flavour) sent to the browser's compiler. */
  maxStatements: number;
  /** Cap on interval steps per pixel (magenta where reached). */
  maxSteps: number;
  /** Where the shader comes from: the server, the WebAssembly kernel, or the server then the kernel. */
  shaderFrom: 'server' | 'wasm' | 'auto';
}

/**
 * About a thousand primitives: a sphere is ~5 statements, a blended or
 * transformed primitive ~7-10 (m2's 100 spheres: 464, the 42-primitive
 * complex hemisphere: 299).
 */
export const DEFAULT_RAYCAST: RaycastOptions = { maxStatements: 6000, maxSteps: 512, shaderFrom: 'auto' };

/** A model mode 4a will not draw, with the reason (the viewer falls back). */
export class RaycastRefused extends Error {
  override name = 'RaycastRefused';
}

/** Whether mode 4a can draw a model of `statements`; the reason when not. */
export function raycastRefusal(statements: number, opts: RaycastOptions = DEFAULT_RAYCAST): string | null {
  if (statements > opts.maxStatements) {
    return `the model's shader has ${statements} statements, more than a browser compiles in reasonable time (limit ${opts.maxStatements}, about 1,000 primitives): drawn by another mode`;
  }
  return null;
}

interface Current {
  key: string;
  program: LinkedProgram;
  artefact: ShaderArtefact;
  bytes: number;
}

class RaycastView implements ModeView {
  readonly mode: Mode = 'gpuRaycast';
  private ctx!: ModeContext;
  private canvas!: HTMLCanvasElement;
  private gl!: WebGL2RenderingContext;
  private compiler!: ProgramCompiler;
  private vao: WebGLVertexArrayObject | null = null;
  private current: Current | null = null;
  private params: number[] = [];
  private bounds: number[] = [-1, -1, -1, 1, 1, 1];
  private section: SectionPlane | null = null;
  private readonly resolution = new ResolutionController();
  private dirty = false;
  private raf = 0;
  private fence: { sync: WebGLSync; start: number; scale: number; moving: boolean; program: LinkedProgram } | null = null;
  private lastScale = 1;
  private frames = 0;
  private waiting: { program: LinkedProgram; resolve: () => void; bytes: number } | null = null;
  private disposed = false;

  constructor(private readonly opts: RaycastOptions = DEFAULT_RAYCAST) {}

  async mount(ctx: ModeContext): Promise<void> {
    this.ctx = ctx;
    const canvas = document.createElement('canvas');
    canvas.style.cssText = 'position:absolute;inset:0;width:100%;height:100%;display:block';
    const gl = canvas.getContext('webgl2', { antialias: false, alpha: false, depth: false, premultipliedAlpha: false });
    if (!gl) throw new Error('WebGL2 is not available: mode 4a cannot draw');
    this.canvas = canvas;
    this.gl = gl;
    this.compiler = new ProgramCompiler(gl);
    this.vao = gl.createVertexArray();
    canvas.addEventListener('webglcontextlost', (e) => {
      e.preventDefault();
      ctx.failed('the WebGL context was lost');
    });
    ctx.container.appendChild(canvas);
    this.stat('mode', 'gpuRaycast');
    this.stat('compilations', '0');
    this.stat('frames', '0');
    this.stat('parallelCompile', String(this.compiler.parallelCompile));
  }

  private stat(name: string, value: string): void {
    this.ctx.container.dataset[name] = value;
  }

  async show(model: ModeModel): Promise<void> {
    const reason = raycastRefusal(model.summary.shaderStatements, this.opts);
    if (reason) {
      this.stat('status', 'refused');
      this.stat('reason', reason);
      this.ctx.failed(reason);
      throw new RaycastRefused(reason);
    }
    this.params = model.show.params.slice();
    this.bounds = model.bounds.slice();
    const key = JSON.stringify([model.show.source, model.bounds]);
    if (this.current?.key === key) {
      // New parameters only: uniforms, no shader request, no compile.
      this.schedule();
      return this.displayed(this.current.program, 0);
    }
    this.stat('status', 'loading');
    const artefact = await this.fetchShader(model);
    if (model.signal.aborted) throw new DOMException('superseded', 'AbortError');
    const fragment = viewerShader(artefact.source);
    const bytes = artefact.source.length;
    if (this.current && this.current.program.source === fragment) {
      // The same code with other constants: new uniform values only.
      this.current = { key, program: this.current.program, artefact, bytes };
      this.schedule();
      return this.displayed(this.current.program, bytes);
    }
    this.stat('status', 'compiling');
    let program: LinkedProgram;
    try {
      program = await this.compiler.compile(VERTEX_SHADER, fragment, model.signal);
    } catch (e) {
      if (!(e instanceof DOMException && e.name === 'AbortError')) {
        this.stat('status', 'failed');
        this.ctx.failed(e instanceof Error ? e.message : String(e));
      }
      throw e;
    } finally {
      this.stat('compilations', String(this.compiler.compilations));
    }
    if (model.signal.aborted || this.disposed) {
      this.gl.deleteProgram(program.program);
      throw new DOMException('superseded', 'AbortError');
    }
    const old = this.current;
    this.current = { key, program, artefact, bytes };
    // The old program drew until now; it goes once the new one is current.
    if (old && old.program !== program) this.gl.deleteProgram(old.program.program);
    this.stat('status', 'ready');
    this.stat('statements', String(artefact.statements));
    this.schedule();
    return this.displayed(program, bytes);
  }

  /** Resolves when a frame of `program` has been displayed. */
  private displayed(program: LinkedProgram, bytes: number): Promise<void> {
    return new Promise((resolve) => {
      this.waiting?.resolve();
      this.waiting = { program, resolve, bytes };
    });
  }

  private async fetchShader(model: ModeModel): Promise<ShaderArtefact> {
    const fromServer = async (): Promise<ShaderArtefact> => {
      const ref = await this.ctx.api.requestArtefact(
        { model: { from: 'source', source: model.show.source }, params: model.show.params, spec: { kind: 'shader' } },
        model.signal,
      );
      const blob = await this.ctx.api.fetchArtefact(ref, undefined, model.signal);
      return JSON.parse(await blob.text()) as ShaderArtefact;
    };
    const fromWasm = async (): Promise<ShaderArtefact> => {
      const { sharedKernel } = await import('../../wasm/client');
      return sharedKernel().shader(model.show.source, model.show.params, model.bounds.slice());
    };
    switch (this.opts.shaderFrom) {
      case 'server':
        return fromServer();
      case 'wasm':
        return fromWasm();
      default:
        try {
          return await fromServer();
        } catch (e) {
          if (e instanceof DOMException && e.name === 'AbortError') throw e;
          this.stat('shaderFrom', 'wasm');
          return fromWasm();
        }
    }
  }

  setCamera(_c: CameraView): void {
    this.schedule();
  }

  setParams(p: number[]): void {
    this.params = p.slice();
    this.schedule();
  }

  setSection(s: SectionPlane | null): void {
    this.section = s;
    this.schedule();
  }

  resize(_w: number, _h: number): void {
    this.schedule();
  }

  private schedule(): void {
    this.dirty = true;
    if (!this.raf && !this.disposed) this.raf = requestAnimationFrame(this.loop);
  }

  private readonly loop = (): void => {
    this.raf = 0;
    if (this.disposed) return;
    const gl = this.gl;
    if (this.fence) {
      const status = gl.getSyncParameter(this.fence.sync, gl.SYNC_STATUS);
      if (status !== gl.SIGNALED) {
        this.raf = requestAnimationFrame(this.loop);
        return;
      }
      this.finished();
    }
    // Still again after a reduced frame: once more at full resolution.
    if (!this.dirty && this.lastScale < 1 && !this.ctx.moving()) this.dirty = true;
    if (this.dirty && this.current) this.draw(this.current);
    if (this.fence || this.dirty || this.lastScale < 1) this.raf = requestAnimationFrame(this.loop);
  };

  private finished(): void {
    const f = this.fence!;
    this.gl.deleteSync(f.sync);
    this.fence = null;
    const ms = performance.now() - f.start;
    this.resolution.record(ms, f.scale, f.moving);
    this.frames++;
    this.stat('frames', String(this.frames));
    this.stat('scale', f.scale.toFixed(3));
    this.ctx.frame();
    if (this.waiting && this.waiting.program === f.program) {
      const w = this.waiting;
      this.waiting = null;
      this.ctx.displayed(w.bytes);
      w.resolve();
    }
  }

  private draw(cur: Current): void {
    const gl = this.gl;
    this.dirty = false;
    const moving = this.ctx.moving();
    const scale = this.resolution.scale(moving);
    const size = this.ctx.size();
    const w = Math.max(1, Math.round(size.width * size.pixelRatio * scale));
    const h = Math.max(1, Math.round(size.height * size.pixelRatio * scale));
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    gl.viewport(0, 0, w, h);
    const p = cur.program;
    gl.useProgram(p.program);
    this.uniforms(cur, w, h);
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const sync = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
    gl.flush();
    this.lastScale = scale;
    if (sync) this.fence = { sync, start: performance.now(), scale, moving, program: p };
  }

  private uniforms(cur: Current, w: number, h: number): void {
    const gl = this.gl;
    const p = cur.program;
    for (const u of cur.artefact.uniforms) {
      if (u.name === 'u_consts' || u.name === 'u_xextra') setUniform(gl, p, u.name, u.type, u.values);
      if (u.name === 'u_params') {
        const n = Number(/\[(\d+)\]/.exec(u.type)?.[1] ?? u.values.length);
        const vals = Array.from({ length: n }, (_, i) => this.params[i] ?? u.values[i] ?? 0);
        setUniform(gl, p, u.name, u.type, vals);
      }
    }
    setSceneUniforms(gl, p, {
      camera: this.ctx.camera(),
      framing: this.bounds,
      box: cur.artefact.bounds,
      width: w,
      height: h,
      scene: this.ctx.scene,
      section: this.section,
      maxSteps: this.opts.maxSteps,
    });
  }

  dispose(): void {
    this.disposed = true;
    if (this.raf) cancelAnimationFrame(this.raf);
    this.waiting?.resolve();
    this.waiting = null;
    const gl = this.gl;
    if (gl) {
      if (this.fence) gl.deleteSync(this.fence.sync);
      if (this.current) gl.deleteProgram(this.current.program.program);
      if (this.vao) gl.deleteVertexArray(this.vao);
      gl.getExtension('WEBGL_lose_context')?.loseContext();
    }
    this.canvas?.remove();
  }
}

/** The modes this file implements. */
export const modes: readonly Mode[] = ['gpuRaycast'];

/** A mode-4a view. */
export function create(_mode: Mode, opts: RaycastOptions = DEFAULT_RAYCAST): ModeView {
  return new RaycastView(opts);
}
