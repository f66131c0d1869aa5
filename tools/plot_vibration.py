#!/usr/bin/python3
"""Residual vibration against frequency for several profiles (Klipper's shaper graph), from
`gmotion analyze vibration` (PNG, matplotlib; Debian python3-matplotlib).

  plot_vibration.py [--gmotion build/bin/gmotion] [--period 0.001] [--damping 0.1]
                    [--freq-range 10:150] [--points 281] [--mode 45]
                    --profile linear --tau 0.06 --profile mzv:45 ... -o vibration.png

Each --profile may be followed by its own --tau (else analyze's default). Runs `gmotion analyze
vibration` per profile, plots V(f) in % of the applied integer taps, and marks the mode F and
F +- 20 % (the robustness band the shaper tables quote) when --mode is given.
"""
import argparse
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def analyze(gmotion, profile, tau, args):
    cmd = [gmotion, "analyze", "vibration", "--profile", profile, "--period", str(args.period),
           "--damping", str(args.damping), "--freq-range", args.freq_range,
           "--points", str(args.points)]
    if tau is not None:
        cmd += ["--tau", str(tau)]
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    f, v = [], []
    for line in out.splitlines():
        if not line or line.startswith("#") or line.startswith("f_hz"):
            continue
        cols = line.split(",")
        f.append(float(cols[0]))
        v.append(float(cols[1]))
    if not f:
        sys.exit(f"plot_vibration: no rows from {' '.join(cmd)}")
    return f, v


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--gmotion", default="build/bin/gmotion")
    ap.add_argument("--period", type=float, default=0.001)
    ap.add_argument("--damping", type=float, default=0.1)
    ap.add_argument("--freq-range", default="10:150")
    ap.add_argument("--points", type=int, default=281)
    ap.add_argument("--mode", type=float, help="the machine's mode (Hz): marks F and F +- 20 %%")
    ap.add_argument("--profile", action="append", required=True)
    ap.add_argument("--tau", action="append", type=float, default=[])
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()
    taus = args.tau + [None] * (len(args.profile) - len(args.tau))

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for profile, tau in zip(args.profile, taus):
        f, v = analyze(args.gmotion, profile, tau, args)
        label = profile if tau is None else f"{profile}, tau {tau * 1000:g} ms"
        ax.plot(f, v, label=label)
    if args.mode:
        ax.axvline(args.mode, color="k", lw=0.8)
        ax.axvspan(0.8 * args.mode, 1.2 * args.mode, color="0.9", zorder=0)
    ax.axhline(5.0, color="0.5", lw=0.6, ls="--")
    ax.set_xlabel("mode frequency (Hz)")
    ax.set_ylabel("residual vibration V (%)")
    ax.set_title(f"residual vibration, damping {args.damping:g}, T = {args.period * 1000:g} ms")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)


if __name__ == "__main__":
    main()
