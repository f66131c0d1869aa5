#!/usr/bin/env bash
# Installs the Debian packages gmotion's build, tests and tools need — only those missing.
# Idempotent; quiet when nothing is missing; works as root or through sudo.
# Usage: tools/install-deps.sh [--with-oracle] [--with-fuzz] [--with-bench] [--with-browser]
#   --with-oracle adds linuxcnc-uspace (rs274, for the differential tests);
#   --with-fuzz adds clang-14 and libclang-rt-14-dev (libFuzzer and the sanitizers, tools/fuzz.sh);
#   --with-bench adds GNU time (peak RSS in tools/bench.sh);
#   --with-browser adds chromium (the report_chromium test renders `gmotion report` headless).
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  libeigen3-dev libboost-dev libfmt-dev catch2 libcli11-dev libtomlplusplus-dev libbenchmark-dev
  libzstd-dev zlib1g-dev
  python3 python3-matplotlib clang-format python3-dev python3-numpy pybind11-dev
  python3-venv python3-pip python3-setuptools python3-wheel
)
for flag in "$@"; do
  case "$flag" in
    --with-oracle) packages+=(linuxcnc-uspace) ;;
    --with-fuzz) packages+=(clang-14 libclang-rt-14-dev) ;;
    --with-bench) packages+=(time) ;;
    --with-browser) packages+=(chromium) ;;
    *) echo "install-deps: unknown flag '$flag' (accepted: --with-oracle, --with-fuzz, --with-bench, --with-browser)" >&2; exit 2 ;;
  esac
done

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo_cmd=()
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "install-deps: not root and no sudo; install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
# Refresh the package lists once if they are empty or older than a day.
if [[ -z "$(find /var/lib/apt/lists -maxdepth 1 -name '*Packages*' -mtime -1 2>/dev/null | head -n1)" ]]; then
  "${sudo_cmd[@]}" apt-get update -qq
fi
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
