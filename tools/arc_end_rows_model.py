#!/usr/bin/env python3
"""Model of the end rows the interpolator commands at a pre-compensated arc's ends
(src/interpolator/arc_end_rows.*), written apart from the C++ as its reference: the same rule
and the same fit, in numpy.

The rule: a sample u advances from an arc's start (its count since the arc's first sample plus
how far past the start that one lay, of its advance) or from its end is commanded off the arc by
radial(u)*c outwards and along(u)*c along the motion (reversed at the end), c = R(1/A(x) - 1),
piecewise linear in u with knots at u = 1, 2, 3: 0 at u = 0, the steady (1, 0) from u = 4. The
knot values depend on the rate x (knots at fractions of the limit where A = 0.5, linear
between) and come in two sets: Moving (a start, an end the command moves on from) and Stopping
(an end where it stops). Each is fitted on entries into an endless arc of unit radius at
constant rate (8 phases of the join), at half of the phases also with the speed falling at the
interpolator's ramp rate (v/(N + 1) a sample) from 0, 2 or 4 samples after the join or rising
at it to reach v 0, 2 or 4 samples after the join (an override changing near an end), and
(Moving) from rest with the ramp; Stopping on the same runs held on the join before (the stop
seen backwards in time). The fit minimises M_p^2 + mu c^2 |u|^2, M_p the power mean of
|y - x(sbar)| over all the runs' samples, p raised 2, 4, ..., 128 by Newton steps (the along
knots in units of c/x while fitted). Figures: fractions of the steady loss R(1 - A).
docs/tolerance-arc-ends.md, "End rows". Needs numpy.
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from arc_blend_model import add_filter_args, taps  # noqa: E402  (same folder)
from arc_end_model import Arc, gain  # noqa: E402

SPAN = 4
INNER = (1.0, 2.0, 3.0)
RATE_KNOTS = (0.02, 0.1, 0.3, 0.55, 0.8, 1.0)
MU = 1e-4
PHASES = 8


def limit(h):
    """The rate where A falls to 0.5."""
    lo, hi = 0.0, 1e-3
    while gain(h, hi) >= 0.5:
        lo, hi = hi, hi + 1e-3
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if gain(h, mid) >= 0.5 else (lo, mid)
    return lo


def basis(u):
    """The fixed part and the hat weights of the inner knots at u."""
    hat = np.zeros(len(INNER))
    if u <= 0:
        return 0.0, hat
    if u >= SPAN:
        return 1.0, hat
    k = min(int(u), SPAN - 1)
    f = u - k
    fixed = 0.0
    if k >= 1:
        hat[k - 1] += 1 - f
    if k + 1 <= len(INNER):
        hat[k] += f
    else:
        fixed = f
    return fixed, hat


def entry_u(arc, advance=None):
    """Per sample on the arc: its count since the first plus the first's phase (of its own
    advance, or of `advance`)."""
    u = np.full(len(arc.s), np.inf)
    on = np.where(arc.on)[0]
    adv = arc.rate * arc.r
    phase = arc.s[on[0]] / (adv[on[0]] if advance is None else advance)
    u[on] = np.arange(len(on)) + phase
    return u


def fit_knots(h, period, x, runs, stopping, mu=MU):
    """The six knot values (radial, then along in units of c/x) for `runs` (Arc) at rate x."""
    r0s, jacs = [], []
    c_unit = None
    for arc in runs:
        px, py, nx, ny, tx, ty = arc.geometry(arc.s)
        bx, by = px.copy(), py.copy()
        n = len(arc.s)
        cx, cy = np.zeros((n, 6)), np.zeros((n, 6))
        u = entry_u(arc, x if stopping else None)
        for i in np.where(arc.on)[0]:
            fixed, hat = basis(u[i])
            c = arc.c[i]
            bx[i] += fixed * c * nx[i]
            by[i] += fixed * c * ny[i]
            cx[i, :3], cy[i, :3] = hat * c * nx[i], hat * c * ny[i]
            cx[i, 3:], cy[i, 3:] = hat * c / x * tx[i], hat * c / x * ty[i]
        qx, qy, _, _, _, _ = arc.geometry(arc.sbar)
        v = arc.valid
        r0s.append(np.stack([(arc.conv @ bx - qx)[v], (arc.conv @ by - qy)[v]], axis=1))
        jacs.append(np.stack([(arc.conv @ cx)[v], (arc.conv @ cy)[v]], axis=1))
        if c_unit is None:
            c_unit = arc.c_arc
    r0, jac = np.concatenate(r0s), np.concatenate(jacs)
    reg = mu * c_unit ** 2
    u = np.zeros(6)

    def objective(w, p):
        d = np.linalg.norm(r0 + jac @ w, axis=1)
        t0 = d.max()
        return (t0 * np.mean((d / t0) ** p) ** (1 / p)) ** 2 + reg * w @ w

    p = 2
    while p <= 128:
        for _ in range(30):
            r = r0 + jac @ u
            d = np.linalg.norm(r, axis=1)
            t0 = d.max()
            s = np.mean((d / t0) ** p)
            mp = t0 * s ** (1 / p)
            j0 = mp * mp + reg * u @ u
            pos = d > 0
            w = np.where(pos, 2 * s ** (2 / p - 1) / len(d) * (d / t0) ** (p - 2), 0.0)
            jr = np.einsum('kdf,kd->kf', jac, r)
            g = 2 * reg * u + jr.T @ w
            hess = (2 * reg * np.eye(6) + np.einsum('k,kdf,kdg->fg', w, jac, jac)
                    + np.einsum('k,kf,kg->fg', w * (p - 2) / np.where(pos, d, 1.0) ** 2, jr, jr))
            gm = g - 2 * reg * u
            whole = hess - (0.5 * p - 1) / (mp * mp) * np.outer(gm, gm)
            try:
                np.linalg.cholesky(whole)
                step = -np.linalg.solve(whole, g)
            except np.linalg.LinAlgError:
                step = -np.linalg.solve(hess, g)
            a = 1.0
            while a > 1e-6 and objective(u + a * step, p) > j0:
                a *= 0.5
            if a <= 1e-6:
                break
            u = u + a * step
            if np.linalg.norm(a * step) <= 1e-9 * (1 + np.linalg.norm(u)):
                break
        p *= 2
    return u


def fitting_runs(h, period, x, stopping):
    """The entries the knots are fitted on (see the module's doc)."""
    m, v = len(h), x / period
    runs = []
    for j in range(PHASES):
        for fall in (-1, 0, 2, 4, 10, 12, 14):
            if fall >= 0 and j % 2 == 1:
                continue
            n = 6 * m
            speeds = np.full(n, v)
            first = 2 * m
            i = np.arange(n)
            if 0 <= fall < 10:
                speeds = np.where(i >= first + fall,
                                  v * np.maximum(0.5, 1 - (i - first - fall) / m), speeds)
            if fall >= 10:  # rising to v at fall - 10 samples after the join
                speeds = v * np.clip(1 + (i - first - (fall - 10)) / m, 0.5, 1.0)
            phase = (j + 0.5) / PHASES
            if stopping:  # held on the join, the first sample `phase` of an advance past it
                speeds[:first] = 0.0
                speeds[first] *= phase
                phase = 1.0
            runs.append(Arc(h, period, 1.0, math.inf, speeds, first, phase, v))
    if not stopping:
        n, first = 6 * m, 2 * m
        i = np.arange(n)
        speeds = v * np.clip((i - first + 1) / m, 0.0, 1.0)
        runs.append(Arc(h, period, 1.0, math.inf, speeds, first, 1.0, v))
    return runs


class EndRows:
    """The knots of both sets at every rate knot, along kept in units of c."""

    def __init__(self, h, period):
        self.limit = limit(h)
        self.xs = [f * self.limit for f in RATE_KNOTS]
        self.sets = {}
        for stopping in (False, True):
            rows = []
            for x in self.xs:
                u = fit_knots(h, period, x, fitting_runs(h, period, x, stopping), stopping)
                rows.append(np.concatenate([u[:3], u[3:] / x]))
            self.sets[stopping] = np.array(rows)

    def shape(self, u, x, stopping):
        fixed, hat = basis(u)
        k = np.array([np.interp(x, self.xs, self.sets[stopping][:, q]) for q in range(6)])
        return fixed + hat @ k[:3], hat @ k[3:]

    def command(self, arc, stopping=False):
        """An arc at constant speed commanded by the rows, both ends."""
        px, py, nx, ny, tx, ty = arc.geometry(arc.s)
        cx, cy = px.copy(), py.copy()
        u_in = entry_u(arc)
        adv = arc.rate * arc.r
        for i in np.where(arc.on)[0]:
            c, x = arc.c[i], arc.rate[i]
            rad, along = 1.0, 0.0
            for u, sign, stop in ((u_in[i], 1, False), ((arc.len - arc.s[i]) / adv[i], -1, stopping)):
                if u < SPAN:
                    r, a = self.shape(u, x, stop)
                    rad += r - 1.0
                    along += sign * a
            cx[i] += rad * c * nx[i] + along * c * tx[i]
            cy[i] += rad * c * ny[i] + along * c * ty[i]
        return cx, cy


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    add_filter_args(ap)
    args = ap.parse_args()
    h = taps(args.gmotion, args.profile, args.tau, args.period)
    t = args.period
    rows = EndRows(h, t)
    print(f"{args.profile} tau {args.tau} s, T {t} s, {len(h)} taps, limit {rows.limit:.7f}")
    print("| rate / limit | set | radial at u = 1, 2, 3 | along (x c) at u = 1, 2, 3 |")
    print("| --- | --- | --- | --- |")
    for stopping in (False, True):
        for f, k in zip(RATE_KNOTS, rows.sets[stopping]):
            print(f"| {f} | {'stopping' if stopping else 'moving'} | "
                  f"{', '.join(f'{v:.3f}' for v in k[:3])} | {', '.join(f'{v:.3f}' for v in k[3:])} |")
    print()
    print("A unit arc of 300.5 samples at constant speed, both ends by the rows (moving), and the")
    print("radial blend: worst |y - x(sbar)| and worst distance / steady loss.")
    print("| rate / limit | phase | rows | blend | rows, distance | blend, distance |")
    print("| --- | --- | --- | --- | --- | --- |")
    for frac, phase in ((0.3, 0.25), (0.45, 0.37), (0.8, 0.9)):
        x = frac * rows.limit
        arc = Arc.steady(h, t, x / t, 1.0, th=300.5 * x, phase=phase)
        new, old = arc.measure(*rows.command(arc)), arc.measure(*arc.today())
        print(f"| {frac} | {phase} | {new[1]:.4f} | {old[1]:.4f} | {new[0]:.4f} | {old[0]:.4f} |")


if __name__ == "__main__":
    main()
