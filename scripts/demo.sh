#!/usr/bin/env bash
# The main job on a fresh machine: check an example model and evaluate it at a
# few points (x y z per line on stdin; positive values are inside).
# Usage: scripts/demo.sh [MODEL.hf]   (default: examples/sake_pot.hf)
set -euo pipefail
cd "$(dirname "$0")/.."
model="${1:-examples/sake_pot.hf}"
cargo build --release --locked -p frep-cli
frep=target/release/frep
echo "== frep check $model"
"$frep" check "$model"
echo "== frep eval $model"
"$frep" eval "$model" <<'POINTS'
0 0 0
0 0 -0.9
0.72 0 -0.3
0 0 0.9
2 2 2
POINTS
