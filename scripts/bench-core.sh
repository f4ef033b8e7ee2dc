#!/usr/bin/env bash
# frep's kernel benchmark against fidget 0.5 on the same models, in one run
# (crates/frep-bench/benches/core.rs): compile times of the examples and of the
# shared HyperFun corpus (when present), batch (1M points) and interval (4096
# boxes) throughput of frep, fidget's VM and fidget's JIT, then a plain table
# with the ratios frep / fidget.
#
# Extra arguments go to criterion, e.g. a filter: scripts/bench-core.sh m3_gyroid
# Environment: FREP_BENCH_CRITERION=0 prints the table only (about a minute),
# FREP_BENCH_TABLE=0 runs criterion only, FREP_HYPERFUN_CORPUS=<dir> names the
# corpus folder. Without fidget: cargo bench -p frep-bench --bench core
set -euo pipefail
cd "$(dirname "$0")/.."
cargo bench -p frep-bench --features anchors --bench core -- "$@"
