/**
 * The one camera of every mode, as numbers: frep-wire's {@link CameraView}
 * turned into an eye, a target, an orthonormal frame and a projection with
 * exactly the server ray caster's formulas (frep-render's `Camera::orbit`
 * and `RayMaker::ray_at`, with frep-artefact's zoom and pan), so a client
 * view and a server image of the same camera coincide pixel for pixel.
 *
 * Conventions (crates/frep-render/src/camera.rs): world z up; yaw 0 looks
 * along +y; yaw turns the eye counter-clockwise seen from above; pitch
 * raises it. The right vector comes from yaw alone, so pitch ±90° is well
 * defined. The bounding sphere of the model box fills the shorter side of
 * the image at zoom 1; the field of view (or the orthographic extent)
 * applies to the shorter side. Zoom divides the eye's distance
 * (perspective) or the half extent (orthographic); pan moves the target
 * and the eye together; an orthographic eye sits 2r + |pan| from the target
 * (crates/frep-artefact/src/camera.rs).
 *
 * Also the interactions on a camera (orbit, pan, zoom, standard views,
 * fit), pure functions of a CameraView.
 */
import type { CameraView } from '../wire';

/** A 3-vector. */
export type Vec3 = [number, number, number];
/** A model box `[x0, y0, z0, x1, y1, z1]`. */
export type Box6 = readonly number[];

/** The camera of one viewport: frame and projection. */
export interface CameraFrame {
  /** Eye (orthographic: centre of the plane the rays start from). */
  eye: Vec3;
  /** The point looked at (box centre + pan). */
  target: Vec3;
  /** Unit vectors: right, up (in the image) and forward (eye to target). */
  right: Vec3;
  up: Vec3;
  forward: Vec3;
  /** Whether the projection is perspective. */
  perspective: boolean;
  /** tan(fov/2) (perspective) or the half extent (orthographic) across the shorter side. */
  k: number;
  /** Vertical field of view in degrees (three.js's `fov`), perspective only. */
  fovY: number;
  /** Half the world extent across the width and the height (orthographic). */
  halfWidth: number;
  halfHeight: number;
  /** Distance from the eye to the target. */
  distance: number;
  /** Near and far planes that hold the whole box (three.js). */
  near: number;
  far: number;
  /** The viewport in pixels. */
  width: number;
  height: number;
}

/** A ray: origin and unit direction. */
export interface Ray {
  origin: Vec3;
  dir: Vec3;
}

const deg = Math.PI / 180;

function add(a: Vec3, b: Vec3): Vec3 {
  return [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
}
function sub(a: Vec3, b: Vec3): Vec3 {
  return [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
}
function scale(a: Vec3, s: number): Vec3 {
  return [a[0] * s, a[1] * s, a[2] * s];
}
function cross(a: Vec3, b: Vec3): Vec3 {
  return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
}
function length(a: Vec3): number {
  return Math.hypot(a[0], a[1], a[2]);
}
function normalize(a: Vec3): Vec3 {
  const l = length(a);
  return l > 0 ? scale(a, 1 / l) : a;
}

/** The centre of a box. */
export function boxCenter(b: Box6): Vec3 {
  return [0.5 * (b[0] + b[3]), 0.5 * (b[1] + b[4]), 0.5 * (b[2] + b[5])];
}

/** The radius of a box's bounding sphere (half the diagonal; frep-render's `Aabb::radius`). */
export function boxRadius(b: Box6): number {
  return 0.5 * Math.hypot(b[3] - b[0], b[4] - b[1], b[5] - b[2]);
}

/** Smallest zoom allowed, and largest. */
export const ZOOM_MIN = 0.05;
export const ZOOM_MAX = 200;
/** Pitch stays strictly inside ±90° while orbiting by drag (standard views may reach it). */
export const PITCH_LIMIT = 89.9;

/** The frame and projection of `view` for a `width`×`height` viewport framing `bounds`. */
export function cameraFrame(view: CameraView, bounds: Box6, width: number, height: number): CameraFrame {
  const r = Math.max(boxRadius(bounds), 1e-12);
  const fin = (v: number | undefined) => (v !== undefined && Number.isFinite(v) ? v : 0);
  const pan: Vec3 = [fin(view.pan[0]), fin(view.pan[1]), fin(view.pan[2])];
  const target = add(boxCenter(bounds), pan);
  const yaw = view.yaw * deg;
  const pitch = view.pitch * deg;
  const back: Vec3 = [Math.cos(pitch) * Math.sin(yaw), -Math.cos(pitch) * Math.cos(yaw), Math.sin(pitch)];
  const right: Vec3 = [Math.cos(yaw), Math.sin(yaw), 0];
  const forward = scale(back, -1);
  const up = normalize(cross(right, forward));
  const zoom = view.zoom > 0 && Number.isFinite(view.zoom) ? view.zoom : 1;
  const w = Math.max(1, width);
  const h = Math.max(1, height);
  const short = Math.min(w, h);
  const perspective = view.fov !== null && view.fov !== undefined;
  let distance: number;
  let k: number;
  if (perspective) {
    const half = 0.5 * Math.min(179, Math.max(1e-3, view.fov as number)) * deg;
    distance = r / Math.sin(half) / zoom;
    k = Math.tan(0.5 * (view.fov as number) * deg);
  } else {
    // In front of the whole box wherever it is panned to (frep-artefact's camera).
    distance = 2 * r + length(pan);
    k = r / zoom;
  }
  const eye = add(target, scale(back, distance));
  // The whole box lies within r of its centre; the centre is |pan| from the target.
  const reach = r * 1.02 + length(pan);
  const far = distance + reach;
  // Orthographic near may be negative (three.js allows it): the box may reach behind the ray plane.
  const near = perspective ? Math.max(far * 1e-4, distance - reach) : distance - reach;
  return {
    eye,
    target,
    right,
    up,
    forward,
    perspective,
    k,
    fovY: perspective ? (2 * Math.atan((k * h) / short)) / deg : 0,
    halfWidth: perspective ? 0 : (k * w) / short,
    halfHeight: perspective ? 0 : (k * h) / short,
    distance,
    near,
    far,
    width: w,
    height: h,
  };
}

/**
 * The ray through the continuous image point `(x, y)` (pixels, (0, 0) the
 * top-left corner, y down): frep-render's `RayMaker::ray_at`.
 */
export function rayAt(f: CameraFrame, x: number, y: number): Ray {
  const s = 0.5 * Math.min(f.width, f.height);
  const u = (x - 0.5 * f.width) / s;
  const v = (0.5 * f.height - y) / s;
  const side = add(scale(f.right, u * f.k), scale(f.up, v * f.k));
  if (f.perspective) return { origin: f.eye, dir: normalize(add(f.forward, side)) };
  return { origin: add(f.eye, side), dir: f.forward };
}

/**
 * Where a world point lands in the image (pixels, y down), the inverse of
 * {@link rayAt}; null behind a perspective eye.
 */
export function project(f: CameraFrame, p: Vec3): [number, number] | null {
  const d = sub(p, f.eye);
  const z = d[0] * f.forward[0] + d[1] * f.forward[1] + d[2] * f.forward[2];
  const xr = d[0] * f.right[0] + d[1] * f.right[1] + d[2] * f.right[2];
  const yu = d[0] * f.up[0] + d[1] * f.up[1] + d[2] * f.up[2];
  const s = 0.5 * Math.min(f.width, f.height);
  if (f.perspective) {
    if (z <= 0) return null;
    return [0.5 * f.width + (xr / z / f.k) * s, 0.5 * f.height - (yu / z / f.k) * s];
  }
  return [0.5 * f.width + (xr / f.k) * s, 0.5 * f.height - (yu / f.k) * s];
}

/** Orbits by a drag of `(dx, dy)` CSS pixels (0.4° a pixel; dragging right turns the model right). */
export function orbit(view: CameraView, dx: number, dy: number, degPerPixel = 0.4): CameraView {
  const yaw = wrapDegrees(view.yaw - dx * degPerPixel);
  const pitch = Math.max(-PITCH_LIMIT, Math.min(PITCH_LIMIT, view.pitch + dy * degPerPixel));
  return { ...view, yaw, pitch };
}

/** Multiplies the zoom by `factor` (clamped to [ZOOM_MIN, ZOOM_MAX]). */
export function zoomBy(view: CameraView, factor: number): CameraView {
  const zoom = Math.max(ZOOM_MIN, Math.min(ZOOM_MAX, view.zoom * factor));
  return { ...view, zoom };
}

/** Pans by a drag of `(dx, dy)` pixels of a `width`×`height` viewport: the point under the cursor follows it at the target's depth. */
export function panBy(view: CameraView, bounds: Box6, width: number, height: number, dx: number, dy: number): CameraView {
  const f = cameraFrame(view, bounds, width, height);
  const s = 0.5 * Math.min(f.width, f.height);
  const perPixel = f.perspective ? (f.distance * f.k) / s : f.k / s;
  const move = add(scale(f.right, -dx * perPixel), scale(f.up, dy * perPixel));
  return { ...view, pan: [view.pan[0] + move[0], view.pan[1] + move[1], view.pan[2] + move[2]] };
}

/** The standard views. */
export type StandardView = 'front' | 'back' | 'left' | 'right' | 'top' | 'bottom' | 'iso';

/** A standard view keeps the projection and zoom, and recentres. */
export function standardView(view: CameraView, which: StandardView): CameraView {
  const angles: Record<StandardView, [number, number]> = {
    front: [0, 0],
    back: [180, 0],
    right: [90, 0],
    left: [-90, 0],
    top: [0, 90],
    bottom: [0, -90],
    iso: [45, 35.264],
  };
  const [yaw, pitch] = angles[which];
  return { ...view, yaw, pitch, pan: [0, 0, 0] };
}

/** Zoom to fit: the box's bounding sphere fills the shorter side again. */
export function fitView(view: CameraView): CameraView {
  return { ...view, zoom: 1, pan: [0, 0, 0] };
}

/** Degrees into (-180, 180]. */
export function wrapDegrees(d: number): number {
  let x = ((d % 360) + 360) % 360;
  if (x > 180) x -= 360;
  return x;
}

/** Whether two cameras are the same view (within rounding). */
export function sameCamera(a: CameraView, b: CameraView, eps = 1e-9): boolean {
  const close = (x: number, y: number) => Math.abs(x - y) <= eps * Math.max(1, Math.abs(x), Math.abs(y));
  return (
    close(wrapDegrees(a.yaw), wrapDegrees(b.yaw)) &&
    close(a.pitch, b.pitch) &&
    (a.fov ?? null) === (b.fov ?? null) &&
    close(a.zoom, b.zoom) &&
    close(a.pan[0], b.pan[0]) &&
    close(a.pan[1], b.pan[1]) &&
    close(a.pan[2], b.pan[2])
  );
}
