/**
 * The achieved frame rate of the current mode: a sliding window of frame
 * times (the last `windowMs`), reported as frames per second over the
 * window and the median interval between frames. Gaps longer than
 * `idleMs` end a burst (the user stopped interacting), so idle time never
 * counts as slow frames.
 */

/** Frame-rate summary. */
export interface FrameRate {
  /** Frames per second over the window. */
  fps: number;
  /** Median ms between frames. */
  frameMs: number;
  /** Frames in the window. */
  frames: number;
}

/** A sliding window of frame times. */
export class FrameRateWindow {
  private times: number[] = [];

  constructor(
    readonly windowMs = 3000,
    readonly idleMs = 500,
  ) {}

  /** A frame was drawn at `t` ms. */
  add(t: number): void {
    const last = this.times[this.times.length - 1];
    if (last !== undefined && t - last > this.idleMs) this.times = [];
    this.times.push(t);
    const from = t - this.windowMs;
    let drop = 0;
    while (drop < this.times.length && this.times[drop] < from) drop++;
    if (drop) this.times.splice(0, drop);
  }

  /** Forgets everything (mode switch). */
  clear(): void {
    this.times = [];
  }

  /** The rate now, or null with fewer than `minFrames` frames in the window. */
  rate(minFrames = 3): FrameRate | null {
    const n = this.times.length;
    if (n < Math.max(2, minFrames)) return null;
    const gaps: number[] = [];
    for (let i = 1; i < n; i++) gaps.push(this.times[i] - this.times[i - 1]);
    gaps.sort((a, b) => a - b);
    const span = this.times[n - 1] - this.times[0];
    const mid = gaps.length >> 1;
    const frameMs = gaps.length % 2 ? gaps[mid] : 0.5 * (gaps[mid - 1] + gaps[mid]);
    return { fps: span > 0 ? ((n - 1) * 1000) / span : 0, frameMs, frames: n };
  }
}
