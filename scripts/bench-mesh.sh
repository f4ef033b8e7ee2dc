#!/usr/bin/env bash
# Meshing benchmark: ours (watertight, +simplification, dual contouring, uniform MC
# baseline) side by side with fidget 0.5 on M1-M4 and the examples, at depths 6, 7, 8.
# Prints a Markdown table. Env: FREP_BENCH_REPS (3), FREP_BENCH_DEPTHS (6,7,8),
# FREP_BENCH_MODELS (substring filter).
set -euo pipefail
cd "$(dirname "$0")/.."
exec cargo bench -p frep-bench --features anchors --bench mesh -- "$@"
