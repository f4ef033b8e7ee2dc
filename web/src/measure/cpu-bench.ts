/**
 * The JS main-thread benchmark: a fixed loop of floating-point work (an
 * implicit sphere-and-torus field sampled on a grid), timed with
 * `performance.now()`. Slow CPUs and throttled pages show as larger ms.
 * The loop's result is returned so the engine cannot drop the work.
 */

/** Samples per run (about 2–5 ms on a desktop). */
export const CPU_BENCH_SAMPLES = 200_000;

/** Runs the loop once; `now` is the clock. */
export function cpuBench(now: () => number = () => performance.now(), samples = CPU_BENCH_SAMPLES): { ms: number; checksum: number } {
  const t0 = now();
  let acc = 0;
  const n = Math.max(1, Math.round(Math.cbrt(samples)));
  for (let i = 0; i < n; i++) {
    const x = -1.5 + (3 * i) / n;
    for (let j = 0; j < n; j++) {
      const y = -1.5 + (3 * j) / n;
      for (let k = 0; k < n; k++) {
        const z = -1.5 + (3 * k) / n;
        const sphere = 1 - (x * x + y * y + z * z);
        const q = Math.sqrt(x * x + y * y) - 0.8;
        const torus = 0.09 - (q * q + z * z);
        acc += Math.max(sphere, torus) + Math.sin(x * 3) * 0.01;
      }
    }
  }
  return { ms: now() - t0, checksum: acc };
}
