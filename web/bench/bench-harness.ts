/**
 * The studio bench's in-page harness: mounts the whole adaptive viewer
 * (createViewer: session, decision, badge, modes) in a fixed-size box on
 * the server's origin, exactly as the studio does, and times two things
 * with the page's own clock:
 *
 * - `open`: from the `show()` call to the first display (of the forced
 *   mode, or of any mode in auto, then also of the server's decision);
 * - `move`: from a `setParams()` call (a slider move) to the next display.
 *
 * A display is the moment the viewer root's `data-displays` counter grows
 * (the viewer sets it when the mode has drawn its first frame); a
 * MutationObserver on the root catches it without polling. Bundled by
 * studio-bench.mjs with Vite and served through page.route.
 */
import { Api } from '../src/api/client';
import { createViewer, type Viewer } from '../src/viewer/index';
import type { Mode } from '../src/wire';

let viewer: Viewer | null = null;
let box: HTMLElement | null = null;

/** What one timed step saw. */
interface Timed {
  /** Milliseconds from the call to the display, page clock. */
  ms: number;
  /** The viewer's own figure (`data-last-display-ms`: its request start to the display). */
  viewerMs: number;
  /** The mode displayed then. */
  mode: string;
  /** The server's decision known then (auto). */
  decision: string;
  /** `performance.now()` at the call: resources after it belong to the step. */
  t0: number;
}

function root(): HTMLElement {
  const r = box?.querySelector<HTMLElement>('[data-testid=viewer]');
  if (!r) throw new Error('viewer not mounted');
  return r;
}

/** Resolves with the time when `ok(dataset)` first holds (checked now and on every attribute change). */
function when(ok: (d: DOMStringMap) => boolean, timeoutMs: number): Promise<number> {
  const r = root();
  return new Promise((resolve, reject) => {
    if (ok(r.dataset)) return resolve(performance.now());
    const obs = new MutationObserver(() => {
      if (!ok(r.dataset)) return;
      const t = performance.now();
      obs.disconnect();
      clearTimeout(timer);
      resolve(t);
    });
    const timer = setTimeout(() => {
      obs.disconnect();
      reject(new Error(`no display within ${timeoutMs} ms (state ${r.dataset.state}, mode ${r.dataset.mode}, status ${statusText()})`));
    }, timeoutMs);
    obs.observe(r, { attributes: true });
  });
}

function statusText(): string {
  return box?.querySelector('.frep-status')?.textContent ?? '';
}

function timed(t0: number, t: number): Timed {
  const d = root().dataset;
  return { ms: t - t0, viewerMs: Number(d.lastDisplayMs ?? NaN), mode: d.mode ?? '', decision: d.decision ?? '', t0 };
}

const harness = {
  /** Mounts the viewer in a `size`² box; `mode` forces a mode (null: auto, the server decides). */
  mount(size: number, mode: Mode | null): void {
    box = document.createElement('div');
    box.style.cssText = `position:relative;width:${size}px;height:${size}px`;
    document.body.style.margin = '0';
    document.body.append(box);
    viewer = createViewer(box, { api: new Api(''), forceMode: mode, panel: false });
  },

  /**
   * Shows a model and times its first display. Forced: the first display of
   * that mode. Auto: the first display of any mode (`first`), then the
   * first of the decided mode (`decided`, null if it never came in time).
   */
  async open(source: string, params: number[], mode: Mode | null, timeoutMs: number): Promise<{ first: Timed; decided: Timed | null }> {
    const shown = (d: DOMStringMap) => d.state === 'displayed' && Number(d.displays ?? 0) > 0;
    const t0 = performance.now();
    const firstP = when((d) => shown(d) && (mode === null || d.mode === mode), timeoutMs);
    viewer!.show({ modelId: null, version: null, source, params });
    const first = timed(t0, await firstP);
    if (mode !== null) return { first, decided: null };
    const left = Math.max(1, timeoutMs - first.ms);
    const t = await when((d) => shown(d) && !!d.decision && d.mode === d.decision, left).catch(() => null);
    return { first, decided: t === null ? null : timed(t0, t) };
  },

  /** A slider move: new parameters, timed to the next display of `mode`. */
  async move(params: number[], mode: Mode, timeoutMs: number): Promise<Timed> {
    const before = Number(root().dataset.displays ?? 0);
    const t0 = performance.now();
    const p = when((d) => d.state === 'displayed' && Number(d.displays ?? 0) > before && d.mode === mode, timeoutMs);
    viewer!.setParams(params);
    return timed(t0, await p);
  },

  /** Resource timings since `t0` (same origin, so every field is filled). */
  resources(t0: number): { name: string; start: number; end: number; bytes: number }[] {
    return performance
      .getEntriesByType('resource')
      .filter((e) => e.startTime >= t0)
      .map((e) => {
        const r = e as PerformanceResourceTiming;
        return { name: r.name, start: r.startTime, end: r.responseEnd, bytes: r.transferSize || r.encodedBodySize };
      });
  },
};

(window as unknown as { frepBench: typeof harness }).frepBench = harness;
document.title = 'frep bench harness ready';
