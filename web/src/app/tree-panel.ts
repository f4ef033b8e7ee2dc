/**
 * The tree view of the construction (set operations, blends, primitives
 * with their transformations), read from the source by
 * `editor/construction`. Clicking a node selects its text in the editor.
 */
import type { ShapeNode } from '../editor/construction';
import { clear, h } from './dom';

const LABELS: Record<string, string> = {
  union: '∪ union',
  intersection: '∩ intersection',
  subtraction: '− subtraction',
  product: '@ product',
  negation: '~ negation',
};

/** The tree panel. */
export class TreePanel {
  readonly el: HTMLElement;
  private readonly root: HTMLElement;

  constructor(private readonly select: (from: number, to: number) => void) {
    this.root = h('div', { class: 'tree', role: 'tree', 'aria-label': 'Construction' });
    this.el = h('section', { class: 'panel-section tree-section' }, h('h2', { text: 'Construction' }), this.root);
  }

  /** Shows a tree (null: none could be read). */
  show(tree: ShapeNode | null): void {
    clear(this.root);
    if (!tree) {
      this.root.append(h('p', { class: 'hint', text: 'No result statement found.' }));
      return;
    }
    this.root.append(h('ul', { role: 'group' }, this.node(tree)));
  }

  private node(n: ShapeNode): HTMLElement {
    const label = LABELS[n.kind] ?? n.label;
    const button = h(
      'button',
      { type: 'button', class: `tree-node tree-${n.kind}`, 'data-kind': n.kind, onclick: () => this.select(n.from, n.to) },
      n.variable ? h('span', { class: 'tree-var', text: `${n.variable} = ` }) : null,
      h('span', { class: 'tree-label', text: label }),
      ...n.transforms.map((t) => h('span', { class: 'tree-transform', text: t })),
    );
    const li = h('li', { role: 'treeitem' }, button);
    if (n.children.length) li.append(h('ul', { role: 'group' }, ...n.children.map((c) => this.node(c))));
    return li;
  }
}
