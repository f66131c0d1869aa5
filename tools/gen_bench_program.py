#!/usr/bin/env python3
"""Seeded generator of the end-to-end benchmark program: N blocks mixing G1 lines and G2/G3 arcs.

The program is what a CAM post-processor writes for 3-axis contouring: short G1 segments
(0.2-2 mm), G2/G3 arcs in IJK form and in R form (radius 0.5-5 mm, sweep up to 171 degrees),
occasional Z steps, feeds between 1200 and 6000 mm/min. Every arc is built from an actual
centre, its end point written with 4 decimals, so its start and end radii agree to 1e-4 mm
(inside every arc tolerance); the position stays inside a 200 mm box. Output is deterministic
for a given seed and block count.

With --long, the moves are long instead (what the block engine's headline figure is measured on):
lines of 20-60 mm and arcs of radius 10-40 mm and at least 20 mm of arc, all at F3000, so every
move takes at least 100 samples at T = 4 ms.

Usage: gen_bench_program.py --blocks N [--long] [--seed S] [-o FILE]   (default: stdout)
"""
from __future__ import annotations

import argparse
import math
import random
import sys

BOX_MM = 100.0  # |x|, |y| stay below this


def fmt(v: float) -> str:
    s = f"{v:.4f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def generate(out, blocks: int, seed: int, long_moves: bool = False) -> None:
    rng = random.Random(seed)
    w = out.write
    line_mm, rad_mm = ((20.0, 60.0), (10.0, 40.0)) if long_moves else ((0.2, 2.0), (0.5, 5.0))
    kind = "long-move " if long_moves else ""
    w(f"(gmotion end-to-end {kind}benchmark: {blocks} blocks, seed {seed})\n")
    w("G21 G90 G17 G94\nG0 X0 Y0 Z5\nG1 Z0 F3000\n")
    x = y = 0.0
    z = 0.0
    n = 3
    while n < blocks - 1:
        r = rng.random()
        if r < 0.02 and not long_moves:  # a Z step with a new feed
            z = round(rng.uniform(-5.0, 0.0), 4)
            w(f"G1 Z{fmt(z)} F{rng.choice((1200, 2400))}\n")
        elif r < 0.60:  # a short line, pulled back towards the middle near the box edge
            ang = rng.uniform(0, 2 * math.pi) if max(abs(x), abs(y)) < BOX_MM else math.atan2(-y, -x)
            d = rng.uniform(*line_mm)
            x, y = round(x + d * math.cos(ang), 4), round(y + d * math.sin(ang), 4)
            feed = f" F{rng.choice((2400, 4000, 6000))}" if rng.random() < 0.05 else ""
            feed = "" if long_moves else feed
            w(f"G1 X{fmt(x)} Y{fmt(y)}{feed}\n")
        else:  # an arc from a real centre
            rad = rng.uniform(*rad_mm)
            a0 = rng.uniform(0, 2 * math.pi) if max(abs(x), abs(y)) < BOX_MM else math.atan2(y, x)
            cx, cy = x - rad * math.cos(a0), y - rad * math.sin(a0)  # centre: start is at angle a0
            ccw = rng.random() < 0.5
            least = 20.0 / rad if long_moves else 0.05  # radians: 20 mm of arc for long moves
            sweep = rng.uniform(least, 0.95 * math.pi) * (1 if ccw else -1)
            a1 = a0 + sweep
            ex, ey = round(cx + rad * math.cos(a1), 4), round(cy + rad * math.sin(a1), 4)
            g = "G3" if ccw else "G2"
            if rng.random() < 0.5:
                w(f"{g} X{fmt(ex)} Y{fmt(ey)} I{fmt(cx - x)} J{fmt(cy - y)}\n")
            else:
                w(f"{g} X{fmt(ex)} Y{fmt(ey)} R{fmt(rad)}\n")  # sweep < 180 degrees: R > 0
            x, y = ex, ey
        n += 1
    w("M2\n")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--blocks", type=int, required=True)
    ap.add_argument("--long", action="store_true", help="long moves (>= 100 samples each)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("-o", "--output", default="-")
    a = ap.parse_args()
    if a.output == "-":
        generate(sys.stdout, a.blocks, a.seed, a.long)
    else:
        with open(a.output, "w", encoding="ascii", buffering=1 << 20) as f:
            generate(f, a.blocks, a.seed, a.long)
    return 0


if __name__ == "__main__":
    sys.exit(main())
