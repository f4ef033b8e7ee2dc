#!/usr/bin/env bash
# The studio on a fresh clone: builds what is needed and starts the server on
# http://127.0.0.1:8080 with the example models loaded.
#
#   scripts/studio.sh                 # data in target/studio-data (FREP_DATA overrides)
#   scripts/studio.sh --config frep.json
#
# Steps: the browser kernel (web/public/frep.wasm, scripts/build-wasm.sh) when
# the wasm32 target is installed; the studio (web/dist: npm ci when
# web/node_modules is missing, then npm run build) when web/index.html
# exists; then `frep serve` in release mode. Without a built studio the
# server answers / with its own HTML list of the models (images and
# downloads). Extra arguments go to `frep serve`. Ctrl-C stops it gracefully.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
data="${FREP_DATA:-target/studio-data}"

if [ -f web/index.html ]; then
  if rustup target list --installed 2>/dev/null | grep -qx wasm32-unknown-unknown; then
    scripts/build-wasm.sh
  else
    echo "studio: no wasm32-unknown-unknown target: the studio runs without its browser kernel" >&2
    echo "studio: (rustup target add wasm32-unknown-unknown, then run this again)" >&2
  fi
  if ! command -v npm >/dev/null 2>&1; then
    echo "studio: npm is missing (Node.js 20 with npm): install it, or run scripts/setup.sh" >&2
    exit 1
  fi
  if [ ! -d web/node_modules ]; then
    (cd web && npm ci)
  fi
  (cd web && npm run build)
fi

cargo build --release --locked -p frep-cli
echo "studio: http://127.0.0.1:8080 (data in $data)"
exec target/release/frep serve --addr 127.0.0.1:8080 --data "$data" --static web/dist "$@"
