import { describe, expect, it } from 'vitest';
import { sameSection, sectionField } from '../../src/viewer/section';
import type { ArtefactSpec } from '../../src/wire';

const spec = (extra: object): ArtefactSpec => ({
  kind: 'image',
  camera: { yaw: 30, pitch: 20, fov: 30, zoom: 1, pan: [0, 0, 0] },
  width: 64,
  height: 48,
  format: 'png',
  quality: 80,
  ...extra,
});

describe('section plane on the wire', () => {
  it('adds no field without a plane, so the spec (and its key) is as before', () => {
    expect(sectionField(null)).toEqual({});
    expect(JSON.stringify(spec(sectionField(null)))).toBe(JSON.stringify(spec({})));
    expect(JSON.stringify(spec(sectionField(null)))).not.toContain('section');
  });

  it('sends the plane as the wire form, a copy of the viewer state', () => {
    const plane = { normal: [1, 0, 0] as [number, number, number], offset: 0.25 };
    const f = sectionField(plane);
    expect(f).toEqual({ section: { normal: [1, 0, 0], offset: 0.25 } });
    plane.normal[0] = -1;
    expect(f.section!.normal[0]).toBe(1);
    expect(JSON.parse(JSON.stringify(spec(f))).section).toEqual({ normal: [1, 0, 0], offset: 0.25 });
  });

  it('asks for a new picture only when the cut changes', () => {
    const a = { normal: [0, 0, 1] as [number, number, number], offset: 0.1 };
    expect(sameSection(null, null)).toBe(true);
    expect(sameSection(a, null)).toBe(false);
    expect(sameSection(null, a)).toBe(false);
    expect(sameSection(a, { normal: [0, 0, 1], offset: 0.1 })).toBe(true);
    expect(sameSection(a, { normal: [0, 0, 1], offset: 0.2 })).toBe(false);
    expect(sameSection(a, { normal: [0, 1, 0], offset: 0.1 })).toBe(false);
    expect(sameSection(a, { normal: [0, 0, -1], offset: 0.1 })).toBe(false);
  });
});
