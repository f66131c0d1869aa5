#!/bin/sh
# `gmotion check` over LinuxCNC's sample programs: prints the ones that fail and fails if fewer
# than MIN pass (the count only grows as codes land). Exit 77 (skip) without the samples.
# Usage: linuxcnc_samples.sh GMOTION MIN [DIR]
gm=$1
min=$2
dir=${3:-/usr/share/linuxcnc/ncfiles}
[ -d "$dir" ] || { echo "no $dir: skipped"; exit 77; }
pass=0
total=0
for f in "$dir"/*.ngc; do
  total=$((total + 1))
  if "$gm" check "$f" >/dev/null 2>&1; then pass=$((pass + 1)); else echo "fails: $(basename "$f")"; fi
done
echo "linuxcnc samples: $pass of $total pass gmotion check (at least $min expected)"
[ "$pass" -ge "$min" ]
