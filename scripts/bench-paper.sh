#!/usr/bin/env bash
# The seed paper's experiment in a real browser, and the adaptive choice
# measured (docs/paper.md). Needs target/release/frep and web/dist (the
# README's setup: scripts/test.sh builds both). Arguments go to
# web/bench/paper-bench.mjs: --quick (CI: two models, two profiles, one
# repetition; non-zero exit when a case shows no non-blank frame),
# --reps N, --models a,b, --techs a,b, --profiles FILE, --base FILE,
# --out DIR.
# Environment: FREP_BIN, FREP_CHROMIUM, FREP_BENCH_CASE_TIMEOUT_MS.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root/web"
exec node bench/paper-bench.mjs "$@"
