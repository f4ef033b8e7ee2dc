/**
 * Latest-only delivery of streamed frames: while one frame decodes, newer
 * arrivals replace the waiting one (only the newest waits), and a frame
 * older than the one last shown is dropped. The display never goes
 * backwards and never queues stale frames. Every frame ends in exactly one
 * of `onShown` and `onDropped` (the server counts frames in flight until
 * the client answers for them).
 */

/** A frame with its sequence number. */
export interface Sequenced {
  seq: number;
}

/** Decodes and shows one frame; resolves when it is on screen (false: not shown). */
export type ShowFrame<F extends Sequenced> = (frame: F) => Promise<boolean>;

/** Latest-only frame pump. */
export class LatestFrames<F extends Sequenced> {
  private waiting: F | null = null;
  private busy = false;
  private lastShown = -1;
  /** Frames dropped because a newer one arrived or they were stale. */
  dropped = 0;
  /** Frames shown. */
  shown = 0;

  constructor(
    private readonly showFrame: ShowFrame<F>,
    private readonly onShown: (frame: F) => void = () => {},
    private readonly onDropped: (frame: F) => void = () => {},
  ) {}

  /** The sequence number last shown (-1: none). */
  get lastSeq(): number {
    return this.lastShown;
  }

  /** A frame arrived. */
  push(frame: F): void {
    if (frame.seq <= this.lastShown) {
      this.drop(frame);
      return;
    }
    if (this.waiting) {
      if (this.waiting.seq > frame.seq) {
        this.drop(frame);
        return;
      }
      this.drop(this.waiting);
    }
    this.waiting = frame;
    if (!this.busy) void this.pump();
  }

  /** Forgets the waiting frame and the order (a new model: sequence restarts). */
  reset(): void {
    this.waiting = null;
    this.lastShown = -1;
  }

  private drop(f: F): void {
    this.dropped++;
    this.onDropped(f);
  }

  private async pump(): Promise<void> {
    this.busy = true;
    try {
      while (this.waiting) {
        const f = this.waiting;
        this.waiting = null;
        if (f.seq <= this.lastShown) {
          this.drop(f);
          continue;
        }
        let ok = false;
        try {
          ok = await this.showFrame(f);
        } catch {
          ok = false;
        }
        if (ok && f.seq > this.lastShown) {
          this.lastShown = f.seq;
          this.shown++;
          this.onShown(f);
        } else this.drop(f);
      }
    } finally {
      this.busy = false;
    }
  }
}
