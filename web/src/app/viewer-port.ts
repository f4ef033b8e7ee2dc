/**
 * The studio's side of the viewer: the interface it drives, and how it
 * gets one.
 *
 * The adaptive viewer lives in `src/viewer` (another part of the studio,
 * choosing among the delivery modes); it is loaded when present through
 * `import.meta.glob`, so the studio builds and works without it. Until it
 * is there, or if it fails to start, {@link StillViewer} shows server still
 * images (mode 1 over plain HTTP: `POST /api/artefacts` with an image
 * spec, then the image's URL), orbiting by drag and zooming by wheel.
 */
import type { Api } from '../api/client';
import { describeError } from '../api/errors';
import type { ArtefactRequest, CameraView, CompileSummary, ModelRef } from '../wire';
import { h } from './dom';

/** What the viewer is asked to show. */
export interface ShowRequest {
  /** The saved model, when the source is a stored version's. */
  modelId: string | null;
  /** Its version (null: latest or unsaved). */
  version: number | null;
  /** The source to show (the editor's text). */
  source: string;
  /** Parameter values `a[1..]`. */
  params: number[];
  /** The compile summary when the studio has it (spares the viewer a compile). */
  summary?: CompileSummary | null;
}

/** The viewer as the studio drives it. */
export interface StudioViewer {
  show(req: ShowRequest): void;
  setParams(params: number[]): void;
  readonly camera: CameraView;
  setCamera(camera: CameraView): void;
  onCameraChange(cb: (camera: CameraView) => void): () => void;
  /** Progress of an artefact the session computes (0..1), when known. */
  onProgress?(cb: (key: string, fraction: number) => void): () => void;
  /** Resolves at the first display (of any model). */
  firstDisplayed?(): Promise<void>;
  dispose?(): void;
}

/** The default camera (frep-wire's `CameraView::default`). */
export const DEFAULT_CAMERA: CameraView = { yaw: 30, pitch: 20, fov: 30, zoom: 1, pan: [0, 0, 0] };

type ViewerModule = { createViewer?: (container: HTMLElement, opts: Record<string, unknown>) => unknown };
const viewerModules = import.meta.glob<ViewerModule>('../viewer/index.ts');

function isViewer(v: unknown): v is StudioViewer {
  const o = v as Record<string, unknown> | null;
  return !!o && typeof o.show === 'function' && typeof o.setParams === 'function' && typeof o.setCamera === 'function';
}

/** Mounts the adaptive viewer if the build has it, else the still-image viewer. */
export async function mountViewer(container: HTMLElement, api: Api, camera: CameraView): Promise<StudioViewer> {
  const load = viewerModules['../viewer/index.ts'];
  if (load) {
    try {
      const mod = await load();
      const v = mod.createViewer?.(container, { api, camera });
      if (isViewer(v)) return v;
      console.warn('src/viewer does not export a usable createViewer; using server stills');
    } catch (e) {
      console.warn('the viewer failed to start; using server stills', e);
    }
  }
  return new StillViewer(container, api, camera);
}

/** Mode 1 over HTTP: a server still per camera, parameters and source. */
export class StillViewer implements StudioViewer {
  private cam: CameraView;
  private req: ShowRequest | null = null;
  private readonly img: HTMLImageElement;
  private readonly status: HTMLElement;
  private readonly listeners = new Set<(c: CameraView) => void>();
  private seq = 0;
  private timer: ReturnType<typeof setTimeout> | null = null;

  constructor(
    private readonly root: HTMLElement,
    private readonly api: Api,
    camera: CameraView,
  ) {
    this.cam = camera;
    this.img = h('img', { class: 'still-image', alt: 'model view', draggable: false });
    this.status = h('div', { class: 'viewer-status', 'data-testid': 'viewer-status' });
    const badge = h('div', { class: 'mode-badge', title: 'Server still images (the adaptive viewer is not loaded)', text: 'server still' });
    root.append(h('div', { class: 'still-viewer' }, this.img, badge, this.status));
    this.bindPointer();
  }

  get camera(): CameraView {
    return this.cam;
  }

  show(req: ShowRequest): void {
    this.req = req;
    this.schedule(0);
  }

  setParams(params: number[]): void {
    if (!this.req) return;
    this.req = { ...this.req, params };
    this.schedule(120);
  }

  setCamera(camera: CameraView): void {
    this.cam = camera;
    this.schedule(0);
  }

  onCameraChange(cb: (c: CameraView) => void): () => void {
    this.listeners.add(cb);
    return () => this.listeners.delete(cb);
  }

  dispose(): void {
    this.root.replaceChildren();
  }

  private schedule(ms: number): void {
    if (this.timer) clearTimeout(this.timer);
    this.timer = setTimeout(() => void this.render(), ms);
  }

  private async render(): Promise<void> {
    const req = this.req;
    if (!req) return;
    const seq = ++this.seq;
    const rect = this.root.getBoundingClientRect();
    const dpr = Math.min(2, window.devicePixelRatio || 1);
    const side = (v: number) => Math.max(64, Math.min(1024, Math.round((v || 256) * dpr)));
    const model: ModelRef =
      req.modelId && req.version !== null
        ? { from: 'version', modelId: req.modelId, version: req.version }
        : { from: 'source', source: req.source };
    const body: ArtefactRequest = {
      model,
      params: req.params,
      spec: { kind: 'image', camera: this.cam, width: side(rect.width), height: side(rect.height), format: 'jpeg', quality: 80 },
    };
    this.status.textContent = 'rendering…';
    try {
      const ref = await this.api.requestArtefact(body);
      if (seq !== this.seq) return;
      const url = this.api.url(ref.url);
      await new Promise<void>((ok, fail) => {
        const probe = new Image();
        probe.onload = () => ok();
        probe.onerror = () => fail(new Error('the image did not load'));
        probe.src = url;
      });
      if (seq !== this.seq) return;
      this.img.src = url;
      this.status.textContent = '';
    } catch (e) {
      if (seq === this.seq) this.status.textContent = describeError(e);
    }
  }

  private bindPointer(): void {
    let drag: { x: number; y: number; cam: CameraView } | null = null;
    const el = this.img;
    el.addEventListener('pointerdown', (e) => {
      drag = { x: e.clientX, y: e.clientY, cam: this.cam };
      el.setPointerCapture(e.pointerId);
    });
    el.addEventListener('pointermove', (e) => {
      if (!drag) return;
      const yaw = drag.cam.yaw - (e.clientX - drag.x) * 0.5;
      const pitch = Math.max(-89, Math.min(89, drag.cam.pitch + (e.clientY - drag.y) * 0.5));
      this.cam = { ...drag.cam, yaw, pitch };
      this.emit();
    });
    el.addEventListener('pointerup', () => {
      if (drag) this.schedule(0);
      drag = null;
    });
    el.addEventListener(
      'wheel',
      (e) => {
        e.preventDefault();
        const zoom = Math.max(0.1, Math.min(20, this.cam.zoom * Math.exp(-e.deltaY * 0.001)));
        this.cam = { ...this.cam, zoom };
        this.emit();
        this.schedule(150);
      },
      { passive: false },
    );
  }

  private emit(): void {
    for (const cb of this.listeners) cb(this.cam);
  }
}
