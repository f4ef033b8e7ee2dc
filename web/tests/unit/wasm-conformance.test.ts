/**
 * The WebAssembly kernel against the reference interpreter's golden values:
 * the same files and tolerance as frep-core's native suites
 * (crates/frep-core/tests/golden.rs and conformance.rs). The point
 * evaluator reproduces every value and every runtime error message; the
 * batch evaluator every value, NaN where an error reaches it.
 */
import { existsSync, readdirSync, readFileSync } from 'node:fs';
import { join } from 'node:path';
import { beforeAll, describe, expect, it } from 'vitest';
import type { FrepKernel } from '../../src/wasm/kernel';
import { loadKernel, repoRoot, wasmAvailable } from './wasm-support';

interface GoldenPoint {
  inputs: number[];
  values: number[] | null;
  error: string | null;
  line: number;
}

const dataDir = join(repoRoot, 'crates/frep-core/tests/data');
const corpusDir = join(repoRoot, '../shared/hyperfun/corpus');

function parseGolden(text: string): { body: string; points: GoldenPoint[] } {
  let body = 'my_model';
  const points: GoldenPoint[] = [];
  text.split('\n').forEach((raw, i) => {
    const line = raw.trim();
    if (line.startsWith('#')) {
      const at = line.indexOf('body:');
      if (at >= 0) body = line.slice(at + 5).trim();
      return;
    }
    if (!line) return;
    const [lhs, rhs] = line.split('|') as [string, string];
    const inputs = lhs.trim().split(/\s+/).map(Number);
    const r = rhs.trim();
    if (r.startsWith('error ')) points.push({ inputs, values: null, error: r.slice(6).trim(), line: i + 1 });
    else points.push({ inputs, values: r.split(/\s+/).map(Number), error: null, line: i + 1 });
  });
  return { body, points };
}

/** frep-core's `close`: 1e-9 relative or 1e-12 absolute. */
function close(a: number, b: number): boolean {
  return a === b || Math.abs(a - b) <= 1e-12 || Math.abs(a - b) <= 1e-9 * Math.max(Math.abs(a), Math.abs(b));
}

function goldenModels(): { name: string; source: string; body: string; points: GoldenPoint[] }[] {
  const out = [];
  for (const f of readdirSync(join(dataDir, 'golden')).sort()) {
    const name = f.replace(/\.txt$/, '');
    const conf = join(dataDir, 'conformance', `${name}.hf`);
    const corpus = join(corpusDir, `${name}.hf`);
    const path = existsSync(conf) ? conf : existsSync(corpus) ? corpus : null;
    if (!path) continue;
    const g = parseGolden(readFileSync(join(dataDir, 'golden', f), 'utf8'));
    out.push({ name, source: readFileSync(path, 'utf8'), ...g });
  }
  return out;
}

const available = wasmAvailable();

describe.skipIf(!available)('WebAssembly kernel conformance', () => {
  let kernel: FrepKernel;
  const models = goldenModels();

  beforeAll(async () => {
    kernel = await loadKernel();
  });

  it('finds every conformance model', () => {
    const conformance = readdirSync(join(dataDir, 'conformance')).filter((f) => f.endsWith('.hf')).length;
    expect(models.length).toBeGreaterThanOrEqual(conformance);
  });

  it('the point evaluator reproduces every golden value and error', () => {
    const failures: string[] = [];
    let checked = 0;
    for (const m of models) {
      const c = kernel.compile(m.source, { body: m.body, noBounds: true });
      if (!c.ok) {
        failures.push(`${m.name}: compile error ${c.diagnostics[0]?.rendered}`);
        continue;
      }
      for (const p of m.points) {
        const [x, y, z, ...a] = p.inputs as [number, number, number, ...number[]];
        const r = kernel.evalPoint(c.handle, x, y, z, a);
        checked++;
        if (p.error !== null) {
          if (r.ok || r.error !== p.error) failures.push(`${m.name}:${p.line}: expected error ${p.error}, got ${JSON.stringify(r)}`);
        } else if (!r.ok || r.values.length !== p.values!.length || !r.values.every((v, k) => close(v, p.values![k]!))) {
          failures.push(`${m.name}:${p.line}: expected ${p.values}, got ${JSON.stringify(r)}`);
        }
      }
      kernel.freeModel(c.handle);
    }
    expect(checked).toBeGreaterThan(500);
    expect(failures.slice(0, 20)).toEqual([]);
  });

  it('the batch evaluator reproduces every golden value', () => {
    const failures: string[] = [];
    // Each batch's values go into the array of the one before (stale
    // values, other sizes): what is returned is all this batch's.
    let out: Float64Array | undefined;
    for (const m of models) {
      const c = kernel.compile(m.source, { body: m.body, noBounds: true });
      expect(c.ok).toBe(true);
      // All the model's points of one parameter vector in one batch: the
      // lanes see many different points.
      const groups = new Map<string, GoldenPoint[]>();
      for (const p of m.points) {
        const key = p.inputs.slice(3).join(',');
        groups.set(key, [...(groups.get(key) ?? []), p]);
      }
      for (const pts of groups.values()) {
        const n = pts.length;
        const xyz = new Float64Array(3 * n);
        pts.forEach((p, i) => {
          xyz[i] = p.inputs[0]!;
          xyz[n + i] = p.inputs[1]!;
          xyz[2 * n + i] = p.inputs[2]!;
        });
        const { outputs, values } = kernel.evalPoints(c.handle, xyz, pts[0]!.inputs.slice(3), out);
        expect(values.length).toBe(outputs * n);
        out = values.length > (out?.length ?? 0) ? values : out;
        pts.forEach((p, i) => {
          if (p.values === null) return; // the native batch suite compares these with the value tape
          for (let k = 0; k < Math.min(outputs, p.values.length); k++) {
            const got = values[k * n + i]!;
            if (!close(p.values[k]!, got)) failures.push(`${m.name}:${p.line} output ${k}: expected ${p.values[k]}, got ${got}`);
          }
        });
      }
      kernel.freeModel(c.handle);
    }
    expect(failures.slice(0, 20)).toEqual([]);
  });
});
