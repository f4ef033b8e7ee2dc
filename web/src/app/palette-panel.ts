/**
 * The palette: buttons that write HyperFun into the source — primitives
 * (combined with the model by the chosen set operation or blend),
 * transformations of a chosen shape, and a negation of the whole. The
 * text comes from `editor/palette-edits`; the editor applies it as one
 * undoable edit, and the tree view reads it back.
 */
import { type Combine, type EditResult, PRIMITIVES, TRANSFORMS, addShape, addTransform, negateResult } from '../editor/palette-edits';
import { notify } from './dialogs';
import { clear, h } from './dom';

/** What the palette needs from the studio. */
export interface PaletteHooks {
  source(): string;
  /** Applies an edit's new source (one undoable change). */
  apply(result: EditResult & { ok: true }): void;
  /** Names of the shapes that can be transformed (tree order). */
  shapes(): string[];
}

const COMBINES: [Combine, string][] = [
  ['union', 'union ∪ ( | )'],
  ['intersection', 'intersection ∩ ( & )'],
  ['subtraction', 'subtraction − ( \\ )'],
  ['blendUnion', 'blended union (hfBlendUni)'],
  ['blendIntersection', 'blended intersection (hfBlendInt)'],
];

/** The palette panel. */
export class PalettePanel {
  readonly el: HTMLElement;
  private readonly combine: HTMLSelectElement;
  private readonly target: HTMLSelectElement;

  constructor(private readonly hooks: PaletteHooks) {
    this.combine = h('select', { 'aria-label': 'Combine with' });
    for (const [v, label] of COMBINES) this.combine.append(h('option', { value: v, text: label }));
    this.target = h('select', { 'aria-label': 'Shape to transform', onfocus: () => this.refreshTargets() });
    const prims = h('div', { class: 'palette-grid' });
    for (const [name, tpl] of Object.entries(PRIMITIVES)) {
      prims.append(
        h('button', {
          type: 'button',
          text: name,
          title: `${tpl.fn}: add it to the model`,
          'data-palette': name,
          onclick: () => this.run(addShape(this.hooks.source(), tpl, this.combine.value as Combine)),
        }),
      );
    }
    const transforms = h('div', { class: 'palette-grid' });
    for (const [name, t] of Object.entries(TRANSFORMS)) {
      transforms.append(
        h('button', {
          type: 'button',
          text: name,
          title: `${t.fn} on the chosen shape's coordinates`,
          'data-palette': name,
          onclick: () => {
            this.refreshTargets();
            const target = this.target.value;
            if (!target) return notify('Choose a shape to transform (a primitive assigned to a variable).', 'warning');
            this.run(addTransform(this.hooks.source(), target, t));
          },
        }),
      );
    }
    this.el = h(
      'section',
      { class: 'panel-section palette' },
      h('h2', { text: 'Palette' }),
      h('label', { class: 'field' }, h('span', { text: 'Combine with' }), this.combine),
      h('h3', { text: 'Primitives' }),
      prims,
      h('h3', { text: 'Transformations' }),
      h('label', { class: 'field' }, h('span', { text: 'Shape' }), this.target),
      transforms,
      h('h3', { text: 'Whole model' }),
      h('div', { class: 'palette-grid' }, h('button', { type: 'button', text: 'negate ~', 'data-palette': 'negate', onclick: () => this.run(negateResult(this.hooks.source())) })),
    );
  }

  /** Refills the list of shapes (after the source changed). */
  refreshTargets(): void {
    const keep = this.target.value;
    clear(this.target);
    for (const s of this.hooks.shapes()) this.target.append(h('option', { value: s, text: s }));
    if ([...this.target.options].some((o) => o.value === keep)) this.target.value = keep;
  }

  private run(r: EditResult): void {
    if (!r.ok) {
      notify(r.error, 'warning');
      return;
    }
    this.hooks.apply(r);
    this.refreshTargets();
  }
}
