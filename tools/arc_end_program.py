#!/usr/bin/env python3
"""A whole program's pre-compensated arcs with today's radial blend against 2-D end rows fitted
for each arc's actual speeds (tools/arc_end_model.py), at today's plan and at its speeds scaled.

Runs `gmotion run PROGRAM --no-servo --trace` (the plan as the interpolator samples it) and
`gmotion moves PROGRAM`, recovers each sample's path position from the commanded position (the
nearest point of its block; the trace's BLU rounding is the noise), and re-commands the path in
a model: every speed below its block's feed raised k times, up to the feed, the
steady correction c on arcs from each sample's own advance, the arc's ends either blended as the
interpolator does today or with rows fitted for that arc's speeds (both ends together, 6 samples,
lambda 1e-3). The output y = sum h_i x_(n-i) in double precision, its worst distance from the
program's path (every element). XY lines and arcs only. docs/tolerance-arc-ends.md, "The arc's
ends in two directions". Needs numpy.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from arc_end_model import Arc, gain  # noqa: E402  (same folder)


class Element:
    """A line from a to b, or an arc about c of radius r from angle a0 through sweep sw (signed)."""

    def __init__(self, move, start, s0):
        self.line, self.s0, self.a = move["line"], s0, start
        self.feed = move["feed"] / 60.0  # mm/s
        self.b = np.array(move["end"][:2], float)
        self.kind = move["kind"]
        if self.kind == "line":
            self.len = float(np.linalg.norm(self.b - start))
            return
        self.c = np.array(move["center"][:2], float)
        self.r = float(np.linalg.norm(start - self.c))
        self.a0 = math.atan2(start[1] - self.c[1], start[0] - self.c[0])
        a1 = math.atan2(self.b[1] - self.c[1], self.b[0] - self.c[0])
        ccw = move["dir"] == "ccw"
        sweep = (a1 - self.a0) % (2 * math.pi) if ccw else -((self.a0 - a1) % (2 * math.pi))
        turns = move.get("turns", 1)
        if abs(sweep) < 1e-12:
            sweep = 2 * math.pi if ccw else -2 * math.pi
        sweep += (turns - 1) * 2 * math.pi * (1 if ccw else -1)
        self.sw = sweep
        self.len = abs(sweep) * self.r

    def frame(self, s):
        """Point, outward normal (zero on a line) and tangent at local path length s."""
        if self.kind == "line":
            u = (self.b - self.a) / self.len
            return self.a + u * s, np.zeros(2), u
        sign = 1.0 if self.sw > 0 else -1.0
        ang = self.a0 + sign * s / self.r
        out = np.array([math.cos(ang), math.sin(ang)])
        return self.c + self.r * out, out, sign * np.array([-math.sin(ang), math.cos(ang)])

    def local(self, q):
        """Path length of the point of this element nearest q."""
        if self.kind == "line":
            u = (self.b - self.a) / self.len
            return float(np.clip((q - self.a) @ u, 0.0, self.len))
        sign = 1.0 if self.sw > 0 else -1.0
        rel = ((math.atan2(q[1] - self.c[1], q[0] - self.c[0]) - self.a0) * sign) % (2 * math.pi)
        if rel > abs(self.sw):  # past an end: the nearer one
            rel = 0.0 if rel > math.pi + abs(self.sw) / 2 else abs(self.sw)
        return rel * self.r

    def distance(self, y):
        if self.kind == "line":
            u = (self.b - self.a) / self.len
            t = np.clip((y - self.a) @ u, 0.0, self.len)
            return np.linalg.norm(y - (self.a + np.outer(t, u)), axis=1)
        d = y - self.c
        sign = 1.0 if self.sw > 0 else -1.0
        rel = ((np.arctan2(d[:, 1], d[:, 0]) - self.a0) * sign) % (2 * math.pi)
        ends = np.minimum(np.linalg.norm(y - self.a, axis=1), np.linalg.norm(y - self.b, axis=1))
        return np.where(rel <= abs(self.sw) + 1e-12, np.abs(np.hypot(d[:, 0], d[:, 1]) - self.r), ends)


def load(gmotion, program, trace):
    moves = subprocess.run([gmotion, "moves", program], capture_output=True, text=True,
                           check=True).stdout.splitlines()
    elements, at, s0 = [], np.zeros(2), 0.0
    for text in moves:
        move = json.loads(text)
        if move["kind"] not in ("line", "arc"):
            continue
        if abs(move["end"][2]) > 1e-9:
            sys.exit(f"{program}: XY moves only (line {move['line']} moves Z)")
        if move["kind"] == "line" and np.linalg.norm(np.array(move["end"][:2]) - at) < 1e-9:
            continue
        el = Element(move, at.copy(), s0)
        elements.append(el)
        s0, at = s0 + el.len, el.b
    subprocess.run([gmotion, "run", program, "--no-servo", "--trace", trace], check=True,
                   capture_output=True)
    blu, period, name, tau = 0.001, 0.004, "blackman", 0.164  # the trace header says otherwise
    with open(trace) as f:
        lines = f.readlines()
    for text in lines:
        if text.startswith("# blu_mm:"):
            blu = float(text.split(":")[1].split(",")[0])
        if text.startswith("# period_s:"):
            period = float(text.split(":")[1])
        if text.startswith("# profile:"):
            profile = dict(kv.split("=") for kv in text.split()[3:])
            tau = float(profile["tau_s"])
            name = text.split()[2]
    by_line = {el.line: i for i, el in enumerate(elements)}
    path, last = [], 0.0
    for row in csv.DictReader(t for t in lines if not t.startswith("#")):
        i = by_line.get(int(row["line"]))
        if i is None:
            path.append(last)
            continue
        q = np.array([float(row["x_cmd"]), float(row["y_cmd"])]) * blu
        last = max(last, elements[i].s0 + elements[i].local(q))  # the plan never goes back
        path.append(last)
    path = np.array(path)
    total = s0
    path[path >= total - 1.5 * blu] = total  # the run ends on the program's end point exactly
    return elements, path, period, name, tau


def rescaled(elements, path_tr, period, k):
    """The plan's path positions with every speed below its block's feed raised k times, up to
    the feed: each sample's advance taken in period * max(1/k, v/F)."""
    adv = np.diff(path_tr)
    starts = np.array([el.s0 for el in elements])
    mid = np.clip(np.searchsorted(starts, path_tr[:-1] + adv / 2, side="right") - 1, 0,
                  len(elements) - 1)
    feed = np.array([elements[i].feed for i in mid])
    dt = period * np.maximum(1.0 / k, adv / period / feed)
    t = np.concatenate([[0.0], np.cumsum(dt)])
    return np.interp(np.arange(0.0, t[-1] + period, period), t, path_tr)


def simulate(h, period, elements, path_tr, k, rows):
    m = len(h)
    pos = rescaled(elements, path_tr, period, k)
    n = len(pos)
    starts = np.array([el.s0 for el in elements])
    idx = np.clip(np.searchsorted(starts, pos, side="left") - 1, 0, len(elements) - 1)
    adv = np.diff(np.concatenate([[pos[0]], pos]))
    cmd = np.array([elements[idx[i]].frame(pos[i] - elements[idx[i]].s0)[0] for i in range(n)])
    for e, el in enumerate(elements):
        samples = np.where((idx == e) & (pos > el.s0) & (pos < el.s0 + el.len))[0]
        if el.kind != "arc" or len(samples) == 0:
            continue
        v = adv[samples].max() / period
        if not rows:
            blend = min(el.len / 2, 2 * period * v)
            for i in samples:
                s = pos[i] - el.s0
                x = adv[i] / el.r
                w = min(1.0, min(s, el.len - s) / blend)
                cmd[i] += w * el.r * (1 / gain(h, x) - 1) * el.frame(s)[1]
            continue
        first, last = samples[0], samples[-1]
        lo, hi = first - 3 * m, last + 3 * m
        speeds = [max(adv[min(max(j, 1), n - 1)], 1e-12) / period for j in range(lo, hi + 1)]
        arc = Arc(list(h), period, el.r, abs(el.sw), speeds, first - lo,
                  (pos[first] - el.s0) / adv[first], v)
        fx, fy, _ = arc.fit(6, 1e-3)
        px, py, nx, ny, tx, ty = arc.geometry(arc.s)
        for j in np.where(arc.on)[0]:
            i = lo + j
            if 0 <= i < n and idx[i] == e:
                _, normal, tangent = el.frame(pos[i] - el.s0)
                radial = (fx[j] - px[j]) * nx[j] + (fy[j] - py[j]) * ny[j]
                along = (fx[j] - px[j]) * tx[j] + (fy[j] - py[j]) * ty[j]
                cmd[i] += radial * normal + along * tangent
    padded = np.vstack([np.repeat(cmd[:1], m, 0), cmd, np.repeat(cmd[-1:], m, 0)])
    y = np.column_stack([np.convolve(padded[:, a], h)[:len(padded)] for a in (0, 1)])[m - 1:]
    worst = np.min(np.column_stack([el.distance(y) for el in elements]), axis=1).max()
    moving = np.where(pos < pos[-1])[0]
    return worst, (moving[-1] + 1) * period if len(moving) else 0.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("program")
    ap.add_argument("--gmotion", default="build/bin/gmotion")
    ap.add_argument("--scales", type=float, nargs="+", default=[1.0, 1.5, 2.0, 2.5])
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        elements, path, period, name, tau = load(args.gmotion, args.program,
                                                 os.path.join(tmp, "trace.csv"))
    out = subprocess.run([args.gmotion, "design", "--json", "--profile", name, "--tau", str(tau),
                          "--period", str(period)], check=True, capture_output=True, text=True)
    d = json.loads(out.stdout)
    h = np.array([t / d["b_s"] for t in d["taps_int"]])
    arcs = sum(el.kind == "arc" for el in elements)
    print(f"{args.program}: {len(elements)} elements, {arcs} arcs; {name} tau {tau} s, T {period} s")
    print("| speeds x k | motion s | today's blend: worst um | 2-D rows fitted per arc: worst um |")
    print("| --- | --- | --- | --- |")
    for k in args.scales:
        today, time_s = simulate(h, period, elements, path, k, False)
        fitted, _ = simulate(h, period, elements, path, k, True)
        print(f"| {k} | {time_s:.3f} | {today * 1000:.2f} | {fitted * 1000:.2f} |")


if __name__ == "__main__":
    main()
