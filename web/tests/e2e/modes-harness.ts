/**
 * The viewer's harness for modes.spec.ts: mounts the whole adaptive viewer
 * (createViewer: session, decision, badge, modes) in a fixed-size box on
 * the server's origin, and reads back what the tests compare: the mode
 * shown, the decision, the camera, and the silhouette of the displayed
 * picture (the top mode layer composited over the background gradient,
 * thresholded against that gradient) and of a server reference image.
 * Bundled by the spec with Vite and served through page.route.
 */
import { Api } from '../../src/api/client';
import { measureClient } from '../../src/measure/capabilities';
import { createViewer, type SectionPlane, type Viewer } from '../../src/viewer/index';
import { backgroundAt } from '../../src/viewer/scene';
import type { CameraView, Mode } from '../../src/wire';

let viewer: Viewer | null = null;
let box: HTMLElement | null = null;

/** 1 where a pixel differs from its row's background by more than `tol` (sum of |ΔRGB|). */
function silhouette(data: Uint8ClampedArray, w: number, h: number, tol: number): number[] {
  const out: number[] = new Array(w * h);
  for (let y = 0; y < h; y++) {
    const bg = backgroundAt(h > 1 ? y / (h - 1) : 0.5);
    for (let x = 0; x < w; x++) {
      const o = 4 * (y * w + x);
      const d = Math.abs(data[o] - bg[0]) + Math.abs(data[o + 1] - bg[1]) + Math.abs(data[o + 2] - bg[2]);
      out[y * w + x] = d > tol ? 1 : 0;
    }
  }
  return out;
}

/** A canvas painted with the background gradient, row by row (the server's ramp). */
function gradientCanvas(w: number, h: number): CanvasRenderingContext2D {
  const c = document.createElement('canvas');
  c.width = w;
  c.height = h;
  const g = c.getContext('2d', { willReadFrequently: true })!;
  for (let y = 0; y < h; y++) {
    const [r, gg, b] = backgroundAt(h > 1 ? y / (h - 1) : 0.5);
    g.fillStyle = `rgb(${r},${gg},${b})`;
    g.fillRect(0, y, w, 1);
  }
  return g;
}

const harness = {
  /** Mounts the viewer in a `size`² box; `mode` forces a mode (null: the server decides). */
  mount(size: number, mode: Mode | null): void {
    box = document.createElement('div');
    box.style.cssText = `position:relative;width:${size}px;height:${size}px`;
    document.body.style.margin = '0';
    document.body.append(box);
    viewer = createViewer(box, { api: new Api(''), forceMode: mode, panel: true });
  },

  show(source: string, params: number[]): void {
    viewer!.show({ modelId: null, version: null, source, params });
  },

  setParams(params: number[]): void {
    viewer!.setParams(params);
  },

  setOverride(mode: Mode | null): void {
    viewer!.setOverride(mode);
  },

  setCamera(c: CameraView): void {
    viewer!.setCamera(c);
  },

  setSection(plane: SectionPlane | null): void {
    viewer!.setSection(plane);
  },

  camera(): CameraView {
    return viewer!.getCamera();
  },

  /** The viewer root's data attributes (mode, state, displays, lastDisplayMs, session). */
  state(): Record<string, string> {
    const root = box!.querySelector<HTMLElement>('[data-testid=viewer]')!;
    return { ...root.dataset } as Record<string, string>;
  },

  /** The badge's words (title, reason) and its tooltip. */
  badge(): { text: string; detail: string; mode: string } {
    const b = box!.querySelector<HTMLElement>('[data-testid=mode-badge]')!;
    return { text: b.textContent ?? '', detail: b.title, mode: b.dataset.mode ?? '' };
  },

  /** Hides the viewer's controls (badge, tools, panel) for a screenshot of the picture alone. */
  hideChrome(hide: boolean): void {
    for (const el of box!.querySelectorAll<HTMLElement>('.frep-badge, .frep-tools, .frep-section, .frep-measure-panel, .frep-status, .frep-probe'))
      el.style.visibility = hide ? 'hidden' : '';
  },

  /** The silhouette of a PNG screenshot (base64) of the viewer. */
  async pngMask(png: string, tol: number): Promise<{ width: number; height: number; mask: number[] }> {
    const bytes = Uint8Array.from(atob(png), (c) => c.charCodeAt(0));
    const img = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
    const c = document.createElement('canvas');
    c.width = img.width;
    c.height = img.height;
    const g = c.getContext('2d', { willReadFrequently: true })!;
    g.drawImage(img, 0, 0);
    return { width: img.width, height: img.height, mask: silhouette(g.getImageData(0, 0, img.width, img.height).data, img.width, img.height, tol) };
  },

  /** The displayed picture's size in device pixels and its silhouette, read from the mode's canvas. */
  displayMask(tol: number): { width: number; height: number; mask: number[] } | null {
    const root = box!.querySelector<HTMLElement>('[data-testid=viewer]')!;
    const mode = root.dataset.mode;
    const layers = [...root.querySelectorAll<HTMLElement>('.frep-layer[data-mode]')].filter((l) => l.dataset.mode === mode && l.style.visibility !== 'hidden');
    const canvas = layers[layers.length - 1]?.querySelector('canvas');
    if (!canvas || !canvas.width) return null;
    const g = gradientCanvas(canvas.width, canvas.height);
    g.drawImage(canvas, 0, 0);
    const data = g.getImageData(0, 0, canvas.width, canvas.height).data;
    return { width: canvas.width, height: canvas.height, mask: silhouette(data, canvas.width, canvas.height, tol) };
  },

  /**
   * The server's reference render (PNG) of `source` at the viewer's camera
   * and a size (cut by `section` when given), as a silhouette.
   */
  async referenceMask(source: string, params: number[], width: number, height: number, tol: number, section?: SectionPlane | null): Promise<number[]> {
    const api = new Api('');
    const ref = await api.requestArtefact({
      model: { from: 'source', source },
      params,
      spec: { kind: 'image', camera: viewer!.getCamera(), width, height, format: 'png', quality: 90, ...(section ? { section } : {}) },
    });
    const blob = await api.fetchArtefact(ref);
    const img = await createImageBitmap(blob);
    const g = gradientCanvas(img.width, img.height);
    g.drawImage(img, 0, 0);
    return silhouette(g.getImageData(0, 0, img.width, img.height).data, img.width, img.height, tol);
  },

  /** The client's report as measured here. */
  async report(): Promise<unknown> {
    return measureClient();
  },
};

(window as unknown as { frepModes: typeof harness }).frepModes = harness;
document.title = 'frep modes harness ready';
