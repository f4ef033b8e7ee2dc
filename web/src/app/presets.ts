/**
 * Named parameter presets, kept in the source as comments so they are
 * saved with the version and travel with the model:
 * `-- preset: NAME = v1, v2, …` (values of `a[1]`, `a[2]`, …).
 * The kernel ignores comments, so presets never change the shape.
 */

/** A named set of parameter values. */
export interface Preset {
  name: string;
  values: number[];
}

const LINE = /^--\s*preset:\s*(.+?)\s*=\s*([-+0-9.eE,\s]*)$/;

/** The presets of a source, in order (a later one of the same name wins). */
export function readPresets(src: string): Preset[] {
  const byName = new Map<string, Preset>();
  for (const line of src.split('\n')) {
    const m = LINE.exec(line.trim());
    if (!m) continue;
    const values = m[2].split(',').map((s) => s.trim()).filter(Boolean).map(Number);
    if (values.some((v) => !Number.isFinite(v))) continue;
    byName.set(m[1], { name: m[1], values });
  }
  return [...byName.values()];
}

/** The comment line of a preset. */
export function presetLine(p: Preset): string {
  const name = p.name.replace(/[=\n\r]/g, ' ').trim();
  return `-- preset: ${name} = ${p.values.map((v) => String(Number(v.toPrecision(8)))).join(', ')}`;
}

/**
 * Writes a preset into a source: replaces the line of the same name, else
 * adds it after the leading comment block (before the first body).
 */
export function writePreset(src: string, p: Preset): string {
  const lines = src.split('\n');
  const line = presetLine(p);
  const at = lines.findIndex((l) => LINE.exec(l.trim())?.[1] === p.name.trim());
  if (at >= 0) {
    lines[at] = line;
    return lines.join('\n');
  }
  let insert = 0;
  while (insert < lines.length && lines[insert].trim().startsWith('--')) insert++;
  lines.splice(insert, 0, line);
  return lines.join('\n');
}

/** Removes a preset's line. */
export function removePreset(src: string, name: string): string {
  return src
    .split('\n')
    .filter((l) => LINE.exec(l.trim())?.[1] !== name.trim())
    .join('\n');
}
