/**
 * A tolerant reader of HyperFun for the studio: tokens with their offsets,
 * and the statements of each body with their expression trees.
 *
 * It is not the compiler (the kernel's parser decides what is valid and
 * reports errors); it reads enough structure for the tree view, the
 * palette's edits and the constant sliders, and never throws: text it
 * cannot read becomes an `other` node spanning it. Precedences follow the
 * kernel's parser: unary `+ - ~` above `^` (left-assoc) above `* /` above
 * `+ - | & \ @` (one level, left-assoc). Offsets are UTF-16 indices into
 * the source string (CodeMirror positions).
 */

/** Kinds of tokens. */
export type TokKind = 'num' | 'ident' | 'punct' | 'string' | 'eof';

/** A token with its `[from, to)` range. */
export interface Tok {
  kind: TokKind;
  /** The text as written (identifiers keep their case). */
  text: string;
  from: number;
  to: number;
}

/** Reserved words (lower case; HyperFun folds case). */
export const KEYWORDS = [
  'array', 'if', 'then', 'else', 'endif', 'while', 'loop', 'endloop', 'and', 'or', 'not', 'xor',
];

/** Built-in functions of the language (not the hf* library). */
export const BUILTINS = [
  'sqrt', 'exp', 'log', 'logd', 'sin', 'cos', 'tan', 'asin', 'acos', 'atan', 'abs', 'sinh', 'cosh',
  'tanh', 'ceil', 'floor', 'int', 'frac', 'sign', 'mod', 'max', 'min', 'atan2',
];

const TWO_CHAR = new Set(['/=', '<=', '>=']);

/** Splits a source into tokens; `--` comments and whitespace are skipped. */
export function tokenize(src: string): Tok[] {
  const out: Tok[] = [];
  let i = 0;
  const n = src.length;
  while (i < n) {
    const c = src[i];
    if (c === ' ' || c === '\t' || c === '\r' || c === '\n') {
      i++;
    } else if (c === '-' && src[i + 1] === '-') {
      while (i < n && src[i] !== '\n') i++;
    } else if (/[0-9]/.test(c) || (c === '.' && /[0-9]/.test(src[i + 1] ?? ''))) {
      const m = /^(\d*\.?\d*)([eE][+-]?\d+)?/.exec(src.slice(i));
      const len = m && m[0].length > 0 ? m[0].length : 1;
      out.push({ kind: 'num', text: src.slice(i, i + len), from: i, to: i + len });
      i += len;
    } else if (/[A-Za-z]/.test(c)) {
      let j = i + 1;
      while (j < n && /[A-Za-z0-9_]/.test(src[j])) j++;
      out.push({ kind: 'ident', text: src.slice(i, j), from: i, to: j });
      i = j;
    } else if (c === '"') {
      let j = i + 1;
      while (j < n && src[j] !== '"' && src[j] !== '\n') j++;
      j = Math.min(n, j + 1);
      out.push({ kind: 'string', text: src.slice(i, j), from: i, to: j });
      i = j;
    } else {
      const two = src.slice(i, i + 2);
      const len = TWO_CHAR.has(two) ? 2 : 1;
      out.push({ kind: 'punct', text: src.slice(i, i + len), from: i, to: i + len });
      i += len;
    }
  }
  out.push({ kind: 'eof', text: '', from: n, to: n });
  return out;
}

/** An expression. */
export type Expr =
  | { type: 'num'; value: number; from: number; to: number }
  | { type: 'ident'; name: string; from: number; to: number }
  | { type: 'index'; name: string; index: Expr; from: number; to: number }
  | { type: 'call'; name: string; args: Expr[]; from: number; to: number; nameTo: number }
  | { type: 'unary'; op: string; arg: Expr; from: number; to: number }
  | { type: 'binary'; op: string; left: Expr; right: Expr; from: number; to: number }
  | { type: 'paren'; inner: Expr; from: number; to: number }
  | { type: 'other'; from: number; to: number };

/** A statement (`if`/`while` keep their inner statements). */
export type Stmt =
  | { type: 'assign'; target: string; value: Expr; from: number; to: number }
  | { type: 'indexAssign'; target: string; index: Expr; value: Expr; from: number; to: number }
  | { type: 'arrayLiteral'; target: string; items: Expr[]; from: number; to: number }
  | { type: 'block'; keyword: 'if' | 'while'; body: Stmt[]; from: number; to: number }
  | { type: 'other'; from: number; to: number };

/** A declared array: `array c[3]`. */
export interface ArrayDecl {
  name: string;
  size: number | null;
  from: number;
  to: number;
}

/** One body `name(x[3], a[n]) { ... }`. */
export interface Body {
  name: string;
  from: number;
  to: number;
  /** Offset just after `{`. */
  open: number;
  /** Offset of the closing `}`. */
  close: number;
  /** Size of `a` in the header, when declared. */
  aSize: number | null;
  arrays: ArrayDecl[];
  /** End of the last `array ...;` declaration (or `open`). */
  declsEnd: number;
  stmts: Stmt[];
  /** The final `name = expr;` statement, when found. */
  result: (Stmt & { type: 'assign' }) | null;
}

/** The bodies of a source. */
export interface Program {
  bodies: Body[];
}

class Reader {
  i = 0;
  constructor(readonly toks: Tok[]) {}
  get t(): Tok {
    return this.toks[Math.min(this.i, this.toks.length - 1)];
  }
  peek(k = 1): Tok {
    return this.toks[Math.min(this.i + k, this.toks.length - 1)];
  }
  atEnd(): boolean {
    return this.t.kind === 'eof';
  }
  is(text: string): boolean {
    return this.t.kind !== 'eof' && this.t.text.toLowerCase() === text;
  }
  eat(text: string): boolean {
    if (this.is(text)) {
      this.i++;
      return true;
    }
    return false;
  }
  prevEnd(): number {
    return this.toks[Math.max(0, this.i - 1)].to;
  }
}

const ADD_OPS = new Set(['+', '-', '|', '&', '\\', '@']);
const MUL_OPS = new Set(['*', '/']);
const MAX_DEPTH = 200;

function primary(r: Reader, depth: number): Expr {
  const t = r.t;
  if (depth > MAX_DEPTH || t.kind === 'eof') return { type: 'other', from: t.from, to: t.from };
  if (t.kind === 'num') {
    r.i++;
    return { type: 'num', value: Number(t.text), from: t.from, to: t.to };
  }
  if (t.text === '(') {
    r.i++;
    const inner = expr(r, depth + 1);
    r.eat(')');
    return { type: 'paren', inner, from: t.from, to: r.prevEnd() };
  }
  if (t.kind === 'ident') {
    r.i++;
    if (r.is('(')) {
      r.i++;
      const args: Expr[] = [];
      if (!r.is(')')) {
        for (;;) {
          args.push(expr(r, depth + 1));
          if (!r.eat(',')) break;
        }
      }
      r.eat(')');
      return { type: 'call', name: t.text, args, from: t.from, to: r.prevEnd(), nameTo: t.to };
    }
    if (r.is('[')) {
      r.i++;
      const index = expr(r, depth + 1);
      r.eat(']');
      return { type: 'index', name: t.text, index, from: t.from, to: r.prevEnd() };
    }
    return { type: 'ident', name: t.text, from: t.from, to: t.to };
  }
  r.i++;
  return { type: 'other', from: t.from, to: t.to };
}

function unary(r: Reader, depth: number): Expr {
  const t = r.t;
  if (t.kind === 'punct' && (t.text === '-' || t.text === '+' || t.text === '~') && depth < MAX_DEPTH) {
    r.i++;
    const arg = unary(r, depth + 1);
    return { type: 'unary', op: t.text, arg, from: t.from, to: arg.to };
  }
  return primary(r, depth);
}

function binaryLevel(r: Reader, depth: number, ops: Set<string>, next: (r: Reader, d: number) => Expr): Expr {
  let left = next(r, depth + 1);
  while (r.t.kind === 'punct' && ops.has(r.t.text)) {
    const op = r.t.text;
    r.i++;
    const right = next(r, depth + 1);
    left = { type: 'binary', op, left, right, from: left.from, to: right.to };
  }
  return left;
}

const POW_OPS = new Set(['^']);
function power(r: Reader, d: number): Expr {
  return binaryLevel(r, d, POW_OPS, unary);
}
function product(r: Reader, d: number): Expr {
  return binaryLevel(r, d, MUL_OPS, power);
}
/** Reads an expression (the additive / set-operation level). */
function expr(r: Reader, d: number): Expr {
  return binaryLevel(r, d, ADD_OPS, product);
}

/** Skips to just after the next `;` (or to a stop word), returning its end. */
function skipStatement(r: Reader, stops: string[]): number {
  while (!r.atEnd() && !r.is(';') && !stops.some((s) => r.is(s))) r.i++;
  r.eat(';');
  return r.prevEnd();
}

function statements(r: Reader, stops: string[], depth: number): Stmt[] {
  const out: Stmt[] = [];
  while (!r.atEnd() && !stops.some((s) => r.is(s))) {
    const start = r.t.from;
    if ((r.is('if') || r.is('while')) && depth < 50) {
      const keyword = r.t.text.toLowerCase() as 'if' | 'while';
      const end = keyword === 'if' ? 'endif' : 'endloop';
      while (!r.atEnd() && !r.is('then') && !r.is('loop')) r.i++;
      r.i++;
      const body = statements(r, [end, 'else', '}'], depth + 1);
      if (r.eat('else')) body.push(...statements(r, [end, '}'], depth + 1));
      r.eat(end);
      r.eat(';');
      out.push({ type: 'block', keyword, body, from: start, to: r.prevEnd() });
      continue;
    }
    if (r.t.kind === 'ident' && r.peek().text === '=') {
      const target = r.t.text;
      r.i += 2;
      if (r.is('[')) {
        r.i++;
        const items: Expr[] = [];
        while (!r.atEnd() && !r.is(']') && !r.is(';')) {
          items.push(unary(r, 0));
          if (!r.eat(',')) break;
        }
        r.eat(']');
        r.eat(';');
        out.push({ type: 'arrayLiteral', target, items, from: start, to: r.prevEnd() });
        continue;
      }
      const value = expr(r, 0);
      const to = r.is(';') ? (r.i++, r.prevEnd()) : value.to;
      out.push({ type: 'assign', target, value, from: start, to });
      continue;
    }
    if (r.t.kind === 'ident' && r.peek().text === '[') {
      const target = r.t.text;
      r.i += 2;
      const index = expr(r, 0);
      r.eat(']');
      if (r.eat('=')) {
        const value = expr(r, 0);
        r.eat(';');
        out.push({ type: 'indexAssign', target, index, value, from: start, to: r.prevEnd() });
        continue;
      }
    }
    const to = skipStatement(r, stops);
    if (to <= start) r.i++;
    out.push({ type: 'other', from: start, to: Math.max(to, r.prevEnd()) });
  }
  return out;
}

function headerSize(r: Reader, name: string): number | null {
  // Looks for `name[n]` in the header's parameter list.
  for (let k = r.i; k < r.toks.length && r.toks[k].text !== ')'; k++) {
    const t = r.toks[k];
    if (t.kind === 'ident' && t.text.toLowerCase() === name && r.toks[k + 1]?.text === '[') {
      const n = Number(r.toks[k + 2]?.text);
      return Number.isFinite(n) ? n : null;
    }
  }
  return null;
}

function body(r: Reader): Body | null {
  const nameTok = r.t;
  if (nameTok.kind !== 'ident' || r.peek().text !== '(') {
    r.i++;
    return null;
  }
  r.i += 2;
  const aSize = headerSize(r, 'a');
  while (!r.atEnd() && !r.is(')')) r.i++;
  r.eat(')');
  if (!r.is('{')) return null;
  const open = r.t.to;
  r.i++;
  const arrays: ArrayDecl[] = [];
  let declsEnd = open;
  while (r.is('array')) {
    r.i++;
    while (r.t.kind === 'ident') {
      const t = r.t;
      r.i++;
      let size: number | null = null;
      if (r.eat('[')) {
        const n = Number(r.t.text);
        size = Number.isFinite(n) ? n : null;
        while (!r.atEnd() && !r.is(']') && !r.is(';')) r.i++;
        r.eat(']');
      }
      arrays.push({ name: t.text, size, from: t.from, to: r.prevEnd() });
      if (!r.eat(',')) break;
    }
    r.eat(';');
    declsEnd = r.prevEnd();
  }
  const stmts = statements(r, ['}'], 0);
  const close = r.t.from;
  r.eat('}');
  const last = stmts[stmts.length - 1];
  const result =
    last && last.type === 'assign' && last.target.toLowerCase() === nameTok.text.toLowerCase() ? last : null;
  if (result) stmts.pop();
  return { name: nameTok.text, from: nameTok.from, to: r.prevEnd(), open, close, aSize, arrays, declsEnd, stmts, result };
}

/** Reads every body of a source (never throws). */
export function parseProgram(src: string): Program {
  const r = new Reader(tokenize(src));
  const bodies: Body[] = [];
  while (!r.atEnd()) {
    const b = body(r);
    if (b) bodies.push(b);
  }
  return { bodies };
}

/** The body the studio edits: `my_model` if present, else the first. */
export function mainBody(p: Program): Body | null {
  return p.bodies.find((b) => b.name.toLowerCase() === 'my_model') ?? p.bodies[0] ?? null;
}

/** Every number literal of a source with its range (for constant sliders). */
export function numberAt(src: string, pos: number): { from: number; to: number; value: number } | null {
  for (const t of tokenize(src)) {
    if (t.kind === 'num' && t.from <= pos && pos <= t.to) {
      const v = Number(t.text);
      return Number.isFinite(v) ? { from: t.from, to: t.to, value: v } : null;
    }
    if (t.from > pos) break;
  }
  return null;
}
