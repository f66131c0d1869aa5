#!/usr/bin/env python3
"""Shaped stops, measured: how much of an exact stop's time a commanded speed profile shaped
for the known filter could win back (docs/tolerance.md, "Not done": a stop costs about tau).

An exact stop through the FIR: the command runs at feed F to the vertex and waits there; the
output (y = h * x) slows over the window and reaches the vertex at rest tau after the command,
losing about tau/2 against running on at F, and as much again starting. LinuxCNC's planner
loses F/(2a) on each side. The filter is linear and known, so the command may be shaped: run
faster than F for a while, slow earlier, so that the output brakes later and harder. This
finds the best such command by a linear programme, per side (a start is a stop reversed):

  variables   w_k, the command's speed at sample k of a horizon of K samples before the output
              rests (F before it; 0 over its last N + 1 samples: the command waits at the
              vertex a whole window, which an exact stop needs, since a window holding samples
              on both sides of the vertex leaves the path);
  subject to  the output's speed h * w within [0, F] (never past the vertex, never faster
              than the feed), and the command's total variation sum |w_k - w_(k-1)| within any
              window at most the design's velocity step V_s (`gmotion design --v-override`):
              the output's acceleration sum h_i dw_(k-i)/T and jerk then stay within a step of
              V_s's, the limits the filter was designed for;
  maximise    sum w_k (the path covered in the horizon: what the output gains on the stop).

Printed per feed: the plain stop's loss per side (ms), the shaped one's, and LinuxCNC's F/(2a)
at a = V_s/tau (the filter's mean ramp acceleration at V_s). Nothing here is in gmotion.
Needs numpy and scipy (python3-scipy comes with python3-matplotlib).
"""
import argparse
import os
import sys

import numpy as np
from scipy.optimize import linprog

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from arc_blend_model import add_filter_args, taps  # noqa: E402  (same folder)


def shaped_stop(h, feed, vstep, horizon):
    """The LP above; returns the command's speeds w (mm/s per sample) over the horizon."""
    n, K = len(h), horizon
    nv = 2 * K  # w_0..w_(K-1), then d_k >= |w_k - w_(k-1)| (w_(-1) = F)
    rows, rhs = [], []
    for k in range(K):  # 0 <= g_k = sum_i h_i w_(k-i) <= F, w before the horizon F
        row, const = np.zeros(nv), 0.0
        for i in range(n):
            if k - i < 0:
                const += h[i] * feed
            else:
                row[k - i] += h[i]
        rows += [row, -row]
        rhs += [feed - const, const]
    for k in range(K):  # d_k >= +-(w_k - w_(k-1))
        for sign in (1.0, -1.0):
            row = np.zeros(nv)
            row[k], row[K + k] = sign, -1.0
            if k > 0:
                row[k - 1] = -sign
            rows.append(row)
            rhs.append(sign * feed if k == 0 else 0.0)
    for k in range(K):  # the variation within every window of n samples
        row = np.zeros(nv)
        row[K + max(0, k - n + 1):K + k + 1] = 1.0
        rows.append(row)
        rhs.append(vstep)
    bounds = [(None, None)] * K + [(0.0, None)] * K
    for k in range(K - n, K):
        bounds[k] = (0.0, 0.0)
    cost = np.zeros(nv)
    cost[:K] = -1.0
    res = linprog(cost, A_ub=np.array(rows), b_ub=np.array(rhs), bounds=bounds, method="highs")
    if res.status != 0:
        sys.exit(f"stop_shaping_model.py: the LP failed at F {feed}: {res.message}")
    return res.x[:K]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_filter_args(ap)
    ap.add_argument("--feeds", type=float, nargs="+", default=[10, 25, 50, 100], help="mm/s")
    ap.add_argument("--vstep", type=float, default=100.0,
                    help="the design's velocity step V_s, mm/s (gmotion design --v-override)")
    args = ap.parse_args()
    h = np.array(taps(args.gmotion, args.profile, args.tau, args.period))
    n, T = len(h), args.period
    horizon = 4 * n
    m = float(np.dot(np.arange(n), h))  # the taps' centroid, samples
    accel = args.vstep / (n * T)
    print(f"{args.profile} tau {args.tau} s, T {T} s, {n} taps, V_s {args.vstep:g} mm/s")
    print("| feed mm/s | plain stop, loss per side | shaped | won back | largest command speed |"
          f" LinuxCNC F/(2a), a {accel:.0f} mm/s² |")
    print("| --- | --- | --- | --- | --- | --- |")
    for feed in args.feeds:
        w = shaped_stop(h, feed, args.vstep, horizon)
        # Plain: the output rests n - 1 samples after the command reaches the vertex, where
        # running on at F it would pass it m samples after (its lag). Both commands rest on the
        # vertex for the horizon's last n samples: the shaped one covers sum(w)*T of path in the
        # horizon against F*(K - n)*T, and started that much further back at F.
        plain = (n - 1 - m) * T
        gained = (w.sum() - feed * (horizon - n)) * T / feed
        print(f"| {feed:g} | {plain * 1e3:.1f} ms | {(plain - gained) * 1e3:.1f} ms |"
              f" {gained * 1e3:.1f} ms | {w.max():.1f} mm/s | {feed / (2 * accel) * 1e3:.1f} ms |")


if __name__ == "__main__":
    main()
