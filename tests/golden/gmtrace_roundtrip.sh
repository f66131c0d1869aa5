#!/usr/bin/env bash
# tools/gmtrace.py reads the schema (src/trace/trace_columns.def) as the C++ writer does: a
# binary trace converted by it is byte-identical to the CSV trace of the same run, with and
# without the optional columns.
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
# The same with the optional tool tip columns (a machine with modes): x_tip ... in both.
m="$root/programs/machines/ringing-40hz.toml"
"$gmotion" run "$root/programs/ringing.nc" --machine "$m" --trace "$dir/r.csv" > /dev/null
"$gmotion" run "$root/programs/ringing.nc" --machine "$m" --trace "$dir/r.bin" --trace-format bin \
    > /dev/null
python3 "$root/tools/gmtrace.py" "$dir/r.bin" > "$dir/r-back.csv"
cmp "$dir/r.csv" "$dir/r-back.csv"
grep -q '^t_s,line,x_cmd,x_ref,x_enc,x_ferr,x_tip,y_cmd' "$dir/r.csv"
