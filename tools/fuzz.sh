#!/usr/bin/env bash
# Fuzzes the G-code program, override-schedule, machine-file and LinuxCNC INI readers, generated
# programs through the interpreter and through the whole pipeline, with libFuzzer, bounded.
# Usage: tools/fuzz.sh [SECONDS_PER_TARGET]   (default 60)
# Installs what is missing (tools/install-deps.sh --with-fuzz), builds the four targets in the
# 'asan' preset's folder (clang-14, ASan+UBSan, libFuzzer coverage; the same build the sanitized
# tests run from, so CI compiles the core once for both), seeds build-asan/corpus/<target> from tests/fuzz/seeds.txt and
# tests/fuzz/regressions/<target>/, then runs each target (with its libFuzzer options from
# tests/fuzz/options.txt) for SECONDS_PER_TARGET and prints one
# line per target: executions, seconds, corpus size, result. Exits 1 on a crash, timeout (> 10 s
# for one input, or the target's -timeout in tests/fuzz/options.txt), out-of-memory (> 2048 MB) or leak, naming the input saved under
# build-asan/artifacts/<target>/ and how to replay it. The targets run as many at a time as
# the machine has cores.
set -euo pipefail
cd "$(dirname "$0")/.."

secs="${1:-60}"
if ! [[ "$secs" =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: tools/fuzz.sh [SECONDS_PER_TARGET]  (a whole number of seconds >= 1)" >&2
  exit 2
fi

tools/install-deps.sh --with-fuzz
cmake --preset asan >/dev/null
cmake --build --preset fuzz

targets=(program override machine ini gcode pipeline)
declare -A globs=()
while read -r target rest; do
  [[ -z "$target" || "$target" == \#* ]] && continue
  globs[$target]="$rest"
done < tests/fuzz/seeds.txt
declare -A options=()  # libFuzzer options per target
while read -r target rest; do
  [[ -z "$target" || "$target" == \#* ]] && continue
  options[$target]="$rest"
done < tests/fuzz/options.txt

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}"
shopt -s nullglob

# fuzz_one TARGET: seeds and runs one target, writes its exit status to build-asan/fuzz-TARGET.rc.
fuzz_one() {
  local t=$1 corpus=build-asan/corpus/$1 artifacts=build-asan/artifacts/$1 log=build-asan/fuzz-$1.log
  mkdir -p "$corpus" "$artifacts"
  # Seeds are named by content, as libFuzzer names what it adds (same basename, different folder).
  # shellcheck disable=SC2086  # the globs must expand
  for f in ${globs[$t]:-} tests/fuzz/regressions/"$t"/*; do
    [[ -f "$f" ]] && cp -f "$f" "$corpus/$(sha1sum <"$f" | cut -c1-40)"
  done
  local start rc=0 dict=()  # the generator targets read choices, not text: no dictionary
  start=$(date +%s)
  [[ -f tests/fuzz/$t.dict ]] && dict=(-dict="tests/fuzz/$t.dict")
  # shellcheck disable=SC2086  # the options are words
  "build-asan/bin/fuzz_$t" "$corpus" -max_total_time="$secs" -timeout=10 -rss_limit_mb=2048 \
    "${dict[@]}" ${options[$t]:-} -artifact_prefix="$artifacts/" -print_final_stats=1 >"$log" 2>&1 || rc=$?
  echo "$rc $(($(date +%s) - start))" >"build-asan/fuzz-$t.rc"
}

# The targets run as many at a time as the machine has cores (each is one process, single
# threaded): every target still gets its SECONDS_PER_TARGET. The results print in a fixed order.
jobs=$(nproc 2>/dev/null || echo 1)
running=0
for t in "${targets[@]}"; do
  rm -f "build-asan/fuzz-$t.rc"
  fuzz_one "$t" &
  running=$((running + 1))
  if [[ $running -ge $jobs ]]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait

failed=()
printf 'fuzz: %-9s %12s %8s %7s  %s\n' target executions seconds corpus result
for t in "${targets[@]}"; do
  corpus=build-asan/corpus/$t
  artifacts=build-asan/artifacts/$t
  log=build-asan/fuzz-$t.log
  rc=1 elapsed='?'
  [[ -f "build-asan/fuzz-$t.rc" ]] && read -r rc elapsed <"build-asan/fuzz-$t.rc"
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n1)
  if [[ -z "$execs" ]]; then  # no final stats after a crash: the last status line has the count
    execs=$(sed -n 's/^#\([0-9][0-9]*\).*/\1/p' "$log" | tail -n1)
  fi
  size=$(find "$corpus" -maxdepth 1 -type f | wc -l)

  result=clean
  if [[ $rc -ne 0 ]]; then
    if grep -q 'ERROR: libFuzzer: timeout' "$log"; then result=timeout
    elif grep -q 'ERROR: libFuzzer: out-of-memory' "$log"; then result=oom
    elif grep -q 'ERROR: LeakSanitizer' "$log"; then result=leak
    else result=crash
    fi
  fi
  printf 'fuzz: %-9s %12s %8s %7s  %s\n' "$t" "${execs:-?}" "$elapsed" "$size" "$result"
  if [[ $result != clean ]]; then
    failed+=("$t")
    artifact=$(sed -n 's/.*Test unit written to \(.*\)$/\1/p' "$log" | tail -n1)
    echo "fuzz: $t: $result; log: $log" >&2
    grep -E -m5 'ERROR:|SUMMARY:|runtime error:' "$log" | sed 's/^/fuzz:   /' >&2 || true
    if [[ -n "$artifact" ]]; then
      echo "fuzz: $t: input saved as $artifact" >&2
      echo "fuzz: $t: replay it with: build-asan/bin/fuzz_$t $artifact" >&2
    fi
  fi
done

if [[ ${#failed[@]} -gt 0 ]]; then
  echo "fuzz: failing targets: ${failed[*]} (add each input to tests/fuzz/regressions/<target>/ once fixed)" >&2
  exit 1
fi
echo "fuzz: every target clean for ${secs} s"
