#!/usr/bin/python3
"""Plots of gmotion traces and Acc/Dec profiles (PNG, matplotlib; Debian python3-matplotlib).

  plot_trace.py path TRACE.csv -o path.png [--magnify K]
      XY path, command against actual, and a ballbar view: the contour error magnified K times
      around the programmed path (for circles: radius error against angle, polar).
  plot_trace.py radius TRACE.csv [TRACE.csv ...] [--labels a,b,...] -o fig13.png
      radius error (contour_err, BLU) against angle for circle tests, several traces in one
      plot (the paper's Fig. 13: the same circle through several profiles).
  plot_trace.py motion TRACE.csv -o motion.png
      per-axis velocity, acceleration and jerk of the Acc/Dec output against time.
  plot_trace.py response --gmotion build/bin/gmotion [--profiles P1,P2,...]
                [--tau 0.164] [--period 0.004] -o fig12.png
      taps and amplitude response of the profiles (the paper's Fig. 11/12).

Traces may be CSV or binary (read by tools/gmtrace.py, with the schema of
src/trace/trace_columns.def).
"""
import argparse
import json
import math
import os
import subprocess
import sys


sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gmtrace  # noqa: E402  (the trace schema and reader)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_trace(path):
    """Returns (header dict, columns dict of lists of floats); CSV or binary (tools/gmtrace.py)."""
    return gmtrace.read_columns(path)


def blu_mm(header):
    return [float(x) for x in header.get("blu_mm", "0.001,0.001,0.001").split(",")]


def centre(cols):
    """Centre of a circle test: the middle of the commanded X/Y range (BLU)."""
    xs, ys = cols["x_cmd"], cols["y_cmd"]
    return (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2


def angle_deg(cols, cx, cy):
    return [math.degrees(math.atan2(y - cy, x - cx)) % 360 for x, y in zip(cols["x_enc"], cols["y_enc"])]


def plot_path(args):
    header, c = read_trace(args.trace)
    b = blu_mm(header)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5.2))
    ax1.plot([x * b[0] for x in c["x_cmd"]], [y * b[1] for y in c["y_cmd"]], lw=0.8, label="command (interpolator)")
    ax1.plot([x * b[0] for x in c["x_enc"]], [y * b[1] for y in c["y_enc"]], lw=0.8, ls="--", label="actual (encoder)")
    ax1.set_xlabel("X [mm]")
    ax1.set_ylabel("Y [mm]")
    ax1.set_aspect("equal", adjustable="datalim")
    ax1.legend(loc="best", fontsize=8)
    ax1.set_title("XY path")
    # Ballbar view: the nominal radius plus the contour error magnified K times, polar.
    cx, cy = centre(c)
    r_nom = max(max(c["x_cmd"]) - min(c["x_cmd"]), max(c["y_cmd"]) - min(c["y_cmd"])) / 2
    ax2.remove()
    ax2 = fig.add_subplot(1, 2, 2, projection="polar")
    # Only the samples on the circle (a rapid to the start point is not part of a ballbar test).
    on = [(math.atan2(y - cy, x - cx), r_nom + args.magnify * e)
          for x, y, e in zip(c["x_enc"], c["y_enc"], c["contour_err"])
          if abs(math.hypot(x - cx, y - cy) - r_nom) < 0.5 * r_nom]
    ax2.plot([p[0] for p in on], [p[1] for p in on], lw=0.8, label=f"actual, error x{args.magnify:g}")
    spread = max([abs(p[1] - r_nom) for p in on] + [1.0])
    ax2.set_rlim(max(0.0, r_nom - 1.3 * spread), r_nom + 0.6 * spread)
    ax2.plot([i * 2 * math.pi / 360 for i in range(361)], [r_nom] * 361, lw=0.6, color="grey", label="programmed radius")
    ax2.set_title(f"ballbar view: radius {r_nom:.0f} BLU, contour error magnified x{args.magnify:g}", fontsize=9)
    ax2.legend(loc="lower left", fontsize=7)
    fig.suptitle(f"{header.get('program', '')} — {header.get('profile', '')}", fontsize=9)
    fig.tight_layout()
    fig.savefig(args.output, dpi=args.dpi)


def plot_radius(args):
    labels = args.labels.split(",") if args.labels else args.traces
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for path, label in zip(args.traces, labels):
        header, c = read_trace(path)
        cx, cy = centre(c)
        ang = angle_deg(c, cx, cy)
        # Only the samples on the circle (the rapid to the start is not part of the test).
        r_nom = max(max(c["x_cmd"]) - min(c["x_cmd"]), max(c["y_cmd"]) - min(c["y_cmd"])) / 2
        pts = [(a, e) for a, e, x, y in zip(ang, c["contour_err"], c["x_enc"], c["y_enc"])
               if abs(math.hypot(x - cx, y - cy) - r_nom) < 0.5 * r_nom]
        pts.sort()
        ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", ms=2, label=label)
    ax.set_xlabel("angle [deg]")
    ax.set_ylabel("radius error [BLU]")
    ax.set_xlim(0, 360)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, markerscale=4)
    ax.set_title(args.title, fontsize=10)
    fig.tight_layout()
    fig.savefig(args.output, dpi=args.dpi)


def diff(v, t):
    return [0.0] + [(v[i] - v[i - 1]) / t for i in range(1, len(v))]


def plot_motion(args):
    header, c = read_trace(args.trace)
    b = blu_mm(header)
    t = c["t_s"]
    T = t[1] - t[0] if len(t) > 1 else float(header.get("period_s", "0.004"))
    fig, axes = plt.subplots(3, 1, figsize=(9, 7.5), sharex=True)
    # Every axis of the trace, in its order (x, y, z, then a, b, c in degrees, u, v, w).
    letters = [n[0] for n in c if len(n) == 5 and n.endswith("_ref")]
    for i, a in enumerate(letters):
        pos = [p * b[i] for p in c[f"{a}_ref"]]
        v = diff(pos, T)
        acc = diff(v, T)
        jerk = diff(acc, T)
        axes[0].plot(t, v, lw=0.8, label=a.upper())
        axes[1].plot(t, acc, lw=0.8, label=a.upper())
        axes[2].plot(t, jerk, lw=0.8, label=a.upper())
    for ax, unit in zip(axes, ["velocity [mm/s, deg/s]", "acceleration [mm/s², deg/s²]",
                               "jerk [mm/s³, deg/s³]"]):
        ax.set_ylabel(unit)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    axes[2].set_xlabel("time [s]")
    fig.suptitle(f"Acc/Dec output per axis — {header.get('program', '')}, {header.get('profile', '')}", fontsize=9)
    fig.tight_layout()
    fig.savefig(args.output, dpi=args.dpi)


def paper_profiles(gmotion):
    """The paper's profiles, from gmotion's profile registry (`design --list-profiles`)."""
    out = subprocess.run([gmotion, "design", "--list-profiles"], check=True, capture_output=True,
                         text=True).stdout
    return [line.split("\t")[0] for line in out.splitlines() if line.split("\t")[2] == "paper"]


def plot_response(args):
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    profiles = args.profiles.split(",") if args.profiles else paper_profiles(args.gmotion)
    for p in profiles:
        out = subprocess.run([args.gmotion, "analyze", "response", "--profile", p, "--tau", str(args.tau),
                              "--period", str(args.period), "--points", "400", "--json"],
                             check=True, capture_output=True, text=True).stdout
        d = json.loads(out)
        ax1.plot(range(len(d["taps"])), d["taps"], ".-", ms=3, lw=0.8, label=p)
        ax2.plot([r["f_hz"] for r in d["response"]], [r["amplitude"] for r in d["response"]], lw=0.9, label=p)
    ax1.set_xlabel("tap i")
    ax1.set_ylabel("b_i / b_s")
    ax1.set_title(f"taps (tau = {args.tau} s, T = {args.period} s)", fontsize=10)
    ax2.set_xlabel("frequency [Hz]")
    ax2.set_ylabel("|D(e^{jωT})|")
    ax2.set_xlim(0, 40)
    ax2.set_title("amplitude response", fontsize=10)
    for ax in (ax1, ax2):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=args.dpi)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("path")
    p.add_argument("trace")
    p.add_argument("--magnify", type=float, default=20.0)
    r = sub.add_parser("radius")
    r.add_argument("traces", nargs="+")
    r.add_argument("--labels")
    r.add_argument("--title", default="radius error against angle")
    m = sub.add_parser("motion")
    m.add_argument("trace")
    s = sub.add_parser("response")
    s.add_argument("--gmotion", default="build/bin/gmotion")
    s.add_argument("--profiles", default="", help="comma-separated; default: the paper's four (from gmotion)")
    s.add_argument("--tau", type=float, default=0.164)
    s.add_argument("--period", type=float, default=0.004)
    for q in (p, r, m, s):
        q.add_argument("-o", "--output", required=True)
        q.add_argument("--dpi", type=int, default=100)
    args = ap.parse_args()
    {"path": plot_path, "radius": plot_radius, "motion": plot_motion, "response": plot_response}[args.cmd](args)


if __name__ == "__main__":
    main()
