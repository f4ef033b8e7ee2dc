/**
 * The adaptive viewer: one camera, one model, the mode the server decides
 * (or the user forces), and the measurements that feed the decision.
 *
 * Show requests are versioned: each gets its own AbortSignal, and a newer
 * one aborts the older (superseded work is cancelled). The displayed
 * picture belongs to the mode layer on top; a new mode is mounted beneath
 * it and only replaces it once its first display is ready, so the last
 * good display stays until the next one is there. A mode that is missing
 * or fails falls back (client modes → server mesh → still) and the badge
 * says so. The camera lives here, never in a mode: switching mode or
 * editing the model never moves it.
 */
import type { Api } from '../api/client';
import { glFacts, measureClient } from '../measure/capabilities';
import { runWasmBench } from '../measure/wasm-hook';
import { FrameRateWindow } from '../measure/framerate';
import { Session, sessionUrl } from '../session/session';
import type { CameraView, CompileSummary, Decision, Mode } from '../wire';
import { type StandardView, fitView, rayAt, cameraFrame, sameCamera, standardView } from './camera';
import { ViewerChrome } from './chrome';
import { bindControls } from './controls';
import { DimensionsOverlay } from './dimensions';
import { createModeView, fallbackMode, preloadMode } from './mode-registry';
import { MeasurePanel } from './panel';
import { probeHooks, probeText } from './probe';
import { DEFAULT_CAMERA, SCENE } from './scene';
import { injectStyle } from './style';
import type { ModeContext, ModeModel, ModeView, ModelShow, SectionPlane, Viewer, ViewerOptions, ViewSize } from './types';

type Box = [number, number, number, number, number, number];

/** A mounted mode with its layer. */
interface Layer {
  view: ModeView;
  el: HTMLElement;
}

/** Re-measure the client this often when idle (ms). */
const REMEASURE_MS = 60_000;
/** Report the frame rate this often while interacting (ms). */
const FPS_REPORT_MS = 2000;
/** The longest the hello waits for the first display (ms). */
const HELLO_WAIT_MS = 1500;

class AdaptiveViewer implements Viewer {
  private cam: CameraView;
  private readonly root: HTMLElement;
  private readonly layers: HTMLElement;
  private readonly input: HTMLElement;
  private readonly chrome: ViewerChrome;
  private readonly panel: MeasurePanel | null;
  private readonly dims = new DimensionsOverlay();
  private readonly session: Session | null;
  private readonly controls: { dispose(): void; moving(): boolean };
  private readonly camListeners = new Set<(c: CameraView) => void>();
  private readonly progressListeners = new Set<(k: string, f: number) => void>();
  private readonly fps = new FrameRateWindow();
  private readonly timers: ReturnType<typeof setInterval>[] = [];
  private readonly resizeObs: ResizeObserver | null;
  private current: Layer | null = null;
  private pending: Layer | null = null;
  private wanted: Mode;
  private override: Mode | null;
  private note: string | null = null;
  private model: ModelShow | null = null;
  private summary: CompileSummary | null = null;
  /** The source `summary` belongs to. */
  private summarySource: string | null = null;
  private request: AbortController | null = null;
  /** The mode the request in flight is showing (null when none is). */
  private showing: Mode | null = null;
  private requestStart = 0;
  private displayedOnce: Promise<void> = Promise.resolve();
  private resolveDisplayed: (() => void) | null = null;
  private resolveFirst: (() => void) | null = null;
  /** Resolved at the viewer's first display. */
  private readonly firstDisplay = new Promise<void>((ok) => (this.resolveFirst = ok));
  private section: SectionPlane | null = null;
  private showDims = false;
  private probing = false;
  private webgl = true;
  private lastInteract = 0;
  private lastFpsReport = 0;
  private displays = 0;

  constructor(container: HTMLElement, private readonly opts: ViewerOptions) {
    this.cam = opts.camera ?? DEFAULT_CAMERA;
    this.override = opts.forceMode ?? null;
    this.wanted = this.override ?? 'still';
    this.root = document.createElement('div');
    this.root.className = 'frep-viewer';
    this.root.dataset.testid = 'viewer';
    this.root.style.background = injectStyle();
    this.layers = document.createElement('div');
    this.layers.className = 'frep-layer';
    this.input = document.createElement('div');
    this.input.className = 'frep-input';
    this.chrome = new ViewerChrome({
      override: (m) => this.setOverride(m),
      view: (w: StandardView) => this.setCamera(standardView(this.cam, w)),
      fit: () => this.setCamera(fitView(this.cam)),
      projection: (p) => this.setCamera({ ...this.cam, fov: p ? (DEFAULT_CAMERA.fov ?? 30) : null }),
      section: (axis, t, flip) => this.setSection(axis ? this.axisSection(axis, t, flip) : null),
      dimensions: (on) => {
        this.showDims = on;
        this.dims.element.style.display = on ? '' : 'none';
        this.drawDims();
      },
      probe: (on) => {
        this.probing = on;
        if (!on) this.chrome.probeOut.textContent = '';
      },
    });
    this.dims.element.style.display = 'none';
    this.panel = opts.panel === false ? null : new MeasurePanel();
    this.root.append(this.layers, this.dims.element, this.input, this.chrome.badge, this.chrome.tools, this.chrome.status, this.chrome.probeOut);
    if (this.panel) this.root.append(this.panel.element);
    container.append(this.root);
    this.controls = bindControls(this.input, {
      camera: () => this.cam,
      bounds: () => this.bounds(),
      size: () => this.size(),
      setCamera: (c) => this.moveCamera(c),
      rest: () => this.rest(),
      click: (x, y) => void this.probeAt(x, y),
    });
    this.resizeObs = typeof ResizeObserver !== 'undefined' ? new ResizeObserver(() => this.resized()) : null;
    this.resizeObs?.observe(this.root);
    // WebGL's presence steers fallbacks.
    this.webgl = glFacts().webgl2;
    this.session = opts.session === false ? null : this.connect();
    this.timers.push(setInterval(() => this.tick(), 1000));
    this.chrome.setProjection(this.cam.fov !== null);
    this.updateBadge();
  }

  get camera(): CameraView {
    return this.cam;
  }

  get mode(): Mode | null {
    return this.current?.view.mode ?? null;
  }

  getCamera(): CameraView {
    return this.cam;
  }

  show(model: ModelShow): void {
    const prev = this.model;
    this.model = { ...model };
    if (!prev || prev.source !== model.source || prev.modelId !== model.modelId || prev.version !== model.version || !sameParams(prev.params, model.params))
      this.session?.open(model.modelId ?? null, model.version ?? null, model.source, model.params);
    void this.refresh();
  }

  setParams(params: number[]): void {
    if (!this.model) return;
    this.show({ ...this.model, params, summary: null });
  }

  setCamera(c: CameraView): void {
    this.moveCamera(c);
    this.rest();
  }

  onCameraChange(cb: (c: CameraView) => void): () => void {
    this.camListeners.add(cb);
    return () => this.camListeners.delete(cb);
  }

  onProgress(cb: (key: string, fraction: number) => void): () => void {
    this.progressListeners.add(cb);
    return () => this.progressListeners.delete(cb);
  }

  setSection(plane: SectionPlane | null): void {
    this.section = plane;
    this.current?.view.setSection(plane);
    this.pending?.view.setSection(plane);
    this.updateBadge();
  }

  setOverride(mode: Mode | null): void {
    this.override = mode;
    this.session?.override(mode);
    const next = mode ?? this.session?.decision?.mode ?? this.wanted;
    this.updateBadge();
    if (next !== this.current?.view.mode) {
      this.wanted = next;
      void this.refresh();
    }
  }

  whenDisplayed(): Promise<void> {
    return this.displayedOnce;
  }

  firstDisplayed(): Promise<void> {
    return this.firstDisplay;
  }

  dispose(): void {
    this.request?.abort();
    this.timers.forEach((t) => clearInterval(t));
    this.resizeObs?.disconnect();
    this.controls.dispose();
    this.session?.dispose();
    this.pending?.view.dispose();
    this.current?.view.dispose();
    this.root.remove();
  }

  // ---- session and measurements ----

  private connect(): Session {
    // The client is measured once the first display is up (or after
    // HELLO_WAIT_MS). The CPU and GPU benchmarks hold the main thread, and
    // on software WebGL they take the cores the first display needs. Auto
    // shows server stills until the decision, so nothing waits on it.
    // The WASM benchmark (which loads the kernel) follows as a report.
    const report = async () => {
      await Promise.race([this.firstDisplay, new Promise((ok) => setTimeout(ok, HELLO_WAIT_MS))]);
      const r = await measureClient({ wasm: false });
      void runWasmBench().then((meps) => {
        if (meps !== null && s.state === 'open') s.report({ ...r, wasmBenchMeps: meps });
      });
      return r;
    };
    const s = new Session({ url: this.opts.sessionUrl ?? sessionUrl(), report });
    s.on('decision', (d) => this.decided(d));
    s.on('progress', (k, f) => this.progress(k, f));
    s.on('state', (st) => (this.root.dataset.session = st));
    s.on('error', (m) => console.warn('session:', m));
    // A mode forced at creation is the user's choice: the server must know it.
    if (this.override) s.override(this.override);
    s.connect();
    this.timers.push(
      setInterval(() => {
        if (performance.now() - this.lastInteract > 10_000 && s.state === 'open') void measureClient().then((r) => s.report(r));
      }, REMEASURE_MS),
    );
    return s;
  }

  private decided(d: Decision): void {
    this.root.dataset.decision = d.mode;
    const next = this.override ?? d.mode;
    this.updateBadge();
    // A first display already under way in the decided mode goes on: a
    // restart would make it wait for the decision and a second request.
    if (next !== this.wanted || (next !== this.current?.view.mode && this.showing !== next)) {
      this.wanted = next;
      void this.refresh();
    }
  }

  private tick(): void {
    const rate = this.fps.rate();
    const interacting = performance.now() - this.lastInteract < FPS_REPORT_MS;
    const d = this.session?.decision ?? null;
    this.panel?.push({
      bandwidthBps: this.session?.bandwidthBps() ?? d?.network.bandwidthBps ?? null,
      rttMs: d?.network.rttMs ?? null,
      fps: interacting && rate ? rate.fps : null,
    });
    const now = performance.now();
    if (interacting && rate && this.current && now - this.lastFpsReport >= FPS_REPORT_MS) {
      this.lastFpsReport = now;
      this.session?.frameRate(this.current.view.mode, rate.fps, rate.frameMs);
    }
  }

  private progress(key: string, f: number): void {
    for (const cb of this.progressListeners) cb(key, f);
  }

  // ---- camera ----

  private moveCamera(c: CameraView): void {
    if (sameCamera(c, this.cam)) return;
    this.cam = c;
    this.lastInteract = performance.now();
    this.current?.view.setCamera(c);
    this.pending?.view.setCamera(c);
    this.chrome.setProjection(c.fov !== null);
    this.drawDims();
    for (const cb of this.camListeners) cb(c);
  }

  private rest(): void {
    // The resting camera: modes that draw cheaper frames while moving draw the full one.
    this.current?.view.setCamera(this.cam);
  }

  private bounds(): Box {
    const b = this.summary?.bounds;
    return b ? (b as Box) : [-1, -1, -1, 1, 1, 1];
  }

  private size(): ViewSize {
    const r = this.root.getBoundingClientRect();
    return { width: Math.max(1, Math.round(r.width)), height: Math.max(1, Math.round(r.height)), pixelRatio: Math.min(2, window.devicePixelRatio || 1) };
  }

  private resized(): void {
    const { width, height } = this.size();
    this.current?.view.resize(width, height);
    this.pending?.view.resize(width, height);
    this.drawDims();
  }

  private drawDims(): void {
    if (!this.showDims || !this.summary) return;
    const { width, height } = this.size();
    this.dims.draw(this.cam, this.bounds(), width, height);
  }

  /**
   * The plane across `axis` at fraction `t` of the box. The half towards
   * the eye is the one cut away, so the cut face looks at the user
   * (`flip` keeps that half instead).
   */
  private axisSection(axis: 'x' | 'y' | 'z', t: number, flip: boolean): SectionPlane {
    const k = axis === 'x' ? 0 : axis === 'y' ? 1 : 2;
    const b = this.bounds();
    const { width, height } = this.size();
    const towardsEye = -cameraFrame(this.cam, b, width, height).forward[k];
    const sign = (towardsEye >= 0 ? 1 : -1) * (flip ? -1 : 1);
    const n: [number, number, number] = [0, 0, 0];
    n[k] = sign;
    const at = b[k] + t * (b[k + 3] - b[k]);
    return { normal: n, offset: sign * at };
  }

  // ---- showing ----

  private async refresh(): Promise<void> {
    if (!this.model) return;
    this.request?.abort();
    const ac = new AbortController();
    this.request = ac;
    this.showing = this.wanted;
    try {
      await this.showModel(this.model, ac);
    } finally {
      if (this.request === ac) this.showing = null;
    }
  }

  /** One request: the summary (compiled when needed), then the wanted mode. */
  private async showModel(model: ModelShow, ac: AbortController): Promise<void> {
    this.requestStart = performance.now();
    if (!this.resolveDisplayed) this.displayedOnce = new Promise((ok) => (this.resolveDisplayed = ok));
    this.root.dataset.state = 'loading';
    // The server frames every artefact with the box detected at the default
    // parameters (it stays put while a slider moves): so does the viewer.
    // A given summary is used when its box cannot depend on parameters.
    let summary = model.summary && model.summary.boundsOrigin !== 'extent' ? model.summary : null;
    if (!summary && this.summary && this.summarySource === model.source) summary = this.summary;
    if (!summary) {
      // The mode's code loads while the server compiles.
      preloadMode(this.wanted);
      try {
        const res = await this.opts.api.compile({ source: model.source, params: [], body: null }, ac.signal);
        if (ac.signal.aborted) return;
        if (!res.ok || !res.summary) {
          this.chrome.status.textContent = res.diagnostics[0]?.message ?? 'the model does not compile';
          this.root.dataset.state = 'error';
          return;
        }
        summary = res.summary;
      } catch (e) {
        if (ac.signal.aborted) return;
        this.chrome.status.textContent = `cannot compile: ${(e as Error).message}`;
        this.root.dataset.state = 'error';
        return;
      }
    }
    this.summary = summary;
    this.summarySource = model.source;
    this.drawDims();
    await this.showIn(this.wanted, model, summary, ac);
  }

  private async showIn(mode: Mode, show: ModelShow, summary: CompileSummary, ac: AbortController): Promise<void> {
    let target: Mode | null = mode;
    const notes: string[] = [];
    while (target && !ac.signal.aborted) {
      try {
        const layer = await this.layerFor(target, ac.signal);
        const model: ModeModel = {
          show,
          summary,
          bounds: summary.bounds as Box,
          settings: this.settingsFor(target),
          signal: ac.signal,
        };
        this.chrome.status.textContent = '';
        await layer.view.show(model);
        if (ac.signal.aborted) return;
        this.promote(layer);
        this.note = notes.length ? notes.join('; ') : null;
        this.finishDisplay();
        return;
      } catch (e) {
        if (ac.signal.aborted) return;
        const next = fallbackMode(target, this.webgl);
        notes.push(`${target} failed here (${(e as Error).message})${next ? `, showing ${next}` : ''}`);
        this.dropPending();
        target = next;
      }
    }
    if (!ac.signal.aborted) {
      this.note = notes.join('; ');
      this.chrome.status.textContent = 'the model could not be shown';
      this.root.dataset.state = 'error';
      this.updateBadge();
    }
  }

  private settingsFor(mode: Mode) {
    const d = this.session?.decision;
    return d && d.mode === mode ? d.settings : null;
  }

  /** The layer showing `mode`: the current one, or a new one beneath it. */
  private async layerFor(mode: Mode, signal: AbortSignal): Promise<Layer> {
    if (this.current?.view.mode === mode) {
      this.dropPending();
      return this.current;
    }
    if (this.pending?.view.mode === mode) return this.pending;
    this.dropPending();
    const view = await createModeView(mode);
    if (!view) throw new Error('not available in this build');
    // A newer request may have come meanwhile: it makes its own layer.
    if (signal.aborted) throw new DOMException('superseded', 'AbortError');
    this.dropPending();
    const el = document.createElement('div');
    el.className = 'frep-layer';
    el.dataset.mode = mode;
    el.style.visibility = 'hidden';
    this.layers.prepend(el);
    const layer = { view, el };
    this.pending = layer;
    try {
      await view.mount(this.context(layer));
    } catch (e) {
      this.dropPending();
      throw e;
    }
    view.setSection(this.section);
    return layer;
  }

  private dropPending(): void {
    if (!this.pending) return;
    this.pending.view.dispose();
    this.pending.el.remove();
    this.pending = null;
  }

  private promote(layer: Layer): void {
    if (this.current === layer) return;
    const old = this.current;
    this.current = layer;
    if (this.pending === layer) this.pending = null;
    layer.el.style.visibility = '';
    this.layers.append(layer.el);
    this.fps.clear();
    if (old) {
      old.view.dispose();
      old.el.remove();
    }
  }

  private finishDisplay(): void {
    this.displays++;
    this.root.dataset.state = 'displayed';
    this.root.dataset.mode = this.current?.view.mode ?? '';
    this.root.dataset.displays = String(this.displays);
    this.updateBadge();
    this.resolveDisplayed?.();
    this.resolveDisplayed = null;
    // Consumers of the first display (the client's benchmarks, the
    // studio's deferred work) hold the main thread: they start once the
    // frame is painted, not when it is merely in the DOM.
    const first = this.resolveFirst;
    this.resolveFirst = null;
    if (first) afterPaint(first);
  }

  private context(layer: Layer): ModeContext {
    return {
      container: layer.el,
      api: this.opts.api,
      apiBase: this.opts.api.url(''),
      session: this.session,
      scene: SCENE,
      camera: () => this.cam,
      size: () => this.size(),
      moving: () => this.controls.moving(),
      decision: () => this.session?.decision ?? null,
      frame: () => {
        if (this.current === layer) this.fps.add(performance.now());
      },
      displayed: (bytes) => {
        const ms = performance.now() - this.requestStart;
        this.root.dataset.lastDisplayMs = ms.toFixed(0);
        this.session?.displayed(layer.view.mode, ms, bytes);
      },
      progress: (k, f) => this.progress(k, f),
      failed: (m) => {
        this.chrome.status.textContent = m;
      },
    };
  }

  private updateBadge(): void {
    this.chrome.setBadge(this.current?.view.mode ?? null, this.session?.decision ?? null, this.note, this.override);
  }

  // ---- probe ----

  private async probeAt(x: number, y: number): Promise<void> {
    if (!this.probing || !this.model || !this.summary) return;
    const model = this.model;
    const hooks = await probeHooks();
    let result = (await this.current?.view.probe?.(x, y)) ?? null;
    if (result && hooks?.probePoint) {
      const v = await hooks.probePoint({ source: model.source, params: model.params, point: result.point }).catch(() => null);
      if (v) result = { ...result, value: v.value, attributes: v.attributes, source: 'wasm' };
    } else if (result) {
      result = { ...result, source: 'the value needs the WASM kernel (src/wasm/probe.ts)' };
    } else if (hooks?.probeRay) {
      const { width, height } = this.size();
      const ray = rayAt(cameraFrame(this.cam, this.bounds(), width, height), x, y);
      const hit = await hooks.probeRay({ source: model.source, params: model.params, bounds: this.bounds(), origin: ray.origin, dir: ray.dir }).catch(() => null);
      result = hit ? { ...hit, source: 'wasm' } : null;
    } else {
      this.chrome.probeOut.textContent = 'probing this mode needs the WASM kernel (src/wasm/probe.ts)';
      return;
    }
    this.chrome.probeOut.textContent = probeText(result);
  }
}

/** Runs `fn` after the next frame is painted (at once where there are no frames). */
function afterPaint(fn: () => void): void {
  if (typeof requestAnimationFrame !== 'function') return fn();
  requestAnimationFrame(() => setTimeout(fn, 0));
}

function sameParams(a: number[], b: number[]): boolean {
  return a.length === b.length && a.every((v, i) => v === b[i]);
}

/** Mounts the viewer in `container`. */
export function createViewer(container: HTMLElement, opts: ViewerOptions | { api: Api; camera?: CameraView }): Viewer {
  return new AdaptiveViewer(container, opts as ViewerOptions);
}
