#!/usr/bin/env bash
# End-to-end benchmark: builds the bench preset (Release), generates a program of N blocks
# mixing G1 and G2/G3 (IJK and R) with tools/gen_bench_program.py, and measures
#   - parse+interpret: `gmotion check` MB/s and blocks/s, and `rs274 -g PROGRAM /dev/null`
#     on the same program with the ratio (when rs274 is installed: install-deps --with-oracle);
#     the same ratio in CPU seconds of check's busiest thread (tools/thread_cpu.py, best of 5),
#     what bounds check on two idle cores whatever else the machine runs;
#   - the same for a 10^6-iteration O-word `while` loop of arithmetic, SIN and a G1
#     (tests/diff/lang/loop_arith.ngc with its count raised; rs274 once, it takes minutes);
#   - `gmotion run` without a trace (default machine: 3 axes, blackman, tau 0.164 s, T 4 ms,
#     servo on and off): samples/s and peak RSS, on the short-move program and on a long-move one
#     (gen_bench_program.py --long: every move >= 100 samples), and per profile family on the
#     long-move program;
#   - `gmotion run` on the same program with A, B, C moving on a six-axis machine (--axes XYZABC);
#   - `gmotion run` on a 40,000-block program of the same kind at `G64 P0.01` (the tolerance
#     planner) against without P: samples/s and their ratio, and the CPU seconds of the
#     planner's thread (the run's busiest; tools/thread_cpu.py, best of 5);
#   - `gmotion run --trace`: CSV rows/s to /dev/null and to a file, binary rows/s to a file;
#   - with --instructions: callgrind's instructions per sample on each thread of the long-move
#     run, and the per-stage breakdown of the main thread (valgrind; slow: about a minute);
#   - per-sample step latency (tests/bench/latency.cpp) on the first 100,000 blocks;
#   - with --big: peak RSS of check and run on a 10 MB and a 1 GB program (the 10 MB body
#     repeated; each copy starts with a rapid back to the origin), to show it stays flat;
#   - with --micro: the Google Benchmark micro-benchmarks per stage.
# Each timing is the best of 5 runs for check and rs274, 3 for run, 1 for the traced run and
# the 1 GB ones (this machine's speed varies by tens of percent from minute to minute).
# Prints a Markdown table at the end. Work files go to build-bench/e2e/ (ignored by git).
#
# Usage: tools/bench.sh [--blocks N] [--big] [--micro] [--instructions]
set -euo pipefail
cd "$(dirname "$0")/.."

blocks=1000000 big=0 micro=0 instructions=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --blocks) blocks=$2; shift 2 ;;
    --big) big=1; shift ;;
    --micro) micro=1; shift ;;
    --instructions) instructions=1; shift ;;
    *) echo "usage: tools/bench.sh [--blocks N] [--big] [--micro] [--instructions]" >&2; exit 2 ;;
  esac
done

tools/install-deps.sh --with-bench
cmake --preset bench >/dev/null
cmake --build --preset bench >/dev/null
bin=build-bench/bin
work=build-bench/e2e
mkdir -p "$work"

gen() {  # gen BLOCKS FILE: the benchmark program, generated once and kept
  [[ -s "$2" ]] || python3 tools/gen_bench_program.py --blocks "$1" -o "$2"
}

# measure RUNS CMD...: sets $secs (best wall time, s), $user_s (best user CPU time, s) and $rss_kb
# (largest peak RSS, KB).
measure() {
  local runs=$1 e m u; shift
  secs="" user_s="" rss_kb=0
  for ((i = 0; i < runs; i++)); do
    /usr/bin/time -f "%e %M %U" -o "$work/time.txt" "$@" >/dev/null 2>"$work/stderr.txt" ||
      { echo "bench: '$*' failed:" >&2; tail -3 "$work/stderr.txt" >&2; exit 1; }
    read -r e m u <"$work/time.txt"
    if [[ -z "$secs" ]] || awk "BEGIN{exit !($e < $secs)}"; then secs=$e; fi
    if [[ -z "$user_s" ]] || awk "BEGIN{exit !($u < $user_s)}"; then user_s=$u; fi
    if ((m > rss_kb)); then rss_kb=$m; fi
  done
}
calc() { awk "BEGIN{printf \"$1\", $2}"; }
# busiest RUNS CMD...: the least CPU seconds of the command's busiest thread over RUNS runs.
busiest() {
  local runs=$1; shift
  python3 tools/thread_cpu.py --runs "$runs" -- "$@" | awk 'NR == 1 || $1 < m {m = $1} END {print m}'
}
samples_of() { python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["samples"])' "$1"; }

prog=$work/bench-$blocks.nc
gen "$blocks" "$prog"
bytes=$(stat -c %s "$prog")
mb=$(calc "%.1f" "$bytes / 1e6")
echo "program: $prog ($blocks blocks, $mb MB)"
rows=()

measure 5 "$bin/gmotion" check "$prog"
check_s=$secs
rows+=("| parse+interpret (\`gmotion check\`) | $(calc "%.0f" "$bytes / 1e6 / $secs") MB/s, $(calc "%.2f" "$blocks / 1e6 / $secs") M blocks/s | $secs s, peak RSS $((rss_kb / 1024)) MB |")
if command -v rs274 >/dev/null; then
  measure 5 rs274 -g "$prog" /dev/null
  rows+=("| \`rs274 -g PROGRAM /dev/null\` (LinuxCNC) | $(calc "%.1f" "$bytes / 1e6 / $secs") MB/s | $secs s: gmotion check is $(calc "%.1f" "$secs / $check_s")x faster |")
  check_cpu=$(busiest 5 "$bin/gmotion" check "$prog")
  rs274_cpu=$(busiest 5 rs274 -g "$prog" /dev/null)
  rows+=("| parse+interpret against rs274 in CPU seconds (\`tools/thread_cpu.py\`, best of 5) | $(calc "%.1f" "$rs274_cpu / $check_cpu")x | check's busiest thread $check_cpu s, rs274 $rs274_cpu s |")
else
  rows+=("| \`rs274\` | not installed (tools/install-deps.sh --with-oracle) | |")
fi

loop=$work/loop-1e6.ngc
sed 's/LT 300\]/LT 1000000]/' tests/diff/lang/loop_arith.ngc >"$loop"
measure 3 "$bin/gmotion" check "$loop"
loop_s=$secs
rows+=("| 10⁶-iteration \`while\` loop (arithmetic, SIN, G1), \`gmotion check\` | $(calc "%.2f" "1 / $secs") M iterations/s | $secs s, peak RSS $((rss_kb / 1024)) MB |")
if command -v rs274 >/dev/null; then
  measure 1 rs274 -g "$loop" /dev/null
  rows+=("| the same loop, \`rs274 -g\` | $(calc "%.3f" "1 / $secs") M iterations/s | $secs s, peak RSS $((rss_kb / 1024)) MB: gmotion check is $(calc "%.1f" "$secs / $loop_s")x faster |")
fi

measure 3 "$bin/gmotion" run "$prog" --summary-json "$work/summary.json"
samples=$(samples_of "$work/summary.json")
rows+=("| \`gmotion run\`, no trace (blackman 41 taps, servo on) | $(calc "%.2f" "$samples / 1e6 / $secs") M samples/s | $samples samples in $secs s, peak RSS $((rss_kb / 1024)) MB |")
measure 3 "$bin/gmotion" run "$prog" --no-servo
rows+=("| \`gmotion run --no-servo\`, no trace | $(calc "%.2f" "$samples / 1e6 / $secs") M samples/s | $secs s |")

# Six axes: the same program with A, B, C words on every motion block (A turning steadily, B
# swinging, C turning back; X Y Z still set each block's time), on the built-in machine with
# --axes XYZABC (A B C take the X axis's servo).
prog6=$work/bench-$blocks-abc.nc
[[ -s "$prog6" ]] || awk '/^G[0-3] /{n++; printf "%s A%.3f B%.3f C%.3f\n", $0, n*0.01, 10*sin(n/50), -n*0.005; next} {print}' "$prog" >"$prog6"
measure 3 "$bin/gmotion" run "$prog6" --axes XYZABC --summary-json "$work/summary6.json"
samples6=$(samples_of "$work/summary6.json")
rows+=("| \`gmotion run --axes XYZABC\`, six axes moving, no trace | $(calc "%.2f" "$samples6 / 1e6 / $secs") M samples/s | $samples6 samples in $secs s, peak RSS $((rss_kb / 1024)) MB |")

# Planning: the same kind of program, 40,000 blocks, with `G64 P0.01` (the tolerance planner,
# arcs pre-compensated from the residual table) against without P: samples/s of each (wall
# time) and their ratio, also by user CPU time (steadier on a shared machine; docs/tolerance.md,
# "Planning cost").
plan_prog=$work/bench-40000.nc
gen 40000 "$plan_prog"
plan_p=$work/bench-40000-p001.nc
[[ -s "$plan_p" ]] || sed 's/^G21 G90 G17 G94$/G21 G90 G17 G94 G64 P0.01/' "$plan_prog" >"$plan_p"
measure 3 "$bin/gmotion" run "$plan_prog" --summary-json "$work/summary-plan0.json"
free_rate=$(calc "%.4f" "$(samples_of "$work/summary-plan0.json") / 1e6 / $secs")
free_user=$(calc "%.4f" "$(samples_of "$work/summary-plan0.json") / 1e6 / $user_s")
measure 3 "$bin/gmotion" run "$plan_p" --summary-json "$work/summary-plan.json"
psamples=$(samples_of "$work/summary-plan.json")
plan_rate=$(calc "%.4f" "$psamples / 1e6 / $secs")
plan_user=$(calc "%.4f" "$psamples / 1e6 / $user_s")
plan_cpu=$(busiest 5 "$bin/gmotion" run "$plan_p")  # the planner's thread, the run's busiest
rows+=("| \`gmotion run\`, \`G64 P0.01\` (40,000 blocks, planned) | $(calc "%.2f" "$plan_rate") M samples/s, $(calc "%.2f" "$plan_rate / $free_rate")x the rate without P ($(calc "%.2f" "$plan_user / $free_user")x by user CPU) | $psamples samples in $secs s ($user_s s user), peak RSS $((rss_kb / 1024)) MB; without P $(calc "%.2f" "$free_rate") M samples/s; the planner's thread $plan_cpu s of CPU (\`tools/thread_cpu.py\`, best of 5) |")

# Long moves: every move takes at least 100 samples (what the block engine's headline is on).
long=$work/long-20000.nc
[[ -s "$long" ]] || python3 tools/gen_bench_program.py --blocks 20000 --long -o "$long"
measure 3 "$bin/gmotion" run "$long" --summary-json "$work/summary-long.json"
lsamples=$(samples_of "$work/summary-long.json")
rows+=("| long moves, \`gmotion run\`, no trace, servo on | $(calc "%.2f" "$lsamples / 1e6 / $secs") M samples/s | $lsamples samples in $secs s, peak RSS $((rss_kb / 1024)) MB |")
measure 3 "$bin/gmotion" run "$long" --no-servo
rows+=("| long moves, \`gmotion run --no-servo\` | $(calc "%.2f" "$lsamples / 1e6 / $secs") M samples/s | $secs s |")
# cascade:14,14,15 has 14 + 14 + 15 - 2 = 41 taps, the default tau (0.164 s at T = 4 ms).
for prof in linear scurve2 hann cascade:14,14,15; do
  measure 3 "$bin/gmotion" run "$long" --profile "$prof" --summary-json "$work/summary-prof.json"
  ps=$(samples_of "$work/summary-prof.json")
  rows+=("| long moves, \`--profile $prof\`, servo on | $(calc "%.2f" "$ps / 1e6 / $secs") M samples/s | $ps samples in $secs s |")
done
measure 3 "$bin/gmotion" run "$long" --trace /dev/null
rows+=("| long moves, \`--trace /dev/null\` (CSV) | $(calc "%.2f" "$lsamples / 1e6 / $secs") M rows/s | $secs s |")
measure 1 "$bin/gmotion" run "$long" --trace "$work/trace.csv"
trace_mb=$(calc "%.0f" "$(stat -c %s "$work/trace.csv") / 1e6")
rm -f "$work/trace.csv"
rows+=("| long moves, \`--trace FILE.csv\` | $(calc "%.2f" "$lsamples / 1e6 / $secs") M rows/s | $secs s, $trace_mb MB of CSV |")
measure 1 "$bin/gmotion" run "$long" --trace "$work/trace.bin" --trace-format bin
trace_mb=$(calc "%.0f" "$(stat -c %s "$work/trace.bin") / 1e6")
rm -f "$work/trace.bin"
rows+=("| long moves, \`--trace FILE --trace-format bin\` | $(calc "%.2f" "$lsamples / 1e6 / $secs") M rows/s | $secs s, $trace_mb MB |")

measure 1 "$bin/gmotion" run "$prog" --trace "$work/trace.csv"
trace_mb=$(calc "%.0f" "$(stat -c %s "$work/trace.csv") / 1e6")
rm -f "$work/trace.csv"
rows+=("| \`gmotion run --trace FILE.csv\` | $(calc "%.2f" "$samples / 1e6 / $secs") M rows/s | $secs s, $trace_mb MB of CSV, peak RSS $((rss_kb / 1024)) MB |")

if ((instructions)) && command -v valgrind >/dev/null; then
  # Instructions per sample, per thread, on 1,000 long moves; the main thread's stages.
  small_long=$work/long-1000.nc
  [[ -s "$small_long" ]] || python3 tools/gen_bench_program.py --blocks 1000 --long -o "$small_long"
  rm -f "$work"/callgrind.out.*
  (cd "$work" && valgrind --tool=callgrind --separate-threads=yes "../bin/gmotion" run \
    "$(basename "$small_long")" --summary-json summary-cg.json >/dev/null 2>&1)
  cs=$(samples_of "$work/summary-cg.json")
  for f in "$work"/callgrind.out.*-0[12]; do
    total=$(callgrind_annotate "$f" 2>/dev/null | awk '/PROGRAM TOTALS/{gsub(",","",$1); print $1}')
    rows+=("| instructions a sample, thread ${f##*-} (callgrind, 1,000 long moves) | $(calc "%.0f" "$total / $cs") | $cs samples |")
  done
  while read -r ir _ fn; do
    fn=${fn#???:}
    rows+=("| main thread: \`${fn%%(*}\` | $(calc "%.0f" "${ir//,/} / $cs") instructions a sample | inclusive |")
  done < <(callgrind_annotate --inclusive=yes "$work"/callgrind.out.*-01 2>/dev/null |
    grep -E 'stages_n|stage_row|step_block|command_n|command_span|Interpolator::span|FirAccDec|ServoBank|ServoAxis::step')
fi

lat_prog=$work/bench-100000.nc
gen 100000 "$lat_prog"
"$bin/gmotion_latency" "$lat_prog" --repeat 3 | tee "$work/latency.txt"
one=$(grep '^step, one run' "$work/latency.txt" | sed -E 's/.*p50 ([0-9.]+) +p99 ([0-9.]+) +p99.9 ([0-9.]+) +p99.99 ([0-9.]+).*/p50 \1, p99 \2, p99.9 \3, p99.99 \4/')
best=$(grep '^step, fastest' "$work/latency.txt" | sed -E 's/.*p50 ([0-9.]+) +p99 ([0-9.]+) +p99.9 ([0-9.]+) +p99.99 ([0-9.]+).*/p50 \1, p99 \2, p99.9 \3, p99.99 \4/')
gaps=$(grep '^machine:' "$work/latency.txt" | sed -E 's/.*\(([0-9]+)\/s;.*/\1/')
rows+=("| per-sample step latency, one run (µs) | $one | the machine interrupts a bare clock loop $gaps times/s |")
rows+=("| per-sample step latency, fastest of 3 runs per sample (µs) | $best | the work itself, interruptions removed |")

if ((big)); then
  body=$work/body-10mb.nc
  [[ -s $body ]] || python3 tools/gen_bench_program.py --blocks 370000 --seed 7 | grep -v '^M2$' >"$body"
  small=$work/prog-10mb.nc huge=$work/prog-1gb.nc
  [[ -s $small ]] || { cat "$body"; echo M2; } >"$small"
  [[ -s $huge ]] || { for _ in $(seq 100); do cat "$body"; done; echo M2; } >"$huge"
  for p in "$small" "$huge"; do
    sz=$(calc "%.0f" "$(stat -c %s "$p") / 1e6")
    measure 1 "$bin/gmotion" check "$p"
    rows+=("| peak RSS, \`gmotion check\`, $sz MB program | $((rss_kb / 1024)) MB | $secs s |")
    measure 1 "$bin/gmotion" run "$p" --summary-json "$work/summary-big.json"
    rows+=("| peak RSS, \`gmotion run\`, $sz MB program | $((rss_kb / 1024)) MB | $(samples_of "$work/summary-big.json") samples in $secs s |")
  done
fi

if ((micro)); then
  "$bin/gmotion_bench" --benchmark_min_time=0.2
fi

echo
echo "gmotion $(git describe --always --dirty 2>/dev/null || echo '?'), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(date -u +%Y-%m-%d)"
echo
echo "| measure | result | detail |"
echo "|---|---|---|"
printf '%s\n' "${rows[@]}"
