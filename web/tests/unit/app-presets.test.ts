import { describe, expect, it } from 'vitest';
import { readPresets, removePreset, writePreset } from '../../src/app/presets';

const src = '-- description: a ball\n-- bounds: -1,-1,-1,1,1,1\nmy_model(x[3], a[2])\n{\n  my_model = a[1] - x[1]*x[1];\n}\n';

describe('presets in the source', () => {
  it('writes after the leading comments and reads back', () => {
    const out = writePreset(src, { name: 'big', values: [1.5, -2] });
    expect(out.split('\n')[2]).toBe('-- preset: big = 1.5, -2');
    expect(readPresets(out)).toEqual([{ name: 'big', values: [1.5, -2] }]);
  });

  it('replaces a preset of the same name, keeps the others', () => {
    let out = writePreset(src, { name: 'a', values: [1] });
    out = writePreset(out, { name: 'b', values: [2] });
    out = writePreset(out, { name: 'a', values: [3] });
    expect(readPresets(out)).toEqual([
      { name: 'a', values: [3] },
      { name: 'b', values: [2] },
    ]);
    expect(readPresets(removePreset(out, 'a'))).toEqual([{ name: 'b', values: [2] }]);
  });

  it('ignores malformed lines and keeps names clean', () => {
    expect(readPresets('-- preset: x = 1, abc\n-- preset x = 1\n-- preset: ok = 1e-3')).toEqual([{ name: 'ok', values: [0.001] }]);
    const out = writePreset('', { name: 'a=b', values: [1] });
    expect(readPresets(out)).toEqual([{ name: 'a b', values: [1] }]);
  });

  it('round-trips values exactly enough for sliders', () => {
    const v = [0.1 + 0.2, 1 / 3];
    const [p] = readPresets(writePreset(src, { name: 'p', values: v }));
    expect(p.values[0]).toBeCloseTo(v[0], 7);
    expect(p.values[1]).toBeCloseTo(v[1], 7);
  });
});
