#!/usr/bin/env bash
# What the fuzzers reach: replays each fuzz target's corpus through a coverage build and prints
# line and function coverage of src/ and grammar/, per stage folder and per file (markdown).
# Usage: tools/fuzz_coverage.sh [CORPUS_ROOT]   (default build-asan/corpus, which tools/fuzz.sh
# and a campaign fill; a target without a folder there replays its seeds and regressions only)
# Builds the six fuzz_*_replay executables in the 'coverage' preset's folder (build-cov/, clang-14,
# -fprofile-instr-generate -fcoverage-mapping), runs each over its inputs with LLVM_PROFILE_FILE,
# merges the profiles (build-cov/fuzz.profdata) and writes build-cov/coverage-files.md and
# build-cov/coverage-stages.md; the stage table is also printed.
set -euo pipefail
cd "$(dirname "$0")/.."

root="${1:-build-asan/corpus}"
cmake --preset coverage >/dev/null
cmake --build --preset coverage

targets=(program override machine ini gcode pipeline)
declare -A globs=()
while read -r target rest; do
  [[ -z "$target" || "$target" == \#* ]] && continue
  globs[$target]="$rest"
done < tests/fuzz/seeds.txt

shopt -s nullglob
rm -rf build-cov/prof
mkdir -p build-cov/prof
objects=()
for t in "${targets[@]}"; do
  inputs=()
  # shellcheck disable=SC2206  # the globs must expand
  inputs+=(${globs[$t]:-})
  inputs+=("tests/fuzz/regressions/$t")
  [[ -d "$root/$t" ]] && inputs+=("$root/$t")
  count=$(find "${inputs[@]}" -maxdepth 1 -type f ! -name '.*' | wc -l)
  start=$(date +%s)
  LLVM_PROFILE_FILE="build-cov/prof/$t-%p.profraw" \
    "build-cov/bin/fuzz_${t}_replay" "${inputs[@]}" >"build-cov/prof/$t.log" 2>&1 || {
    echo "fuzz_coverage: fuzz_${t}_replay failed (build-cov/prof/$t.log)" >&2
    exit 1
  }
  printf 'coverage: %-9s %7d inputs %5d s\n' "$t" "$count" $(($(date +%s) - start))
  objects+=(-object "build-cov/bin/fuzz_${t}_replay")
done

llvm-profdata-14 merge -sparse build-cov/prof/*.profraw -o build-cov/fuzz.profdata
# The first -object is the binary, the others follow as -object; only our own sources count
# (selected below: a ccache build with base_dir names them build-cov/../src/..., which a
# source-path filter here would not match).
llvm-cov-14 export -summary-only -instr-profile build-cov/fuzz.profdata "${objects[@]:1}" \
  >build-cov/coverage.json

python3 - "$PWD" <<'EOF'
import json, os, sys, collections
top = sys.argv[1] + "/"
data = json.load(open("build-cov/coverage.json"))["data"][0]["files"]
rows, stages = [], collections.defaultdict(lambda: [0, 0, 0, 0])
for f in data:
    name = os.path.normpath(f["filename"]).replace(top, "")
    if not (name.startswith("src/") or name.startswith("grammar/")):
        continue
    lines, funcs = f["summary"]["lines"], f["summary"]["functions"]
    parts = name.split("/")
    stage = parts[0] if parts[0] == "grammar" else "/".join(parts[:2])
    s = stages[stage]
    s[0] += lines["covered"]; s[1] += lines["count"]; s[2] += funcs["covered"]; s[3] += funcs["count"]
    rows.append((name, lines["covered"], lines["count"], funcs["covered"], funcs["count"]))

def pct(a, b):
    return f"{100.0 * a / b:.1f} %" if b else "-"

with open("build-cov/coverage-files.md", "w") as out:
    out.write("| file | lines | covered | functions | covered |\n| --- | ---: | ---: | ---: | ---: |\n")
    for name, lc, ln, fc, fn in sorted(rows):
        out.write(f"| {name} | {ln} | {pct(lc, ln)} | {fn} | {pct(fc, fn)} |\n")
total = [sum(s[i] for s in stages.values()) for i in range(4)]
table = ["| stage | lines | covered | functions | covered |", "| --- | ---: | ---: | ---: | ---: |"]
for stage in sorted(stages):
    lc, ln, fc, fn = stages[stage]
    table.append(f"| {stage} | {ln} | {pct(lc, ln)} | {fn} | {pct(fc, fn)} |")
table.append(f"| **all** | {total[1]} | {pct(total[0], total[1])} | {total[3]} | {pct(total[2], total[3])} |")
open("build-cov/coverage-stages.md", "w").write("\n".join(table) + "\n")
print("\n".join(table))
EOF
