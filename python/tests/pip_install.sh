#!/usr/bin/env bash
# `pip install --no-build-isolation .` into a fresh venv, offline, with Debian's setuptools,
# wheel, CMake and pybind11; then the installed package (not build/python) runs a program and
# must give the command line's summary. Usage: pip_install.sh SOURCE_DIR WORK_DIR GMOTION_BIN
set -euo pipefail
src=$1 work=$2 bin=$3
rm -rf "$work"
mkdir -p "$work"
/usr/bin/python3 -m venv --system-site-packages "$work/venv"   # Debian's numpy stays visible
cd "$src"
GMOTION_PIP_BUILD_DIR="$work/build" PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 \
  "$work/venv/bin/pip" install --no-build-isolation --no-index -q .
"$bin" run "$src/programs/square.nc" --summary-json "$work/cli.json" >/dev/null
cd "$work"  # away from the source tree: the import must find the installed package
PYTHONPATH= "$work/venv/bin/python" - "$src" "$work" <<'PY'
import json, os, sys
import gmotion
src, work = sys.argv[1], sys.argv[2]
where = os.path.realpath(gmotion.__file__)
assert where.startswith(os.path.realpath(work) + "/venv/"), f"imported {where}, not the venv's"
r = gmotion.run(os.path.join(src, "programs", "square.nc"))
with open(os.path.join(work, "cli.json")) as f:
    cli = json.load(f)
assert r.finished
assert r.summary == cli, (r.summary, cli)
print(f"pip-installed gmotion {gmotion.__version__} at {where}: square.nc cycle "
      f"{r.summary['cycle_time_s']} s, {len(r.trace['t_s'])} samples, summary equal to the CLI's")
PY
