#!/usr/bin/env bash
# The test command of this repository (README.md, "Tests"): every crate's unit,
# integration and doc tests, after scripts/setup.sh has installed the non-Rust
# test tools it finds missing. Extra arguments go to `cargo test`, e.g.
#   scripts/test.sh -p frep-core
# The fidget anchors of frep-bench are behind its `anchors` feature and are not
# built here (see crates/frep-bench/Cargo.toml); test them with
#   cargo test -p frep-bench --features anchors
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cargo test --workspace --locked "$@"
