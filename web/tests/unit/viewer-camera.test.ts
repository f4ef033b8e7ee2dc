import * as THREE from 'three';
import { describe, expect, it } from 'vitest';
import {
  cameraFrame,
  fitView,
  orbit,
  panBy,
  PITCH_LIMIT,
  project,
  rayAt,
  sameCamera,
  standardView,
  type Vec3,
  wrapDegrees,
  zoomBy,
} from '../../src/viewer/camera';
import { applyCamera, clippingPlane } from '../../src/viewer/three-scene';
import type { CameraView } from '../../src/wire';
import { RUST_CAMERAS } from './viewer-camera-rust';

const close = (a: readonly number[], b: readonly number[], eps = 1e-9) => {
  expect(a.length).toBe(b.length);
  a.forEach((v, i) => expect(Math.abs(v - b[i])).toBeLessThanOrEqual(eps * Math.max(1, Math.abs(b[i]))));
};
const sub = (a: Vec3, b: Vec3): Vec3 => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const dot = (a: Vec3, b: Vec3) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cube = [-1, -1, -1, 1, 1, 1];

describe('camera equals the server ray caster (numbers printed by frep-artefact::camera::camera)', () => {
  for (const [i, c] of RUST_CAMERAS.entries()) {
    it(`camera ${i}: ${JSON.stringify(c.view)} at ${c.width}x${c.height}`, () => {
      const f = cameraFrame(c.view, c.bounds, c.width, c.height);
      close(f.eye, c.eye);
      close(f.target, c.target);
      close(f.up, c.up);
      close(f.right, c.right);
      close(f.forward, c.forward);
      expect(f.perspective).toBe(c.perspective);
      if (!c.perspective) expect(f.k).toBeCloseTo(c.projection, 12);
      for (const r of c.rays) {
        const ray = rayAt(f, r.x, r.y);
        close(ray.origin, r.origin);
        close(ray.dir, r.dir);
      }
    });
  }
});

describe('framing', () => {
  it('at zoom 1 the bounding sphere touches the shorter side (perspective and orthographic)', () => {
    const b = [-2, 0, -1, 4, 3, 5];
    const r = 0.5 * Math.hypot(6, 3, 6);
    const c: Vec3 = [1, 1.5, 2];
    for (const fov of [30, 60, null]) {
      for (const [w, h] of [[300, 200], [200, 300]]) {
        const f = cameraFrame({ yaw: 40, pitch: 25, fov, zoom: 1, pan: [0, 0, 0] }, b, w, h);
        const s = 0.5 * Math.min(w, h);
        const edge = w < h ? rayAt(f, w / 2 + s, h / 2) : rayAt(f, w / 2, h / 2 - s);
        // Distance from the centre to the edge ray equals the radius.
        const oc = sub(c, edge.origin);
        const t = dot(oc, edge.dir);
        const d = Math.sqrt(Math.max(0, dot(oc, oc) - t * t));
        expect(d).toBeCloseTo(r, 9);
        const centre = project(f, c)!;
        expect(centre[0]).toBeCloseTo(w / 2, 9);
        expect(centre[1]).toBeCloseTo(h / 2, 9);
      }
    }
  });

  it('zoom 2 halves the seen extent; pan moves the target', () => {
    const f1 = cameraFrame({ yaw: 0, pitch: 0, fov: null, zoom: 1, pan: [0, 0, 0] }, cube, 100, 100);
    const f2 = cameraFrame({ yaw: 0, pitch: 0, fov: null, zoom: 2, pan: [0.5, 0, 0] }, cube, 100, 100);
    expect(f2.k).toBeCloseTo(f1.k / 2, 12);
    close(f2.target, [0.5, 0, 0]);
    // An orthographic eye stays in front of the panned box.
    expect(f2.distance).toBeCloseTo(2 * Math.sqrt(3) + 0.5, 12);
  });

  it('pitch 90 looks straight down with +x to the right at yaw 0', () => {
    const f = cameraFrame({ yaw: 0, pitch: 90, fov: 30, zoom: 1, pan: [0, 0, 0] }, cube, 64, 64);
    close(f.forward, [0, 0, -1], 1e-12);
    close(f.right, [1, 0, 0], 1e-12);
    close(f.up, [0, 1, 0], 1e-12);
  });
});

describe('three.js camera matches the frame', () => {
  const views: CameraView[] = [
    { yaw: 30, pitch: 20, fov: 30, zoom: 1, pan: [0, 0, 0] },
    { yaw: -120, pitch: 65, fov: 50, zoom: 3, pan: [0.2, -0.4, 0.1] },
    { yaw: 200, pitch: -40, fov: null, zoom: 0.7, pan: [0, 1, 0] },
  ];
  for (const v of views)
    for (const [w, h] of [[320, 180], [180, 320]]) {
      it(`projects like the ray caster: ${JSON.stringify(v)} ${w}x${h}`, () => {
        const stage = {
          renderer: null as unknown as THREE.WebGLRenderer,
          scene: new THREE.Scene(),
          camera: new THREE.PerspectiveCamera() as THREE.PerspectiveCamera | THREE.OrthographicCamera,
          lights: new THREE.Group(),
        };
        stage.camera.add(stage.lights);
        stage.scene.add(stage.camera);
        applyCamera(stage, v, cube, w, h);
        const f = cameraFrame(v, cube, w, h);
        for (const p of [[0, 0, 0], [0.9, -0.3, 0.4], [-1, 1, -1], [0.2, 0.8, 1]] as Vec3[]) {
          const ndc = new THREE.Vector3(...p).project(stage.camera);
          const px = [(ndc.x + 1) * 0.5 * w, (1 - ndc.y) * 0.5 * h];
          const want = project(f, p)!;
          expect(px[0]).toBeCloseTo(want[0], 6);
          expect(px[1]).toBeCloseTo(want[1], 6);
          expect(ndc.z).toBeGreaterThan(-1);
          expect(ndc.z).toBeLessThan(1);
        }
      });
    }

  it('a section keeps the side behind the plane', () => {
    const p = clippingPlane({ normal: [0, 1, 0], offset: 0.25 });
    expect(p.distanceToPoint(new THREE.Vector3(0, 0, 0))).toBeGreaterThan(0);
    expect(p.distanceToPoint(new THREE.Vector3(0, 0.5, 0))).toBeLessThan(0);
  });
});

describe('interactions', () => {
  const base: CameraView = { yaw: 30, pitch: 20, fov: 30, zoom: 1, pan: [0, 0, 0] };

  it('orbit turns yaw and pitch, pitch clamped', () => {
    const o = orbit(base, 10, -5, 0.5);
    expect(o.yaw).toBeCloseTo(25, 12);
    expect(o.pitch).toBeCloseTo(17.5, 12);
    expect(orbit(base, 0, 1000).pitch).toBe(PITCH_LIMIT);
    expect(orbit(base, 0, -1000).pitch).toBe(-PITCH_LIMIT);
    expect(orbit({ ...base, yaw: 179 }, -10, 0, 1).yaw).toBeCloseTo(-171, 12);
  });

  it('zoom multiplies within limits', () => {
    expect(zoomBy(base, 2).zoom).toBe(2);
    expect(zoomBy(base, 1e-9).zoom).toBeGreaterThan(0);
    expect(zoomBy(base, 1e9).zoom).toBeLessThan(1e9);
  });

  it('pan keeps the point under the cursor under it', () => {
    for (const fov of [30, null]) {
      const v = { ...base, fov, zoom: 1.7 };
      const f0 = cameraFrame(v, cube, 400, 300);
      const moved = panBy(v, cube, 400, 300, 37, -21);
      const f1 = cameraFrame(moved, cube, 400, 300);
      const at = project(f1, f0.target)!;
      expect(at[0]).toBeCloseTo(200 + 37, 6);
      expect(at[1]).toBeCloseTo(150 - 21, 6);
    }
  });

  it('standard views and fit', () => {
    const front = cameraFrame(standardView(base, 'front'), cube, 10, 10);
    expect(front.eye[1]).toBeLessThan(0);
    const right = cameraFrame(standardView(base, 'right'), cube, 10, 10);
    expect(right.eye[0]).toBeGreaterThan(0);
    const top = cameraFrame(standardView(base, 'top'), cube, 10, 10);
    expect(top.eye[2]).toBeGreaterThan(0);
    const fitted = fitView({ ...base, zoom: 5, pan: [1, 2, 3] });
    expect(fitted).toEqual({ ...base, zoom: 1, pan: [0, 0, 0] });
  });

  it('wraps degrees and compares cameras', () => {
    expect(wrapDegrees(190)).toBe(-170);
    expect(wrapDegrees(-190)).toBe(170);
    expect(wrapDegrees(180)).toBe(180);
    expect(sameCamera(base, { ...base, yaw: 390 })).toBe(true);
    expect(sameCamera(base, { ...base, fov: null })).toBe(false);
  });
});
