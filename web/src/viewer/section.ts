/**
 * The section plane on the wire: what the server-drawn modes (the still,
 * its streamed frames, the view set) send with their requests, and when a
 * new plane asks for a new picture.
 *
 * No plane is sent as an absent field, never as `null`: the spec's JSON,
 * and with it the artefact's content address, is then the one it was
 * before sections existed (a cached picture stays a cache hit).
 */
import type { SectionPlane as WireSection } from '../wire';
import type { SectionPlane } from './types';

/** The spec field of a plane: `{ section }`, or nothing without one. */
export function sectionField(s: SectionPlane | null): { section?: WireSection } {
  return s ? { section: { normal: [s.normal[0], s.normal[1], s.normal[2]], offset: s.offset } } : {};
}

/** Whether two planes (or none) cut the same way: a new picture is needed when not. */
export function sameSection(a: SectionPlane | null, b: SectionPlane | null): boolean {
  if (a === null || b === null) return a === b;
  return a.offset === b.offset && a.normal[0] === b.normal[0] && a.normal[1] === b.normal[1] && a.normal[2] === b.normal[2];
}
