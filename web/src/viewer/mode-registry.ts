/**
 * Where each mode's view comes from: the files of `src/viewer/modes/`,
 * loaded lazily by a naming convention (still.ts, viewset.ts, mesh.ts here;
 * raycast*.ts, wasmmesh*.ts, volume*.ts from the client-modes part), and
 * the fallback order when a mode is missing or fails on this client.
 */
import type { Mode } from '../wire';
import type { ModeModule, ModeView } from './types';

const modules = import.meta.glob<ModeModule>('./modes/*.ts');

const FILE_PREFIX: Record<Mode, string> = {
  still: 'still',
  viewSet: 'viewset',
  serverMesh: 'mesh',
  gpuRaycast: 'raycast',
  wasmMesh: 'wasmmesh',
  volume: 'volume',
};

/** The files that may implement `mode` (by prefix). */
export function candidateFiles(mode: Mode, files: readonly string[] = Object.keys(modules)): string[] {
  const prefix = `./modes/${FILE_PREFIX[mode]}`;
  return files.filter((f) => f.startsWith(prefix) && !f.endsWith('.test.ts'));
}

/** Creates a view of `mode`, or null when no file implements it. */
export async function createModeView(mode: Mode): Promise<ModeView | null> {
  for (const file of candidateFiles(mode)) {
    const mod = await modules[file]();
    if (Array.isArray(mod.modes) && mod.modes.includes(mode) && typeof mod.create === 'function') return mod.create(mode);
  }
  return null;
}

/**
 * Starts loading the code of `mode` (no view is created), so that it is
 * there when a request needs it; failures surface in {@link createModeView}.
 */
export function preloadMode(mode: Mode): void {
  for (const file of candidateFiles(mode)) void modules[file]().catch(() => {});
}

/**
 * What to show instead of `mode` when it is missing or fails: client modes
 * fall back to the server mesh (with WebGL) and then to the still; the
 * still has no fallback.
 */
export function fallbackMode(mode: Mode, webgl: boolean): Mode | null {
  switch (mode) {
    case 'gpuRaycast':
    case 'wasmMesh':
    case 'volume':
      return webgl ? 'serverMesh' : 'still';
    case 'serverMesh':
    case 'viewSet':
      return 'still';
    case 'still':
      return null;
  }
}
