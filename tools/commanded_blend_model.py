#!/usr/bin/env python3
"""A commanded blend at a corner, through the default filter: what it leaves of the corner's
rounding (docs/tolerance.md, "Not done": the commanded blend inside P).

A corner turning by theta between two lines at constant path speed v; the command either keeps
the sharp vertex, or replaces it by a blend arc of radius Rb tangent to both lines, either as it
is or pre-compensated (commanded on Rb/A(x), x = v*T/Rb, the steady correction only, no end
rows). The filter's output (the weights of `gmotion design --json`) is judged by its worst
distance from the sharp corner's path (the programmed one), over 8 phases of the vertex within
its sample. Prints the sharp corner's error and each blend's, in um. Needs numpy; GMOTION names
the gmotion binary (default build/bin/gmotion).
"""
import json
import os
import subprocess
import sys

import numpy as np

TOP = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
T = 0.004


def weights():
    gm = os.environ.get("GMOTION", os.path.join(TOP, "build", "bin", "gmotion"))
    d = json.loads(subprocess.run([gm, "design", "--json"], capture_output=True, check=True,
                                  text=True).stdout)

    def find(o):
        if isinstance(o, dict):
            for k, v in o.items():
                if k in ("taps", "weights") and isinstance(v, list):
                    return v
                r = find(v)
                if r:
                    return r
        if isinstance(o, list):
            for v in o:
                r = find(v)
                if r:
                    return r
        return None

    h = np.array(find(d), float)
    return h / h.sum()


def path(s, th, rb, c=0.0):
    """Points at path lengths s of the blended path (rb 0: the sharp corner), the blend's samples
    moved outwards by c (its steady correction)."""
    t = rb * np.tan(th / 2.0)
    length = rb * th
    u2 = np.array([np.cos(th), np.sin(th)])
    out = np.zeros((len(s), 2))
    for i, q in enumerate(s):
        if q < -t:
            out[i] = [q, 0.0]
        elif rb > 0.0 and q < -t + length:
            a = (q + t) / rb
            p = np.array([-t + rb * np.sin(a), rb * (1.0 - np.cos(a))])
            n = p - np.array([-t, rb])
            out[i] = p + c * n / np.linalg.norm(n)
        else:
            out[i] = t * u2 + (q - (-t + length)) * u2
    return out


def sharp_distance(y, th):
    u2 = np.array([np.cos(th), np.sin(th)])
    d1 = np.where(y[:, 0] <= 0.0, np.abs(y[:, 1]), np.hypot(y[:, 0], y[:, 1]))
    along = y @ u2
    across = y @ np.array([-u2[1], u2[0]])
    d2 = np.where(along >= 0.0, np.abs(across), np.hypot(y[:, 0], y[:, 1]))
    return np.minimum(d1, d2)


def worst(h, th, v, rb, compensated):
    n, m = len(h), (len(h) - 1) / 2.0
    gain = None
    if compensated and rb > 0.0:
        x = v * T / rb
        gain = float((h * np.cos((np.arange(n) - m) * x)).sum())
        if gain < 0.5:  # ArcCompensation::kMinGain: not compensated
            return float("nan")
    c = rb * (1.0 / gain - 1.0) if gain else 0.0
    result = 0.0
    for phase in np.arange(8) / 8.0 + 0.01:
        s = (np.arange(-200, 200) + phase) * v * T
        p = path(s, th, rb, c)
        y = np.array([h @ p[k - n + 1:k + 1][::-1] for k in range(n - 1, len(s))])
        result = max(result, float(sharp_distance(y, th).max()))
    return result


def main():
    h = weights()
    radii = (0.5, 1.0, 2.0, 5.0, 10.0)
    print("| v mm/s | turn | sharp um | " + " | ".join(f"Rb {r} as is / compensated" for r in radii)
          + " |")
    print("| --- | --- | --- | " + " | ".join("---" for _ in radii) + " |")
    for v in (10.0, 20.0, 40.0):
        for deg in (2.0, 7.6, 13.0, 30.0):
            th = np.radians(deg)
            cells = [f"{1e3 * worst(h, th, v, rb, False):.2f} / {1e3 * worst(h, th, v, rb, True):.2f}"
                     for rb in radii]
            print(f"| {v:.0f} | {deg}° | {1e3 * worst(h, th, v, 0.0, False):.2f} | "
                  + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
