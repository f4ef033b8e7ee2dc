#!/usr/bin/env bash
# The studio's performance bench (headless Chromium on loopback): see
# docs/bench-studio.md. Needs target/release/frep (cargo build --release -p
# frep-cli) and web/dist (scripts/build-wasm.sh, then cd web && npx vite build).
# Arguments go to web/bench/studio-bench.mjs: --quick (two models, still and
# auto, one repetition), --out FILE. Environment: FREP_BENCH_REPS,
# FREP_BENCH_URL, FREP_BENCH_CASE_TIMEOUT_MS, FREP_BIN, FREP_CHROMIUM.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root/web"
exec node bench/studio-bench.mjs "$@"
