#!/usr/bin/env bash
# tools/gmtrace.py reads the schema (src/trace/trace_columns.def) as the C++ writer does: a
# binary trace converted by it is byte-identical to the CSV trace of the same run.
set -euo pipefail
gmotion=$1
root=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$gmotion" run "$root/programs/paper-circle.nc" --machine "$root/programs/machines/paper.toml" \
    --override 150 --trace "$dir/t.csv" > /dev/null
"$gmotion" run "$root/programs/paper-circle.nc" --machine "$root/programs/machines/paper.toml" \
    --override 150 --trace "$dir/t.bin" --trace-format bin > /dev/null
python3 "$root/tools/gmtrace.py" "$dir/t.bin" > "$dir/back.csv"
cmp "$dir/t.csv" "$dir/back.csv"
test "$(wc -l < "$dir/t.csv")" -gt 900
