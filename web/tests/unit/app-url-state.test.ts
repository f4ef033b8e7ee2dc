import { describe, expect, it } from 'vitest';
import { decodeCamera, decodeState, encodeCamera, encodeState } from '../../src/app/url-state';
import type { CameraView } from '../../src/wire';

const cam: CameraView = { yaw: 30.5, pitch: -20, fov: 45, zoom: 1.25, pan: [0.1, -0.2, 0] };

describe('url state', () => {
  it('round-trips model, version and camera', () => {
    const s = { modelId: 'abc-123', version: 4, camera: cam };
    const hash = encodeState(s);
    expect(hash).toBe('#/model/abc-123?v=4&cam=30.5,-20,1.25,45,0.1,-0.2,0');
    expect(decodeState(hash)).toEqual(s);
  });

  it('writes an orthographic camera as o', () => {
    const c = { ...cam, fov: null };
    expect(encodeCamera(c)).toContain(',o,');
    expect(decodeCamera(encodeCamera(c))).toEqual(c);
  });

  it('rounds to thousandths', () => {
    const c = decodeCamera(encodeCamera({ ...cam, yaw: 1 / 3 }))!;
    expect(c.yaw).toBe(0.333);
  });

  it('escapes ids', () => {
    const s = { modelId: 'a b/c?d', version: null, camera: null };
    expect(decodeState(encodeState(s))).toEqual(s);
  });

  it('leaves out what it cannot read', () => {
    expect(decodeState('#/model/x?v=abc&cam=1,2')).toEqual({ modelId: 'x', version: null, camera: null });
    expect(decodeState('#/model/x?v=0')).toEqual({ modelId: 'x', version: null, camera: null });
    expect(decodeState('#/elsewhere')).toEqual({ modelId: null, version: null, camera: null });
    expect(decodeState('')).toEqual({ modelId: null, version: null, camera: null });
    expect(decodeState('#/model/%E0%A4%A')).toEqual({ modelId: null, version: null, camera: null });
    expect(decodeCamera('1,2,0,45,0,0,0')).toBeNull();
    expect(decodeCamera('1,2,1,200,0,0,0')).toBeNull();
    expect(decodeCamera('1,2,1,x,0,0,0')).toBeNull();
  });

  it('clamps the pitch', () => {
    expect(decodeCamera('0,120,1,o,0,0,0')?.pitch).toBe(90);
  });

  it('the list is #/', () => {
    expect(encodeState({ modelId: null, version: 3, camera: cam })).toBe('#/');
  });
});
