#!/usr/bin/env bash
# Benchmark of `gmotion golden`: generates a suite of N short programs (default 1,000; lines and
# arcs, about a second of motion each on the built-in machine, servo on) in a temporary folder,
# records it, then times `gmotion golden verify` on it. Nothing is written to the repository.
#   tools/golden_bench.sh [N] [GMOTION]
set -euo pipefail
n=${1:-1000}
bin=$(realpath "${2:-build/bin/gmotion}")
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
python3 - "$dir" "$n" <<'PY'
import random, sys
d, n = sys.argv[1], int(sys.argv[2])
for i in range(n):
    r = random.Random(i)
    x, y = r.uniform(-5, 5), r.uniform(-5, 5)
    lines = ["%", f"(bench {i})", "G21 G17 G90 G64", f"G0 X{x:.3f} Y{y:.3f} Z1", "G1 Z0 F600"]
    for _ in range(r.randint(3, 6)):
        if r.random() < 0.6:
            x, y = r.uniform(-5, 5), r.uniform(-5, 5)
            lines.append(f"G1 X{x:.3f} Y{y:.3f} F{r.choice([1200, 1800, 2400])}")
        else:
            rad = r.uniform(1, 3)
            lines.append(f"G{r.choice([2, 3])} X{x:.3f} Y{y:.3f} I{rad:.3f} J0 F1800")
    lines += ["G0 Z1", "M2", "%"]
    open(f"{d}/p{i:04d}.nc", "w").write("\n".join(lines) + "\n")
PY
echo "golden_bench: $n programs in $dir, $(nproc) cores"
start=$(date +%s.%N)
"$bin" golden record "$dir" | tail -1
mid=$(date +%s.%N)
"$bin" golden verify "$dir" | tail -1
end=$(date +%s.%N)
du -sh "$dir/golden" | awk '{print "golden_bench: store " $1}'
cat "$dir"/golden/*.summary.json | grep -o '"samples":[0-9]*' |
  awk -F: -v n="$n" '{s += $2} END {printf "golden_bench: %.0f samples per case on average (T = 4 ms)\n", s / n}'
start1=$(date +%s.%N)
"$bin" golden verify "$dir" -j 1 | tail -1
end1=$(date +%s.%N)
awk -v a="$start" -v b="$mid" -v c="$end" -v n="$n" \
  -v d="$start1" -v e="$end1" \
  'BEGIN { printf "golden_bench: record %.1f s, verify %.1f s (%.1f ms per case), verify -j 1 %.1f s\n", b - a, c - b, (c - b) * 1000 / n, e - d }'
