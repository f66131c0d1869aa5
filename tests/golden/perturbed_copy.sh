#!/usr/bin/env bash
# A trace with one encoder count changed must make `gmotion diff` fail and name that value;
# the unchanged copy must pass. Usage: perturbed_copy.sh GMOTION REPO_DIR
set -euo pipefail
bin=$1 repo=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
golden=$tmp/square.csv
(cd "$repo" && "$bin" run programs/square.nc --decimate 4 --trace "$golden" >/dev/null)
cp "$golden" "$tmp/same.csv"
"$bin" diff "$golden" "$tmp/same.csv" >/dev/null
# Row 100 of the data (after the header), column 5 (x_enc): add one count.
awk -F, -v OFS=, '/^#/ || /^t_s/ {print; next} {n++} n == 100 {$5 = $5 + 1} {print}' "$golden" > "$tmp/bumped.csv"
if out=$("$bin" diff "$golden" "$tmp/bumped.csv"); then
  echo "FAIL: a changed encoder count was not caught"; exit 1
fi
grep -q "first divergence: row 100 .*column x_enc" <<<"$out" || { echo "FAIL: wrong divergence: $out"; exit 1; }
"$bin" diff --tol 1 "$golden" "$tmp/bumped.csv" >/dev/null || { echo "FAIL: --tol 1 should accept it"; exit 1; }
echo "ok: the perturbed copy fails at row 100, x_enc; --tol 1 accepts it"
