/**
 * The studio's page structure: a top bar, a left panel with tabs (models,
 * history, palette, construction), the viewer in the centre, and the editor
 * with the parameter panel on the right. On a narrow screen the side
 * panels collapse behind toggles in the top bar and stack under the view.
 */
import { h } from './dom';

/** The containers the studio fills. */
export interface Layout {
  root: HTMLElement;
  title: HTMLElement;
  status: HTMLElement;
  actions: HTMLElement;
  left: HTMLElement;
  tabs: Record<LeftTab, HTMLElement>;
  showTab(tab: LeftTab): void;
  viewer: HTMLElement;
  editor: HTMLElement;
  params: HTMLElement;
}

/** The left panel's tabs. */
export type LeftTab = 'models' | 'history' | 'palette' | 'tree';

const TAB_LABELS: Record<LeftTab, string> = { models: 'Models', history: 'History', palette: 'Palette', tree: 'Tree' };

/** Builds the page inside `root`. */
export function buildLayout(root: HTMLElement): Layout {
  const title = h('span', { class: 'model-title', 'data-testid': 'model-title' });
  const status = h('span', { class: 'compile-status', 'data-testid': 'compile-status', role: 'status' });
  const actions = h('div', { class: 'top-actions' });
  const leftToggle = h('button', { type: 'button', class: 'toggle', 'aria-label': 'Show or hide the side panel', text: '☰' });
  const rightToggle = h('button', { type: 'button', class: 'toggle', 'aria-label': 'Show or hide the code', text: '</>' });
  const bar = h(
    'header',
    { class: 'topbar' },
    leftToggle,
    h('a', { class: 'brand', href: '#/', text: 'frep' }),
    title,
    status,
    actions,
    rightToggle,
  );
  const tabBar = h('div', { class: 'tabs', role: 'tablist' });
  const tabs = {} as Record<LeftTab, HTMLElement>;
  const tabButtons = {} as Record<LeftTab, HTMLElement>;
  const left = h('aside', { class: 'side left', 'aria-label': 'Models and tools' }, tabBar);
  for (const t of Object.keys(TAB_LABELS) as LeftTab[]) {
    tabButtons[t] = h('button', { type: 'button', role: 'tab', text: TAB_LABELS[t], onclick: () => showTab(t) });
    tabBar.append(tabButtons[t]);
    tabs[t] = h('div', { class: 'tab-panel', role: 'tabpanel', 'data-tab': t });
    left.append(tabs[t]);
  }
  const showTab = (tab: LeftTab) => {
    for (const t of Object.keys(tabs) as LeftTab[]) {
      tabs[t].hidden = t !== tab;
      tabButtons[t].setAttribute('aria-selected', String(t === tab));
    }
    root.classList.remove('left-collapsed');
  };
  const viewer = h('section', { class: 'centre', 'aria-label': 'View' });
  const editor = h('div', { class: 'editor-host' });
  const params = h('div', { class: 'params-host' });
  const right = h('aside', { class: 'side right', 'aria-label': 'Code and parameters' }, editor, params);
  root.append(bar, h('main', { class: 'workspace' }, left, viewer, right));
  const narrow = window.matchMedia('(max-width: 900px)');
  if (narrow.matches) root.classList.add('left-collapsed', 'right-collapsed');
  leftToggle.addEventListener('click', () => root.classList.toggle('left-collapsed'));
  rightToggle.addEventListener('click', () => root.classList.toggle('right-collapsed'));
  showTab('models');
  if (narrow.matches) root.classList.add('left-collapsed');
  return { root, title, status, actions, left, tabs, showTab, viewer, editor, params };
}
