#!/usr/bin/env python3
"""Corner rows, measured: how much of a small corner's rounding an offset commanded around its
vertex could take away (docs/tolerance.md, "Not done": cambam-engrave.nc's kinks).

A corner turning by theta at constant path speed v leaves the filter D(0)*|du|*v off the path at
most (|du| = 2 sin(theta/2)), linear in |du|*v for small turns. The arc's end rows take most of
an arc's end transition away by an offset over a few samples; this does the same for a corner:
offsets in both directions (along the bisector's normal and along the path) at the samples
within K of the vertex, one piecewise-linear shape in u (the sample's advances from the vertex,
knots at the integers) for every phase of the vertex within its sample, each offset at most
B*D(0)*|du|*v, fitted by a linear programme for the least worst component of y - x(sbar) over
every sample of the runs at four phases. Printed: the worst |y - x(sbar)| as a fraction of
D(0)*|du|*v, with per-phase fits (each phase its own offsets: a lower bound) beside; then the
same shapes when the speed steps near the vertex (an override change, a feed hold), each
sample's offset scaled by its own speed. Nothing here is in gmotion yet. Needs numpy and scipy (python3-scipy comes with python3-matplotlib).
"""
import argparse
import math
import os
import sys

import numpy as np
from scipy.optimize import linprog

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from arc_blend_model import add_filter_args, taps  # noqa: E402  (same folder)

PHASES = (0.0, 0.25, 0.5, 0.75)


def d0(h, period):
    """D(0) = T * sum h_i max(i - m, 0), s (symmetric taps)."""
    m = (len(h) - 1) / 2.0
    return period * sum(w * max(i - m, 0.0) for i, w in enumerate(h))


def corner_rows(h, period, theta, v, phase):
    """A corner at s = 0 sampled from -150 to 150 advances (first sample `phase` past a whole
    advance): the samples' u, the uncompensated errors y - x(sbar) once the window is full (one
    row per output), and each output's weights on the samples (newest first)."""
    n = len(h)
    u = np.arange(-150, 151) + phase
    s = u * v * period
    u1 = np.array([1.0, 0.0])
    u2 = np.array([math.cos(theta), math.sin(theta)])
    x = np.where(s[:, None] < 0.0, s[:, None] * u1, s[:, None] * u2)
    outs = []
    for k in range(n - 1, len(s)):
        win = np.arange(k, k - n, -1)
        y = (h[:, None] * x[win]).sum(0)
        sbar = float((h * s[win]).sum())
        outs.append((win, y - (sbar * u1 if sbar < 0.0 else sbar * u2)))
    return u, outs


def fit(h, period, theta, v, span, bound, phases):
    """Offsets at knots u = -span..span (two components each) shared by `phases`, each within
    `bound` mm: the LP's worst |y - x(sbar)| over every run, and without offsets, mm."""
    knots = np.arange(-span, span + 1)
    nk = len(knots)
    nv = 2 * nk + 1
    a_ub, b_ub, runs = [], [], []
    for phase in phases:
        u, outs = corner_rows(h, period, theta, v, phase)
        # interpolation of the knots at each sample's u (0 outside the span)
        interp = np.zeros((len(u), nk))
        for j, uu in enumerate(u):
            if -span <= uu <= span:
                i = min(int(math.floor(uu + span)), nk - 2)
                t = uu + span - i
                interp[j, i] += 1.0 - t
                interp[j, i + 1] += t
        for win, e in outs:
            w = (h[:, None] * interp[win]).sum(0)  # the output's weight on each knot
            runs.append((w, e))
            for c in range(2):
                row = np.zeros(nv)
                row[c * nk:(c + 1) * nk] = w
                row[-1] = -1.0
                a_ub.append(row)
                b_ub.append(-e[c])
                row = -row
                row[-1] = -1.0
                a_ub.append(row)
                b_ub.append(e[c])
    cost = np.zeros(nv)
    cost[-1] = 1.0
    res = linprog(cost, A_ub=np.array(a_ub), b_ub=np.array(b_ub),
                  bounds=[(-bound, bound)] * (2 * nk) + [(0.0, None)], method="highs")
    o = res.x[:2 * nk]
    before = max(float(np.linalg.norm(e)) for _, e in runs)
    after = max(float(np.hypot(e[0] + w @ o[:nk], e[1] + w @ o[nk:])) for w, e in runs)
    return after, before, (knots, o[:nk], o[nk:])


def stepped(h, period, theta, v, shape, speeds, start):
    """The worst |y - x(sbar)| of the corner run at per-sample `speeds` from path position
    `start`, each sample commanded off the path by the shape at its u (its distance from the
    vertex in advances at its own speed), scaled by its own speed as the fit's offsets are by v
    (None: no offsets), mm."""
    n = len(h)
    s = start + np.cumsum(speeds) * period
    u1 = np.array([1.0, 0.0])
    u2 = np.array([math.cos(theta), math.sin(theta)])
    x = np.where(s[:, None] < 0.0, s[:, None] * u1, s[:, None] * u2)
    if shape is not None:
        knots, ox, oy = shape
        for k, vk in enumerate(speeds):
            if vk > 0.0:
                u = s[k] / (vk * period)
                if knots[0] <= u <= knots[-1]:
                    x[k] += np.array([np.interp(u, knots, ox), np.interp(u, knots, oy)]) * vk / v
    worst = 0.0
    for k in range(n - 1, len(s)):
        win = np.arange(k, k - n, -1)
        y = (h[:, None] * x[win]).sum(0)
        sbar = float((h * s[win]).sum())
        worst = max(worst, float(np.linalg.norm(y - (sbar * u1 if sbar < 0.0 else sbar * u2))))
    return worst


def worst_step(h, period, theta, v, shape):
    """stepped's worst over speed steps near the vertex: down from v to f*v, or up from f*v to v
    (f = 0, 0.3, 0.6, 0.9), at every second sample from 40 before to 40 after the one where the
    vertex lies at constant speed, two phases."""
    worst = 0.0
    for f in (0.0, 0.3, 0.6, 0.9):
        for j in range(-40, 41, 2):
            for ph in (0.0, 0.5):
                down = np.full(300, v)
                down[150 + j:] = f * v
                worst = max(worst, stepped(h, period, theta, v, shape, down, (ph - 150) * v * period))
                if f > 0.0:
                    up = np.full(300, f * v)
                    up[150 + j:] = v
                    worst = max(worst, stepped(h, period, theta, v, shape, up,
                                               (ph - 150) * f * v * period))
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_filter_args(ap)
    ap.add_argument("--turn-deg", type=float, default=0.9)
    ap.add_argument("--speed", type=float, default=25.0, help="path speed, mm/s")
    args = ap.parse_args()
    h = np.array(taps(args.gmotion, args.profile, args.tau, args.period))
    theta = math.radians(args.turn_deg)
    scale = d0(h, args.period) * 2.0 * math.sin(theta / 2.0) * args.speed
    print(f"{args.profile} tau {args.tau} s, T {args.period} s, {len(h)} taps; a {args.turn_deg} deg "
          f"corner at {args.speed} mm/s: D(0)*|du|*v = {scale * 1000:.3f} um")
    print("| offsets within (x D(0)|du|v) | knots each side | one shape, 4 phases | per phase |")
    print("| --- | --- | --- | --- |")
    shapes = {}
    for b in (2.5, 5.0, 12.0):
        for span in (2, 5, 10, 20):
            one, before, shapes[b, span] = fit(h, args.period, theta, args.speed, span, b * scale,
                                               PHASES)
            each = max(fit(h, args.period, theta, args.speed, span, b * scale, (p,))[0]
                       for p in PHASES)
            print(f"| {b} | {span} | {one / scale:.3f} | {each / scale:.3f} |")
    print(f"(without offsets: {before / scale:.3f})")
    print()
    print("The same shapes when the speed steps near the vertex (worst_step), / D(0)|du|v:")
    print("| offsets within | knots each side | worst over the steps |")
    print("| --- | --- | --- |")
    for key in ((5.0, 5), (5.0, 10)):
        worst = worst_step(h, args.period, theta, args.speed, shapes[key])
        print(f"| {key[0]} | {key[1]} | {worst / scale:.3f} |")
    print(f"(without offsets: {worst_step(h, args.period, theta, args.speed, None) / scale:.3f})")


if __name__ == "__main__":
    main()
