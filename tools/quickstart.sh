#!/usr/bin/env bash
# README command 1: install what is missing, build gmotion (default preset), and run the paper's
# circle test through the four Acc/Dec profiles, printed as one table.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake --preset default >/dev/null
cmake --build --preset default --target gmotion
echo
build/bin/gmotion compare programs/paper-circle.nc --machine programs/machines/paper.toml
