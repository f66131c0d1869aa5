#!/usr/bin/env python3
"""A random tangent chain of G1 lines and G2/G3 arcs whose feeds change from block to block.

The tolerance planner's property sweeps keep one feed per shape; CAM output changes the feed
between a lead-in, a fillet and a plunge. This writes one program: G64 P (0.005 to 0.05 mm), 4
to 12 blocks, lines of 0.5 to 20 mm and arcs of R 0.3 to 20 mm turning 0.1 to 3 rad, each at a
feed from F100 to F9000, tangent to the block before, with a small kink (up to 0.05 rad) now
and then. docs/tolerance.md ("A fast arc ending into a crawling block") ran 450 of them:

  for i in $(seq 1 450); do python3 tools/gen_feed_chain.py $i > c.nc
    gmotion run c.nc --no-servo --check-tolerance --summary-json s.json || echo "seed $i"; done

Usage: tools/gen_feed_chain.py SEED  (the program on stdout)
"""
import math
import random
import sys


def chain(seed):
    rng = random.Random(seed)
    p = rng.choice([0.005, 0.01, 0.02, 0.05])
    x = y = heading = 0.0
    out = [f"G21 G90 G17 G64 P{p}", "G1 X0 Y0 F1000"]
    for _ in range(rng.randint(4, 12)):
        feed = rng.choice([100, 300, 600, 1200, 3000, 6000, 9000])
        if rng.random() < 0.5:
            length = rng.uniform(0.5, 20)
            x += length * math.cos(heading)
            y += length * math.sin(heading)
            out.append(f"G1 X{x:.4f} Y{y:.4f} F{feed}")
        else:
            r = rng.choice([0.3, 0.5, 1, 2, 5, 10, 20]) * rng.uniform(0.8, 1.2)
            ccw = rng.random() < 0.5
            sweep = rng.uniform(0.1, 3.0)
            sign = 1 if ccw else -1
            cx, cy = x - sign * r * math.sin(heading), y + sign * r * math.cos(heading)
            a1 = math.atan2(y - cy, x - cx) + sign * sweep
            nx, ny = cx + r * math.cos(a1), cy + r * math.sin(a1)
            out.append(f"{'G3' if ccw else 'G2'} X{nx:.4f} Y{ny:.4f} "
                       f"I{cx - x:.4f} J{cy - y:.4f} F{feed}")
            x, y = nx, ny
            heading += sign * sweep
        if rng.random() < 0.15:
            heading += rng.uniform(-0.05, 0.05)
    out.append("M2")
    return "\n".join(out)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    print(chain(int(sys.argv[1])))
