/**
 * The camera, scene and section uniforms of the client-drawn modes (4a and
 * volume; declared by frep-glsl's scene.glsl, scene-glsl.ts), from the viewer's
 * camera (cameraFrame: the server's camera exactly) and scene conventions.
 */
import type { CameraView } from '../../wire';
import { cameraFrame, type Vec3 } from '../camera';
import type { SceneConventions, SectionPlane } from '../types';
import { type LinkedProgram, setUniform } from './raycast-gl';

/** frep-render's `to_world` of a camera light (x right, y up, z towards the viewer). */
export function lightToWorld(d: readonly number[], right: Vec3, up: Vec3, forward: Vec3): Vec3 {
  const v: Vec3 = [0, 1, 2].map((k) => right[k]! * d[0]! + up[k]! * d[1]! - forward[k]! * d[2]!) as Vec3;
  const l = Math.hypot(v[0], v[1], v[2]);
  return l > 0 ? [v[0] / l, v[1] / l, v[2] / l] : v;
}

/** What the scene uniforms are made from. */
export interface SceneState {
  camera: CameraView;
  /** The box the camera frames (the viewer's). */
  framing: readonly number[];
  /** The box rays are clipped to. */
  box: readonly number[];
  /** The render target in pixels. */
  width: number;
  height: number;
  scene: SceneConventions;
  section: SectionPlane | null;
  maxSteps: number;
}

/** Uploads the scene uniforms (the program must be in use). */
export function setSceneUniforms(gl: WebGL2RenderingContext, p: LinkedProgram, st: SceneState): void {
  const f = cameraFrame(st.camera, st.framing, st.width, st.height);
  const s = st.scene;
  const v3 = (name: string, v: readonly number[]): void => setUniform(gl, p, name, 'vec3', v);
  const f1 = (name: string, v: number): void => setUniform(gl, p, name, 'float', [v]);
  setUniform(gl, p, 'u_resolution', 'vec2', [st.width, st.height]);
  v3('u_eye', f.eye);
  v3('u_right', f.right);
  v3('u_up', f.up);
  v3('u_forward', f.forward);
  f1('u_k', f.k);
  f1('u_perspective', f.perspective ? 1 : 0);
  v3('u_box_min', st.box.slice(0, 3));
  v3('u_box_max', st.box.slice(3, 6));
  setUniform(gl, p, 'u_max_steps', 'int', [st.maxSteps]);
  v3('u_bg_top', s.backgroundTop);
  v3('u_bg_bottom', s.backgroundBottom);
  v3('u_base', s.baseColor);
  v3('u_cap', s.sectionCap);
  v3('u_key', lightToWorld(s.key.dir, f.right, f.up, f.forward));
  v3('u_fill', lightToWorld(s.fill.dir, f.right, f.up, f.forward));
  v3('u_rim', lightToWorld(s.rim.dir, f.right, f.up, f.forward));
  v3('u_key_color', s.key.color);
  v3('u_fill_color', s.fill.color);
  v3('u_rim_color', s.rim.color);
  v3('u_sky', s.sky);
  v3('u_ground', s.ground);
  f1('u_specular', s.specular);
  f1('u_shininess', s.shininess);
  const sec = st.section;
  setUniform(gl, p, 'u_section', 'vec4', sec ? [...sec.normal, sec.offset] : [0, 0, 1, 0]);
  f1('u_section_on', sec ? 1 : 0);
}
