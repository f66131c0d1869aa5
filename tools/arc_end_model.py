#!/usr/bin/env python3
"""Model of a pre-compensated arc's ends judged by the distance of the Acc/Dec output from the
path (the contour error), not by |y - x(sbar)|: how small a correction of a few samples in both
directions (radial and tangential) makes the end transitions, and what it costs.

The filter's taps come from `gmotion design --json` (default: Blackman, tau 0.164 s, T 4 ms).
A line runs into an arc (and, for whole arcs, out onto the tangent line after it) at a constant
path speed; the command is the path plus the steady correction c = R(1/A - 1) along the outward
normal on the arc, except on the arc's first (and last) K samples, whose offsets are free in
both directions. They are chosen to minimise the largest distance of the output from the path
(iteratively reweighted least squares on the linearised distance, Tikhonov weight lam in units
of c), the output y = sum h_i x_(n-i) exactly. Figures are fractions of the steady loss R(1 - A).
docs/tolerance.md, "The arc's ends in two directions, judged by the distance to the path".
Needs numpy (tools/install-deps.sh installs python3-numpy).
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from arc_blend_model import taps  # noqa: E402  (same folder)


class Arc:
    """Line along +x into a CCW arc of radius r and sweep th (th = inf: the arc never ends), then
    the tangent line; samples at phase + k of the sample's travel v*T from the arc's start."""

    def __init__(self, h, period, v, r, th=math.inf, phase=0.25, before=2, after=4):
        self.h, self.m, self.t, self.v, self.r, self.th = h, len(h), period, v, r, th
        self.x = v * period / r
        mid = sum(i * w for i, w in enumerate(h))
        gain = sum(w * math.cos((i - mid) * self.x) for i, w in enumerate(h))
        self.c, self.loss = r * (1 / gain - 1), r * (1 - gain)
        self.len = r * th if not math.isinf(th) else 1e9
        arc_samples = 0 if math.isinf(th) else int(self.len / (v * period))
        k = np.arange(-before * self.m, arc_samples + after * self.m)
        self.s = (k + phase) * v * period
        self.k_in = self.s / (v * period)
        self.k_out = (self.len - self.s) / (v * period)
        n = len(self.s)
        self.conv = np.zeros((n, n))
        for i, w in enumerate(h):
            self.conv += np.eye(n, k=-i) * w
        self.valid = np.arange(n) >= self.m - 1  # the window is full
        self.sbar = self.conv @ self.s

    def geometry(self, s):
        """Point, outward normal (zero on the lines) and unit tangent at path length s."""
        r, th, length = self.r, self.th, self.len
        a = np.clip(s, 0, length) / r
        on = (s > 0) & (s <= length)
        end_x, end_y = r * math.sin(min(th, 1e9)), r * (1 - math.cos(min(th, 1e9)))
        ct, st = (math.cos(th), math.sin(th)) if not math.isinf(th) else (1.0, 0.0)
        px = np.where(s <= 0, s, np.where(on, r * np.sin(a), end_x + (s - length) * ct))
        py = np.where(s <= 0, 0.0, np.where(on, r * (1 - np.cos(a)), end_y + (s - length) * st))
        nx = np.where(on, np.sin(a), 0.0)
        ny = np.where(on, -np.cos(a), 0.0)
        return px, py, nx, ny, np.cos(np.where(s <= 0, 0, a)), np.sin(np.where(s <= 0, 0, a))

    def distance(self, yx, yy):
        """Distance to the line before, the arc and the line after."""
        r, th = self.r, self.th
        d = np.where(yx <= 0, np.abs(yy), np.hypot(yx, yy))
        turn = np.mod(np.arctan2(yy - r, yx) + math.pi / 2, 2 * math.pi)
        if math.isinf(th):  # a long arc: the circle wherever the window has left the line
            on = (yx >= 0) | (self.sbar > r * math.pi / 2)
            return np.minimum(d, np.where(on, np.abs(np.hypot(yx, yy - r) - r), np.inf))
        ex, ey = r * math.sin(th), r * (1 - math.cos(th))
        on = turn <= th
        d = np.minimum(d, np.where(on, np.abs(np.hypot(yx, yy - r) - r), np.hypot(yx - ex, yy - ey)))
        along = (yx - ex) * math.cos(th) + (yy - ey) * math.sin(th)
        across = np.abs(-(yx - ex) * math.sin(th) + (yy - ey) * math.cos(th))
        return np.minimum(d, np.where(along >= 0, across, np.hypot(yx - ex, yy - ey)))

    def command(self, shape=None, k=2):
        """The interpolator's command. shape None: today's linear blend over the arc's first and
        last k samples; else shape(k_from_end) -> (radial / c, tangential * x / c) on the arc's
        first and last k samples (mirrored at the exit: the tangential part reversed)."""
        px, py, nx, ny, tx, ty = self.geometry(self.s)
        on = (self.s > 0) & (self.s <= self.len)
        near = np.minimum(self.k_in, self.k_out)
        if shape is None:
            w = np.clip(near / k, 0, 1) * on
            return px + w * self.c * nx, py + w * self.c * ny
        cx, cy = px + on * self.c * nx, py + on * self.c * ny
        for i in np.where(on & (near < k))[0]:
            entry = self.k_in[i] < self.k_out[i]
            rad, tan = shape(self.k_in[i] if entry else self.k_out[i])
            tan = (tan if entry else -tan) * self.c / self.x
            rad = (rad - 1) * self.c
            cx[i] += rad * nx[i] + tan * tx[i]
            cy[i] += rad * ny[i] + tan * ty[i]
        return cx, cy

    def measure(self, cx, cy):
        """Worst distance / loss, worst |y - x(sbar)| / loss, output speed range / v, largest
        output jerk (mm/s^3), largest command step / (v T)."""
        yx, yy = self.conv @ cx, self.conv @ cy
        qx, qy, _, _, _, _ = self.geometry(self.sbar)
        v = self.valid
        full = slice(self.m + 4, None)
        speed = np.hypot(np.diff(yx), np.diff(yy))[full] / self.t
        jerk = np.hypot(np.diff(yx, 3), np.diff(yy, 3))[full] / self.t ** 3
        step = np.hypot(np.diff(cx), np.diff(cy)).max() / (self.v * self.t)
        return (self.distance(yx, yy)[v].max() / self.loss,
                np.hypot(yx - qx, yy - qy)[v].max() / self.loss,
                (speed.min() / self.v, speed.max() / self.v), jerk.max(), step)

    def fit(self, k, lam, iters=40):
        """Offsets on the arc's first and last k samples minimising the worst distance; returns
        the command and the entry's shape: rows (k_in, radial / c, tangential * x / c)."""
        px, py, nx, ny, tx, ty = self.geometry(self.s)
        on = (self.s > 0) & (self.s <= self.len)
        near = on & (np.minimum(self.k_in, self.k_out) < k)
        base_x, base_y = px + on * ~near * self.c * nx, py + on * ~near * self.c * ny
        cols = []  # (sample, direction): radial and tangential, in units of c
        for i in np.where(near)[0]:
            cols.append((i, self.c * nx[i], self.c * ny[i]))
            cols.append((i, self.c * tx[i], self.c * ty[i]))
        n, f = len(self.s), len(cols)
        ux, uy = np.zeros((n, f)), np.zeros((n, f))
        for q, (i, dx, dy) in enumerate(cols):
            ux[i, q], uy[i, q] = dx, dy
        cux, cuy = self.conv @ ux, self.conv @ uy
        y0x, y0y = self.conv @ base_x, self.conv @ base_y
        u, weight, eps = np.zeros(f), np.ones(int(self.valid.sum())), 1e-7 * self.r
        for _ in range(iters):
            yx, yy = y0x + cux @ u, y0y + cuy @ u
            d = self.distance(yx, yy)
            gx = (self.distance(yx + eps, yy) - d) / eps
            gy = (self.distance(yx, yy + eps) - d) / eps
            a = (gx[:, None] * cux + gy[:, None] * cuy)[self.valid]
            rhs = d[self.valid] - a @ u
            lhs = np.vstack([a * np.sqrt(weight)[:, None], math.sqrt(lam) * self.c * np.eye(f)])
            u = np.linalg.lstsq(lhs, np.concatenate([-rhs * np.sqrt(weight), np.zeros(f)]),
                                rcond=None)[0]
            e = np.abs(a @ u + rhs)
            weight = weight * (e / e.max() + 1e-3)
            weight /= weight.mean()
        cx, cy = base_x + ux @ u, base_y + uy @ u
        rows = {}
        for q, (i, _, _) in enumerate(cols):
            if self.k_in[i] < self.k_out[i]:
                rows.setdefault(i, [self.k_in[i], 0.0, 0.0])[1 + q % 2] += u[q] * (self.x if q % 2 else 1)
        return cx, cy, [tuple(rw) for _, rw in sorted(rows.items())]


def table_shape(rows):
    """The fitted entry rows as a function of k_in (the sample's row; the steady c beyond)."""
    def shape(k):
        j = int(math.floor(k))
        return (rows[j][1], rows[j][2]) if j < len(rows) else (1.0, 0.0)
    return shape


def phase_table(h, period, x, k, lam, phases):
    """Entry shapes fitted at `phases` (fractions of a sample), unit radius, rate x."""
    return [Arc(h, period, x / period, 1.0, phase=p).fit(k, lam)[2] for p in phases]


def interpolated(tables, phases, p):
    j = max(i for i, q in enumerate(phases) if q <= p)
    j = min(j, len(phases) - 2)
    f = (p - phases[j]) / (phases[j + 1] - phases[j])
    return [(a[0], a[1] * (1 - f) + b[1] * f, a[2] * (1 - f) + b[2] * f)
            for a, b in zip(tables[j], tables[j + 1])]


def both_ends(arc, knots, tables, phases, k):
    """The command with both ends from the tables (fitted on long arcs at the rates `knots`),
    linear in the rate between knots and in the phase between phases; the exit mirrored."""
    j = min(max(i for i, q in enumerate(knots) if q <= arc.x) if arc.x >= knots[0] else 0,
            len(knots) - 2)
    f = min(max((arc.x - knots[j]) / (knots[j + 1] - knots[j]), 0.0), 1.0)
    px, py, nx, ny, tx, ty = arc.geometry(arc.s)
    on = (arc.s > 0) & (arc.s <= arc.len)
    cx, cy = px + on * arc.c * nx, py + on * arc.c * ny
    ends = []
    for entry, kk in ((True, arc.k_in), (False, arc.k_out)):
        p = min(max(kk[on].min() % 1, phases[0]), phases[-1])
        lo, hi = interpolated(tables[j], phases, p), interpolated(tables[j + 1], phases, p)
        ends.append((entry, kk, [(a[1] * (1 - f) + b[1] * f, a[2] * (1 - f) + b[2] * f)
                                 for a, b in zip(lo, hi)]))
    for i in np.where(on)[0]:
        for entry, kk, rows in ends:
            if kk[i] < k:
                rad, tan = rows[int(math.floor(kk[i]))]
                tan = (tan if entry else -tan) * arc.c / arc.x
                cx[i] += (rad - 1) * arc.c * nx[i] + tan * tx[i]
                cy[i] += (rad - 1) * arc.c * ny[i] + tan * ty[i]
    return cx, cy


def ramp(h, x0, low):
    """A steady arc of unit radius at rate x0, the speed ramped to low * x0 over the window (the
    interpolator's rate limit), held 60 samples and ramped back, c following the command's rate:
    the worst distance and the worst |y - x(sbar)|, over the steady loss at x0."""
    m = len(h)
    mid = sum(i * w for i, w in enumerate(h))

    def gain(x):
        return sum(w * math.cos((i - mid) * x) for i, w in enumerate(h))
    rates, x = [x0] * (3 * m), x0
    while x > low * x0 + 1e-12:
        x = max(low * x0, x - x0 / m)
        rates.append(x)
    rates += [x] * 60
    while x < x0 - 1e-12:
        x = min(x0, x + x0 / m)
        rates.append(x)
    rates = np.array(rates + [x0] * (3 * m))
    angle = np.cumsum(rates)
    radius = np.array([1 / gain(v) if v > 0 else 1.0 for v in rates])
    n = len(rates)
    yx = np.convolve(radius * np.sin(angle), h)[:n]
    yy = np.convolve(1 - radius * np.cos(angle), h)[:n]
    sbar = np.convolve(angle, h)[:n]
    full = np.arange(n) >= m - 1
    loss = 1 - gain(x0)
    dist = np.abs(np.hypot(yx, yy - 1) - 1)[full].max()
    vec = np.hypot(yx - np.sin(sbar), yy - 1 + np.cos(sbar))[full].max()
    return dist / loss, vec / loss


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--gmotion", default="build/bin/gmotion")
    ap.add_argument("--profile", default="blackman")
    ap.add_argument("--tau", type=float, default=0.164)
    ap.add_argument("--period", type=float, default=0.004)
    args = ap.parse_args()
    h = taps(args.gmotion, args.profile, args.tau, args.period)
    t = args.period
    print(f"{args.profile} tau {args.tau} s, T {t} s, {len(h)} taps; errors / steady loss R(1 - A)")
    print()
    print("Entry: a line into a long arc of unit radius at rate x = omega*T, phase 0.25.")
    print("| correction | x | distance | abs(y - x(sbar)) | output speed / v | jerk / today's | "
          "largest command step / (v T) |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for x in (0.03, 0.06, 0.1):
        base = Arc(h, t, x / t, 1.0)
        today = base.measure(*base.command())
        for name, k, lam in (("today: radial, linear over 2 samples", 2, None),
                             ("2-D, arc's first 2 samples, lam 0", 2, 0.0),
                             ("2-D, arc's first 2 samples, lam 1e-3", 2, 1e-3),
                             ("2-D, arc's first 6 samples, lam 1e-3", 6, 1e-3),
                             ("2-D, arc's first 6 samples, lam 1e-2", 6, 1e-2)):
            m = today if lam is None else base.measure(*base.fit(k, lam)[:2])
            print(f"| {name} | {x} | {m[0]:.3f} | {m[1]:.3f} | {m[2][0]:.3f} to {m[2][1]:.3f} | "
                  f"{m[3] / today[3]:.2f} | {m[4]:.2f} |")
    print()
    k, lam = 6, 1e-3
    print(f"One table of shapes (2-D, {k} samples, lam {lam}) per phase of the join in its sample,")
    print("fitted at x = 0.03 and scaled (radial by c, tangential by c / x), linear between")
    print("phases, used at the phases half-way between: worst distance / loss.")
    print("| phases in the table | x = 0.02 | 0.03 | 0.06 | 0.1 | one phase (0.25) for all, x = 0.03 |")
    print("| --- | --- | --- | --- | --- | --- |")
    single = table_shape(phase_table(h, t, 0.03, k, lam, [0.25])[0])
    worst1 = 0.0
    for p in (0.0, 0.25, 0.5, 0.75, 0.99):
        arc = Arc(h, t, 0.03 / t, 1.0, phase=p)
        worst1 = max(worst1, arc.measure(*arc.command(single, k))[0])
    for count in (4, 8, 16):
        phases = [0.001 + 0.998 * j / count for j in range(count + 1)]
        tables = phase_table(h, t, 0.03, k, lam, phases)
        cells = []
        for x in (0.02, 0.03, 0.06, 0.1):
            worst = 0.0
            for j in range(count):
                p = 0.5 * (phases[j] + phases[j + 1])
                arc = Arc(h, t, x / t, 1.0, phase=p)
                rows = interpolated(tables, phases, p)
                worst = max(worst, arc.measure(*arc.command(table_shape(rows), k))[0])
            cells.append(f"{worst:.3f}")
        print(f"| {count} | " + " | ".join(cells) + f" | {worst1:.3f} |")
    print()
    print("The ramp on a steady arc (today's rule: c follows the command's rate), to rest and to")
    print("0.6 of the speed and back, worst distance and worst |y - x(sbar)| / steady loss:")
    print("| x | to rest: distance | abs(y - x(sbar)) | to 0.6: distance | abs(y - x(sbar)) |")
    print("| --- | --- | --- | --- | --- |")
    for x in (0.03, 0.06, 0.1, 0.2):
        rest, slow = ramp(h, x, 0.0), ramp(h, x, 0.6)
        print(f"| {x} | {rest[0]:.3f} | {rest[1]:.3f} | {slow[0]:.3f} | {slow[1]:.3f} |")
    print()
    phases = [0.001 + 0.998 * j / 8 for j in range(9)]
    knots = (0.03, 0.06, 0.1)
    tables = [phase_table(h, t, x, k, lam, phases) for x in knots]
    print("Whole arcs, line - arc - line at constant speed (mm, mm/s): both ends fitted together,")
    print(f"and both from tables ({k} samples, lam {lam}, 8 phases, fitted on long arcs at")
    print(f"x = {', '.join(map(str, knots))}, linear between; the exit mirrored):")
    print("| R mm | sweep | v mm/s | x | arc in samples | steady loss um | today | 2-D, 2 + 2 samples | "
          "2-D, 6 + 6 samples | 6 + 6 from the tables |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r, deg, v in ((1, 90, 13.5), (1, 90, 25), (2, 180, 18), (2, 180, 30), (3, 180, 22.4),
                      (4, 180, 26), (2, 90, 50)):
        arc = Arc(h, t, v, r, math.radians(deg))
        cells = [f"{arc.measure(*arc.command())[0]:.3f}"]
        for kk in (2, 6):
            cells.append(f"{arc.measure(*arc.fit(kk, lam)[:2])[0]:.3f}")
        cells.append(f"{arc.measure(*both_ends(arc, knots, tables, phases, k))[0]:.3f}")
        print(f"| {r} | {deg}° | {v} | {arc.x:.3f} | {arc.len / (v * t):.0f} | {arc.loss * 1000:.1f} | "
              + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
