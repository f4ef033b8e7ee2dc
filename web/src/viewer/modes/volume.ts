/**
 * The volume mode: the server's 8-bit 3D texture of the field (`slices`
 * artefact: raw bytes, x fastest, with its VolumeLayout in the
 * `x-frep-volume` header) ray marched on the GPU (volume-glsl.ts).
 *
 * Refined progressively: a coarse grid first (64³, a quarter of a
 * megabyte) is shown as soon as it arrives, then the decided grid (128³ by
 * default) replaces it; on the GPU the march steps a voxel while the user
 * orbits (at the adaptive resolution) and a quarter voxel when still. For a
 * model with colours, the WebAssembly kernel samples the attributes `s[]`
 * into a colour volume: the section plane then shows the inside in them.
 * The camera, background and lighting are the other modes'.
 */
import type { CameraView, Mode, VolumeLayout } from '../../wire';
import type { ModeContext, ModeModel, ModeView, SectionPlane } from '../types';
import { type LinkedProgram, ProgramCompiler, setUniform } from './raycast-gl';
import { VERTEX_SHADER } from './scene-glsl';
import { ResolutionController } from './raycast-resolution';
import { setSceneUniforms } from './raycast-scene';
import { VOLUME_FRAGMENT } from './volume-glsl';

/** The volume mode's choices. */
export interface VolumeOptions {
  /** The grid shown first (0: none). */
  coarseGrid: number;
  /** The grid when the decision gives none. */
  grid: number;
  /** Samples per axis of the colour volume (models with s[]). */
  colorGrid: number;
  /** March step in voxels while moving, and when still. */
  movingStep: number;
  stillStep: number;
}

export const DEFAULT_VOLUME: VolumeOptions = { coarseGrid: 64, grid: 128, colorGrid: 64, movingStep: 1, stillStep: 0.25 };

/** The grids fetched in turn for a decided grid. */
export function volumeGrids(decided: number | undefined, opts: VolumeOptions = DEFAULT_VOLUME): number[] {
  const g = decided && decided > 1 ? decided : opts.grid;
  return opts.coarseGrid > 1 && opts.coarseGrid < g ? [opts.coarseGrid, g] : [g];
}

/** Reads and checks the `x-frep-volume` header against the body's size. */
export function parseVolumeLayout(header: string | null, bytes: number): VolumeLayout {
  if (!header) throw new Error('the slices artefact has no x-frep-volume header');
  const l = JSON.parse(header) as VolumeLayout;
  const [nx, ny, nz] = l.dims;
  if (!(nx! > 0 && ny! > 0 && nz! > 0) || l.bounds.length !== 6) throw new Error('bad x-frep-volume header');
  if (nx! * ny! * nz! !== bytes) throw new Error(`the volume has ${bytes} bytes, its layout says ${nx}×${ny}×${nz}`);
  return l;
}

class VolumeView implements ModeView {
  readonly mode: Mode = 'volume';
  private ctx!: ModeContext;
  private canvas!: HTMLCanvasElement;
  private gl!: WebGL2RenderingContext;
  private program: LinkedProgram | null = null;
  private volume: WebGLTexture | null = null;
  private colors: WebGLTexture | null = null;
  private layout: VolumeLayout | null = null;
  private hasColors = false;
  private framing: number[] = [-1, -1, -1, 1, 1, 1];
  private section: SectionPlane | null = null;
  private readonly resolution = new ResolutionController();
  private vao: WebGLVertexArrayObject | null = null;
  private raf = 0;
  private dirty = false;
  private fence: { sync: WebGLSync; start: number; scale: number; moving: boolean; generation: number } | null = null;
  /** Bumped at each volume upload: a frame shows the volume of its generation. */
  private generation = 0;
  private firstFrame: { generation: number; resolve: () => void } | null = null;
  private lastFine = true;
  private request = 0;
  private disposed = false;

  constructor(private readonly opts: VolumeOptions = DEFAULT_VOLUME) {}

  async mount(ctx: ModeContext): Promise<void> {
    this.ctx = ctx;
    const canvas = document.createElement('canvas');
    canvas.style.cssText = 'position:absolute;inset:0;width:100%;height:100%;display:block';
    const gl = canvas.getContext('webgl2', { antialias: false, alpha: false, depth: false });
    if (!gl) throw new Error('WebGL2 is not available: the volume mode cannot draw');
    this.canvas = canvas;
    this.gl = gl;
    this.vao = gl.createVertexArray();
    ctx.container.appendChild(canvas);
    ctx.container.dataset.mode = 'volume';
    this.program = await new ProgramCompiler(gl).compile(VERTEX_SHADER, VOLUME_FRAGMENT);
    this.volume = gl.createTexture();
    this.colors = gl.createTexture();
    // An empty colour volume until one arrives.
    this.upload(this.colors, 1, 1, 1, new Uint8Array(4), true);
  }

  private upload(tex: WebGLTexture | null, nx: number, ny: number, nz: number, data: Uint8Array, rgba: boolean): void {
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_3D, tex);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    gl.texImage3D(gl.TEXTURE_3D, 0, rgba ? gl.RGBA8 : gl.R8, nx, ny, nz, 0, rgba ? gl.RGBA : gl.RED, gl.UNSIGNED_BYTE, data);
    gl.texParameteri(gl.TEXTURE_3D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_3D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    for (const w of [gl.TEXTURE_WRAP_S, gl.TEXTURE_WRAP_T, gl.TEXTURE_WRAP_R]) gl.texParameteri(gl.TEXTURE_3D, w, gl.CLAMP_TO_EDGE);
  }

  private async fetchVolume(model: ModeModel, grid: number): Promise<{ layout: VolumeLayout; bytes: Uint8Array }> {
    const api = this.ctx.api;
    const ref = await api.requestArtefact(
      { model: { from: 'source', source: model.show.source }, params: model.show.params, spec: { kind: 'slices', grid } },
      model.signal,
    );
    const r = await fetch(api.url(ref.url), { signal: model.signal });
    if (!r.ok) throw new Error(`the volume (${grid}³) failed: HTTP ${r.status}`);
    const bytes = new Uint8Array(await r.arrayBuffer());
    return { layout: parseVolumeLayout(r.headers.get('x-frep-volume'), bytes.byteLength), bytes };
  }

  async show(model: ModeModel): Promise<void> {
    const id = ++this.request;
    this.framing = model.bounds.slice();
    const live = (): boolean => id === this.request && !model.signal.aborted && !this.disposed;
    const grids = volumeGrids(model.settings?.volumeGrid, this.opts);
    if (model.summary.attributes >= 3) void this.loadColors(model, live);
    else this.hasColors = false;
    const v = await this.fetchVolume(model, grids[0]!);
    if (!live()) throw new DOMException('superseded', 'AbortError');
    this.useVolume(v.layout, v.bytes);
    this.ctx.progress(`volume-${id}`, 1 / grids.length);
    const generation = this.generation;
    const drawn = new Promise<void>((resolve) => (this.firstFrame = { generation, resolve }));
    this.schedule();
    await drawn;
    this.ctx.displayed(v.bytes.byteLength);
    if (grids.length > 1) void this.refineLater(model, grids.slice(1), live);
  }

  private useVolume(layout: VolumeLayout, bytes: Uint8Array): void {
    const [nx, ny, nz] = layout.dims as [number, number, number];
    this.upload(this.volume, nx, ny, nz, bytes, false);
    this.layout = layout;
    this.generation++;
    this.ctx.container.dataset.grid = String(nx);
  }

  /** The finer grids after the first display (show() has resolved). */
  private async refineLater(model: ModeModel, grids: number[], live: () => boolean): Promise<void> {
    for (const grid of grids) {
      try {
        const v = await this.fetchVolume(model, grid);
        if (!live()) return;
        this.useVolume(v.layout, v.bytes);
        this.ctx.progress(`volume-${this.request}`, 1);
        this.schedule();
      } catch (e) {
        if (live() && !(e instanceof DOMException && e.name === 'AbortError')) {
          this.ctx.container.dataset.refineError = e instanceof Error ? e.message : String(e);
        }
        return;
      }
    }
  }

  private async loadColors(model: ModeModel, live: () => boolean): Promise<void> {
    try {
      const { sharedKernel } = await import('../../wasm/client');
      const k = sharedKernel();
      await k.whenReady();
      const g = this.opts.colorGrid;
      const rgba = await k.colorVolume(model.show.source, model.show.params, this.layout?.bounds ?? model.bounds.slice(), g);
      if (!live()) return;
      this.upload(this.colors, g, g, g, rgba, true);
      this.hasColors = true;
      this.ctx.container.dataset.colors = 'wasm';
      this.schedule();
    } catch {
      // Without the kernel the cut face keeps the section colour.
      this.hasColors = false;
    }
  }

  setCamera(_c: CameraView): void {
    this.schedule();
  }

  setParams(_p: number[]): void {
    // The viewer calls show() with the new parameters: a new volume.
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
      if (gl.getSyncParameter(this.fence.sync, gl.SYNC_STATUS) !== gl.SIGNALED) {
        this.raf = requestAnimationFrame(this.loop);
        return;
      }
      const f = this.fence;
      gl.deleteSync(f.sync);
      this.fence = null;
      this.resolution.record(performance.now() - f.start, f.scale, f.moving);
      this.ctx.frame();
      if (this.firstFrame && f.generation >= this.firstFrame.generation) {
        const r = this.firstFrame;
        this.firstFrame = null;
        r.resolve();
      }
    }
    // Still again after a coarse frame: once more in full.
    if (!this.dirty && !this.lastFine && !this.ctx.moving()) this.dirty = true;
    if (this.dirty && this.layout && this.program) this.draw();
    if (this.fence || this.dirty || !this.lastFine) this.raf = requestAnimationFrame(this.loop);
  };

  private draw(): void {
    const gl = this.gl;
    const p = this.program!;
    const layout = this.layout!;
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
    gl.useProgram(p.program);
    const step = moving ? this.opts.movingStep : this.opts.stillStep;
    const n = Math.max(...layout.dims);
    // Enough steps to cross the box's diagonal.
    const maxSteps = Math.ceil((Math.sqrt(3) * n) / step) + 2;
    setSceneUniforms(gl, p, {
      camera: this.ctx.camera(),
      framing: this.framing,
      box: layout.bounds,
      width: w,
      height: h,
      scene: this.ctx.scene,
      section: this.section,
      maxSteps,
    });
    setUniform(gl, p, 'u_dims', 'vec3', layout.dims);
    setUniform(gl, p, 'u_step', 'float', [step]);
    setUniform(gl, p, 'u_has_colors', 'float', [this.hasColors ? 1 : 0]);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_3D, this.volume);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_3D, this.colors);
    const loc = (name: string): WebGLUniformLocation | null => gl.getUniformLocation(p.program, name);
    gl.uniform1i(loc('u_volume'), 0);
    gl.uniform1i(loc('u_colors'), 1);
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const sync = gl.fenceSync(gl.SYNC_GPU_COMMANDS_COMPLETE, 0);
    gl.flush();
    this.lastFine = !moving && scale >= 1;
    if (sync) this.fence = { sync, start: performance.now(), scale, moving, generation: this.generation };
  }

  dispose(): void {
    this.disposed = true;
    if (this.raf) cancelAnimationFrame(this.raf);
    this.firstFrame?.resolve();
    const gl = this.gl;
    if (gl) {
      if (this.fence) gl.deleteSync(this.fence.sync);
      if (this.program) gl.deleteProgram(this.program.program);
      gl.deleteTexture(this.volume);
      gl.deleteTexture(this.colors);
      gl.getExtension('WEBGL_lose_context')?.loseContext();
    }
    this.canvas?.remove();
  }
}

/** The modes this file implements. */
export const modes: readonly Mode[] = ['volume'];

/** A volume view. */
export function create(_mode: Mode, opts: VolumeOptions = DEFAULT_VOLUME): ModeView {
  return new VolumeView(opts);
}
