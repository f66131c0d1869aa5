#!/usr/bin/env python3
"""Model of a pre-compensated arc's ends judged by the distance of the Acc/Dec output from the
path (the contour error), not by |y - x(sbar)|: how small a correction of a few samples in both
directions (radial and tangential) makes the end transitions, and what it costs.

The filter's taps come from `gmotion design --json` (default: Blackman, tau 0.164 s, T 4 ms).
A line runs into an arc (and, for whole arcs, out onto the tangent line after it) at path speeds
given per sample; the command is the path plus the steady correction c = R(1/A(x) - 1) along the
outward normal on the arc (x = the sample's advance / R, c following it as the interpolator's
does), except on the arc's first (and last) K samples, whose offsets are free in both
directions. They are chosen to minimise the largest distance of the output from the path
(iteratively reweighted least squares on the linearised distance, the best pass kept, Tikhonov
weight lam in units of c), the output y = sum h_i x_(n-i) exactly. Figures are fractions of the steady loss
R(1 - A) at the arc's speed. docs/tolerance-arc-ends.md, "The arc's ends in two directions,
judged by the distance to the path". Needs numpy (tools/install-deps.sh installs python3-numpy).
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from arc_blend_model import add_filter_args, taps  # noqa: E402  (same folder)


def gain(h, x):
    """A(x) = sum h_i cos((i - m) x): the filter's amplitude at rate x = omega*T."""
    mid = sum(i * w for i, w in enumerate(h))
    return sum(w * math.cos((i - mid) * x) for i, w in enumerate(h))


class Arc:
    """A line along +x into a CCW arc of radius r and sweep th (inf: the arc never ends), then the
    tangent line. `speeds` are the path speeds of the samples, in order, mm/s; the first sample
    on the arc is speeds[join] and lies `phase` of its advance past the arc's start. `v` is the
    arc's speed (the loss and today's blend length are taken at it)."""

    def __init__(self, h, period, r, th, speeds, join, phase, v):
        self.h, self.m, self.t, self.r, self.th, self.v = h, len(h), period, r, th, v
        self.x = v * period / r
        self.loss = r * (1 - gain(h, self.x))
        self.c_arc = r * (1 / gain(h, self.x) - 1)  # the steady correction at the arc's speed
        self.len = r * th if not math.isinf(th) else 1e9
        adv = np.asarray(speeds, float) * period
        s = np.cumsum(adv)
        self.s = s - s[join] + phase * adv[join]
        self.rate = adv / r
        self.c = np.array([r * (1 / gain(h, x) - 1) if x > 0 else 0.0 for x in self.rate])
        self.on = (self.s > 0) & (self.s < self.len - 1e-9 * r)  # one resting on the end is past it
        idx = np.arange(len(self.s))
        on_idx = idx[self.on]
        self.first, self.last = on_idx[0], on_idx[-1]
        self.phase_in = self.s[self.first] / adv[self.first]
        self.phase_out = (self.len - self.s[self.last]) / adv[self.last]
        self.j_in = np.where(self.on, idx - self.first, 10 ** 9)   # samples since the start
        self.j_out = np.where(self.on, self.last - idx, 10 ** 9)   # samples before the end
        n = len(self.s)
        self.conv = np.zeros((n, n))
        for i, w in enumerate(h):
            self.conv += np.eye(n, k=-i) * w
        self.valid = idx >= self.m - 1  # the window is full
        self.sbar = self.conv @ self.s

    @classmethod
    def steady(cls, h, period, v, r, th=math.inf, phase=0.25):
        """Constant speed v: two windows of line before, the arc, four windows after."""
        m = len(h)
        arc_samples = 0 if math.isinf(th) else int(r * th / (v * period))
        n = 2 * m + arc_samples + 4 * m
        return cls(h, period, r, th, [v] * n, 2 * m, phase, v)

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
        if math.isinf(th):  # a long arc: the circle wherever the window has left the line
            on = (yx >= 0) | (self.sbar > r * math.pi / 2)
            return np.minimum(d, np.where(on, np.abs(np.hypot(yx, yy - r) - r), np.inf))
        turn = np.mod(np.arctan2(yy - r, yx) + math.pi / 2, 2 * math.pi)
        ex, ey = r * math.sin(th), r * (1 - math.cos(th))
        arc = np.where(turn <= th, np.abs(np.hypot(yx, yy - r) - r), np.hypot(yx - ex, yy - ey))
        along = (yx - ex) * math.cos(th) + (yy - ey) * math.sin(th)
        across = np.abs(-(yx - ex) * math.sin(th) + (yy - ey) * math.cos(th))
        return np.minimum(np.minimum(d, arc), np.where(along >= 0, across, np.hypot(yx - ex, yy - ey)))

    def today(self):
        """The interpolator's command today: c blended in (out) linearly over the arc's first
        (last) min(L/2, 2 T v) of path."""
        px, py, nx, ny, _, _ = self.geometry(self.s)
        blend = min(self.len / 2, 2 * self.t * self.v)
        w = np.clip(np.minimum(self.s, self.len - self.s) / blend, 0, 1) * self.on
        return px + w * self.c * nx, py + w * self.c * ny

    def with_rows(self, rows_in, rows_out):
        """The command with the arc's first (last) len(rows) samples offset by rows[j] =
        (radial / c, tangential * x / c), scaled by each sample's own c and x; the exit mirrored
        (its tangential part reversed). Where both ends reach a sample, both offsets add."""
        px, py, nx, ny, tx, ty = self.geometry(self.s)
        cx, cy = px + self.on * self.c * nx, py + self.on * self.c * ny
        for i in np.where(self.on)[0]:
            for j, rows, sign in ((self.j_in[i], rows_in, 1), (self.j_out[i], rows_out, -1)):
                if j < len(rows):
                    rad = (rows[j][0] - 1) * self.c[i]
                    tan = sign * rows[j][1] * self.c[i] / self.rate[i]
                    cx[i] += rad * nx[i] + tan * tx[i]
                    cy[i] += rad * ny[i] + tan * ty[i]
        return cx, cy

    def measure(self, cx, cy):
        """Worst distance / loss, worst |y - x(sbar)| / loss, output speed range / v, largest
        output jerk (mm/s^3), largest command step / (v T)."""
        yx, yy = self.conv @ cx, self.conv @ cy
        qx, qy, _, _, _, _ = self.geometry(self.sbar)
        full = slice(self.m + 4, None)
        speed = np.hypot(np.diff(yx), np.diff(yy))[full] / self.t
        jerk = np.hypot(np.diff(yx, 3), np.diff(yy, 3))[full] / self.t ** 3
        step = np.hypot(np.diff(cx), np.diff(cy)).max() / (self.v * self.t)
        return (self.distance(yx, yy)[self.valid].max() / self.loss,
                np.hypot(yx - qx, yy - qy)[self.valid].max() / self.loss,
                (speed.min() / self.v, speed.max() / self.v), jerk.max(), step)

    def fit(self, k, lam, iters=40, issued=None, free_from=0):
        """Offsets on the arc's first and last k samples minimising the worst distance. Returns
        the command and the entry's rows (radial / c, tangential * x / c). With `issued` (a
        command (cx, cy)), the samples before `free_from` are already commanded as it says and
        only the later ones are fitted (a refit when the speeds change)."""
        px, py, nx, ny, tx, ty = self.geometry(self.s)
        near = self.on & (np.minimum(self.j_in, self.j_out) < k)
        base_x = px + (self.on & ~near) * self.c * nx
        base_y = py + (self.on & ~near) * self.c * ny
        if issued is not None:
            done = np.arange(len(self.s)) < free_from
            base_x, base_y = np.where(done, issued[0], base_x), np.where(done, issued[1], base_y)
            near = near & ~done
        cols = []  # (sample, direction): radial and tangential, in units of the sample's c
        for i in np.where(near)[0]:
            cols.append((i, self.c[i] * nx[i], self.c[i] * ny[i]))
            cols.append((i, self.c[i] * tx[i], self.c[i] * ty[i]))
        n, f = len(self.s), len(cols)
        ux, uy = np.zeros((n, f)), np.zeros((n, f))
        for q, (i, dx, dy) in enumerate(cols):
            ux[i, q], uy[i, q] = dx, dy
        cux, cuy = self.conv @ ux, self.conv @ uy
        y0x, y0y = self.conv @ base_x, self.conv @ base_y
        u, weight, eps = np.zeros(f), np.ones(int(self.valid.sum())), 1e-7 * self.r
        best, best_u = math.inf, u
        for it in range(iters + 1):
            yx, yy = y0x + cux @ u, y0y + cuy @ u
            d = self.distance(yx, yy)
            if d[self.valid].max() < best:  # the reweighting can overshoot: keep the best pass
                best, best_u = d[self.valid].max(), u
            if it == iters:
                break
            gx = (self.distance(yx + eps, yy) - d) / eps
            gy = (self.distance(yx, yy + eps) - d) / eps
            a = (gx[:, None] * cux + gy[:, None] * cuy)[self.valid]
            rhs = d[self.valid] - a @ u
            lhs = np.vstack([a * np.sqrt(weight)[:, None], math.sqrt(lam) * self.c_arc * np.eye(f)])
            u = np.linalg.lstsq(lhs, np.concatenate([-rhs * np.sqrt(weight), np.zeros(f)]),
                                rcond=None)[0]
            e = np.abs(a @ u + rhs)
            weight = weight * (e / e.max() + 1e-3)
            weight /= weight.mean()
        u = best_u
        rows = {}
        for q, (i, _, _) in enumerate(cols):
            if self.j_in[i] < k and self.j_in[i] <= self.j_out[i]:
                row = rows.setdefault(self.j_in[i], [0.0, 0.0])
                row[q % 2] += u[q] * (self.rate[i] if q % 2 else 1.0)
        return base_x + ux @ u, base_y + uy @ u, [tuple(rows[j]) for j in sorted(rows)]


class Tables:
    """Entry rows fitted once on long arcs at constant rate, per rate knot and phase of the join
    within its sample; linear between knots and between phases."""

    def __init__(self, h, period, knots, k, lam, phases):
        self.knots, self.phases = knots, phases
        self.rows = [[Arc.steady(h, period, x / period, 1.0, phase=p).fit(k, lam)[2]
                      for p in phases] for x in knots]

    @staticmethod
    def _mix(a, b, f):
        return [(p[0] * (1 - f) + q[0] * f, p[1] * (1 - f) + q[1] * f) for p, q in zip(a, b)]

    @staticmethod
    def _bracket(grid, value):
        j = min(max([i for i, g in enumerate(grid) if g <= value] or [0]), len(grid) - 2)
        return j, min(max((value - grid[j]) / (grid[j + 1] - grid[j]), 0.0), 1.0)

    def at(self, x, phase):
        j, f = self._bracket(self.knots, x)
        i, g = self._bracket(self.phases, phase)
        lo = self._mix(self.rows[j][i], self.rows[j][i + 1], g)
        hi = self._mix(self.rows[j + 1][i], self.rows[j + 1][i + 1], g)
        return self._mix(lo, hi, f)

    def command(self, arc):
        """Both ends from the tables at the arc's rate and each end's phase."""
        return arc.with_rows(self.at(arc.x, arc.phase_in), self.at(arc.x, arc.phase_out))


def phases_of(count):
    return [0.001 + 0.998 * j / count for j in range(count + 1)]


def ramp(h, x0, low):
    """A steady arc of unit radius at rate x0, the speed ramped to low * x0 over the window (the
    interpolator's rate limit), held 60 samples and ramped back, c following the command's rate:
    the worst distance and the worst |y - x(sbar)|, over the steady loss at x0."""
    m = len(h)
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
    radius = np.array([1 / gain(h, v) if v > 0 else 1.0 for v in rates])
    n = len(rates)
    yx = np.convolve(radius * np.sin(angle), h)[:n]
    yy = np.convolve(1 - radius * np.cos(angle), h)[:n]
    sbar = np.convolve(angle, h)[:n]
    full = np.arange(n) >= m - 1
    loss = 1 - gain(h, x0)
    dist = np.abs(np.hypot(yx, yy - 1) - 1)[full].max()
    vec = np.hypot(yx - np.sin(sbar), yy - 1 + np.cos(sbar))[full].max()
    return dist / loss, vec / loss


def speed_cases(m, v):
    """Speed profiles around an entry (samples, the join's index), the arc at v: the line at
    another speed stepping at the join, the interpolator's ramp (v/m per sample) through the
    join, and a start from rest at the join."""
    def ramp_between(a, b):
        out, s = [], a
        while abs(s - b) > 1e-12:
            s = min(b, s + v / m) if b > a else max(b, s - v / m)
            out.append(s)
        return out
    up = ramp_between(0.4 * v, v)
    down = ramp_between(v, 0.4 * v)
    rest = ramp_between(0.0, v)
    return [("line at 0.5 v, step at the join", [0.5 * v] * 3 * m + [v] * 4 * m, 3 * m),
            ("line at 2 v, step at the join", [2 * v] * 3 * m + [v] * 4 * m, 3 * m),
            ("ramp 0.4 v to v through the join", [0.4 * v] * 3 * m + up + [v] * 4 * m,
             3 * m + len(up) // 2),
            ("ramp v to 0.4 v through the join", [v] * 3 * m + down + [0.4 * v] * 4 * m,
             3 * m + len(down) // 2),
            ("from rest at the join", [1e-9] * 3 * m + rest + [v] * 4 * m, 3 * m)]


def override_near_join(h, period, x, low, start):
    """Speeds for an entry at rate x whose override ramps (x/window per sample) to low·x from
    sample `start` relative to the join on."""
    m = len(h)
    v, cur, speeds = x / period, x / period, []
    for i in range(7 * m):
        if i >= 3 * m + start:
            cur = max(low * v, cur - v / m) if low < 1 else min(low * v, cur + v / m)
        speeds.append(cur)
    return speeds


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_filter_args(ap)
    args = ap.parse_args()
    h = taps(args.gmotion, args.profile, args.tau, args.period)
    t, m = args.period, len(h)
    k, lam = 6, 1e-3
    print(f"{args.profile} tau {args.tau} s, T {t} s, {m} taps; errors / steady loss R(1 - A)")
    print()
    print("Entry: a line into a long arc of unit radius at rate x = omega*T, phase 0.25.")
    print("| correction | x | distance | abs(y - x(sbar)) | output speed / v | jerk / today's | "
          "largest command step / (v T) |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for x in (0.03, 0.06, 0.1):
        arc = Arc.steady(h, t, x / t, 1.0)
        today = arc.measure(*arc.today())
        for name, kk, lm in (("today: radial, linear over 2 samples", 2, None),
                             ("2-D, arc's first 2 samples, lam 0", 2, 0.0),
                             ("2-D, arc's first 2 samples, lam 1e-3", 2, 1e-3),
                             ("2-D, arc's first 6 samples, lam 1e-3", 6, 1e-3),
                             ("2-D, arc's first 6 samples, lam 1e-2", 6, 1e-2)):
            r = today if lm is None else arc.measure(*arc.fit(kk, lm)[:2])
            print(f"| {name} | {x} | {r[0]:.3f} | {r[1]:.3f} | {r[2][0]:.3f} to {r[2][1]:.3f} | "
                  f"{r[3] / today[3]:.2f} | {r[4]:.2f} |")
    print()
    print(f"One table of rows (2-D, {k} samples, lam {lam}) per phase of the join in its sample,")
    print("fitted at x = 0.03 and scaled (radial by c, tangential by c / x), linear between")
    print("phases, used at the phases half-way between: worst distance / loss.")
    print("| phases in the table | x = 0.02 | 0.03 | 0.06 | 0.1 | one phase (0.25) for all, x = 0.03 |")
    print("| --- | --- | --- | --- | --- | --- |")
    single = Tables(h, t, (0.03, 0.031), k, lam, [0.25, 0.251])
    worst1 = 0.0
    for p in (0.0, 0.25, 0.5, 0.75, 0.99):
        arc = Arc.steady(h, t, 0.03 / t, 1.0, phase=p)
        worst1 = max(worst1, arc.measure(*arc.with_rows(single.at(0.03, 0.25), []))[0])
    for count in (4, 8, 16):
        phases = phases_of(count)
        tables = Tables(h, t, (0.03, 0.031), k, lam, phases)
        cells = []
        for x in (0.02, 0.03, 0.06, 0.1):
            worst = 0.0
            for j in range(count):
                p = 0.5 * (phases[j] + phases[j + 1])
                arc = Arc.steady(h, t, x / t, 1.0, phase=p)
                worst = max(worst, arc.measure(*arc.with_rows(tables.at(0.03, p), []))[0])
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
    print("Rows fitted for a constant speed (x = 0.03, phase 0.4) while the override ramps to 0.4")
    print("or 1.5 of it from a sample near the join (the worst / steady loss at x = 0.03); the")
    print("samples not yet commanded refitted when the ramp starts; all fitted for the ramp:")
    print("| override to | ramp from the join's sample | today | constant-speed rows | refitted "
          "from the change | fitted for the ramp |")
    print("| --- | --- | --- | --- | --- | --- |")
    steady_rows = Arc.steady(h, t, 0.03 / t, 1.0, phase=0.4).fit(k, lam)[2]
    for low in (0.4, 1.5):
        for start in (-20, -3, 0, 2, 5, 10):
            arc = Arc(h, t, 1.0, math.inf, override_near_join(h, t, 0.03, low, start), 3 * m, 0.4,
                      0.03 / t)
            issued = arc.with_rows(steady_rows, [])
            refit = arc.fit(k, lam, issued=issued, free_from=3 * m + start)[:2]
            cells = [arc.measure(*arc.today())[0], arc.measure(*issued)[0],
                     arc.measure(*refit)[0], arc.measure(*arc.fit(k, lam)[:2])[0]]
            print(f"| {low} | {start:+d} | " + " | ".join(f"{c:.3f}" for c in cells) + " |")
    print()
    knots = (0.01, 0.03, 0.06, 0.1)
    tables = Tables(h, t, knots, k, lam, phases_of(8))
    print("Whole arcs, line - arc - line at constant speed (mm, mm/s): both ends fitted together,")
    print(f"and both from tables ({k} samples, lam {lam}, 8 phases, fitted on long arcs at")
    print(f"x = {', '.join(map(str, knots))}, linear between; the exit mirrored):")
    print("| R mm | sweep | v mm/s | x | arc in samples | steady loss um | today | 2-D, 2 + 2 samples | "
          "2-D, 6 + 6 samples | 6 + 6 from the tables |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for r, deg, v in ((1, 90, 13.5), (1, 90, 25), (2, 180, 18), (2, 180, 30), (3, 180, 22.4),
                      (4, 180, 26), (2, 90, 50)):
        arc = Arc.steady(h, t, v, r, math.radians(deg))
        cells = [f"{arc.measure(*arc.today())[0]:.3f}"]
        for kk in (2, 6):
            cells.append(f"{arc.measure(*arc.fit(kk, lam)[:2])[0]:.3f}")
        cells.append(f"{arc.measure(*tables.command(arc))[0]:.3f}")
        print(f"| {r} | {deg}° | {v} | {arc.x:.3f} | {arc.len / (v * t):.0f} | "
              f"{arc.loss * 1000:.1f} | " + " | ".join(cells) + " |")
    print()
    print("Entries into a long arc of unit radius whose speed changes near the join (worst over")
    print("the join's phases 0.1, 0.4, 0.7, 0.95): today's blend, the constant-speed tables (each")
    print("sample's own c and x), and rows fitted for that speed profile:")
    print("| x at the arc's speed | speeds | today | tables | fitted for the profile |")
    print("| --- | --- | --- | --- | --- |")
    for x in (0.03, 0.06):
        for name, speeds, join in speed_cases(m, x / t):
            cells = ["", "", ""]
            worst = [0.0, 0.0, 0.0]
            for p in (0.1, 0.4, 0.7, 0.95):
                arc = Arc(h, t, 1.0, math.inf, speeds, join, p, x / t)
                worst[0] = max(worst[0], arc.measure(*arc.today())[0])
                worst[1] = max(worst[1], arc.measure(*arc.with_rows(
                    tables.at(arc.rate[arc.first], arc.phase_in), []))[0])
                worst[2] = max(worst[2], arc.measure(*arc.fit(k, lam)[:2])[0])
            cells = [f"{w:.3f}" for w in worst]
            print(f"| {x} | {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
