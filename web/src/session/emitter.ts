/**
 * A small typed event emitter: `on` returns the unsubscribe; a listener
 * that throws is reported on the console and does not stop the others.
 */
type Listener = (...a: unknown[]) => void;

/** Typed events `E` (event name → argument tuple). */
export class Emitter<E extends Record<string, unknown[]>> {
  private readonly map = new Map<keyof E, Set<Listener>>();

  /** Adds a listener; returns the function that removes it. */
  on<K extends keyof E>(event: K, cb: (...args: E[K]) => void): () => void {
    let set = this.map.get(event);
    if (!set) this.map.set(event, (set = new Set()));
    set.add(cb as unknown as Listener);
    return () => set.delete(cb as unknown as Listener);
  }

  /** Calls every listener of `event`. */
  emit<K extends keyof E>(event: K, ...args: E[K]): void {
    const set = this.map.get(event);
    if (!set) return;
    for (const cb of [...set]) {
      try {
        (cb as unknown as (...a: E[K]) => void)(...args);
      } catch (e) {
        console.error(`listener of ${String(event)} failed`, e);
      }
    }
  }

  /** Whether `event` has a listener. */
  has<K extends keyof E>(event: K): boolean {
    return (this.map.get(event)?.size ?? 0) > 0;
  }

  /** Removes every listener. */
  clear(): void {
    this.map.clear();
  }
}
