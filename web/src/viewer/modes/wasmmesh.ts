/**
 * Mode 4b: the model polygonized in the browser by the WebAssembly kernel
 * (frep-mesh, the server's mesher) in a Web Worker, coarse first and then
 * refined, drawn with three.js on the viewer's shared stage
 * (three-scene.ts: the server camera, lights and section plane).
 *
 * A new model or new parameters start a new mesh request; the worker
 * drops the older one between its passes (coarse, refined), and a pass
 * that arrives for a superseded request is not shown. The previous mesh
 * stays on screen until the new coarse pass replaces it.
 */
import * as THREE from 'three';
import type { CameraView, Mode } from '../../wire';
import type { ModeContext, ModeModel, ModeView, ProbeResult, SectionPlane } from '../types';
import { applyCamera, clippingPlane, createStage, type ThreeStage } from '../three-scene';
import type { KernelClient, MeshPass } from '../../wasm/client';
import type { KernelMesh } from '../../wasm/kernel';

/** Depths of mode 4b when the decision gives none: coarse, then refined. */
export const DEFAULT_DEPTHS = { coarse: 5, fine: 7 };

/** Deepest mesh made in the browser (2^8 cells a side: memory and time). */
export const MAX_BROWSER_DEPTH = 8;

/** The coarse-then-refined depths for a decision's settings. */
export function meshDepths(settings: { meshDepth: number; coarseDepth: number } | null): number[] {
  const fine = Math.min(MAX_BROWSER_DEPTH, settings?.meshDepth || DEFAULT_DEPTHS.fine);
  const coarse = Math.min(fine, settings?.coarseDepth || DEFAULT_DEPTHS.coarse);
  return coarse < fine ? [coarse, fine] : [fine];
}

/** A three.js geometry of a kernel mesh (normals computed when absent). */
export function meshGeometry(m: KernelMesh): THREE.BufferGeometry {
  const g = new THREE.BufferGeometry();
  g.setAttribute('position', new THREE.BufferAttribute(m.positions, 3));
  if (m.normals) g.setAttribute('normal', new THREE.BufferAttribute(m.normals, 3));
  if (m.colors) {
    // Attribute colours are sRGB (as the server's renderer reads them).
    const lin = new Float32Array(m.colors.length);
    const c = new THREE.Color();
    for (let i = 0; i < m.colors.length; i += 3) {
      c.setRGB(m.colors[i]!, m.colors[i + 1]!, m.colors[i + 2]!, THREE.SRGBColorSpace);
      lin[i] = c.r;
      lin[i + 1] = c.g;
      lin[i + 2] = c.b;
    }
    g.setAttribute('color', new THREE.BufferAttribute(lin, 3));
  }
  g.setIndex(new THREE.BufferAttribute(m.indices, 1));
  if (!m.normals) g.computeVertexNormals();
  g.computeBoundingSphere();
  return g;
}

class WasmMeshView implements ModeView {
  readonly mode: Mode = 'wasmMesh';
  private ctx!: ModeContext;
  private canvas!: HTMLCanvasElement;
  private stage!: ThreeStage;
  private mesh: THREE.Mesh | null = null;
  private capMesh: THREE.Mesh | null = null;
  private readonly material: THREE.MeshPhongMaterial;
  private readonly cap: THREE.MeshBasicMaterial;
  private section: SectionPlane | null = null;
  private bounds: number[] = [-1, -1, -1, 1, 1, 1];
  private kernel: KernelClient | null = null;
  private raf = 0;
  private request = 0;
  private disposed = false;

  constructor(private readonly kernelFor: () => Promise<KernelClient> = defaultKernel) {
    this.material = new THREE.MeshPhongMaterial({ side: THREE.FrontSide });
    this.cap = new THREE.MeshBasicMaterial({ side: THREE.BackSide });
  }

  async mount(ctx: ModeContext): Promise<void> {
    this.ctx = ctx;
    const s = ctx.scene;
    this.material.color.setRGB(s.baseColor[0], s.baseColor[1], s.baseColor[2], THREE.SRGBColorSpace);
    this.material.specular = new THREE.Color(s.specular, s.specular, s.specular);
    this.material.shininess = s.shininess;
    this.cap.color.setRGB(s.sectionCap[0], s.sectionCap[1], s.sectionCap[2], THREE.SRGBColorSpace);
    const canvas = document.createElement('canvas');
    canvas.style.cssText = 'position:absolute;inset:0;width:100%;height:100%;display:block';
    this.canvas = canvas;
    this.stage = createStage(canvas, s);
    ctx.container.appendChild(canvas);
    ctx.container.dataset.mode = 'wasmMesh';
    this.kernel = await this.kernelFor();
  }

  async show(model: ModeModel): Promise<void> {
    const kernel = this.kernel;
    if (!kernel) throw new Error('mode 4b is not mounted');
    const id = ++this.request;
    const depths = meshDepths(model.settings);
    // A superseded request stops at its next pass (unless a newer one,
    // which supersedes it anyway, was already sent).
    const stop = (): void => {
      if (id === this.request) kernel.cancel('mesh');
    };
    model.signal.addEventListener('abort', stop, { once: true });
    let first: (() => void) | null = null;
    const firstShown = new Promise<void>((r) => (first = r));
    const onPass = (p: MeshPass): void => {
      if (id !== this.request || model.signal.aborted || this.disposed) return;
      this.replace(p, model.bounds.slice());
      this.ctx.container.dataset.depth = String(p.depth);
      this.ctx.container.dataset.triangles = String(p.mesh.triangles);
      this.ctx.progress(`wasm-mesh-${id}`, p.final ? 1 : 0.5);
      if (first) {
        first();
        first = null;
        this.ctx.displayed(0);
      }
    };
    const done = kernel
      .mesh({ source: model.show.source, params: model.show.params, bounds: model.bounds.slice(), depths }, onPass)
      .finally(() => model.signal.removeEventListener('abort', stop));
    // The first (coarse) pass displayed, or the request failed first.
    await Promise.race([firstShown, done.then(() => undefined)]);
    done.catch((e: unknown) => {
      if (id === this.request && !model.signal.aborted) this.ctx.failed(e instanceof Error ? e.message : String(e));
    });
  }

  private replace(p: MeshPass, bounds: number[]): void {
    const geometry = meshGeometry(p.mesh);
    const colored = p.mesh.colors !== null;
    if (this.material.vertexColors !== colored) {
      this.material.vertexColors = colored;
      // Vertex colours multiply the material's: white then (mode 3's rule).
      const s = this.ctx.scene;
      if (colored) this.material.color.setRGB(1, 1, 1);
      else this.material.color.setRGB(s.baseColor[0], s.baseColor[1], s.baseColor[2], THREE.SRGBColorSpace);
      this.material.needsUpdate = true;
    }
    if (this.mesh && this.capMesh) {
      this.mesh.geometry.dispose();
      this.mesh.geometry = geometry;
      this.capMesh.geometry = geometry;
    } else {
      this.mesh = new THREE.Mesh(geometry, this.material);
      this.capMesh = new THREE.Mesh(geometry, this.cap);
      this.stage.scene.add(this.mesh, this.capMesh);
    }
    this.capMesh.visible = this.section !== null;
    this.bounds = bounds;
    this.render();
  }

  setCamera(_c: CameraView): void {
    this.render();
  }

  setParams(_p: number[]): void {
    // The viewer calls show() with the new parameters: a new mesh.
  }

  setSection(s: SectionPlane | null): void {
    this.section = s;
    const planes = s ? [clippingPlane(s)] : [];
    this.material.clippingPlanes = planes;
    this.cap.clippingPlanes = planes;
    // Back faces show only where the section opens the solid.
    if (this.capMesh) this.capMesh.visible = s !== null;
    this.render();
  }

  async probe(x: number, y: number): Promise<ProbeResult | null> {
    if (!this.mesh) return null;
    const { width, height } = this.ctx.size();
    applyCamera(this.stage, this.ctx.camera(), this.bounds, width, height);
    const ray = new THREE.Raycaster();
    ray.setFromCamera(new THREE.Vector2((2 * x) / width - 1, 1 - (2 * y) / height), this.stage.camera);
    const sec = this.section;
    const hit = ray
      .intersectObject(this.mesh, false)
      .find((h) => !sec || sec.normal[0] * h.point.x + sec.normal[1] * h.point.y + sec.normal[2] * h.point.z <= sec.offset);
    if (!hit) return null;
    return { point: [hit.point.x, hit.point.y, hit.point.z], value: null, attributes: [], source: 'mesh' };
  }

  resize(_w: number, _h: number): void {
    this.render();
  }

  private render(): void {
    if (this.raf || this.disposed) return;
    this.raf = requestAnimationFrame(() => {
      this.raf = 0;
      if (this.disposed) return;
      const size = this.ctx.size();
      this.stage.renderer.setPixelRatio(size.pixelRatio);
      this.stage.renderer.setSize(size.width, size.height, false);
      applyCamera(this.stage, this.ctx.camera(), this.bounds, size.width, size.height);
      this.stage.renderer.render(this.stage.scene, this.stage.camera);
      this.ctx.frame();
    });
  }

  dispose(): void {
    this.disposed = true;
    if (this.raf) cancelAnimationFrame(this.raf);
    this.kernel?.cancel('mesh');
    this.mesh?.geometry.dispose();
    this.material.dispose();
    this.cap.dispose();
    this.stage?.renderer.dispose();
    this.canvas?.remove();
  }
}

async function defaultKernel(): Promise<KernelClient> {
  const { sharedKernel } = await import('../../wasm/client');
  const k = sharedKernel();
  await k.whenReady();
  return k;
}

/** The modes this file implements. */
export const modes: readonly Mode[] = ['wasmMesh'];

/** A mode-4b view (`kernel`: the worker client, the studio's shared one by default). */
export function create(_mode: Mode, kernel?: () => Promise<KernelClient>): ModeView {
  return new WasmMeshView(kernel);
}
