#!/usr/bin/python3
"""LinuxCNC's planner against gmotion's on the CAM-style programs, at the same G64 P.

Runs programs/cam-fillets.nc, cam-slot.nc, corners.nc, small-arcs.nc and pocket.nc, their mode
(G64 [P..] or G61 on the G21 line) replaced by each `--tol` (G64 P0.01 and G64 P0.05 by default),
through LinuxCNC 2.9 headless (tools/linuxcnc_headless: sim XYZ machine, servo 1 ms, every
MAX_VELOCITY 100 mm/s = gmotion's rapid, MAX_ACCELERATION each `--accel`: 610 mm/s² is the mean
acceleration of gmotion's FIR ramp to 100 mm/s, 1750 its peak) and through `gmotion run
--no-servo --check-tolerance`, and prints a Markdown table: cycle time and worst distance of the
commanded (LinuxCNC) or Acc/Dec output (gmotion) position from the programmed path, every sample.
Run by hand as root, one LinuxCNC at a time, not in CI (about 5 minutes):

  /usr/bin/python3 tools/linuxcnc_cam_table.py [--tol 0.01 0.05] [--accel 610 1750] [--repeat 1]

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

PROGRAMS = ["cam-fillets", "cam-slot", "corners", "small-arcs", "pocket"]
MODE = re.compile(r"G64( P[0-9.]+)?|G61(\.1)?")


def write_program(name, tol, tmp):
    """programs/NAME.nc with the mode on its G21 line replaced by `G64 P<tol>`."""
    out, done = [], False
    for ln in open(os.path.join(TOP, "programs", f"{name}.nc")):
        if not done and ln.startswith("G21") and MODE.search(ln):
            ln, done = MODE.sub(f"G64 P{tol:g}", ln, count=1), True
        out.append(ln)
    if not done:
        sys.exit(f"linuxcnc_cam_table.py: no G64/G61 on the G21 line of {name}.nc")
    path = os.path.join(tmp, f"{name}-P{tol:g}.ngc")
    with open(path, "w") as f:
        f.writelines(out)
    return path


def run_gmotion(gm, prog):
    """Cycle time, worst contour error (mm, every sample) and samples over P, servo off."""
    with tempfile.NamedTemporaryFile(suffix=".json") as js:
        subprocess.run([gm, "run", prog, "--no-servo", "--summary-json", js.name],
                       capture_output=True, check=True)
        d = json.load(open(js.name))
    tol = d.get("tolerance", {})
    over = sum(tol.get(k, {}).get("over", 0) for k in ("cutting", "rapids"))
    return d["cycle_time_s"], d["contour_err_max_blu"]["value"] * 1e-3, over  # BLU 1 µm


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tol", type=float, nargs="+", default=[0.01, 0.05])
    ap.add_argument("--accel", type=float, nargs="+", default=[610, 1750])
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--programs", nargs="+", default=PROGRAMS)
    ap.add_argument("--gmotion", default=os.path.join(TOP, "build", "bin", "gmotion"))
    a = ap.parse_args()
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
    rows, notes, n, version = [], [], 0, ""
    for name in a.programs:
        for tol in a.tol:
            prog = write_program(name, tol, tmp)
            segs = headless.path_of(a.gmotion, prog)
            cells = []
            for acc in a.accel:
                ms = []
                for _ in range(a.repeat):
                    for attempt in range(3):  # a loaded machine can time a session out
                        n += 1
                        try:
                            r, info = headless.run_linuxcnc(prog, acc,
                                                            os.path.join(tmp, f"run{n}"))
                            m = headless.measure(r, info, segs)
                            break
                        except SystemExit as e:
                            print(f"{e}; attempt {attempt + 1} of 3", file=sys.stderr)
                            if attempt == 2:
                                raise
                    version = version or m["version"]
                    ms.append(m)
                    print(f"{name} P{tol:g} a {acc:g}: {m['cycle_s']:.3f} s {m['err_mm']:.4f} mm "
                          f"gaps {m['gaps']} overruns {m['overruns']} {m['errors'] or ''}",
                          file=sys.stderr, flush=True)
                    if m["gaps"] or m["overruns"] or m["errors"]:
                        notes.append(f"{name} P{tol:g} a {acc:g}: {m}")
                ts = [m["cycle_s"] for m in ms]
                cells.append(f"{statistics.median(ts):.3f} s, {max(m['err_mm'] for m in ms):.4f} mm")
            gt, ge, over = run_gmotion(a.gmotion, prog)
            cells.append(f"{gt:.3f} s, {ge:.4f} mm, {over} over")
            rows.append(f"| {name}.nc | P{tol:g} | " + " | ".join(cells) + " |")
    print(f"\nLinuxCNC {version}, servo 1 ms, median of {a.repeat} run(s); "
          "gmotion run --no-servo --check-tolerance\n")
    print("| program | G64 | " + " | ".join(f"LinuxCNC a {acc:g}: time, error" for acc in a.accel)
          + " | gmotion: time, error, samples over P |")
    print("|" + " --- |" * (3 + len(a.accel)))
    print("\n".join(rows))
    for x in notes:
        print("note:", x)
    shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
