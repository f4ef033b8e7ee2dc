/**
 * Dimensions on demand: the model box's edges drawn over the view (SVG, the
 * box's corners projected with the shared camera) and its sizes written on
 * three edges that meet at a visible corner.
 */
import type { CameraView } from '../wire';
import { type Box6, type Vec3, cameraFrame, project } from './camera';

const SVG = 'http://www.w3.org/2000/svg';

/** The sizes of a box along x, y, z. */
export function boxSizes(b: Box6): [number, number, number] {
  return [b[3] - b[0], b[4] - b[1], b[5] - b[2]];
}

/** A length for labels: 4 significant digits. */
export function formatLength(v: number): string {
  return Number(v.toPrecision(4)).toString();
}

/** The overlay. */
export class DimensionsOverlay {
  readonly element: SVGSVGElement;

  constructor() {
    this.element = document.createElementNS(SVG, 'svg');
    this.element.setAttribute('class', 'frep-dimensions');
    this.element.dataset.testid = 'dimensions';
  }

  /** Redraws for a camera, a box and the viewport (CSS px). */
  draw(view: CameraView, b: Box6, width: number, height: number): void {
    const f = cameraFrame(view, b, width, height);
    this.element.setAttribute('viewBox', `0 0 ${width} ${height}`);
    const corner = (i: number): Vec3 => [i & 1 ? b[3] : b[0], i & 2 ? b[4] : b[1], i & 4 ? b[5] : b[2]];
    const pts = Array.from({ length: 8 }, (_, i) => project(f, corner(i)));
    const kids: SVGElement[] = [];
    for (let i = 0; i < 8; i++)
      for (const bit of [1, 2, 4]) {
        const j = i | bit;
        if (j === i) continue;
        const a = pts[i];
        const c = pts[j];
        if (!a || !c) continue;
        const line = document.createElementNS(SVG, 'line');
        line.setAttribute('x1', String(a[0]));
        line.setAttribute('y1', String(a[1]));
        line.setAttribute('x2', String(c[0]));
        line.setAttribute('y2', String(c[1]));
        kids.push(line);
      }
    // Label the three edges from the corner nearest the eye.
    let near = 0;
    let best = Infinity;
    for (let i = 0; i < 8; i++) {
      const p = corner(i);
      const d = Math.hypot(p[0] - f.eye[0], p[1] - f.eye[1], p[2] - f.eye[2]);
      if (d < best) {
        best = d;
        near = i;
      }
    }
    const sizes = boxSizes(b);
    ['x', 'y', 'z'].forEach((axis, k) => {
      const other = near ^ (1 << k);
      const a = pts[near];
      const c = pts[other];
      if (!a || !c) return;
      const t = document.createElementNS(SVG, 'text');
      t.setAttribute('x', String(0.5 * (a[0] + c[0])));
      t.setAttribute('y', String(0.5 * (a[1] + c[1])));
      t.textContent = `${axis} ${formatLength(sizes[k])}`;
      t.dataset.axis = axis;
      kids.push(t);
    });
    this.element.replaceChildren(...kids);
  }
}
