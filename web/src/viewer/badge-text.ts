/**
 * Words for the badge: the mode's name, the engine's reason with its
 * numbers, and the network it assumed, in plain words. Pure functions (unit
 * tested); the badge's DOM is in badge.ts.
 */
import type { Decision, Mode } from '../wire';

/** Every mode's plain name. */
export const MODE_NAMES: Record<Mode, string> = {
  still: 'server still image',
  viewSet: 'server view set',
  serverMesh: 'server mesh',
  gpuRaycast: 'GPU ray casting',
  wasmMesh: 'mesh made in the browser',
  volume: 'volume on the GPU',
};

/** Short labels for the menu and the badge. */
export const MODE_LABELS: Record<Mode, string> = {
  still: '1 · still',
  viewSet: '2 · view set',
  serverMesh: '3 · server mesh',
  gpuRaycast: '4a · GPU ray cast',
  wasmMesh: '4b · WASM mesh',
  volume: 'volume',
};

/** A bit rate in plain words: "850 kbit/s", "12.5 Mbit/s". */
export function formatBandwidth(bps: number | null | undefined): string {
  if (bps === null || bps === undefined || !Number.isFinite(bps) || bps <= 0) return '—';
  if (bps >= 1e9) return `${(bps / 1e9).toFixed(bps >= 1e10 ? 0 : 1)} Gbit/s`;
  if (bps >= 1e6) return `${(bps / 1e6).toFixed(bps >= 1e7 ? 0 : 1)} Mbit/s`;
  if (bps >= 1e3) return `${Math.round(bps / 1e3)} kbit/s`;
  return `${Math.round(bps)} bit/s`;
}

/** A duration: "8 ms", "1.2 s". */
export function formatMs(ms: number | null | undefined): string {
  if (ms === null || ms === undefined || !Number.isFinite(ms)) return '—';
  if (ms >= 1000) return `${(ms / 1000).toFixed(ms >= 10000 ? 0 : 1)} s`;
  if (ms >= 10) return `${Math.round(ms)} ms`;
  return `${ms.toFixed(1)} ms`;
}

/** A byte count: "950 B", "12 kB", "1.4 MB". */
export function formatBytes(b: number | null | undefined): string {
  if (b === null || b === undefined || !Number.isFinite(b)) return '—';
  if (b >= 1e6) return `${(b / 1e6).toFixed(1)} MB`;
  if (b >= 1e3) return `${Math.round(b / 1e3)} kB`;
  return `${Math.round(b)} B`;
}

/** What the badge says. */
export interface BadgeText {
  /** The headline: the mode shown. */
  title: string;
  /** Why, in plain words with numbers. */
  reason: string;
  /** The tooltip: the reason, the network and the engine's predictions. */
  detail: string;
}

/**
 * The badge's words for the mode shown, the decision (null before one) and
 * a note when the viewer had to differ from the decision (a fallback).
 */
export function badgeText(shown: Mode | null, decision: Decision | null, note: string | null = null, override: Mode | null = null): BadgeText {
  const title = shown ? MODE_NAMES[shown] : 'starting…';
  const parts: string[] = [];
  if (override && override === shown) parts.push('chosen by you');
  else if (decision) parts.push(decision.reason.trim());
  else parts.push('no decision yet: the server still image comes first');
  if (note) parts.push(note);
  const reason = parts.filter(Boolean).join(' — ');
  const lines = [reason];
  if (decision) {
    const n = decision.network;
    lines.push(`network: round trip ${formatMs(n.rttMs)}, ${formatBandwidth(n.bandwidthBps)} (${n.samples} samples)`);
    lines.push(`decision #${decision.seq} (${decision.trigger})${decision.overridden ? ', overridden' : ''}`);
    for (const p of decision.predictions) {
      lines.push(
        p.feasible
          ? `${MODE_LABELS[p.mode]}: first ${formatMs(p.firstDisplayMs)}, orbit ${formatMs(p.orbitMs)}, edit ${formatMs(p.editMs)}, ${formatBytes(p.bytes)}`
          : `${MODE_LABELS[p.mode]}: not possible (${p.refusal ?? 'refused'})`,
      );
    }
  }
  return { title, reason, detail: lines.join('\n') };
}
