/**
 * Pointer input on the viewer: left drag orbits, right drag (or shift +
 * drag, or two fingers) pans, the wheel zooms, a click without a drag
 * probes. The camera math is ./camera's; this file only turns events into
 * calls. `moving` is true while a drag lasts and briefly after a wheel
 * turn, so modes can draw cheaper frames meanwhile.
 */
import type { CameraView } from '../wire';
import { type Box6, orbit, panBy, zoomBy } from './camera';

/** What the controls drive. */
export interface ControlTarget {
  camera(): CameraView;
  bounds(): Box6;
  size(): { width: number; height: number };
  setCamera(c: CameraView, moving: boolean): void;
  /** The interaction ended (the camera is at rest). */
  rest(): void;
  click(x: number, y: number): void;
}

/** A drag shorter than this (CSS px) is a click. */
const CLICK_SLOP = 4;
/** ms after a wheel turn the camera counts as moving. */
const WHEEL_REST_MS = 220;

/** Binds the controls to `el`; returns the unbinding. */
export function bindControls(el: HTMLElement, t: ControlTarget): { dispose(): void; moving(): boolean } {
  let drag: { id: number; x: number; y: number; sx: number; sy: number; pan: boolean; moved: boolean } | null = null;
  let wheelTimer: ReturnType<typeof setTimeout> | null = null;
  let wheeling = false;
  const down = (e: PointerEvent) => {
    if (drag) return;
    drag = { id: e.pointerId, x: e.clientX, y: e.clientY, sx: e.clientX, sy: e.clientY, pan: e.button === 2 || e.button === 1 || e.shiftKey, moved: false };
    el.setPointerCapture?.(e.pointerId);
    e.preventDefault();
  };
  const move = (e: PointerEvent) => {
    if (!drag || e.pointerId !== drag.id) return;
    const dx = e.clientX - drag.x;
    const dy = e.clientY - drag.y;
    if (!drag.moved && Math.hypot(e.clientX - drag.sx, e.clientY - drag.sy) < CLICK_SLOP) return;
    drag.moved = true;
    drag.x = e.clientX;
    drag.y = e.clientY;
    const cam = t.camera();
    if (drag.pan) {
      const { width, height } = t.size();
      t.setCamera(panBy(cam, t.bounds(), width, height, dx, dy), true);
    } else t.setCamera(orbit(cam, dx, dy), true);
  };
  const up = (e: PointerEvent) => {
    if (!drag || e.pointerId !== drag.id) return;
    const d = drag;
    drag = null;
    el.releasePointerCapture?.(e.pointerId);
    if (d.moved) t.rest();
    else {
      const r = el.getBoundingClientRect();
      t.click(e.clientX - r.left, e.clientY - r.top);
    }
  };
  const wheel = (e: WheelEvent) => {
    e.preventDefault();
    wheeling = true;
    t.setCamera(zoomBy(t.camera(), Math.exp(-e.deltaY * 0.0015)), true);
    if (wheelTimer) clearTimeout(wheelTimer);
    wheelTimer = setTimeout(() => {
      wheeling = false;
      t.rest();
    }, WHEEL_REST_MS);
  };
  const menu = (e: Event) => e.preventDefault();
  el.addEventListener('pointerdown', down);
  el.addEventListener('pointermove', move);
  el.addEventListener('pointerup', up);
  el.addEventListener('pointercancel', up);
  el.addEventListener('wheel', wheel, { passive: false });
  el.addEventListener('contextmenu', menu);
  return {
    moving: () => !!drag?.moved || wheeling,
    dispose: () => {
      if (wheelTimer) clearTimeout(wheelTimer);
      el.removeEventListener('pointerdown', down);
      el.removeEventListener('pointermove', move);
      el.removeEventListener('pointerup', up);
      el.removeEventListener('pointercancel', up);
      el.removeEventListener('wheel', wheel);
      el.removeEventListener('contextmenu', menu);
    },
  };
}
