#!/usr/bin/env bash
# `gmotion golden` end to end on small temporary suites: record/verify round trip; a one-count
# change in a program, a τ change in the machine and an override-schedule change each caught at
# the right line and column; a set-up or version change named as such; JUnit XML shape; a run
# that does not complete refused by record; --update; pictures; output stable across runs and -j.
# Usage: golden_suite_test.sh GMOTION REPO_DIR
set -euo pipefail
bin=$1 repo=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
expect() {  # expect PATTERN TEXT: grep -E PATTERN must match TEXT
  grep -qE -- "$1" <<<"$2" || fail "expected /$1/ in:"$'\n'"$2"
}

s=$tmp/suite
mkdir -p "$s/machines"
cp "$repo/programs/square.nc" "$repo/programs/override-replay.nc" "$repo/programs/override-replay.csv" "$s/"
cp "$repo/programs/machines/default.toml" "$s/machines/mill.toml"
cat > "$s/suite.toml" <<'TOML'
[defaults]
machine = "machines/mill.toml"

[[case]]
program = "square.nc"
columns = ["t_s", "line", "*_cmd", "*_ref", "*_enc"]   # positions (contour_err left out)

[[case]]
name = "replay"
program = "override-replay.nc"
override_file = "override-replay.csv"
decimate = 2

[[case]]
name = "square-tol"
program = "square.nc"
columns = ["*_enc", "contour_err"]
tolerance_blu = 0
tolerances = { "y_*" = 2 }
summary = false
TOML

# 1. Round trip: record, then verify passes; the store holds the three files per case.
out=$("$bin" golden record "$s")
expect '^RECORDED  square: recorded \([0-9.]+ KiB\)$' "$out"
expect '^3 cases: 3 recorded, 0 changed, 0 unchanged, 0 errors' "$out"
for f in square.trace.zst square.summary.json square.golden.toml; do
  [[ -s $s/golden/$f ]] || fail "record left no $f"
done
[[ $(head -c 4 "$s/golden/square.trace.zst" | od -An -tx1 | tr -d ' ') == 28b52ffd ]] ||
  fail "the trace is not zstd-compressed"
grep -q "^gmotion_version = '$("$bin" --version | cut -d' ' -f2)'" "$s/golden/square.golden.toml" ||
  fail "the record does not name the gmotion version"
out=$("$bin" golden verify "$s" --junit "$tmp/pass.xml")
expect '^PASS      square$' "$out"
expect '^3 cases: 3 passed, 0 failed, 0 errors$' "$out"

# 2. A one-count change: line 7 `G1 X20 F1200` now also moves Y by 1 µm (one BLU). Y's command
# rounds to 1 once half the 20 mm line is done: first divergence on line 7, column y_cmd, 0 -> 1
# (X moves 2.5e-8 µm less: no count changes). Row 1 is t = 0; line 7 starts after line 6's
# 1 mm at F300 (0.2 s) and the filter's settling; half of 1 s later is row ~ 0.2/T + 125 +.
sed -i 's/^G1 X20 F1200$/G1 X20 Y0.001 F1200/' "$s/square.nc"
if out=$("$bin" golden verify "$s" --case square --pictures "$tmp/pics"); then fail "one count not caught"; fi
expect '^FAIL      square: first divergence t = [0-9.]+ s, line 7, column y_cmd: golden 0, now 1 \(row [0-9]+\)$' "$out"
expect '^          largest difference per column: .*y_cmd=1' "$out"
[[ $(head -c 8 "$tmp/pics/square.png" | od -An -c | tr -d ' ') == '211PNG\r\n032\n' ]] ||
  fail "no PNG picture of the divergence"
[[ $(stat -c %s "$tmp/pics/square.png") -gt 2000 ]] || fail "the picture is nearly empty"
# Pinned columns and tolerances: square-tol pins only the encoders (y within 2) and contour_err.
out=$("$bin" golden verify "$s" --case square-tol || true)
expect '^(PASS|FAIL)      square-tol' "$out"
! grep -q 'column [xyz]_cmd' <<<"$out" || fail "an unpinned column was compared: $out"
! grep -q 'column y_' <<<"$out" || fail "y diverged beyond its tolerance of 2 BLU: $out"
cp "$repo/programs/square.nc" "$s/square.nc"

# 3. A τ change in the machine: a set-up change, named, then where the motion diverged. The first
# move is line 5's rapid to Z1 (X0 Y0 from the origin): 1 mm at 100 mm/s, done within 10 ms, so
# the interpolator is on line 6 when the filter's output z_ref (the Blackman taps start near 0)
# first moves by a count: t = 12 ms, row 4, line 6, z_ref; the interpolator's z_cmd is unchanged.
sed -i 's/^tau_s = 0.164 /tau_s = 0.1 /' "$s/machines/mill.toml"
grep -q '^tau_s = 0.1 ' "$s/machines/mill.toml" || fail "could not edit tau_s"
if out=$("$bin" golden verify "$s" --case square -j 1); then fail "tau change not caught"; fi
expect '^FAIL      square: set-up changed since recorded \(machine hash [0-9a-f]{16}, now [0-9a-f]{16}: \[accdec\] tau_s: 0.164 -> 0.1\)$' "$out"
expect '^          first divergence t = 0.012000 s, line 6, column z_ref: golden 0, now [1-9][0-9]* \(row 4\)$' "$out"
cp "$repo/programs/machines/default.toml" "$s/machines/mill.toml"

# 4. An override-schedule change: 150 % from 0.80 s becomes 120 %. The schedule is not part of
# the set-up (like the program): the arc on line 6 diverges right after 0.80 s.
sed -i 's/^0.80,150$/0.80,120/' "$s/override-replay.csv"
if out=$("$bin" golden verify "$s" --case replay); then fail "schedule change not caught"; fi
expect '^FAIL      replay: first divergence t = 0\.8[01][0-9]+ s, line 6, column [xy]_cmd: ' "$out"
cp "$repo/programs/override-replay.csv" "$s/"

# 5. Stable output: the same failing verify twice, on one core and on all, prints the same bytes.
sed -i 's/^Y20$/Y20.002/' "$s/square.nc"
"$bin" golden verify "$s" -j 1 > "$tmp/run1.txt" 2>/dev/null || true
"$bin" golden verify "$s" -j 4 > "$tmp/run2.txt" 2>/dev/null || true
cmp "$tmp/run1.txt" "$tmp/run2.txt" || fail "verify output differs between runs"
expect '^3 cases: 1 passed, 2 failed, 0 errors$' "$(cat "$tmp/run1.txt")"

# 6. JUnit XML: the usual shape (testsuites > testsuite > testcase, failure with message and
# type), counts that add up, parseable.
"$bin" golden verify "$s" --junit "$tmp/fail.xml" >/dev/null || true
python3 - "$tmp/pass.xml" "$tmp/fail.xml" <<'PY'
import sys, xml.etree.ElementTree as ET
for path, failures in ((sys.argv[1], 0), (sys.argv[2], 2)):
    root = ET.parse(path).getroot()
    assert root.tag == "testsuites", root.tag
    suites = root.findall("testsuite")
    assert len(suites) == 1
    ts = suites[0]
    cases = ts.findall("testcase")
    assert [c.get("name") for c in cases] == ["square", "replay", "square-tol"], cases
    for c in cases:
        assert c.get("classname") == "golden." + ts.get("name") and float(c.get("time")) >= 0
    got = [c for c in cases if c.find("failure") is not None]
    assert len(got) == failures == int(ts.get("failures")) == int(root.get("failures")), path
    assert int(ts.get("tests")) == 3 and int(ts.get("errors")) == 0
    for c in got:
        f = c.find("failure")
        assert f.get("type") == "divergence" and "first divergence" in f.get("message"), f.attrib
        assert "largest difference per column" in f.text
PY

# 7. --update re-records what changed and says so; verify passes afterwards. (Y20 -> Y20.002 on
# line 8 moves the end of that line by 2 counts: line 8's samples are unchanged until it ends, so
# the motion first differs on line 9, in X, which now starts from a later point in time.)
out=$("$bin" golden verify "$s" --update)
expect '^CHANGED   square: re-recorded: first divergence t = [0-9.]+ s, line 9, column x_cmd' "$out"
expect '^UNCHANGED replay$' "$out"
"$bin" golden verify "$s" >/dev/null || fail "verify fails after --update"

# 8. Another gmotion version, same values: a pass that says so.
sed -i "s/^gmotion_version = .*/gmotion_version = '0.0.1'/" "$s/golden/replay.golden.toml"
out=$("$bin" golden verify "$s" --case replay)
expect '^PASS      replay \(recorded with gmotion 0.0.1, this is ' "$out"

# 9. Record refuses a run that does not complete, and stores nothing for it.
p=$tmp/partial
mkdir -p "$p"
cp "$repo/programs/square.nc" "$p/"
printf '[[case]]\nprogram = "square.nc"\nflags = "--max-time 0.5"\n' > "$p/suite.toml"
if out=$("$bin" golden record "$p"); then fail "a run stopped by --max-time was recorded"; fi
expect '^ERROR     square: the run did not complete \(nothing recorded\): run stopped at --max-time 0.5 s' "$out"
[[ ! -e $p/golden/square.golden.toml && ! -e $p/golden/square.trace.zst ]] || fail "a partial run left a golden"

# 10. A folder of programs without suite.toml runs each with the defaults; a missing golden is an error.
f=$tmp/folder
mkdir -p "$f"
cp "$repo/programs/square.nc" "$repo/programs/zigzag.nc" "$f/"
if out=$("$bin" golden verify "$f"); then fail "verify passed with no goldens"; fi
expect '^ERROR     square: no golden recorded' "$out"
"$bin" golden record "$f" >/dev/null
out=$("$bin" golden verify "$f")
expect '^2 cases: 2 passed, 0 failed, 0 errors$' "$out"
echo "ok"
