/**
 * The client modes' harness for client.spec.ts: mounts one mode view (4a,
 * 4b or volume) in a fixed-size layer with a minimal ModeContext (the
 * viewer's scene conventions, a settable camera), so the tests drive a
 * mode directly. Bundled by the spec with Vite and served on the server's
 * origin (the API and /frep.wasm are the real ones).
 */
import { Api } from '../../src/api/client';
import { backgroundCss, DEFAULT_CAMERA, SCENE } from '../../src/viewer/scene';
import type { ModeContext, ModeView } from '../../src/viewer/types';
import type { CameraView, CompileSummary, Mode } from '../../src/wire';
import * as raycast from '../../src/viewer/modes/raycast';
import * as volume from '../../src/viewer/modes/volume';
import * as wasmmesh from '../../src/viewer/modes/wasmmesh';

interface Mounted {
  view: ModeView;
  layer: HTMLElement;
  camera: CameraView;
  frames: number;
  failures: string[];
  size: number;
}

let m: Mounted | null = null;
let shows = 0;

const harness = {
  /** Mounts `mode` in a `size`×`size` CSS-pixel layer (`shaderFrom`: mode 4a's shader source). */
  async mount(mode: Mode, size: number, shaderFrom?: 'server' | 'wasm'): Promise<void> {
    const layer = document.createElement('div');
    layer.id = 'layer';
    layer.style.cssText = `position:relative;width:${size}px;height:${size}px;background:${backgroundCss(SCENE)}`;
    document.body.style.margin = '0';
    document.body.appendChild(layer);
    const mods: Record<string, { create(m: Mode): ModeView }> = { gpuRaycast: raycast, wasmMesh: wasmmesh, volume };
    const view = shaderFrom
      ? raycast.create(mode, { ...raycast.DEFAULT_RAYCAST, shaderFrom })
      : mods[mode]!.create(mode);
    const state: Mounted = { view, layer, camera: { ...DEFAULT_CAMERA }, frames: 0, failures: [], size };
    const ctx: ModeContext = {
      container: layer,
      api: new Api(''),
      apiBase: '',
      session: null,
      scene: SCENE,
      camera: () => state.camera,
      size: () => ({ width: size, height: size, pixelRatio: 1 }),
      moving: () => false,
      decision: () => null,
      frame: () => {
        state.frames++;
      },
      displayed: () => undefined,
      progress: () => undefined,
      failed: (msg) => {
        state.failures.push(msg);
      },
    };
    m = state;
    await view.mount(ctx);
  },

  /** Shows a model; resolves at its first display, or with the error's name and message. */
  async show(source: string, params: number[], summary: CompileSummary): Promise<{ ok: boolean; error?: string; name?: string }> {
    const s = m!;
    const ac = new AbortController();
    shows++;
    try {
      await s.view.show({
        show: { source, params },
        summary,
        bounds: summary.bounds as [number, number, number, number, number, number],
        settings: null,
        signal: ac.signal,
      });
      return { ok: true };
    } catch (e) {
      return { ok: false, error: (e as Error).message, name: (e as Error).name };
    }
  },

  /** New parameter values as the viewer gives them (setParams, then show). */
  async setParams(source: string, params: number[], summary: CompileSummary): Promise<void> {
    m!.view.setParams(params);
    await harness.show(source, params, summary);
  },

  /** A section plane (keeps normal · p <= offset), or none; resolves after a few frames. */
  async setSection(plane: { normal: [number, number, number]; offset: number } | null): Promise<void> {
    m!.view.setSection(plane);
    await harness.frames_(4);
  },

  /**
   * Pixels of a PNG (base64) whose colour is near `rgb` (sRGB bytes):
   * within `tol` on each channel after scaling to the brightest channel
   * (so shading does not matter, the hue does).
   */
  async countHue(pngBase64: string, rgb: [number, number, number], tol: number): Promise<number> {
    const bytes = Uint8Array.from(atob(pngBase64), (c) => c.charCodeAt(0));
    const img = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const g = c.getContext('2d')!;
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, img.width, img.height).data;
    const norm = (v: number[]) => {
      const k = Math.max(...v, 1);
      return v.map((x) => (255 * x) / k);
    };
    const want = norm(rgb);
    let n = 0;
    for (let i = 0; i < d.length; i += 4) {
      if (Math.max(d[i]!, d[i + 1]!, d[i + 2]!) < 40) continue;
      const got = norm([d[i]!, d[i + 1]!, d[i + 2]!]);
      if (got.every((v, k) => Math.abs(v - want[k]!) <= tol)) n++;
    }
    return n;
  },

  /** Frames displayed so far. */
  frames(): number {
    return m!.frames;
  },

  /** The failures the mode reported. */
  failures(): string[] {
    return m!.failures.slice();
  },

  /** The layer's data attributes. */
  stats(): Record<string, string> {
    return { ...m!.layer.dataset } as Record<string, string>;
  },

  /** Resolves after `n` animation frames. */
  async frames_(n: number): Promise<void> {
    for (let i = 0; i < n; i++) await new Promise((r) => requestAnimationFrame(r));
  },

  /**
   * The silhouette of a PNG (base64): 1 where the pixel differs from the
   * background gradient of its row by more than `tol` (sum over RGB).
   */
  async mask(pngBase64: string, tol: number): Promise<number[]> {
    const bytes = Uint8Array.from(atob(pngBase64), (c) => c.charCodeAt(0));
    const img = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const g = c.getContext('2d')!;
    g.drawImage(img, 0, 0);
    const d = g.getImageData(0, 0, img.width, img.height).data;
    const out: number[] = [];
    const s = SCENE;
    for (let y = 0; y < img.height; y++) {
      const t = img.height > 1 ? y / (img.height - 1) : 0.5;
      const bg = [0, 1, 2].map((k) => 255 * (s.backgroundTop[k]! + (s.backgroundBottom[k]! - s.backgroundTop[k]!) * t));
      for (let x = 0; x < img.width; x++) {
        const o = 4 * (y * img.width + x);
        const diff = Math.abs(d[o]! - bg[0]!) + Math.abs(d[o + 1]! - bg[1]!) + Math.abs(d[o + 2]! - bg[2]!);
        out.push(diff > tol ? 1 : 0);
      }
    }
    return out;
  },

  shows: () => shows,
};

(window as unknown as { frepClient: typeof harness }).frepClient = harness;
document.title = 'frep client harness ready';
