/**
 * The kernel's Web Worker: loads frep.wasm and serves the protocol
 * (protocol.ts) through KernelHost, so that compiling, meshing and
 * generating shaders never block the page.
 */
/// <reference lib="webworker" />
import { FrepKernel } from './kernel';
import { KernelHost } from './host';
import type { KernelRequest } from './protocol';

const scope = self as unknown as DedicatedWorkerGlobalScope;

const host = new KernelHost(
  null,
  (r, transfer) => scope.postMessage(r, transfer ?? []),
  (url) => FrepKernel.fromUrl(url),
);

scope.onmessage = (ev: MessageEvent<KernelRequest>) => {
  void host.handle(ev.data);
};
