#!/usr/bin/env bash
# Builds the frep kernel for the browser (crates/frep-wasm) into
# web/public/frep.wasm: release, SIMD (simd128) on, no debug info.
#
# Needs only cargo and the wasm32-unknown-unknown target (`rustup target add
# wasm32-unknown-unknown`, once): the module has a raw ABI, so there is no
# wasm-bindgen CLI to install. No wasm-opt either: Debian's build breaks the
# module it rewrites.
#
# Its own target directory (target/wasm): RUSTFLAGS differ from the native
# build's, and sharing target/ would rebuild the native crates every time.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if ! rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
  echo "build-wasm: the wasm32-unknown-unknown target is missing: rustup target add wasm32-unknown-unknown" >&2
  exit 1
fi
RUSTFLAGS="-C target-feature=+simd128" \
CARGO_PROFILE_RELEASE_DEBUG=0 \
CARGO_PROFILE_RELEASE_STRIP=debuginfo \
  cargo build --release --target wasm32-unknown-unknown -p frep-wasm --target-dir target/wasm "$@"
mkdir -p web/public
cp target/wasm/wasm32-unknown-unknown/release/frep_wasm.wasm web/public/frep.wasm.tmp
mv web/public/frep.wasm.tmp web/public/frep.wasm
echo "build-wasm: web/public/frep.wasm ($(wc -c < web/public/frep.wasm) bytes)"
