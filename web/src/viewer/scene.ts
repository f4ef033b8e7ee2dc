/**
 * The scene conventions every mode shares: frep-render's default lighting
 * and colours (`Lighting::default()` in crates/frep-render/src/image.rs),
 * so server images and client-drawn modes look alike, and the default
 * camera (frep-wire's `CameraView::default`).
 */
import type { CameraView } from '../wire';
import type { SceneConventions } from './types';

/** frep-render's `Lighting::default()`. */
export const SCENE: SceneConventions = {
  backgroundTop: [0.26, 0.29, 0.34],
  backgroundBottom: [0.09, 0.1, 0.12],
  baseColor: [0.72, 0.74, 0.78],
  sectionCap: [0.85, 0.45, 0.3],
  key: { dir: [-0.5, 0.7, 0.6], color: [0.85, 0.82, 0.78] },
  fill: { dir: [0.7, 0.1, 0.5], color: [0.22, 0.25, 0.3] },
  rim: { dir: [0.2, 0.4, -1.0], color: [0.15, 0.15, 0.15] },
  sky: [0.22, 0.24, 0.28],
  ground: [0.08, 0.07, 0.06],
  specular: 0.25,
  shininess: 40,
};

/** frep-wire's `CameraView::default()`. */
export const DEFAULT_CAMERA: CameraView = { yaw: 30, pitch: 20, fov: 30, zoom: 1, pan: [0, 0, 0] };

/** An sRGB 0..1 triple as CSS `rgb()`. */
export function cssColor(c: readonly [number, number, number]): string {
  const b = (v: number) => Math.round(Math.max(0, Math.min(1, v)) * 255);
  return `rgb(${b(c[0])}, ${b(c[1])}, ${b(c[2])})`;
}

/** The background gradient as CSS (the server's images use the same ramp, top to bottom). */
export function backgroundCss(s: SceneConventions = SCENE): string {
  return `linear-gradient(to bottom, ${cssColor(s.backgroundTop)}, ${cssColor(s.backgroundBottom)})`;
}

/** The background colour at a fraction `t` (0 top, 1 bottom) of the height, 0..255. */
export function backgroundAt(t: number, s: SceneConventions = SCENE): [number, number, number] {
  const u = Math.max(0, Math.min(1, t));
  const mix = (k: number) => Math.round(255 * (s.backgroundTop[k] + (s.backgroundBottom[k] - s.backgroundTop[k]) * u));
  return [mix(0), mix(1), mix(2)];
}
