// Validates .glb files with the Khronos glTF validator.
//
// Usage: node validate_glb.mjs <npm prefix> <file.glb>...
// where <npm prefix>/node_modules holds `gltf-validator` and `meshoptimizer`.
//
// The validator does not implement EXT_meshopt_compression, so each file that uses it is
// also decompressed with meshoptimizer's JavaScript decoder (the one three.js's GLTFLoader
// uses through MeshoptDecoder) into a plain GLB, which is validated in full: accessor
// bounds, index ranges and normal lengths of the decoded data.
// Prints every report and exits with status 1 when any file has errors.
import { createRequire } from 'node:module';
import { readFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { pathToFileURL } from 'node:url';

const [prefix, ...files] = process.argv.slice(2);
const modules = join(resolve(prefix), 'node_modules');
const validator = createRequire(join(modules, 'noop.js'))('gltf-validator');
const { MeshoptDecoder } = await import(pathToFileURL(join(modules, 'meshoptimizer/meshopt_decoder.mjs')).href);
await MeshoptDecoder.ready;

const MESHOPT = 'EXT_meshopt_compression';

function parseGlb(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let json, bin = new Uint8Array(0);
  for (let at = 12; at + 8 <= view.getUint32(8, true); ) {
    const len = view.getUint32(at, true), type = view.getUint32(at + 4, true);
    const data = bytes.subarray(at + 8, at + 8 + len);
    if (type === 0x4e4f534a) json = JSON.parse(new TextDecoder().decode(data));
    if (type === 0x004e4942) bin = data;
    at += 8 + len;
  }
  return { json, bin };
}

function writeGlb(json, bin) {
  let text = new TextEncoder().encode(JSON.stringify(json));
  const pad = (n) => (4 - (n % 4)) % 4;
  const jsonLen = text.length + pad(text.length), binLen = bin.length + pad(bin.length);
  const out = new Uint8Array(12 + 8 + jsonLen + 8 + binLen);
  const view = new DataView(out.buffer);
  view.setUint32(0, 0x46546c67, true); view.setUint32(4, 2, true); view.setUint32(8, out.length, true);
  view.setUint32(12, jsonLen, true); view.setUint32(16, 0x4e4f534a, true);
  out.fill(0x20, 20, 20 + jsonLen); out.set(text, 20);
  view.setUint32(20 + jsonLen, binLen, true); view.setUint32(24 + jsonLen, 0x004e4942, true);
  out.set(bin, 28 + jsonLen);
  return out;
}

/// Decompresses every meshopt buffer view into the fallback buffer's layout.
function decompress(bytes) {
  const { json, bin } = parseGlb(bytes);
  const fallback = json.buffers.findIndex((b) => b.extensions?.[MESHOPT]?.fallback);
  const out = new Uint8Array(json.buffers[fallback].byteLength);
  for (const bv of json.bufferViews) {
    const ext = bv.extensions?.[MESHOPT];
    if (!ext) throw new Error('uncompressed view in a meshopt file');
    const source = bin.subarray(ext.byteOffset ?? 0, (ext.byteOffset ?? 0) + ext.byteLength);
    const target = new Uint8Array(ext.count * ext.byteStride);
    MeshoptDecoder.decodeGltfBuffer(target, ext.count, ext.byteStride, source, ext.mode, ext.filter ?? 'NONE');
    out.set(target, bv.byteOffset ?? 0);
    delete bv.extensions;
    bv.buffer = 0;
  }
  json.buffers = [{ byteLength: out.length }];
  json.extensionsUsed = json.extensionsUsed.filter((e) => e !== MESHOPT);
  json.extensionsRequired = json.extensionsRequired.filter((e) => e !== MESHOPT);
  return writeGlb(json, out);
}

async function validate(name, bytes) {
  const report = await validator.validateBytes(bytes, {
    maxIssues: 100,
    externalResourceFunction: (uri) => Promise.reject(new Error(`unexpected external resource ${uri}`)),
  });
  const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
  console.log(`${name}: validator ${report.validatorVersion}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints`);
  for (const m of messages) {
    console.log(`  [${['error', 'warning', 'info', 'hint'][m.severity]}] ${m.code} at ${m.pointer ?? ''}: ${m.message}`);
  }
  return numErrors === 0;
}

let ok = true;
for (const file of files) {
  const bytes = new Uint8Array(readFileSync(file));
  ok = (await validate(file, bytes)) && ok;
  if (parseGlb(bytes).json.extensionsUsed?.includes(MESHOPT)) {
    ok = (await validate(`${file} (decompressed by MeshoptDecoder)`, decompress(bytes))) && ok;
  }
}
process.exit(ok ? 0 : 1);
