/**
 * Mode 2, the server's view set: one sprite sheet of views around the
 * model (`views` per ring, one ring per elevation) with its index
 * (`viewSetIndex`: ViewSetLayout). The camera picks the nearest view in yaw
 * and pitch, so dragging rotates through the views and the rings at once,
 * with no round trip. Each view frames the box as the camera does at zoom
 * 1 (the bounding sphere fills the shorter side); zoom and pan are applied
 * as a scale and a shift of that view (exact for orthographic views, close
 * for perspective ones). A section plane cuts every view: a new plane asks
 * for the view set of the new cut (superseding the one under way), and the
 * sheet shown stays until that one is decoded.
 */
import type { CameraView, ImageEncoding, Mode, ViewSetLayout } from '../../wire';
import { cameraFrame, wrapDegrees } from '../camera';
import { sameSection, sectionField } from '../section';
import type { ModeContext, ModeModel, ModeModule, ModeView, SectionPlane } from '../types';
import { decodeImage, fetchArtefact, isAbort } from './artefact';

/** The view of a layout nearest to a camera: ring and view index. */
export function nearestView(layout: ViewSetLayout, yaw: number, pitch: number): { ring: number; view: number; index: number } {
  let ring = 0;
  let best = Infinity;
  layout.elevations.forEach((e, i) => {
    const d = Math.abs(e - pitch);
    if (d < best) {
      best = d;
      ring = i;
    }
  });
  const n = Math.max(1, layout.viewsPerRing);
  const step = 360 / n;
  const rel = wrapDegrees(yaw - layout.startYaw);
  const view = ((Math.round(rel / step) % n) + n) % n;
  return { ring, view, index: ring * n + view };
}

/** Where view `index` is on the sheet (pixels). */
export function viewRect(layout: ViewSetLayout, index: number): { x: number; y: number; w: number; h: number } {
  const cols = Math.max(1, layout.columns);
  const [w, h] = layout.viewSize;
  return { x: (index % cols) * w, y: Math.floor(index / cols) * h, w, h };
}

class ViewSetView implements ModeView {
  readonly mode: Mode = 'viewSet';
  private ctx!: ModeContext;
  private canvas!: HTMLCanvasElement;
  private sheet: ImageBitmap | HTMLImageElement | null = null;
  private layout: ViewSetLayout | null = null;
  private bounds: readonly number[] = [-1, -1, -1, 1, 1, 1];
  private raf = 0;
  private model: ModeModel | null = null;
  private section: SectionPlane | null = null;
  /** The request under way (a newer plane aborts it). */
  private request: AbortController | null = null;

  async mount(ctx: ModeContext): Promise<void> {
    this.ctx = ctx;
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'frep-mode-canvas';
    this.canvas.dataset.mode = 'viewSet';
    ctx.container.append(this.canvas);
  }

  async show(model: ModeModel): Promise<void> {
    this.model = model;
    this.request?.abort();
    const ac = new AbortController();
    this.request = ac;
    const signal = AbortSignal.any ? AbortSignal.any([ac.signal, model.signal]) : model.signal;
    const st = model.settings;
    const { width, height, pixelRatio } = this.ctx.size();
    const side = Math.max(64, Math.min(st?.width ?? 512, Math.round(Math.min(width, height) * pixelRatio)));
    const format: ImageEncoding = st?.format ?? 'jpeg';
    const common = {
      views: st?.views ?? 24,
      elevations: st?.elevations?.length ? st.elevations : [0, 20, 45],
      width: side,
      height: side,
      format,
      quality: st?.quality ?? 80,
      fov: this.ctx.camera().fov ?? null,
      ...sectionField(this.section),
    };
    try {
      const [index, sheet] = await Promise.all([
        fetchArtefact(this.ctx.api, model.show, { kind: 'viewSetIndex', ...common }, signal),
        fetchArtefact(this.ctx.api, model.show, { kind: 'viewSet', ...common }, signal, this.ctx.progress, (k) =>
          this.ctx.session?.cancel(k),
        ),
      ]);
      const layout = JSON.parse(await index.blob.text()) as ViewSetLayout;
      const img = await decodeImage(sheet.blob);
      if (signal.aborted) return;
      if (this.sheet && 'close' in this.sheet) this.sheet.close();
      this.sheet = img;
      this.layout = layout;
      this.bounds = model.bounds;
      this.canvas.dataset.section = common.section ? 'on' : 'off';
      this.draw();
      this.ctx.displayed(index.bytes + sheet.bytes);
    } catch (e) {
      if (isAbort(e) || signal.aborted) return;
      throw e;
    }
  }

  setCamera(_c: CameraView): void {
    if (this.raf) return;
    this.raf = requestAnimationFrame(() => {
      this.raf = 0;
      this.draw();
    });
  }

  setParams(): void {}

  setSection(s: SectionPlane | null): void {
    if (sameSection(s, this.section)) return;
    this.section = s;
    const model = this.model;
    if (model && !model.signal.aborted) void this.show(model).catch(() => {});
  }

  resize(): void {
    this.draw();
  }

  dispose(): void {
    this.request?.abort();
    if (this.raf) cancelAnimationFrame(this.raf);
    if (this.sheet && 'close' in this.sheet) this.sheet.close();
    this.canvas.remove();
  }

  private draw(): void {
    const layout = this.layout;
    const sheet = this.sheet;
    if (!layout || !sheet) return;
    const cam = this.ctx.camera();
    const { width, height, pixelRatio } = this.ctx.size();
    const w = Math.max(1, Math.round(width * pixelRatio));
    const h = Math.max(1, Math.round(height * pixelRatio));
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    const g = this.canvas.getContext('2d');
    if (!g) return;
    const pick = nearestView(layout, cam.yaw, cam.pitch);
    const r = viewRect(layout, pick.index);
    // The view's shorter side holds the bounding sphere, as the viewport's does at zoom 1.
    const fit = Math.min(w, h) / Math.min(r.w, r.h);
    const s = fit * cam.zoom;
    const shift = this.panPixels(cam, layout.elevations[pick.ring], layout.startYaw + (360 * pick.view) / Math.max(1, layout.viewsPerRing), w, h);
    const dw = r.w * s;
    const dh = r.h * s;
    g.clearRect(0, 0, w, h);
    g.drawImage(sheet, r.x, r.y, r.w, r.h, 0.5 * (w - dw) - shift[0], 0.5 * (h - dh) + shift[1], dw, dh);
    this.canvas.dataset.view = String(pick.index);
    this.canvas.dataset.yaw = String(layout.startYaw + (360 * pick.view) / Math.max(1, layout.viewsPerRing));
    this.canvas.dataset.pitch = String(layout.elevations[pick.ring]);
    this.ctx.frame();
  }

  /** The pan's shift in device pixels in the shown view's frame. */
  private panPixels(cam: CameraView, pitch: number, yaw: number, w: number, h: number): [number, number] {
    if (!cam.pan.some((v) => v !== 0)) return [0, 0];
    const f = cameraFrame({ ...cam, yaw, pitch }, this.bounds, w, h);
    const perPixel = (f.perspective ? f.distance * f.k : f.k) / (0.5 * Math.min(w, h));
    const dot = (a: number[]) => a[0] * cam.pan[0] + a[1] * cam.pan[1] + a[2] * cam.pan[2];
    return [dot(f.right) / perPixel, dot(f.up) / perPixel];
  }
}

/** Mode 2. */
export const modes: readonly Mode[] = ['viewSet'];

/** Creates the view-set view. */
export function create(): ModeView {
  return new ViewSetView();
}

const _check: ModeModule = { modes, create };
void _check;
