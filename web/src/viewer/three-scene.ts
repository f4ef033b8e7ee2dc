/**
 * three.js set up with the shared conventions, for the modes that draw with
 * WebGL (server mesh here; the client modes may use it too): a camera that
 * is exactly the server's ray-cast camera ({@link cameraFrame}), the
 * server's camera-fixed key, fill and rim lights and hemisphere ambient,
 * a transparent clear so the viewer's background gradient shows through,
 * and a section plane as a three.js clipping plane.
 */
import * as THREE from 'three';
import type { CameraView } from '../wire';
import { type Box6, cameraFrame } from './camera';
import { SCENE } from './scene';
import type { SceneConventions, SectionPlane } from './types';

/** A renderer, scene and camera following the conventions. */
export interface ThreeStage {
  renderer: THREE.WebGLRenderer;
  scene: THREE.Scene;
  /** The camera in use (perspective or orthographic, swapped with the view). */
  camera: THREE.PerspectiveCamera | THREE.OrthographicCamera;
  /** Lights parented to the camera. */
  lights: THREE.Object3D;
}

/** Makes a stage on `canvas` (throws when WebGL is unavailable). */
export function createStage(canvas: HTMLCanvasElement, scene: SceneConventions = SCENE): ThreeStage {
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, alpha: true, preserveDrawingBuffer: true });
  renderer.setClearColor(0x000000, 0);
  renderer.localClippingEnabled = true;
  const s = new THREE.Scene();
  const lights = new THREE.Group();
  const add = (l: { dir: [number, number, number]; color: [number, number, number] }) => {
    // Colours are linear intensities, as three.js expects with its default working space.
    const light = new THREE.DirectionalLight(new THREE.Color().setRGB(l.color[0], l.color[1], l.color[2], THREE.LinearSRGBColorSpace), Math.PI);
    light.position.set(l.dir[0], l.dir[1], l.dir[2]);
    light.target.position.set(0, 0, 0);
    lights.add(light, light.target);
  };
  add(scene.key);
  add(scene.fill);
  add(scene.rim);
  const hemi = new THREE.HemisphereLight(
    new THREE.Color().setRGB(scene.sky[0], scene.sky[1], scene.sky[2], THREE.LinearSRGBColorSpace),
    new THREE.Color().setRGB(scene.ground[0], scene.ground[1], scene.ground[2], THREE.LinearSRGBColorSpace),
    Math.PI,
  );
  hemi.position.set(0, 0, 1);
  s.add(hemi);
  const camera = new THREE.PerspectiveCamera();
  camera.add(lights);
  s.add(camera);
  return { renderer, scene: s, camera, lights };
}

/** Points the stage's camera as `view` for a `width`×`height` viewport (CSS px) framing `bounds`. */
export function applyCamera(stage: ThreeStage, view: CameraView, bounds: Box6, width: number, height: number): void {
  const f = cameraFrame(view, bounds, width, height);
  let cam = stage.camera;
  const wantPersp = f.perspective;
  if (wantPersp !== cam instanceof THREE.PerspectiveCamera) {
    cam.remove(stage.lights);
    stage.scene.remove(cam);
    cam = wantPersp ? new THREE.PerspectiveCamera() : new THREE.OrthographicCamera();
    cam.add(stage.lights);
    stage.scene.add(cam);
    stage.camera = cam;
  }
  if (cam instanceof THREE.PerspectiveCamera) {
    cam.fov = f.fovY;
    cam.aspect = f.width / f.height;
  } else {
    cam.left = -f.halfWidth;
    cam.right = f.halfWidth;
    cam.top = f.halfHeight;
    cam.bottom = -f.halfHeight;
  }
  cam.near = f.near;
  cam.far = f.far;
  cam.position.set(f.eye[0], f.eye[1], f.eye[2]);
  // The camera looks down its −z: basis (right, up, −forward) exactly as the server's frame.
  const m = new THREE.Matrix4().makeBasis(
    new THREE.Vector3(...f.right),
    new THREE.Vector3(...f.up),
    new THREE.Vector3(-f.forward[0], -f.forward[1], -f.forward[2]),
  );
  cam.quaternion.setFromRotationMatrix(m);
  cam.updateProjectionMatrix();
  cam.updateMatrixWorld(true);
}

/**
 * The three.js clipping plane of a section: keeps `normal · p <= offset`
 * (three.js keeps the side where `n · p + c >= 0`).
 */
export function clippingPlane(s: SectionPlane): THREE.Plane {
  return new THREE.Plane(new THREE.Vector3(-s.normal[0], -s.normal[1], -s.normal[2]), s.offset);
}
