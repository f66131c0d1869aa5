#!/usr/bin/env bash
# Fails when a tracked C++ file differs from what clang-format (.clang-format) makes of it.
# Usage: tools/check-format.sh [--fix]   (--fix rewrites the files in place)
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.hpp')
if [[ "${1:-}" == "--fix" ]]; then
  clang-format -i "${files[@]}"
  exit 0
fi
if ! clang-format --dry-run --Werror "${files[@]}" 2>/tmp/gmotion-format.$$; then
  grep -E '^[^ ].*: (error|warning):' /tmp/gmotion-format.$$ | cut -d: -f1 | sort -u |
    sed 's/^/check-format: not formatted: /' >&2
  rm -f /tmp/gmotion-format.$$
  echo "check-format: run tools/check-format.sh --fix" >&2
  exit 1
fi
rm -f /tmp/gmotion-format.$$
echo "check-format: ${#files[@]} files formatted"
