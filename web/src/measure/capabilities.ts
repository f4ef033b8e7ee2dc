/**
 * The client's capability report (frep-wire `ClientReport`): what the
 * browser tells (WebGL2 and its unmasked renderer, texture limits, WebGPU
 * presence, screen, pixel ratio, mobile, memory, cores) and what the page
 * measures (GPU micro-benchmark, JS loop, WASM benchmark when present).
 * The network is measured by the server on the socket.
 */
import type { ClientReport } from '../wire';
import { cpuBench } from './cpu-bench';
import { gpuBench } from './gpu-bench';
import { runWasmBench } from './wasm-hook';

/** WebGL facts. */
export interface GlFacts {
  webgl2: boolean;
  renderer: string | null;
  maxTextureSize: number;
  max3dTextureSize: number;
}

/** Reads WebGL2's facts from a throwaway context. */
export function glFacts(): GlFacts {
  const none: GlFacts = { webgl2: false, renderer: null, maxTextureSize: 0, max3dTextureSize: 0 };
  if (typeof document === 'undefined') return none;
  const canvas = document.createElement('canvas');
  canvas.width = canvas.height = 1;
  let gl: WebGL2RenderingContext | null = null;
  try {
    gl = canvas.getContext('webgl2');
  } catch {
    gl = null;
  }
  if (!gl) return none;
  const ext = gl.getExtension('WEBGL_debug_renderer_info');
  const renderer = ext ? String(gl.getParameter(ext.UNMASKED_RENDERER_WEBGL)) : String(gl.getParameter(gl.RENDERER));
  const facts = {
    webgl2: true,
    renderer,
    maxTextureSize: Number(gl.getParameter(gl.MAX_TEXTURE_SIZE)) || 0,
    max3dTextureSize: Number(gl.getParameter(gl.MAX_3D_TEXTURE_SIZE)) || 0,
  };
  gl.getExtension('WEBGL_lose_context')?.loseContext();
  return facts;
}

/** Whether a renderer string names a software rasterizer. */
export function isSoftwareRenderer(renderer: string | null | undefined): boolean {
  if (!renderer) return false;
  return /swiftshader|llvmpipe|softpipe|basic render|microsoft basic|software/i.test(renderer);
}

/** `userAgentData.mobile`, else a guess from the user agent. */
export function isMobile(nav: Navigator | undefined = typeof navigator !== 'undefined' ? navigator : undefined): boolean {
  if (!nav) return false;
  const uad = (nav as Navigator & { userAgentData?: { mobile?: boolean } }).userAgentData;
  if (uad && typeof uad.mobile === 'boolean') return uad.mobile;
  return /Android|iPhone|iPad|iPod|Mobile|Windows Phone/i.test(nav.userAgent ?? '');
}

/** What the browser tells without measuring (fast). */
export function basicReport(): ClientReport {
  const nav = typeof navigator !== 'undefined' ? navigator : undefined;
  const gl = glFacts();
  const scr = typeof screen !== 'undefined' ? screen : undefined;
  const mem = nav ? (nav as Navigator & { deviceMemory?: number }).deviceMemory : undefined;
  return {
    userAgent: nav?.userAgent ?? '',
    webgl2: gl.webgl2,
    renderer: gl.renderer,
    maxTextureSize: gl.maxTextureSize,
    max3dTextureSize: gl.max3dTextureSize,
    webgpu: !!nav && 'gpu' in nav && !!(nav as Navigator & { gpu?: unknown }).gpu,
    gpuBenchMs: null,
    wasmBenchMeps: null,
    cpuBenchMs: null,
    screen: {
      width: Math.round(scr?.width ?? (typeof window !== 'undefined' ? window.innerWidth : 0)),
      height: Math.round(scr?.height ?? (typeof window !== 'undefined' ? window.innerHeight : 0)),
      pixelRatio: typeof window !== 'undefined' ? window.devicePixelRatio || 1 : 1,
    },
    mobile: isMobile(nav),
    deviceMemoryGb: typeof mem === 'number' ? mem : null,
    cores: nav && typeof nav.hardwareConcurrency === 'number' ? nav.hardwareConcurrency : null,
  };
}

/** The full report: the basics plus the GPU, CPU and WASM benchmarks. */
export async function measureClient(opts: { wasm?: boolean } = {}): Promise<ClientReport> {
  const report = basicReport();
  report.cpuBenchMs = round(cpuBench().ms);
  if (report.webgl2) {
    const g = gpuBench();
    report.gpuBenchMs = g ? round(g.frameMs) : null;
  }
  if (opts.wasm !== false) report.wasmBenchMeps = await runWasmBench();
  return report;
}

function round(v: number): number {
  return Math.round(v * 1000) / 1000;
}
