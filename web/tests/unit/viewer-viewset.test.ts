import { describe, expect, it } from 'vitest';
import { nearestView, viewRect } from '../../src/viewer/modes/viewset';
import { candidateFiles, fallbackMode } from '../../src/viewer/mode-registry';
import type { ViewSetLayout } from '../../src/wire';

const layout: ViewSetLayout = { viewsPerRing: 24, elevations: [0, 20, 45], startYaw: 0, viewSize: [128, 128], columns: 24, sheetSize: [3072, 384] };

describe('view set browsing', () => {
  it('picks the nearest ring and view, wrapping yaw', () => {
    expect(nearestView(layout, 30, 20)).toEqual({ ring: 1, view: 2, index: 26 });
    expect(nearestView(layout, -15, 0)).toEqual({ ring: 0, view: 23, index: 23 });
    expect(nearestView(layout, 352.6, 80)).toEqual({ ring: 2, view: 0, index: 48 });
    expect(nearestView(layout, 7.4, 9.9)).toEqual({ ring: 0, view: 0, index: 0 });
    expect(nearestView(layout, 7.6, 10.1)).toEqual({ ring: 1, view: 1, index: 25 });
    expect(nearestView({ ...layout, startYaw: 7.5 }, 7.5, 0).view).toBe(0);
  });

  it('finds a view on the sheet, ring-major', () => {
    expect(viewRect(layout, 26)).toEqual({ x: 256, y: 128, w: 128, h: 128 });
    const grid = { ...layout, columns: 8 };
    expect(viewRect(grid, 26)).toEqual({ x: 256, y: 384, w: 128, h: 128 });
  });
});

describe('mode registry', () => {
  const files = ['./modes/still.ts', './modes/viewset.ts', './modes/mesh.ts', './modes/raycast.ts', './modes/raycast-gl.ts', './modes/artefact.ts', './modes/wasmmesh.ts'];
  it('finds mode files by name', () => {
    expect(candidateFiles('still', files)).toEqual(['./modes/still.ts']);
    expect(candidateFiles('gpuRaycast', files)).toEqual(['./modes/raycast.ts', './modes/raycast-gl.ts']);
    expect(candidateFiles('serverMesh', files)).toEqual(['./modes/mesh.ts']);
    expect(candidateFiles('volume', files)).toEqual([]);
  });

  it('falls back towards the server still', () => {
    expect(fallbackMode('gpuRaycast', true)).toBe('serverMesh');
    expect(fallbackMode('wasmMesh', false)).toBe('still');
    expect(fallbackMode('serverMesh', true)).toBe('still');
    expect(fallbackMode('viewSet', true)).toBe('still');
    expect(fallbackMode('still', true)).toBeNull();
  });
});
