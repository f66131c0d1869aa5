#!/usr/bin/env python3
"""Random LinuxCNC lathe-cycle programs (G70, G71/G71.1/G71.2, G72/G72.1/G72.2) for
tools/rs274_diff.py: a profile subroutine of G1 lines and G2/G3 arcs (R or I K), with fillets A and
chamfers C, sometimes a pocket, in G7 or G8, mm or inch, sometimes on G55 or written in G91
increments; one cycle with random D I R (G70: D P). Many are refused by rs274 (not monotonic,
parallel lines): those only check that gmotion refuses them too.

Usage: gen_random_g7x.py DIR FIRST_SEED COUNT   (writes DIR/g7x-SEED.ngc)
COUNT is shrunk by GMOTION_TEST_SCALE (a fraction in (0, 1]), as rs274_diff.py shrinks --random:
the asan test preset compares the first seeds only.
"""
import cmath
import math
import os
import random
import sys
from pathlib import Path


def program(seed: int) -> str:
    r = random.Random(seed)
    out = ["G18 %s G90 G40 %s" % (r.choice(["G21", "G21", "G20"]), r.choice(["G8", "G8", "G7"])),
           "F%d" % r.randint(50, 400)]
    if r.random() < 0.3:
        out += ["G10 L2 P2 X%.2f Z%.2f" % (r.uniform(-5, 5), r.uniform(-5, 5)), "G55"]
    facing = r.random() < 0.4
    sz, sx = r.choice([1, -1]), r.choice([1, -1])
    # The profile in a frame of its own: u along the cut (decreasing), v across it.
    u, v = 0.0, r.uniform(2, 6)
    v_first = v
    body = []
    pocket = r.random() < 0.3
    n = r.randint(2, 7)
    for k in range(n):
        du = -r.uniform(1, 6)
        dv = r.uniform(-2 if pocket else 0, 4) if r.random() < 0.7 else 0.0
        extra = ""
        if k < n - 1 and r.random() < 0.2:
            extra = " A%.2f" % r.uniform(0.2, 0.6)
        elif k < n - 1 and r.random() < 0.15:
            extra = " C%.2f" % r.uniform(0.2, 0.6)
        if r.random() < 0.25 and abs(dv) > 0.5:
            rad = math.hypot(du, dv) / 2 * r.uniform(1.05, 2.5)
            body.append((r.choice(["G2", "G3"]), u + du, v + dv, rad, extra))
        else:
            body.append(("G1", u + du, v + dv, None, extra))
        u, v = u + du, v + dv

    def xz(uu, vv):  # (X, Z) of a profile point
        return (uu * sx + 20 * sx, vv * sz) if facing else (vv * sx, uu * sz)

    x0, z0 = xz(0.0, v_first)
    inc = r.random() < 0.25
    use_ik = r.random() < 0.5
    # The cycle starts beyond the profile.
    if facing:
        start = (x0 + 2 * sx, (max([v_first] + [b[2] for b in body]) + 2) * sz)
    else:
        start = ((max([v_first] + [b[2] for b in body]) + 2) * sx, z0 + 2 * sz)
    sub = ["O100 SUB"]
    px, pz = start if inc else (None, None)
    for g, nu, nv, rad, extra in [("G0", 0.0, v_first, None, "")] + body:
        x, z = xz(nu, nv)
        x, z = float("%.3f" % x), float("%.3f" % z)
        words = extra
        if rad is not None:
            if use_ik:  # the centre R gives, as I K from the start
                s, e = complex(pz_abs, px_abs), complex(z, x)
                d = 1j * math.sqrt((rad * rad - abs(e - s) ** 2 / 4) / abs(e - s) ** 2) * (e - s)
                c = (s + e) / 2 + (d if g == "G3" else -d)
                words = " I%.4f K%.4f" % (c.imag - px_abs, c.real - pz_abs) + extra
            else:
                words = " R%.3f" % rad + extra
        if inc:
            sub.append("  %s X%.3f Z%.3f%s" % (g, x - px, z - pz, words))
            px, pz = x, z
        else:
            sub.append("  %s X%.3f Z%.3f%s" % (g, x, z, words))
        px_abs, pz_abs = x, z
    sub.append("O100 ENDSUB")
    out += sub
    out.append("G0 X%.3f Z%.3f" % start)
    if inc:
        out.append("G91")
    words = "" if inc else " X%.3f Z%.3f" % start
    d = r.choice([0, 0.2, 0.5, 1.0])
    cyc = r.choice(["G71", "G71.1", "G71.2", "G72", "G72.1", "G72.2", "G70"])
    if cyc == "G70":
        out.append("G70 Q100%s D%g P%d" % (words, d, r.randint(1, 3)))
    else:
        out.append("%s Q100%s D%g I%g R%g" % (cyc, words, d, r.choice([0.5, 0.8, 1, 1.5]),
                                             r.choice([0.3, 0.5, 1])))
    if inc:
        out.append("G90")
    out.append("M2")
    return "\n".join(out) + "\n"


def main() -> int:
    if len(sys.argv) != 4:
        print(__doc__, file=sys.stderr)
        return 2
    d = Path(sys.argv[1])
    d.mkdir(parents=True, exist_ok=True)
    for old in d.glob("g7x-*.ngc"):
        old.unlink()
    first, count = int(sys.argv[2]), int(sys.argv[3])
    try:
        scale = float(os.environ.get("GMOTION_TEST_SCALE", "1"))
    except ValueError:
        scale = 1.0
    if 0.0 < scale < 1.0:
        count = max(1, round(count * scale))
    for s in range(first, first + count):
        (d / f"g7x-{s}.ngc").write_text(program(s))
    return 0


if __name__ == "__main__":
    sys.exit(main())
