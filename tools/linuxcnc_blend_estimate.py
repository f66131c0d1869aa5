#!/usr/bin/python3
"""Cycle time of a closed polygon at feed F under LinuxCNC's documented G64 P blend rules
(docs/tolerance.md compares it with gmotion's planner and with LinuxCNC itself, run headless by
tools/linuxcnc_headless/run.py).

Rules used (LinuxCNC 2.9 trajectory planner, circular blend arcs, src/emc/tp/blendmath.h as
documented there): every corner is replaced by a circular arc tangent to both lines whose
distance from the vertex is at most P and whose tangent points use at most half of each line;
the speed on the arc is at most sqrt(a_n * R) with a_n = a_max * sqrt(1 - 0.5^2) (the normal
share of the acceleration); lines run a trapezoidal profile at a_max, starting and ending at rest.

  linuxcnc_blend_estimate.py --side 20 --feed 6000 --accel 1750 --tol 0.01 0.1
"""
import argparse
import math


def seg_time(length, v0, v1, vmax, a):
    """Time for `length` from v0 to v1, speed <= vmax, |accel| <= a (trapezoid or triangle)."""
    vpeak = math.sqrt(a * length + 0.5 * (v0 * v0 + v1 * v1))
    vp = min(vmax, vpeak)
    d_acc = (vp * vp - v0 * v0) / (2 * a)
    d_dec = (vp * vp - v1 * v1) / (2 * a)
    cruise = max(0.0, length - d_acc - d_dec)
    return (vp - v0) / a + (vp - v1) / a + cruise / vp


def square_time(side, feed_mm_min, accel, tol, corners=4, as_measured=False):
    """as_measured adds what the headless run of LinuxCNC 2.9 showed (tools/linuxcnc_headless):
    in G61 every line ramps at (1 - ARC_BLEND_KINK_RATIO) * a_max = 0.9 a_max, and in G64 the
    last line, still marked for a parabolic blend, at a_max / 2."""
    v = feed_mm_min / 60.0
    turn = 2 * math.pi / corners  # exterior angle of a regular polygon
    alpha = math.pi - turn  # interior angle
    k = 1.0 / math.sin(alpha / 2) - 1.0  # vertex-to-arc distance per unit radius
    r = tol / k if tol > 0 else 0.0
    d = r / math.tan(alpha / 2)  # tangent length from the vertex
    d = min(d, side / 2)
    r = d * math.tan(alpha / 2)
    a_n = accel * math.sqrt(1 - 0.25)
    vb = min(v, math.sqrt(a_n * r)) if r > 0 else 0.0
    arc_len = r * turn
    # Path: line, (blend, line) x (corners-1): the closing corner is not blended (path ends).
    t = 0.0
    n_lines = corners
    for i in range(n_lines):
        start_v = 0.0 if i == 0 else vb
        end_v = 0.0 if i == n_lines - 1 else vb
        length = side - (d if i > 0 else 0.0) - (d if i < n_lines - 1 else 0.0)
        a_line = accel
        if as_measured:
            a_line = 0.9 * accel if tol == 0 else (0.5 * accel if i == n_lines - 1 else accel)
        t += seg_time(length, start_v, end_v, v, a_line)
    if vb > 0:
        t += (corners - 1) * arc_len / vb
    return t, r, vb


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--side", type=float, default=20.0)
    ap.add_argument("--feed", type=float, default=6000.0)
    ap.add_argument("--accel", type=float, default=1750.0)
    ap.add_argument("--tol", type=float, nargs="+", default=[0.001, 0.003, 0.01, 0.03, 0.1, 0.3, 1])
    ap.add_argument("--as-measured", action="store_true",
                    help="add LinuxCNC 2.9's G61 0.9 a_max and last-line a_max/2 (measured)")
    a = ap.parse_args()
    print("tol_mm,blend_radius_mm,blend_speed_mm_s,cycle_s")
    t0, _, _ = square_time(a.side, a.feed, a.accel, 0.0, as_measured=a.as_measured)
    print(f"0 (exact stop),0,0,{t0:.3f}")
    for tol in a.tol:
        t, r, vb = square_time(a.side, a.feed, a.accel, tol, as_measured=a.as_measured)
        print(f"{tol:g},{r:.4f},{vb:.2f},{t:.3f}")


if __name__ == "__main__":
    main()
