#!/usr/bin/env bash
# The project's golden traces (tests/golden, a `gmotion golden` suite): check one case, or
# re-record them on purpose.
#
#   tools/golden.sh check NAME [GMOTION]   run NAME fresh; exit 1 if its trace or summary differ
#   tools/golden.sh regen [GMOTION]        re-record every case that changed and print what changed
#
# Cases are listed in tests/golden/suite.toml; their goldens are in tests/golden/data (docs/golden.md).
# GMOTION defaults to build/bin/gmotion. Traces compare exactly (encoder counts included). A golden
# may only change in a commit that says why.
set -euo pipefail
cd "$(dirname "$0")/.."
mode=${1:?usage: tools/golden.sh check NAME [GMOTION] | regen [GMOTION]}
case "$mode" in
  check)
    name=${2:?usage: tools/golden.sh check NAME [GMOTION]}
    exec "${3:-build/bin/gmotion}" golden verify tests/golden --case "$name" -j 1
    ;;
  regen)
    exec "${2:-build/bin/gmotion}" golden verify tests/golden --update
    ;;
  *) echo "usage: tools/golden.sh check NAME [GMOTION] | regen [GMOTION]" >&2; exit 2 ;;
esac
