#!/usr/bin/env bash
# Runs the `parse` fuzz target (lexer, parser, compiler and evaluators) for
# SECONDS (default 60) with cargo-fuzz.
#
#   crates/frep-core/fuzz/run.sh [SECONDS] [extra libFuzzer flags...]
#
# Installs cargo-fuzz if it is missing. Uses the nightly toolchain when one is
# installed, else the stable one with RUSTC_BOOTSTRAP=1 (cargo-fuzz needs
# nightly-only sanitizer flags). The seed corpus (conformance models, and the
# shared HyperFun corpus when present) is copied into fuzz/corpus/parse, which
# is git-ignored; crashes land in fuzz/artifacts/parse.
set -euo pipefail

secs="${1:-60}"
shift || true
fuzz_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
crate_dir="$(dirname "$fuzz_dir")"

if ! cargo fuzz --version >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked
fi

toolchain=()
if cargo +nightly --version >/dev/null 2>&1; then
    toolchain=(+nightly)
else
    export RUSTC_BOOTSTRAP=1
fi

corpus="$fuzz_dir/corpus/parse"
mkdir -p "$corpus"
seed() {
    local f
    for f in "$1"/*.hf; do
        [ -f "$f" ] || continue
        # Keep seeds small so that mutations stay fast.
        if [ "$(wc -c <"$f")" -le 16384 ]; then
            cp -f "$f" "$corpus/seed-$(basename "$f")"
        fi
    done
}
seed "$crate_dir/tests/data/conformance"
for shared in "$crate_dir/../../../shared/hyperfun/corpus" "$crate_dir/../../../../shared/hyperfun/corpus"; do
    if [ -d "$shared" ]; then
        seed "$shared"
        break
    fi
done

cd "$crate_dir"
exec cargo "${toolchain[@]}" fuzz run parse --fuzz-dir "$fuzz_dir" "$corpus" -- \
    -max_total_time="$secs" -max_len=16384 -dict="$fuzz_dir/hyperfun.dict" -print_final_stats=1 "$@"
