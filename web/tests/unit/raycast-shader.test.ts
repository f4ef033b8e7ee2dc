/**
 * Mode 4a without a GPU: the shader is frep-glsl's viewer shader, whole
 * (from the WebAssembly kernel: the same Rust as the server's artefact),
 * parameters only change uniforms,
 * large models are refused with a reason, camera lights follow
 * frep-render's convention, and the resolution controller holds the frame
 * rate while moving and returns to full resolution when still.
 */
import { beforeAll, describe, expect, it } from 'vitest';
import { SCENE_UNIFORMS, viewerShader } from '../../src/viewer/modes/raycast-glsl';
import { DEFAULT_RAYCAST, lightToWorld, raycastRefusal } from '../../src/viewer/modes/raycast';
import { FrameRate, ResolutionController } from '../../src/viewer/modes/raycast-resolution';
import type { FrepKernel } from '../../src/wasm/kernel';
import { example, loadKernel, wasmAvailable } from './wasm-support';

describe.skipIf(!wasmAvailable())("the kernel's viewer shader", () => {
  let kernel: FrepKernel;
  beforeAll(async () => {
    kernel = await loadKernel();
  });

  it.each([
    ['sphere', false],
    ['android_robot', true],
  ] as const)('%s has the fields, the scene and one main', (name, attrs) => {
    const c = kernel.compile(example(name));
    const s = kernel.shader(c.handle);
    const full = viewerShader(s.source);
    expect(full.startsWith('#version 300 es')).toBe(true);
    expect(full.match(/void main\(\)/g)).toHaveLength(1);
    expect(full).toContain(`#define HF_ATTRS ${attrs ? 1 : 0}`);
    // Exactly one call site of each field function in main (SwiftShader's rule).
    const main = full.slice(full.indexOf('void main()'));
    expect(main.match(/\bfield_grad\(/g)).toHaveLength(1);
    expect(main.match(/\bhf_trace\(/g)).toHaveLength(1);
    expect(full.match(/\bfield\(o \+ d \* t\)/g)).toHaveLength(1); // in hf_trace
    expect(full.match(/\bfield_iv\(/g)!.length).toBeGreaterThanOrEqual(2); // definition + hf_segment_iv
    for (const u of SCENE_UNIFORMS) expect(full).toMatch(new RegExp(`uniform \\w+ ${u};`));
    // The viewer's camera, not the standalone shader's matrix; the model's uniforms.
    expect(full).not.toContain('u_inv_view_proj');
    expect(full).toContain('u_consts');
  });

  it('new parameter values keep the code and change the uniforms only', () => {
    const src = 'my_model(x[3], a[1]) { my_model = a[1] - x[1]^2 - x[2]^2 - x[3]^2; }';
    const c = kernel.compile(src, { params: [1] });
    const bounds = [-2, -2, -2, 2, 2, 2];
    const sa = kernel.shader(c.handle, { bounds, params: [1] });
    const sb = kernel.shader(c.handle, { bounds, params: [2.5] });
    expect(sa.source).toBe(sb.source);
    const params = (s: typeof sa) => s.uniforms.find((u) => u.name === 'u_params')!.values;
    expect([params(sa), params(sb)]).toEqual([[1], [2.5]]);
  });

  it("refuses what is not frep-glsl's viewer shader", () => {
    expect(() => viewerShader('void main() {}')).toThrow(/not frep-glsl's viewer shader/);
  });
});

describe('mode 4a limits and conventions', () => {
  it('refuses a shader over the statement limit, with the reason', () => {
    expect(raycastRefusal(464)).toBeNull();
    const r = raycastRefusal(DEFAULT_RAYCAST.maxStatements + 1);
    expect(r).toMatch(/statements/);
    expect(r).toMatch(/1,000 primitives/);
    expect(raycastRefusal(100, { ...DEFAULT_RAYCAST, maxStatements: 50 })).not.toBeNull();
  });

  it('turns camera lights into world directions (x right, y up, z towards the viewer)', () => {
    const right: [number, number, number] = [1, 0, 0];
    const up: [number, number, number] = [0, 0, 1];
    const forward: [number, number, number] = [0, 1, 0];
    expect(lightToWorld([0, 0, 1], right, up, forward)).toEqual([0, -1, 0]);
    const k = lightToWorld([-0.5, 0.7, 0.6], right, up, forward);
    expect(Math.hypot(...k)).toBeCloseTo(1, 12);
    expect(k[0]).toBeLessThan(0);
    expect(k[2]).toBeGreaterThan(0);
  });

  it('lowers the resolution while slow frames orbit, full again when still', () => {
    const c = new ResolutionController({ targetFps: 30, minScale: 0.25 });
    expect(c.scale(true)).toBe(1);
    c.record(133, 1, true); // 4x too slow: half the side
    expect(c.scale(true)).toBeCloseTo(0.5, 1);
    expect(c.scale(false)).toBe(1);
    for (let i = 0; i < 10; i++) c.record(1000, c.scale(true), true);
    expect(c.scale(true)).toBe(0.25);
    for (let i = 0; i < 40; i++) c.record(5, c.scale(true), true);
    expect(c.scale(true)).toBe(1);
  });

  it('measures the frame rate over a window', () => {
    const f = new FrameRate(1000);
    expect(f.fps()).toBe(0);
    for (let i = 0; i <= 20; i++) f.tick(i * 50);
    expect(f.fps()).toBeCloseTo(20, 6);
  });
});
