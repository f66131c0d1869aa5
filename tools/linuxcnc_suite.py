#!/usr/bin/env python3
"""LinuxCNC's own interpreter regression tests, run through LinuxCNC's `rs274` and `gmotion moves`.

A developer points it at a LinuxCNC source checkout; nothing of LinuxCNC's is copied into gmotion:
  tools/linuxcnc_suite.py --linuxcnc ~/src/linuxcnc --gmotion build/bin/gmotion [--rs274 rs274]

The pure-interpreter suites are tests/interp (with its m98m99 folder), tests/ccomp and tests/oword.
A test is a folder holding `test.sh` (or `test`, a script over every *.ngc of the folder). Its
script is read for the `rs274` commands it runs: the program and the flags -t (tool table),
-i (INI), -v (parameter file) and -n (continue mode); `! rs274 ...` marks a program the test
expects to be refused. Each such run is made twice, from a scratch copy of the test folder:
  * rs274 (LinuxCNC 2.9's standalone interpreter) with the same flags, every run with its own
    empty HOME, on the program renumbered N<file line> so that it reports source lines;
  * `gmotion moves` with the flags a user would pass: the INI as --machine, the tool table as
    --tool-table (converted from rs274's inches to mm; without -t the table rs274 then reads,
    --rs274-tools), the parameter file as --parameter-file
    (likewise), --axes XYZABCUVW, --messages and --io.
Both outputs are compared as tools/rs274_diff.py compares them (its parser and comparator are
imported). One line per test, then the totals:
  pass                  every run agrees (moves, messages, I/O), or both refuse where expected
  differs               a run differs: the first difference is named
  both refuse           every run is refused by both (an error test)
  rs274 cannot run it   LinuxCNC 2.9's rs274 refuses or never finishes a program the test expects
                        to run (a feature newer than 2.9, an endless loop the test was written to
                        catch), or the test needs more than rs274 (`linuxcnc -r`, a compiler, a
                        plugin interpreter, Python's canon module)
Exit status: 0 when nothing differs, 1 otherwise, 2 on a usage error.
"""
from __future__ import annotations

import argparse
import glob
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import rs274_diff as rd  # noqa: E402

SUITES = ("interp", "ccomp", "oword")
GMOTION_AXES = "XYZABCUVW"  # rs274's canon drives nine axes
RS274_TIMEOUT_S = 10.0       # the endless-loop tests give rs274 5-10 s
GMOTION_TIMEOUT_S = 60.0
# The table rs274 2.9 reads when not given -t (EMC2_DEFAULT_TOOLTABLE of linuxcnc-uspace), inches
RS274_DEFAULT_TOOLS = "/usr/share/doc/linuxcnc/examples/sample-configs/common/tool.tbl"

# What a test script runs instead of rs274 on G-code: it is beyond an interpreter comparison.
NEEDS_MORE = [
    (re.compile(r"^\s*(exec\s+)?linuxcnc\s"), "needs a running LinuxCNC (linuxcnc -r)"),
    (re.compile(r"^\s*g\+\+\s"), "compiles a program against LinuxCNC's interpreter library"),
    (re.compile(r"python3\s+-mcanon"), "drives the interpreter from Python's canon module"),
    (re.compile(r"\brs274\b.*\s-p\s"), "a plugin interpreter (canterp reads canon calls)"),
]


@dataclass
class Run:
    program: str                                  # relative to the test folder
    flags: dict = field(default_factory=dict)     # rs274 option letter -> value
    expect_error: bool = False


@dataclass
class Test:
    name: str
    folder: Path
    runs: list = field(default_factory=list)
    needs: str = ""                               # why rs274 alone cannot run it


def _shell_lines(text: str) -> list[str]:
    """The script's command lines: comments dropped, backslash continuations joined."""
    out, cur = [], ""
    for raw in text.splitlines():
        line = raw.rstrip()
        if line.lstrip().startswith("#"):
            continue
        if line.endswith("\\"):
            cur += line[:-1] + " "
            continue
        out.append(cur + line)
        cur = ""
    return out


_STOP = {"|", "||", "&&", ";", "&", "}", ">", "2>&1", "then"}


def parse_rs274_command(line: str, folder: Path) -> list[Run]:
    """The rs274 runs of one script line: `[!] rs274 [-t T] [-i I] [-v V] [-n N] -g PROGRAM`.
    A program named with a shell variable (a loop over names) stands for every file it matches."""
    try:
        words = shlex.split(line.replace(";", " ; "), posix=True)
    except ValueError:
        return []
    if "rs274" not in words:
        return []
    at = words.index("rs274")
    expect_error = "!" in words[:at]  # `! rs274 ...`, `if ! rs274 ...`
    flags, programs, i = {}, [], at + 1
    while i < len(words) and words[i] not in _STOP and not words[i].startswith((">", "2>")):
        w = words[i]
        if w in ("-t", "-i", "-v", "-n", "-p"):
            flags[w[1]] = words[i + 1] if i + 1 < len(words) else ""
            i += 2
            continue
        if not w.startswith("-"):
            programs.append(w)
        i += 1
    if not programs:
        return []
    prog = programs[0]
    if "$" in prog:
        pattern = re.sub(r"\$\{?\w+\}?", "*", prog)
        names = sorted(os.path.basename(p) for p in glob.glob(str(folder / pattern)))
    else:
        names = [prog]
    # m98m99/11's loop over test-illegal-*.ngc fails when one of them runs
    return [Run(n, dict(flags), expect_error or "illegal" in n) for n in names]


def discover(root: Path) -> list[Test]:
    tests = []
    for suite in SUITES:
        base = root / "tests" / suite
        if not base.is_dir():
            continue
        for script in sorted(list(base.rglob("test.sh")) + list(base.rglob("test"))):
            if not script.is_file():
                continue
            folder = script.parent
            t = Test(str(folder.relative_to(root / "tests")), folder)
            text = script.read_text(errors="replace")
            if script.name == "test":
                # bad/ and good/: a Python script running `rs274 -g` on every *.ngc of the folder
                refused = "accepted bad gcode" in text
                t.runs = [Run(p.name, {}, refused) for p in sorted(folder.glob("*.ngc"))]
            else:
                for line in _shell_lines(text):
                    for pat, why in NEEDS_MORE:
                        if pat.search(line):
                            t.needs = t.needs or why
                    if not t.needs:
                        t.runs += parse_rs274_command(line, folder)
            if t.needs:
                t.runs = []
            tests.append(t)
    return sorted(tests, key=lambda t: t.name)


# ---------------------------------------------------------------------------------------------
# one run on both sides

def _scale_tool_table(text_in: str) -> str:
    """A tool table rs274 reads in inches -> the same table in mm for gmotion."""
    out = []
    for line in text_in.splitlines():
        body, sep, comment = line.partition(";")

        def conv(m):
            letter, val = m.group(1).upper(), float(m.group(2))
            if letter in "XYZUVWD":
                return f"{letter}{val * rd.MM_PER_INCH:.10g}"
            return m.group(0)
        out.append(rd._TBL_WORD.sub(conv, body) + sep + comment)
    return "\n".join(out) + "\n"


def _scale_var_file(text_in: str) -> str:
    """A parameter file in rs274's inches -> mm (the lengths of G28, G30, G92, G54-G59.3)."""
    out = []
    for line in text_in.splitlines():
        f = line.split()
        if len(f) >= 2 and f[0].isdigit() and rd._var_is_length(int(f[0])):
            line = f"{f[0]}\t{float(f[1]) * rd.MM_PER_INCH:.6f}"
        out.append(line)
    return "\n".join(out) + "\n"


@dataclass
class Side:
    ok: bool
    moves: list = field(default_factory=list)
    error: str = ""
    hung: bool = False


def run_rs274(rs274: str, work: Path, run: Run) -> Side:
    """rs274 in `work` (a scratch copy of the test folder, the program renumbered in place)."""
    prog = work / run.program
    prog.write_text(rd.number_lines(prog.read_text(errors="replace")))
    cmd = [rs274]
    for k in ("t", "i", "v", "n"):
        if k in run.flags:
            cmd += [f"-{k}", run.flags[k]]
    cmd += ["-g", run.program]
    home = work / ".home"
    home.mkdir(exist_ok=True)
    env = dict(os.environ, HOME=str(home))
    for _attempt in range(3):
        try:
            p = subprocess.run(cmd, cwd=work, stdin=subprocess.DEVNULL, capture_output=True,
                               text=True, errors="replace", timeout=RS274_TIMEOUT_S, env=env)
        except subprocess.TimeoutExpired:
            return Side(False, error=f"did not finish within {RS274_TIMEOUT_S:g} s", hung=True)
        if p.returncode >= 0:  # a death by signal (a shared-memory race) is retried
            break
    err = "\n".join(ln for ln in p.stderr.splitlines() if ln.strip() != "executing")
    if p.returncode != 0:
        return Side(False, error=err or f"exit status {p.returncode}")
    return Side(True, rd.parse_rs274_output(p.stdout))


def run_gmotion(gmotion: str, work: Path, run: Run, default_tools: str) -> Side:
    """`gmotion moves` in `work` (a scratch copy of the test folder, the program as written).
    Without -t it gets the table rs274 reads then (`default_tools`), not its own built-in one."""
    cmd = [gmotion, "moves", run.program, "--messages", "--io", "--axes", GMOTION_AXES]
    if "i" in run.flags:
        cmd += ["--machine", run.flags["i"]]
    tools = work / run.flags["t"] if "t" in run.flags else Path(default_tools)
    if tools.is_file():
        mm = work / ".tools-mm.tbl"
        mm.write_text(_scale_tool_table(tools.read_text(errors="replace")))
        cmd += ["--tool-table", str(mm)]
    if "v" in run.flags:
        var = work / run.flags["v"]
        if var.exists():
            var.write_text(_scale_var_file(var.read_text()))
        cmd += ["--parameter-file", run.flags["v"]]
    try:
        p = subprocess.run(cmd, cwd=work, stdin=subprocess.DEVNULL, capture_output=True,
                           text=True, errors="replace", timeout=GMOTION_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return Side(False, error=f"did not finish within {GMOTION_TIMEOUT_S:g} s", hung=True)
    if p.returncode != 0:
        return Side(False, error=p.stderr.strip() or f"exit status {p.returncode}")
    try:
        return Side(True, rd.parse_gmotion_output(p.stdout))
    except ValueError as e:
        return Side(False, error=str(e))


_LONG_NUM = re.compile(r"-?\d+\.\d{5,}")


def _as_printed(moves: list) -> list:
    """gmotion's I/O records with their numbers rounded as rs274 prints them (%.4f)."""
    for m in moves:
        if m.kind == "io" and m.text:
            m.text = _LONG_NUM.sub(lambda x: f"{float(x.group(0)):.4f}", m.text)
    return moves


def compare(ref: list, got: list) -> str | None:
    """None if gmotion's moves match rs274's, else the first difference (as rs274_diff does)."""
    got = _as_printed(got)
    for m in ref:
        # rs274 prints a move held by cutter compensation with the line that releases it; in a
        # loop that line can come before the move's own, so its line is not compared
        if m.held:
            m.line = None
    ref, _ = rd.drop_zero_length(ref, 1e-12)
    got, _ = rd.drop_zero_length(got, 2 * rd.RS274_PRINT_HALF_ULP)
    got = rd.collapse_splines(ref, got)
    mm = rd.compare_moves(ref, got, rd.Tol())
    if mm is None:
        return None
    idx, why = mm
    r = ref[idx] if idx < len(ref) else None
    g = got[idx] if idx < len(got) else None
    return f"move #{idx + 1}: {why}; rs274 {r if r else '(none)'}; gmotion {g if g else '(none)'}"


def _first(text: str) -> str:
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[0][:160] if lines else ""


def _gm_error(text: str) -> tuple[int | None, str]:
    """gmotion's first error: (line, message)."""
    for ln in text.splitlines():
        m = rd._GM_ERR.search(ln)
        if m:
            return int(m.group(1)), m.group(3)[:160]
    return None, _first(text)


def _error_expected(folder: Path, error: str) -> bool:
    """True if rs274's error (its message or the block it echoes) is in the test's expected
    output: a test that runs rs274 with `2>&1` and expects the refusal."""
    exp = folder / "expected"
    if not exp.is_file():
        return False
    text = exp.read_text(errors="replace")
    for ln in error.splitlines():
        s = re.sub(r"^/?\s*N\d+\s*", "", ln.strip())
        if len(s) > 3 and s in text:
            return True
    return False


def judge(args, test: Test, run: Run) -> tuple[str, str]:
    """(verdict, detail) of one run: pass | differs | both refuse | rs274 cannot run it."""
    with tempfile.TemporaryDirectory(prefix="lcncsuite-") as tmp:
        rs_dir, gm_dir = Path(tmp) / "rs274", Path(tmp) / "gmotion"
        shutil.copytree(test.folder, rs_dir, symlinks=True)
        shutil.copytree(test.folder, gm_dir, symlinks=True)
        for d in (rs_dir, gm_dir):  # a `.template` the script copies before running
            for tpl in d.glob("*.template"):
                shutil.copy(tpl, d / tpl.name[:-len(".template")])
        rs = run_rs274(args.rs274, rs_dir, run)
        numbered = (rs_dir / run.program).read_text(errors="replace")
        gm = run_gmotion(args.gmotion, gm_dir, run, args.rs274_tools)
    if rs.hung:
        return "rs274 cannot run it", f"rs274 {rs.error}" + (
            "; gmotion refuses it" if not gm.ok else "; gmotion runs it")
    if not rs.ok and not gm.ok:
        # as rs274_diff --errors: both must stop on the same line (when rs274 names one)
        rl = rd.rs274_error_line(rs.error, numbered)
        gl, gmsg = _gm_error(gm.error)
        detail = f"rs274 line {rl}: {_first(rs.error)} / gmotion line {gl}: {gmsg}"
        if rl is not None and gl is not None and rl != gl:
            return "differs", "both refuse, on different lines: " + detail
        if not (run.expect_error or _error_expected(test.folder, rs.error)):
            return "rs274 cannot run it", f"rs274 2.9 refuses what the test expects to run " \
                f"({_first(rs.error)}); gmotion refuses it too ({gmsg})"
        return "both refuse", detail
    if not rs.ok:
        if run.expect_error:
            return "differs", f"gmotion accepts what LinuxCNC refuses ({_first(rs.error)})"
        return "rs274 cannot run it", f"rs274 2.9 refuses: {_first(rs.error)} (gmotion runs it)"
    if not gm.ok:
        gl, gmsg = _gm_error(gm.error)
        return "differs", f"gmotion refuses: line {gl}: {gmsg}"
    if run.expect_error:
        return "rs274 cannot run it", "rs274 2.9 runs what the test expects refused (gmotion " \
            "runs it too" + (")" if compare(rs.moves, gm.moves) is None else ", differently)")
    why = compare(rs.moves, gm.moves)
    if why:
        return "differs", why
    return "pass", f"{len(rs.moves)} records"


ORDER = ["differs", "rs274 cannot run it", "pass", "both refuse"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="LinuxCNC's interpreter tests: rs274 vs gmotion")
    ap.add_argument("--linuxcnc", required=True, help="a LinuxCNC source checkout")
    ap.add_argument("--gmotion", required=True, help="the gmotion executable")
    ap.add_argument("--rs274", default="rs274", help="LinuxCNC 2.9's rs274 (default: rs274)")
    ap.add_argument("--rs274-tools", default=RS274_DEFAULT_TOOLS, metavar="FILE",
                    help="the tool table rs274 reads without -t, given to gmotion for such tests "
                         f"(default {RS274_DEFAULT_TOOLS})")
    ap.add_argument("--only", default="", help="run the tests whose name contains this text")
    ap.add_argument("-v", "--verbose", action="store_true", help="a line for every run too")
    args = ap.parse_args(argv)
    root = Path(args.linuxcnc)
    if not (root / "tests" / "interp").is_dir():
        ap.error(f"{root} holds no tests/interp: not a LinuxCNC checkout")
    if not (shutil.which(args.rs274) or os.access(args.rs274, os.X_OK)):
        ap.error(f"{args.rs274} not found (install linuxcnc-uspace)")
    args.gmotion = os.path.abspath(args.gmotion)
    rd.GMOTION_AXES = GMOTION_AXES
    rd.IO_RECORDS = True
    counts = {k: 0 for k in ORDER}
    for test in discover(root):
        if args.only and args.only not in test.name:
            continue
        if test.needs:
            verdict, detail = "rs274 cannot run it", test.needs
        elif not test.runs:
            verdict, detail = "rs274 cannot run it", "its script runs no rs274 command"
        else:
            results = [(run, *judge(args, test, run)) for run in test.runs]
            if args.verbose:
                for run, v, d in results:
                    print(f"    {test.name}/{run.program}: {v}: {d}")
            verdicts = [v for _, v, _ in results]
            verdict = next(v for v in ORDER if v in verdicts)
            if verdict == "pass":
                n = len(results)
                detail = f"{n} run{'s' if n > 1 else ''}" + (
                    f", {verdicts.count('both refuse')} refused by both"
                    if verdict == "pass" and "both refuse" in verdicts else "")
            else:
                run, _, d = next(r for r in results if r[1] == verdict)
                detail = (f"{run.program}: " if len(results) > 1 else "") + d
        counts[verdict] += 1
        print(f"{verdict:<20} {test.name}: {detail}")
    total = sum(counts.values())
    print(f"linuxcnc_suite: {total} tests: {counts['pass']} pass, {counts['both refuse']} both "
          f"refuse, {counts['differs']} differ, {counts['rs274 cannot run it']} rs274 cannot run")
    return 1 if counts["differs"] else 0


if __name__ == "__main__":
    sys.exit(main())
