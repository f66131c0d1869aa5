#!/usr/bin/env python3
"""Differential test: LinuxCNC's standalone interpreter `rs274 -g` versus `gmotion moves`.

Both sides are reduced to one list of canonical moves in mm and mm/min (the `gmotion moves`
JSON-lines schema) and compared move by move: kind, end point, arc centre (the two in-plane
components), direction, turns, plane, feed and source line.

Usage:
  rs274_diff.py --gmotion BIN FILE...            compare the given programs
  rs274_diff.py --gmotion BIN --programs DIR...  every *.nc under DIR (those rs274 rejects skipped)
  rs274_diff.py --gmotion BIN --random N         N generated programs (tools/gen_random_program.py)
  rs274_diff.py --self-test                      check the rs274 output parser and the comparator
  rs274_diff.py --rs274-moves FILE               print rs274's moves as gmotion-style JSON lines
Exit: 0 all equal, 1 a mismatch / error, 2 usage, 77 rs274 not installed (ctest SKIP).

How rs274 is read (each claim checked against rs274 2.9 output, see --self-test):
  * `rs274 -g FILE` runs in batch mode, stdin closed; exit status 1 on an interpreter error.
  * Values are printed with %.4f in the program's length units at that moment
    (USE_LENGTH_UNITS(CANON_UNITS_INCHES) -> x 25.4). The comparison tolerance therefore adds
    rs274's print rounding (0.5e-4 program units) to the requested tolerance.
  * ARC_FEED(first_end, second_end, first_centre, second_centre, rotation, axis_end, a, b, c):
    XY plane first/second = X/Y, axis = Z; XZ: first = Z, second = X, axis = Y;
    YZ: first = Y, second = Z, axis = X. rotation < 0 is G2 (cw), > 0 G3, |rotation| = turns.
  * SET_FEED_RATE gives program-units/min; in G93 the interpreter itself emits the equivalent
    units/min rate before each move. A rate is converted with the units in force when it is
    emitted and kept as a physical rate across later G20/G21 changes (as LinuxCNC's real canon,
    emccanon, does; F executes before G20/G21 in a block).
  * Move coordinates are printed in the program's coordinate system; the canon adds the work
    offsets. SET_G5X_OFFSET(index, x, y, z, ...) and SET_G92_OFFSET(x, y, z, ...) are converted
    with the units in force when emitted (as emccanon does) and added to ends and centres, giving
    machine coordinates like `gmotion moves`. SET_XY_ROTATION(deg) turns X and Y after G92 and
    before G5x and the tool offset, as emccanon's rotate_and_offset_pos does; its angle is printed
    to 1e-4 degrees, so rotated programs are compared with the tolerance that rounding allows.
  * Only N words are echoed, so the program is fed to rs274 with every line renumbered
    N<file line>, which makes rs274 report source line numbers.
  * STRAIGHT_PROBE (G38.x): rs274's canon (saicanon.cc) moves to the end point without tripping
    and then, unprinted, backs off 0.254 mm (0.01 in) towards the start; both are taken as moves
    of kind "probe" (gmotion moves the same way, interp/steps_probe.cpp).
  * RIGID_TAP (G33.1): in to the point and back out to the start, two moves of kind "rigid_tap".
  * Under cutter radius compensation (between the COMMENTs "interpreter: cutter radius
    compensation on ..." and "... off", or the program end) the interpreter holds each move back
    until the next one fixes its end point, and rs274 prints it with the line being read when it
    is released. Such moves are compared with gmotion's (which keep their own block's line)
    accepting a gmotion line at or before rs274's.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

MM_PER_INCH = 25.4
RS274_PRINT_HALF_ULP = 0.5e-4  # rs274 prints %.4f
SKIP = 77
GMOTION_AXES = ""  # --axes: passed to `gmotion moves`
WRAPPED = ""  # --wrapped: rotary axes that wrap in both (INI for rs274, flag for gmotion)
IO_RECORDS = False  # --io: spindle/coolant/tool/output/stop records compared too (kind "io")
# Moves at a feed: STRAIGHT_FEED, ARC_FEED, RIGID_TAP (G33.1) and STRAIGHT_PROBE (G38.x).
FED_KINDS = ("line", "arc", "rigid_tap", "probe")
STRAIGHT_KINDS = ("rapid", "line", "rigid_tap", "probe")


# ---------------------------------------------------------------------------------------------
# moves

@dataclass
class Move:
    kind: str                      # rapid | line | arc | rigid_tap | probe | dwell
    line: int | None = None        # source line (1-based) if known
    end: list | None = None        # [x, y, z] mm
    feed: float | None = None      # mm/min (lines and arcs)
    center: list | None = None     # [x, y, z] mm, arcs; None entries = not known
    dir: str | None = None         # cw | ccw
    turns: int | None = None
    plane: str | None = None       # XY | XZ | YZ
    seconds: float | None = None   # dwell
    text: str | None = None        # message: MSG/DEBUG text (MESSAGE call) or PRINT output
    held: bool = False             # rs274 printed it under cutter compensation (see below)
    tol_mm: float = 0.0            # extra tolerance: print rounding of this value on rs274's side
    feed_tol: float = 0.0          # the same for the feed, mm/min
    note: str = ""
    rot: dict | None = None        # rotary ends {"A": deg, ...}: rs274 A B C; gmotion "axes"

    def as_dict(self) -> dict:
        d = {"line": self.line, "kind": self.kind}
        if self.kind in ("message", "io"):
            d["text"] = self.text
            return d
        if self.kind == "dwell":
            d["seconds"] = self.seconds
            return d
        d["end"] = self.end
        d["feed"] = self.feed
        if self.kind == "arc":
            d.update(center=self.center, dir=self.dir, turns=self.turns, plane=self.plane)
        if self.rot:
            d["axes"] = self.rot
        return d

    def __str__(self) -> str:
        def r(v):
            if isinstance(v, float):
                return round(v, 6)
            if isinstance(v, list):
                return [r(x) for x in v]
            return v
        s = json.dumps({k: r(v) for k, v in self.as_dict().items()})
        return s + (f"  [{self.note}]" if self.note else "")


# ---------------------------------------------------------------------------------------------
# rs274 side

_CALL = re.compile(r"^\s*(\d+)\s+N(\d*)(?:\.{5})?\s*([A-Z_0-9.]+)\((.*)\)\s*$")


def rs274_io_text(name: str, args: str, selected: list) -> str | None:
    """--io: rs274's spindle, coolant, tool, output and stop calls as gmotion's io text."""
    v = _floats(args)
    simple = {"START_SPINDLE_CLOCKWISE": "spindle dir=cw",
              "START_SPINDLE_COUNTERCLOCKWISE": "spindle dir=ccw",
              "STOP_SPINDLE_TURNING": "spindle dir=off", "MIST_ON": "coolant mist=1",
              "MIST_OFF": "coolant mist=0", "FLOOD_ON": "coolant flood=1",
              "FLOOD_OFF": "coolant flood=0", "PROGRAM_STOP": "stop pause",
              "OPTIONAL_PROGRAM_STOP": "stop optional", "PROGRAM_END": "stop end",
              "CHANGE_TOOL_NUMBER": "tool_number"}
    if name in simple:
        return simple[name]
    if name == "SET_SPINDLE_SPEED":
        return f"spindle_speed rpm={v[1]}"
    if name == "ORIENT_SPINDLE":
        return f"spindle_orient angle={v[1]} mode={int(v[2])}"
    if name.endswith("WAIT_ORIENT_COMPLETE"):
        return f"spindle_orient_wait timeout={v[0]}"
    if name == "SELECT_TOOL":
        selected[0] = int(v[0])
        return f"tool_select tool={int(v[0])}"
    if name == "CHANGE_TOOL":  # prints the pocket: the tool is the one selected
        return f"tool_change tool={selected[0]}"
    m = re.match(r"(SET|CLEAR)_(MOTION|AUX)_OUTPUT_BIT$", name)
    if m:
        return (f"digital_out pin={int(v[0])} on={int(m.group(1) == 'SET')} "
                f"sync={int(m.group(2) == 'MOTION')}")
    m = re.match(r"SET_(MOTION|AUX)_OUTPUT_VALUE$", name)
    if m:
        return f"analog_out channel={int(v[0])} value={v[1]} sync={int(m.group(1) == 'MOTION')}"
    return None


def gmotion_io_text(d: dict) -> str | None:
    """--io: a gmotion io record as the text rs274_io_text gives (None: rs274 prints nothing)."""
    k = d.get("kind")
    b = lambda x: int(bool(x))
    if k == "spindle":
        return f"spindle dir={d['dir']}"
    if k == "spindle_speed":
        return f"spindle_speed rpm={d['rpm']}"
    if k == "spindle_orient":
        return f"spindle_orient angle={d['angle']} mode={d['mode']}"
    if k == "spindle_orient_wait":
        return f"spindle_orient_wait timeout={d['timeout']}"
    if k == "coolant":
        return " ".join(["coolant"] + [f"{c}={b(d[c])}" for c in ("mist", "flood") if c in d])
    if k in ("tool_select", "tool_change"):
        return f"{k} tool={d['tool']}"
    if k == "tool_number":
        return "tool_number"
    if k == "digital_out":
        return f"digital_out pin={d['pin']} on={b(d['on'])} sync={b(d['sync'])}"
    if k == "analog_out":
        return f"analog_out channel={d['channel']} value={d['value']} sync={b(d['sync'])}"
    if k == "stop":
        return {"M0": "stop pause", "M60": "stop pause", "M1": "stop optional",
                "M2": "stop end", "M30": "stop end"}.get(d["code"])
    return None  # wait_input (rs274 prints no WAIT), user_mcode (rs274 knows none), "%"


def _floats(args: str) -> list:
    out = []
    for a in args.replace(",", " ").split():
        try:
            out.append(float(a))
        except ValueError:
            out.append(a)
    return out


def _tool_offsets_mm(text: str, factor: float) -> tuple[list, float]:
    """USE_TOOL_LENGTH_OFFSET(x y z, a b c, u v w) in program units -> (XYZ mm, print tolerance)."""
    v = _floats(text)
    xyz = [v[0] * factor, v[1] * factor, v[2] * factor]
    return xyz, (RS274_PRINT_HALF_ULP * factor if any(xyz) else 0.0)


def parse_rs274_output(text: str) -> list[Move]:
    """Canonical calls printed by `rs274 -g` -> moves in mm / mm/min (see module docstring)."""
    factor = 1.0             # mm per program unit
    plane = "XY"
    feed_mm_min = 0.0
    feed_units_note = ""
    feed_tol = 0.0
    moves: list[Move] = []
    g5x = [0.0, 0.0, 0.0]    # mm
    g92 = [0.0, 0.0, 0.0]    # mm
    g5x_tol = g92_tol = 0.0  # print rounding of the offsets, mm
    tool = [0.0, 0.0, 0.0]   # tool length offsets, mm (USE_TOOL_LENGTH_OFFSET)
    tool_tol = 0.0
    g5x_rot = [0.0, 0.0, 0.0]
    g92_rot = [0.0, 0.0, 0.0]
    xy_rot = 0.0             # SET_XY_ROTATION, degrees
    held = False             # inside a cutter compensation section
    selected = [0]           # --io: the tool SELECT_TOOL named
    spindle_rpm = 0.0        # SET_SPINDLE_SPEED
    sync_k = None            # START_SPEED_FEED_SYNC: mm per revolution (G33), until STOP_...
    per_rev = False          # SET_FEED_MODE(s, 1): G95, the feed rate is per revolution
    css_max = 0.0            # SET_SPINDLE_MODE(s D): G96's cap (0: G97)
    css_surface = 0.0        # G96: the surface speed in mm/min, from S and the units at S

    def start_x_prog():      # program X where the next move starts (the radius under G96)
        prev = next((m.end for m in reversed(moves) if m.end is not None), None)
        x = prev[0] if prev is not None else 0.0
        return x - g5x[0] - g92[0] - tool[0]

    def spindle_rpm_now():
        if css_max <= 0.0:
            return spindle_rpm
        r = abs(start_x_prog())
        return min(css_max, css_surface / (2 * math.pi * r)) if r > 0 else css_max

    def per_rev_feed(mm_per_rev):  # gmotion's feed for a spindle-fed move, where it starts
        rpm = spindle_rpm_now()
        return mm_per_rev * rpm, 5e-7 * factor * rpm + mm_per_rev * RS274_PRINT_HALF_ULP + \
            (mm_per_rev * rpm * 1e-6 if css_max > 0 else 0.0)

    def rot_ends(vals):
        return {"ABC"[i]: vals[i] + g5x_rot[i] + g92_rot[i] for i in range(3)}

    def mach(v, i):
        return None if v is None else v * factor + g5x[i] + g92[i] + tool[i]

    def mach3(v):  # program X Y Z (None: not given) -> machine, with the XY rotation
        if xy_rot == 0.0 or v[0] is None or v[1] is None:
            if xy_rot != 0.0 and (v[0] is not None or v[1] is not None):
                raise ValueError("an arc outside the XY plane in a rotated system is not "
                                 "modelled by rs274_diff")
            return [mach(v[i], i) for i in range(3)]
        t = math.radians(xy_rot)
        x, y = v[0] * factor + g92[0], v[1] * factor + g92[1]
        x, y = x * math.cos(t) - y * math.sin(t), x * math.sin(t) + y * math.cos(t)
        return [x + g5x[0] + tool[0], y + g5x[1] + tool[1], mach(v[2], 2)]

    def rot_tol(xy):  # the rotation's print rounding (0.5e-4 degrees) at that point, mm
        if xy_rot == 0.0 or xy[0] is None or xy[1] is None:
            return 0.0
        return 2.0 * RS274_PRINT_HALF_ULP * factor + math.radians(0.5e-4) * math.hypot(
            xy[0] - g5x[0] - tool[0], xy[1] - g5x[1] - tool[1])

    for raw in text.splitlines():
        m = _CALL.match(raw)
        if not m:
            # (PRINT,...) writes its text straight to stdout, between the canonical calls.
            if raw.strip():
                moves.append(Move(kind="message", text=raw))
            continue
        nword, name, args = m.group(2), m.group(3), m.group(4)
        line = int(nword) if nword else None
        io = rs274_io_text(name, args, selected) if IO_RECORDS else None
        if io is not None:
            moves.append(Move(kind="io", line=line, text=io, held=held))
        if name == "COMMENT" and "interpreter: cutter radius compensation" in args:
            held = " on " in args
        elif name in ("PROGRAM_END", "PROGRAM_STOP", "OPTIONAL_PROGRAM_STOP"):
            held = False
        if name == "USE_LENGTH_UNITS":
            new = MM_PER_INCH if "INCHES" in args else 1.0
            if new != factor and feed_mm_min:
                feed_units_note = "feed carried across a G20/G21 change (physical rate kept)"
            factor = new
        elif name == "SET_G5X_OFFSET":
            v = _floats(args)
            g5x = [v[1] * factor, v[2] * factor, v[3] * factor]
            g5x_rot = [float(x) for x in v[4:7]] if len(v) >= 7 else [0.0, 0.0, 0.0]
            g5x_tol = RS274_PRINT_HALF_ULP * factor if any(v[1:4]) else 0.0
        elif name == "SET_G92_OFFSET":
            v = _floats(args)
            g92 = [v[0] * factor, v[1] * factor, v[2] * factor]
            g92_rot = [float(x) for x in v[3:6]] if len(v) >= 6 else [0.0, 0.0, 0.0]
            g92_tol = RS274_PRINT_HALF_ULP * factor if any(v[0:3]) else 0.0
        elif name == "USE_TOOL_LENGTH_OFFSET":
            tool, tool_tol = _tool_offsets_mm(args, factor)
        elif name == "SET_XY_ROTATION":
            xy_rot = _floats(args)[0]
        elif name == "SELECT_PLANE":
            plane = args.strip().replace("CANON_PLANE_", "")
        elif name == "SET_SPINDLE_SPEED":
            spindle_rpm = _floats(args)[-1]
            css_surface = spindle_rpm * (12 * MM_PER_INCH if factor != 1.0 else 1000.0)
        elif name == "SET_SPINDLE_MODE":
            css_max = _floats(args)[-1]
            css_surface = spindle_rpm * (12 * MM_PER_INCH if factor != 1.0 else 1000.0)
        elif name == "SET_FEED_MODE":
            per_rev = _floats(args)[-1] == 1
        elif name == "START_SPEED_FEED_SYNC":
            sync_k = abs(_floats(args)[0]) * factor
        elif name == "STOP_SPEED_FEED_SYNCH":
            sync_k = None
        elif name == "SET_FEED_RATE":
            feed_mm_min = _floats(args)[0] * factor
            feed_tol = RS274_PRINT_HALF_ULP * factor
            feed_units_note = ""
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED"):
            v = _floats(args)
            end = mach3(v[0:3])
            mv = Move(kind="rapid" if name == "STRAIGHT_TRAVERSE" else "line", line=line,
                      end=end, tol_mm=RS274_PRINT_HALF_ULP * factor + g5x_tol + g92_tol +
                      tool_tol + rot_tol(end),
                      rot=rot_ends(v[3:6]) if len(v) >= 6 else None)
            if mv.kind == "line" and (sync_k is not None or per_rev):
                # G33 / G95: gmotion feeds K or F x the spindle speed where the move starts (its
                # spindle runs at S, or under G96 at surface / 2 pi r, at most D)
                mv.feed, mv.feed_tol = per_rev_feed(sync_k if sync_k is not None else feed_mm_min)
                mv.note = "G33: K x rpm" if sync_k is not None else "G95: F x rpm"
            elif mv.kind == "line":
                mv.feed = feed_mm_min
                mv.feed_tol = feed_tol
                mv.note = feed_units_note
            mv.held = held
            moves.append(mv)
        elif name == "RIGID_TAP":
            # G33.1: in to the point synchronised, the spindle reverses, out to the start at I x
            # the speed (I is not printed: the return's feed is not compared)
            v = _floats(args)
            prev = next((m.end for m in reversed(moves) if m.end is not None),
                        [mach(0.0, i) for i in range(3)])
            tol = RS274_PRINT_HALF_ULP * factor + g5x_tol + g92_tol + tool_tol
            feed, ftol = per_rev_feed(sync_k if sync_k is not None else 0.0)
            moves.append(Move(kind="rigid_tap", line=line, end=mach3(v[0:3]),
                              feed=feed, feed_tol=ftol, tol_mm=tol, note="G33.1 in", held=held))
            moves.append(Move(kind="rigid_tap", line=line, end=list(prev), feed=feed,
                              feed_tol=float("inf"), tol_mm=tol, note="G33.1 out", held=held))
        elif name == "STRAIGHT_PROBE":
            v = _floats(args)
            end = mach3(v[0:3])
            prev = next((m.end for m in reversed(moves) if m.end is not None),
                        [mach(0.0, i) for i in range(3)])
            tol = RS274_PRINT_HALF_ULP * factor + g5x_tol + g92_tol + tool_tol + rot_tol(end)
            moves.append(Move(kind="probe", line=line, end=end, feed=feed_mm_min,
                              feed_tol=feed_tol, tol_mm=tol, note="probe"))
            d = [prev[i] - end[i] for i in range(3)]
            dist = math.sqrt(sum(x * x for x in d))
            if dist != 0.0:
                back = [end[i] + 0.254 * d[i] / dist for i in range(3)]
                moves.append(Move(kind="probe", line=line, end=back, feed=feed_mm_min,
                                  feed_tol=feed_tol, tol_mm=2 * tol, note="probe back-off"))
        elif name == "ARC_FEED":
            v = _floats(args)
            fe, se, fc, sc, rot, ax = v[0], v[1], v[2], v[3], int(v[4]), v[5]
            if plane == "XY":
                end = [fe, se, ax]
                cen = [fc, sc, None]
            elif plane == "XZ":      # first = Z, second = X
                end = [se, ax, fe]
                cen = [sc, None, fc]
            elif plane == "YZ":      # first = Y, second = Z
                end = [ax, fe, se]
                cen = [None, fc, sc]
            else:
                raise ValueError(f"ARC_FEED in unknown plane {plane!r}: {raw}")
            end, cen = mach3(end), mach3(cen)
            moves.append(Move(kind="arc", line=line, end=end, center=cen,
                              dir="cw" if rot < 0 else "ccw", turns=abs(rot), plane=plane,
                              feed=per_rev_feed(feed_mm_min)[0] if per_rev else feed_mm_min,
                              note=feed_units_note,
                              feed_tol=per_rev_feed(feed_mm_min)[1] if per_rev else feed_tol,
                              rot=rot_ends(v[6:9]) if len(v) >= 9 else None,
                              held=held, tol_mm=RS274_PRINT_HALF_ULP * factor + g5x_tol +
                              g92_tol + tool_tol + max(rot_tol(end), rot_tol(cen))))
        elif name == "NURBS_FEED":
            # G5, G5.1, G5.3: rs274 prints only the number of control points (its canon leaves
            # the curve's end unset); gmotion's biarcs of that line are collapsed to match.
            moves.append(Move(kind="spline", line=line, text=args.split(",")[0].strip()))
        elif name == "DWELL":
            moves.append(Move(kind="dwell", line=line, seconds=_floats(args)[0], held=held))
        elif name == "MESSAGE":
            arg = args.strip()
            if arg.startswith('"') and arg.endswith('"'):
                arg = arg[1:-1]
            moves.append(Move(kind="message", line=line, text=arg))
    return moves


_NWORD = re.compile(r"^(\s*/?\s*)[nN]\s*[0-9]+")


def number_lines(text: str) -> str:
    """Give every block the N word of its file line so rs274 echoes source line numbers."""
    out = []
    for i, line in enumerate(text.split("\n"), start=1):
        s = line.strip()
        if not s or s.startswith("%") or re.match(r"^/?\s*[oO]", s):
            out.append(line)
        elif _NWORD.match(line):
            out.append(_NWORD.sub(lambda m: f"{m.group(1)}N{i}", line, count=1))
        else:
            m = re.match(r"^(\s*/?)(.*)$", line)
            out.append(f"{m.group(1)}N{i} {m.group(2)}")
    return "\n".join(out)


@dataclass
class Rs274Result:
    ok: bool
    moves: list = field(default_factory=list)
    error: str = ""


# The tool table of gmotion's built-in default machine (src/machine/tool_table.cpp), mm.
DEFAULT_TOOL_TABLE_MM = """\
T1 P1 Z50 D6 ;6 mm flat end mill
T2 P2 Z60 D3 ;3 mm drill
T3 P3 Z45 D10 ;10 mm flat end mill
T4 P4 Z70 D5 ;5 mm spot drill
"""

_TBL_WORD = re.compile(r"([A-Za-z])\s*([-+]?[0-9]*\.?[0-9]+)")


def tool_table_inches(text_mm: str) -> str:
    """A tool table in mm (gmotion) -> the same table in inches: rs274 reads -t tables in its
    machine units, inches (checked: T1 Z10.5 gives USE_TOOL_LENGTH_OFFSET 266.7 under G21)."""
    out = []
    for line in text_mm.splitlines():
        body, sep, comment = line.partition(";")

        def conv(m):
            letter, val = m.group(1).upper(), float(m.group(2))
            if letter in "XYZABCUVWD" and letter not in "ABC":
                return f"{letter}{val / MM_PER_INCH:.10f}"
            return m.group(0)
        out.append(_TBL_WORD.sub(conv, body) + sep + comment)
    return "\n".join(out) + "\n"


RS274_TIMEOUT: float | None = None  # --rs274-timeout


def run_rs274(rs274: str, program_text: str, timeout: float = 120.0,
              tool_table_mm: str | None = None, subroutine_path: str | None = None) -> Rs274Result:
    """Run `rs274 -g` on the text (renumbered) in a scratch directory that is also its HOME (it
    keeps its tool table in $HOME/.tool.mmap; runs sharing one corrupt each other); with
    `tool_table_mm`, that table (mm) is given with -t (in inches). Parse its moves."""
    with tempfile.TemporaryDirectory(prefix="rs274diff-") as tmp:
        path = os.path.join(tmp, "prog.ngc")
        with open(path, "w") as fh:
            fh.write(number_lines(program_text))
            if not program_text.endswith("\n"):
                fh.write("\n")
        cmd = [rs274]
        if tool_table_mm is not None:
            tbl = os.path.join(tmp, "tools.tbl")
            Path(tbl).write_text(tool_table_inches(tool_table_mm))
            cmd += ["-t", tbl]
        ini_text = ""
        if subroutine_path:
            # rs274 reads SUBROUTINE_PATH from an INI given with -i ([RS274NGC], absolute dirs);
            # its scratch working directory holds no .ngc, so only the path can supply a sub.
            dirs = ":".join(os.path.abspath(d) for d in subroutine_path.split(":") if d)
            ini_text += f"[RS274NGC]\nSUBROUTINE_PATH = {dirs}\n"
        for letter in WRAPPED:
            ini_text += f"[AXIS_{letter}]\nWRAPPED_ROTARY = 1\n"
        if VAR_STATE is not None:
            # The parameter file chained from program to program: -v names it, rs274 reads it at
            # start and writes it at exit (Interp::init, Interp::exit), in inches (VarState).
            cmd += ["-v", VAR_STATE.rs274_var]
        if ini_text:
            ini = os.path.join(tmp, "rs274.ini")
            Path(ini).write_text(ini_text)
            cmd += ["-i", ini]
        cmd += ["-g", path]
        # Every run gets its own empty HOME: rs274 keeps its tool table in $HOME/.tool.mmap and
        # runs sharing one truncate it under each other. A death by signal is retried.
        home = os.path.join(tmp, "home")
        os.mkdir(home)
        env = dict(os.environ, HOME=home)
        for _attempt in range(3):
            try:
                p = subprocess.run(cmd, cwd=tmp, stdin=subprocess.DEVNULL, capture_output=True,
                                   text=True, timeout=RS274_TIMEOUT or timeout, env=env)
            except subprocess.TimeoutExpired:
                # rs274 never returns on some programs (2.9.0~pre1's G7x pocket walk can loop
                # for ever): counted as refused, so gmotion must refuse them too.
                return Rs274Result(False, error=f"rs274 did not finish within "
                                                f"{RS274_TIMEOUT or timeout:g} s (killed)")
            if p.returncode >= 0:
                break
    err = "\n".join(l for l in p.stderr.splitlines() if l.strip() != "executing")
    if p.returncode != 0:
        return Rs274Result(False, error=err or f"rs274 exit status {p.returncode}")
    return Rs274Result(True, parse_rs274_output(p.stdout))


# ---------------------------------------------------------------------------------------------
# gmotion side

def parse_gmotion_output(text: str) -> list[Move]:
    moves = []
    for n, raw in enumerate(text.splitlines(), start=1):
        if not raw.strip():
            continue
        try:
            d = json.loads(raw)
        except json.JSONDecodeError as e:
            raise ValueError(f"gmotion moves output line {n} is not JSON ({e}): {raw!r}")
        if d.get("kind") not in ("rapid", "line", "arc", "rigid_tap", "probe", "dwell", "message"):
            io = gmotion_io_text(d)
            if io is not None:
                moves.append(Move(kind="io", line=d.get("line"), text=io))
            continue
        if d.get("operator"):  # G88's retract by hand: not one of the program's moves
            continue
        moves.append(Move(kind=d.get("kind"), line=d.get("line"), end=d.get("end"),
                          feed=d.get("feed"), center=d.get("center"), dir=d.get("dir"),
                          turns=d.get("turns"), plane=d.get("plane"), seconds=d.get("seconds"),
                          text=d.get("text"), rot=d.get("axes")))
    return moves


SUBROUTINE_PATH: str | None = None  # --subroutine-path, given to every gmotion run


def _var_is_length(n: int) -> bool:
    """A length among the persistent parameters (X Y Z U V W of G28, G30, G92, G54-G59.3)."""
    for base in [5161, 5181, 5211] + [5221 + 20 * k for k in range(9)]:
        if base <= n < base + 9:
            return (n - base) not in (3, 4, 5)  # A B C are degrees
    return False


def _read_var(path) -> dict:
    out = {}
    for line in Path(path).read_text().splitlines():
        f = line.split()
        if len(f) >= 2 and f[0].isdigit():
            out[int(f[0])] = float(f[1])
    return out


class VarState:
    """--var-file: one parameter file per side, carried from program to program (each run reads
    the file the previous one wrote). gmotion gets a copy of programs/machines/default.toml naming
    its file with `parameter_file`. gmotion's file is in mm (a LinuxCNC mm machine's); rs274 2.9's
    standalone driver keeps its "user units" in inches (its [TRAJ]LINEAR_UNITS switch is not in
    the packaged 2.9.0~pre1), so its lengths are divided by 25.4 in the seed and multiplied back
    when the files are compared. (DEBUG of a length parameter differs the same way.)"""

    def __init__(self, seed: str):
        self.dir = tempfile.mkdtemp(prefix="rs274diff-var-")
        self.rs274_var = os.path.join(self.dir, "rs274.var")
        gm_var = os.path.join(self.dir, "gmotion.var")
        if seed != "-":
            shutil.copy(seed, gm_var)
            vals = _read_var(seed)
            Path(self.rs274_var).write_text("".join(
                f"{n}\t{(v / MM_PER_INCH if _var_is_length(n) else v):.6f}\n" for n, v in sorted(vals.items())))
        base = (HERE.parent / "programs" / "machines" / "default.toml").read_text()
        self.machine = os.path.join(self.dir, "machine.toml")
        Path(self.machine).write_text(base.replace("\n[", '\nparameter_file = "gmotion.var"\n\n[', 1))
        self.gm_var = gm_var

    def compare(self) -> str | None:
        """None if both files hold the same numbers with values within print rounding."""
        if not os.path.exists(self.rs274_var) or not os.path.exists(self.gm_var):
            return (f"parameter file missing: rs274 {os.path.exists(self.rs274_var)}, "
                    f"gmotion {os.path.exists(self.gm_var)}")
        a, b = _read_var(self.rs274_var), _read_var(self.gm_var)
        a = {n: (v * MM_PER_INCH if _var_is_length(n) else v) for n, v in a.items()}
        if sorted(a) != sorted(b):
            return f"numbers differ: only rs274 {sorted(set(a) - set(b))}, only gmotion {sorted(set(b) - set(a))}"
        for n in sorted(a):
            if abs(a[n] - b[n]) > 5e-5:  # rs274 prints %f inches
                return f"#{n}: rs274 {a[n]} vs gmotion {b[n]}"
        return None


VAR_STATE: VarState | None = None


def run_gmotion(gmotion: str, path: str, timeout: float = 120.0,
                extra: list | None = None,
                tool_table_path: str | None = None) -> tuple[bool, list, str]:
    tools = ["--tool-table", tool_table_path] if tool_table_path else []
    if GMOTION_AXES:
        tools += ["--axes", GMOTION_AXES]
    if WRAPPED:
        tools += ["--wrapped-rotary", WRAPPED]
    if SUBROUTINE_PATH:
        tools += ["--subroutine-path", SUBROUTINE_PATH]
    if IO_RECORDS:
        tools += ["--io"]
    if VAR_STATE is not None:
        tools += ["--machine", VAR_STATE.machine]
    p = subprocess.run([gmotion, "moves", path, "--messages"] + tools + (extra or []),
                       stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=timeout)
    if p.returncode != 0:
        return False, [], (p.stderr.strip() or f"gmotion exit status {p.returncode}")
    try:
        return True, parse_gmotion_output(p.stdout), ""
    except ValueError as e:
        return False, [], str(e)


# ---------------------------------------------------------------------------------------------
# comparison

@dataclass
class Tol:
    mm: float = 1e-4
    feed_rel: float = 1e-4
    seconds: float = 1e-4


def _vec_diff(a, b, extra):
    """None if a == b within tolerance per component (None components skipped), else a message."""
    if a is None or b is None or len(a) != 3 or len(b) != 3:
        return f"{a} vs {b}"
    for i in range(3):
        if a[i] is None or b[i] is None:
            continue
        if not isinstance(b[i], (int, float)) or not math.isfinite(b[i]) or abs(a[i] - b[i]) > extra:
            return f"{'XYZ'[i]}: {a[i]!r} vs {b[i]!r}"
    return None


_NUM = re.compile(r"-?\d+\.\d+|-?\d+")


def compare_text(ref: str, got: str) -> str | None:
    """Message texts: equal apart from leading/trailing spaces (rs274 keeps the space after the
    comma) and numbers that differ by less than their %f print rounding."""
    a, b = (ref or "").strip(), (got or "").strip()
    if a == b:
        return None
    na, nb = _NUM.findall(a), _NUM.findall(b)
    if _NUM.sub("#", a) != _NUM.sub("#", b) or len(na) != len(nb):
        return f"text {a!r} vs {b!r}"
    for x, y in zip(na, nb):
        fx, fy = float(x), float(y)
        if abs(fx - fy) > 1.5e-6 + 1e-12 * max(abs(fx), abs(fy)):
            return f"text {a!r} vs {b!r} ({x} vs {y})"
    return None


def compare_move(ref: Move, got: Move, tol: Tol) -> str | None:
    """None if `got` (gmotion) matches `ref` (rs274), else a one-line reason."""
    if ref.kind != got.kind:
        return f"kind {ref.kind} vs {got.kind}"
    if ref.line is not None and got.line is not None and ref.line != got.line and not (
            ref.held and got.line < ref.line):
        return f"line {ref.line} vs {got.line}"
    if ref.kind in ("message", "io"):
        return compare_text(ref.text, got.text)
    if ref.kind == "spline":
        return None
    if ref.kind == "dwell":
        if got.seconds is None or abs(ref.seconds - got.seconds) > tol.seconds + RS274_PRINT_HALF_ULP:
            return f"dwell seconds {ref.seconds} vs {got.seconds}"
        return None
    ptol = tol.mm + ref.tol_mm + 1e-9
    d = _vec_diff(ref.end, got.end, ptol)
    if d:
        return f"end {d} (tol {ptol:.3g} mm)"
    # Rotary axes the gmotion machine has (--axes): degrees, printed %.4f by rs274.
    for k, v in (got.rot or {}).items():
        if k in "ABC" and ref.rot is not None:
            rtol = tol.mm + RS274_PRINT_HALF_ULP + 1e-9
            if not isinstance(v, (int, float)) or abs(ref.rot[k] - v) > rtol:
                return f"end {k}: {ref.rot[k]!r} vs {v!r} deg (tol {rtol:.3g})"
    if ref.kind in FED_KINDS:
        if got.feed is None:
            return "feed missing"
        ftol = max(tol.feed_rel * abs(ref.feed), ref.feed_tol) + 1e-9
        if abs(ref.feed - got.feed) > ftol:
            return f"feed {ref.feed!r} vs {got.feed!r} mm/min (tol {ftol:.3g})"
    if ref.kind == "arc":
        if got.plane != ref.plane:
            return f"plane {ref.plane} vs {got.plane}"
        if got.dir != ref.dir:
            return f"dir {ref.dir} vs {got.dir}"
        if got.turns != ref.turns:
            return f"turns {ref.turns} vs {got.turns}"
        d = _vec_diff(ref.center, got.center, ptol)
        if d:
            return f"center {d} (tol {ptol:.3g} mm)"
    return None


def collapse_splines(ref: list[Move], got: list[Move]) -> list[Move]:
    """gmotion draws a G5/G5.1/G5.3 curve as the biarcs LinuxCNC's canon fits (rs274 prints one
    NURBS_FEED): where rs274 has a spline, gmotion's run of lines and arcs of that source line
    becomes one spline move (kind and line compared; its end is checked by the moves after)."""
    out, j = [], 0
    for r in ref:
        if j >= len(got):
            break
        if r.kind == "spline" and got[j].kind in ("line", "arc") and got[j].line == r.line:
            end = got[j].end
            while j < len(got) and got[j].kind in ("line", "arc") and got[j].line == r.line:
                end = got[j].end
                j += 1
            out.append(Move(kind="spline", line=r.line, end=end, text=r.text))
        else:
            out.append(got[j])
            j += 1
    return out + got[j:]


def compare_moves(ref: list[Move], got: list[Move], tol: Tol):
    """(index, reason) of the first mismatch, or None if the lists agree."""
    for i in range(min(len(ref), len(got))):
        why = compare_move(ref[i], got[i], tol)
        if why:
            return i, why
    if len(ref) != len(got):
        return min(len(ref), len(got)), f"move count {len(ref)} (rs274) vs {len(got)} (gmotion)"
    return None


def drop_zero_length(moves: list[Move], eps_mm: float) -> tuple[list[Move], int]:
    """Remove rapids/lines that end where the previous move ended (start: origin)."""
    out, dropped, prev, prev_tol, prev_rot = [], 0, [0.0, 0.0, 0.0], 0.0, {}
    for m in moves:
        rot = {k: v for k, v in (m.rot or {}).items() if k in "ABC"}
        rot_same = all(abs(v - prev_rot.get(k, 0.0)) <= eps_mm for k, v in rot.items())
        # rs274's ends are rounded to 4 decimals in program units: a move that only undoes that
        # rounding (inch mode, then mm) is zero-length too.
        eps = max(eps_mm, 2 * max(m.tol_mm, prev_tol))
        if m.kind in STRAIGHT_KINDS and m.end is not None and all(
                abs(a - b) <= eps for a, b in zip(m.end, prev)) and rot_same:
            dropped += 1
            continue
        if m.kind == "spline":  # rs274 does not say where a curve ends: keep the next move
            prev = [math.nan] * 3
        elif m.end is not None:
            prev, prev_tol = m.end, m.tol_mm
            prev_rot = rot
        out.append(m)
    return out, dropped


def describe_mismatch(ref, got, idx, why, program_text, label) -> str:
    lines = program_text.split("\n")
    out = [f"MISMATCH {label}: move #{idx + 1}: {why}"]
    r = ref[idx] if idx < len(ref) else None
    g = got[idx] if idx < len(got) else None
    out.append(f"  rs274  : {r if r else '(no move)'}")
    out.append(f"  gmotion: {g if g else '(no move)'}")
    ln = (r.line if r and r.line else None) or (g.line if g and g.line else None)
    if ln and 1 <= ln <= len(lines):
        out.append(f"  program line {ln}: {lines[ln - 1]}")
    if idx > 0:
        out.append(f"  previous move (rs274): {ref[idx - 1] if idx - 1 < len(ref) else '-'}")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# drivers

def diff_program(args, text: str, path: str, label: str, *, must_accept: bool) -> str:
    """'ok' | 'skip' | 'fail'; prints the first mismatch."""
    rs = run_rs274(args.rs274, text, tool_table_mm=args.tool_table_text,
                   subroutine_path=args.subroutine_path)
    if not rs.ok:
        if must_accept:
            print(f"FAIL {label}: rs274 rejected it (generator bug):\n  {rs.error}")
            return "fail"
        ok, _, _ = run_gmotion(args.gmotion, path, tool_table_path=args.tool_table_path)
        print(f"SKIP {label}: rs274 rejects it: {rs.error.splitlines()[0] if rs.error else ''}"
              + ("\n  NOTE: gmotion accepts it" if ok else " (gmotion rejects it too)"))
        return "skip"
    ok, got, err = run_gmotion(args.gmotion, path, tool_table_path=args.tool_table_path)
    if not ok:
        print(f"FAIL {label}: gmotion moves failed on a program rs274 accepts:\n  {err[:2000]}")
        return "fail"
    ref = rs.moves
    if args.messages:
        args.messages_compared += sum(1 for m in ref if m.kind == "message")
    else:
        ref = [m for m in ref if m.kind != "message"]
        got = [m for m in got if m.kind != "message"]
    if not args.keep_zero_length:
        # rs274 prints zero-length G0/G1 blocks; a motion pipeline may drop them
        ref, n_ref = drop_zero_length(ref, 1e-12)
        # gmotion prints ends exactly: a move below rs274's print resolution is dropped too
        got, n_got = drop_zero_length(got, 2 * RS274_PRINT_HALF_ULP)
        args.zero_dropped += n_ref
    got = collapse_splines(ref, got)
    mm = compare_moves(ref, got, args.tol)
    if mm:
        print(describe_mismatch(ref, got, mm[0], mm[1], text, label))
        return "fail"
    if args.verbose:
        print(f"ok   {label}: {len(ref)} moves")
    args.moves_compared += len(ref)
    return "ok"


_ERR_LINE = re.compile(r"^\s*/?\s*N(\d+)\b")
_GM_ERR = re.compile(r":(\d+):(\d+): error: (.*)$")


def rs274_error_line(error_text: str, program_text: str | None = None) -> int | None:
    """rs274 prints the message, then the offending block (renumbered: N<file line> first). O-word
    lines are not renumbered; their messages begin with the file line ("9: duplicate O-word
    label ..."), or (G70-G72 errors, found when the profile subroutine returns) the message is
    followed by the O-word line as written: its line in the program, when exactly one line has
    that text."""
    for line in reversed(error_text.splitlines()):
        m = _ERR_LINE.match(line)
        if m:
            return int(m.group(1))
    m = re.match(r"^\s*(\d+): ", error_text)
    if m:
        return int(m.group(1))
    lines = [ln.strip() for ln in error_text.splitlines() if ln.strip()]
    if program_text is not None and len(lines) >= 2 and re.match(r"^[oO]\S+\s", lines[-1]):
        hits = [i + 1 for i, ln in enumerate(program_text.splitlines()) if ln.strip() == lines[-1]]
        if len(hits) == 1:
            return hits[0]
    return None


def gmotion_first_error(gmotion: str, path: str, tool_table_path: str | None) -> tuple[int | None, str]:
    cmd = [gmotion, "check", path] + (["--tool-table", tool_table_path] if tool_table_path else [])
    if GMOTION_AXES:
        cmd += ["--axes", GMOTION_AXES]
    if WRAPPED:
        cmd += ["--wrapped-rotary", WRAPPED]
    p = subprocess.run(cmd, stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120)
    if p.returncode == 0:
        return None, "accepted"
    for line in p.stderr.splitlines():
        m = _GM_ERR.search(line)
        if m:
            return int(m.group(1)), m.group(3)
    return None, p.stderr.strip()[:300]


def main_errors(args) -> int:
    """Every program under --errors must be rejected by rs274 and by gmotion, on the same line."""
    ok = bad = 0
    for f in collect_programs(args.errors):
        text = f.read_text(errors="replace")
        rs = run_rs274(args.rs274, text, tool_table_mm=args.tool_table_text)
        gl, gmsg = gmotion_first_error(args.gmotion, str(f), args.tool_table_path)
        if rs.ok:
            print(f"FAIL {f}: rs274 accepts it (the program is not an error case)")
            bad += 1
            continue
        rl = rs274_error_line(rs.error, text)
        first = rs.error.splitlines()[0] if rs.error else ""
        if gl is None or gl != rl:
            print(f"FAIL {f}: rs274 line {rl} ({first}) vs gmotion line {gl} ({gmsg})")
            bad += 1
        else:
            ok += 1
            if args.verbose:
                print(f"ok   {f}: line {rl}: rs274 '{first}' / gmotion '{gmsg}'")
    print(f"rs274_diff errors: {ok} rejected on the same line by both, {bad} not")
    if ok + bad == 0:
        return 1
    return 1 if bad else 0


def collect_programs(roots: list[str]) -> list[Path]:
    files: list[Path] = []
    for r in roots:
        p = Path(r)
        if p.is_dir():
            files += sorted(p.rglob("*.nc")) + sorted(p.rglob("*.ngc"))
        else:
            files.append(p)
    return files


def main_compare(args) -> int:
    counts = {"ok": 0, "skip": 0, "fail": 0}
    skipped = []
    if args.random_expr:
        import gen_random_expr as genx
        with tempfile.TemporaryDirectory(prefix="rs274diff-gx-") as tmp:
            for k in range(args.random_expr):
                seed = args.seed_base + k
                text = genx.generate(seed, args.blocks)
                path = os.path.join(tmp, f"expr{seed}.nc")
                Path(path).write_text(text)
                res = diff_program(args, text, path, f"expression seed {seed}", must_accept=True)
                counts[res] += 1
                if res == "fail":
                    print(f"  reproduce: tools/gen_random_expr.py --seed {seed} --blocks {args.blocks}")
                    print("  ---- program ----\n" + text + "  -----------------")
                    if counts["fail"] >= args.max_failures:
                        break
    if args.random:
        import gen_random_program as gen
        feats = gen.parse_features(args.features)
        with tempfile.TemporaryDirectory(prefix="rs274diff-gm-") as tmp:
            for k in range(args.random):
                seed = args.seed_base + k
                text = gen.generate(seed, args.blocks, feats)
                path = os.path.join(tmp, f"seed{seed}.nc")
                Path(path).write_text(text)
                res = diff_program(args, text, path, f"seed {seed}", must_accept=True)
                counts[res] += 1
                if res == "fail":
                    print(f"  reproduce: tools/gen_random_program.py --seed {seed} --blocks {args.blocks}"
                          + (f" --features {args.features}" if args.features else ""))
                    print("  ---- program ----\n" + text + "  -----------------")
                    if args.keep:
                        os.makedirs(args.keep, exist_ok=True)
                        shutil.copy(path, args.keep)
                    if counts["fail"] >= args.max_failures:
                        break
    files = collect_programs(args.programs + args.files)
    if args.subroutine_path:  # the subroutine files are not programs of their own
        sub_dirs = [Path(d).resolve() for d in args.subroutine_path.split(":") if d]
        files = [f for f in files if not any(d in f.resolve().parents for d in sub_dirs)]
    if not files and not (args.random or args.random_expr):
        print(f"rs274_diff: no *.nc programs under {args.programs}; skipping")
        return SKIP
    known = set(args.known.split(",")) if args.known else set()
    known_seen = []
    roots = [Path(r).resolve() for r in args.programs if Path(r).is_dir()]

    def rel_name(f: Path) -> str:  # the path below its --programs directory
        for r in roots:
            if r in f.resolve().parents:
                return str(f.resolve().relative_to(r))
        return f.name

    for f in files:
        text = f.read_text(errors="replace")
        res = diff_program(args, text, str(f), str(f), must_accept=args.must_accept)
        name = rel_name(f)
        if name in known:
            known_seen.append(name)
            if res == "fail":  # a documented difference: reported above, not counted
                print(f"  (known difference: {name})")
                res = "known"
            elif res == "ok":
                print(f"FAIL {f}: listed in --known but now equal to rs274: take it off the list")
                res = "fail"
        counts[res] = counts.get(res, 0) + 1
        if res == "skip":
            skipped.append(str(f))
    for k in sorted(known - set(known_seen)):
        print(f"FAIL --known {k}: no such program was compared")
        counts["fail"] += 1
    if counts.get("known"):
        print(f"rs274_diff: {counts['known']} known differences (--known)")
    print(f"rs274_diff: {counts['ok']} equal, {counts['fail']} mismatched, "
          f"{counts['skip']} skipped (rejected by rs274); {args.moves_compared} moves compared"
          + (f" (of them {args.messages_compared} messages)" if args.messages else "")
          + ("" if args.keep_zero_length else
             f" ({args.zero_dropped} zero-length G0/G1 moves of rs274 left out)"))
    for s in skipped:
        print(f"  skipped: {s}")
    if VAR_STATE is not None:
        why = VAR_STATE.compare()
        if why:
            print(f"MISMATCH parameter files after the last program: {why}")
            counts["fail"] += 1
        else:
            print(f"rs274_diff: the parameter files written agree ({VAR_STATE.gm_var})")
    if counts["ok"] + counts["fail"] == 0 and not args.allow_empty:
        print("rs274_diff: nothing was compared")
        return 1
    return 1 if counts["fail"] else 0


# ---------------------------------------------------------------------------------------------
# self test

# Real rs274 2.9 output (trimmed) with hand-worked expectations.
_SELF_TEXT = """\
    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)
    2 N..... SET_G5X_OFFSET(1, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)
    8 N..... SELECT_PLANE(CANON_PLANE_XY)
   10 N3     STRAIGHT_TRAVERSE(1.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
   11 N4     SET_FEED_RATE(100.0000)
   12 N4     STRAIGHT_FEED(10.0000, 2.0000, 3.0000, 0.0000, 0.0000, 0.0000)
   13 N5     SELECT_PLANE(CANON_PLANE_XZ)
   14 N5     ARC_FEED(-1.0000, 10.0000, 1.0000, 10.0000, -1, 2.0000, 0.0000, 0.0000, 0.0000)
   15 N6     SELECT_PLANE(CANON_PLANE_YZ)
   16 N6     ARC_FEED(2.0000, 3.0000, 2.0000, 1.0000, 2, 10.0000, 0.0000, 0.0000, 0.0000)
   17 N7     DWELL(1.5000)
   18 N8     SET_FEED_RATE(10.0000)
   19 N8     USE_LENGTH_UNITS(CANON_UNITS_INCHES)
   20 N8     STRAIGHT_FEED(1.0000, 0.0787, 0.1181, 0.0000, 0.0000, 0.0000)
   21 N9     SET_FEED_RATE(4.0000)
   22 N9     SELECT_PLANE(CANON_PLANE_XY)
   23 N9     ARC_FEED(3.0000, 0.0787, 4.0000, 0.0787, -3, 1.1181, 0.0000, 0.0000, 0.0000)
   24 N100000STRAIGHT_TRAVERSE(4.0000, 0.0787, 1.1181, 0.0000, 0.0000, 0.0000)
   25 N11    SET_G92_OFFSET(1.0000, 0.0000, -0.5000, 0.0000, 0.0000, 0.0000)
   26 N12    USE_LENGTH_UNITS(CANON_UNITS_MM)
   27 N12    SET_G5X_OFFSET(2, 10.0000, 20.0000, 0.0000, 0.0000, 0.0000, 0.0000)
   28 N13    ARC_FEED(0.0000, 0.0000, 5.0000, 0.0000, 1, 0.0000, 0.0000, 0.0000, 0.0000)
   41 N..... PROGRAM_END()
"""


def _self_expected() -> list[Move]:
    i = MM_PER_INCH
    return [
        Move("rapid", 3, [1, 2, 3]),
        Move("line", 4, [10, 2, 3], feed=100),
        # G18: first = Z, second = X  -> end X10 Y2 Z-1, centre X10 Z1, G2
        Move("arc", 5, [10, 2, -1], 100, [10, None, 1], "cw", 1, "XZ"),
        # G19: first = Y, second = Z  -> end X10 Y2 Z3, centre Y2 Z1, G3, P2
        Move("arc", 6, [10, 2, 3], 100, [None, 2, 1], "ccw", 2, "YZ"),
        Move("dwell", 7, seconds=1.5),
        # F10 is executed before G20 in the block -> 10 mm/min
        Move("line", 8, [1 * i, 0.0787 * i, 0.1181 * i], feed=10),
        Move("arc", 9, [3 * i, 0.0787 * i, 1.1181 * i], 4 * i, [4 * i, 0.0787 * i, None], "cw", 3,
             "XY"),
        Move("rapid", 100000, [4 * i, 0.0787 * i, 1.1181 * i]),
        # G92 offset given in inches (1, 0, -0.5) stays 25.4 mm after G21; G55 offset (10, 20, 0) mm
        Move("arc", 13, [10 + i, 20, -0.5 * i], 4 * i, [15 + i, 20, None], "ccw", 1, "XY"),
    ]


# Three small programs with hand-worked moves (mm), run through the real rs274.
_SELF_PROGRAMS = [
    ("xy-mm",
     "G21 G17 G90\nG0 X1 Y2 Z3\nG1 X10 F100\nG2 X20 Y10 I5 J4\nG4 P0.5\nM2\n",
     [Move("rapid", 2, [1, 2, 3]), Move("line", 3, [10, 2, 3], 100),
      Move("arc", 4, [20, 10, 3], 100, [15, 6, None], "cw", 1, "XY"),
      Move("dwell", 5, seconds=0.5)]),
    ("planes-incremental",
     "G21 G90\nG1 X10 Z3 F60\nG18 G2 X10 Z-1 I0 K-2\nG19 G91 G3 Y0 Z4 J0 K2 P2\n"
     "G17 G3 X-2 Y0 I-1 J0 Z1\nM2\n",
     [Move("line", 2, [10, 0, 3], 60),
      Move("arc", 3, [10, 0, -1], 60, [10, None, 1], "cw", 1, "XZ"),
      Move("arc", 4, [10, 0, 3], 60, [None, 0, 1], "ccw", 2, "YZ"),
      Move("arc", 5, [8, 0, 4], 60, [9, 0, None], "ccw", 1, "XY")]),
    ("inch-g93",
     "G20 G17 G90\nG1 X1 F2\nG93 G1 X3 F4\nG94 G1 Y1 F5\nG21 G1 X10\nM2\n",
     [Move("line", 2, [25.4, 0, 0], 2 * 25.4),
      Move("line", 3, [3 * 25.4, 0, 0], 8 * 25.4),     # 2 in in 1/4 min -> 8 in/min
      Move("line", 4, [3 * 25.4, 25.4, 0], 5 * 25.4),
      Move("line", 5, [10, 25.4, 0], 5 * 25.4)]),        # physical rate kept across G21
    ("g92-offset",
     "G20 G17 G90\nG0 X1\nG92 X0 Y2\nG21 G1 X10 F100\nG2 X0 Y40.8 I-10 J0\nM2\n",
     # G92 at X1 in -> offsets (+25.4, -50.8) mm, kept through G21; program centre (0, 50.8)
     [Move("rapid", 2, [25.4, 0, 0]), Move("line", 4, [35.4, 0, 0], 2540),  # F before G21: 100 in/min
      Move("arc", 5, [25.4, -10, 0], 2540, [25.4, 0, None], "cw", 1, "XY")]),
]


def self_test(args) -> int:
    tol = Tol()
    failures = 0

    def check(label, cond, detail=""):
        nonlocal failures
        if not cond:
            failures += 1
            print(f"SELF-TEST FAIL {label} {detail}")
        elif args.verbose:
            print(f"self-test ok   {label}")

    # 1. the parser on known text
    got = parse_rs274_output(_SELF_TEXT)
    exp = _self_expected()
    mm = compare_moves(got, exp, tol)
    check("parse canned rs274 text", mm is None,
          describe_mismatch(got, exp, *mm, "", "canned") if mm else "")
    # 2. the comparator must notice each kind of difference
    base = [Move("arc", 4, [20, 10, 3], 100, [15, 6, 3], "cw", 1, "XY", tol_mm=5e-5)]
    perturb = {
        "end": dict(end=[20, 10.001, 3]), "center": dict(center=[15.001, 6, 3]),
        "dir": dict(dir="ccw"), "turns": dict(turns=2), "plane": dict(plane="XZ"),
        "feed": dict(feed=100.1), "line": dict(line=5), "kind": dict(kind="line"),
    }
    for name, change in perturb.items():
        other = Move(**{**base[0].__dict__, **change, "tol_mm": 0.0})
        check(f"comparator notices {name}", compare_moves(base, [other], tol) is not None)
    near = Move(**{**base[0].__dict__, "end": [20 + 1.4e-4, 10, 3], "feed": 100.009})
    check("comparator accepts within tolerance", compare_moves(base, [near], tol) is None)
    check("comparator notices a missing move", compare_moves(base, [], tol) is not None)
    zl = [Move("rapid", 1, [0, 0, 0]), Move("line", 2, [1, 0, 0], 5), Move("line", 3, [1, 0, 0], 5),
          Move("arc", 4, [1, 0, 0], 5, [0, 0, 0], "cw", 1, "XY"), Move("rapid", 5, [1, 0, 0])]
    kept, n = drop_zero_length(zl, 1e-12)
    check("drop_zero_length", n == 3 and [m.line for m in kept] == [2, 4], f"{n} {[m.line for m in kept]}")
    # messages: MESSAGE calls and PRINT lines are read, texts compared to print resolution
    msgs = parse_rs274_output('    7 N12    MESSAGE(" v=1.500000 #<a>")\nhello 2.000000\n')
    check("parse MESSAGE and PRINT output",
          [(m.kind, m.line, m.text) for m in msgs]
          == [("message", 12, " v=1.500000 #<a>"), ("message", None, "hello 2.000000")],
          repr(msgs))
    check("text equal apart from spaces", compare_text(" v=1.500000", "v=1.500000") is None)
    check("text within print rounding", compare_text("v=1.500000", "v=1.500001") is None)
    check("text notices a value", compare_text("v=1.500000", "v=1.500010") is not None)
    check("text notices a word", compare_text("v=1.500000", "w=1.500000") is not None)
    check("text notices a missing value", compare_text("v=1.5 2", "v=1.5") is not None)
    # 3. renumbering
    check("number_lines", number_lines("G0 X1\n\nN50 G1 X2\n/G1 X3\n%\n")
          == "N1 G0 X1\n\nN3 G1 X2\n/N4 G1 X3\n%\n", repr(number_lines("G0 X1\n\nN50 G1 X2\n/G1 X3\n%\n")))
    # 4. the real rs274 on three small programs against hand-worked moves
    if shutil.which(args.rs274) or os.path.exists(args.rs274):
        for label, text, expected in _SELF_PROGRAMS:
            rs = run_rs274(args.rs274, text)
            check(f"rs274 accepts {label}", rs.ok, rs.error)
            if rs.ok:
                mm = compare_moves(rs.moves, expected, tol)
                check(f"rs274 moves of {label}", mm is None,
                      "\n" + describe_mismatch(rs.moves, expected, *mm, text, label) if mm else "")
        rs = run_rs274(args.rs274, "G21\nG2 X10 Y0 I3 J0 F10\nM2\n")
        check("rs274 rejection is detected", not rs.ok)
    else:
        print(f"self-test: {args.rs274} not found; skipped the live rs274 checks")
    print(f"rs274_diff self-test: {'FAILED (' + str(failures) + ')' if failures else 'passed'}")
    return 1 if failures else 0


# ---------------------------------------------------------------------------------------------

def setup_tool_table(args) -> None:
    """Both sides get the same table: --tool-table FILE (mm), else gmotion's built-in default,
    written to a scratch file for gmotion (rs274 gets it in inches per run)."""
    if args.tool_table:
        args.tool_table_text = Path(args.tool_table).read_text()
        args.tool_table_path = args.tool_table
        return
    args.tool_table_text = DEFAULT_TOOL_TABLE_MM
    fd, args.tool_table_path = tempfile.mkstemp(prefix="gmotion-tools-", suffix=".tbl")
    with os.fdopen(fd, "w") as fh:
        fh.write(DEFAULT_TOOL_TABLE_MM)
    import atexit
    atexit.register(os.unlink, args.tool_table_path)


def scale_random_counts(args):
    """Shrinks --random/--random-expr by GMOTION_TEST_SCALE (a fraction in (0, 1]): the asan test
    preset sets it, so the sanitized build compares fewer seeds (the first ones) and the default
    build compares them all."""
    try:
        scale = float(os.environ.get("GMOTION_TEST_SCALE", "1"))
    except ValueError:
        scale = 1.0
    if 0.0 < scale < 1.0:
        for name in ("random", "random_expr"):
            n = getattr(args, name)
            if n:
                setattr(args, name, max(1, round(n * scale)))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="rs274 vs gmotion moves differential test")
    ap.add_argument("files", nargs="*", help="programs to compare")
    ap.add_argument("--gmotion", help="path of the gmotion executable")
    ap.add_argument("--rs274", default="rs274", help="LinuxCNC standalone interpreter (default: rs274)")
    ap.add_argument("--programs", nargs="*", default=[], help="directories searched for *.nc/*.ngc")
    ap.add_argument("--random", type=int, default=0, help="number of generated programs")
    ap.add_argument("--random-expr", type=int, default=0,
                    help="number of generated expression/parameter programs "
                         "(tools/gen_random_expr.py; implies --messages)")
    ap.add_argument("--messages", action="store_true",
                    help="also compare MSG/DEBUG/PRINT messages (gmotion moves --messages)")
    ap.add_argument("--seed-base", type=int, default=1)
    ap.add_argument("--blocks", type=int, default=40, help="blocks per generated program")
    ap.add_argument("--features", default=None, help="generator features, e.g. +g93,-syntax")
    ap.add_argument("--tol-mm", type=float, default=1e-4)
    ap.add_argument("--rs274-timeout", type=float, default=None,
                    help="seconds before an rs274 run is killed and counted as a refusal "
                         "(default 120)")
    ap.add_argument("--tol-feed-rel", type=float, default=1e-4)
    ap.add_argument("--max-failures", type=int, default=5, help="stop random runs after this many")
    ap.add_argument("--keep", help="copy failing generated programs into this directory")
    ap.add_argument("--keep-zero-length", action="store_true",
                    help="also compare zero-length G0/G1 moves (by default both sides drop them)")
    ap.add_argument("--allow-empty", action="store_true", help="exit 0 if nothing was compared")
    ap.add_argument("--self-test", action="store_true")
    ap.add_argument("--rs274-moves", metavar="FILE", help="print rs274's moves of FILE as JSON lines")
    ap.add_argument("--must-accept", action="store_true",
                    help="a program rs274 rejects is a failure, not a skip")
    ap.add_argument("--known", default="", metavar="NAME[,NAME]",
                    help="programs (paths below their --programs directory) whose difference "
                         "from rs274 is documented: "
                         "reported but not failures (a listed one that agrees is a failure)")
    ap.add_argument("--errors", nargs="*", default=[],
                    help="directories/files of programs both must reject on the same line")
    ap.add_argument("--tool-table", metavar="FILE",
                    help="tool table in mm for both sides (default: gmotion's built-in table)")
    ap.add_argument("--axes", default="",
                    help="gmotion's machine axes (gmotion --axes), e.g. XYZA: its A/B/C ends are "
                         "compared with rs274's too")
    ap.add_argument("--wrapped", default="", metavar="LETTERS",
                    help="rotary axes that wrap: [AXIS_L]WRAPPED_ROTARY = 1 in rs274's INI, "
                         "--wrapped-rotary for gmotion")
    ap.add_argument("--subroutine-path", metavar="DIR[:DIR]",
                    help="subroutine files for both sides (rs274: an INI's SUBROUTINE_PATH)")
    ap.add_argument("--io", action="store_true",
                    help="also compare spindle, coolant, tool, output and stop records "
                         "(gmotion moves --io)")
    ap.add_argument("--var-file", metavar="SEED|-",
                    help="a LinuxCNC parameter file for both sides (rs274 -v, gmotion's machine "
                         "parameter_file), carried through the programs in the order given, and the "
                         "files written compared at the end ('-': start without one)")
    ap.add_argument("-v", "--verbose", action="store_true")
    args = ap.parse_args(argv)
    global GMOTION_AXES, SUBROUTINE_PATH, VAR_STATE, IO_RECORDS, RS274_TIMEOUT, WRAPPED
    GMOTION_AXES = args.axes
    WRAPPED = args.wrapped.upper()
    RS274_TIMEOUT = args.rs274_timeout
    IO_RECORDS = args.io
    SUBROUTINE_PATH = args.subroutine_path
    if args.var_file:
        VAR_STATE = VarState(args.var_file)
    args.tol = Tol(args.tol_mm, args.tol_feed_rel)
    args.moves_compared = 0
    args.messages_compared = 0
    args.zero_dropped = 0
    setup_tool_table(args)
    if args.random_expr:
        args.messages = True
    scale_random_counts(args)

    have_rs274 = bool(shutil.which(args.rs274)) or os.access(args.rs274, os.X_OK)
    if args.self_test:
        return self_test(args)
    if not have_rs274:
        print(f"rs274_diff: {args.rs274} not installed; skipping (install linuxcnc-uspace)")
        return SKIP
    if args.rs274_moves:
        rs = run_rs274(args.rs274, Path(args.rs274_moves).read_text(),
                       tool_table_mm=args.tool_table_text)
        if not rs.ok:
            print(rs.error, file=sys.stderr)
            return 1
        for m in rs.moves:
            print(json.dumps(m.as_dict()))
        return 0
    if not args.gmotion:
        ap.error("--gmotion is required to compare")
    if args.errors:
        return main_errors(args)
    if not (args.files or args.programs or args.random or args.random_expr):
        ap.error("nothing to compare: give FILEs, --programs DIR or --random N")
    return main_compare(args)


if __name__ == "__main__":
    sys.exit(main())
