#!/usr/bin/env python3
"""Seeded random RS274/NGC programs of expressions and parameters, for rs274_diff.py --random-expr.

Each program sets numbered (#1-#40, #100-#5000) and named (#<local>, #<_global>) parameters from
random expression trees (every operator and function, LinuxCNC precedence without brackets
inside a level, unary minus, EXISTS, ATAN[y]/[x], indirect #[...] references), prints them with
(DEBUG,...), and moves to coordinates computed from them, in mm or inch. Several settings share a
line so the rule "settings take effect after the line is read" is exercised. Arguments are kept
inside each function's domain (ACOS of a value folded into [-1, 1], LN of 1 + |x|, ...) and
divisors away from zero, so rs274 accepts every program: a rejection is a generator bug.

Usage: gen_random_expr.py --seed N [--blocks N] [-o FILE]
"""
from __future__ import annotations

import argparse
import random
import sys

FUNCS = ["ABS", "COS", "SIN", "TAN", "FIX", "FUP", "ROUND", "EXP", "LN", "SQRT", "ACOS", "ASIN"]
BINOPS = ["+", "-", "*", "/", "MOD", "**", "EQ", "NE", "GT", "GE", "LT", "LE", "AND", "OR",
          "XOR"]


class Gen:
    def __init__(self, seed: int):
        self.r = random.Random(seed)
        self.numbered: list[int] = []   # parameters set so far (readable)
        self.named: list[str] = []

    def const(self) -> str:
        r = self.r
        k = r.random()
        if k < 0.4:
            return str(r.randint(0, 20))
        if k < 0.8:
            return f"{r.uniform(-50, 50):.{r.randint(1, 4)}f}"
        return f".{r.randint(1, 999)}"

    def ref(self) -> str:
        r = self.r
        if self.named and r.random() < 0.4:
            return f"#<{r.choice(self.named)}>"
        if self.numbered:
            n = r.choice(self.numbered)
            if r.random() < 0.15:  # indirect: #[a+b] with a+b == n
                a = r.randint(0, n - 1)
                return f"#[{a}+{n - a}]"
            return f"#{n}"
        return self.const()

    def atom(self, depth: int) -> str:
        r = self.r
        k = r.random()
        if depth <= 0 or k < 0.3:
            return self.const() if r.random() < 0.5 else self.ref()
        if k < 0.55:
            return self.func(depth - 1)
        if k < 0.62:
            return f"ATAN[{self.expr(depth - 1)}]/[{self.expr(depth - 1)}]"
        if k < 0.66 and (self.named or True):
            name = r.choice(self.named + ["never_set", "_never_global"])
            return f"EXISTS[#<{name}>]"
        if k < 0.72:
            return f"-{self.atom(depth - 1)}"
        return f"[{self.expr(depth - 1)}]"

    def func(self, depth: int) -> str:
        r = self.r
        f = r.choice(FUNCS)
        e = self.expr(depth)
        if f in ("ACOS", "ASIN"):  # fold into [-1, 1]: ([e] MOD 2) - 1
            return f"{f}[[{e}] MOD 2 - 1]"
        if f == "LN":
            return f"LN[1+ABS[{e}]]"
        if f == "SQRT":
            return f"SQRT[ABS[{e}]]"
        if f == "EXP":
            return f"EXP[[{e}] MOD 5]"
        if f == "TAN":  # stay away from the poles
            return f"TAN[[{e}] MOD 80]"
        return f"{f}[{e}]"

    def expr(self, depth: int) -> str:
        r = self.r
        out = self.atom(depth)
        for _ in range(r.randint(0, 2)):
            op = r.choice(BINOPS)
            rhs = self.atom(depth - 1)
            if op == "/":
                rhs = f"[1+ABS[{rhs}]]"
            elif op == "MOD":
                rhs = f"[1+ABS[{rhs}]]"
            elif op == "**":
                # bounded power of a bounded base: [ABS[lhs] MOD 4] ** small integer
                out = f"[ABS[{out}] MOD 4]"
                rhs = str(r.randint(0, 3))
            out = f"{out} {op} {rhs}"
        return out

    def short(self, make, limit: int) -> str:
        """make() until its text has at most `limit` characters (rs274 reads lines of at most
        255 characters; the parameters it reads must be set, so retries draw from the same set)."""
        for _ in range(50):
            t = make()
            if len(t) <= limit:
                return t
        return self.const()

    def bounded(self, depth: int, lo: float, hi: float) -> str:
        """An expression folded into [lo, hi) (a coordinate or feed)."""
        return f"[[{self.expr(depth)}] MOD {hi - lo:g} + {lo:g}]"

    def program(self, blocks: int) -> str:
        r = self.r
        lines = ["(random expression program)", r.choice(["G21", "G20"]) + " G17 G90 G94"]
        for _ in range(blocks):
            k = r.random()
            if k < 0.45:
                # 1-3 settings on one line: they all read the old values
                sets, new_n, new_named = [], [], []
                for _s in range(r.randint(1, 3)):
                    value = self.short(lambda: f"[{self.expr(r.randint(1, 3))}]", 70)
                    if r.random() < 0.3:
                        name = r.choice(["a", "b", "depth", "_g", "_step", "width"])
                        sets.append(f"#<{name}>={value}")
                        new_named.append(name)
                    else:
                        n = r.choice([r.randint(1, 40), r.randint(100, 5000)])
                        sets.append(f"#{n}={value}")
                        new_n.append(n)
                lines.append(" ".join(sets))
                self.numbered += [n for n in new_n if n not in self.numbered]
                self.named += [s for s in new_named if s not in self.named]
            elif k < 0.7:
                refs = " ".join(f"v{i}={self.ref()}" for i in range(r.randint(1, 3)))
                lines.append(f"(DEBUG,{refs})")
            elif k < 0.95:
                g = r.choice(["G0", "G1"])
                words = " ".join(
                    f"{a}" + self.short(lambda: self.bounded(r.randint(0, 2), -100, 200), 55)
                    for a in r.sample("XYZ", r.randint(1, 3)))
                feed = (f" F" + self.short(lambda: self.bounded(1, 10, 1000), 50)
                        if g == "G1" else "")
                lines.append(f"{g} {words}{feed}")
            else:
                lines.append(r.choice(["G20", "G21", "G91", "G90"]))
        lines.append("G90")
        lines.append("M2")
        return "\n".join(lines) + "\n"


def generate(seed: int, blocks: int = 40) -> str:
    return Gen(seed).program(blocks)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, required=True)
    ap.add_argument("--blocks", type=int, default=40)
    ap.add_argument("-o", "--output")
    a = ap.parse_args(argv)
    text = generate(a.seed, a.blocks)
    if a.output:
        with open(a.output, "w") as fh:
            fh.write(text)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
