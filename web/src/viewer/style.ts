/**
 * The viewer's own CSS, injected once (the viewer is a self-contained part
 * of the page): the layers stacked over the background gradient, the badge,
 * the toolbar, the panel and the overlays.
 */
import { backgroundCss } from './scene';

const CSS = `
.frep-viewer { position: relative; overflow: hidden; width: 100%; height: 100%; min-height: 120px; user-select: none; touch-action: none; font: 12px system-ui, sans-serif; color: #e6e8eb; }
.frep-viewer .frep-layer { position: absolute; inset: 0; }
.frep-viewer .frep-mode-canvas { position: absolute; inset: 0; width: 100%; height: 100%; display: block; }
.frep-viewer .frep-input { position: absolute; inset: 0; cursor: grab; }
.frep-viewer .frep-input:active { cursor: grabbing; }
.frep-viewer .frep-badge { position: absolute; left: 8px; top: 8px; max-width: 60%; background: rgba(0,0,0,.55); border-radius: 6px; padding: 4px 8px; }
.frep-viewer .frep-badge b { display: block; }
.frep-viewer .frep-badge .frep-reason { opacity: .85; white-space: normal; }
.frep-viewer .frep-badge select { margin-top: 4px; font: inherit; background: rgba(0,0,0,.55); color: inherit; border: 1px solid rgba(255,255,255,.2); border-radius: 4px; }
.frep-viewer .frep-tools { position: absolute; right: 8px; top: 8px; display: flex; gap: 4px; flex-wrap: wrap; justify-content: flex-end; max-width: 50%; }
.frep-viewer .frep-tools button, .frep-viewer .frep-tools select { font: inherit; background: rgba(0,0,0,.55); color: inherit; border: 1px solid rgba(255,255,255,.2); border-radius: 4px; padding: 2px 6px; }
.frep-viewer .frep-tools button[aria-pressed=true] { background: rgba(80,140,255,.6); }
.frep-viewer .frep-section { flex-basis: 100%; display: flex; justify-content: flex-end; gap: 4px; }
.frep-viewer .frep-section[hidden] { display: none; }
.frep-viewer .frep-section > * { background: rgba(0,0,0,.55); }
.frep-viewer .frep-measure-panel { position: absolute; right: 8px; bottom: 8px; background: rgba(0,0,0,.55); border-radius: 6px; padding: 4px; }
.frep-viewer .frep-measure-legend { display: flex; gap: 8px; }
.frep-viewer .frep-probe { position: absolute; left: 8px; bottom: 8px; background: rgba(0,0,0,.55); border-radius: 4px; padding: 2px 6px; white-space: pre; }
.frep-viewer .frep-status { position: absolute; left: 50%; top: 8px; transform: translateX(-50%); background: rgba(0,0,0,.55); border-radius: 4px; padding: 2px 6px; }
.frep-viewer .frep-status:empty, .frep-viewer .frep-probe:empty { display: none; }
.frep-viewer .frep-dimensions { position: absolute; inset: 0; width: 100%; height: 100%; pointer-events: none; }
.frep-viewer .frep-dimensions line { stroke: #ffd166; stroke-width: 1; stroke-dasharray: 4 3; }
.frep-viewer .frep-dimensions text { fill: #ffd166; font: 12px system-ui, sans-serif; paint-order: stroke; stroke: #000; stroke-width: 3px; }
`;

/** Adds the viewer's CSS to the document once; returns the background for the root. */
export function injectStyle(doc: Document = document): string {
  if (!doc.getElementById('frep-viewer-style')) {
    const el = doc.createElement('style');
    el.id = 'frep-viewer-style';
    el.textContent = CSS;
    doc.head.append(el);
  }
  return backgroundCss();
}
