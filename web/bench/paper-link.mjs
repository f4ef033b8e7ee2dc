/**
 * An emulated network link: a TCP proxy on 127.0.0.1 between the browser
 * and the frep server that shapes both directions of every connection
 * (HTTP and WebSocket alike, which CDP's network emulation does not: it
 * leaves the WebSocket at loopback speed).
 *
 * Algorithm, per direction of each connection: a byte stream leaves the
 * sender in segments of at most 1460 bytes (one TCP segment on Ethernet,
 * so a small message is not delivered late with the bytes read after
 * it: larger chunks made the server's bandwidth probe, a ping then 16 kB,
 * arrive at once); each segment is serialised on the
 * link after the previous one (`free = max(now, free) + bytes·8/rate`),
 * then delivered one one-way delay (RTT/2) later. The link's rate is
 * shared by the connections of one direction (one `free` clock per
 * direction for the whole link), as a real access link would be. Order
 * is kept because delivery times only grow. Loopback (no rate, no delay)
 * needs no proxy.
 */
import { createServer, connect } from 'node:net';

const CHUNK = 1460;

/** One direction of the link: a shared serialisation clock. */
function direction(bps) {
  return { bps, free: 0 };
}

/** Pipes `from` to `to` through the shaped direction `dir` with one-way delay `delayMs`. */
function shape(from, to, dir, delayMs) {
  let lastAt = 0;
  from.on('data', (buf) => {
    for (let o = 0; o < buf.length; o += CHUNK) {
      const part = buf.subarray(o, Math.min(buf.length, o + CHUNK));
      const now = performance.now();
      dir.free = Math.max(now, dir.free) + (part.length * 8 * 1000) / dir.bps;
      // Delivery times of one stream never decrease (TCP keeps order).
      const at = Math.max(lastAt, dir.free + delayMs);
      lastAt = at;
      setTimeout(() => {
        if (!to.destroyed) to.write(part);
      }, Math.max(0, at - now));
    }
  });
  from.on('end', () => setTimeout(() => to.end(), Math.max(0, lastAt - performance.now()) + 1));
  from.on('error', () => to.destroy());
}

/**
 * Starts a shaped proxy to `target` ("http://127.0.0.1:PORT").
 * `link`: { mbps, rttMs }. Resolves with { url, stop() }.
 */
export function startLink(target, link) {
  const t = new URL(target);
  const down = direction(link.mbps * 1e6);
  const up = direction(link.mbps * 1e6);
  const oneWay = link.rttMs / 2;
  const sockets = new Set();
  const server = createServer((client) => {
    const upstream = connect(Number(t.port), t.hostname);
    sockets.add(client).add(upstream);
    client.setNoDelay(true);
    upstream.setNoDelay(true);
    shape(client, upstream, up, oneWay);
    shape(upstream, client, down, oneWay);
    const close = () => {
      client.destroy();
      upstream.destroy();
      sockets.delete(client);
      sockets.delete(upstream);
    };
    client.on('close', close);
    upstream.on('close', close);
  });
  return new Promise((ok, fail) => {
    server.once('error', fail);
    server.listen(0, '127.0.0.1', () => {
      const url = `http://127.0.0.1:${server.address().port}`;
      ok({
        url,
        /** Delay a body of `bytes` served outside the link (page.route) would have taken on it. */
        costMs: (bytes) => link.rttMs + (bytes * 8 * 1000) / (link.mbps * 1e6),
        stop: () =>
          new Promise((r) => {
            for (const s of sockets) s.destroy();
            server.close(() => r());
          }),
      });
    });
  });
}
