/**
 * The hf* library as the kernel declares it: `library.json` is generated
 * from frep-core's own table (`cargo test -p frep-core --test
 * library_table`), so completion, signature help and the palette list
 * exactly the functions the compiler accepts, with its parameter names.
 */
import table from './library.json';

/** A parameter of a library function. */
export interface LibParam {
  name: string;
  kind: 'scalar' | 'array';
}

/** A library function. */
export interface LibFunction {
  /** Lower-case name (HyperFun folds case). */
  name: string;
  /** The documented spelling, e.g. `hfSphere`. */
  display: string;
  params: LibParam[];
  doc: string;
}

/** Every library function, sorted by name. */
export const LIBRARY: readonly LibFunction[] = (table.functions as LibFunction[]).map((f) => ({
  ...f,
  params: f.params.map((p) => ({ name: p.name, kind: p.kind === 'array' ? 'array' : 'scalar' })),
}));

const BY_NAME = new Map(LIBRARY.map((f) => [f.name, f]));

/** Looks a function up, ignoring case. */
export function libraryFunction(name: string): LibFunction | undefined {
  return BY_NAME.get(name.toLowerCase());
}

/** `hfSphere(x[], center[], R)`: arrays marked with `[]`. */
export function signatureText(f: LibFunction): string {
  return `${f.display}(${f.params.map((p) => (p.kind === 'array' ? `${p.name}[]` : p.name)).join(', ')})`;
}

/** What role a function plays in a construction. */
export type LibRole = 'primitive' | 'transform' | 'blend' | 'attribute';

/**
 * The role, read from the kernel's table: transformations take the
 * coordinates `xt` first, primitives the point `x`, blends two fields.
 */
export function roleOf(f: LibFunction): LibRole {
  const first = f.params[0]?.name;
  if (first === 'xt') return 'transform';
  if (first === 'f1') return 'blend';
  if (first === 'x') return 'primitive';
  return 'attribute';
}
