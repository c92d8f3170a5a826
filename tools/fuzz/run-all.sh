#!/usr/bin/env bash
# Fuzzes every target with AFL++ (cargo-afl, stable Rust) and prints what each did.
#
#   tools/fuzz/run-all.sh [EXECS] [MAX_SECONDS] [TARGET...]
#
# EXECS per target (default 10,000,000), each stopped after MAX_SECONDS at the latest
# (default: no limit); one target per CPU at a time. Needs `cargo install cargo-afl` and
# `cargo afl config --build` once. Output under tools/fuzz/out/TARGET (crashes in
# default/crashes, hangs in default/hangs); replay one with
#   tools/fuzz/target/release/fuzz-run TARGET FILE
# and make each crash a regression test in `cargo test`. See docs/reliability.md#fuzzing.
set -euo pipefail
cd "$(dirname "$0")"
execs=${1:-10000000}
max_s=${2:-0}
shift $(( $# < 2 ? $# : 2 ))
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(messages replay obj body svg dxf garmentcode outline design commands)
fi
# LLVM's coverage pass instruments every basic block for cargo-afl (`prune-blocks=0`);
# pruning the blocks whose coverage others imply (libFuzzer's default) still tells which
# blocks ran (not how often the pruned ones did) and runs the commands target 1.5x
# faster (docs/reliability.md#fuzzing).
export RUSTFLAGS="${RUSTFLAGS:-} -C llvm-args=-sanitizer-coverage-prune-blocks=1"
cargo afl build --release
rm -rf seeds
./target/release/fuzz-seeds seeds >/dev/null
export AFL_NO_UI=1 AFL_SKIP_CPUFREQ=1 AFL_I_DONT_CARE_ABOUT_MISSING_CRASHES=1
export AFL_NO_AFFINITY=1 AFL_QUIET=1
lanes=$(nproc)
run() {
    local t=$1 limit=()
    [ "$max_s" -gt 0 ] && limit=(-V "$max_s")
    rm -rf "out/$t"
    # -t: an input that takes over 1 s is a hang; -m none: the targets allocate as the
    # programs do (the oversized-input limits are what is being tested).
    cargo afl fuzz -i "seeds/$t" -o "out/$t" -t 1000 -m none -E "$execs" "${limit[@]}" \
        "target/release/$t" >"out-$t.log" 2>&1 || echo "$t: afl-fuzz exited $?" >&2
}
mkdir -p out
running=0
for t in "${targets[@]}"; do
    run "$t" &
    running=$((running + 1))
    if [ "$running" -ge "$lanes" ]; then
        wait -n
        running=$((running - 1))
    fi
done
wait
printf '%-12s %12s %10s %8s %8s %6s %6s\n' target execs exec/s seconds paths crash hang
for t in "${targets[@]}"; do
    s="out/$t/default/fuzzer_stats"
    [ -f "$s" ] || { echo "$t: no stats (see tools/fuzz/out-$t.log)"; continue; }
    get() { awk -F' *: *' -v k="$1" '$1 == k { print $2 }' "$s"; }
    printf '%-12s %12s %10s %8s %8s %6s %6s\n' "$t" "$(get execs_done)" "$(get execs_per_sec)" \
        "$(get run_time)" "$(get corpus_count)" "$(get saved_crashes)" "$(get saved_hangs)"
done
