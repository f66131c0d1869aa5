#!/usr/bin/env bash
# Golden traces: check one case against tests/golden/data, or regenerate them on purpose.
#
#   tools/golden.sh check NAME [GMOTION]   run NAME fresh; exit 1 if trace or summary differ
#   tools/golden.sh regen [GMOTION]        rewrite every golden and print what changed
#
# Cases are in tests/golden/cases.txt. GMOTION defaults to build/bin/gmotion. Traces compare
# exactly (encoder counts included) with `gmotion diff`; GOLDEN_TOL=N allows ±N BLU. A golden
# may only change in a commit that says why.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:?usage: tools/golden.sh check NAME [GMOTION] | regen [GMOTION]}
data=tests/golden/data

args_of() {
  local line
  line=$(grep -E "^$1\|" tests/golden/cases.txt) || { echo "golden: no case '$1'" >&2; exit 2; }
  echo "${line#*|}"
}

# run NAME GMOTION OUTDIR: writes OUTDIR/NAME.csv and OUTDIR/NAME.summary.json
run_case() {
  # shellcheck disable=SC2046
  "$2" run $(args_of "$1") --trace "$3/$1.csv" --summary-json "$3/$1.summary.json" >/dev/null
}

case "$mode" in
  check)
    name=${2:?usage: tools/golden.sh check NAME [GMOTION]}
    bin=${3:-build/bin/gmotion}
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    run_case "$name" "$bin" "$tmp"
    status=0
    "$bin" diff --tol "${GOLDEN_TOL:-0}" "$data/$name.csv" "$tmp/$name.csv" || status=1
    if ! cmp -s "$data/$name.summary.json" "$tmp/$name.summary.json"; then
      echo "summary differs from $data/$name.summary.json:"
      diff <(tr ',' '\n' < "$data/$name.summary.json") <(tr ',' '\n' < "$tmp/$name.summary.json") || true
      status=1
    fi
    exit $status
    ;;
  regen)
    bin=${2:-build/bin/gmotion}
    mkdir -p "$data"
    tmp=$(mktemp -d)
    trap 'rm -rf "$tmp"' EXIT
    grep -vE '^(#|$)' tests/golden/cases.txt | cut -d'|' -f1 | while read -r name; do
      run_case "$name" "$bin" "$tmp"
      if [[ -f "$data/$name.csv" ]] && "$bin" diff "$data/$name.csv" "$tmp/$name.csv" >"$tmp/diff.txt" 2>&1 &&
         cmp -s "$data/$name.summary.json" "$tmp/$name.summary.json"; then
        echo "$name: unchanged"
      else
        echo "$name: CHANGED"
        [[ -f "$data/$name.csv" ]] && sed 's/^/    /' "$tmp/diff.txt"
        cp "$tmp/$name.csv" "$tmp/$name.summary.json" "$data/"
      fi
    done
    du -k "$data"/* | sort -n | tail -3
    ;;
  *) echo "usage: tools/golden.sh check NAME [GMOTION] | regen [GMOTION]" >&2; exit 2 ;;
esac
