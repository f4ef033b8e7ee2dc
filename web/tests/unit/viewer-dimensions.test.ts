import { describe, expect, it } from 'vitest';
import { boxSizes, formatLength } from '../../src/viewer/dimensions';
import { backgroundAt, backgroundCss, cssColor } from '../../src/viewer/scene';

describe('dimensions', () => {
  it('measures the model box', () => {
    expect(boxSizes([-1, -2, 0, 3, 2, 0.5])).toEqual([4, 4, 0.5]);
  });

  it('writes lengths with four significant digits', () => {
    expect(formatLength(4)).toBe('4');
    expect(formatLength(1.23456)).toBe('1.235');
    expect(formatLength(0.000123456)).toBe('0.0001235');
    expect(formatLength(12345.6)).toBe('12350');
  });
});

describe('background', () => {
  it('is the server renderer ramp: top colour at the first row, bottom at the last', () => {
    expect(backgroundAt(0)).toEqual([66, 74, 87]);
    expect(backgroundAt(1)).toEqual([23, 26, 31]);
    expect(backgroundAt(0.5)).toEqual([45, 50, 59]);
    expect(backgroundAt(-3)).toEqual(backgroundAt(0));
    expect(cssColor([1, 0, 0.5])).toBe('rgb(255, 0, 128)');
    expect(backgroundCss()).toBe('linear-gradient(to bottom, rgb(66, 74, 87), rgb(23, 26, 31))');
  });
});
