/**
 * The palette's edits: HyperFun text written into the source (the source
 * stays the truth; the tree view reads back what these write).
 *
 * * {@link addShape} declares a centre array, assigns a new primitive to a
 *   fresh variable before the result statement, and combines it with the
 *   result: `R | s`, `R & s`, `R \ s`, or `hfBlendUni(R, s, 1, 1, 1)` /
 *   `hfBlendInt(...)`. `| & \` share one left-associative level, so `R op s`
 *   needs no parentheses whatever `R` is.
 * * {@link addTransform} gives a shape its own coordinate array (a copy of
 *   `x`) the first time, then inserts `tN = hfShift3D(xtN, …);` just before
 *   the shape's statement: the library's transformations modify the array
 *   in place, in statement order.
 * * {@link negateResult} wraps the result in `~( … )`.
 *
 * Each returns the whole new source and the range of the text it added
 * (for the editor to select), or an error sentence.
 */
import { type Body, type Stmt, mainBody, parseProgram, tokenize } from './hf-syntax';
import { libraryFunction } from './library';

/** How a new shape joins the model. */
export type Combine = 'union' | 'intersection' | 'subtraction' | 'blendUnion' | 'blendIntersection';

/** A palette entry for a primitive: the function and its other arguments. */
export interface PrimitiveTemplate {
  /** Display name of the library function. */
  fn: string;
  /** The array passed after `x` (centre or vertex). */
  anchor: [number, number, number];
  /** The scalar arguments after it. */
  args: number[];
}

/** The primitives the palette offers (all checked against the library). */
export const PRIMITIVES: Record<string, PrimitiveTemplate> = {
  sphere: { fn: 'hfSphere', anchor: [0, 0, 0], args: [0.5] },
  ellipsoid: { fn: 'hfEllipsoid', anchor: [0, 0, 0], args: [0.6, 0.4, 0.3] },
  block: { fn: 'hfBlock', anchor: [-0.25, -0.25, -0.25], args: [0.5, 0.5, 0.5] },
  torus: { fn: 'hfTorusZ', anchor: [0, 0, 0], args: [0.5, 0.15] },
  cylinder: { fn: 'hfCylinderZ', anchor: [0, 0, 0], args: [0.3] },
  cone: { fn: 'hfConeZ', anchor: [0, 0, 0], args: [0.5] },
  superellipsoid: { fn: 'hfSuperell', anchor: [0, 0, 0], args: [0.5, 0.5, 0.5, 0.5, 0.5] },
};

/** A palette entry for a transformation: its scalar arguments. */
export const TRANSFORMS: Record<string, { fn: string; args: number[] }> = {
  shift: { fn: 'hfShift3D', args: [0.25, 0, 0] },
  rotateX: { fn: 'hfRotate3DX', args: [0.5] },
  rotateY: { fn: 'hfRotate3DY', args: [0.5] },
  rotateZ: { fn: 'hfRotate3DZ', args: [0.5] },
  scale: { fn: 'hfScale3D', args: [1.5, 1, 1] },
  twist: { fn: 'hfTwistZ', args: [-1, 1, -1, 1] },
  taper: { fn: 'hfTaperZ', args: [-1, 1, 1, 0.5] },
  stretch: { fn: 'hfStretch3D', args: [0, 0, 0, 1.5, 1, 1] },
};

/** The result of an edit. */
export type EditResult = { ok: true; source: string; from: number; to: number } | { ok: false; error: string };

interface Insert {
  at: number;
  text: string;
}

/** Applies inserts and one optional replacement; returns the new text and the moved range. */
function apply(src: string, inserts: Insert[], mark: { from: number; to: number }): EditResult {
  const sorted = [...inserts].sort((a, b) => b.at - a.at);
  let out = src;
  let { from, to } = mark;
  for (const ins of sorted) {
    out = out.slice(0, ins.at) + ins.text + out.slice(ins.at);
    if (ins.at <= from) {
      from += ins.text.length;
      to += ins.text.length;
    } else if (ins.at < to) to += ins.text.length;
  }
  return { ok: true, source: out, from, to };
}

function usedNames(src: string): Set<string> {
  return new Set(tokenize(src).filter((t) => t.kind === 'ident').map((t) => t.text.toLowerCase()));
}

function fresh(used: Set<string>, prefix: string): string {
  for (let i = 1; ; i++) {
    const name = `${prefix}${i}`;
    if (!used.has(name)) {
      used.add(name);
      return name;
    }
  }
}

function num(v: number): string {
  return Number.isInteger(v) ? String(v) : String(Number(v.toPrecision(6)));
}

/** Indentation of the line holding `pos`. */
function indentAt(src: string, pos: number): string {
  const start = src.lastIndexOf('\n', pos - 1) + 1;
  return /^[ \t]*/.exec(src.slice(start))?.[0] ?? '';
}

/** Where a new `array` declaration goes and its text. */
function declare(src: string, body: Body, decl: string): Insert {
  if (body.arrays.length > 0) {
    return { at: body.declsEnd, text: `\n${indentAt(src, body.arrays[0].from)}array ${decl};` };
  }
  return { at: body.open, text: `\n  array ${decl};` };
}

const EMPTY_MODEL = 'my_model(x[3], a[1])\n{\n  my_model = 0;\n}\n';

/** Adds a primitive combined with the model's result. */
export function addShape(src: string, primitive: PrimitiveTemplate, combine: Combine): EditResult {
  if (!libraryFunction(primitive.fn)) return { ok: false, error: `${primitive.fn} is not in the library` };
  let text = src;
  let body = mainBody(parseProgram(text));
  if (!body) {
    text = (src.trim() ? `${src.replace(/\s*$/, '')}\n\n` : '') + EMPTY_MODEL;
    body = mainBody(parseProgram(text));
    if (!body) return { ok: false, error: 'could not create a model body' };
  }
  const used = usedNames(text);
  const shape = fresh(used, 's');
  const anchor = fresh(used, 'c');
  const call = `${primitive.fn}(x, ${anchor}, ${primitive.args.map(num).join(', ')})`;
  const result = body.result;
  const at = result ? result.from : body.close;
  const ind = result ? indentAt(text, result.from) : '  ';
  const stmts = `${anchor} = [${primitive.anchor.map(num).join(', ')}];\n${ind}${shape} = ${call};\n${ind}`;
  const inserts: Insert[] = [declare(text, body, `${anchor}[3]`), { at, text: stmts }];
  if (!result) {
    inserts.push({ at, text: `${body.name} = ${shape};\n` });
    return apply(text, inserts, { from: at, to: at });
  }
  // Replace the result's value: splice it out and back with the combination.
  const v = result.value;
  const old = text.slice(v.from, v.to);
  const isZero = /^0(\.0*)?$/.test(old.trim());
  const combined = isZero ? shape : combineText(old, shape, combine);
  const replaced = text.slice(0, v.from) + combined + text.slice(v.to);
  return apply(replaced, inserts, { from: at, to: at });
}

function combineText(old: string, shape: string, combine: Combine): string {
  switch (combine) {
    case 'union':
      return `${old} | ${shape}`;
    case 'intersection':
      return `${old} & ${shape}`;
    case 'subtraction':
      return `${old} \\ ${shape}`;
    case 'blendUnion':
      return `hfBlendUni(${old}, ${shape}, 1, 1, 1)`;
    case 'blendIntersection':
      return `hfBlendInt(${old}, ${shape}, 1, 1, 1)`;
  }
}

function findShapeStmt(body: Body, variable: string): (Stmt & { type: 'assign' }) | null {
  const key = variable.toLowerCase();
  const all = [...body.stmts, ...(body.result ? [body.result] : [])];
  let found: (Stmt & { type: 'assign' }) | null = null;
  for (const s of all) {
    if (s.type === 'assign' && s.target.toLowerCase() === key && s.value.type === 'call') found = s;
  }
  return found;
}

/** Applies a transformation to the coordinates of the shape assigned to `variable`. */
export function addTransform(src: string, variable: string, transform: { fn: string; args: number[] }): EditResult {
  if (!libraryFunction(transform.fn)) return { ok: false, error: `${transform.fn} is not in the library` };
  const body = mainBody(parseProgram(src));
  if (!body) return { ok: false, error: 'no model body' };
  const stmt = findShapeStmt(body, variable);
  if (!stmt || stmt.value.type !== 'call') return { ok: false, error: `no shape assigned to ${variable}` };
  const coords = stmt.value.args[0];
  if (!coords || coords.type !== 'ident') return { ok: false, error: `${variable}'s coordinates are not an array name` };
  const used = usedNames(src);
  const ind = indentAt(src, stmt.from);
  const inserts: Insert[] = [];
  let xt = coords.name;
  let replaceCoords = false;
  if (coords.name.toLowerCase() === 'x') {
    // The shape reads the global point: give it its own copy to transform.
    xt = fresh(used, 'xt');
    inserts.push(declare(src, body, `${xt}[3]`));
    inserts.push({ at: stmt.from, text: `${xt}[1] = x[1];\n${ind}${xt}[2] = x[2];\n${ind}${xt}[3] = x[3];\n${ind}` });
    replaceCoords = true;
  }
  const t = fresh(used, 't');
  const line = `${t} = ${transform.fn}(${xt}, ${transform.args.map(num).join(', ')});\n${ind}`;
  inserts.push({ at: stmt.from, text: line });
  let text = src;
  if (replaceCoords) text = src.slice(0, coords.from) + xt + src.slice(coords.to);
  // coords lies after stmt.from and after the declarations, so inserts before it are unaffected.
  return apply(text, inserts, { from: stmt.from, to: stmt.from });
}

/** Wraps the model's result in a negation `~(…)`. */
export function negateResult(src: string): EditResult {
  const body = mainBody(parseProgram(src));
  if (!body?.result) return { ok: false, error: 'no result statement' };
  const v = body.result.value;
  const text = `${src.slice(0, v.from)}~(${src.slice(v.from, v.to)})${src.slice(v.to)}`;
  return { ok: true, source: text, from: v.from, to: v.to + 3 };
}
