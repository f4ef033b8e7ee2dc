/**
 * The seed paper's baseline in the page: uniform marching cubes at a fixed
 * low resolution by the WebAssembly kernel (frep-wasm's `mc` method:
 * frep-mesh's uniform grid, no pruning) in the kernel worker, drawn with
 * three.js on the viewer's stage. Loaded on demand by paper-harness.ts so
 * that the viewer's modes keep their own code chunks (and pay for them).
 */
import * as THREE from 'three';
import { sharedKernelReady } from '../src/wasm/client';
import { applyCamera, createStage, type ThreeStage } from '../src/viewer/three-scene';
import { meshGeometry } from '../src/viewer/modes/wasmmesh';
import type { CameraView } from '../src/wire';

const CAMERA: CameraView = { yaw: 30, pitch: 20, fov: 30, zoom: 1, pan: [0, 0, 0] };

let stage: ThreeStage | null = null;
let shown: { bounds: number[]; size: number } | null = null;

const painted = () => new Promise<void>((r) => requestAnimationFrame(() => requestAnimationFrame(() => r())));

type Box6 = Parameters<typeof applyCamera>[2];

/** Uniform marching cubes at `depth` (2^depth cells a side), drawn once; `t0` is the request's time. */
export async function baseline(t0: number, size: number, source: string, params: number[], depth: number): Promise<{ ms: number; meshMs: number; triangles: number }> {
  const kernel = await sharedKernelReady();
  const pass = await kernel.mesh({ source, params, bounds: null, depths: [depth], method: 'mc' }, () => {});
  const box = document.createElement('div');
  box.dataset.testid = 'baseline';
  box.style.cssText = `position:relative;width:${size}px;height:${size}px;background:#fff`;
  document.body.style.margin = '0';
  document.body.append(box);
  const canvas = document.createElement('canvas');
  canvas.style.cssText = `width:${size}px;height:${size}px;display:block`;
  box.append(canvas);
  stage = createStage(canvas);
  stage.renderer.setPixelRatio(devicePixelRatio);
  stage.renderer.setSize(size, size, false);
  const geom = meshGeometry(pass.mesh);
  const mat = new THREE.MeshStandardMaterial({ color: geom.getAttribute('color') ? 0xffffff : 0xb0b8c8, vertexColors: !!geom.getAttribute('color'), roughness: 0.6 });
  stage.scene.add(new THREE.Mesh(geom, mat));
  shown = { bounds: pass.bounds.slice(), size };
  applyCamera(stage, CAMERA, shown.bounds as unknown as Box6, size, size);
  stage.renderer.render(stage.scene, stage.camera);
  await painted();
  return { ms: performance.now() - t0, meshMs: pass.ms, triangles: pass.mesh.indices.length / 3 };
}

/** Turns the baseline's mesh for `ms` milliseconds; the median and mean ms per frame. */
export async function orbitBaseline(ms: number): Promise<{ frameMs: number; meanMs: number; frames: number }> {
  if (!stage || !shown) throw new Error('no baseline shown');
  const s = stage;
  const { bounds, size } = shown;
  const times: number[] = [];
  const t0 = performance.now();
  let yaw = CAMERA.yaw;
  while (performance.now() - t0 < ms) {
    yaw += 3;
    applyCamera(s, { ...CAMERA, yaw }, bounds as unknown as Box6, size, size);
    s.renderer.render(s.scene, s.camera);
    await new Promise<void>((r) => requestAnimationFrame(() => r()));
    times.push(performance.now());
  }
  const gaps = times.slice(1).map((t, i) => t - times[i]!).sort((a, b) => a - b);
  const n = times.length;
  return {
    frameMs: gaps.length ? gaps[Math.floor(gaps.length / 2)]! : NaN,
    meanMs: n > 1 ? (times[n - 1]! - times[0]!) / (n - 1) : NaN,
    frames: n,
  };
}

