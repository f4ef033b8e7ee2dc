import { describe, expect, it } from 'vitest';
import { FrameRateWindow } from '../../src/measure/framerate';
import { cpuBench } from '../../src/measure/cpu-bench';
import { isMobile, isSoftwareRenderer } from '../../src/measure/capabilities';

describe('frame-rate window', () => {
  it('measures a steady rhythm', () => {
    const w = new FrameRateWindow(3000, 500);
    for (let i = 0; i <= 30; i++) w.add(1000 + i * 50);
    const r = w.rate();
    expect(r).not.toBeNull();
    expect(r!.fps).toBeCloseTo(20, 6);
    expect(r!.frameMs).toBeCloseTo(50, 6);
  });

  it('keeps only the last window', () => {
    const w = new FrameRateWindow(1000, 500);
    for (let i = 0; i <= 100; i++) w.add(i * 100); // 10 fps for 10 s
    for (let i = 1; i <= 40; i++) w.add(10_000 + i * 25); // then 40 fps for 1 s
    const r = w.rate()!;
    expect(r.frameMs).toBeCloseTo(25, 6);
    expect(r.frames).toBe(41); // the window [10 s, 11 s] holds the frame at 10 s too
  });

  it('an idle gap starts a new burst, so idling is not slowness', () => {
    const w = new FrameRateWindow(3000, 500);
    w.add(0);
    w.add(16);
    w.add(32);
    w.add(2032); // after 2 s idle
    expect(w.rate()).toBeNull(); // one frame in the new burst
    w.add(2048);
    w.add(2064);
    expect(w.rate()!.frameMs).toBeCloseTo(16, 6);
  });

  it('is null with too few frames, and clear forgets', () => {
    const w = new FrameRateWindow();
    expect(w.rate()).toBeNull();
    w.add(0);
    w.add(10);
    w.add(20);
    expect(w.rate()).not.toBeNull();
    w.clear();
    expect(w.rate()).toBeNull();
  });

  it('median frame time ignores one long frame', () => {
    const w = new FrameRateWindow(3000, 1000);
    [0, 20, 40, 60, 400, 420, 440].forEach((t) => w.add(t));
    expect(w.rate()!.frameMs).toBe(20);
  });
});

describe('client facts', () => {
  it('names software renderers', () => {
    expect(isSoftwareRenderer('ANGLE (Google, Vulkan 1.3.0 (SwiftShader Device (Subzero) (0x0000C0DE)), SwiftShader driver)')).toBe(true);
    expect(isSoftwareRenderer('llvmpipe (LLVM 15.0.6, 256 bits)')).toBe(true);
    expect(isSoftwareRenderer('Microsoft Basic Render Driver')).toBe(true);
    expect(isSoftwareRenderer('ANGLE (NVIDIA, NVIDIA GeForce RTX 3060 Direct3D11 vs_5_0 ps_5_0)')).toBe(false);
    expect(isSoftwareRenderer(null)).toBe(false);
  });

  it('takes userAgentData.mobile first, else guesses from the user agent', () => {
    const nav = (ua: string, mobile?: boolean) => ({ userAgent: ua, userAgentData: mobile === undefined ? undefined : { mobile } }) as unknown as Navigator;
    expect(isMobile(nav('Mozilla/5.0 (Linux; Android 14) Mobile Safari', undefined))).toBe(true);
    expect(isMobile(nav('Mozilla/5.0 (X11; Linux x86_64)', undefined))).toBe(false);
    expect(isMobile(nav('Mozilla/5.0 (X11; Linux x86_64)', true))).toBe(true);
    expect(isMobile(nav('iPhone', false))).toBe(false);
  });

  it('the CPU benchmark does its work and times it', () => {
    let t = 0;
    const r = cpuBench(() => (t += 5), 1000);
    expect(r.ms).toBe(5);
    expect(Number.isFinite(r.checksum)).toBe(true);
    expect(r.checksum).not.toBe(0);
  });
});
