#!/usr/bin/env bash
# Installs what the tests need beyond the Rust toolchain, when it is missing.
# Idempotent and quiet when everything is there; run by scripts/test.sh and
# .ci/run. System packages need root (apt-get), as on the project's machines.
#   - glslangValidator (Debian glslang-tools): validates generated WebGL2 shaders;
#   - Debian's chromium: renders them (headless, SwiftShader WebGL2);
#   - node + npm: the Khronos glTF validator (installed by frep-mesh's test
#     itself), playwright-core for the shader harness (never downloads a
#     browser; versions locked in crates/frep-glsl/tests/browser), and the
#     studio's packages (web/, locked in web/package-lock.json);
#   - the wasm32 target, for the studio's kernel (scripts/build-wasm.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

apt_packages=()
command -v glslangValidator >/dev/null 2>&1 || apt_packages+=(glslang-tools)
[ -x /usr/lib/chromium/chromium ] || apt_packages+=(chromium)
if [ ${#apt_packages[@]} -gt 0 ]; then
    echo "setup: installing ${apt_packages[*]}"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${apt_packages[@]}" >/dev/null
fi
for tool in node npm; do
    command -v "$tool" >/dev/null 2>&1 || { echo "setup: $tool is required (Node.js with npm)" >&2; exit 1; }
done
# The studio's packages: installed again whenever the lock file is newer
# than the last install (npm writes node_modules/.package-lock.json).
if [ ! -f web/node_modules/.package-lock.json ] || [ web/package-lock.json -nt web/node_modules/.package-lock.json ]; then
    echo "setup: npm ci in web"
    npm ci --prefix web --no-audit --no-fund --loglevel=error
fi
if command -v rustup >/dev/null 2>&1 && ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
    echo "setup: rustup target add wasm32-unknown-unknown"
    rustup target add wasm32-unknown-unknown
fi
if [ ! -d crates/frep-glsl/tests/browser/node_modules/playwright-core ]; then
    echo "setup: npm ci in crates/frep-glsl/tests/browser"
    npm ci --prefix crates/frep-glsl/tests/browser --no-audit --no-fund --loglevel=error
fi
