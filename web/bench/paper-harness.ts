/**
 * The paper bench's in-page harness: the studio bench's viewer harness
 * (bench-harness.ts: `window.frepBench`, the real adaptive viewer with a
 * forced mode or auto) plus what the paper experiment adds
 * (`window.paperBench`):
 *
 * - `baseline`: the seed paper's own technique, uniform marching cubes in
 *   the browser at a fixed low resolution: the WebAssembly kernel's `mc`
 *   method (frep-mesh's uniform grid, no pruning) in the kernel worker,
 *   drawn once with three.js on the viewer's stage (paper-baseline.ts,
 *   loaded on demand); timed from the call to the frame painted (two
 *   animation frames after the draw), the code's loading included.
 * - `orbitBaseline`: the baseline's mesh turned a step per animation frame;
 *   the median gap between frames is its time per frame.
 * - `pixels`: a screenshot (PNG, from Playwright) decoded and checked not
 *   to be blank: the share of pixels that differ from the corner pixel
 *   (the background) and the spread of luminance.
 */
import './bench-harness';

const paper = {
  /** The baseline (paper-baseline.ts), timed from this call. */
  async baseline(size: number, source: string, params: number[], depth: number): Promise<{ ms: number; meshMs: number; triangles: number }> {
    const t0 = performance.now();
    const b = await import('./paper-baseline');
    return b.baseline(t0, size, source, params, depth);
  },

  /** The baseline's orbit (paper-baseline.ts). */
  async orbitBaseline(ms: number): Promise<{ frameMs: number; meanMs: number; frames: number }> {
    const b = await import('./paper-baseline');
    return b.orbitBaseline(ms);
  },

  /** Decodes a PNG (base64) and says how much of it is not background. */
  async pixels(b64: string): Promise<{ coverage: number; lumaStd: number }> {
    const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
    const bmp = await createImageBitmap(new Blob([bytes], { type: 'image/png' }));
    const c = document.createElement('canvas');
    c.width = bmp.width;
    c.height = bmp.height;
    const g = c.getContext('2d')!;
    g.drawImage(bmp, 0, 0);
    const d = g.getImageData(0, 0, c.width, c.height).data;
    const [r0, g0, b0] = [d[0]!, d[1]!, d[2]!];
    let diff = 0;
    let sum = 0;
    let sum2 = 0;
    const n = d.length / 4;
    for (let i = 0; i < d.length; i += 4) {
      const r = d[i]!;
      const gg = d[i + 1]!;
      const b = d[i + 2]!;
      if (Math.abs(r - r0) + Math.abs(gg - g0) + Math.abs(b - b0) > 24) diff++;
      const y = 0.2126 * r + 0.7152 * gg + 0.0722 * b;
      sum += y;
      sum2 += y * y;
    }
    const mean = sum / n;
    return { coverage: diff / n, lumaStd: Math.sqrt(Math.max(0, sum2 / n - mean * mean)) };
  },
};

(window as unknown as { paperBench: typeof paper }).paperBench = paper;
