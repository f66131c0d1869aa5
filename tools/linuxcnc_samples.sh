#!/bin/sh
# `gmotion check` over LinuxCNC's sample programs, each on the sample configuration it is written
# for, as a LinuxCNC user runs them: lathe*.ngc on sim/axis/lathe.ini (XZ, inch, lathe.tbl), the
# others on sim/axis/axis_9axis.ini (XYZABCUVW, inch, sim.tbl). Prints the ones that fail with
# their first error and fails if fewer than MIN pass (the count only grows as codes land).
# Exit 77 (skip) without the samples. Usage: linuxcnc_samples.sh GMOTION MIN [DIR [SIMDIR]]
gm=$1
min=$2
dir=${3:-/usr/share/linuxcnc/ncfiles}
sim=${4:-/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis}
[ -d "$dir" ] && [ -d "$sim" ] || { echo "no $dir or $sim: skipped"; exit 77; }
pass=0
total=0
for f in "$dir"/*.ngc; do
  total=$((total + 1))
  case $(basename "$f") in
    lathe*) machine=$sim/lathe.ini ;;
    *) machine=$sim/axis_9axis.ini ;;
  esac
  if "$gm" check "$f" --machine "$machine" >/dev/null 2>&1; then
    pass=$((pass + 1))
  else
    echo "fails: $(basename "$f") on $(basename "$machine"): $("$gm" check "$f" --machine "$machine" 2>&1 | grep -m1 'error:' | sed 's/.*error: //')"
  fi
done
echo "linuxcnc samples: $pass of $total pass gmotion check (at least $min expected)"
[ "$pass" -ge "$min" ]
