/**
 * Adaptive resolution of the client-drawn modes (4a, volume): while the
 * user orbits, the render scale follows the measured frame time towards a
 * target frame rate (pixels grow as the square of the scale, so the scale
 * moves by the square root of the time ratio); when still, the view is
 * drawn once at full resolution. The scale reached while moving is kept
 * for the next orbit.
 */

/** Options of {@link ResolutionController}. */
export interface ResolutionOptions {
  /** The frame rate to hold while moving (frames per second). */
  targetFps: number;
  /** The smallest scale (fraction of the full resolution, per side). */
  minScale: number;
}

/** The defaults: 30 fps, down to a quarter of each side. */
export const DEFAULT_RESOLUTION: ResolutionOptions = { targetFps: 30, minScale: 0.25 };

export class ResolutionController {
  private movingScale = 1;

  constructor(private readonly opts: ResolutionOptions = DEFAULT_RESOLUTION) {}

  /** The scale to draw the next frame at. */
  scale(moving: boolean): number {
    return moving ? this.movingScale : 1;
  }

  /**
   * A frame drawn at `scale` took `ms`: adapts the moving scale (still
   * frames tell how long a full frame takes, a moving one starts there).
   */
  record(ms: number, scale: number, moving: boolean): void {
    if (!(ms > 0) || !Number.isFinite(ms)) return;
    const target = 1000 / this.opts.targetFps;
    // The scale that would take the target time, from this frame's cost.
    const fit = scale * Math.sqrt(target / ms);
    if (moving) {
      // Down at once when too slow, up gently when there is room.
      const next = fit < this.movingScale ? fit : Math.min(fit, this.movingScale * 1.15);
      this.movingScale = clamp(next, this.opts.minScale, 1);
    } else if (ms > target) {
      this.movingScale = clamp(Math.min(this.movingScale, fit), this.opts.minScale, 1);
    }
  }
}

function clamp(x: number, lo: number, hi: number): number {
  return Math.max(lo, Math.min(hi, x));
}

/** Frame rate over a sliding window of frame times (for reports). */
export class FrameRate {
  private readonly times: number[] = [];
  constructor(private readonly windowMs = 2000) {}

  /** A frame was displayed at `t` (ms). */
  tick(t: number): void {
    this.times.push(t);
    while (this.times.length > 2 && t - this.times[0]! > this.windowMs) this.times.shift();
  }

  /** Frames per second over the window (0 with fewer than two frames). */
  fps(): number {
    const n = this.times.length;
    if (n < 2) return 0;
    const span = this.times[n - 1]! - this.times[0]!;
    return span > 0 ? ((n - 1) * 1000) / span : 0;
  }
}
