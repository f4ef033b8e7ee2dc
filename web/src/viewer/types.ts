/**
 * The viewer's contracts: what the studio shell drives ({@link Viewer}), and
 * what every delivery mode implements ({@link ModeView}) with what the viewer
 * hands it ({@link ModeContext}).
 *
 * One camera ({@link CameraView}, frep-wire's) serves every mode; the scene
 * conventions (background, lights, colours, framing from the model box) are
 * fixed here so that switching modes never changes the picture's look.
 * Mode implementations live in `src/viewer/modes/*.ts`; each exports
 * {@link ModeModule}'s members and is loaded lazily by the viewer.
 */
import type { Api } from '../api/client';
import type { CameraView, CompileSummary, Decision, Mode, ModeSettings } from '../wire';
import type { Session } from '../session/session';

/** What the viewer is asked to show. */
export interface ModelShow {
  /** The stored model, when the source is a saved version's. */
  modelId?: string | null;
  /** Its version (null or absent: latest or unsaved). */
  version?: number | null;
  /** The HyperFun source shown (the editor's text). */
  source: string;
  /** Parameter values `a[1..]`. */
  params: number[];
  /** The compile summary when the caller has it (else the viewer compiles). */
  summary?: CompileSummary | null;
}

/**
 * A section (clipping) plane: the part of the model with
 * `normal · p > offset` is cut away, showing the solid's inside.
 */
export interface SectionPlane {
  /** Unit normal, world coordinates (z up). */
  normal: [number, number, number];
  /** Offset along the normal, world units. */
  offset: number;
}

/** A probed point of the model. */
export interface ProbeResult {
  /** World coordinates of the point on the surface. */
  point: [number, number, number];
  /** The field value there (null when no evaluator is available). */
  value: number | null;
  /** Attribute values `s[]` there (empty when unknown). */
  attributes: number[];
  /** Where the value came from (`wasm`, or why it is missing). */
  source: string;
}

/** The viewer's options (the shell passes `api` and the initial camera). */
export interface ViewerOptions {
  /** The API client. */
  api: Api;
  /** The initial camera (default: frep-wire's `CameraView::default`). */
  camera?: CameraView;
  /** The session WebSocket URL (default: `/api/session` on the page's origin). */
  sessionUrl?: string | null;
  /** Connect the adaptive session (default true; false: HTTP only, mode as forced). */
  session?: boolean;
  /** Start with this mode instead of automatic. */
  forceMode?: Mode | null;
  /** Show the measurements panel (default true). */
  panel?: boolean;
}

/** The viewer the shell mounts. */
export interface Viewer {
  /** Shows a model (a new model, an edit, or new parameters). */
  show(model: ModelShow): void;
  /** New parameter values for the shown model. */
  setParams(params: number[]): void;
  /** The camera now. */
  getCamera(): CameraView;
  /** The camera now (the shell's `StudioViewer` reads this). */
  readonly camera: CameraView;
  /** Moves the camera (every mode follows). */
  setCamera(c: CameraView): void;
  /** Called whenever the camera changes; returns the unsubscribe. */
  onCameraChange(cb: (c: CameraView) => void): () => void;
  /** Progress of an artefact being computed (0..1). */
  onProgress(cb: (key: string, fraction: number) => void): () => void;
  /** A section plane, or none. */
  setSection(plane: SectionPlane | null): void;
  /** The mode shown now (null before the first display). */
  readonly mode: Mode | null;
  /** Forces a mode, or null for automatic (the badge menu does this too). */
  setOverride(mode: Mode | null): void;
  /** Resolves when the current request has been displayed. */
  whenDisplayed(): Promise<void>;
  /** Resolves at the viewer's first display (of any model). */
  firstDisplayed(): Promise<void>;
  /** Releases the socket, GL contexts and listeners. */
  dispose(): void;
}

/** A light fixed to the camera (frep-render's `Light`). */
export interface CameraLight {
  /** Direction towards the light in camera coordinates: x right, y up, z towards the viewer. */
  dir: [number, number, number];
  /** Linear RGB intensity. */
  color: [number, number, number];
}

/**
 * Fixed look of every mode: frep-render's `Lighting::default()` (the
 * server's images), so client-drawn modes match them.
 */
export interface SceneConventions {
  /** Background at the top of the viewport, sRGB 0..1 (a vertical gradient). */
  backgroundTop: [number, number, number];
  /** Background at the bottom, sRGB 0..1. */
  backgroundBottom: [number, number, number];
  /** Surface colour without attributes, sRGB 0..1. */
  baseColor: [number, number, number];
  /** Colour of a section's cut face, sRGB 0..1. */
  sectionCap: [number, number, number];
  /** Key, fill and rim lights. */
  key: CameraLight;
  /** Fill light. */
  fill: CameraLight;
  /** Rim light. */
  rim: CameraLight;
  /** Hemisphere ambient from world +z, linear RGB. */
  sky: [number, number, number];
  /** Hemisphere ambient from world −z, linear RGB. */
  ground: [number, number, number];
  /** Blinn–Phong strength and exponent of the key light. */
  specular: number;
  /** Blinn–Phong exponent. */
  shininess: number;
}

/** The size of the viewport. */
export interface ViewSize {
  /** CSS pixels. */
  width: number;
  /** CSS pixels. */
  height: number;
  /** Device pixels per CSS pixel (capped). */
  pixelRatio: number;
}

/** The model a mode is asked to show, with what the viewer knows of it. */
export interface ModeModel {
  /** The request. */
  show: ModelShow;
  /** The compiled summary (bounds, parameters, attributes). */
  summary: CompileSummary;
  /** The model box `[x0, y0, z0, x1, y1, z1]` used for framing. */
  bounds: [number, number, number, number, number, number];
  /** The decision's settings for this mode (null: defaults). */
  settings: ModeSettings | null;
  /** Cancelled when this request is superseded. */
  signal: AbortSignal;
}

/** What a mode gets from the viewer when mounted. */
export interface ModeContext {
  /** The mode's own layer (fills the viewport; the mode adds its canvas/img). */
  container: HTMLElement;
  /** The API client. */
  api: Api;
  /** The API base ('' for the page's origin). */
  apiBase: string;
  /** The session, when connected (mode 1 streams frames over it). */
  session: Session | null;
  /** The scene conventions. */
  scene: SceneConventions;
  /** The camera now. */
  camera(): CameraView;
  /** The viewport now. */
  size(): ViewSize;
  /** Whether the user is interacting (orbiting) now. */
  moving(): boolean;
  /** The last decision (null before one). */
  decision(): Decision | null;
  /** A mode reports a displayed frame (for the frame-rate window). */
  frame(): void;
  /** A mode reports its first display of a request: bytes transferred. */
  displayed(bytes: number): void;
  /** A mode reports progress of an artefact (0..1). */
  progress(key: string, fraction: number): void;
  /** A mode reports a failure to show (kept display stays). */
  failed(message: string): void;
}

/** A delivery mode's view. */
export interface ModeView {
  /** Which mode it is. */
  readonly mode: Mode;
  /** Creates its DOM / GL resources. */
  mount(ctx: ModeContext): Promise<void>;
  /**
   * Shows a model; resolves at its first display. The previous display
   * stays until then; a superseded request (its signal aborted) may reject
   * with an AbortError or resolve without displaying.
   */
  show(model: ModeModel): Promise<void>;
  /** The camera moved. */
  setCamera(c: CameraView): void;
  /** New parameter values (the viewer also calls `show` with them). */
  setParams(p: number[]): void;
  /** A section plane or none. */
  setSection(s: SectionPlane | null): void;
  /** The viewport changed (CSS pixels; the mode applies the pixel ratio). */
  resize(width: number, height: number): void;
  /** Probes the model at a viewport point (CSS pixels), if the mode can. */
  probe?(x: number, y: number): Promise<ProbeResult | null>;
  /** Releases its resources and removes its DOM. */
  dispose(): void;
}

/** What a file in `src/viewer/modes/` exports. */
export interface ModeModule {
  /** The modes the file implements. */
  modes: readonly Mode[];
  /** Creates a view of one of them. */
  create(mode: Mode): ModeView;
}
