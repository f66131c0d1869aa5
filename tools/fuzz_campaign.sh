#!/usr/bin/env bash
# The release campaign: runs fuzz targets until each has used CPU_SECONDS of CPU time, on an
# otherwise idle machine (libFuzzer's per-input timeout is wall-clock time: a fuzzer starved of
# CPU, e.g. at nice 19 beside builds, reported 0.9 s and 1.45 s inputs as timeouts).
# Usage: tools/fuzz_campaign.sh CPU_SECONDS [PARALLEL] [TARGET...]
#   (default PARALLEL 2, TARGET all six, in the order program gcode pipeline override machine ini)
# Uses the build and corpora of tools/fuzz.sh (run `tools/fuzz.sh 1` first to build and seed) and
# its memory limit (2048 MB) and the targets' options (tests/fuzz/options.txt); it allows 120 s per input (CI's tools/fuzz.sh keeps 10 s) and
# reports libFuzzer's slowest inputs without counting them as finds. Writes build-asan/campaign-<target>.log. Prints one
# line per target: CPU seconds, wall seconds, executions, corpus size, result. Exits 1 if any
# target found a crash, timeout, out-of-memory or leak (its input under build-asan/artifacts/).
set -euo pipefail
cd "$(dirname "$0")/.."

cpu="${1:-}"
if ! [[ "$cpu" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: tools/fuzz_campaign.sh CPU_SECONDS [PARALLEL] [TARGET...]" >&2
  exit 2
fi
parallel="${2:-2}"
shift $(($# > 1 ? 2 : 1))
targets=("$@")
[[ ${#targets[@]} -eq 0 ]] && targets=(program gcode pipeline override machine ini)

declare -A options=()  # libFuzzer options per target (tests/fuzz/options.txt)
while read -r target rest; do
  [[ -z "$target" || "$target" == \#* ]] && continue
  options[$target]="$rest"
done < tests/fuzz/options.txt

hz=$(getconf CLK_TCK)
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"

# CPU seconds of a process (user + system), from /proc.
cpu_of() { awk -v hz="$hz" '{ print int(($14 + $15) / hz) }' "/proc/$1/stat" 2>/dev/null || echo 0; }

run_one() {
  local t=$1 corpus=build-asan/corpus/$1 artifacts=build-asan/artifacts/$1
  local log=build-asan/campaign-$1.log dict=()
  mkdir -p "$corpus" "$artifacts"
  [[ -f tests/fuzz/$t.dict ]] && dict=(-dict="tests/fuzz/$t.dict")
  local start rc=0 pid used=0
  start=$(date +%s)
  # shellcheck disable=SC2086  # the options are words
  "build-asan/bin/fuzz_$t" "$corpus" -timeout=120 -rss_limit_mb=2048 "${dict[@]}" ${options[$t]:-} \
    -artifact_prefix="$artifacts/" -print_final_stats=1 >"$log" 2>&1 &
  pid=$!
  while kill -0 "$pid" 2>/dev/null; do
    used=$(cpu_of "$pid")
    if ((used >= cpu)); then
      kill -INT "$pid" 2>/dev/null || true
      break
    fi
    sleep 10
  done
  wait "$pid" || rc=$?
  local execs size result=clean
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n1)
  [[ -z "$execs" ]] && execs=$(sed -n 's/^#\([0-9][0-9]*\).*/\1/p' "$log" | tail -n1)
  size=$(find "$corpus" -maxdepth 1 -type f | wc -l)
  # An interrupted run (SIGINT at the CPU budget) exits non-zero without finding anything.
  if grep -qE 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:' "$log"; then
    result="FOUND (see $log)"
  elif ((used < cpu)) && ((rc != 0)); then
    result="stopped early, rc $rc (see $log)"
  fi
  printf 'campaign: %-9s %6d cpu-s %6d wall-s %12s execs %6d corpus  %s\n' \
    "$t" "$used" $(($(date +%s) - start)) "${execs:-?}" "$size" "$result"
  [[ "$result" == clean ]]
}

failed=0
pids=()
for t in "${targets[@]}"; do
  while (($(jobs -rp | wc -l) >= parallel)); do sleep 5; done
  run_one "$t" &
  pids+=($!)
done
for p in "${pids[@]}"; do wait "$p" || failed=1; done
exit $failed
