#!/usr/bin/python3
"""An arc under G64 P with and without pre-compensation, for the README and docs/tolerance.md.

  plot_arc_precomp.py LABEL=TRACE.csv [LABEL=TRACE.csv ...] --centre X,Y --radius R --line N
                      --tolerance P -o out.png

For each gmotion CSV trace (servo off: the table is the Acc/Dec output), the contour error
(signed radial on arcs, + outside) against time, and the commanded radius (x_cmd, y_cmd) less R on
the samples of source line N (the arc), dashed; left the whole run, right zoomed to ±3P with the
band ±P in grey.
"""
import argparse
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path, line_no, cx, cy, r):
    blu, period, names = 0.001, 0.004, None
    t, ref, cmd, tc = [], [], [], []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                if line.startswith("# blu_mm:"):
                    blu = float(line.split(":", 1)[1].strip().split(",")[0])
                if line.startswith("# period_s:"):
                    period = float(line.split(":", 1)[1])
                continue
            parts = line.rstrip("\n").split(",")
            if names is None:
                names = parts
                col = {n: i for i, n in enumerate(names)}
                continue
            ts = float(parts[col["t_s"]]) if "t_s" in col else len(t) * period
            t.append(ts)
            ref.append(float(parts[col["contour_err"]]) * blu)
            if int(parts[col["line"]]) == line_no:
                xc, yc = float(parts[col["x_cmd"]]) * blu, float(parts[col["y_cmd"]]) * blu
                tc.append(ts)
                cmd.append(math.hypot(xc - cx, yc - cy) - r)
    return t, ref, tc, cmd


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("traces", nargs="+")
    ap.add_argument("--centre", default="0,0")
    ap.add_argument("--radius", type=float, required=True)
    ap.add_argument("--line", type=int, required=True)
    ap.add_argument("--tolerance", type=float, required=True)
    ap.add_argument("--title", default="")
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    cx, cy = (float(v) for v in a.centre.split(","))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax in axes:
        ax.axhspan(-a.tolerance, a.tolerance, color="0.9", label=f"±P = ±{a.tolerance:g} mm")
    for spec in a.traces:
        label, path = spec.split("=", 1)
        t, ref, tc, cmd = read(path, a.line, cx, cy, a.radius)
        for ax in axes:
            (h,) = ax.plot(t, ref, lw=1.4, label=f"{label}: contour error")
            if any(abs(c) > 1e-6 for c in cmd):
                ax.plot(tc, cmd, lw=1, ls="--", color=h.get_color(),
                        label=f"{label}: commanded radius − R")
    axes[1].set_ylim(-3 * a.tolerance, 3 * a.tolerance)
    for ax in axes:
        ax.set_xlabel("t, s")
    axes[0].set_ylabel("mm")
    axes[0].set_title(a.title, fontsize=10)
    axes[1].set_title(f"zoomed to ±{3 * a.tolerance:g} mm", fontsize=10)
    axes[1].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(a.output, dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
