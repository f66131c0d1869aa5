#!/usr/bin/python3
"""A model of the Acc/Dec filter's length switched at rests: what it would give on a program.

docs/tolerance.md, "The filter's length is most of the gap", names two routes to speed changes
shorter than the filter; this models the second, the filter's length switched where the machine
rests, without building it. The program's canonical moves (`gmotion moves`) are cut into
stretches: each run of consecutive rapids and each run of consecutive feed moves (lines and
arcs). Between two stretches the machine rests (an exact stop, the filter drained), so that a
stretch can run through its own filter and start exactly where the last one stopped. A rapid
stretch keeps the machine's filter (tau, sized for a step of V = rapid x largest override); a
feed stretch whose fastest move is v (its feed at the largest override) takes the filter
tau_k = max(tau * v / V, --tau-min), rounded up to whole periods: the same mean acceleration,
V / tau, for the largest step it can make.

Each stretch is written as a program of its own (the preamble, an exact-stop G0 to where the
stretch starts, the mode, the stretch's moves with their feeds, arcs by centre and turns) and
run by `gmotion run --no-servo --check-tolerance` on the machine with tau_k; the time of the
same program without the stretch (the preamble and the G0) is subtracted. The stretches' times
add up to the program's, because each starts and ends at rest with the filter drained. The
same cut with every stretch at tau gives the rests' own cost (the first column), and the whole
program in one run the time without them.

  /usr/bin/python3 tools/stretch_filter_model.py PROGRAM.ngc --machine M.toml
      [--mode "G64 P0.01"] [--tau-min 0.02] [--gmotion build/bin/gmotion]

PROGRAM is run as it is (its own mode words stay; --mode only heads each stretch, so give the
mode the program is in). Prints one line: the program's time in one run, cut into stretches
at tau, and cut with each stretch at tau_k; the stretches; and every stretch's samples over P.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
TOP = os.path.dirname(HERE)


def moves(gm, prog, machine):
    out = subprocess.run([gm, "moves", prog, "--machine", machine], capture_output=True,
                         text=True, check=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.strip()]


def machine_with_tau(text, tau, tmp):
    new, n = re.subn(r"(?m)^tau_s\s*=\s*[0-9.eE+-]+", f"tau_s = {tau:.6g}", text)
    if n != 1:
        sys.exit("stretch_filter_model.py: the machine file needs one `tau_s =` line")
    path = os.path.join(tmp, f"m-{tau:.6g}.toml")
    with open(path, "w") as f:
        f.write(new)
    return path


def key(text, name, default):
    m = re.search(rf"(?m)^{name}\s*=\s*([0-9.eE+-]+)", text)
    return float(m.group(1)) if m else default


def fmt(v):
    return f"{v:.6f}".rstrip("0").rstrip(".") if abs(v) > 5e-7 else "0"


def xyz(p):
    return f"X{fmt(p[0])} Y{fmt(p[1])} Z{fmt(p[2])}"


PLANE = {"XY": ("G17", "I", "J", 0, 1), "XZ": ("G18", "I", "K", 0, 2),
         "YZ": ("G19", "J", "K", 1, 2)}


def block(m, start):
    """One canonical move as a block, from `start` (machine coordinates, mm)."""
    if m["kind"] == "rapid":
        return f"G0 {xyz(m['end'])}"
    if m["kind"] == "arc":
        g, a, b, i, j = PLANE[m["plane"]]
        c = m["center"]
        words = f"{g} {'G3' if m['dir'] == 'ccw' else 'G2'} {xyz(m['end'])} " \
                f"{a}{fmt(c[i] - start[i])} {b}{fmt(c[j] - start[j])}"
        if m.get("turns", 1) != 1:
            words += f" P{m['turns']}"
        return words + f" F{fmt(m['feed'])}"
    return f"G1 {xyz(m['end'])} F{fmt(m['feed'])}"


def run_time(gm, text, machine, tmp, name):
    prog = os.path.join(tmp, name + ".ngc")
    with open(prog, "w") as f:
        f.write(text)
    js = os.path.join(tmp, name + ".json")
    r = subprocess.run([gm, "run", prog, "--no-servo", "--check-tolerance", "--machine", machine,
                        "--summary-json", js], capture_output=True, text=True)
    d = json.load(open(js))
    over = d.get("tolerance", {}).get("samples_over", 0) if isinstance(d.get("tolerance"), dict) \
        else 0
    return d["cycle_time_s"], r.returncode, over


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("program")
    ap.add_argument("--machine", required=True)
    ap.add_argument("--mode", default="G64 P0.01")
    ap.add_argument("--tau-min", type=float, default=0.0)
    ap.add_argument("--gmotion", default=os.path.join(TOP, "build", "bin", "gmotion"))
    a = ap.parse_args()
    text = open(a.machine).read()
    tau = key(text, "tau_s", 0.164)
    period = key(text, "period_s", 0.004)
    v_ref = key(text, "rapid_mm_min", 6000) / 60 * key(text, "max_override_percent", 200) / 100
    over_k = key(text, "max_override_percent", 200) / 100
    mv = moves(a.gmotion, a.program, a.machine)

    stretches = []  # (rapid?, [moves])
    for m in mv:
        rapid = m["kind"] == "rapid"
        if not stretches or stretches[-1][0] != rapid:
            stretches.append((rapid, []))
        stretches[-1][1].append(m)

    with tempfile.TemporaryDirectory() as tmp:
        whole, rc, _ = run_time(a.gmotion, open(a.program).read(), a.machine, tmp, "whole")
        pos = [0.0, 0.0, 0.0]
        cut_tau = cut_k = 0.0
        over_total = 0
        taus = []
        for n, (rapid, ms) in enumerate(stretches):
            v = 0.0 if rapid else max(m["feed"] for m in ms) / 60 * over_k
            tk = tau if rapid else min(tau, max(a.tau_min, tau * v / v_ref))
            tk = min(tau, math.ceil(tk / period - 1e-9) * period)
            taus.append(tk)
            head = f"G21 G90 G17 G61.1\nG0 {xyz(pos)}\n"
            body, p = [], list(pos)
            for m in ms:
                body.append(block(m, p))
                p = m["end"][:3]
            prog = head + a.mode + "\n" + "\n".join(body) + "\nM2\n"
            base = head + "M2\n"
            for t, acc in ((tau, "tau"), (tk, "k")):
                mach = machine_with_tau(text, t, tmp)
                full, rc, over = run_time(a.gmotion, prog, mach, tmp, f"s{n}-{acc}")
                empty, _, _ = run_time(a.gmotion, base, mach, tmp, f"b{n}-{acc}")
                if acc == "tau":
                    cut_tau += full - empty
                else:
                    cut_k += full - empty
                    over_total += rc != 0
            pos = p
        feeds = sorted({round(t, 4) for t, (r, _) in zip(taus, stretches) if not r})
        print(f"{os.path.basename(a.program)}: one run {whole:.3f} s; cut at rests, tau "
              f"{tau:g} s: {cut_tau:.3f} s; each feed stretch on its tau_k: {cut_k:.3f} s "
              f"({len(stretches)} stretches, feed tau_k {feeds}; stretches failing the "
              f"tolerance check: {over_total})")


if __name__ == "__main__":
    main()
