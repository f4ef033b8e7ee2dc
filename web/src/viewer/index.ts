/**
 * The studio's adaptive viewer: its public interface.
 *
 * `createViewer(container, opts)` mounts the viewer (the mode layers, the
 * badge with its override menu, the measurements panel) and connects the
 * session; the shell drives it with `show`, `setParams`, `setCamera`,
 * `setSection`. Delivery modes implement {@link ModeView} in
 * `src/viewer/modes/*.ts` (see {@link ModeModule}); camera math shared by
 * every mode is in `./camera` (the server's ray-cast camera, exactly).
 */
export type {
  CameraLight,
  ModeContext,
  ModeModel,
  ModeModule,
  ModeView,
  ModelShow,
  ProbeResult,
  SceneConventions,
  SectionPlane,
  Viewer,
  ViewerOptions,
  ViewSize,
} from './types';
export { SCENE, DEFAULT_CAMERA } from './scene';
export { cameraFrame, type CameraFrame } from './camera';
export { createViewer } from './studio-viewer';
