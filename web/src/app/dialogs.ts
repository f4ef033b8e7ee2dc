/**
 * In-page dialogs (a name to enter, a yes/no question) and notices. They
 * use `<dialog>` rather than `prompt()`/`confirm()`, which block the page
 * (and its rendering) and cannot be styled.
 */
import { h } from './dom';

/** Asks for a line of text; resolves null when cancelled. */
export function askText(title: string, initial = '', okLabel = 'OK'): Promise<string | null> {
  return new Promise((resolve) => {
    const input = h('input', { type: 'text', value: initial, 'aria-label': title, required: true });
    const form = h(
      'form',
      { method: 'dialog', class: 'dialog-form' },
      h('label', { class: 'dialog-title', text: title }),
      input,
      h(
        'div',
        { class: 'dialog-buttons' },
        h('button', { type: 'button', value: 'cancel', text: 'Cancel', onclick: () => finish(null) }),
        h('button', { type: 'submit', class: 'primary', text: okLabel }),
      ),
    );
    const dlg = h('dialog', { class: 'dialog' }, form);
    const finish = (v: string | null) => {
      dlg.close();
      dlg.remove();
      resolve(v);
    };
    form.addEventListener('submit', (e) => {
      e.preventDefault();
      const v = input.value.trim();
      if (v) finish(v);
    });
    dlg.addEventListener('cancel', () => finish(null));
    document.body.append(dlg);
    dlg.showModal();
    input.select();
  });
}

/** Asks a yes/no question. */
export function confirmAction(question: string, yesLabel: string): Promise<boolean> {
  return new Promise((resolve) => {
    const dlg = h('dialog', { class: 'dialog' });
    const finish = (v: boolean) => {
      dlg.close();
      dlg.remove();
      resolve(v);
    };
    dlg.append(
      h('p', { class: 'dialog-title', text: question }),
      h(
        'div',
        { class: 'dialog-buttons' },
        h('button', { type: 'button', text: 'Cancel', onclick: () => finish(false) }),
        h('button', { type: 'button', class: 'danger', text: yesLabel, onclick: () => finish(true) }),
      ),
    );
    dlg.addEventListener('cancel', () => finish(false));
    document.body.append(dlg);
    dlg.showModal();
  });
}

/** A notice bar at the top of the page, with optional actions; returns its remover. */
export function notify(
  message: string,
  kind: 'info' | 'error' | 'warning' = 'info',
  actions: { label: string; run: () => void }[] = [],
  timeoutMs = kind === 'info' ? 4000 : 0,
): () => void {
  let host = document.getElementById('notices');
  if (!host) {
    host = h('div', { id: 'notices', class: 'notices', role: 'status', 'aria-live': 'polite' });
    document.body.append(host);
  }
  const bar = h('div', { class: `notice notice-${kind}` }, h('span', { text: message }));
  const remove = () => bar.remove();
  for (const a of actions) {
    bar.append(h('button', { type: 'button', text: a.label, onclick: () => (remove(), a.run()) }));
  }
  bar.append(h('button', { type: 'button', class: 'notice-close', 'aria-label': 'Dismiss', text: '×', onclick: remove }));
  host.append(bar);
  if (timeoutMs > 0) setTimeout(remove, timeoutMs);
  return remove;
}
