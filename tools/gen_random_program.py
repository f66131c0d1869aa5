#!/usr/bin/env python3
"""Seeded generator of random plain RS274/NGC programs for the rs274 differential test.

generate(seed, blocks=40, features=DEFAULT_FEATURES) -> str returns a program that LinuxCNC's
rs274 accepts: G20/G21, G17/G18/G19, G90/G91, G0/G1, IJK and R arcs (both R signs), helices,
full circles, P multi-turn arcs, feeds, G4 dwells, comments, ending with M2.

Arcs are built from an actual centre so that start and end radii agree to ~1e-6 program units
(far inside every LinuxCNC arc tolerance); coordinates are written with 6 decimals and the
generator tracks the position the interpreter will compute from exactly those decimals.

Command line: gen_random_program.py --seed S [--blocks N] [--features +g93,-syntax]
"""
from __future__ import annotations

import argparse
import math
import random
import sys

MM_PER_INCH = 25.4

# Optional features (name -> on by default?).
#   syntax     lowercase letters, spaces between letter and number, '.5' style, leading '+'
#   comments   (paren) and ; comments, comment-only lines, blank lines
#   units      G20/G21 switches inside the program (the first line always picks one)
#   incremental G91 blocks
#   arcs_r     R-format arcs
#   multiturn  P>1 arcs
#   dwell      G4 dwells
#   g92        G92 axis offsets (set the current position) and G92.1 (clear)
#   g93        inverse-time feed blocks (G93 ... G94)                      [opt-in]
#   offsets    G10 L2 work offsets, G54..G59.3, tool changes from the default table (T M6, then
#              G43/G43 H/G43.1/G49 on the next line), G53 moves, G28.1/G28 [opt-in]
#   rotation   with offsets: G10 L2 ... R turns a coordinate system's XY (arcs stay in G17
#              while the active system is turned: LinuxCNC tilts G18/G19 arcs)     [opt-in]
#   unit_feed  F in the same block as G20/G21, and feed carried across a
#              unit change without a new F (LinuxCNC: F is executed before G20/G21, and the
#              canon keeps the physical rate)                              [opt-in]
DEFAULT_FEATURES = {
    "syntax": True,
    "comments": True,
    "units": True,
    "incremental": True,
    "arcs_r": True,
    "multiturn": True,
    "dwell": True,
    "g92": True,
    "g93": False,
    "unit_feed": False,
    "offsets": False,
    "rotation": False,
}

# gmotion's built-in default tool table (tools/rs274_diff.py gives it to both sides): Z, mm.
DEFAULT_TOOL_Z_MM = {1: 50.0, 2: 60.0, 3: 45.0, 4: 70.0}
COORD_CODES = ["54", "55", "56", "57", "58", "59", "59.1", "59.2", "59.3"]

# In-plane axis indices (first, second) and the normal axis index, per plane code.
PLANES = {17: (0, 1, 2), 18: (2, 0, 1), 19: (1, 2, 0)}
AXIS_LETTERS = "XYZ"
OFFSET_LETTERS = "IJK"


def parse_features(spec: str | None) -> dict:
    """'+g93,-syntax' -> a copy of DEFAULT_FEATURES with those switched; 'all' / 'none' allowed."""
    feats = dict(DEFAULT_FEATURES)
    if not spec:
        return feats
    for item in spec.split(","):
        item = item.strip()
        if not item:
            continue
        if item in ("all", "none"):
            for k in feats:
                feats[k] = item == "all"
            continue
        on = not item.startswith("-")
        name = item.lstrip("+-")
        if name not in feats:
            raise ValueError(f"unknown generator feature '{name}' (known: {', '.join(feats)})")
        feats[name] = on
    return feats


class _Gen:
    def __init__(self, seed: int, features: dict):
        self.rng = random.Random(seed)
        self.f = features
        self.inch = self.rng.random() < 0.5
        self.plane = 17
        self.incremental = False
        self.inverse_time = False
        self.pos = [0.0, 0.0, 0.0]  # current position in program units
        # per axis: is pos exactly a value written in this program's current units (G90 word)?
        # Sums of G91 increments and G20/G21 conversions can differ from the interpreters' own
        # arithmetic by an ulp, which turns an end point written "equal" to the start into a
        # near-full circle whose sweep (~0 or ~2 pi) depends on that ulp.
        self.exact = [True, True, True]
        self.g92 = [0.0, 0.0, 0.0]  # G92 offset, program units: machine = pos + g92
        self.feed_set = False  # an F is in effect in the current unit system
        self.lines: list[str] = []
        # offsets feature: offsets in mm (so unit switches need no conversion)
        self.g5x_mm = [[0.0, 0.0, 0.0] for _ in range(9)]
        self.g5x_rot = [0.0] * 9  # rotation feature: G10 L2 R, degrees
        self.cs = 0
        self.tool_mm = [0.0, 0.0, 0.0]
        self.spindle_tool = 0
        self.g28_mm = [0.0, 0.0, 0.0]
        self.tool_inch = self.inch  # units in force when the tool offset was set

    # ---- formatting -------------------------------------------------------------------------
    def unit(self) -> float:
        """Program units per mm-scaled 'size': typical move sizes are drawn in mm then scaled."""
        return 1.0 / MM_PER_INCH if self.inch else 1.0

    def num(self, v: float, decimals: int = 6) -> str:
        s = f"{v:.{decimals}f}"
        if "." in s:
            s = s.rstrip("0").rstrip(".")
        if s in ("-0", ""):
            s = "0"
        if self.f["syntax"]:
            r = self.rng.random()
            if r < 0.08 and s.startswith("0."):
                s = s[1:]  # .5
            elif r < 0.12 and s.startswith("-0."):
                s = "-" + s[2:]  # -.5
            elif r < 0.15 and not s.startswith("-"):
                s = "+" + s
        return s

    def word(self, letter: str, v: float, decimals: int = 6) -> str:
        text = self.num(v, decimals)
        if self.f["syntax"]:
            if self.rng.random() < 0.1:
                letter = letter.lower()
            if self.rng.random() < 0.05:
                text = " " + text
        return letter + text

    def emit(self, words: list[str]) -> None:
        line = " ".join(w for w in words if w)
        if self.f["comments"] and self.rng.random() < 0.1:
            line += self.rng.choice([" (move)", " ;tail comment", " (comment, with punctuation: 1.5)"])
        self.lines.append(line)

    def rounded(self, v: float) -> float:
        """The value the interpreter reads back from our 6-decimal text."""
        return float(f"{v:.6f}")

    # ---- moves --------------------------------------------------------------------------------
    def target(self, new_abs: list[float], axes: list[int]) -> list[str]:
        """Words moving the given axes to new_abs (program units); updates self.pos exactly."""
        words = []
        for a in axes:
            if self.incremental:
                d = self.rounded(new_abs[a] - self.pos[a])
                words.append(self.word(AXIS_LETTERS[a], d))
                self.pos[a] = self.pos[a] + d
                self.exact[a] = d == 0.0 and self.exact[a]
            else:
                v = self.rounded(new_abs[a])
                words.append(self.word(AXIS_LETTERS[a], v))
                self.pos[a] = v
                self.exact[a] = True
        return words

    def random_point(self) -> list[float]:
        s = self.unit()
        return [self.pos[i] + self.rng.uniform(-40, 40) * s for i in range(3)]

    def feed_words(self, must: bool, length_lb: float = 0.0) -> list[str]:
        """F words for a feed move; length_lb = a lower bound of its path length (program units)."""
        s = self.unit()
        if self.inverse_time:
            # inverse time: F is 1/minutes for this block, required on every feed move. Aim at a
            # units/min rate of 20..3000 mm/min so LinuxCNC's 0.1 units/min floor never applies.
            rate = self.rng.uniform(20.0, 3000.0) * s
            return [self.word("F", max(rate / max(length_lb, 1e-9), 1e-3), 4)]
        if must or not self.feed_set or self.rng.random() < 0.25:
            self.feed_set = True
            return [self.word("F", self.rng.uniform(20.0, 3000.0) * s, 3)]
        return []

    def gcode(self, n: str) -> str:
        if self.f["syntax"] and self.rng.random() < 0.1:
            return "g" + n
        return "G" + n

    def straight(self, rapid: bool) -> None:
        p = self.random_point()
        axes = [a for a in range(3) if self.rng.random() < 0.7] or [self.rng.randrange(3)]
        # make sure the move has non-zero length
        for a in axes:
            if abs(p[a] - self.pos[a]) < 0.05 * self.unit():
                p[a] = self.pos[a] + 1.0 * self.unit()
        words = [self.gcode("0" if rapid else "1")]
        before = list(self.pos)
        words += self.target(p, axes)
        if not rapid:
            words += self.feed_words(False, math.dist(before, self.pos))
        self.emit(words)

    def arc(self) -> None:
        rng = self.rng
        if self.g5x_rot[self.cs] and self.plane != 17:
            self.straight(rapid=False)  # turned G18/G19 arcs: LinuxCNC tilts their plane
            return
        first, second, normal = PLANES[self.plane]
        s = self.unit()
        cw = rng.random() < 0.5
        g = self.gcode("2" if cw else "3")
        start = list(self.pos)
        full = rng.random() < 0.15
        turns = 1
        if self.f["multiturn"] and rng.random() < 0.2:
            turns = rng.randint(2, 3)
        use_r = self.f["arcs_r"] and not full and rng.random() < 0.35
        helix = rng.random() < 0.3
        words = [g]
        if use_r:
            # pick an end point, then R >= half-chord (never too close to a semicircle)
            ang = rng.uniform(0, 2 * math.pi)
            chord = rng.uniform(2.0, 40.0) * s
            end = list(start)
            end[first] = start[first] + chord * math.cos(ang)
            end[second] = start[second] + chord * math.sin(ang)
            if helix:
                end[normal] = start[normal] + rng.uniform(-10, 10) * s
            axes = [first, second] + ([normal] if helix else [])
            words += self.target(end, axes)
            real_chord = math.hypot(self.pos[first] - start[first], self.pos[second] - start[second])
            length_lb = real_chord
            r = real_chord / 2 * rng.uniform(1.05, 3.0)
            if rng.random() < 0.5:
                r = -r  # the >180 degree arc
            words.append(self.word("R", r))
        else:
            radius = rng.uniform(1.0, 30.0) * s
            phi0 = rng.uniform(0, 2 * math.pi)
            # centre from the actual start so |start - centre| == radius
            c1 = start[first] - radius * math.cos(phi0)
            c2 = start[second] - radius * math.sin(phi0)
            i_off = self.rounded(c1 - start[first])
            j_off = self.rounded(c2 - start[second])
            c1 = start[first] + i_off
            c2 = start[second] + j_off
            r_true = math.hypot(i_off, j_off)
            end = list(start)
            axes: list[int] = []
            length_lb = r_true * 2 * math.pi  # full circle
            if not full:
                sweep = rng.uniform(0.2, 2 * math.pi - 0.2)
                phi1 = phi0 + sweep
                length_lb = r_true * min(sweep, 2 * math.pi - sweep) * 0.9
                end[first] = c1 + r_true * math.cos(phi1)
                end[second] = c2 + r_true * math.sin(phi1)
                axes = [first, second]
            elif rng.random() < 0.5 and not self.incremental and all(
                    self.exact[a] for a in (first, second)):
                axes = [first, second]  # full circle with the end point written out (exactly)
            if helix:
                end[normal] = start[normal] + rng.uniform(-10, 10) * s
                axes.append(normal)
            words += self.target(end, axes)
            words.append(self.word(OFFSET_LETTERS[first], i_off))
            words.append(self.word(OFFSET_LETTERS[second], j_off))
        if turns > 1:
            words.append(f"P{turns}")
        words += self.feed_words(False, length_lb)
        self.emit(words)

    def g92_offset(self) -> None:
        if self.rng.random() < 0.3:
            self.emit([self.gcode("92.1")])
            self.pos = [p + o for p, o in zip(self.pos, self.g92)]
            self.exact = [o == 0.0 and e for o, e in zip(self.g92, self.exact)]
            self.g92 = [0.0, 0.0, 0.0]
            return
        axes = [a for a in range(3) if self.rng.random() < 0.6] or [self.rng.randrange(3)]
        words = [self.gcode("92")]
        for a in axes:
            v = self.rounded(self.rng.uniform(-50, 50) * self.unit())
            words.append(self.word(AXIS_LETTERS[a], v))
            self.g92[a] += self.pos[a] - v
            self.pos[a] = v
            self.exact[a] = True
        self.emit(words)

    def dwell(self) -> None:
        self.emit([self.gcode("4"), self.word("P", self.rng.uniform(0.0, 2.0), 3)])

    def switch_units(self) -> None:
        self.inch = not self.inch
        self.pos = [p / MM_PER_INCH if self.inch else p * MM_PER_INCH for p in self.pos]
        self.g92 = [p / MM_PER_INCH if self.inch else p * MM_PER_INCH for p in self.g92]
        self.exact = [p == 0.0 for p in self.pos]
        code = "20" if self.inch else "21"
        if self.f["unit_feed"] and self.rng.random() < 0.5:
            # F in the same block as the unit change: LinuxCNC sets F first, in the old units
            self.emit([self.gcode(code), self.word("F", self.rng.uniform(20.0, 3000.0), 3)])
            self.feed_set = True
        else:
            self.emit([self.gcode(code)])
            # keep the feed unambiguous unless the edge case is wanted
            self.feed_set = self.f["unit_feed"] and self.feed_set

    # ---- offsets and tools (feature "offsets") ---------------------------------------------------
    def _offset_mm(self) -> list[float]:
        """Work offset + tool offset (mm); G92 is tracked apart in program units."""
        return [g + t for g, t in zip(self.g5x_mm[self.cs], self.tool_mm)]

    def _turn(self, q: list[float], sign: float) -> None:
        """Turns q's X and Y by the active system's rotation (sign -1: back)."""
        th = sign * math.radians(self.g5x_rot[self.cs])
        if th:
            q[0], q[1] = (q[0] * math.cos(th) - q[1] * math.sin(th),
                          q[0] * math.sin(th) + q[1] * math.cos(th))

    def _machine_mm(self) -> list[float]:
        u = MM_PER_INCH if self.inch else 1.0
        q = [(p + g) * u for p, g in zip(self.pos, self.g92)]
        self._turn(q, 1.0)  # LinuxCNC: machine = R (program + G92) + G5x + tool, in X and Y
        return [a + o for a, o in zip(q, self._offset_mm())]

    def _program_of(self, m: list[float]) -> list[float]:
        """Program coordinates (program units) of machine point m (mm)."""
        u = MM_PER_INCH if self.inch else 1.0
        q = [a - o for a, o in zip(m, self._offset_mm())]
        self._turn(q, -1.0)
        return [v / u - g for v, g in zip(q, self.g92)]

    def _set_program_from(self, m: list[float], axes) -> None:
        """Program position of machine point m (mm) on `axes` (X and Y together if turned)."""
        p = self._program_of(m)
        if self.g5x_rot[self.cs]:
            axes = sorted(set(axes) | {0, 1})
        for a in axes:
            self.pos[a] = p[a]
            self.exact[a] = False

    def _shift(self, old_off_mm: list[float]) -> None:
        """The offsets changed: the machine position stays, the program position moves."""
        u = MM_PER_INCH if self.inch else 1.0
        for a, (o, n) in enumerate(zip(old_off_mm, self._offset_mm())):
            if o != n:
                self.pos[a] -= (n - o) / u
                self.exact[a] = False

    def offsets_op(self) -> None:
        rng = self.rng
        u = MM_PER_INCH if self.inch else 1.0
        old = self._offset_mm()
        old_rot = self.g5x_rot[self.cs]
        old_m = self._machine_mm()
        r = rng.random()
        if r < 0.25:
            p = rng.randint(0, 9)
            axes = [a for a in range(3) if rng.random() < 0.6] or [rng.randrange(3)]
            words = [self.gcode("10"), "L2", f"P{p}"]
            idx = self.cs if p == 0 else p - 1
            for a in axes:
                v = self.rounded(rng.uniform(-60, 60) / u)
                words.append(self.word(AXIS_LETTERS[a], v))
                self.g5x_mm[idx][a] = v * u
            # (not on the active system under G92: LinuxCNC then turns its current point without
            # the G92 offset, and its next relative move starts from a point off the tool's)
            if self.f["rotation"] and rng.random() < 0.5 and not (idx == self.cs and any(self.g92)):
                rot = rng.choice([0.0, 15.0, 30.0, 45.0, 90.0, -30.0, 12.5, 180.0])
                words.append(self.word("R", rot))
                self.g5x_rot[idx] = rot
            self.emit(words)
        elif r < 0.5:
            self.cs = rng.randrange(9)
            self.emit([self.gcode(COORD_CODES[self.cs])])
        # rs274's standalone canon hands the interpreter a tool offset in the units it was set in
        # (real LinuxCNC converts it): G53 and G28 after a unit change would differ, so not then.
        tool_ok = not any(self.tool_mm) or self.tool_inch == self.inch
        if r < 0.5:
            pass
        elif r < 0.75 and not self.incremental:
            # a full absolute move first: rs274's standalone canon resyncs the position after M6
            # from the last move's program coordinates
            self.straight_all_axes()
            t = rng.randint(0, 4)
            self.emit([f"T{t}", "M6"])
            if t != 0:  # rs274: T0 M6 keeps the spindle's tool data for G43 without H
                self.spindle_tool = t
            k = rng.random()
            if k < 0.4:
                self.emit([self.gcode("43")])
                self.tool_mm = [0.0, 0.0, DEFAULT_TOOL_Z_MM.get(self.spindle_tool, 0.0)]
            elif k < 0.7:
                h = rng.randint(0, 4)
                self.emit([self.gcode("43"), f"H{h}"])
                # rs274: H0 is the spindle's tool data
                self.tool_mm = [0.0, 0.0, DEFAULT_TOOL_Z_MM.get(h or self.spindle_tool, 0.0)]
            elif k < 0.85:
                z = self.rounded(rng.uniform(-20, 20) / u)
                self.emit([self.gcode("43.1"), self.word("Z", z)])
                self.tool_mm[2] = z * u
            else:
                self.emit([self.gcode("49")])
                self.tool_mm = [0.0, 0.0, 0.0]
            self.tool_inch = self.inch
            self._shift(old)
            old = self._offset_mm()
            self.straight_all_axes()  # and after it (the resync lags the tool offset)
        elif r < 0.88 and not self.incremental and tool_ok:
            axes = [a for a in range(3) if rng.random() < 0.6] or [rng.randrange(3)]
            words = [self.gcode("53"), self.gcode("0")]
            m = self._machine_mm()
            for a in axes:
                v = self.rounded(rng.uniform(-80, 80) / u)
                words.append(self.word(AXIS_LETTERS[a], v))
                m[a] = v * u
            self.emit(words)
            self._set_program_from(m, axes)
        elif r < 0.94 and tool_ok:  # (G28.1 reads the same stale tool offset)
            self.emit([self.gcode("28.1")])
            self.g28_mm = self._machine_mm()
        elif not self.incremental and tool_ok:
            # G28 with the intermediate point on some axes, then those axes go home
            axes = [a for a in range(3) if rng.random() < 0.5] or [rng.randrange(3)]
            p = self.random_point()
            words = [self.gcode("28")] + self.target(p, axes)
            self.emit(words)
            # the words name program axes: the stored point in program coordinates on those
            home = self._program_of(self.g28_mm)
            for a in axes:
                self.pos[a] = home[a]
                self.exact[a] = False
        if old_rot or self.g5x_rot[self.cs]:
            if r < 0.5:  # offsets or the system changed, the machine stayed
                self._set_program_from(old_m, [0, 1, 2])
            return
        self._shift(old)

    def straight_all_axes(self) -> None:
        p = self.random_point()
        self.emit([self.gcode("0")] + self.target(p, [0, 1, 2]))

    # ---- program ---------------------------------------------------------------------------------
    def program(self, blocks: int) -> str:
        rng = self.rng
        if self.f["comments"]:
            self.lines.append("(gen_random_program)")
        self.lines.append(f"{self.gcode('20' if self.inch else '21')} {self.gcode('17')} "
                          f"{self.gcode('90')} {self.gcode('94')}")
        for _ in range(blocks):
            if self.f["offsets"] and rng.random() < 0.15:
                self.offsets_op()
                continue
            r = rng.random()
            if r < 0.15:
                self.straight(rapid=True)
            elif r < 0.45:
                self.straight(rapid=False)
            elif r < 0.80:
                self.arc()
            elif r < 0.86:
                self.plane = rng.choice([17, 18, 19])
                self.emit([self.gcode(str(self.plane))])
            elif r < 0.90 and self.f["incremental"]:
                self.incremental = not self.incremental
                self.emit([self.gcode("91" if self.incremental else "90")])
            elif r < 0.93 and self.f["units"]:
                self.switch_units()
            elif r < 0.95 and self.f["dwell"]:
                self.dwell()
            elif r < 0.955 and self.f["g92"]:
                self.g92_offset()
            elif r < 0.965 and self.f["offsets"]:
                self.offsets_op()
            elif r < 0.97 and self.f["g93"]:
                self.inverse_time = not self.inverse_time
                self.emit([self.gcode("93" if self.inverse_time else "94")])
                if not self.inverse_time:
                    self.feed_set = False  # LinuxCNC zeroes the feed on leaving G93
            elif self.f["comments"]:
                if rng.random() < 0.5:
                    self.lines.append(rng.choice(["(comment only)", "; semicolon comment", ""]))
                else:
                    self.straight(rapid=False)
            else:
                self.straight(rapid=False)
        self.lines.append("M2")
        return "\n".join(self.lines) + "\n"


def generate(seed: int, blocks: int = 40, features: dict | None = None) -> str:
    """A random program (text, '\\n' line ends) for `seed`; same seed+blocks+features -> same text."""
    return _Gen(seed, features or dict(DEFAULT_FEATURES)).program(blocks)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--blocks", type=int, default=40)
    ap.add_argument("--features", default=None,
                    help="comma list of +name/-name (names: %s)" % ", ".join(DEFAULT_FEATURES))
    ap.add_argument("-o", "--output", default="-")
    args = ap.parse_args(argv)
    text = generate(args.seed, args.blocks, parse_features(args.features))
    if args.output == "-":
        sys.stdout.write(text)
    else:
        with open(args.output, "w") as fh:
            fh.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
