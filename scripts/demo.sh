#!/usr/bin/env bash
# The main job on a fresh machine: check an example model, evaluate it at a few
# points, render a still image (delivery mode 1) and mesh it (mode 3).
# Usage: scripts/demo.sh [MODEL.hf]   (default: examples/sake_pot.hf)
set -euo pipefail
cd "$(dirname "$0")/.."
model="${1:-examples/sake_pot.hf}"
name="$(basename "$model" .hf)"
out=target/demo
cargo build --release --locked -p frep-cli
frep=target/release/frep
mkdir -p "$out"
echo "== frep check $model"
"$frep" check "$model"
echo "== frep eval $model (x y z per line; positive values are inside)"
"$frep" eval "$model" <<'POINTS'
0 0 0
0 0 -0.9
0.72 0 -0.3
0 0 0.9
2 2 2
POINTS
echo "== frep render $model -o $out/$name.png"
"$frep" render "$model" -o "$out/$name.png" --size 512,512
echo "== frep mesh $model -o $out/$name.glb"
"$frep" mesh "$model" -o "$out/$name.glb" --depth 7 --quiet
echo "== wrote $out/$name.png and $out/$name.glb"
