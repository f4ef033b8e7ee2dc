#!/usr/bin/env bash
# The test command of this repository (README.md, "Tests"): every test of
# every part, after scripts/setup.sh has installed the non-Rust tools it
# finds missing.
#   1. Rust: every crate's unit, integration and doc tests;
#   2. the kernel for the browser: scripts/build-wasm.sh (wasm32 + SIMD);
#   3. the studio (web/): type check, unit tests (the WASM kernel's
#      conformance included), the production build;
#   4. end to end: the release `frep` serves the built studio and Playwright
#      drives Debian's Chromium against it (web/tests/e2e).
# Extra arguments run only the Rust tests, with those arguments, e.g.
#   scripts/test.sh -p frep-core
# The fidget anchors of frep-bench are behind its `anchors` feature and are not
# built here (see crates/frep-bench/Cargo.toml); test them with
#   cargo test -p frep-bench --features anchors
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
if [ $# -gt 0 ]; then
    exec cargo test --workspace --locked "$@"
fi
step() { printf '\n--> %s\n' "$*"; }

step "cargo test --workspace"
cargo test --workspace --locked

step "the WASM kernel"
scripts/build-wasm.sh

step "studio: type check, unit tests, build"
(cd web && npm run --silent typecheck)
(cd web && FREP_REQUIRE_WASM=1 npx vitest run)
(cd web && npx vite build --logLevel warn)

step "studio: end to end (release frep, headless Chromium)"
cargo build --release --locked -p frep-cli
(cd web && FREP_E2E_NO_BUILD=1 npx playwright test)
