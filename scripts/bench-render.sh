#!/usr/bin/env bash
# Render benchmark: frep's ray caster on M1-M4 and every example at 512² and
# 1024² (2 threads and 1 thread, peak heap beyond the image), side by side
# with fidget 0.5's 3D renderer (JIT and VM) on M1-M4, same view and size.
# Prints a Markdown table. Options through the environment:
#   FREP_BENCH_REPS=N   runs per measurement at least, minimum reported (default 3)
#   FREP_BENCH_MIN_MS=T ...and more runs until they took T ms in all (default 1000)
#   (ours on 2 threads, top view, is measured in ~50 ms turns with fidget)
#   FREP_BENCH_SLOW=1   also run fidget's interpreter on M4 (minutes)
# Extra arguments: a model-name filter, e.g. `scripts/bench-render.sh m4`.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo bench -p frep-bench --features anchors --bench render -- "$@"
