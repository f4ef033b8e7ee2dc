/** Every mode in the paper's order (frep-wire's `Mode::ALL`). */
import type { Mode } from '../wire';

export const MODES_ALL: readonly Mode[] = ['still', 'viewSet', 'serverMesh', 'gpuRaycast', 'wasmMesh', 'volume'];
