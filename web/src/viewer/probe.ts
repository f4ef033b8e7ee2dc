/**
 * Probing: the point under the cursor with its field value and attributes.
 *
 * The point comes from the mode when it can ray cast what it draws (the
 * meshes), else from the WASM kernel marching the pixel's ray; the field
 * value and attributes need an evaluator, the WASM kernel, through an
 * optional module `src/wasm/probe.ts` (client-modes part) exporting
 * {@link ProbeHooks}' functions. Without it the probe says why the value
 * is missing.
 */
import type { ProbeResult } from './types';

/** What `src/wasm/probe.ts` may export. */
export interface ProbeHooks {
  /** Field value and attributes at a point. */
  probePoint?(req: { source: string; params: number[]; point: [number, number, number] }): Promise<{ value: number; attributes: number[] }>;
  /** The first surface point along a ray inside the box, with value and attributes. */
  probeRay?(req: {
    source: string;
    params: number[];
    bounds: readonly number[];
    origin: [number, number, number];
    dir: [number, number, number];
  }): Promise<{ point: [number, number, number]; value: number; attributes: number[] } | null>;
}

const modules = import.meta.glob<ProbeHooks>('../wasm/probe.ts');

/** The hooks, when the kernel part provides them. */
export async function probeHooks(): Promise<ProbeHooks | null> {
  const load = modules['../wasm/probe.ts'];
  if (!load) return null;
  try {
    return await load();
  } catch {
    return null;
  }
}

/** The probe readout in plain words. */
export function probeText(p: ProbeResult | null): string {
  if (!p) return 'no surface under the cursor';
  const f = (v: number) => (Math.abs(v) >= 1000 || (Math.abs(v) < 1e-3 && v !== 0) ? v.toExponential(3) : v.toFixed(4));
  const parts = [`x ${f(p.point[0])}  y ${f(p.point[1])}  z ${f(p.point[2])}`];
  parts.push(p.value === null ? `f: ${p.source}` : `f = ${f(p.value)}`);
  if (p.attributes.length) parts.push(`s = [${p.attributes.map(f).join(', ')}]`);
  return parts.join('   ');
}
