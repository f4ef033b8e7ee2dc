/**
 * Shared by the wasm-*.test.ts files: loads web/public/frep.wasm (built by
 * scripts/build-wasm.sh) into a FrepKernel in Node. When the file is
 * missing the tests are skipped with a message, unless FREP_REQUIRE_WASM
 * is set (CI), where a missing module fails.
 */
import { existsSync, readFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { FrepKernel } from '../../src/wasm/kernel';

const here = dirname(fileURLToPath(import.meta.url));

/** The repository root. */
export const repoRoot = resolve(here, '../../..');

/** The built module. */
export const wasmPath = join(repoRoot, 'web/public/frep.wasm');

/** Whether the module is there (false: the tests skip, or fail under FREP_REQUIRE_WASM). */
export function wasmAvailable(): boolean {
  if (existsSync(wasmPath)) return true;
  if (process.env.FREP_REQUIRE_WASM) {
    throw new Error(`${wasmPath} is missing and FREP_REQUIRE_WASM is set: run scripts/build-wasm.sh`);
  }
  console.warn(`NOTE: ${wasmPath} is missing: the WebAssembly kernel tests are skipped (run scripts/build-wasm.sh)`);
  return false;
}

/** A fresh kernel instance from the built module. */
export async function loadKernel(): Promise<FrepKernel> {
  return FrepKernel.fromBytes(readFileSync(wasmPath));
}

/** An example model's source. */
export function example(name: string): string {
  return readFileSync(join(repoRoot, 'examples', `${name}.hf`), 'utf8');
}
