import { describe, expect, it } from 'vitest';
import { LatestFrames } from '../../src/session/latest';

type F = { seq: number };

/** A show function whose frames finish when the test says. */
function controlled() {
  const started: number[] = [];
  const finish: (() => void)[] = [];
  const show = (f: F) =>
    new Promise<boolean>((ok) => {
      started.push(f.seq);
      finish.push(() => ok(true));
    });
  return { started, finish, show };
}

const tick = () => new Promise((r) => setTimeout(r, 0));

describe('latest-only frames', () => {
  it('shows only the newest of frames that arrive while one decodes', async () => {
    const c = controlled();
    const shown: number[] = [];
    const pump = new LatestFrames<F>(c.show, (f) => shown.push(f.seq));
    pump.push({ seq: 1 });
    pump.push({ seq: 2 });
    pump.push({ seq: 3 });
    pump.push({ seq: 4 });
    expect(c.started).toEqual([1]);
    c.finish[0]();
    await tick();
    expect(c.started).toEqual([1, 4]);
    c.finish[1]();
    await tick();
    expect(shown).toEqual([1, 4]);
    expect(pump.dropped).toBe(2);
    expect(pump.lastSeq).toBe(4);
  });

  it('drops frames older than the one shown and out-of-order arrivals', async () => {
    const c = controlled();
    const pump = new LatestFrames<F>(c.show);
    pump.push({ seq: 5 });
    c.finish[0]();
    await tick();
    pump.push({ seq: 3 });
    expect(c.started).toEqual([5]);
    pump.push({ seq: 9 });
    pump.push({ seq: 8 }); // older than the waiting 9
    c.finish[1]();
    await tick();
    expect(c.started).toEqual([5, 9]);
    expect(pump.dropped).toBe(2);
  });

  it('a frame that fails to show is not counted and the next one still goes', async () => {
    let n = 0;
    const shown: number[] = [];
    const pump = new LatestFrames<F>(
      async () => ++n !== 1,
      (f) => shown.push(f.seq),
    );
    pump.push({ seq: 1 });
    await tick();
    pump.push({ seq: 2 });
    await tick();
    expect(shown).toEqual([2]);
  });

  it('every frame is either shown or dropped, exactly once', async () => {
    const c = controlled();
    const shown: number[] = [];
    const dropped: number[] = [];
    const pump = new LatestFrames<F>(c.show, (f) => shown.push(f.seq), (f) => dropped.push(f.seq));
    for (const seq of [1, 2, 3, 2, 5]) pump.push({ seq });
    c.finish[0]();
    await tick();
    c.finish[1]();
    await tick();
    pump.push({ seq: 4 });
    expect(shown).toEqual([1, 5]);
    expect(dropped.sort()).toEqual([2, 2, 3, 4]);
  });

  it('reset starts the order again (a new model)', async () => {
    const shown: number[] = [];
    const pump = new LatestFrames<F>(async () => true, (f) => shown.push(f.seq));
    pump.push({ seq: 10 });
    await tick();
    pump.reset();
    pump.push({ seq: 1 });
    await tick();
    expect(shown).toEqual([10, 1]);
  });
});
