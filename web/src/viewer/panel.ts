/**
 * The measurements panel: a small plot of the live measurements
 * (bandwidth, round trip, frame rate), one sample a second over the last
 * minute, each series scaled to its own maximum, with the latest values
 * written beside it. Series history is kept in {@link SeriesHistory}
 * (pure, unit tested); the canvas drawing is best-effort.
 */
import { formatBandwidth, formatMs } from './badge-text';

/** One sample of the measurements (null: unknown now). */
export interface MeasureSample {
  bandwidthBps: number | null;
  rttMs: number | null;
  fps: number | null;
}

/** A bounded history of samples. */
export class SeriesHistory {
  readonly samples: MeasureSample[] = [];
  constructor(readonly capacity = 60) {}

  /** Adds a sample, dropping the oldest past the capacity. */
  push(s: MeasureSample): void {
    this.samples.push(s);
    if (this.samples.length > this.capacity) this.samples.splice(0, this.samples.length - this.capacity);
  }

  /** The largest known value of a series (null: none known). */
  max(key: keyof MeasureSample): number | null {
    let m: number | null = null;
    for (const s of this.samples) {
      const v = s[key];
      if (v !== null && Number.isFinite(v) && (m === null || v > m)) m = v;
    }
    return m;
  }

  /** The latest known value of a series. */
  latest(key: keyof MeasureSample): number | null {
    for (let i = this.samples.length - 1; i >= 0; i--) {
      const v = this.samples[i][key];
      if (v !== null) return v;
    }
    return null;
  }
}

const SERIES: { key: keyof MeasureSample; color: string; label: (v: number | null) => string }[] = [
  { key: 'bandwidthBps', color: '#6cb6ff', label: (v) => `bw ${formatBandwidth(v)}` },
  { key: 'rttMs', color: '#f0b44c', label: (v) => `rtt ${formatMs(v)}` },
  { key: 'fps', color: '#7ee787', label: (v) => `${v === null ? '—' : v.toFixed(v >= 10 ? 0 : 1)} fps` },
];

/** The panel's DOM. */
export class MeasurePanel {
  readonly element: HTMLElement;
  private readonly canvas: HTMLCanvasElement;
  private readonly legend: HTMLElement;
  readonly history = new SeriesHistory();

  constructor() {
    this.element = document.createElement('div');
    this.element.className = 'frep-measure-panel';
    this.element.dataset.testid = 'measure-panel';
    this.canvas = document.createElement('canvas');
    this.canvas.width = 180;
    this.canvas.height = 48;
    this.legend = document.createElement('div');
    this.legend.className = 'frep-measure-legend';
    this.element.append(this.canvas, this.legend);
  }

  /** Adds a sample and redraws. */
  push(s: MeasureSample): void {
    this.history.push(s);
    this.draw();
  }

  private draw(): void {
    const g = this.canvas.getContext('2d');
    const { width: w, height: h } = this.canvas;
    const n = this.history.capacity;
    if (g) {
      g.clearRect(0, 0, w, h);
      for (const s of SERIES) {
        const max = this.history.max(s.key);
        if (!max || max <= 0) continue;
        g.strokeStyle = s.color;
        g.lineWidth = 1.5;
        g.beginPath();
        let started = false;
        const start = n - this.history.samples.length;
        this.history.samples.forEach((smp, i) => {
          const v = smp[s.key];
          if (v === null) {
            started = false;
            return;
          }
          const x = ((start + i) / (n - 1)) * (w - 2) + 1;
          const y = h - 2 - (v / max) * (h - 4);
          if (started) g.lineTo(x, y);
          else g.moveTo(x, y);
          started = true;
        });
        g.stroke();
      }
    }
    this.legend.replaceChildren(
      ...SERIES.map((s) => {
        const span = document.createElement('span');
        span.style.color = s.color;
        span.textContent = s.label(this.history.latest(s.key));
        span.dataset.series = s.key;
        return span;
      }),
    );
  }
}
