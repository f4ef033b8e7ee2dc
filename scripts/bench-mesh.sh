#!/usr/bin/env bash
# Meshing benchmark: ours (watertight, dual contouring, uniform MC baseline, and our smallest
# verified simplification at fidget's symmetric Hausdorff error) side by side with fidget 0.5
# on M1-M4 and the examples (via to_fidget), same box and depth, at depths 6, 7, 8.
# Prints a Markdown table. Env: FREP_BENCH_REPS (3), FREP_BENCH_DEPTHS (6,7,8),
# FREP_BENCH_MODELS (a part of the row's name, or =NAME for exactly that name).
set -euo pipefail
cd "$(dirname "$0")/.."
exec cargo bench -p frep-bench --features anchors --bench mesh -- "$@"
