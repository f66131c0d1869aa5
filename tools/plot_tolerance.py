#!/usr/bin/python3
"""The square's corners with and without a contour tolerance (G64 P), for docs/tolerance.md.

  plot_tolerance.py LABEL=TRACE.csv [LABEL=TRACE.csv ...] --corner X,Y --zoom MM -o out.png

Left: the whole XY path of the Acc/Dec output (x_ref, y_ref) of each trace; right: the same
around one corner, ±MM. Traces are gmotion CSV traces (BLU columns; the header names the BLU).
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_xy(path):
    blu, names, xs, ys = 0.001, None, [], []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                if line.startswith("# blu_mm:"):
                    blu = float(line.split(":", 1)[1].strip().split(",")[0])
                continue
            parts = line.rstrip("\n").split(",")
            if names is None:
                names = parts
                ix, iy = names.index("x_ref"), names.index("y_ref")
                continue
            xs.append(float(parts[ix]) * blu)
            ys.append(float(parts[iy]) * blu)
    return xs, ys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("traces", nargs="+")
    ap.add_argument("--corner", default="20,0")
    ap.add_argument("--zoom", type=float, default=1.2)
    ap.add_argument("--path", default="0,0;20,0;20,20;0,20;0,0", help="programmed path x,y;...")
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    cx, cy = (float(v) for v in a.corner.split(","))
    px, py = zip(*[(float(p.split(",")[0]), float(p.split(",")[1])) for p in a.path.split(";")])
    fig, (full, zoom) = plt.subplots(1, 2, figsize=(9, 4.2))
    for ax in (full, zoom):
        ax.plot(px, py, color="0.6", lw=3, label="programmed")
    for spec in a.traces:
        label, path = spec.split("=", 1)
        xs, ys = read_xy(path)
        full.plot(xs, ys, lw=1, label=label)
        zoom.plot(xs, ys, lw=1.2, marker=".", ms=2, label=label)
    full.set_aspect("equal")
    full.set_title("Acc/Dec output, 20 mm square at F6000")
    zoom.set_xlim(cx - a.zoom, cx + a.zoom * 0.3)
    zoom.set_ylim(cy - a.zoom * 0.3, cy + a.zoom)
    zoom.set_aspect("equal")
    zoom.set_title(f"corner ({cx:g}, {cy:g}), mm")
    zoom.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(a.output, dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
