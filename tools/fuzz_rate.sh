#!/usr/bin/env bash
# Measures a fuzz target's rate from its seeds: executions and valid programs per CPU-second.
# Usage: tools/fuzz_rate.sh TARGET SECONDS [LIBFUZZER_OPTION...]   (SECONDS of wall time, <= 180)
# Copies the target's seeds (tests/fuzz/seeds.txt and regressions/<target>/) into a fresh corpus
# under build-asan/rate-<target>/, runs build-asan/bin/fuzz_<target> on it with the target's
# dictionary, GMOTION_FUZZ_STATS=1, its options (tests/fuzz/options.txt) and then the options
# given (e.g. -entropic=1 for libFuzzer's default schedule, -max_len=2048; the last one wins), and
# prints the executions, the CPU seconds (user + system, /usr/bin/time) and both rates. CPU time,
# not wall time: the machine may be shared. Build first: cmake --build --preset fuzz.
set -euo pipefail
cd "$(dirname "$0")/.."

t="${1:-}"
secs="${2:-}"
if [[ -z "$t" ]] || ! [[ "$secs" =~ ^[1-9][0-9]*$ ]] || ((secs > 180)); then
  echo "usage: tools/fuzz_rate.sh TARGET SECONDS [LIBFUZZER_OPTION...]  (SECONDS 1..180)" >&2
  exit 2
fi
shift 2
bin=build-asan/bin/fuzz_$t
[[ -x "$bin" ]] || { echo "fuzz_rate: $bin missing (cmake --build --preset fuzz)" >&2; exit 2; }

globs=$(sed -n "s/^$t //p" tests/fuzz/seeds.txt)
read -r -a options <<<"$(sed -n "s/^$t //p" tests/fuzz/options.txt)"
dir=build-asan/rate-$t
rm -rf "$dir"
mkdir -p "$dir/corpus"
shopt -s nullglob
# shellcheck disable=SC2086  # the globs must expand
for f in $globs tests/fuzz/regressions/"$t"/*; do
  [[ -f "$f" ]] && cp -f "$f" "$dir/corpus/$(sha1sum <"$f" | cut -c1-40)"
done
seeds=$(find "$dir/corpus" -type f | wc -l)

dict=()
[[ -f tests/fuzz/$t.dict ]] && dict=(-dict="tests/fuzz/$t.dict")
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
GMOTION_FUZZ_STATS=1 /usr/bin/time -f 'cpu %U %S' -o "$dir/time" \
  "$bin" "$dir/corpus" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 "${dict[@]}" \
  -artifact_prefix="$dir/" -print_final_stats=1 "${options[@]}" "$@" >"$dir/log" 2>&1 || {
  echo "fuzz_rate: the fuzzer stopped (see $dir/log)" >&2
  grep -E -m5 'ERROR:|SUMMARY:|runtime error:' "$dir/log" >&2 || true
  exit 1
}
execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$dir/log" | tail -n1)
valid=$(sed -n 's/.* \([0-9][0-9]*\) valid .*/\1/p' "$dir/log" | tail -n1)
read -r _ user sys <"$dir/time"
corpus=$(find "$dir/corpus" -type f | wc -l)
awk -v t="$t" -v e="$execs" -v v="${valid:-}" -v u="$user" -v s="$sys" -v n="$seeds" \
  -v c="$corpus" -v opts="${options[*]} $*" 'BEGIN {
    cpu = u + s
    printf "fuzz_rate: %s %s: %d seeds, %d executions in %.1f CPU-s = %.0f/CPU-s", t, opts, n, e, cpu, e / cpu
    if (v != "") printf ", %d valid (%.1f %%) = %.0f valid/CPU-s", v, 100 * v / e, v / cpu
    printf ", corpus %d\n", c
  }'
