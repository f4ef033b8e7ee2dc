/**
 * The viewer's probe hooks (src/viewer/probe.ts's ProbeHooks), answered by
 * the WebAssembly kernel in the studio's worker: the field value and the
 * attributes at a point (the point evaluator, as the server's), and the
 * first surface point along a pixel's ray for the modes that cannot say
 * where their pixels are.
 */
import { sharedKernel } from './client';

/** Field value and attributes at a point. */
export async function probePoint(req: {
  source: string;
  params: number[];
  point: [number, number, number];
}): Promise<{ value: number; attributes: number[] }> {
  const k = sharedKernel();
  await k.whenReady();
  const hit = await k.probe({ source: req.source, params: req.params, point: req.point });
  if (!hit) throw new Error('no value at this point');
  return { value: hit.value, attributes: hit.attributes };
}

/** The first surface point along a ray inside the box, with its value and attributes. */
export async function probeRay(req: {
  source: string;
  params: number[];
  bounds: readonly number[];
  origin: [number, number, number];
  dir: [number, number, number];
}): Promise<{ point: [number, number, number]; value: number; attributes: number[] } | null> {
  const k = sharedKernel();
  await k.whenReady();
  return k.probe({ source: req.source, params: req.params, ray: { origin: req.origin, dir: req.dir, bounds: req.bounds.slice() } });
}
