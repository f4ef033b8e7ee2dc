import { describe, expect, it } from 'vitest';
import { badgeText, formatBandwidth, formatBytes, formatMs, MODE_NAMES } from '../../src/viewer/badge-text';
import { probeText } from '../../src/viewer/probe';
import { SeriesHistory } from '../../src/viewer/panel';
import type { Decision } from '../../src/wire';

const decision: Decision = {
  mode: 'viewSet',
  settings: { width: 256, height: 256, quality: 75, movingScale: 2, movingQuality: 50, format: 'jpeg', views: 24, elevations: [0, 30], meshDepth: 6, coarseDepth: 4, volumeGrid: 64 },
  reason: 'no WebGL2: the view set turns at once (first display 420 ms, 180 kB at 1.5 Mbit/s)',
  overridden: false,
  predictions: [
    { mode: 'still', feasible: true, refusal: null, firstDisplayMs: 250, orbitMs: 300, editMs: 260, bytes: 22_000, cost: 1 },
    { mode: 'serverMesh', feasible: false, refusal: 'no WebGL2', firstDisplayMs: 0, orbitMs: 0, editMs: 0, bytes: 0, cost: 0 },
  ],
  network: { rttMs: 152.4, bandwidthBps: 1_480_000, samples: 5 },
  trigger: 'connect',
  seq: 3,
};

describe('badge words', () => {
  it('formats rates, durations and sizes in plain words', () => {
    expect(formatBandwidth(1_480_000)).toBe('1.5 Mbit/s');
    expect(formatBandwidth(85_000_000)).toBe('85 Mbit/s');
    expect(formatBandwidth(640_000)).toBe('640 kbit/s');
    expect(formatBandwidth(2.5e9)).toBe('2.5 Gbit/s');
    expect(formatBandwidth(null)).toBe('—');
    expect(formatBandwidth(0)).toBe('—');
    expect(formatMs(4.25)).toBe('4.3 ms');
    expect(formatMs(152.4)).toBe('152 ms');
    expect(formatMs(1234)).toBe('1.2 s');
    expect(formatMs(Number.NaN)).toBe('—');
    expect(formatBytes(950)).toBe('950 B');
    expect(formatBytes(22_000)).toBe('22 kB');
    expect(formatBytes(1_400_000)).toBe('1.4 MB');
  });

  it('shows the mode and the engine reason, with the numbers in the detail', () => {
    const t = badgeText('viewSet', decision);
    expect(t.title).toBe(MODE_NAMES.viewSet);
    expect(t.reason).toContain('no WebGL2');
    expect(t.detail).toContain('round trip 152 ms, 1.5 Mbit/s (5 samples)');
    expect(t.detail).toContain('decision #3 (connect)');
    expect(t.detail).toContain('1 · still: first 250 ms, orbit 300 ms, edit 260 ms, 22 kB');
    expect(t.detail).toContain('3 · server mesh: not possible (no WebGL2)');
  });

  it('says when the user chose the mode, and adds a fallback note', () => {
    expect(badgeText('serverMesh', decision, null, 'serverMesh').reason).toBe('chosen by you');
    const t = badgeText('still', decision, 'gpuRaycast failed here');
    expect(t.reason).toBe(`${decision.reason} — gpuRaycast failed here`);
    expect(badgeText(null, null).title).toBe('starting…');
    expect(badgeText('still', null).reason).toMatch(/no decision yet/);
  });

  it('probe readout says why the value is missing', () => {
    expect(probeText(null)).toBe('no surface under the cursor');
    expect(probeText({ point: [1, 0.5, -2], value: null, attributes: [], source: 'needs the WASM kernel' })).toBe(
      'x 1.0000  y 0.5000  z -2.0000   f: needs the WASM kernel',
    );
    expect(probeText({ point: [0, 0, 0], value: 1e-5, attributes: [0.5, 1], source: 'wasm' })).toContain('f = 1.000e-5   s = [0.5000, 1.0000]');
  });
});

describe('measurement history', () => {
  it('keeps the last samples and finds the latest and largest known values', () => {
    const h = new SeriesHistory(3);
    h.push({ bandwidthBps: 1e6, rttMs: 10, fps: null });
    h.push({ bandwidthBps: 5e6, rttMs: null, fps: 30 });
    h.push({ bandwidthBps: 2e6, rttMs: 12, fps: null });
    h.push({ bandwidthBps: null, rttMs: 11, fps: null });
    expect(h.samples.length).toBe(3);
    expect(h.max('bandwidthBps')).toBe(5e6);
    expect(h.latest('bandwidthBps')).toBe(2e6);
    expect(h.latest('fps')).toBe(30);
    expect(h.max('rttMs')).toBe(12);
  });
});
