/**
 * Exports end to end: each format downloads a file that parses (binary STL
 * header and triangle count, OBJ v/f lines, PLY header, GLB magic, 3MF
 * zip), at a small depth to keep the run short.
 */
import { readFileSync } from 'node:fs';
import { expect, test } from '@playwright/test';
import { createModel, uniqueName } from './support/api';
import { openModel } from './support/studio';

function checkFile(format: string, b: Buffer): void {
  switch (format) {
    case 'stl': {
      expect(b.length).toBeGreaterThan(84);
      const n = b.readUInt32LE(80);
      expect(n).toBeGreaterThan(0);
      expect(b.length).toBe(84 + 50 * n);
      break;
    }
    case 'obj': {
      const t = b.toString('utf8');
      expect(t).toMatch(/^v\s+-?\d/m);
      expect(t).toMatch(/^f\s+\d/m);
      break;
    }
    case 'ply': {
      const t = b.subarray(0, 400).toString('latin1');
      expect(t.startsWith('ply\n')).toBe(true);
      expect(t).toMatch(/element vertex \d+/);
      expect(t).toMatch(/property uchar red/);
      expect(t).toContain('end_header');
      break;
    }
    case 'glb':
      expect(b.subarray(0, 4).toString('latin1')).toBe('glTF');
      expect(b.readUInt32LE(8)).toBe(b.length);
      break;
    case '3mf':
      expect(b.subarray(0, 4)).toEqual(Buffer.from([0x50, 0x4b, 0x03, 0x04]));
      expect(b.toString('latin1')).toContain('3D/3dmodel.model');
      break;
  }
}

/** A red sphere: colours in s[1..3], so the PLY carries vertex colours. */
const RED_SPHERE = [
  'my_model(x[3], a[1], s[3])',
  '{',
  '  array c[3];',
  '  c = [0, 0, 0];',
  '  s[1] = 0.9;',
  '  s[2] = 0.2;',
  '  s[3] = 0.1;',
  '  my_model = hfSphere(x, c, 0.8);',
  '}',
  '',
].join('\n');

test('each export downloads a file that parses', async ({ page }) => {
  const d = await createModel(uniqueName('export'), RED_SPHERE);
  await openModel(page, d.model.id, 'hfSphere');
  await page.locator('.exports > summary').click();
  await page.getByLabel('Export depth').fill('4');
  for (const format of ['stl', 'obj', 'ply', 'glb', '3mf']) {
    await page.getByLabel('Export format').selectOption(format);
    const [download] = await Promise.all([page.waitForEvent('download'), page.getByRole('button', { name: 'Download', exact: true }).click()]);
    expect(download.suggestedFilename()).toMatch(new RegExp(`\\.${format}$`));
    const path = await download.path();
    checkFile(format, readFileSync(path));
    await expect(page.getByTestId('export-status')).toContainText(format.toUpperCase());
  }
});
