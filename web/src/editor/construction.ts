/**
 * The construction tree of a model: what the tree view shows.
 *
 * Read from the source of the main body: its result expression, with set
 * operations (`|` union, `&` intersection, `\` subtraction, `~` negation,
 * `@` product) and blends as inner nodes, library primitives as leaves,
 * and variables followed to their assignment before the result (the last
 * top-level one). Transformations are attached to the primitive whose
 * coordinate array they modify (`t = hfShift3D(xt, …)` before
 * `s = hfSphere(xt, …)`). Anything else (arithmetic, built-in calls) is an
 * `expression` leaf. Ranges point into the source so the view can select.
 */
import { type Body, type Expr, type Stmt, mainBody, parseProgram } from './hf-syntax';
import { libraryFunction, roleOf } from './library';

/** Kinds of construction nodes. */
export type ShapeKind =
  | 'union'
  | 'intersection'
  | 'subtraction'
  | 'product'
  | 'negation'
  | 'blendUnion'
  | 'blendIntersection'
  | 'primitive'
  | 'expression';

/** A node of the construction tree. */
export interface ShapeNode {
  kind: ShapeKind;
  /** What the view prints: an operation's name or a function's. */
  label: string;
  /** The variable it was assigned to, when it was. */
  variable: string | null;
  /** Source range of its expression. */
  from: number;
  to: number;
  children: ShapeNode[];
  /** Transformations applied to a primitive's coordinates, in order. */
  transforms: string[];
}

const SET_OPS: Record<string, ShapeKind> = {
  '|': 'union',
  '&': 'intersection',
  '\\': 'subtraction',
  '@': 'product',
};

interface Scope {
  src: string;
  /** Shape variables: name (lower case) → value and the statement's start. */
  vars: Map<string, { value: Expr; at: number }>;
  /** Transformations per coordinate array: name → [(function, offset)]. */
  transforms: Map<string, { fn: string; at: number }[]>;
}

function scopeOf(src: string, body: Body): Scope {
  const vars = new Map<string, { value: Expr; at: number }>();
  const transforms = new Map<string, { fn: string; at: number }[]>();
  const visit = (stmts: Stmt[]) => {
    for (const s of stmts) {
      if (s.type === 'block') visit(s.body);
      if (s.type !== 'assign') continue;
      const v = s.value;
      const f = v.type === 'call' ? libraryFunction(v.name) : undefined;
      if (f && roleOf(f) === 'transform' && v.type === 'call' && v.args[0]?.type === 'ident') {
        const key = v.args[0].name.toLowerCase();
        const list = transforms.get(key) ?? [];
        list.push({ fn: f.display, at: s.from });
        transforms.set(key, list);
      } else {
        vars.set(s.target.toLowerCase(), { value: v, at: s.from });
      }
    }
  };
  visit(body.stmts);
  return { src, vars, transforms };
}

function leaf(sc: Scope, e: Expr): ShapeNode {
  const text = sc.src.slice(e.from, e.to).replace(/\s+/g, ' ');
  return {
    kind: 'expression',
    label: text.length > 40 ? `${text.slice(0, 37)}…` : text,
    variable: null,
    from: e.from,
    to: e.to,
    children: [],
    transforms: [],
  };
}

function node(e: Expr, kind: ShapeKind, label: string, children: ShapeNode[]): ShapeNode {
  return { kind, label, variable: null, from: e.from, to: e.to, children, transforms: [] };
}

function build(sc: Scope, e: Expr, seen: Set<string>, before: number): ShapeNode {
  switch (e.type) {
    case 'paren':
      return build(sc, e.inner, seen, before);
    case 'binary': {
      const kind = SET_OPS[e.op];
      if (!kind) return leaf(sc, e);
      // Flatten chains of the same operation: a | b | c is one union of three.
      const parts: Expr[] = [];
      const collect = (x: Expr) => {
        if (x.type === 'binary' && x.op === e.op) {
          collect(x.left);
          parts.push(x.right);
        } else parts.push(x);
      };
      collect(e);
      return node(e, kind, kind, parts.map((p) => build(sc, p, seen, before)));
    }
    case 'unary':
      return e.op === '~' ? node(e, 'negation', 'negation', [build(sc, e.arg, seen, before)]) : leaf(sc, e);
    case 'call': {
      const f = libraryFunction(e.name);
      if (!f) return leaf(sc, e);
      const role = roleOf(f);
      if (role === 'blend' && e.args.length >= 2) {
        const kind = f.name === 'hfblendint' ? 'blendIntersection' : 'blendUnion';
        return node(e, kind, f.display, e.args.slice(0, 2).map((a) => build(sc, a, seen, before)));
      }
      if (role !== 'primitive') return leaf(sc, e);
      const n = node(e, 'primitive', f.display, []);
      const coords = e.args[0];
      if (coords?.type === 'ident') {
        const list = sc.transforms.get(coords.name.toLowerCase()) ?? [];
        n.transforms = list.filter((t) => t.at < before).map((t) => t.fn);
      }
      return n;
    }
    case 'ident': {
      const key = e.name.toLowerCase();
      const v = sc.vars.get(key);
      if (!v || seen.has(key)) return leaf(sc, e);
      const inner = build(sc, v.value, new Set([...seen, key]), v.at);
      return { ...inner, variable: e.name, from: e.from, to: e.to };
    }
    default:
      return leaf(sc, e);
  }
}

/** The construction tree of a source's main body (null: no result found). */
export function constructionTree(src: string): ShapeNode | null {
  const body = mainBody(parseProgram(src));
  if (!body || !body.result) return null;
  const sc = scopeOf(src, body);
  const root = build(sc, body.result.value, new Set(), body.result.from);
  return { ...root, variable: root.variable ?? body.result.target };
}

/** Every primitive of a tree, depth first (what the palette can transform). */
export function primitives(tree: ShapeNode | null): ShapeNode[] {
  if (!tree) return [];
  if (tree.kind === 'primitive') return [tree];
  return tree.children.flatMap(primitives);
}
