/**
 * The viewer's controls around the picture: the mode badge with its
 * override menu (auto, or any mode), the toolbar (standard views, zoom to
 * fit, projection, section, dimensions, probe), the section controls, the
 * probe readout and the status line. DOM only; the viewer wires the calls.
 */
import type { Decision, Mode } from '../wire';
import { type StandardView } from './camera';
import { MODE_LABELS, badgeText } from './badge-text';
import { MODES_ALL } from './modes-all';

/** What the chrome calls back. */
export interface ChromeActions {
  override(mode: Mode | null): void;
  view(which: StandardView): void;
  fit(): void;
  projection(perspective: boolean): void;
  section(axis: 'x' | 'y' | 'z' | null, fraction: number, flip: boolean): void;
  dimensions(on: boolean): void;
  probe(on: boolean): void;
}

function el<K extends keyof HTMLElementTagNameMap>(tag: K, cls: string, text = ''): HTMLElementTagNameMap[K] {
  const e = document.createElement(tag);
  if (cls) e.className = cls;
  if (text) e.textContent = text;
  return e;
}

/** The chrome. */
export class ViewerChrome {
  readonly badge = el('div', 'frep-badge');
  readonly tools = el('div', 'frep-tools');
  readonly sectionBox = el('div', 'frep-section');
  readonly probeOut = el('div', 'frep-probe');
  readonly status = el('div', 'frep-status');
  private readonly title = el('b', '');
  private readonly reason = el('span', 'frep-reason');
  readonly menu = el('select', '');
  private readonly projBtn = el('button', '', 'persp');
  private perspective = true;

  constructor(private readonly act: ChromeActions) {
    this.badge.dataset.testid = 'mode-badge';
    this.menu.dataset.testid = 'mode-menu';
    this.status.dataset.testid = 'viewer-status';
    this.probeOut.dataset.testid = 'probe-readout';
    this.menu.append(new Option('auto', ''), ...MODES_ALL.map((m) => new Option(MODE_LABELS[m], m)));
    this.menu.title = 'Delivery mode: automatic (the server decides) or forced';
    this.menu.addEventListener('change', () => act.override((this.menu.value || null) as Mode | null));
    this.badge.append(this.title, this.reason, el('br', ''), this.menu);
    this.buildSection();
    this.buildTools();
  }

  /** Updates the badge. */
  setBadge(shown: Mode | null, decision: Decision | null, note: string | null, override: Mode | null): void {
    const t = badgeText(shown, decision, note, override);
    this.title.textContent = t.title;
    this.reason.textContent = t.reason;
    this.badge.title = t.detail;
    this.badge.dataset.mode = shown ?? '';
    this.menu.value = override ?? '';
  }

  /** Shows the camera's projection on its button. */
  setProjection(perspective: boolean): void {
    this.perspective = perspective;
    this.projBtn.textContent = perspective ? 'persp' : 'ortho';
  }

  private toggle(label: string, title: string, on: (v: boolean) => void, testid: string): HTMLButtonElement {
    const b = el('button', '', label);
    b.title = title;
    b.dataset.testid = testid;
    b.setAttribute('aria-pressed', 'false');
    b.addEventListener('click', () => {
      const v = b.getAttribute('aria-pressed') !== 'true';
      b.setAttribute('aria-pressed', String(v));
      on(v);
    });
    return b;
  }

  private buildTools(): void {
    const views = el('select', '');
    views.title = 'Standard views';
    views.dataset.testid = 'view-menu';
    views.append(new Option('view…', ''), ...(['front', 'back', 'left', 'right', 'top', 'bottom', 'iso'] as const).map((v) => new Option(v, v)));
    views.addEventListener('change', () => {
      if (views.value) this.act.view(views.value as StandardView);
      views.value = '';
    });
    const fit = el('button', '', 'fit');
    fit.title = 'Zoom to fit';
    fit.dataset.testid = 'zoom-fit';
    fit.addEventListener('click', () => this.act.fit());
    this.projBtn.title = 'Perspective or orthographic';
    this.projBtn.addEventListener('click', () => this.act.projection(!this.perspective));
    const section = this.toggle('section', 'Section plane', (v) => {
      this.sectionBox.hidden = !v;
      this.emitSection(v);
    }, 'section-toggle');
    const dims = this.toggle('dims', 'Dimensions (model box)', (v) => this.act.dimensions(v), 'dims-toggle');
    const probe = this.toggle('probe', 'Click the model to probe a point', (v) => this.act.probe(v), 'probe-toggle');
    // The section's controls wrap under the buttons, inside the toolbar.
    this.tools.append(views, fit, this.projBtn, section, dims, probe, this.sectionBox);
  }

  private axis = el('select', '');
  private slider = el('input', '');
  private flip = el('input', '');

  private buildSection(): void {
    this.sectionBox.hidden = true;
    this.axis.append(new Option('x', 'x'), new Option('y', 'y'), new Option('z', 'z'));
    this.axis.value = 'y';
    this.slider.type = 'range';
    this.slider.min = '0';
    this.slider.max = '1';
    this.slider.step = '0.01';
    this.slider.value = '0.5';
    this.slider.dataset.testid = 'section-offset';
    this.flip.type = 'checkbox';
    this.flip.title = 'Keep the other side';
    const on = () => this.emitSection(true);
    this.axis.addEventListener('change', on);
    this.slider.addEventListener('input', on);
    this.flip.addEventListener('change', on);
    this.sectionBox.append(this.axis, this.slider, this.flip);
  }

  private emitSection(on: boolean): void {
    this.act.section(on ? (this.axis.value as 'x' | 'y' | 'z') : null, Number(this.slider.value), this.flip.checked);
  }
}
