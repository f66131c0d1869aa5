#!/usr/bin/python3
"""LinuxCNC's planner against gmotion's on CAM programs, in the same path-control mode.

Runs the project's CAM-style programs (programs/cam-fillets.nc, cam-slot.nc, corners.nc,
small-arcs.nc, pocket.nc) and the public CAM programs (programs/public/cam/, SOURCES.md there),
each in every `--modes` entry (default P0.01 P0.05 G61 G64), through LinuxCNC 2.9 headless
(tools/linuxcnc_headless: sim XYZ machine, servo 1 ms, every MAX_VELOCITY 100 mm/s = gmotion's
rapid, MAX_ACCELERATION each `--accel`: 610 mm/s² is the mean acceleration of gmotion's FIR ramp
to 100 mm/s, 1750 its peak) and through `gmotion run --no-servo --check-tolerance`, and prints a
Markdown table: cycle time and worst distance of the commanded (LinuxCNC) or Acc/Dec output
(gmotion) position from the programmed path, every sample; gmotion's samples over P; and
gmotion's time in G61.1 (exact stop) beside it. Run by hand as root, one LinuxCNC at a time,
not in CI (each LinuxCNC session takes its cycle time plus about 10 s):

  /usr/bin/python3 tools/linuxcnc_cam_table.py [--modes P0.01 P0.05 G61 G64]
      [--accel 610 1750] [--programs NAME ...] [--repeat 1] [--gmotion PATH]
      [--max-override 100] [--tau 0.164]

Both planners plan for the same largest feed override, `--max-override` percent (100: LinuxCNC's
default when its INI has no [DISPLAY]MAX_FEED_OVERRIDE; gmotion's built-in machine says 200):
LinuxCNC's MAX_FEED_OVERRIDE and gmotion's `max_override_percent` (tools/linuxcnc_headless/
run.py, `gmotion_machine`). The G61.1 column is gmotion on the same machine. `--tau S` runs
gmotion with an Acc/Dec filter S seconds long instead of the built-in 0.164 s (its mean ramp
acceleration to 100 mm/s is then 100/S mm/s², the `--accel` to compare it with).

Modes: `P<tol>` is `G64 P<tol>`, `G64` is G64 without P (unbounded), `G61` is LinuxCNC's exact
path (gmotion's G61 is the same: docs/tolerance.md, "G61: exact path"), `G61.1` exact stop.
`--tol 0.01 0.05` (the old option) is `--modes P0.01 P0.05`.

How the mode gets into a program (the text written to a scratch .ngc; the file itself is not
changed):
  * a project program (programs/NAME.nc, a bare NAME) has its mode on its `G21` line; that mode
    (G64 [P..], G61, G61.1) is replaced by the requested one, as before;
  * a public program (a path under programs/, e.g. public/cam/cambam-engrave.nc) first loses
    every G61, G61.1 and G64 it sets itself (with the P and Q words right after a G64), outside
    comments; then the mode is inserted as a line of its own just before the first line that
    has an axis word (X Y Z A B C U V W) outside comments, i.e. after the program's preamble
    (units, plane, distance mode, tool and spindle lines, a leading `%`). Both planners then
    start the first move in the requested mode, whatever the program asked for.

LinuxCNC's `G64 P` also merges nearly collinear lines within Q = P (naive CAM); gmotion merges
only with an explicit Q (docs/tolerance.md, "G64 Q").
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(HERE, "linuxcnc_headless"))
import run as headless  # noqa: E402  (tools/linuxcnc_headless/run.py)

PROJECT = ["cam-fillets", "cam-slot", "corners", "small-arcs", "pocket"]
PUBLIC = ["public/cam/fusion-bore-tests.nc", "public/cam/fusion-tab-contour.nc",
          "public/cam/cambam-engrave.nc", "public/cam/sketchucam-rword.gcode"]
MODES = ["P0.01", "P0.05", "G61", "G64"]
MODE = re.compile(r"G64( P[0-9.]+)?|G61(\.1)?")
# A path-control word a public program sets itself: G61, G61.1, G64 with its P and Q.
OWN_MODE = re.compile(r"G0*61(\.1)?(?![0-9.])|G0*64(?![0-9.])(\s*[PQ]\s*[-+]?[0-9.]+)*",
                      re.IGNORECASE)
AXIS_WORD = re.compile(r"[XYZABCUVW]\s*[-+]?[0-9.#\[]", re.IGNORECASE)
COMMENT = re.compile(r"\([^)]*\)|;.*")


def mode_words(mode):
    """`P0.01` -> `G64 P0.01`; `G61`, `G61.1`, `G64` as they are."""
    if re.fullmatch(r"P[0-9.]+", mode):
        return f"G64 {mode}"
    if mode in ("G61", "G61.1", "G64"):
        return mode
    sys.exit(f"linuxcnc_cam_table.py: unknown mode {mode!r} (P<tol>, G61, G61.1 or G64)")


def source_of(name):
    """programs/NAME.nc for a bare project name, else programs/NAME (or NAME as a path)."""
    if "/" not in name and "." not in name:
        return os.path.join(TOP, "programs", f"{name}.nc"), True
    path = name if os.path.exists(name) else os.path.join(TOP, "programs", name)
    return path, False


def code_sub(line, pattern, repl):
    """pattern replaced by repl in the code of line, comments left as they are."""
    out, at = [], 0
    for m in COMMENT.finditer(line):
        out += [pattern.sub(repl, line[at:m.start()]), m.group(0)]
        at = m.end()
    out.append(pattern.sub(repl, line[at:]))
    return "".join(out)


def with_mode_public(lines, mode):
    """The public-program rule (docstring): own modes out, the mode before the first axis word,
    its P in inches ([tol/25.4]) when the preamble sets G20."""
    out, done, inch = [], False, False
    for ln in lines:
        ln = code_sub(ln, OWN_MODE, "")
        code = COMMENT.sub("", ln)
        inch = inch or bool(re.search(r"G0*20(?![0-9.])", code, re.IGNORECASE))
        if not done and AXIS_WORD.search(code):
            words = mode_words(mode)
            if inch and mode.startswith("P"):
                words = f"G64 P[{mode[1:]}/25.4]"
            eol = "\r\n" if ln.endswith("\r\n") else "\n"
            out.append(words + eol)
            done = True
        out.append(ln)
    if not done:
        sys.exit("linuxcnc_cam_table.py: a program without an axis word")
    return out


def write_program(name, mode, tmp):
    """The program NAME in MODE (see the docstring), written to tmp; its path."""
    src, project = source_of(name)
    words = mode_words(mode)
    lines = open(src, newline="").readlines()
    if project:
        out, done = [], False
        for ln in lines:
            if not done and ln.startswith("G21") and MODE.search(ln):
                ln, done = MODE.sub(words, ln, count=1), True
            out.append(ln)
        if not done:
            sys.exit(f"linuxcnc_cam_table.py: no G64/G61 on the G21 line of {name}.nc")
    else:
        out = with_mode_public(lines, mode)
    stem = os.path.splitext(os.path.basename(src))[0]
    path = os.path.join(tmp, f"{stem}-{mode}.ngc")
    with open(path, "w", newline="") as f:
        f.writelines(out)
    return path


def run_gmotion(gm, prog, machine):
    """Cycle time, worst contour error (mm, every sample) and samples over P, servo off, on the
    machine file `machine` (headless.gmotion_machine)."""
    with tempfile.NamedTemporaryFile(suffix=".json") as js:
        subprocess.run([gm, "run", prog, "--no-servo", "--machine", machine, "--summary-json",
                        js.name], capture_output=True, check=True)
        d = json.load(open(js.name))
    tol = d.get("tolerance", {})
    over = sum(tol.get(k, {}).get("over", 0) for k in ("cutting", "rapids")) if tol else None
    return d["cycle_time_s"], d["contour_err_max_blu"]["value"] * 1e-3, over  # BLU 1 µm


def linuxcnc_cell(a, prog, segs, acc, tmp, label, notes, counter):
    """Median time and worst error of `--repeat` LinuxCNC runs (retried when one times out)."""
    ms = []
    for _ in range(a.repeat):
        for attempt in range(3):  # a loaded machine can time a session out
            counter[0] += 1
            try:
                r, info = headless.run_linuxcnc(prog, acc, os.path.join(tmp, f"run{counter[0]}"),
                                                a.max_override)
                m = headless.measure(r, info, segs)
                break
            except (SystemExit, subprocess.TimeoutExpired) as e:
                print(f"{label} a {acc:g}: {e}; attempt {attempt + 1} of 3", file=sys.stderr)
                if attempt == 2:
                    raise
        ms.append(m)
        at = " ".join(f"{x:.3f}" for x in m["err_at_mm"])
        print(f"{label} a {acc:g}: {m['cycle_s']:.3f} s {m['err_mm']:.4f} mm (at {at}, "
              f"{m['err_at_s']:.3f} s) gaps {m['gaps']} overruns {m['overruns']} "
              f"{m['errors'] or ''}",
              file=sys.stderr, flush=True)
        if m["gaps"] or m["overruns"] or m["errors"]:
            notes.append(f"{label} a {acc:g}: {m}")
    ts = [m["cycle_s"] for m in ms]
    return ms[0]["version"], f"{statistics.median(ts):.3f} s, {max(m['err_mm'] for m in ms):.4f} mm"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--modes", nargs="+", default=None,
                    help="P<tol> (G64 P<tol>), G61, G64 (no P), G61.1; default " + " ".join(MODES))
    ap.add_argument("--tol", type=float, nargs="+", help="the same as --modes P<tol> ...")
    ap.add_argument("--accel", type=float, nargs="+", default=[610, 1750])
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--programs", nargs="+", default=PUBLIC + PROJECT,
                    help="project names (programs/NAME.nc) or paths under programs/")
    ap.add_argument("--no-g611", action="store_true", help="leave out the gmotion G61.1 column")
    ap.add_argument("--gmotion", default=os.path.join(TOP, "build", "bin", "gmotion"))
    ap.add_argument("--max-override", type=float, default=100.0,
                    help="the largest feed override both planners plan for, percent")
    ap.add_argument("--tau", type=float, default=None,
                    help="gmotion's Acc/Dec filter length, s (default the built-in machine's "
                    "0.164; its mean ramp acceleration to 100 mm/s is 100/tau mm/s2)")
    a = ap.parse_args()
    modes = a.modes or ([f"P{t:g}" for t in a.tol] if a.tol else MODES)
    for m in modes:
        mode_words(m)
    for tool in ("linuxcnc", "halsampler", "rtapi_app", "milltask"):
        if not shutil.which(tool):
            sys.exit(f"linuxcnc_cam_table.py: LinuxCNC is missing ({tool} not on PATH); install "
                     "linuxcnc-uspace (tools/install-deps.sh --with-oracle)")
    if subprocess.run(["/usr/bin/python3", "-c", "import linuxcnc, hal"]).returncode:
        sys.exit("linuxcnc_cam_table.py: LinuxCNC's Python modules do not load in /usr/bin/python3")
    if subprocess.run(["pgrep", "-x", "rtapi_app"], capture_output=True).returncode == 0:
        sys.exit("linuxcnc_cam_table.py: another LinuxCNC (rtapi_app) is running; run one at a time")
    if os.geteuid() != 0:
        sys.exit("linuxcnc_cam_table.py: LinuxCNC's uspace rtapi_app needs root here")
    if not os.access(a.gmotion, os.X_OK):
        sys.exit(f"linuxcnc_cam_table.py: no gmotion at {a.gmotion} (build it, or --gmotion PATH)")
    tmp = tempfile.mkdtemp(prefix="lcnc-cam.")
    os.chmod(tmp, 0o755)
    rows, notes, counter, version = [], [], [0], ""
    machine = headless.gmotion_machine(a.max_override, tmp, a.tau)
    for name in a.programs:
        label = os.path.basename(source_of(name)[0])
        if not a.no_g611:
            st, se, _ = run_gmotion(a.gmotion, write_program(name, "G61.1", tmp), machine)
            stop = f" {st:.3f} s |"
        for mode in modes:
            prog = write_program(name, mode, tmp)
            segs = headless.path_of(a.gmotion, prog)
            cells = []
            for acc in a.accel:
                v, cell = linuxcnc_cell(a, prog, segs, acc, tmp, f"{label} {mode}", notes, counter)
                version = version or v
                cells.append(cell)
            gt, ge, over = run_gmotion(a.gmotion, prog, machine)
            cells.append(f"{gt:.3f} s, {ge:.4f} mm, " + ("-" if over is None else f"{over} over"))
            rows.append(f"| {label} | {mode} | " + " | ".join(cells) + " |"
                        + ("" if a.no_g611 else stop))
            print(rows[-1], file=sys.stderr, flush=True)
    print(f"\nLinuxCNC {version}, servo 1 ms, median of {a.repeat} run(s); "
          "gmotion run --no-servo --check-tolerance; both planned for overrides up to "
          f"{a.max_override:g} %" + ("" if a.tau is None else f"; gmotion's tau {a.tau:g} s")
          + "\n")
    print("| program | mode | " + " | ".join(f"LinuxCNC a {acc:g}: time, error" for acc in a.accel)
          + " | gmotion: time, error, samples over P |"
          + ("" if a.no_g611 else " gmotion G61.1: time |"))
    print("|" + " --- |" * (3 + len(a.accel) + (0 if a.no_g611 else 1)))
    print("\n".join(rows))
    for x in notes:
        print("note:", x)
    shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
