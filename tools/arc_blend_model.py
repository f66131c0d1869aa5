#!/usr/bin/env python3
"""Model of a pre-compensated arc's entry: the worst distance of the Acc/Dec output from the path
while a line runs into a long arc at constant speed, as a fraction of the steady loss R(1 - A).

The filter's taps come from `gmotion design --json` (default: Blackman, tau 0.164 s, T 4 ms).
Unit radius, rate x = omega*T, samples at a quarter sample's phase; error |y - x(sbar)| as the
planner's check (ArcPrecompCheck) measures it. Corrections compared (docs/tolerance-arc-ends.md,
"Starting the correction on the line before the arc"):
  * the interpolator's linear blend over the arc's first 2 samples, and a step at its start;
  * a radial ramp that starts on the line before the arc;
  * the least-squares best correction on the samples from -K1 (on the line) to K2 (on the arc),
    radial only, or in any direction (radial and tangential), with a Tikhonov weight lam.
The exit mirrors the entry (symmetric taps), so the arc's two ends leave the same.
"""
import argparse
import json
import math
import subprocess


def taps(gmotion, profile, tau, period):
    out = subprocess.run([gmotion, "design", "--json", "--profile", profile, "--tau", str(tau),
                          "--period", str(period)], check=True, capture_output=True, text=True)
    d = json.loads(out.stdout)
    return [t / d["b_s"] for t in d["taps_int"]]


class Entry:
    def __init__(self, h, x, phase=0.25):
        self.h, self.n, self.x = h, len(h), x
        m = sum(i * w for i, w in enumerate(h))
        self.gain = sum(w * math.cos((i - m) * x) for i, w in enumerate(h))
        self.c = 1.0 / self.gain - 1.0  # steady correction, units of R
        self.loss = 1.0 - self.gain
        self.ks = list(range(-3 * self.n, 3 * self.n))
        self.s = [(k + phase) * x for k in self.ks]

    @staticmethod
    def point(s):
        return (s, 0.0) if s <= 0 else (math.sin(s), 1.0 - math.cos(s))

    @staticmethod
    def frame(s):  # outward normal, tangent
        if s <= 0:
            return (0.0, -1.0), (1.0, 0.0)
        return (math.sin(s), -math.cos(s)), (math.cos(s), math.sin(s))

    def output(self, cmd, k):
        h = self.h
        yx = sum(h[i] * cmd[k - i][0] for i in range(self.n))
        yy = sum(h[i] * cmd[k - i][1] for i in range(self.n))
        sb = sum(h[i] * self.s[k - i] for i in range(self.n))
        return yx, yy, self.point(sb)

    def worst(self, cmd):
        w = 0.0
        for k in range(self.n - 1, len(self.s)):
            yx, yy, p = self.output(cmd, k)
            w = max(w, math.hypot(yx - p[0], yy - p[1]))
        return w / self.loss

    def commanded(self, radial):  # radial(s/(vT)) -> fraction of c along the outward normal
        cmd = []
        for s in self.s:
            p = self.point(s)
            nn, _ = self.frame(s)
            w = radial(s / self.x)
            cmd.append((p[0] + w * self.c * nn[0], p[1] + w * self.c * nn[1]))
        return cmd

    def least_squares(self, k1, k2, lam, tangential):
        """Free samples -k1 <= k < k2 (radial, or radial and tangential), the steady correction
        from k2 on, nothing before -k1: minimise the sum of squared errors. Returns the worst
        error / loss and the largest offset of the command from the line before the arc / c."""
        base = self.commanded(lambda p: 1.0 if p >= k2 else 0.0)
        free = []  # (sample index, direction vector)
        for j, (k, s) in enumerate(zip(self.ks, self.s)):
            if -k1 <= s / self.x < k2:
                nn, tt = self.frame(s)
                free.append((j, (self.c * nn[0], self.c * nn[1])))
                if tangential:
                    free.append((j, (self.c * tt[0], self.c * tt[1])))
        col = {}
        for q, (j, _) in enumerate(free):
            col.setdefault(j, []).append(q)
        f = len(free)
        a = [[0.0] * f for _ in range(f)]
        b = [0.0] * f
        for k in range(self.n - 1, len(self.s)):
            yx, yy, p = self.output(base, k)
            rx, ry = yx - p[0], yy - p[1]
            items = []
            for i in range(self.n):
                for q in col.get(k - i, []):
                    d = free[q][1]
                    items.append((q, self.h[i] * d[0], self.h[i] * d[1]))
            for q, ax, ay in items:
                b[q] -= ax * rx + ay * ry
                for r, bx, by in items:
                    a[q][r] += ax * bx + ay * by
        for q in range(f):
            a[q][q] += lam * self.c * self.c
        u = solve(a, b)
        cmd = [list(p) for p in base]
        for q, (j, d) in enumerate(free):
            cmd[j][0] += u[q] * d[0]
            cmd[j][1] += u[q] * d[1]
        off = 0.0
        for j, _ in free:
            if self.s[j] <= 0:
                off = max(off, math.hypot(cmd[j][0] - self.s[j], cmd[j][1]))
        # The shape in samples of travel (radial, tangential) per free sample.
        shape = {}
        for q, (j, d) in enumerate(free):
            nn, tt = self.frame(self.s[j])
            key = self.s[j] / self.x
            r_, t_ = shape.get(key, (0.0, 0.0))
            along_n = (d[0] * nn[0] + d[1] * nn[1]) / self.c
            along_t = (d[0] * tt[0] + d[1] * tt[1]) / self.c
            shape[key] = (r_ + u[q] * along_n, t_ + u[q] * along_t)
        self.shape = sorted(shape.items())
        return self.worst(cmd), off / self.c

    def with_shape(self, shape, k2, stretch):
        """The command with a shape fitted at another speed: its knots at samples of travel
        p·stretch (stretch = v_fit/v: the interpolator places it by path length), linear
        between them, the steady c·n from k2·stretch on."""
        cmd = []
        for s in self.s:
            p = s / self.x
            nn, tt = self.frame(s)
            pt = self.point(s)
            if p >= k2 * stretch:
                wr, wt = 1.0, 0.0
            elif p < shape[0][0] * stretch:
                wr, wt = 0.0, 0.0
            else:
                wr, wt = shape[-1][1]
                for (a, va), (b, vb) in zip(shape, shape[1:]):
                    if a * stretch <= p < b * stretch:
                        f = (p / stretch - a) / (b - a)
                        wr = va[0] * (1 - f) + vb[0] * f
                        wt = va[1] * (1 - f) + vb[1] * f
                        break
            cmd.append((pt[0] + self.c * (wr * nn[0] + wt * tt[0]),
                        pt[1] + self.c * (wr * nn[1] + wt * tt[1])))
        return self.worst(cmd)


def solve(a, b):
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(n):
            if r != c and m[r][c] != 0.0:
                f = m[r][c] / m[c][c]
                m[r] = [x - f * y for x, y in zip(m[r], m[c])]
    return [m[i][n] / m[i][i] for i in range(n)]


def ramp(a, b):  # linear from -a to +b samples' travel around the arc's start
    return lambda k: 0.0 if k <= -a else 1.0 if k >= b else (k + a) / (a + b)


def add_filter_args(ap):
    """The filter's options of the arc models: the gmotion binary, profile, tau and period."""
    ap.add_argument("--gmotion", default="build/bin/gmotion")
    ap.add_argument("--profile", default="blackman")
    ap.add_argument("--tau", type=float, default=0.164)
    ap.add_argument("--period", type=float, default=0.004)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_filter_args(ap)
    ap.add_argument("--rates", type=float, nargs="+", default=[0.03, 0.1, 0.2], help="x = omega*T")
    ap.add_argument("--lam", type=float, default=1e-3)
    args = ap.parse_args()
    h = taps(args.gmotion, args.profile, args.tau, args.period)
    n = len(h)
    print(f"{args.profile} tau {args.tau} s, T {args.period} s, {n} taps; worst error / steady loss")
    print("| correction | " + " | ".join(f"x = {x}" for x in args.rates) + " |")
    print("| --- |" + " --- |" * len(args.rates))
    models = [Entry(h, x) for x in args.rates]

    def row(name, f):
        print(f"| {name} | " + " | ".join(f(e) for e in models) + " |")

    row("linear blend over the arc's first 2 samples (today)", lambda e: f"{e.worst(e.commanded(ramp(0, 2))):.3f}")
    row("step at the arc's start", lambda e: f"{e.worst(e.commanded(ramp(0, 1e-9))):.3f}")
    for a in (10, n):
        row(f"radial ramp over the line's last {a} samples", lambda e, a=a: f"{e.worst(e.commanded(ramp(a, 0))):.3f}")
    for k1, k2, tan in ((0, 4, False), (0, 20, False), (0, 4, True), (0, 20, True), (10, 10, True),
                        (20, 20, True), (n, 20, True)):
        name = (f"least squares, {'radial and tangential' if tan else 'radial'}, "
                f"line's last {k1}, arc's first {k2} samples")
        row(name, lambda e, k1=k1, k2=k2, tan=tan: "{:.3f} (line offset {:.1f} c)".format(
            *e.least_squares(k1, k2, args.lam, tan)) if k1 else
            f"{e.least_squares(k1, k2, args.lam, tan)[0]:.3f}")
    print()
    print("A 2-D least-squares shape fitted at x, used at 0.6·x (placed by path length, as the")
    print("interpolator would): worst error at 0.6·x / steady loss at x (the check takes both)")
    for x in args.rates:
        for k1, k2, w_fit, w_slow in speeds(h, x, args.lam):
            print(f"x = {x}: line's last {k1}, arc's first {k2} samples: {w_fit:.3f} at x, "
                  f"{w_slow:.3f} at 0.6·x")


def speeds(h, x, lam):
    """2-D shapes fitted at rate x, then used at 0.6·x as the check also simulates (stretched:
    placed by path length); the error at 0.6·x against the steady loss at x."""
    rows = []
    for k1, k2 in ((0, 4), (0, 20), (20, 20)):
        fit = Entry(h, x)
        w_fit, _ = fit.least_squares(k1, k2, lam, True)
        slow = Entry(h, 0.6 * x)
        rows.append((k1, k2, w_fit, slow.with_shape(fit.shape, k2, 1.0 / 0.6) * slow.loss / fit.loss))
    return rows


if __name__ == "__main__":
    main()
