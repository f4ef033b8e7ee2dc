/**
 * Reconnection delays: exponential backoff with full jitter, capped, reset
 * after a connection that stayed up.
 */

/** Backoff settings (ms). */
export interface BackoffOptions {
  /** First delay. */
  baseMs: number;
  /** Largest delay. */
  maxMs: number;
  /** Random source (tests inject one). */
  random?: () => number;
}

/** Default: 0.5 s doubling up to 15 s. */
export const DEFAULT_BACKOFF: BackoffOptions = { baseMs: 500, maxMs: 15_000 };

/** Successive reconnection delays. */
export class Backoff {
  private attempt = 0;
  constructor(private readonly opts: BackoffOptions = DEFAULT_BACKOFF) {}

  /** The delay before the next attempt: uniform in [ceiling/2, ceiling]. */
  next(): number {
    const ceiling = Math.min(this.opts.maxMs, this.opts.baseMs * 2 ** this.attempt);
    this.attempt = Math.min(this.attempt + 1, 30);
    const r = (this.opts.random ?? Math.random)();
    return ceiling / 2 + (ceiling / 2) * r;
  }

  /** The connection succeeded. */
  reset(): void {
    this.attempt = 0;
  }
}
