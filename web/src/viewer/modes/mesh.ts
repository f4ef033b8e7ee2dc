/**
 * Mode 3, the server's mesh: a meshopt-compressed glb (GLTFLoader with
 * MeshoptDecoder) drawn with three.js under the shared camera and lights.
 * A coarse level comes first (`coarseDepth`), then the full one
 * (`meshDepth`); each replaces the last only once decoded. Attribute
 * colours (s[] as COLOR_0) are used when the mesh has them, else the
 * server's base colour. A section plane clips the mesh; back faces drawn in
 * the cap colour show the solid's cut. Probing ray casts the mesh.
 */
import * as THREE from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/examples/jsm/libs/meshopt_decoder.module.js';
import type { CameraView, Mode } from '../../wire';
import { type ThreeStage, applyCamera, clippingPlane, createStage } from '../three-scene';
import type { ModeContext, ModeModel, ModeModule, ModeView, ProbeResult, SectionPlane } from '../types';
import { fetchArtefact, isAbort } from './artefact';

class MeshView implements ModeView {
  readonly mode: Mode = 'serverMesh';
  private ctx!: ModeContext;
  private canvas!: HTMLCanvasElement;
  private stage!: ThreeStage;
  private group: THREE.Group | null = null;
  private bounds: readonly number[] = [-1, -1, -1, 1, 1, 1];
  private section: SectionPlane | null = null;
  private raf = 0;
  private readonly loader = new GLTFLoader();
  private readonly surface: THREE.MeshPhongMaterial;
  private readonly cap: THREE.MeshBasicMaterial;

  constructor() {
    this.loader.setMeshoptDecoder(MeshoptDecoder);
    const sc = this.scene();
    this.surface = new THREE.MeshPhongMaterial({
      color: new THREE.Color().setRGB(sc.baseColor[0], sc.baseColor[1], sc.baseColor[2], THREE.SRGBColorSpace),
      specular: new THREE.Color(sc.specular, sc.specular, sc.specular),
      shininess: sc.shininess,
      side: THREE.FrontSide,
    });
    this.cap = new THREE.MeshBasicMaterial({
      color: new THREE.Color().setRGB(sc.sectionCap[0], sc.sectionCap[1], sc.sectionCap[2], THREE.SRGBColorSpace),
      side: THREE.BackSide,
    });
  }

  private scene() {
    return this.ctx?.scene ?? {
      baseColor: [0.72, 0.74, 0.78] as [number, number, number],
      sectionCap: [0.85, 0.45, 0.3] as [number, number, number],
      specular: 0.25,
      shininess: 40,
    };
  }

  async mount(ctx: ModeContext): Promise<void> {
    this.ctx = ctx;
    this.canvas = document.createElement('canvas');
    this.canvas.className = 'frep-mode-canvas';
    this.canvas.dataset.mode = 'serverMesh';
    ctx.container.append(this.canvas);
    this.stage = createStage(this.canvas, ctx.scene);
    const { width, height, pixelRatio } = ctx.size();
    this.stage.renderer.setPixelRatio(pixelRatio);
    this.stage.renderer.setSize(width, height, false);
  }

  async show(model: ModeModel): Promise<void> {
    const st = model.settings;
    const full = st?.meshDepth ?? 6;
    const coarse = Math.min(full, st?.coarseDepth ?? Math.max(3, full - 2));
    this.bounds = model.bounds;
    let bytes = 0;
    let first = true;
    for (const depth of coarse < full ? [coarse, full] : [full]) {
      try {
        const got = await fetchArtefact(this.ctx.api, model.show, { kind: 'mesh', depth }, model.signal, this.ctx.progress, (k) =>
          this.ctx.session?.cancel(k),
        );
        const gltf = await this.loader.parseAsync(await got.blob.arrayBuffer(), '');
        if (model.signal.aborted) return;
        bytes += got.bytes;
        this.replace(gltf.scene);
        this.draw();
        if (first) this.ctx.displayed(bytes);
        first = false;
      } catch (e) {
        if (isAbort(e) || model.signal.aborted) return;
        // A failed refinement keeps the coarse mesh; a failed first level is the mode's failure.
        if (first) throw e;
        this.ctx.failed(`refined mesh: ${(e as Error).message}`);
        return;
      }
    }
  }

  setCamera(_c: CameraView): void {
    this.schedule();
  }

  setParams(): void {}

  setSection(s: SectionPlane | null): void {
    this.section = s;
    this.applySection();
    this.schedule();
  }

  resize(width: number, height: number): void {
    this.stage.renderer.setPixelRatio(this.ctx.size().pixelRatio);
    this.stage.renderer.setSize(width, height, false);
    this.draw();
  }

  async probe(x: number, y: number): Promise<ProbeResult | null> {
    if (!this.group) return null;
    const { width, height } = this.ctx.size();
    const ray = new THREE.Raycaster();
    ray.setFromCamera(new THREE.Vector2((2 * x) / width - 1, 1 - (2 * y) / height), this.stage.camera);
    const hits = ray.intersectObject(this.group, true).filter((h) => {
      if (!this.section) return true;
      const n = this.section.normal;
      return n[0] * h.point.x + n[1] * h.point.y + n[2] * h.point.z <= this.section.offset;
    });
    if (!hits.length) return null;
    const p = hits[0].point;
    return { point: [p.x, p.y, p.z], value: null, attributes: [], source: 'mesh' };
  }

  dispose(): void {
    if (this.raf) cancelAnimationFrame(this.raf);
    this.clear();
    this.surface.dispose();
    this.cap.dispose();
    this.stage.renderer.dispose();
    this.stage.renderer.forceContextLoss();
    this.canvas.remove();
  }

  private replace(scene: THREE.Object3D): void {
    this.clear();
    const group = new THREE.Group();
    // The glb's node transforms stay on the nodes: quantized positions
    // (integers, KHR_mesh_quantization) must not be transformed in place.
    const meshes: THREE.Mesh[] = [];
    scene.traverse((o) => {
      if (o instanceof THREE.Mesh) meshes.push(o);
    });
    for (const o of meshes) {
      const geom = o.geometry as THREE.BufferGeometry;
      const colored = !!geom.getAttribute('color');
      const mat = colored ? this.surface.clone() : this.surface;
      if (colored) {
        mat.vertexColors = true;
        mat.color.setRGB(1, 1, 1);
      }
      o.material = mat;
      const cap = new THREE.Mesh(geom, this.cap);
      cap.position.copy(o.position);
      cap.quaternion.copy(o.quaternion);
      cap.scale.copy(o.scale);
      o.parent?.add(cap);
    }
    group.add(scene);
    this.group = group;
    this.stage.scene.add(group);
    this.applySection();
  }

  private clear(): void {
    if (!this.group) return;
    this.stage.scene.remove(this.group);
    this.group.traverse((o) => {
      if (!(o instanceof THREE.Mesh)) return;
      o.geometry.dispose();
      if (o.material !== this.surface && o.material !== this.cap) (o.material as THREE.Material).dispose();
    });
    this.group = null;
  }

  private applySection(): void {
    const planes = this.section ? [clippingPlane(this.section)] : [];
    const cap = !!this.section;
    this.group?.traverse((o) => {
      if (!(o instanceof THREE.Mesh)) return;
      const m = o.material as THREE.Material;
      m.clippingPlanes = planes;
      // Back faces show only where the section opens the solid.
      if (m === this.cap) o.visible = cap;
    });
    this.surface.clippingPlanes = planes;
    this.cap.clippingPlanes = planes;
  }

  private schedule(): void {
    if (this.raf) return;
    this.raf = requestAnimationFrame(() => {
      this.raf = 0;
      this.draw();
    });
  }

  private draw(): void {
    if (!this.group) return;
    const { width, height } = this.ctx.size();
    applyCamera(this.stage, this.ctx.camera(), this.bounds, width, height);
    this.stage.renderer.render(this.stage.scene, this.stage.camera);
    this.ctx.frame();
  }
}

/** Mode 3. */
export const modes: readonly Mode[] = ['serverMesh'];

/** Creates the server-mesh view. */
export function create(): ModeView {
  return new MeshView();
}

const _check: ModeModule = { modes, create };
void _check;
