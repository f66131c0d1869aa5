#!/usr/bin/python3
"""Cycle time and contour error of LinuxCNC's own planner (headless uspace) against gmotion's.

Runs the 20 mm square at F6000 and programs/corners.nc under several G64 P / G61 on a sim XYZ
machine (sim.ini.in, sim.hal, display.py here) at each acceleration, samples the commanded
positions every 1 ms servo cycle, and prints a markdown table next to `gmotion run --no-servo`
and the blend-rule model (tools/linuxcnc_blend_estimate.py). Run by hand as root, not in CI:

  /usr/bin/python3 tools/linuxcnc_headless/run.py [--repeat 3] [--accel 610 1750]
      [--max-override 100]

Both planners plan for the same largest feed override (`--max-override`, percent): LinuxCNC's
[DISPLAY]MAX_FEED_OVERRIDE (its planner's maxFeedScale, 1.0 when the INI leaves it out:
src/emc/ini/initraj.cc) and gmotion's `max_override_percent` (a copy of
programs/machines/default.toml, the built-in machine, with that key changed).

"model" is tools/linuxcnc_blend_estimate.py: its blend rules alone, and with the two line
accelerations the runs showed (G61 0.9 a_max, the last G64 line a_max / 2).
"""
import argparse
import json
import math
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(TOP, "tools"))
from linuxcnc_blend_estimate import square_time  # noqa: E402

SQUARE = "G21 G90 G17 {}\nG1 X20 Y0 F6000\nY20\nX0\nY0\nM2\n"  # as tests/planner's kSquare
SQUARE_MODES = [("G64", 1e9),  # no P: the model with unbounded P
                ("G64 P1", 1), ("G64 P0.3", 0.3), ("G64 P0.1", 0.1),
                ("G64 P0.03", 0.03), ("G64 P0.01", 0.01), ("G64 P0.003", 0.003), ("G61", 0.0),
                ("G61.1", 0.0)]  # G61.1, exact stop: no kink reduction, the rules alone
CORNER_MODES = ["G64 P0.02", "G64 P0.1", "G61", "G64"]


def programs(tmp):
    """(name, path, model tolerance or None) for every program, written to tmp."""
    out = []
    for mode, tol in SQUARE_MODES:
        p = os.path.join(tmp, f"square {mode}.ngc".replace(" ", "_"))
        with open(p, "w") as f:
            f.write(SQUARE.format(mode))
        out.append((f"square {mode}", p, tol))
    text = open(os.path.join(TOP, "programs", "corners.nc")).read()
    for mode in CORNER_MODES:
        p = os.path.join(tmp, f"corners {mode}.ngc".replace(" ", "_"))
        with open(p, "w") as f:
            f.write(text.replace("G21 G17 G90 G64 P0.02", "G21 G17 G90 " + mode, 1))
        out.append((f"corners {mode}", p, None))
    return out


# The in-plane axes (u, v) and the normal w of each arc plane, u x v = +w (G17, G18, G19).
PLANE_AXES = {"XY": (0, 1, 2), "XZ": (2, 0, 1), "YZ": (1, 2, 0)}


def path_of(gm, prog):
    """Programmed path from `gmotion moves`: ('L', a, b) or ('A', a, b, c, ccw, plane)."""
    moves = subprocess.run([gm, "moves", prog], capture_output=True, text=True, check=True)
    pos, segs = (0.0, 0.0, 0.0), []
    for ln in moves.stdout.splitlines():
        m = json.loads(ln)
        if "end" not in m:
            continue
        end = tuple(m["end"][:3])
        if m["kind"] == "arc":
            plane = m.get("plane", "XY")
            assert plane in PLANE_AXES and m.get("turns", 1) == 1, m
            segs.append(("A", pos, end, tuple(m["center"][:3]), m["dir"] == "ccw", plane))
        elif end != pos:
            segs.append(("L", pos, end))
        pos = end
    return segs


def dist(p, s):
    """Distance from point p to segment s (line, or arc in its plane; a helix's axial part
    measured from the height it has at p's angle)."""
    return float(dists(np.array([p], dtype=float), s)[0])


def dists(pts, s):
    """dist() of every row of the N x 3 array pts to segment s, vectorised."""
    if s[0] == "L":
        a, b = np.array(s[1]), np.array(s[2])
        d = b - a
        t = np.clip((pts - a) @ d / (d @ d), 0.0, 1.0)
        return np.linalg.norm(pts - (a + t[:, None] * d), axis=1)
    _, a, b, c, ccw, plane = s
    u, v, w = PLANE_AXES[plane]
    r = math.hypot(a[u] - c[u], a[v] - c[v])
    t0 = math.atan2(a[v] - c[v], a[u] - c[u])
    sweep = (math.atan2(b[v] - c[v], b[u] - c[u]) - t0) % (2 * math.pi) or 2 * math.pi
    ang = np.arctan2(pts[:, v] - c[v], pts[:, u] - c[u]) - t0
    ang = ang % (2 * math.pi) if ccw else (-ang) % (2 * math.pi)
    if not ccw:
        sweep = (2 * math.pi - sweep) % (2 * math.pi) or 2 * math.pi
    radial = np.hypot(pts[:, u] - c[u], pts[:, v] - c[v]) - r
    axial = pts[:, w] - (a[w] + (b[w] - a[w]) * np.minimum(ang / sweep, 1.0))
    ends = np.minimum(np.linalg.norm(pts - np.array(a), axis=1),
                      np.linalg.norm(pts - np.array(b), axis=1))
    return np.where(ang <= sweep, np.hypot(radial, axial), ends)


def worst_distance(pts, segs):
    """Largest distance of any row of pts to the nearest segment of the path, and that row."""
    best = np.full(len(pts), np.inf)
    for s in segs:
        np.minimum(best, dists(pts, s), out=best)
    k = int(best.argmax())
    return float(best[k]), k


def run_linuxcnc(prog, accel, work, max_override=100.0):
    """One LinuxCNC session in its own HOME and working dir, planned for feed overrides up to
    max_override percent; returns the samples and info."""
    os.makedirs(work)
    os.chmod(work, 0o755)
    home, run, fifo = (os.path.join(work, d) for d in ("home", "run", "rtapi"))
    for d in (home, run, fifo):
        os.makedirs(d)
    os.chown(fifo, 65534, -1)  # rtapi_app creates its socket as RTAPI_UID (nobody)
    ini = open(os.path.join(HERE, "sim.ini.in")).read()
    with open(os.path.join(run, "sim.ini"), "w") as f:
        f.write(ini.replace("@ACCEL@", f"{accel:g}").replace("@DIR@", HERE)
                .replace("@MAX_FEED_OVERRIDE@", f"{max_override / 100.0:g}"))
    with open(os.path.join(run, "tool.tbl"), "w") as f:  # T1 for programs that change to it
        f.write("T1 P1 D6 Z0 ;6 mm end mill, no length\n")
    samples = os.path.join(run, "samples.txt")
    env = dict(os.environ, HOME=home, RTAPI_UID="65534", RTAPI_FIFO_PATH=fifo + "/fifo",
               LCNC_PROGRAM=prog, LCNC_SAMPLES=samples)
    log = os.path.join(work, "linuxcnc.log")
    with open(log, "w") as f:
        r = subprocess.run(["linuxcnc", "-r", "sim.ini"], cwd=run, env=env, stdout=f,
                           stderr=subprocess.STDOUT, timeout=300)
    if r.returncode != 0 or not os.path.exists(samples + ".json"):
        sys.exit(f"linuxcnc failed on {prog} (exit {r.returncode}); see {log}")
    info = json.load(open(samples + ".json"))
    rows = [ln.split() for ln in open(samples) if ln.strip()]
    return rows, info


def measure(rows, info, segs):
    """Cycle time (first to last servo cycle that moves), worst distance to the path, checks."""
    tags = [int(r[0]) for r in rows]
    gaps = sum(1 for a, b in zip(tags, tags[1:]) if b != a + 1)
    pos = [tuple(float(x) for x in r[1:4]) for r in rows]
    moving = [k for k in range(1, len(pos)) if pos[k] != pos[k - 1]]
    if not moving:
        sys.exit(f"run.py: LinuxCNC did not move; errors: {info['errors']}")
    first, last = moving[0], moving[-1]
    worst, at = worst_distance(np.array(pos[first - 1:last + 1]), segs)
    period = [int(r[7]) for r in rows[first:last + 1]]
    med = statistics.median(period)
    step = max(math.dist(pos[k], pos[k - 1]) for k in range(first, last + 1))  # mm per cycle
    still = sum(1 for k in range(first, last) if pos[k + 1] == pos[k])  # resting cycles inside
    return {"still": still, "step_mm": step, "cycle_s": (last - first + 1) * 1e-3,
            "err_mm": worst, "err_at_mm": pos[first - 1 + at],
            "err_at_s": (at - 1) * 1e-3, "gaps": gaps,
            "overruns": int(info["sampler.0.overruns"]), "errors": info["errors"],
            "period_max_ms": max(period) / med, "late_cycles": sum(p > 2 * med for p in period),
            "cycles": last - first + 1, "version": info.get("version", "")}


def gmotion_machine(max_override, tmp, tau_s=None):
    """The built-in machine (programs/machines/default.toml) planned for feed overrides up to
    max_override percent, and with its Acc/Dec filter `tau_s` long when given (its [accdec]
    tau_s, 0.164 s, otherwise), written to tmp; its path."""
    text = open(os.path.join(TOP, "programs", "machines", "default.toml")).read()
    text, n = re.subn(r"(?m)^max_override_percent\s*=\s*[0-9.]+",
                      f"max_override_percent = {max_override:g}", text)
    if n != 1:
        sys.exit("run.py: no max_override_percent line in programs/machines/default.toml")
    if tau_s is not None:
        text, n = re.subn(r"(?m)^tau_s\s*=\s*[0-9.]+", f"tau_s = {tau_s:g}", text)
        if n != 1:
            sys.exit("run.py: no tau_s line in programs/machines/default.toml")
    path = os.path.join(tmp, f"machine-{max_override:g}" +
                        ("" if tau_s is None else f"-tau{tau_s:g}") + ".toml")
    with open(path, "w") as f:
        f.write(text)
    return path


def run_gmotion(gm, prog, machine):
    with tempfile.NamedTemporaryFile(suffix=".json") as js:
        subprocess.run([gm, "run", prog, "--no-servo", "--machine", machine, "--summary-json",
                        js.name], capture_output=True, check=True)
        d = json.load(open(js.name))
    return d["cycle_time_s"], d["contour_err_max_blu"]["value"] * 1e-3  # built-in BLU 1 um


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--accel", type=float, nargs="+", default=[610, 1750])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--gmotion", default=os.path.join(TOP, "build", "bin", "gmotion"))
    ap.add_argument("--only", help="run only programs whose name contains this")
    ap.add_argument("--keep", action="store_true", help="keep the work directory")
    ap.add_argument("--max-override", type=float, default=100.0,
                    help="the largest feed override both planners plan for, percent")
    a = ap.parse_args()
    for tool in ("linuxcnc", "halsampler", "rtapi_app", "milltask"):
        if not shutil.which(tool):
            sys.exit(f"run.py: LinuxCNC is missing ({tool} not on PATH); install linuxcnc-uspace "
                     "(tools/install-deps.sh --with-oracle)")
    if subprocess.run(["/usr/bin/python3", "-c", "import linuxcnc, hal"]).returncode:
        sys.exit("run.py: LinuxCNC's Python modules do not load in /usr/bin/python3")
    if subprocess.run(["pgrep", "-x", "rtapi_app"], capture_output=True).returncode == 0:
        sys.exit("run.py: another LinuxCNC (rtapi_app) is running; HAL is shared, run one at a time")
    if os.geteuid() != 0:
        sys.exit("run.py: LinuxCNC's uspace rtapi_app needs root here (run as root)")
    if not os.access(a.gmotion, os.X_OK):
        sys.exit(f"run.py: no gmotion at {a.gmotion} (build it, or --gmotion PATH)")
    tmp = tempfile.mkdtemp(prefix="lcnc-headless.")
    os.chmod(tmp, 0o755)
    progs = [p for p in programs(tmp) if not a.only or a.only in p[0]]
    machine = gmotion_machine(a.max_override, tmp)
    res, notes, n = {}, [], 0
    for name, prog, tol in progs:
        segs = path_of(a.gmotion, prog)
        for acc in a.accel:
            for k in range(a.repeat):
                n += 1
                rows, info = run_linuxcnc(prog, acc, os.path.join(tmp, f"run{n}"),
                                          a.max_override)
                m = measure(rows, info, segs)
                res.setdefault((name, acc), []).append(m)
                print(f"{name:18} a {acc:g}: {m['cycle_s']:.3f} s  {m['err_mm']:.4f} mm  "
                      f"still {m['still']} gaps {m['gaps']} overruns {m['overruns']} "
                      f"late {m['late_cycles']} max period {m['period_max_ms']:.1f} ms "
                      f"{m['errors'] or ''}",
                      file=sys.stderr, flush=True)
    version = next(iter(res.values()))[0]["version"]
    hdr = "| program | " + " | ".join(
        f"LinuxCNC a {acc:g}: time (spread), error | model a {acc:g}: rules / +measured"
        for acc in a.accel) + " | gmotion: time, error |"
    print(f"\nLinuxCNC {version}, servo 1 ms, {a.repeat} runs each; gmotion run --no-servo; "
          f"both planned for overrides up to {a.max_override:g} %\n")
    print(hdr)
    print("|" + " --- |" * (2 + 2 * len(a.accel)))
    for name, prog, tol in progs:
        cells = []
        for acc in a.accel:
            ms = res[(name, acc)]
            ts = [m["cycle_s"] for m in ms]
            es = [m["err_mm"] for m in ms]
            spread = f"{max(ts) - min(ts):.3f}" if len(ts) > 1 else "-"
            cells.append(f"{statistics.median(ts):.3f} s ({spread}), {max(es):.4f} mm")
            notes += [f"{name} a {acc:g}: {m}" for m in ms
                      if m["gaps"] or m["overruns"] or m["errors"]]
            if tol is None:
                cells.append("-")
            else:
                kink = not name.endswith("G61.1")
                rules, meas = (square_time(20, 6000, acc, tol, as_measured=x)[0]
                               for x in (False, kink))
                cells.append(f"{rules:.3f} / {meas:.3f} s")
        gt, ge = run_gmotion(a.gmotion, prog, machine)
        cells.append(f"{gt:.3f} s, {ge:.4f} mm")
        print(f"| {name} | " + " | ".join(cells) + " |")
    all_m = [m for ms in res.values() for m in ms]
    print(f"\nsampler gaps {sum(m['gaps'] for m in all_m)}, overruns "
          f"{sum(m['overruns'] for m in all_m)}; servo cycles later than 2 ms: "
          f"{sum(m['late_cycles'] for m in all_m)} of {sum(m['cycles'] for m in all_m)}, "
          f"longest wall-clock period {max(m['period_max_ms'] for m in all_m):.1f} ms; largest "
          f"step per sample {max(m['step_mm'] for m in all_m):.4f} mm (100 mm/s x 1 ms = 0.1)")
    for x in notes:
        print("note:", x)
    if a.keep:
        print(f"work directory kept: {tmp}")
    else:
        shutil.rmtree(tmp)


if __name__ == "__main__":
    main()
