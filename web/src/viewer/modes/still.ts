/**
 * Mode 1, the server's still image: a still is requested over HTTP at the
 * viewport's size in device pixels for the current camera (content
 * addressed, so a repeated view is a cache hit); while the user orbits, the
 * camera goes to the session and the server streams frames (lower
 * resolution while moving), shown latest-only and acknowledged. Without a
 * session, moving frames are HTTP stills at the moving scale, one at a
 * time. When the camera stops, a full-resolution HTTP still replaces them
 * (streamed frames are not shown at rest: they carry no model identity, so
 * a late one could belong to the previous edit).
 * The previous picture stays on screen until the next one is decoded.
 * A section plane goes with every request and camera message; a new plane
 * asks for a new still at once (superseding the one under way).
 */
import type { CameraView, ImageEncoding, Mode } from '../../wire';
import { frameMime } from '../../session/binary';
import { LatestFrames } from '../../session/latest';
import type { ReceivedFrame } from '../../session/session';
import { sameCamera } from '../camera';
import { sameSection, sectionField } from '../section';
import type { ModeContext, ModeModel, ModeModule, ModeView, SectionPlane } from '../types';
import { decodeImage, fetchArtefact, isAbort } from './artefact';

/** Limits of a still (device pixels). */
const MAX_SIDE = 2048;
/** Parameters unchanged this long are at rest: the full still follows (ms). */
const PARAMS_REST_MS = 200;

type Drawable = ImageBitmap | HTMLImageElement;

class StillView implements ModeView {
  readonly mode: Mode = 'still';
  private ctx!: ModeContext;
  private canvas!: HTMLCanvasElement;
  private model: ModeModel | null = null;
  private frames!: LatestFrames<ReceivedFrame>;
  private offFrame: (() => void) | null = null;
  private stillAbort: AbortController | null = null;
  private movingBusy = false;
  private movingWanted = false;
  private stillTimer: ReturnType<typeof setTimeout> | null = null;
  private shownCamera: CameraView | null = null;
  /** Whether the picture shown is a reduced (moving) one. */
  private shownReduced = false;
  /** The section plane now, and the one the picture shown was cut by. */
  private section: SectionPlane | null = null;
  private shownSection: SectionPlane | null = null;

  async mount(ctx: ModeContext): Promise<void> {
    this.ctx = ctx;
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'frep-mode-canvas';
    this.canvas.dataset.mode = 'still';
    ctx.container.append(this.canvas);
    this.frames = new LatestFrames<ReceivedFrame>(
      (f) => this.drawFrame(f),
      (f) => {
        // Unknown asker (a frame the server sent on its own): from its arrival.
        const latency = performance.now() - (f.askedAt ?? f.arrivedAt);
        this.ctx.session?.frameAck(f.header.seq, latency);
        this.ctx.frame();
      },
      // A frame not shown (superseded, or arriving at rest) is answered at
      // once: the server counts frames in flight until the client answers.
      (f) => this.ctx.session?.frameAck(f.header.seq, performance.now() - f.arrivedAt),
    );
    if (ctx.session) this.offFrame = ctx.session.on('frame', (f) => this.frames.push(f));
  }

  async show(model: ModeModel): Promise<void> {
    const prev = this.model;
    this.model = model;
    this.frames.reset();
    // New parameter values of the model shown (a slider being dragged):
    // a reduced still first, as while orbiting, and the full one once the
    // values rest. The engine learns only from full-size displays.
    const dragging = prev !== null && this.shownCamera !== null && prev.show.source === model.show.source && !sameValues(prev.show.params, model.show.params);
    let bytes: number | null = null;
    for (;;) {
      const section = this.section;
      bytes = await this.fetchStill(this.ctx.camera(), dragging, model.signal);
      // A new plane while the first picture came: the first display is of the new one.
      if (bytes !== null || model.signal.aborted || this.model !== model || sameSection(section, this.section)) break;
    }
    if (bytes === null) return;
    if (!dragging) {
      this.ctx.displayed(bytes);
      return;
    }
    if (this.stillTimer) clearTimeout(this.stillTimer);
    this.stillTimer = setTimeout(() => {
      this.stillTimer = null;
      if (this.model === model) this.refreshStill();
    }, PARAMS_REST_MS);
  }

  setCamera(c: CameraView): void {
    if (!this.model) return;
    const s = this.ctx.session;
    const moving = this.ctx.moving();
    const size = this.ctx.size();
    if (s && s.state === 'open') {
      s.camera(c, moving, Math.round(size.width * size.pixelRatio), Math.round(size.height * size.pixelRatio), sectionField(this.section).section);
    } else if (moving) {
      this.movingWanted = true;
      void this.pumpMoving();
    }
    // The still of a resting camera comes over HTTP (cached by content), after a short calm.
    if (this.stillTimer) clearTimeout(this.stillTimer);
    this.stillTimer = setTimeout(() => {
      this.stillTimer = null;
      if (!this.ctx.moving()) this.refreshStill();
    }, moving ? 250 : 30);
  }

  setParams(): void {}

  setSection(s: SectionPlane | null): void {
    if (sameSection(s, this.section)) return;
    this.section = s;
    if (!this.model) return;
    // Frames streamed from now on are cut too; the still of the new cut at once.
    const sess = this.ctx.session;
    const size = this.ctx.size();
    if (sess && sess.state === 'open')
      sess.camera(this.ctx.camera(), this.ctx.moving(), Math.round(size.width * size.pixelRatio), Math.round(size.height * size.pixelRatio), sectionField(s).section);
    this.refreshStill();
  }

  resize(): void {
    if (this.model) this.refreshStill();
  }

  dispose(): void {
    this.offFrame?.();
    this.stillAbort?.abort();
    if (this.stillTimer) clearTimeout(this.stillTimer);
    this.canvas.remove();
  }

  private refreshStill(): void {
    if (!this.model) return;
    const cam = this.ctx.camera();
    if (this.shownCamera && !this.shownReduced && sameCamera(cam, this.shownCamera) && sameSection(this.section, this.shownSection) && !this.sizeChanged())
      return;
    this.stillAbort?.abort();
    const ac = new AbortController();
    this.stillAbort = ac;
    const both = AbortSignal.any ? AbortSignal.any([ac.signal, this.model.signal]) : ac.signal;
    void this.fetchStill(cam, false, both).catch(() => {});
  }

  private sizeChanged(): boolean {
    const { width, height, pixelRatio } = this.ctx.size();
    return this.canvas.width !== this.pixels(width, pixelRatio, 1) || this.canvas.height !== this.pixels(height, pixelRatio, 1);
  }

  private async pumpMoving(): Promise<void> {
    if (this.movingBusy) return;
    this.movingBusy = true;
    try {
      while (this.movingWanted && this.model) {
        this.movingWanted = false;
        await this.fetchStill(this.ctx.camera(), true, this.model.signal).catch(() => null);
      }
    } finally {
      this.movingBusy = false;
    }
  }

  private pixels(css: number, ratio: number, scale: number): number {
    return Math.max(16, Math.min(MAX_SIDE, Math.round((css * ratio) / scale)));
  }

  /** Fetches and draws one still; resolves with its bytes (null: superseded). */
  private async fetchStill(camera: CameraView, moving: boolean, signal: AbortSignal): Promise<number | null> {
    const model = this.model;
    if (!model) return null;
    const st = model.settings;
    const { width, height, pixelRatio } = this.ctx.size();
    // The decision's pixel budget (width × height) caps the still; moving frames are smaller again.
    const budget = st && st.width > 0 && st.height > 0 ? st.width * st.height : Infinity;
    const fit = Math.max(1, Math.sqrt((width * pixelRatio * height * pixelRatio) / budget));
    const scale = fit * (moving ? Math.max(1, st?.movingScale ?? 2) : 1);
    const format: ImageEncoding = st?.format ?? 'jpeg';
    const quality = moving ? (st?.movingQuality ?? 50) : (st?.quality ?? 85);
    const section = this.section;
    try {
      const got = await fetchArtefact(
        this.ctx.api,
        model.show,
        { kind: 'image', camera, width: this.pixels(width, pixelRatio, scale), height: this.pixels(height, pixelRatio, scale), format, quality, ...sectionField(section) },
        signal,
        this.ctx.progress,
        (k) => this.ctx.session?.cancel(k),
      );
      const img = await decodeImage(got.blob);
      // (A picture of a plane since replaced is not shown: its successor is under way.)
      if (signal.aborted || this.model !== model || !sameSection(section, this.section)) return null;
      this.draw(img, camera, moving, section);
      this.ctx.frame();
      return got.bytes;
    } catch (e) {
      if (isAbort(e) || signal.aborted) return null;
      throw e;
    }
  }

  private async drawFrame(f: ReceivedFrame): Promise<boolean> {
    // Streamed frames are for orbiting only: at rest the HTTP still is shown.
    // (Frames carry no model or parameters, so a late one could be of the
    // last edit; the still of the camera at rest is content-addressed.)
    if (!this.ctx.moving()) return false;
    const blob = new Blob([f.payload as BlobPart], { type: frameMime(f.header.format) });
    const img = await decodeImage(blob);
    this.draw(img, f.header.camera, true, this.section);
    return true;
  }

  private draw(img: Drawable, camera: CameraView, reduced: boolean, section: SectionPlane | null): void {
    const { width, height, pixelRatio } = this.ctx.size();
    const w = this.pixels(width, pixelRatio, 1);
    const h = this.pixels(height, pixelRatio, 1);
    if (this.canvas.width !== w || this.canvas.height !== h) {
      this.canvas.width = w;
      this.canvas.height = h;
    }
    const g = this.canvas.getContext('2d');
    if (!g) return;
    g.imageSmoothingEnabled = true;
    g.clearRect(0, 0, w, h);
    g.drawImage(img, 0, 0, w, h);
    if ('close' in img) img.close();
    this.shownCamera = camera;
    this.shownReduced = reduced;
    this.shownSection = section;
    this.canvas.dataset.section = section ? 'on' : 'off';
    // Whether the picture is a reduced one (tests and the bench read it).
    this.canvas.dataset.reduced = reduced ? '1' : '0';
  }
}

function sameValues(a: readonly number[], b: readonly number[]): boolean {
  return a.length === b.length && a.every((v, i) => v === b[i]);
}

/** Mode 1. */
export const modes: readonly Mode[] = ['still'];

/** Creates the still-image view. */
export function create(): ModeView {
  return new StillView();
}

const _check: ModeModule = { modes, create };
void _check;
