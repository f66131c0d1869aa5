#!/usr/bin/env bash
# Installs the build into a scratch prefix, builds tests/package/consumer against it with
# find_package(gmotion), runs a bundled program through it and compares its summary JSON with
# the CLI's: the installed package is complete and gives the same run.
# Usage: consumer_test.sh BUILD_DIR SOURCE_DIR GMOTION_BIN
set -euo pipefail
build=$1 src=$2 gmotion=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"
for f in lib/cmake/gmotion/gmotionConfig.cmake lib/cmake/gmotion/gmotionConfigVersion.cmake \
         include/gmotion/pipeline/run.hpp include/gmotion/grammar/parse.hpp \
         include/gmotion/trace/trace_columns.def bin/gmotion; do
  [[ -e "$work/prefix/$f" ]] || { echo "consumer_test: $f was not installed" >&2; exit 1; }
done
if [[ -e "$work/prefix/include/gmotion/cli" ]]; then
  echo "consumer_test: the command line's private headers were installed" >&2; exit 1
fi
cmake -S "$src/tests/package/consumer" -B "$work/consumer" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" >"$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/consumer" >"$work/build.log" || { cat "$work/build.log"; exit 1; }
for prog in square.nc helix.nc; do
  "$work/consumer/app" "$src/programs/$prog" >"$work/app.json"
  "$gmotion" run "$src/programs/$prog" --summary-json "$work/cli.json" >/dev/null
  cmp "$work/app.json" "$work/cli.json" || { echo "consumer_test: $prog: summaries differ" >&2; exit 1; }
  echo "consumer_test: $prog: the installed package's run equals the CLI's ($(wc -c <"$work/app.json") bytes of summary)"
done
# A program it cannot run is an error, not a crash.
if "$work/consumer/app" "$src/tests/bad/arc_zero_radius.nc" >/dev/null 2>"$work/err.txt"; then
  echo "consumer_test: a bad program ran" >&2; exit 1
fi
grep -q "arc_zero_radius.nc" "$work/err.txt" || { cat "$work/err.txt"; exit 1; }
