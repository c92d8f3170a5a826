#!/usr/bin/env bash
# Fuzzes every target with AFL++ (cargo-afl, stable Rust) and prints what each did.
#
#   tools/fuzz/run-all.sh [EXECS] [MAX_SECONDS] [TARGET...]
#
# EXECS per target (default 10,000,000), each stopped after MAX_SECONDS at the latest
# (default: no limit); one instance per CPU at a time, the slow targets (outline, design,
# commands) as two instances of half the executions each. Needs `cargo install
# cargo-afl` and `cargo afl config --build` once. Output under tools/fuzz/out/TARGET
# (crashes in INSTANCE/crashes, hangs in INSTANCE/hangs; INSTANCE is default, or m and
# s2); replay one with
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
# The slow targets (hundreds to a few thousand executions a second) run as two
# instances on one output, a main (-M m) and a secondary (-S s2) sharing their finds,
# each to half the executions; the others as one. Jobs wait for a free CPU in this order.
slow=" outline design commands "
jobs=()
for t in "${targets[@]}"; do
    rm -rf "out/$t"
    if [[ $slow == *" $t "* && $lanes -gt 1 ]]; then
        jobs+=("$t m $(( (execs + 1) / 2 ))" "$t s2 $(( execs / 2 ))")
    else
        jobs+=("$t default $execs")
    fi
done
run() {
    local t=$1 role=$2 n=$3 limit=() who=()
    [ "$max_s" -gt 0 ] && limit=(-V "$max_s")
    case $role in m) who=(-M m) ;; s2) who=(-S s2) ;; esac
    # -t: an input that takes over 1 s is a hang; -m none: the targets allocate as the
    # programs do (the oversized-input limits are what is being tested).
    cargo afl fuzz -i "seeds/$t" -o "out/$t" "${who[@]}" -t 1000 -m none -E "$n" \
        "${limit[@]}" "target/release/$t" >"out-$t-$role.log" 2>&1 ||
        echo "$t ($role): afl-fuzz exited $?" >&2
}
mkdir -p out
running=0
for j in "${jobs[@]}"; do
    # shellcheck disable=SC2086 # a job is three words
    run $j &
    running=$((running + 1))
    if [ "$running" -ge "$lanes" ]; then
        wait -n
        running=$((running - 1))
    fi
done
wait
printf '%-12s %12s %10s %8s %8s %6s %6s\n' target execs exec/s seconds paths crash hang
for t in "${targets[@]}"; do
    stats=(out/"$t"/*/fuzzer_stats)
    [ -f "${stats[0]}" ] || { echo "$t: no stats (see tools/fuzz/out-$t-*.log)"; continue; }
    # Summed over the target's instances (paths: the most any one holds; seconds: the
    # longest).
    sum() { awk -F' *: *' -v k="$1" '$1 == k { s += $2 } END { printf "%d", s }' "${stats[@]}"; }
    most() { awk -F' *: *' -v k="$1" '$1 == k && $2 > m { m = $2 } END { printf "%d", m }' "${stats[@]}"; }
    printf '%-12s %12s %10s %8s %8s %6s %6s\n' "$t" "$(sum execs_done)" "$(sum execs_per_sec)" \
        "$(most run_time)" "$(most corpus_count)" "$(sum saved_crashes)" "$(sum saved_hangs)"
done
