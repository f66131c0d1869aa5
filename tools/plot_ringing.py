#!/usr/bin/python3
"""The ringing test as a picture: the tool tip of programs/ringing.nc on a machine with a
structural mode, with the machine's own Acc/Dec profile and with the one `gmotion design --mode`
proposes (PNG, matplotlib; Debian python3-matplotlib).

  plot_ringing.py [--gmotion build/bin/gmotion] [--program programs/ringing.nc]
                  [--machine programs/machines/ringing-40hz.toml]
                  [--designed linear+zv:40@0.02] [--designed-tau 0.073] [--axis x]
                  -o docs/img/ringing.png

Runs `gmotion run --trace` for both profiles and plots, for the axis: over the whole program the
tool tip minus the encoder (x_tip - x_enc, BLU: the modes' deflection, within half a count, on a
semi-closed loop), and around the first stop the tool tip minus the Acc/Dec output (x_tip - x_ref)
from the instant that output comes to rest. The traces are read with tools/gmtrace.py (the tip
columns exist only on a machine with modes).
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import gmtrace  # noqa: E402  (the trace schema and reader)
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def run(gmotion, program, machine, profile, tau, path):
    cmd = [gmotion, "run", program, "--machine", machine, "--trace", path]
    if profile:
        cmd += ["--profile", profile, "--tau", str(tau)]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    return gmtrace.read_columns(path)


def first_rest(cols, axis, still=20):
    """(t_rest, t_next): when the axis's Acc/Dec output comes to rest after its first move
    (unchanged for `still` samples from there) and when it moves again."""
    ref, t = cols[f"{axis}_ref"], cols["t_s"]
    moved = False
    for i in range(1, len(ref) - still):
        if ref[i] != ref[i - 1]:
            moved = True
        elif moved and all(ref[j] == ref[i] for j in range(i, i + still)):
            nxt = next((j for j in range(i + 1, len(ref)) if ref[j] != ref[i]), len(ref) - 1)
            return t[i], t[nxt]
    return t[0], t[-1]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--gmotion", default="build/bin/gmotion")
    p.add_argument("--program", default="programs/ringing.nc")
    p.add_argument("--machine", default="programs/machines/ringing-40hz.toml")
    p.add_argument("--designed", default="linear+zv:40@0.02")
    p.add_argument("--designed-tau", type=float, default=0.073)
    p.add_argument("--axis", default="x")
    p.add_argument("-o", "--output", required=True)
    a = p.parse_args()
    ax = a.axis.lower()
    with tempfile.TemporaryDirectory() as d:
        runs = [("machine's profile", run(a.gmotion, a.program, a.machine, None, None,
                                          os.path.join(d, "default.csv"))),
                (f"{a.designed}, tau {a.designed_tau} s",
                 run(a.gmotion, a.program, a.machine, a.designed, a.designed_tau,
                     os.path.join(d, "designed.csv")))]
    for _, (hd, c) in runs:
        if f"{ax}_tip" not in c:
            raise SystemExit(f"{a.machine}: no {ax}_tip column (the machine has no modes)")
    fig, (top, zoom) = plt.subplots(2, 1, figsize=(10, 6.4))
    colours = ["#d62728", "#1f77b4"]
    lim, span = 0.0, 0.2
    for (label, (hd, c)), colour in zip(runs, colours):
        defl = [tip - enc for tip, enc in zip(c[f"{ax}_tip"], c[f"{ax}_enc"])]
        top.plot(c["t_s"], defl, lw=0.7, color=colour, label=label)
        dev = [tip - ref for tip, ref in zip(c[f"{ax}_tip"], c[f"{ax}_ref"])]
        t0, t1 = first_rest(c, ax)
        span = min(span, t1 - t0)
        rel = [t - t0 for t in c["t_s"]]
        zoom.plot(rel, dev, lw=1.0, color=colour, label=label)
    for _, (hd, c) in runs:
        t0, _ = first_rest(c, ax)
        lim = max([lim] + [abs(tip - ref) for t, tip, ref in zip(c["t_s"], c[f"{ax}_tip"], c[f"{ax}_ref"])
                           if 0 <= t - t0 <= span])
    top.set_xlabel("t [s]")
    top.set_ylabel(f"{ax.upper()} tip - encoder [BLU]")
    top.set_title(f"{os.path.basename(a.program)} on {os.path.basename(a.machine)}")
    top.legend(loc="upper right", fontsize=8)
    top.grid(alpha=0.3)
    zoom.set_xlim(-0.01, span)
    zoom.set_ylim(-1.2 * lim, 1.2 * lim)
    zoom.set_xlabel(f"t since {ax.upper()}'s Acc/Dec output came to rest after its first stroke, "
                    "until it moves again [s]")
    zoom.set_ylabel(f"{ax.upper()} tip - Acc/Dec output [BLU]")
    zoom.grid(alpha=0.3)
    zoom.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(a.output, dpi=90)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
