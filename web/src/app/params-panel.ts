/**
 * The parameter panel: a slider for every model parameter `a[i]` (named,
 * ranged and defaulted by the compiler's summary) and for each numeric
 * constant the user picked in the code, plus named presets.
 *
 * Dragging a parameter slider calls `onParams` at once (the studio passes
 * the values to the viewer, which updates live); dragging a constant's
 * slider rewrites the number in the source (the source stays the truth)
 * through `onConstant`. Values go with the version when it is saved.
 */
import type { ParamInfo } from '../wire';
import { askText } from './dialogs';
import { clear, h } from './dom';
import { type Preset, readPresets } from './presets';

/** A constant slider as the panel shows it. */
export interface ConstantSlider {
  id: number;
  value: number | null;
  /** Line of the constant, for the label. */
  line: number;
}

/** What the panel tells the studio. */
export interface ParamsHooks {
  onParams(values: number[]): void;
  onConstant(id: number, value: number, step: number): void;
  dropConstant(id: number): void;
  /** Asks to track the number at the editor's cursor. */
  pickConstant(): void;
  /** Saves the current values as a named preset (written into the source). */
  savePreset(preset: Preset): void;
}

function stepFor(min: number, max: number): number {
  const span = Math.abs(max - min) || 1;
  return 10 ** (Math.floor(Math.log10(span)) - 2);
}

/** The parameter panel. */
export class ParamsPanel {
  readonly el: HTMLElement;
  private readonly paramsBox: HTMLElement;
  private readonly constBox: HTMLElement;
  private readonly presetBox: HTMLElement;
  private infos: ParamInfo[] = [];
  private values: number[] = [];
  private presets: Preset[] | null = null;

  constructor(private readonly hooks: ParamsHooks) {
    this.paramsBox = h('div', { class: 'param-list', 'aria-label': 'Model parameters' });
    this.constBox = h('div', { class: 'param-list', 'aria-label': 'Constants' });
    this.presetBox = h('div', { class: 'presets' });
    this.el = h(
      'section',
      { class: 'panel-section params' },
      h('div', { class: 'section-head' }, h('h2', { text: 'Parameters' })),
      this.paramsBox,
      this.presetBox,
      h(
        'div',
        { class: 'section-head' },
        h('h3', { text: 'Constants' }),
        h('button', {
          type: 'button',
          text: 'Slider for number at cursor',
          title: 'Put the cursor on a number in the code, then press this',
          onclick: () => this.hooks.pickConstant(),
        }),
      ),
      this.constBox,
    );
  }

  /** The current parameter values. */
  get current(): number[] {
    return [...this.values];
  }

  /** Sets parameters (from a compile summary) and values (from a version). */
  setParams(infos: ParamInfo[], values: number[]): void {
    this.infos = [...infos].sort((a, b) => a.index - b.index);
    const n = Math.max(values.length, ...this.infos.map((p) => p.index), 0);
    this.values = Array.from({ length: n }, (_, i) => values[i] ?? this.infos.find((p) => p.index === i + 1)?.default ?? 0);
    this.renderParams();
  }

  /** Replaces the values (a preset, a version) and tells the studio. */
  applyValues(values: number[]): void {
    this.values = this.values.map((v, i) => values[i] ?? v);
    this.renderParams();
    this.hooks.onParams(this.current);
  }

  /** The presets found in the source. */
  setSource(src: string): void {
    const next = readPresets(src);
    if (JSON.stringify(next) === JSON.stringify(this.presets)) return;
    this.presets = next;
    this.renderPresets();
  }

  private renderParams(): void {
    clear(this.paramsBox);
    if (this.infos.length === 0) {
      this.paramsBox.append(h('p', { class: 'hint', text: 'This model has no parameters a[].' }));
      return;
    }
    for (const p of this.infos) this.paramsBox.append(this.paramRow(p));
  }

  private paramRow(p: ParamInfo): HTMLElement {
    const i = p.index - 1;
    const min = Math.min(p.min, this.values[i]);
    const max = Math.max(p.max, this.values[i]);
    const step = stepFor(min, max);
    const out = h('output', { text: fmt(this.values[i]) });
    const slider = h('input', {
      type: 'range',
      min,
      max,
      step,
      value: String(this.values[i]),
      'aria-label': p.name,
      'data-param': p.index,
      oninput: () => {
        this.values[i] = Number(slider.value);
        out.textContent = fmt(this.values[i]);
        this.hooks.onParams(this.current);
      },
    });
    return h('label', { class: 'param-row' }, h('span', { class: 'param-name', text: p.name }), slider, out);
  }

  /** Shows the constant sliders. */
  setConstants(list: ConstantSlider[]): void {
    clear(this.constBox);
    for (const c of list) this.constBox.append(this.constantRow(c));
  }

  private constantRow(c: ConstantSlider): HTMLElement {
    const drop = h('button', { type: 'button', class: 'icon', 'aria-label': 'Remove slider', text: '×', onclick: () => this.hooks.dropConstant(c.id) });
    if (c.value === null) {
      return h('div', { class: 'param-row lost' }, h('span', { class: 'param-name', text: `line ${c.line}` }), h('span', { text: 'no longer a number' }), drop);
    }
    // Constants are unsigned literals: the range runs from 0 to twice the value (at least 1).
    const max = Math.max(1, c.value * 2);
    const step = stepFor(0, max);
    const out = h('output', { text: fmt(c.value) });
    const slider = h('input', {
      type: 'range',
      min: 0,
      max,
      step,
      value: String(c.value),
      'aria-label': `constant on line ${c.line}`,
      'data-constant': c.id,
      oninput: () => {
        const v = Number(slider.value);
        out.textContent = fmt(v);
        this.hooks.onConstant(c.id, v, step);
      },
    });
    return h('label', { class: 'param-row' }, h('span', { class: 'param-name', text: `line ${c.line}` }), slider, out, drop);
  }

  private renderPresets(): void {
    clear(this.presetBox);
    const presets = this.presets ?? [];
    const select = h('select', { 'aria-label': 'Presets' }, h('option', { value: '', text: 'Presets…' }));
    for (const p of presets) select.append(h('option', { value: p.name, text: p.name }));
    select.addEventListener('change', () => {
      const p = presets.find((k) => k.name === select.value);
      if (p) this.applyValues(p.values);
      select.value = '';
    });
    const save = h('button', {
      type: 'button',
      text: 'Save preset',
      onclick: async () => {
        const name = await askText('Name of the preset', `preset ${presets.length + 1}`, 'Save');
        if (name) this.hooks.savePreset({ name, values: this.current });
      },
    });
    this.presetBox.append(presets.length ? select : h('span', { class: 'hint', text: 'No presets.' }), save);
  }
}

function fmt(v: number): string {
  return Number.isInteger(v) ? String(v) : v.toFixed(Math.abs(v) < 1 ? 3 : 2);
}
